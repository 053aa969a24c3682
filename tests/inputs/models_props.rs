//! Property tests: no OBJ text makes the loader panic, and whatever it
//! accepts is a mesh the renderer can use.

use proptest::prelude::*;
use relief_scene::obj;

fn number() -> impl Strategy<Value = String> {
    prop_oneof![
        (-3.0f32..3.0).prop_map(|x| x.to_string()),
        Just("0".to_string()),
        Just("-0".to_string()),
        Just("1e38".to_string()),
        Just("-1e-40".to_string()),
        Just("nan".to_string()),
        Just("inf".to_string()),
        Just("x".to_string()),
    ]
}

fn index() -> impl Strategy<Value = String> {
    prop_oneof![
        4 => (1i64..8).prop_map(|i| i.to_string()),
        1 => (-8i64..0).prop_map(|i| i.to_string()),
        1 => Just("0".to_string()),
        1 => Just(String::new()),
        1 => Just("99999999999999999999".to_string()),
        1 => Just("-9223372036854775808".to_string()),
    ]
}

fn corner() -> impl Strategy<Value = String> {
    prop_oneof![
        index(),
        (index(), index()).prop_map(|(a, b)| format!("{a}/{b}")),
        (index(), index(), index()).prop_map(|(a, b, c)| format!("{a}/{b}/{c}")),
        (index(), index()).prop_map(|(a, c)| format!("{a}//{c}")),
    ]
}

fn line() -> impl Strategy<Value = String> {
    prop_oneof![
        4 => prop::collection::vec(number(), 2..8).prop_map(|n| format!("v {}", n.join(" "))),
        2 => prop::collection::vec(number(), 1..4).prop_map(|n| format!("vt {}", n.join(" "))),
        2 => prop::collection::vec(number(), 2..5).prop_map(|n| format!("vn {}", n.join(" "))),
        4 => prop::collection::vec(corner(), 1..7).prop_map(|c| format!("f {}", c.join(" "))),
        1 => prop::collection::vec(corner(), 1..4).prop_map(|c| format!("l {}", c.join(" "))),
        1 => Just("o thing".to_string()),
        1 => Just("g".to_string()),
        1 => Just("usemtl".to_string()),
        1 => Just("usemtl brick".to_string()),
        1 => Just("mtllib ../../etc/passwd".to_string()),
        1 => Just("# comment".to_string()),
        1 => ".{0,12}",
    ]
}

/// Four good positions first, so many random files get as far as building a mesh.
fn text() -> impl Strategy<Value = String> {
    prop::collection::vec(line(), 0..24).prop_map(|lines| {
        let mut s = String::from("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n");
        s += &lines.join("\n");
        s
    })
}

/// Only valid lines: random positions, UVs, normals and faces over them,
/// so the mesh building (degenerate, duplicated, mirrored, flipped faces) is exercised.
fn valid_text() -> impl Strategy<Value = String> {
    let coordinate = || prop_oneof![(-2.0f32..2.0), Just(0.0f32), Just(1.0f32)];
    let vertex =
        (coordinate(), coordinate(), coordinate()).prop_map(|(x, y, z)| format!("v {x} {y} {z}"));
    let uv = (coordinate(), coordinate()).prop_map(|(u, v)| format!("vt {u} {v}"));
    let normal =
        (coordinate(), coordinate(), coordinate()).prop_map(|(x, y, z)| format!("vn {x} {y} {z}"));
    let face = (prop::collection::vec(1usize..7, 3..6), any::<u8>()).prop_map(|(c, style)| {
        let corners: Vec<String> = c
            .iter()
            .map(|&i| match style % 4 {
                0 => format!("{i}"),
                1 => format!("{i}/{}", (i % 3) + 1),
                2 => format!("{i}//{}", (i % 2) + 1),
                _ => format!("{i}/{}/{}", (i % 3) + 1, (i % 2) + 1),
            })
            .collect();
        format!("f {}", corners.join(" "))
    });
    (
        prop::collection::vec(vertex, 6..7),
        prop::collection::vec(uv, 3..4),
        prop::collection::vec(normal, 2..3),
        prop::collection::vec(face, 1..12),
    )
        .prop_map(|(v, t, n, f)| [v, t, n, f].concat().join("\n"))
}

proptest! {
    #[test]
    fn random_valid_obj_builds_a_usable_mesh_or_says_why(text in valid_text()) {
        check(&text)?;
    }

    #[test]
    fn random_obj_text_never_panics(text in text()) {
        check(&text)?;
    }
}

fn check(text: &str) -> Result<(), TestCaseError> {
    match obj::parse("random.obj", text) {
        Ok(mesh) => {
            prop_assert!(!mesh.triangles.is_empty());
            for v in &mesh.vertices {
                prop_assert!(v.position.is_finite() && v.normal.is_finite());
                prop_assert!(v.tangent_u.is_finite() && v.tangent_v.is_finite());
                prop_assert!(v.uv.is_finite() && v.color.is_finite());
                prop_assert!(v.position.length() <= relief_scene::corners::FIT_RADIUS * 1.0001);
                prop_assert!((v.normal.length() - 1.0).abs() < 1e-3);
                prop_assert!(v.tangent_u.length() > 0.0 && v.tangent_v.length() > 0.0);
            }
            for t in &mesh.faces() {
                prop_assert!(
                    t.indices
                        .iter()
                        .all(|&i| (i as usize) < mesh.vertices.len())
                );
                prop_assert!(t.face_normal.is_finite() && t.face_tangent_u.is_finite());
            }
        }
        Err(e) => {
            let line = e.to_string();
            prop_assert!(!line.chars().any(char::is_control), "{:?}", line);
        }
    }
    Ok(())
}
