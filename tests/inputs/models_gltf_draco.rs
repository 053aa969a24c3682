//! `KHR_draco_mesh_compression`: a GLB whose primitive is one Draco
//! stream (written by the `draco-core` crate's encoder) reads as
//! its plain twin; a broken or lying stream is refused in one sentence;
//! and the Khronos Duck's Draco twin reads as the Duck (needs `../shared`).

use std::path::Path;

use relief_scene::gltf::{Model, load};

use super::models_gltf::{glb, load_ok, refused, write};

use super::octahedron::{FACES, POINTS, uv};

/// The octahedron as one Draco stream: POSITION (id 0), NORMAL (id 1,
/// the point's own direction), TEXCOORD_0 (id 2), as the `draco-core`
/// crate's encoder writes it with its default options
/// (`tools/draco-octahedron` made the file; `cargo run --manifest-path
/// tools/draco-octahedron/Cargo.toml > tests/data/octahedron.drc` makes it
/// again). Kept as a file so that no test build needs the encoder, whose
/// feature would make `cargo test` build the scene and everything above it
/// a second time after `cargo build`.
fn octahedron_stream() -> Vec<u8> {
    include_bytes!("../data/octahedron.drc").to_vec()
}

/// A GLB of `stream` as the Draco data of one primitive whose accessors
/// declare `points` points and `corners` indices and have no bufferView.
fn draco_glb(stream: &[u8], points: usize, corners: usize) -> Vec<u8> {
    let ext = r#"{"bufferView":0,"attributes":{"POSITION":0,"NORMAL":1,"TEXCOORD_0":2}}"#;
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},"extensionsUsed":["KHR_draco_mesh_compression"],
"extensionsRequired":["KHR_draco_mesh_compression"],"scene":0,"scenes":[{{"nodes":[0]}}],
"nodes":[{{"mesh":0}}],"meshes":[{{"primitives":[{{"attributes":{{"POSITION":0,"NORMAL":1,"TEXCOORD_0":2}},
"indices":3,"extensions":{{"KHR_draco_mesh_compression":{ext}}}}}]}}],
"accessors":[{{"componentType":5126,"count":{points},"type":"VEC3","min":[-1,-1,-1],"max":[1,1,1]}},
{{"componentType":5126,"count":{points},"type":"VEC3"}},{{"componentType":5126,"count":{points},"type":"VEC2"}},
{{"componentType":5123,"count":{corners},"type":"SCALAR"}}],
"bufferViews":[{{"buffer":0,"byteOffset":0,"byteLength":{}}}],"buffers":[{{"byteLength":{}}}]}}"#,
        stream.len(),
        stream.len()
    );
    glb(&json, stream)
}

/// The octahedron written plainly (float accessors, short indices).
pub(super) fn plain_glb() -> Vec<u8> {
    let mut bin = crate::glb_writer::Bin::default();
    let flat: Vec<f32> = POINTS.iter().flatten().copied().collect();
    let uvs: Vec<f32> = POINTS.iter().flat_map(|&p| uv(p)).collect();
    let position = bin.positions(&flat);
    let normal = bin.floats(&flat, "VEC3");
    let texcoord = bin.floats(&uvs, "VEC2");
    let faces: Vec<u16> = FACES.iter().flatten().map(|&i| i as u16).collect();
    let indices = bin.shorts(&faces, "SCALAR");
    bin.glb(&format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0}}],
"meshes":[{{"primitives":[{{"attributes":{{"POSITION":{position},"NORMAL":{normal},"TEXCOORD_0":{texcoord}}},"indices":{indices}}}]}}]"#
    ))
}

/// Every triangle of the model as its corners' position, normal and
/// texture coordinate, each triangle turned to start at its least corner
/// (keeping its winding), the list sorted: the same for two files that
/// number their points differently.
pub(super) fn triangles(model: &Model) -> Vec<[[f32; 8]; 3]> {
    let mut all = Vec::new();
    for part in &model.parts {
        let v = &part.mesh.vertices;
        for t in &part.mesh.triangles {
            let c = t.indices.map(|i| {
                let x = &v[i as usize];
                let (p, n, uv) = (x.position, x.normal, x.uv);
                [p.x, p.y, p.z, n.x, n.y, n.z, uv.x, uv.y]
            });
            let least = (0..3)
                .min_by(|&a, &b| c[a].partial_cmp(&c[b]).unwrap())
                .unwrap();
            all.push([c[least], c[(least + 1) % 3], c[(least + 2) % 3]]);
        }
    }
    all.sort_by(|a, b| a.partial_cmp(b).unwrap());
    all
}

/// The two lists hold the same triangles, each number within `tolerance`.
pub(super) fn assert_same_triangles(a: &[[[f32; 8]; 3]], b: &[[[f32; 8]; 3]], tolerance: f32) {
    assert_eq!(a.len(), b.len());
    for (s, t) in a.iter().zip(b) {
        for (x, y) in s.iter().flatten().zip(t.iter().flatten()) {
            assert!((x - y).abs() <= tolerance, "{s:?} against {t:?}");
        }
    }
}

#[test]
fn a_draco_octahedron_reads_as_its_plain_twin() {
    let stream = octahedron_stream();
    let draco = load_ok(&write("draco", "draco.glb", &draco_glb(&stream, 6, 24)));
    let plain = load_ok(&write("draco", "plain.glb", &plain_glb()));
    let got = triangles(&draco);
    assert_eq!(got.len(), 8);
    assert_same_triangles(&got, &triangles(&plain), 1e-5);
    assert!(draco.warnings.is_empty(), "{:?}", draco.warnings);
}

#[test]
fn a_broken_draco_stream_is_refused_in_one_sentence() {
    let stream = octahedron_stream();
    let cut = &stream[..stream.len() / 2];
    let m = refused("draco-cut", &draco_glb(cut, 6, 24));
    assert!(
        m.contains("meshes[0].primitives[0]: its Draco data cannot be decoded"),
        "{m}"
    );
    // Accessors that declare fewer points than the stream holds: the
    // decoder's limit, not the stream, decides what is allocated.
    let m = refused("draco-lying", &draco_glb(&stream, 2, 24));
    assert!(m.contains("its Draco data cannot be decoded"), "{m}");
    // Every cut of the stream is refused or read, never a panic (which
    // `load` would contain and report as the reader failing).
    for end in 0..stream.len() {
        let path = write("draco-cuts", "cut.glb", &draco_glb(&stream[..end], 6, 24));
        if let Err(e) = load(&path) {
            assert!(!e.to_string().contains("reader failed"), "{end}: {e}");
        }
    }
}

/// The Khronos Duck and its Draco twin (`../shared/testdata/khronos/Duck`):
/// the same 4,212 triangles; each of the Duck's has a Draco twin whose
/// corners lie within a thousandth of the duck's size (its positions are
/// quantised; fitted to radius 1.5, the duck is about 2 across), with
/// normals within 0.02 a component (about a degree) and texture
/// coordinates within 1 %.
#[test]
#[ignore = "needs ../shared: run by name by .ci/run"]
fn the_draco_duck_reads_as_the_duck() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/testdata/khronos/Duck");
    let plain = triangles(&load_ok(&dir.join("Duck.glb")));
    let draco = triangles(&load_ok(&dir.join("glTF-Draco/Duck.gltf")));
    assert_eq!(plain.len(), 4212);
    assert_eq!(plain.len(), draco.len());
    let gap = |s: &[[f32; 8]; 3], t: &[[f32; 8]; 3], k: std::ops::Range<usize>| {
        (0..3)
            .flat_map(|c| k.clone().map(move |i| (s[c][i] - t[c][i]).abs()))
            .fold(0.0f32, f32::max)
    };
    let (mut positions, mut normals, mut uvs) = (0.0f32, 0.0f32, 0.0f32);
    for s in &plain {
        // Its nearest Draco triangle, in every turn of its corners.
        let (t, d) = draco
            .iter()
            .flat_map(|t| (0..3).map(move |r| [t[r], t[(r + 1) % 3], t[(r + 2) % 3]]))
            .map(|t| (t, gap(s, &t, 0..3)))
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .unwrap();
        positions = positions.max(d);
        normals = normals.max(gap(s, &t, 3..6));
        uvs = uvs.max(gap(s, &t, 6..8));
    }
    let found = format!("positions {positions}, normals {normals}, uvs {uvs}");
    assert!(positions < 2e-3 && normals < 2e-2 && uvs < 1e-2, "{found}");
}
