//! Every model rendered, read back from the raw framebuffer: silhouettes
//! where the geometry says, nothing non-finite, any orientation.

use std::path::Path;
use std::sync::Arc;

use glam::{Vec2, Vec3};
use proptest::prelude::*;
use relief_core::framebuffer::Framebuffer;
use relief_core::settings::Settings;
use relief_core::settings::{Normals, Shading};
use relief_pipeline::render::render_frame;
use relief_scene::{Built, ModelChoice, Scene, SceneKind, build_scene, rotation_matrix};
use relief_texture::decode::procedural;

/// A background no lit model can produce (green is at least the ambient share).
const MAGENTA: [u8; 3] = [255, 0, 255];

fn model_scene(model: &ModelChoice) -> Scene {
    let texture = Arc::new(procedural::brick());
    match build_scene(SceneKind::Cube, model, texture, false).unwrap() {
        Built::Scene(s) => {
            // The reference camera, which the silhouettes are projected with
            // (a model file's own framing is tests/render/model_view.rs's).
            let mut s = (*s).into_reference_view();
            s.background = MAGENTA;
            s
        }
        Built::Plasma(_) => panic!("a 3D scene"),
    }
}

fn data(name: &str) -> ModelChoice {
    ModelChoice::File(
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/data")
            .join(name),
    )
}

fn models() -> Vec<ModelChoice> {
    vec![
        ModelChoice::Triangle,
        ModelChoice::Plane,
        ModelChoice::Cube,
        ModelChoice::Sphere,
        data("cube.obj"),
        data("cube_positions_only.obj"),
        data("pyramid_relative.obj"),
    ]
}

fn covered(fb: &Framebuffer) -> usize {
    fb.pixels().iter().filter(|&&p| p != MAGENTA).count()
}

/// Convex hull (monotone chain) of 2D points, counter-clockwise.
fn hull(mut p: Vec<Vec2>) -> Vec<Vec2> {
    p.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    p.dedup();
    if p.len() < 3 {
        return p;
    }
    let cross = |o: Vec2, a: Vec2, b: Vec2| (a - o).perp_dot(b - o);
    let mut lower: Vec<Vec2> = Vec::new();
    for &q in &p {
        while lower.len() >= 2 && cross(lower[lower.len() - 2], lower[lower.len() - 1], q) <= 0.0 {
            lower.pop();
        }
        lower.push(q);
    }
    let mut upper: Vec<Vec2> = Vec::new();
    for &q in p.iter().rev() {
        while upper.len() >= 2 && cross(upper[upper.len() - 2], upper[upper.len() - 1], q) <= 0.0 {
            upper.pop();
        }
        upper.push(q);
    }
    lower.pop();
    upper.pop();
    lower.extend(upper);
    lower
}

/// Area and perimeter of the projected silhouette of a convex model, in pixels.
fn silhouette(scene: &Scene, settings: &Settings, w: usize, h: usize) -> (f32, f32) {
    let object = &scene.objects[0];
    let model = object.transform * rotation_matrix(settings.rotation);
    let vp = scene.camera.projection(w as f32 / h as f32) * scene.camera.view();
    let points: Vec<Vec2> = object
        .mesh
        .vertices
        .iter()
        .map(|v| {
            let c = vp * model.transform_point3(v.position).extend(1.0);
            Vec2::new(
                (c.x / c.w * 0.5 + 0.5) * w as f32,
                (0.5 - c.y / c.w * 0.5) * h as f32,
            )
        })
        .collect();
    let hull = hull(points);
    let n = hull.len();
    let area = (0..n)
        .map(|i| hull[i].perp_dot(hull[(i + 1) % n]))
        .sum::<f32>()
        .abs()
        / 2.0;
    let perimeter = (0..n).map(|i| hull[i].distance(hull[(i + 1) % n])).sum();
    (area, perimeter)
}

#[test]
fn every_model_covers_its_projected_silhouette() {
    let (w, h) = (320, 240);
    for model in models() {
        let scene = model_scene(&model);
        for rotation in [Vec3::new(25.0, 35.0, 0.0), Vec3::new(-10.0, 20.0, 5.0)] {
            for shading in [Shading::Flat, Shading::Gouraud, Shading::Phong] {
                let settings = Settings {
                    rotation,
                    shading,
                    ..Settings::default()
                };
                let (fb, stats) = render_frame(&scene, &settings, w, h);
                assert_eq!(stats.counters.nonfinite, 0, "{model} {shading:?}");
                let (area, perimeter) = silhouette(&scene, &settings, w, h);
                let got = covered(&fb) as f32;
                // Pixel centres inside the silhouette: off by at most about
                // half a pixel along its outline.
                assert!(
                    (got - area).abs() <= 0.5 * perimeter + 4.0,
                    "{model} {rotation} {shading:?}: {got} pixels, silhouette {area} (perimeter {perimeter})"
                );
            }
        }
    }
}

#[test]
fn the_sphere_covers_the_disc_it_projects_to() {
    let (w, h) = (320, 240);
    let scene = model_scene(&ModelChoice::Sphere);
    let (fb, _) = render_frame(&scene, &Settings::default(), w, h);
    // A unit sphere 5 units away subtends asin(1/5); the 60° field spans h/2 per tan(30°).
    let distance = scene.camera.eye.length();
    let angle = (1.0 / distance).asin();
    let radius = angle.tan() / 30f32.to_radians().tan() * (h as f32 / 2.0);
    let disc = std::f32::consts::PI * radius * radius;
    let got = covered(&fb) as f32;
    // The 32 × 16 sphere is inscribed in the true one: a little less, never more.
    assert!(got < disc && got > 0.97 * disc, "{got} pixels, disc {disc}");
    // And it is centred.
    let (mut sx, mut sy) = (0.0, 0.0);
    for y in 0..h {
        for x in 0..w {
            if fb.get(x, y) != MAGENTA {
                sx += x as f32 + 0.5;
                sy += y as f32 + 0.5;
            }
        }
    }
    assert!((sx / got - w as f32 / 2.0).abs() < 0.5 && (sy / got - h as f32 / 2.0).abs() < 0.5);
}

#[test]
fn open_models_are_seen_from_behind() {
    for model in [ModelChoice::Triangle, ModelChoice::Plane] {
        let scene = model_scene(&model);
        let settings = Settings {
            rotation: Vec3::new(0.0, 180.0, 0.0),
            ..Settings::default()
        };
        let (fb, stats) = render_frame(&scene, &settings, 160, 120);
        let (area, _) = silhouette(&scene, &settings, 160, 120);
        assert!(area > 500.0 && covered(&fb) as f32 > 0.9 * area, "{model}");
        assert_eq!(stats.counters.nonfinite, 0);
    }
}

#[test]
fn hard_edges_stay_hard_on_a_loaded_cube() {
    // Face normals and vertex normals give the same picture when every
    // vertex normal is its face's normal (the smoothed-cube pitfall avoided).
    for name in ["cube.obj", "cube_positions_only.obj"] {
        let scene = model_scene(&data(name));
        let vertex = Settings {
            shading: Shading::Gouraud,
            ..Settings::default()
        };
        let face = Settings {
            normals: Normals::Face,
            ..vertex
        };
        let (a, _) = render_frame(&scene, &vertex, 160, 120);
        let (b, _) = render_frame(&scene, &face, 160, 120);
        assert_eq!(a, b, "{name}");
    }
}

fn any_model() -> impl Strategy<Value = ModelChoice> {
    prop::sample::select(models())
}

fn angle() -> impl Strategy<Value = f32> {
    prop_oneof![
        -360.0f32..360.0,
        Just(1e9f32),
        Just(-1e9f32),
        Just(f32::NAN),
        Just(f32::INFINITY),
        Just(90.0),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    #[test]
    fn any_model_any_orientation_stays_finite(
        model in any_model(),
        x in angle(), y in angle(), z in angle(),
        shading in prop::sample::select(vec![Shading::Flat, Shading::Gouraud, Shading::Phong]),
        normals in prop::sample::select(vec![Normals::Vertex, Normals::Face]),
        lights in any::<bool>(),
        attenuation in any::<bool>(),
        shadow in any::<bool>(),
    ) {
        let settings = Settings {
            rotation: Vec3::new(x, y, z),
            shading,
            normals,
            lights,
            attenuation,
            ..Settings::default()
        };
        let scene = if shadow {
            match build_scene(SceneKind::Shadow, &model, Arc::new(procedural::brick()), false) {
                Ok(Built::Scene(s)) => *s,
                _ => unreachable!("the shadow scene always builds"),
            }
        } else {
            model_scene(&model)
        };
        let (_, stats) = render_frame(&scene, &settings, 96, 64);
        prop_assert_eq!(stats.counters.nonfinite, 0);
        // Built-in models are convex or flat: alone, they never need the pass.
        let built_in = !matches!(model, ModelChoice::File(_));
        if !lights || (built_in && !shadow) {
            prop_assert_eq!(stats.counters.shadow_lookups, 0);
            prop_assert_eq!(stats.counters.shadow_texels, 0);
        }
    }
}
