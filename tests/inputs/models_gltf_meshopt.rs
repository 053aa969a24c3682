//! `EXT_meshopt_compression` and `KHR_meshopt_compression`: the
//! octahedron of the Draco tests with its positions, normals and indices
//! in compressed bufferViews (the streams of tests/data/meshopt, written by
//! `tools/meshopt-streams` with the meshoptimizer-rs encoders) over a
//! fallback buffer that holds no bytes, read as its plain twin; a broken
//! stream refused in one sentence.

use super::meshopt_streams::named;
use super::models_gltf::{glb, load_ok, refused, write};
use super::models_gltf_draco::{assert_same_triangles, plain_glb, triangles};
use super::octahedron::{FACES, POINTS};

/// One compressed view: its stream, the element count and stride, the
/// mode and filter.
struct Packed {
    stream: Vec<u8>,
    count: usize,
    stride: usize,
    mode: String,
    filter: String,
}

/// The octahedron's positions, normals (octahedral, 8 bits, stride 4)
/// and texture coordinates by the vertex codec (`version`), its indices
/// by the index codec.
fn packed(version: u8) -> Vec<Packed> {
    let view = |name: String| {
        let c = named(&name);
        Packed {
            stream: c.stream,
            count: c.count,
            stride: c.stride,
            mode: c.mode_name,
            filter: c.filter_name,
        }
    };
    let vertices =
        ["positions", "normals", "uvs"].map(|a| view(format!("octahedron_{a}_v{version}")));
    let mut views: Vec<Packed> = vertices.into();
    views.push(view("octahedron_indices".into()));
    views
}

/// A GLB whose binary chunk holds the streams and whose second buffer is
/// the fallback, without bytes.
fn meshopt_glb(views: &[Packed], extension: &str) -> Vec<u8> {
    let (mut bin, mut json_views, mut fallback) = (Vec::new(), Vec::new(), 0);
    for v in views {
        let length = v.count * v.stride;
        let stride = match v.mode.as_str() {
            "ATTRIBUTES" => format!(r#","byteStride":{}"#, v.stride),
            _ => String::new(),
        };
        json_views.push(format!(
            r#"{{"buffer":1,"byteOffset":{fallback},"byteLength":{length}{stride},"extensions":{{"{extension}":{{"buffer":0,"byteOffset":{},"byteLength":{},"byteStride":{},"count":{},"mode":"{}","filter":"{}"}}}}}}"#,
            bin.len(),
            v.stream.len(),
            v.stride,
            v.count,
            v.mode,
            v.filter
        ));
        bin.extend_from_slice(&v.stream);
        bin.resize(bin.len().next_multiple_of(4), 0);
        fallback += length.next_multiple_of(4);
    }
    let n = POINTS.len();
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},"extensionsUsed":["{extension}","KHR_mesh_quantization"],
"extensionsRequired":["{extension}","KHR_mesh_quantization"],"scene":0,"scenes":[{{"nodes":[0]}}],
"nodes":[{{"mesh":0}}],"meshes":[{{"primitives":[{{"attributes":{{"POSITION":0,"NORMAL":1,"TEXCOORD_0":2}},"indices":3}}]}}],
"accessors":[{{"bufferView":0,"componentType":5126,"count":{n},"type":"VEC3","min":[-1,-1,-1],"max":[1,1,1]}},
{{"bufferView":1,"componentType":5120,"normalized":true,"count":{n},"type":"VEC3"}},
{{"bufferView":2,"componentType":5126,"count":{n},"type":"VEC2"}},
{{"bufferView":3,"componentType":5123,"count":{},"type":"SCALAR"}}],
"bufferViews":[{}],
"buffers":[{{"byteLength":{}}},{{"byteLength":{fallback},"extensions":{{"{extension}":{{"fallback":true}}}}}}]}}"#,
        FACES.len() * 3,
        json_views.join(","),
        bin.len()
    );
    glb(&json, &bin)
}

/// Read, the compressed octahedron has the plain one's triangles:
/// positions and texture coordinates exactly, normals within the
/// octahedral 8-bit step (the axes come back exact: 1e-2 is generous).
#[test]
fn a_meshopt_octahedron_reads_as_its_plain_twin() {
    let plain = triangles(&load_ok(&write("meshopt", "plain.glb", &plain_glb())));
    for (extension, version) in [
        ("EXT_meshopt_compression", 0),
        ("KHR_meshopt_compression", 1),
    ] {
        let bytes = meshopt_glb(&packed(version), extension);
        let model = load_ok(&write("meshopt", "packed.glb", &bytes));
        assert!(model.warnings.is_empty(), "{:?}", model.warnings);
        assert_same_triangles(&triangles(&model), &plain, 1e-2);
        let exact = |range: std::ops::Range<usize>| {
            triangles(&model)
                .iter()
                .zip(&plain)
                .all(|(s, t)| (0..3).all(|c| range.clone().all(|i| s[c][i] == t[c][i])))
        };
        assert!(exact(0..3) && exact(6..8), "{extension}");
    }
}

#[test]
fn a_broken_meshopt_stream_is_refused_in_one_sentence() {
    let mut views = packed(0);
    let cut = views[0].stream.len() / 2;
    views[0].stream.truncate(cut);
    let m = refused(
        "meshopt-cut",
        &meshopt_glb(&views, "EXT_meshopt_compression"),
    );
    assert!(
        m.contains("bufferViews[0]: its meshopt data cannot be decoded"),
        "{m}"
    );
    let mut views = packed(0);
    views[1].filter = "SPIRAL".into();
    let m = refused(
        "meshopt-filter",
        &meshopt_glb(&views, "EXT_meshopt_compression"),
    );
    assert!(
        m.contains("the filter 'SPIRAL' is not one relief reads"),
        "{m}"
    );
    // Every cut of every stream is refused or read, never a panic (which
    // `load` would contain and report as the reader failing).
    for k in 0..4 {
        for end in 0..packed(0)[k].stream.len() {
            let mut views = packed(0);
            views[k].stream.truncate(end);
            let bytes = meshopt_glb(&views, "EXT_meshopt_compression");
            let path = write("meshopt-cuts", "cut.glb", &bytes);
            if let Err(e) = relief_scene::gltf::load(&path) {
                assert!(!e.to_string().contains("reader failed"), "{k} {end}: {e}");
            }
        }
    }
}
