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
use relief_scene::model_view::TextureReach;
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
    let dir = crate::common::scratch::scratch_dir(&format!("view-{test}"));
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

/// `scene` drawn at 160×120 with `settings`.
fn pixels(scene: &Scene, settings: &Settings) -> Vec<[u8; 3]> {
    let mut fb = Framebuffer::new(160, 120);
    Renderer::new().render(scene, settings, &mut fb);
    fb.pixels().to_vec()
}

/// A model file that names no material and gives no colour (an OBJ
/// without MTL, as an STL or a PLY of positions) is drawn plain in the
/// model view: the same pixels with the texture, the bump and the vertex
/// colours on or off, i.e. white. Once the user chooses a texture, the
/// scene's texture goes on it (with the reference colours still left
/// out: texture on and off then differ, colours on and off do not).
#[test]
fn a_model_without_material_is_plain_until_a_texture_is_chosen() {
    let mut scene = model_scene(box_obj("plain", Vec3::splat(-1.0), Vec3::splat(1.0)));
    assert!(scene.objects.iter().all(|o| o.mesh.colours_invented));
    assert_eq!(scene.texture_reach(), Some(TextureReach::WhenChosen));
    let view = scene.model_view.as_mut().unwrap();
    assert!(!view.file_texture);
    view.texture_chosen = false;
    let start = start_view();
    let plain = pixels(&scene, &start);
    let bare = Settings {
        texture: false,
        bump: false,
        colors: false,
        ..start
    };
    assert_eq!(plain, pixels(&scene, &bare));
    for other in [
        Settings {
            texture: false,
            ..start
        },
        Settings {
            bump: false,
            ..start
        },
        Settings {
            colors: false,
            ..start
        },
    ] {
        assert_eq!(plain, pixels(&scene, &other));
    }
    // Plain and lit: grey levels only, none of the reference's tints.
    let background = scene.background;
    let model: Vec<_> = plain.iter().filter(|p| **p != background).collect();
    assert!(model.len() > 1000, "{} model pixels", model.len());
    assert!(
        model.iter().all(|p| p[0] == p[1] && p[1] == p[2]),
        "not grey"
    );

    scene.model_view.as_mut().unwrap().texture_chosen = true;
    let dressed = pixels(&scene, &start);
    assert_ne!(plain, dressed);
    let untextured = Settings {
        texture: false,
        bump: false,
        ..start
    };
    assert_eq!(plain, pixels(&scene, &untextured));
    let uncoloured = Settings {
        colors: false,
        ..start
    };
    assert_eq!(dressed, pixels(&scene, &uncoloured));
}

/// A model whose file gives its vertices colours keeps them in the model
/// view: colours on and off differ, texture on and off do not (no texture
/// was chosen).
#[test]
fn a_model_keeps_the_colours_its_file_gives() {
    let path = box_obj("colours", Vec3::splat(-1.0), Vec3::splat(1.0));
    let text = std::fs::read_to_string(&path).unwrap();
    let coloured: String = text
        .lines()
        .map(|l| match l.strip_prefix("v ") {
            Some(p) => format!("v {p} 0.9 0.2 0.1\n"),
            None => format!("{l}\n"),
        })
        .collect();
    std::fs::write(&path, coloured).unwrap();
    let mut scene = model_scene(path);
    assert!(scene.objects.iter().all(|o| !o.mesh.colours_invented));
    scene.model_view.as_mut().unwrap().texture_chosen = false;
    let start = start_view();
    let shown = pixels(&scene, &start);
    let off = Settings {
        colors: false,
        ..start
    };
    assert_ne!(shown, pixels(&scene, &off));
    let untextured = Settings {
        texture: false,
        ..start
    };
    assert_eq!(shown, pixels(&scene, &untextured));
    // Red: the file's colour, not white.
    let background = scene.background;
    let reddish = shown
        .iter()
        .filter(|p| **p != background && p[0] > 2 * p[1] && p[0] > 2 * p[2])
        .count();
    assert!(reddish > 1000, "{reddish} red pixels");
}

/// A model whose MTL names a colour map keeps it on its faces without the
/// user choosing a texture: the map is the file's (`file_texture`).
#[test]
fn a_model_keeps_the_texture_its_file_names() {
    let path = box_obj("own-map", Vec3::splat(-1.0), Vec3::splat(1.0));
    let dir = path.parent().unwrap();
    let brick = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/reference-brick.png");
    std::fs::copy(brick, dir.join("brick.png")).unwrap();
    std::fs::write(dir.join("model.mtl"), "newmtl brick\nmap_Kd brick.png\n").unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    let with_material = format!("mtllib model.mtl\nusemtl brick\n{text}");
    std::fs::write(&path, with_material).unwrap();
    let mut scene = model_scene(path);
    assert_eq!(scene.texture_reach(), Some(TextureReach::Own));
    let view = scene.model_view.as_mut().unwrap();
    assert!(view.file_texture);
    view.texture_chosen = false;
    let start = start_view();
    let untextured = Settings {
        texture: false,
        ..start
    };
    assert_ne!(pixels(&scene, &start), pixels(&scene, &untextured));
}
