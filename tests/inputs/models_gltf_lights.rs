//! A glTF file's own lights (KHR_lights_punctual; docs/models.md, "Lights
//! of the file"): placed by their nodes in the fitted model, their colour
//! times intensity scaled with the fit, and a spot's cone on the picture.

use std::path::Path;
use std::sync::Arc;

use glam::Vec3;
use relief_core::framebuffer::Framebuffer;
use relief_core::settings::Settings;
use relief_pipeline::render::Renderer;
use relief_scene::Scene;
use relief_scene::gltf::load_bytes;
use relief_scene::light::{Cone, DIRECTIONAL_DISTANCE, Falloff};
use relief_texture::decode::procedural;

use crate::glb_writer::Bin;

/// A 2×2 quad facing +Z at z = 0, with `lights` (the extension's list) on
/// the nodes `light_nodes` (JSON objects, one light each).
fn quad_with_lights(lights: &str, light_nodes: &[&str]) -> Vec<u8> {
    let mut bin = Bin::default();
    let position = bin.positions(&[
        -1.0, -1.0, 0.0, 1.0, -1.0, 0.0, 1.0, 1.0, 0.0, -1.0, 1.0, 0.0,
    ]);
    let normal = bin.floats(&[0.0, 0.0, 1.0].repeat(4), "VEC3");
    let indices = bin.shorts(&[0, 1, 2, 0, 2, 3], "SCALAR");
    let nodes: Vec<String> = (0..=light_nodes.len()).map(|i| i.to_string()).collect();
    bin.glb(&format!(
        r#"{{"asset":{{"version":"2.0"}},"extensionsUsed":["KHR_lights_punctual"],
        "extensions":{{"KHR_lights_punctual":{{"lights":[{lights}]}}}},
        "scene":0,"scenes":[{{"nodes":[{}]}}],
        "nodes":[{{"mesh":0}},{}],
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":{position},"NORMAL":{normal}}},
            "indices":{indices}}}]}}]"#,
        nodes.join(","),
        light_nodes.join(",")
    ))
}

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).abs().max_element() <= 1e-4 * b.abs().max_element().max(1.0)
}

#[test]
fn point_spot_and_directional_lights_are_placed_and_scaled_with_the_model() {
    let lights = r#"{"type":"point","color":[1,0.5,0.25],"intensity":10,"range":3},
        {"type":"spot","intensity":2,"spot":{"innerConeAngle":0.2,"outerConeAngle":0.5}},
        {"type":"directional","color":[0,1,0],"intensity":3}"#;
    let nodes = [
        r#"{"translation":[0,0,2],"extensions":{"KHR_lights_punctual":{"light":0}}}"#,
        r#"{"translation":[0,0,3],"extensions":{"KHR_lights_punctual":{"light":1}}}"#,
        // Turned −90° about X: its −Z looks down −Y.
        r#"{"rotation":[-0.70710678,0,0,0.70710678],"translation":[5,5,5],
            "extensions":{"KHR_lights_punctual":{"light":2}}}"#,
    ];
    let model = load_bytes("lit.glb", &quad_with_lights(lights, &nodes), Path::new(".")).unwrap();
    assert!(
        model.warnings.iter().all(|w| !w.contains("lights")),
        "{:?}",
        model.warnings
    );
    // The fit's scale: the quad's corner x = 1 lands at x = s.
    let mesh = &model.parts[0].mesh;
    let s = mesh
        .vertices
        .iter()
        .map(|v| v.position.x)
        .fold(0.0, f32::max);
    assert!(s > 0.1, "scale {s}");
    let [point, spot, sun] = model.lights[..] else {
        panic!("{} lights", model.lights.len());
    };
    // 1 / d² in the file's metres is s² / d² in the fitted space.
    assert!(close(point.position, Vec3::new(0.0, 0.0, 2.0 * s)));
    assert!(close(point.color, Vec3::new(10.0, 5.0, 2.5) * s * s));
    assert_eq!(
        point.falloff,
        Falloff::InverseSquare {
            range: 3.0 * s,
            cone: None
        }
    );
    assert!(close(spot.position, Vec3::new(0.0, 0.0, 3.0 * s)));
    assert!(close(spot.color, Vec3::splat(2.0 * s * s)));
    let Falloff::InverseSquare {
        range,
        cone: Some(cone),
    } = spot.falloff
    else {
        panic!("{:?}", spot.falloff);
    };
    assert!(range.is_infinite());
    let want = Cone::new(Vec3::NEG_Z, 0.2, 0.5);
    assert!(close(cone.axis, want.axis));
    assert!((cone.scale - want.scale).abs() < 1e-3 && (cone.offset - want.offset).abs() < 1e-3);
    // A directional light ignores its node's place: it stands far against
    // its direction, and its lux are not scaled.
    assert!(close(
        sun.position,
        Vec3::new(0.0, DIRECTIONAL_DISTANCE, 0.0)
    ));
    assert_eq!(sun.color, Vec3::new(0.0, 3.0, 0.0));
    assert_eq!(sun.falloff, Falloff::None);
    assert!(model.lights.iter().all(|l| l.turns_with_model));
    // The model view lights the model with them, not with its rig.
    let scene = Scene::gltf(model, Arc::new(procedural::brick())).into_model_view();
    assert_eq!(scene.lights.len(), 3);
    assert_eq!(scene.lights[0].falloff, point.falloff);
}

#[test]
fn a_spot_light_lights_its_cone_and_leaves_the_rest_dark() {
    // A white spot 2 above the quad's centre, looking straight down at it:
    // full within 0.1 rad (0.2 of the quad's half-width of 1), nothing
    // beyond 0.3 rad (0.62).
    let lights =
        r#"{"type":"spot","intensity":40,"spot":{"innerConeAngle":0.1,"outerConeAngle":0.3}}"#;
    let nodes = [r#"{"translation":[0,0,2],"extensions":{"KHR_lights_punctual":{"light":0}}}"#];
    let model = load_bytes(
        "spot.glb",
        &quad_with_lights(lights, &nodes),
        Path::new("."),
    )
    .unwrap();
    let scene = Scene::gltf(model, Arc::new(procedural::brick())).into_model_view();
    let settings = Settings {
        rotation: Vec3::ZERO,
        ..Settings::default()
    };
    let mut fb = Framebuffer::new(160, 160);
    Renderer::new().render(&scene, &settings, &mut fb);
    let lum = |x: usize, y: usize| fb.get(x, y).iter().map(|&c| c as u32).sum::<u32>();
    // The quad fills the middle of the square picture; find its extent on
    // the centre row.
    let row = 80;
    let quad: Vec<usize> = (0..160)
        .filter(|&x| fb.get(x, row) != scene.background)
        .collect();
    let (left, right) = (quad[0], *quad.last().unwrap());
    let centre = (left + right) / 2;
    let half = (right - left) / 2;
    // Inside the inner cone against near the quad's edge (0.9 of the way
    // out: 24° off the axis, outside the outer cone's 17°).
    let lit = lum(centre, row);
    let edge = (
        lum(centre - half * 9 / 10, row),
        lum(centre + half * 9 / 10, row),
    );
    assert!(
        lit > 2 * edge.0.max(edge.1) && lit > 300,
        "centre {lit}, edges {edge:?}"
    );
    // The cone is round: the same light a quarter of the way out on either
    // side (the camera looks from above, so rows are not alike), less than
    // at the centre (7° off the axis, past the inner cone's 5.7°).
    let q = half / 4;
    let (l, r) = (lum(centre - q, row), lum(centre + q, row));
    assert!(l.abs_diff(r) <= 3 && l < lit, "centre {lit}, {l} and {r}");
}
