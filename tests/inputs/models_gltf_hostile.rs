//! glTF files that a fuzzing run of relief found crashing it, panicking in
//! a reader or refused although valid, each written here: every one is
//! drawn when it is valid, else refused with one plain sentence.

use super::models_gltf::{
    Doc, Prim, covered, dot3, encode, good, json_fix, load_ok, materials_with_normal, quad,
    refused, render, scene_of, tilted_map, write,
};

/// What a caught panic or a leaked internal looks like in a message.
const INTERNALS: &[&str] = &[
    "panicked",
    "unreachable",
    "index out of bounds",
    "unwrap",
    "assertion",
    "the reader failed",
    "TexCoords(",
    "Positions",
];

/// The message for a refused file: plain, naming the place.
fn refused_plainly(test: &str, bytes: &[u8], place: &str) -> String {
    let m = refused(test, bytes);
    for word in INTERNALS {
        assert!(!m.contains(word), "{test}: {m}");
    }
    assert!(m.contains(place), "{test}: {m}");
    m
}

/// A normal-mapped document (no TANGENT: relief makes them) of `prims`.
fn normal_mapped(prims: Vec<Prim>) -> Doc {
    let mut doc = Doc::new(
        prims
            .into_iter()
            .map(|p| Prim {
                material: Some(0),
                ..p
            })
            .collect(),
    );
    doc.materials = materials_with_normal(None);
    doc.images = vec![tilted_map()];
    doc
}

/// `count` triangles whose corners are all one point.
fn repeated_point(count: usize) -> Prim {
    Prim {
        pos: vec![[0.0, 0.0, 1.0]; 3],
        nrm: vec![[0.0, 0.0, 1.0]; 3],
        uv: vec![[0.5, 0.5]; 3],
        idx: (0..3 * count).map(|i| (i % 3) as u16).collect(),
        ..Default::default()
    }
}

/// Normal-mapped primitives whose triangles repeat one point made the
/// tangent generator fault (1,000 of them) or read memory it does not own
/// (one): beside a quad, the quad is drawn; alone, the file is refused
/// in plain words.
#[test]
fn a_normal_mapped_primitive_of_repeated_points_never_reaches_the_tangent_generator() {
    for count in [1, 1000] {
        let test = format!("repeated-{count}");
        let doc = normal_mapped(vec![repeated_point(count), good().prims.remove(0)]);
        let model = load_ok(&write(&test, "ok.glb", &encode(&doc)));
        assert!(covered(&render(&scene_of(model), &dot3())) > 0, "{test}");

        let alone = normal_mapped(vec![repeated_point(count)]);
        let m = refused_plainly(&format!("{test}-alone"), &encode(&alone), "bad.glb");
        assert!(m.ends_with("all its points coincide"), "{m}");
    }
}

/// A second node showing the normal-mapped mesh at scale 0 (valid glTF, a
/// way to hide a part) was refused: now the picture is that of the one
/// visible node (the quad is centred, so the fit is the same).
#[test]
fn a_node_at_scale_zero_hides_its_instance() {
    let one = normal_mapped(vec![quad(-1.0, 1.0, -0.5, 0.5, 0.0, 1.0)]);
    let mut two = normal_mapped(vec![quad(-1.0, 1.0, -0.5, 0.5, 0.0, 1.0)]);
    two.nodes = r#"[{"children":[1,2]},{"mesh":0},{"mesh":0,"scale":[0,0,0]}]"#.into();
    let draw = |test: &str, doc: &Doc| {
        let model = load_ok(&write(test, "m.glb", &encode(doc)));
        render(&scene_of(model), &dot3())
    };
    let (a, b) = (draw("scale-one", &one), draw("scale-zero", &two));
    assert!(covered(&a) > 0);
    assert_eq!(a.pixels(), b.pixels());
}

/// Files the `gltf` crate panicked on, or reached code it marks
/// unreachable: one plain sentence naming the place.
#[test]
fn invalid_accessors_are_refused_in_plain_words() {
    // The quad's accessors: 0 POSITION, 1 NORMAL, 2 TEXCOORD_0, 3 indices.
    let cases = [
        (
            "position-99",
            r#""POSITION":0"#,
            r#""POSITION":99"#,
            "POSITION names accessors[99]",
        ),
        (
            "no-accessors",
            r#""accessors":["#,
            r#""accessorz":["#,
            "but the file has no accessors",
        ),
        (
            "indices-short",
            r#""componentType":5123"#,
            r#""componentType":5122"#,
            "indices cannot be SCALAR of signed shorts",
        ),
        (
            "indices-vec3",
            r#""indices":3"#,
            r#""indices":0"#,
            "indices cannot be VEC3 of floats",
        ),
        (
            "stride-4",
            r#"{"buffer":0,"byteOffset":0,"#,
            r#"{"buffer":0,"byteStride":4,"byteOffset":0,"#,
            "byteStride 4 is shorter than one element (12 bytes)",
        ),
        (
            "texcoord-past-view",
            r#""count":4,"type":"VEC2""#,
            r#""count":400,"type":"VEC2""#,
            "TEXCOORD_0 of meshes[0].primitives[0]",
        ),
    ];
    for (test, from, to, says) in cases {
        let bytes = json_fix(encode(&good()), from, to);
        refused_plainly(test, &bytes, says);
    }
}

/// An image in a bufferView without its (required) MIME type is decoded
/// by its bytes, as an image file is.
#[test]
fn an_embedded_image_without_a_mime_type_is_read_by_its_bytes() {
    let doc = normal_mapped(vec![quad(-1.0, 1.0, -0.5, 0.5, 0.0, 1.0)]);
    let bytes = json_fix(encode(&doc), r#","mimeType":"image/png""#, "");
    let model = load_ok(&write("no-mime", "m.glb", &bytes));
    let with_mime = load_ok(&write("mime", "m.glb", &encode(&doc)));
    let (a, b) = (scene_of(model), scene_of(with_mime));
    assert_eq!(render(&a, &dot3()).pixels(), render(&b, &dot3()).pixels());
}

/// Extensions relief reads may be required; one it does not read refuses
/// the file, by name.
#[test]
fn required_extensions_that_relief_reads_are_accepted() {
    for ext in ["KHR_texture_transform", "KHR_materials_emissive_strength"] {
        let mut doc = good();
        doc.extra = format!(r#","extensionsUsed":["{ext}"],"extensionsRequired":["{ext}"]"#);
        load_ok(&write(ext, "m.glb", &encode(&doc)));
    }
    let mut doc = good();
    doc.extra = r#","extensionsUsed":["EXT_unknown"],"extensionsRequired":["EXT_unknown"]"#.into();
    refused_plainly("unknown-ext", &encode(&doc), "'EXT_unknown'");
}

/// The JSON and binary chunk of a GLB, the JSON's buffer given `uri`.
fn split_with_uri(glb: &[u8], uri: &str) -> (String, Vec<u8>) {
    let json_len = u32::from_le_bytes(glb[12..16].try_into().unwrap()) as usize;
    let json = std::str::from_utf8(&glb[20..20 + json_len]).unwrap();
    let json = json.trim_end().replacen(
        r#""buffers":[{"byteLength":"#,
        &format!(r#""buffers":[{{"uri":"{uri}","byteLength":"#),
        1,
    );
    let bin_at = 20 + json_len;
    let bin_len = u32::from_le_bytes(glb[bin_at..bin_at + 4].try_into().unwrap()) as usize;
    (json, glb[bin_at + 8..bin_at + 8 + bin_len].to_vec())
}

/// A buffer URI is read inside the model's folder only: one that is
/// absolute, climbs out with `../` or goes through a link that leads out
/// is refused (a file from the internet could read any file otherwise).
#[test]
fn buffer_uris_stay_inside_the_models_folder() {
    let root = write("uris", "outside.bin", b"")
        .parent()
        .unwrap()
        .to_path_buf();
    let (_, bin) = split_with_uri(&encode(&good()), "");
    std::fs::write(root.join("outside.bin"), &bin).unwrap();
    let dir = root.join("model");
    std::fs::create_dir_all(dir.join("sub")).unwrap();
    std::fs::write(dir.join("inside.bin"), &bin).unwrap();
    let _ = std::fs::remove_file(dir.join("link.bin"));
    std::os::unix::fs::symlink(root.join("outside.bin"), dir.join("link.bin")).unwrap();
    let outside = root.join("outside.bin");
    let absolute = outside.to_str().unwrap();
    let try_uri = |uri: &str| {
        let (json, _) = split_with_uri(&encode(&good()), uri);
        let path = dir.join("m.gltf");
        std::fs::write(&path, json).unwrap();
        relief_scene::gltf::load(&path)
            .map(|_| ())
            .map_err(|e| e.to_string())
    };
    assert_eq!(try_uri("inside.bin"), Ok(()));
    assert_eq!(try_uri("sub/../inside.bin"), Ok(()));
    assert_eq!(try_uri("./sub/..%2Finside.bin"), Ok(()));
    for uri in [
        "../outside.bin",
        "sub/../../outside.bin",
        absolute,
        "link.bin",
        "..%2Foutside.bin",
    ] {
        let m = try_uri(uri).expect_err(uri);
        assert!(
            m.contains("points outside the model's folder"),
            "{uri}: {m}"
        );
    }
}
