//! The model view (docs/models.md, "The model view"): a model file is
//! framed to fill the picture from the start view, whatever its shape,
//! place and the picture's aspect; the reference scenes keep their camera.

use std::path::PathBuf;
use std::sync::Arc;

use glam::Vec3;
use relief_core::framebuffer::Framebuffer;
use relief_core::settings::Settings;
use relief_core::settings::UpAxis;
use relief_pipeline::render::Renderer;
use relief_scene::{Built, ModelChoice, Scene, SceneKind, build_scene};
use relief_texture::decode::procedural;

/// A box from `lo` to `hi` as an OBJ file (its eight corners, twelve
/// triangles counter-clockwise from outside).
fn box_obj(test: &str, lo: Vec3, hi: Vec3) -> PathBuf {
    let mut text = String::new();
    for i in 0..8 {
        let pick = |bit: usize, a: f32, b: f32| if i & bit != 0 { b } else { a };
        let p = Vec3::new(
            pick(1, lo.x, hi.x),
            pick(2, lo.y, hi.y),
            pick(4, lo.z, hi.z),
        );
        text += &format!("v {} {} {}\n", p.x, p.y, p.z);
    }
    // Corner index i = x + 2y + 4z (1-based in the file).
    let quads = [
        [1, 3, 4, 2], // −Z
        [5, 6, 8, 7], // +Z
        [1, 5, 7, 3], // −X
        [2, 4, 8, 6], // +X
        [1, 2, 6, 5], // −Y
        [3, 7, 8, 4], // +Y
    ];
    for q in quads {
        text += &format!(
            "f {} {} {}\nf {} {} {}\n",
            q[0], q[1], q[2], q[0], q[2], q[3]
        );
    }
    let dir = std::env::temp_dir().join(format!("relief-view-{}-{test}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("model.obj");
    std::fs::write(&path, text).unwrap();
    path
}

fn model_scene(path: PathBuf) -> Scene {
    let built = build_scene(
        SceneKind::Cube,
        &ModelChoice::File(path),
        Arc::new(procedural::brick()),
        false,
    )
    .unwrap();
    match built {
        Built::Scene(scene) => *scene,
        Built::Plasma(_) => unreachable!(),
    }
}

/// The model file's start settings (as `relief render FILE` has them).
fn start_view() -> Settings {
    Settings {
        rotation: relief_scene::model_view::START_ROTATION,
        ..Settings::default()
    }
}

/// The bounding box of the pixels that are not the background:
/// (left, top, right, bottom), inclusive.
fn silhouette(fb: &Framebuffer, background: [u8; 3]) -> Option<(usize, usize, usize, usize)> {
    let (w, h) = (fb.width(), fb.height());
    let mut b: Option<(usize, usize, usize, usize)> = None;
    for y in 0..h {
        for x in 0..w {
            if fb.pixels()[y * w + x] != background {
                b = Some(match b {
                    None => (x, y, x, y),
                    Some((l, t, r, bo)) => (l.min(x), t.min(y), r.max(x), bo.max(y)),
                });
            }
        }
    }
    b
}

/// The silhouette's larger extent over the picture's shorter side, after
/// checking that it touches no edge (the model is not cut).
fn fill(scene: &Scene, settings: &Settings, w: usize, h: usize) -> f32 {
    let mut fb = Framebuffer::new(w, h);
    Renderer::new().render(scene, settings, &mut fb);
    let (l, t, r, b) = silhouette(&fb, scene.background).expect("the model is drawn");
    assert!(
        l > 0 && t > 0 && r < w - 1 && b < h - 1,
        "the model is cut at the picture's edge: {l},{t}..{r},{b} in {w}x{h}"
    );
    let extent = (r - l + 1).max(b - t + 1) as f32;
    extent / w.min(h) as f32
}

const SIZES: [(usize, usize); 4] = [(160, 120), (90, 160), (240, 60), (96, 96)];

#[test]
fn every_model_fills_at_least_four_fifths_of_the_shorter_side() {
    let models = [
        (
            "elongated",
            Vec3::new(-5.0, -0.3, -0.3),
            Vec3::new(5.0, 0.3, 0.3),
        ),
        ("tall", Vec3::new(-0.2, 0.0, -0.2), Vec3::new(0.2, 8.0, 0.2)),
        (
            "flat",
            Vec3::new(-2.0, -0.01, -3.0),
            Vec3::new(2.0, 0.01, 3.0),
        ),
        (
            "offset",
            Vec3::new(100.0, 50.0, -20.0),
            Vec3::new(101.0, 51.5, -19.0),
        ),
    ];
    for (name, lo, hi) in models {
        let scene = model_scene(box_obj(name, lo, hi));
        for (w, h) in SIZES {
            let f = fill(&scene, &start_view(), w, h);
            assert!(
                f >= 0.8,
                "{name} at {w}x{h} fills {f:.3} of the shorter side"
            );
        }
    }
}

#[test]
fn a_z_up_model_is_framed_too() {
    let scene = model_scene(box_obj(
        "zup",
        Vec3::new(-0.5, -0.5, 0.0),
        Vec3::new(0.5, 0.5, 6.0),
    ));
    let settings = Settings {
        up: UpAxis::Z,
        ..start_view()
    };
    for (w, h) in SIZES {
        let f = fill(&scene, &settings, w, h);
        assert!(f >= 0.8, "at {w}x{h} it fills {f:.3}");
    }
}

#[test]
fn turning_the_model_keeps_the_start_framing() {
    // With the start rotation as the pose, the camera stays where the start
    // view put it: the same turn gives the same picture whatever the pose
    // was framed from, and the start view itself fills the picture.
    let mut scene = model_scene(box_obj(
        "pose",
        Vec3::new(-2.0, -0.5, -0.5),
        Vec3::new(2.0, 0.5, 0.5),
    ));
    if let Some(view) = &mut scene.model_view {
        view.pose = Some(relief_scene::model_view::START_ROTATION);
    }
    let turned = Settings {
        rotation: Vec3::new(0.0, 60.0, 0.0),
        ..start_view()
    };
    let (mut a, mut b) = (Framebuffer::new(120, 90), Framebuffer::new(120, 90));
    let mut renderer = Renderer::new();
    renderer.render(&scene, &start_view(), &mut a);
    renderer.render(&scene, &turned, &mut b);
    let mut fresh = Framebuffer::new(120, 90);
    Renderer::new().render(&scene, &turned, &mut fresh);
    assert_eq!(
        b.pixels(),
        fresh.pixels(),
        "the framing depends on the pose only"
    );
    assert_ne!(a.pixels(), b.pixels());
    assert!(fill(&scene, &start_view(), 120, 90) >= 0.8);
}

#[test]
fn the_built_in_models_keep_the_reference_camera_and_lights() {
    for model in [ModelChoice::Cube, ModelChoice::Sphere] {
        let built = build_scene(
            SceneKind::Cube,
            &model,
            Arc::new(procedural::brick()),
            false,
        );
        let Ok(Built::Scene(scene)) = built else {
            panic!("the {model} scene is built");
        };
        assert!(scene.model_view.is_none());
        assert_eq!(scene.camera, relief_scene::Camera::default());
        assert_eq!(scene.lights, relief_scene::light::reference_lights());
    }
}

#[test]
fn a_model_file_is_lit_by_white_lights_only() {
    let scene = model_scene(box_obj("rig", Vec3::splat(-1.0), Vec3::splat(1.0)));
    assert!(scene.model_view.is_some());
    for light in &scene.lights {
        let c = light.color;
        assert!(c.x == c.y && c.y == c.z && c.x > 0.0, "{c}");
    }
}
