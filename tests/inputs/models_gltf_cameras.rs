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

/// A 2×2 quad facing +Z at z = 0, and a camera 4 in front of it with a
/// vertical field of view of 2·atan(½): at the quad the view is 4 tall.
fn quad_and_camera(projection: &str) -> Vec<u8> {
    let mut bin = Bin::default();
    let position = bin.positions(&[
        -1.0, -1.0, 0.0, 1.0, -1.0, 0.0, 1.0, 1.0, 0.0, -1.0, 1.0, 0.0,
    ]);
    let normal = bin.floats(&[0.0, 0.0, 1.0].repeat(4), "VEC3");
    let indices = bin.shorts(&[0, 1, 2, 0, 2, 3], "SCALAR");
    bin.glb(&format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0,1]}}],
        "nodes":[{{"mesh":0}},{{"camera":0,"translation":[0,0,4]}}],
        "cameras":[{projection}],
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":{position},"NORMAL":{normal}}},
            "indices":{indices}}}]}}]"#
    ))
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
    let perspective = r#"{"type":"perspective","perspective":{"yfov":0.9272952,"znear":0.1}}"#;
    let model = load_bytes("cam.glb", &quad_and_camera(perspective), Path::new(".")).unwrap();
    assert_eq!(model.cameras.len(), 1);
    let mut scene = Scene::gltf(model, Arc::new(procedural::brick())).into_model_view();
    scene.background = MAGENTA;
    if let Some(view) = &mut scene.model_view {
        view.camera = Some(0);
    }
    let settings = Settings {
        rotation: Vec3::ZERO,
        ..Settings::default()
    };
    let mut fb = Framebuffer::new(160, 120);
    Renderer::new().render(&scene, &settings, &mut fb);
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
fn an_orthographic_camera_is_named_as_not_drawn() {
    let ortho =
        r#"{"type":"orthographic","orthographic":{"xmag":1,"ymag":1,"znear":0.1,"zfar":10}}"#;
    let model = load_bytes("cam.glb", &quad_and_camera(ortho), Path::new(".")).unwrap();
    assert!(model.cameras.is_empty());
    let line = model.warnings.join("\n");
    assert!(line.contains("its orthographic camera"), "{line}");
}
