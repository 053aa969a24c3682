//! The OBJ reader cuts big files into line-aligned chunks read in parallel
//! (crates/scene/src/obj/read.rs): whatever the cut, the model, its warnings and
//! its first error must be those of one chunk. Random files with every
//! kind of line, cut into 1 to 12 chunks so the cuts fall anywhere.

use proptest::prelude::*;
use relief_scene::loaded_model::LoadedModel;
use relief_scene::model_error::ObjError;
use relief_scene::obj::parse_in_chunks;

fn line() -> impl Strategy<Value = String> {
    let number = prop_oneof![
        (-100i32..100).prop_map(|k| format!("{}", k as f32 / 7.0)),
        Just("3.1+e2".to_string()),
        Just("1e-2".to_string()),
    ];
    let index = prop_oneof![(1i32..=8), (-8i32..=-1)];
    let attribute = prop_oneof![Just(None), (1i32..=10).prop_map(Some)];
    let corner = (index, attribute.clone(), attribute).prop_map(|(v, t, n)| match (t, n) {
        (None, None) => format!("{v}"),
        (Some(t), None) => format!("{v}/{t}"),
        (None, Some(n)) => format!("{v}//{n}"),
        (Some(t), Some(n)) => format!("{v}/{t}/{n}"),
    });
    prop_oneof![
        4 => prop::collection::vec(number.clone(), 3).prop_map(|n| format!("v {}", n.join(" "))),
        1 => prop::collection::vec(number.clone(), 6).prop_map(|n| format!("v {}", n.join(" "))),
        2 => prop::collection::vec(number.clone(), 2).prop_map(|n| format!("vt {}", n.join(" "))),
        2 => prop::collection::vec(number, 3).prop_map(|n| format!("vn {}", n.join(" "))),
        8 => prop::collection::vec(corner, 3..7).prop_map(|c| format!("f {}", c.join(" "))),
        1 => prop_oneof![Just(""), Just("mat a"), Just("mat b"), Just("c d")]
            .prop_map(|m| format!("usemtl {m}")),
        1 => Just("mtllib lib one.mtl".to_string()),
        1 => Just("# a comment v 1 2 3".to_string()),
        1 => Just("g group".to_string()),
        1 => Just(String::new()),
    ]
}

/// A file: 8 positions first (faces may use any of them), then the lines,
/// with a bad line somewhere now and then, and mixed line endings.
fn file() -> impl Strategy<Value = String> {
    let bad = prop_oneof![
        Just("v 1 x 2"),
        Just("f 1 2 99"),
        Just("f 1/a 2 3"),
        Just("vn 1 2"),
        Just("v 1 2 3 0"),
    ];
    (
        prop::collection::vec(line(), 1..120),
        prop::option::weighted(0.3, (bad, any::<prop::sample::Index>())),
        prop::collection::vec(prop_oneof![Just("\n"), Just("\r\n"), Just("\r")], 1..4),
    )
        .prop_map(|(mut lines, bad, endings)| {
            let mut text = String::new();
            for k in 0..8 {
                text += &format!("v {} {} {}\n", k & 1, (k >> 1) & 1, (k >> 2) & 1);
            }
            if let Some((bad, at)) = bad {
                let i = at.index(lines.len() + 1);
                lines.insert(i, bad.to_string());
            }
            for (k, l) in lines.iter().enumerate() {
                text += l;
                text += endings[k % endings.len()];
            }
            text
        })
}

/// The parts (mesh and material), the warnings, or the error.
fn summary(model: Result<LoadedModel, ObjError>) -> Result<String, ObjError> {
    model.map(|m| {
        let parts: Vec<String> = m
            .parts
            .iter()
            .map(|p| format!("{:?} {:?}", p.material, p.mesh))
            .collect();
        format!("{parts:?} {:?}", m.warnings)
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 200, ..ProptestConfig::default() })]

    #[test]
    fn any_cut_reads_the_same_model(text in file(), chunks in 2usize..13) {
        let one = summary(parse_in_chunks("random.obj", text.as_bytes(), None, Some(1)));
        let cut = summary(parse_in_chunks("random.obj", text.as_bytes(), None, Some(chunks)));
        prop_assert_eq!(one, cut);
    }
}

/// Hand-made cuts: a chunk ending in `\r` of a `\r\n`, a chunk of one
/// `usemtl` line, faces whose positions are all in earlier chunks, and a
/// negative index reaching back across a cut.
#[test]
fn cuts_inside_parts_and_line_endings_read_the_same() {
    let mut text = String::new();
    for k in 0..8 {
        text += &format!("v {} {} {}\r\n", k & 1, (k >> 1) & 1, (k >> 2) & 1);
    }
    text += "usemtl a\r\nf 1 2 4\r\nusemtl b\nf -1 -2 -3\rf 5 6 8 7\nusemtl a\nf 1 3 4\nvt 0 1\nf 2/1 3/2 4/1\n";
    let one = summary(parse_in_chunks("cut.obj", text.as_bytes(), None, Some(1)));
    assert!(one.is_ok(), "{one:?}");
    for chunks in 1..=text.len() {
        let cut = summary(parse_in_chunks(
            "cut.obj",
            text.as_bytes(),
            None,
            Some(chunks),
        ));
        assert_eq!(one, cut, "{chunks} chunks");
    }
}

/// A grid of `n × n` quads as OBJ text.
fn grid(n: usize) -> String {
    let mut s = String::new();
    for j in 0..=n {
        for i in 0..=n {
            s += &format!("v {i} {j} {}\n", (i * j % 7) as f32 / 10.0);
        }
    }
    let at = |i: usize, j: usize| j * (n + 1) + i + 1;
    for j in 0..n {
        for i in 0..n {
            s += &format!(
                "f {} {} {} {}\n",
                at(i, j),
                at(i + 1, j),
                at(i + 1, j + 1),
                at(i, j + 1)
            );
        }
    }
    s
}

#[test]
fn a_load_reports_each_pass_over_each_chunk_then_each_build_step() {
    use relief_scene::load_progress::{LoadProgress, LoadStep, run_with};
    let text = grid(40);
    let p = LoadProgress::new();
    let model = run_with(&p, || {
        parse_in_chunks("grid.obj", text.as_bytes(), None, Some(5))
    });
    assert!(model.is_ok());
    // The reading's passes are over (a cancelled load below shows their
    // count); the build ran its seven steps.
    let now = p.now();
    assert_eq!((now.step, now.done, now.total), (LoadStep::Building, 6, 6));
}

#[test]
fn a_cancelled_load_stops_with_an_error_naming_the_model() {
    use relief_scene::load_progress::{LoadProgress, LoadStep, run_with};
    let text = grid(40);
    let p = LoadProgress::new();
    p.cancel();
    let got = run_with(&p, || {
        parse_in_chunks("grid.obj", text.as_bytes(), None, Some(5))
    });
    assert_eq!(
        got.err(),
        Some(ObjError::Cancelled {
            name: "grid.obj".into()
        })
    );
    // It stopped after the first pass: the counting.
    let now = p.now();
    assert_eq!(now.step, LoadStep::Parsing);
    assert_eq!(
        (now.done, now.total),
        (text.len() as u64, 3 * text.len() as u64)
    );
}
