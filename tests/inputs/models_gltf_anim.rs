//! Animated glTF models (docs/models.md, "Animation"): files written here
//! with skins, morph targets and animations, posed at known instants and
//! compared with the positions worked out by hand.

use std::path::Path;

use glam::{Mat4, Vec3};
use relief_scene::Object;
use relief_scene::gltf::{Model, load_bytes};

use crate::glb_writer::{Bin, two_joint_strip};

fn load(bytes: &[u8]) -> Model {
    load_bytes("test.glb", bytes, Path::new(".")).unwrap_or_else(|e| panic!("{e}"))
}

/// The model's objects posed at `time` seconds into `clip`, each vertex
/// taken back from the unit view to the file's world space.
fn posed(model: &mut Model, clip: Option<usize>, time: f32) -> Vec<Vec<Vec3>> {
    let motion = model.motion.as_mut().expect("the model is animated");
    let mut objects: Vec<Object> = model
        .parts
        .iter_mut()
        .map(|p| Object {
            mesh: std::mem::take(&mut p.mesh),
            transform: Mat4::IDENTITY,
            rotates: true,
        })
        .collect();
    motion.show(&mut objects, clip, time);
    let back = motion.rig.fit.inverse();
    let out = objects
        .iter()
        .map(|o| {
            let world = o.mesh.vertices.iter();
            world.map(|v| back.transform_point3(v.position)).collect()
        })
        .collect();
    for (p, o) in model.parts.iter_mut().zip(objects) {
        p.mesh = o.mesh;
    }
    out
}

fn near(a: Vec3, b: Vec3) -> bool {
    (a - b).length() < 1e-4
}

#[test]
fn a_two_joint_skin_bends_as_its_joint_turns() {
    let mut model = load(&two_joint_strip());
    // At rest (0 s) the strip is as the file gives it.
    let rest = posed(&mut model, Some(0), 0.0);
    assert!(near(rest[0][5], Vec3::new(0.1, 2.0, 0.0)), "{:?}", rest[0]);
    // At 1 s the child has turned 90° about Z about y = 1: the top pair,
    // one unit above it, is one unit to the left of it (x = −1), the
    // turned ±0.1 now along y: (0.1, 2) → (−1, 1.1), (−0.1, 2) → (−1, 0.9).
    let bent = posed(&mut model, Some(0), 1.0);
    assert!(near(bent[0][5], Vec3::new(-1.0, 1.1, 0.0)), "{:?}", bent[0]);
    assert!(near(bent[0][4], Vec3::new(-1.0, 0.9, 0.0)), "{:?}", bent[0]);
    // The middle pair is half on each joint: (0.1, 1) is half itself and
    // half (0, 1.1), so (0.05, 1.05).
    assert!(
        near(bent[0][3], Vec3::new(0.05, 1.05, 0.0)),
        "{:?}",
        bent[0]
    );
    // The bottom pair follows the root, which does not move.
    assert!(near(bent[0][1], Vec3::new(0.1, 0.0, 0.0)), "{:?}", bent[0]);
    // At ½ s, 45°: (0.1, 1) above the joint turns to (0.1c − s, 0.1s + c).
    let (s, c) = std::f32::consts::FRAC_PI_4.sin_cos();
    let half = posed(&mut model, Some(0), 0.5);
    let want = Vec3::new(0.1 * c - s, 1.0 + 0.1 * s + c, 0.0);
    assert!(near(half[0][5], want), "{:?} vs {want}", half[0][5]);
    // Normals follow the turn: the strip faces +Z throughout.
    let normal = model.parts[0].mesh.vertices[5].normal;
    assert!(near(normal, Vec3::Z), "{normal}");
}

/// One triangle whose one morph target lifts its third corner by 1 in
/// y; the clip's weights go from 0 at 0 s to 1 at 2 s, with `weights` as
/// the node's own (`""`: none).
fn morphing_triangle(weights: &str, interpolation: &str) -> Vec<u8> {
    let mut bin = Bin::default();
    let position = bin.positions(&[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]);
    let normal = bin.floats(&[0.0, 0.0, 1.0].repeat(3), "VEC3");
    let lift = bin.positions(&[0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0]);
    let times = bin.floats(&[0.0, 2.0], "SCALAR");
    let values = bin.floats(&[0.0, 1.0], "SCALAR");
    bin.glb(&format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],
        "nodes":[{{"mesh":0{weights}}}],
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":{position},"NORMAL":{normal}}},
            "targets":[{{"POSITION":{lift}}}]}}]}}],
        "animations":[{{"samplers":[{{"input":{times},"output":{values},"interpolation":"{interpolation}"}}],
            "channels":[{{"sampler":0,"target":{{"node":0,"path":"weights"}}}}]}}]"#
    ))
}

#[test]
fn morph_weights_move_the_corner_by_their_share() {
    let mut model = load(&morphing_triangle("", "LINEAR"));
    for (time, lift) in [(0.0, 0.0), (1.0, 0.5), (2.0, 1.0)] {
        let p = posed(&mut model, Some(0), time);
        assert!(
            near(p[0][2], Vec3::new(0.0, 1.0 + lift, 0.0)),
            "{time} s: {:?}",
            p[0]
        );
        assert!(near(p[0][1], Vec3::X), "{time} s: {:?}", p[0]);
    }
    // STEP holds the first weight until the second key.
    let mut model = load(&morphing_triangle("", "STEP"));
    let p = posed(&mut model, Some(0), 1.9);
    assert!(near(p[0][2], Vec3::Y), "{:?}", p[0]);
    // Without a clip, the node's own weights pose it.
    let mut model = load(&morphing_triangle(r#","weights":[0.5]"#, "LINEAR"));
    let p = posed(&mut model, None, 0.0);
    assert!(near(p[0][2], Vec3::new(0.0, 1.5, 0.0)), "{:?}", p[0]);
}

/// A triangle on a node translated by a cubic spline from x = 0 at 0 s to
/// x = 1 at 2 s, leaving at 3 units a second and arriving at −1.
fn spline_triangle() -> Vec<u8> {
    let mut bin = Bin::default();
    let position = bin.positions(&[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]);
    let times = bin.floats(&[0.0, 2.0], "SCALAR");
    // Per key: in-tangent, value, out-tangent.
    let keys = [
        [9.0, 9.0, 9.0, 0.0, 0.0, 0.0, 3.0, 0.0, 0.0],
        [-1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 9.0, 9.0, 9.0],
    ]
    .concat();
    let values = bin.floats(&keys, "VEC3");
    // A second, still triangle at x = 5 keeps the fit from following.
    bin.glb(&format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0,1]}}],
        "nodes":[{{"mesh":0}},{{"mesh":0,"translation":[5,0,0]}}],
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":{position}}}}}]}}],
        "animations":[{{"samplers":[{{"input":{times},"output":{values},"interpolation":"CUBICSPLINE"}}],
            "channels":[{{"sampler":0,"target":{{"node":0,"path":"translation"}}}}]}}]"#
    ))
}

#[test]
fn a_cubic_spline_moves_a_node_along_its_hermite_curve() {
    let mut model = load(&spline_triangle());
    // At 1 s, s = ½ of a 2 s span: ½·0 + ⅛·2·3 + ½·1 − ⅛·2·(−1) = 1.5.
    let p = posed(&mut model, Some(0), 1.0);
    assert!(near(p[0][0], Vec3::new(1.5, 0.0, 0.0)), "{:?}", p[0]);
    assert!(near(p[1][0], Vec3::new(5.0, 0.0, 0.0)), "{:?}", p[1]);
    // The keys themselves.
    let p = posed(&mut model, Some(0), 2.0);
    assert!(near(p[0][0], Vec3::X), "{:?}", p[0]);
    // No normals: the flat ones stay the face's.
    let n = model.parts[0].mesh.vertices[0].normal;
    assert!(near(n, Vec3::Z), "{n}");
}

#[test]
fn bad_animation_data_is_refused_with_the_place() {
    // A joint index past the skin's joints.
    let bytes = two_joint_strip();
    let bad = replace_once(&bytes, br#""joints":[0,1]"#, br#""joints":[0]  "#);
    let e = load_bytes("bad.glb", &bad, Path::new("."))
        .err()
        .expect("refused");
    assert!(e.contains("joint 1 is past the skin's 1 joints"), "{e}");
    // Key times that go back.
    let mut bin = Bin::default();
    let position = bin.positions(&[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]);
    let times = bin.floats(&[1.0, 0.0], "SCALAR");
    let values = bin.floats(&[0.0; 6], "VEC3");
    let bytes = bin.glb(&format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],
        "nodes":[{{"mesh":0}}],
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":{position}}}}}]}}],
        "animations":[{{"samplers":[{{"input":{times},"output":{values}}}],
            "channels":[{{"sampler":0,"target":{{"node":0,"path":"translation"}}}}]}}]"#
    ));
    let e = load_bytes("bad.glb", &bytes, Path::new("."))
        .err()
        .expect("refused");
    assert!(e.contains("animations[0].channels[0]"), "{e}");
    assert!(e.contains("increasing order"), "{e}");
}

/// `bytes` with `from` replaced once by `to` (of the same length).
fn replace_once(bytes: &[u8], from: &[u8], to: &[u8]) -> Vec<u8> {
    assert_eq!(from.len(), to.len());
    let at = bytes
        .windows(from.len())
        .position(|w| w == from)
        .expect("the text is there");
    let mut out = bytes.to_vec();
    out[at..at + from.len()].copy_from_slice(to);
    out
}
