//! A glTF file's own cameras (docs/models.md, "Cameras of the file"): the
//! model seen from where its author put the camera, with its field of
//! view, checked against the projection worked out by hand.

use std::path::Path;
use std::sync::Arc;

use glam::Vec3;
use relief_core::framebuffer::Framebuffer;
use relief_core::settings::Settings;
use relief_pipeline::render::Renderer;
use relief_scene::Scene;
use relief_scene::gltf::load_bytes;
use relief_texture::decode::procedural;

use crate::glb_writer::Bin;

const MAGENTA: [u8; 3] = [255, 0, 255];

/// A 2×2 quad facing +Z at z = 0, and a camera `distance` in front of it
/// with the given projection.
fn quad_and_camera(projection: &str, distance: u32) -> Vec<u8> {
    let mut bin = Bin::default();
    let position = bin.positions(&[
        -1.0, -1.0, 0.0, 1.0, -1.0, 0.0, 1.0, 1.0, 0.0, -1.0, 1.0, 0.0,
    ]);
    let normal = bin.floats(&[0.0, 0.0, 1.0].repeat(4), "VEC3");
    let indices = bin.shorts(&[0, 1, 2, 0, 2, 3], "SCALAR");
    bin.glb(&format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0,1]}}],
        "nodes":[{{"mesh":0}},{{"camera":0,"translation":[0,0,{distance}]}}],
        "cameras":[{projection}],
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":{position},"NORMAL":{normal}}},
            "indices":{indices}}}]}}]"#
    ))
}

/// `scene`'s model seen through its file's first camera, unturned, at
/// 160×120 on a magenta background.
fn through_the_files_camera(scene: Scene) -> Framebuffer {
    through_the_files_camera_with(scene, Settings::default())
}

/// `through_the_files_camera` with `settings` (unturned).
fn through_the_files_camera_with(scene: Scene, settings: Settings) -> Framebuffer {
    let mut scene = scene.into_model_view();
    scene.background = MAGENTA;
    if let Some(view) = &mut scene.model_view {
        view.camera = Some(0);
    }
    let settings = Settings {
        rotation: Vec3::ZERO,
        ..settings
    };
    let mut fb = Framebuffer::new(160, 120);
    Renderer::new().render(&scene, &settings, &mut fb);
    fb
}

/// The rows and columns the model covers (not the background).
fn covered(fb: &Framebuffer) -> Option<((usize, usize), (usize, usize))> {
    let mut rows = (usize::MAX, 0);
    let mut cols = (usize::MAX, 0);
    for y in 0..fb.height() {
        for x in 0..fb.width() {
            if fb.get(x, y) != MAGENTA {
                rows = (rows.0.min(y), rows.1.max(y));
                cols = (cols.0.min(x), cols.1.max(x));
            }
        }
    }
    (rows.0 <= rows.1).then_some((rows, cols))
}

#[test]
fn the_files_camera_shows_the_quad_where_its_projection_puts_it() {
    // A vertical field of view of 2·atan(½), 4 in front: at the quad the
    // view is 4 tall.
    let perspective = r#"{"type":"perspective","perspective":{"yfov":0.9272952,"znear":0.1}}"#;
    let model = load_bytes("cam.glb", &quad_and_camera(perspective, 4), Path::new(".")).unwrap();
    assert_eq!(model.cameras.len(), 1);
    let fb = through_the_files_camera(Scene::gltf(model, Arc::new(procedural::brick())));
    // The quad is half the view's height (2 of 4): rows 30 to 89; the view
    // is 4·160/120 wide there, so the quad's 2 are 3/8 of the width:
    // columns 50 to 109.
    let ((top, bottom), (left, right)) = covered(&fb).expect("the quad is seen");
    for (got, want) in [(top, 30), (bottom, 89), (left, 50), (right, 109)] {
        assert!(
            got.abs_diff(want) <= 1,
            "rows {top}..{bottom}, columns {left}..{right}"
        );
    }
}

#[test]
fn an_orthographic_camera_shows_the_quad_at_its_size_from_any_distance() {
    // ymag 2: the view is 4 tall wherever the camera stands, so the 2×2
    // quad covers the same rows 30 to 89 and columns 50 to 109 as through
    // the perspective camera above, from 4 in front and from 9.
    let ortho =
        r#"{"type":"orthographic","orthographic":{"xmag":2,"ymag":2,"znear":0.1,"zfar":10}}"#;
    for distance in [4, 9] {
        let glb = quad_and_camera(ortho, distance);
        let model = load_bytes("cam.glb", &glb, Path::new(".")).unwrap();
        assert_eq!(model.cameras.len(), 1);
        assert!(model.warnings.iter().all(|w| !w.contains("orthographic")));
        let fb = through_the_files_camera(Scene::gltf(model, Arc::new(procedural::brick())));
        let ((top, bottom), (left, right)) = covered(&fb).expect("the quad is seen");
        for (got, want) in [(top, 30), (bottom, 89), (left, 50), (right, 109)] {
            assert!(
                got.abs_diff(want) <= 1,
                "from {distance}: rows {top}..{bottom}, columns {left}..{right}"
            );
        }
    }
}

/// The distinct colours of the pixels the model covers.
fn shades(fb: &Framebuffer) -> std::collections::BTreeSet<[u8; 3]> {
    let pixels = (0..fb.height()).flat_map(|y| (0..fb.width()).map(move |x| (x, y)));
    pixels
        .map(|(x, y)| fb.get(x, y))
        .filter(|&c| c != MAGENTA)
        .collect()
}

#[test]
fn through_an_orthographic_camera_a_flat_quad_is_one_shade() {
    // With the rig's (near, point) lights off, the environment alone
    // lights the quad: every pixel sees it along the same axis with the
    // same normal, so one colour. Through a perspective camera the view
    // direction turns across the quad and so does the reflection.
    let ortho =
        r#"{"type":"orthographic","orthographic":{"xmag":2,"ymag":2,"znear":0.1,"zfar":10}}"#;
    let perspective = r#"{"type":"perspective","perspective":{"yfov":0.9272952,"znear":0.1}}"#;
    let seen = |projection: &str| {
        let glb = quad_and_camera(projection, 4);
        let model = load_bytes("cam.glb", &glb, Path::new(".")).unwrap();
        let settings = Settings {
            lights: false,
            ..Settings::default()
        };
        let scene = Scene::gltf(model, Arc::new(procedural::brick()));
        shades(&through_the_files_camera_with(scene, settings))
    };
    let flat = seen(ortho);
    assert_eq!(flat.len(), 1, "{flat:?}");
    assert!(seen(perspective).len() > 1);
}
