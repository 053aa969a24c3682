//! glTF accessors as real tools write them: sparse accessors (core glTF)
//! and `KHR_mesh_quantization`'s integer attributes, read equal to their
//! plain float twins; and the one line naming what a file has that relief
//! draws without. The GLBs are written here.

use std::process::Command;

use glam::Vec3;
use relief_scene::corners::FIT_RADIUS;
use relief_scene::gltf::{Model, load};

use super::models_gltf::{glb, load_ok, refused, write};

/// One accessor as written: its bytes (after padding to 4), component
/// type, element type, whether normalized, its bufferView's byteStride,
/// and a sparse part if any.
#[derive(Clone, Default)]
struct Acc {
    bytes: Vec<u8>,
    ct: u32,
    ty: &'static str,
    count: usize,
    normalized: bool,
    stride: Option<usize>,
    /// No bufferView: the base is zeros.
    no_view: bool,
    /// Sparse: index component type, index bytes, value bytes, count.
    sparse: Option<(u32, Vec<u8>, Vec<u8>, usize)>,
}

fn f32s(v: &[[f32; 3]]) -> Vec<u8> {
    v.iter().flatten().flat_map(|f| f.to_le_bytes()).collect()
}

fn floats(v: &[[f32; 3]]) -> Acc {
    Acc {
        bytes: f32s(v),
        ct: 5126,
        ty: "VEC3",
        count: v.len(),
        ..Acc::default()
    }
}

/// A GLB of one quad primitive (indices 0 1 2, 0 2 3) with these
/// attributes, its node `node` (JSON) and `extra` top-level JSON.
fn quad_glb(attributes: &[(&str, Acc)], node: &str, extra: &str) -> Vec<u8> {
    let idx: Vec<u8> = [0u16, 1, 2, 0, 2, 3]
        .iter()
        .flat_map(|i| i.to_le_bytes())
        .collect();
    let indices = Acc {
        bytes: idx,
        ct: 5123,
        ty: "SCALAR",
        count: 6,
        ..Acc::default()
    };
    quad_glb_indexed(attributes, &indices, node, extra)
}

/// [`quad_glb`] with its indices' accessor written as `indices` says.
fn quad_glb_indexed(attributes: &[(&str, Acc)], indices: &Acc, node: &str, extra: &str) -> Vec<u8> {
    let mut bin: Vec<u8> = Vec::new();
    let mut views = Vec::new();
    let mut view = |bin: &mut Vec<u8>, bytes: &[u8], stride: Option<usize>| {
        while !bin.len().is_multiple_of(4) {
            bin.push(0);
        }
        let stride = stride.map_or(String::new(), |s| format!(r#","byteStride":{s}"#));
        views.push(format!(
            r#"{{"buffer":0,"byteOffset":{},"byteLength":{}{stride}}}"#,
            bin.len(),
            bytes.len()
        ));
        bin.extend_from_slice(bytes);
        views.len() - 1
    };
    let mut accessors = Vec::new();
    let mut attrs = Vec::new();
    for (name, a) in attributes.iter().chain([&("", indices.clone())]) {
        let base = if a.no_view {
            String::new()
        } else {
            format!(r#","bufferView":{}"#, view(&mut bin, &a.bytes, a.stride))
        };
        let sparse = a.sparse.as_ref().map_or(String::new(), |(ict, idx, val, n)| {
            let i = view(&mut bin, idx, None);
            let v = view(&mut bin, val, None);
            format!(
                r#","sparse":{{"count":{n},"indices":{{"bufferView":{i},"componentType":{ict}}},"values":{{"bufferView":{v}}}}}"#
            )
        });
        let minmax = if *name == "POSITION" {
            r#","min":[-100,-100,-100],"max":[100,100,100]"#
        } else {
            ""
        };
        accessors.push(format!(
            r#"{{"componentType":{},"count":{},"type":"{}","normalized":{}{base}{sparse}{minmax}}}"#,
            a.ct, a.count, a.ty, a.normalized
        ));
        if !name.is_empty() {
            attrs.push(format!(r#""{name}":{}"#, accessors.len() - 1));
        }
    }
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{node}],"meshes":[{{"primitives":[{{"attributes":{{{}}},"indices":{}}}]}}],"accessors":[{}],"bufferViews":[{}],"buffers":[{{"byteLength":{}}}]{extra}}}"#,
        attrs.join(","),
        accessors.len() - 1,
        accessors.join(","),
        views.join(","),
        bin.len().next_multiple_of(4)
    );
    glb(&json, &bin)
}

/// The quad the sparse and quantized files describe, in floats.
const QUAD: [[f32; 3]; 4] = [
    [0.0, 0.0, 0.0],
    [3.0, 0.0, 0.0],
    [1.0, 1.0, 0.0],
    [0.0, 2.0, 0.0],
];
const UP: [[f32; 3]; 4] = [[0.0, 0.0, 1.0]; 4];

fn positions(model: &Model) -> Vec<Vec3> {
    let mesh = &model.parts[0].mesh;
    mesh.vertices.iter().map(|v| v.position).collect()
}

fn twin(test: &str) -> Model {
    let bytes = quad_glb(
        &[("POSITION", floats(&QUAD)), ("NORMAL", floats(&UP))],
        r#"{"mesh":0}"#,
        "",
    );
    load_ok(&write(test, "twin.glb", &bytes))
}

/// A sparse POSITION accessor: the base square (0,0) (1,0) (1,1) (0,1)
/// with points 1 and 3 replaced by (3,0) and (0,2). Read, the positions
/// are the float twin's, and by hand: the box's centre is (1.5, 1, 0) and
/// the farthest points (0,0), (3,0), (0,2) lie √3.25 from it, so each point
/// p is (p − c)·1.5/√3.25.
#[test]
fn a_sparse_position_accessor_reads_its_substitutions() {
    let base = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
    ];
    let indices: Vec<u8> = [1u16, 3].iter().flat_map(|i| i.to_le_bytes()).collect();
    let sparse = Acc {
        sparse: Some((5123, indices, f32s(&[QUAD[1], QUAD[3]]), 2)),
        ..floats(&base)
    };
    let bytes = quad_glb(
        &[("POSITION", sparse), ("NORMAL", floats(&UP))],
        r#"{"mesh":0}"#,
        "",
    );
    let model = load_ok(&write("sparse", "sparse.glb", &bytes));
    let got = positions(&model);
    assert_eq!(got, positions(&twin("sparse")));
    let (c, s) = (Vec3::new(1.5, 1.0, 0.0), FIT_RADIUS / 3.25f32.sqrt());
    for (p, q) in got.iter().zip(QUAD) {
        let want = (Vec3::from(q) - c) * s;
        assert!((*p - want).length() < 1e-5, "{p} against {want}");
    }
    // Without a bufferView the base is zeros: all four points replaced.
    let indices: Vec<u8> = (0u8..4).collect();
    let zeros = Acc {
        no_view: true,
        sparse: Some((5121, indices, f32s(&QUAD), 4)),
        ..floats(&base)
    };
    let bytes = quad_glb(
        &[("POSITION", zeros), ("NORMAL", floats(&UP))],
        r#"{"mesh":0}"#,
        "",
    );
    let model = load_ok(&write("sparse", "zeros.glb", &bytes));
    assert_eq!(positions(&model), positions(&twin("sparse-zeros")));
    // Indices out of order are refused, naming the place.
    let indices: Vec<u8> = [3u16, 1].iter().flat_map(|i| i.to_le_bytes()).collect();
    let unordered = Acc {
        sparse: Some((5123, indices, f32s(&[QUAD[3], QUAD[1]]), 2)),
        ..floats(&base)
    };
    let bytes = quad_glb(
        &[("POSITION", unordered), ("NORMAL", floats(&UP))],
        r#"{"mesh":0}"#,
        "",
    );
    let m = refused("sparse-order", &bytes);
    assert!(
        m.contains("accessors[0]") && m.contains("sparse index 1 (1) does not follow"),
        "{m}"
    );
}

/// The quad's indices as unsigned bytes, shorts and ints, and as bytes
/// 0 1 2 0 1 2 with a sparse part replacing the last two by 2 and 3 (and
/// as no bufferView at all, zeros, with all six replaced): every file has
/// the twin's triangles, 0 1 2 and 0 2 3.
#[test]
fn index_accessors_of_every_unsigned_type_and_sparse_read_as_their_twin() {
    let quad = [0u32, 1, 2, 0, 2, 3];
    let acc = |ct: u32, bytes: Vec<u8>| Acc {
        bytes,
        ct,
        ty: "SCALAR",
        count: 6,
        ..Acc::default()
    };
    let u8s = |v: &[u32]| v.iter().map(|&i| i as u8).collect::<Vec<u8>>();
    let u16s = |v: &[u32]| v.iter().flat_map(|&i| (i as u16).to_le_bytes()).collect();
    let u32s = |v: &[u32]| v.iter().flat_map(|&i| i.to_le_bytes()).collect();
    let cases = [
        ("u8", acc(5121, u8s(&quad))),
        ("u16", acc(5123, u16s(&quad))),
        ("u32", acc(5125, u32s(&quad))),
        (
            "sparse",
            Acc {
                sparse: Some((5121, vec![4, 5], u8s(&[2, 3]), 2)),
                ..acc(5121, u8s(&[0, 1, 2, 0, 1, 2]))
            },
        ),
        (
            "sparse-u32",
            Acc {
                sparse: Some((5125, u32s(&[4, 5]), u32s(&[2, 3]), 2)),
                ..acc(5125, u32s(&[0, 1, 2, 0, 1, 2]))
            },
        ),
        (
            "sparse-zeros",
            Acc {
                no_view: true,
                sparse: Some((5123, u16s(&[0, 1, 2, 3, 4, 5]), u16s(&quad), 6)),
                ..acc(5123, Vec::new())
            },
        ),
    ];
    let twin = twin("index-types");
    let corners = |m: &Model| -> Vec<[u32; 3]> {
        m.parts[0]
            .mesh
            .triangles
            .iter()
            .map(|t| t.indices)
            .collect()
    };
    assert_eq!(corners(&twin).len(), 2);
    for (name, indices) in cases {
        let bytes = quad_glb_indexed(
            &[("POSITION", floats(&QUAD)), ("NORMAL", floats(&UP))],
            &indices,
            r#"{"mesh":0}"#,
            "",
        );
        let model = load_ok(&write("index-types", &format!("{name}.glb"), &bytes));
        assert_eq!(corners(&model), corners(&twin), "{name}");
        assert_eq!(positions(&model), positions(&twin), "{name}");
    }
}

/// KHR_mesh_quantization: positions as signed shorts (twice the quad, the
/// node scaling by ½), normals as normalized signed bytes (stride 4),
/// texture coordinates as normalized unsigned shorts. Read, positions,
/// normals and UVs equal the float twin's.
#[test]
fn a_quantized_quad_reads_as_its_float_twin() {
    let shorts: Vec<u8> = QUAD
        .iter()
        .flatten()
        .flat_map(|&f| ((2.0 * f) as i16).to_le_bytes())
        .collect();
    let position = Acc {
        bytes: shorts,
        ct: 5122,
        ty: "VEC3",
        count: 4,
        ..Acc::default()
    };
    let normal = Acc {
        bytes: [0u8, 0, 127, 0].repeat(4),
        ct: 5120,
        ty: "VEC3",
        count: 4,
        normalized: true,
        stride: Some(4),
        ..Acc::default()
    };
    let uv = |unit: f32, bytes: fn(f32) -> Vec<u8>, ct: u32| Acc {
        bytes: [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]
            .iter()
            .flatten()
            .flat_map(|&f: &f32| bytes(f * unit))
            .collect(),
        ct,
        ty: "VEC2",
        count: 4,
        normalized: ct != 5126,
        ..Acc::default()
    };
    let ext = r#","extensionsUsed":["KHR_mesh_quantization"],"extensionsRequired":["KHR_mesh_quantization"]"#;
    let quantized = quad_glb(
        &[
            ("POSITION", position.clone()),
            ("NORMAL", normal.clone()),
            (
                "TEXCOORD_0",
                uv(65535.0, |f| (f as u16).to_le_bytes().to_vec(), 5123),
            ),
        ],
        r#"{"mesh":0,"scale":[0.5,0.5,0.5]}"#,
        ext,
    );
    let model = load_ok(&write("quantized", "q.glb", &quantized));
    let plain = quad_glb(
        &[
            ("POSITION", floats(&QUAD)),
            ("NORMAL", floats(&UP)),
            ("TEXCOORD_0", uv(1.0, |f| f.to_le_bytes().to_vec(), 5126)),
        ],
        r#"{"mesh":0}"#,
        "",
    );
    let twin = load_ok(&write("quantized", "plain.glb", &plain));
    let (a, b) = (&model.parts[0].mesh.vertices, &twin.parts[0].mesh.vertices);
    assert_eq!(a.len(), b.len());
    for (p, q) in a.iter().zip(b) {
        assert_eq!((p.position, p.normal, p.uv), (q.position, q.normal, q.uv));
    }
    // Without the extension, shorts are no positions glTF allows.
    let bytes = quad_glb(
        &[("POSITION", position), ("NORMAL", normal)],
        r#"{"mesh":0}"#,
        "",
    );
    let m = refused("unquantized", &bytes);
    assert!(
        m.contains("POSITION cannot be VEC3 of signed shorts"),
        "{m}"
    );
}

/// What the file has that relief draws without is named once, in one
/// line: by the loader, and on `relief render`'s standard error.
#[test]
fn what_is_not_drawn_is_named_in_one_line() {
    let ext = r#","extensionsUsed":["KHR_texture_transform","KHR_lights_punctual","KHR_materials_iridescence","KHR_materials_sheen","KHR_materials_transmission"],"cameras":[{"type":"perspective","perspective":{"yfov":0.8,"znear":0.1}}]"#;
    let bytes = quad_glb(
        &[("POSITION", floats(&QUAD)), ("NORMAL", floats(&UP))],
        r#"{"mesh":0}"#,
        ext,
    );
    let path = write("skipped", "lamp.glb", &bytes);
    let model = load(&path).unwrap();
    assert_eq!(model.warnings.len(), 1, "{:?}", model.warnings);
    let line = &model.warnings[0];
    assert!(
        line.contains("the extension KHR_materials_iridescence"),
        "{line}"
    );
    // A perspective camera is read (`V` shows through it).
    assert!(!line.contains("camera"), "{line}");
    // The extensions relief reads are not named.
    for read in [
        "KHR_texture_transform",
        "KHR_lights_punctual",
        "KHR_materials_sheen",
        "KHR_materials_transmission",
    ] {
        assert!(!line.contains(read), "{line}");
    }
    assert!(!line.contains('\n'), "{line}");
    let out = Command::new(env!("CARGO_BIN_EXE_relief"))
        .arg("render")
        .arg(&path)
        .arg("--out")
        .arg(path.with_extension("png"))
        .output()
        .unwrap();
    assert!(out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(stderr.matches("drawn without").count(), 1, "{stderr}");
    // A file with nothing left out says nothing.
    assert!(twin("skipped-none").warnings.is_empty());
}

/// A transmission texture is read on either coordinate set: the line of
/// what is not drawn says nothing of it.
#[test]
fn a_transmission_texture_on_either_set_is_not_named() {
    let png = {
        let img = image::RgbaImage::from_pixel(2, 2, image::Rgba([255, 255, 255, 255]));
        relief_texture::picture::encode(&img.into(), image::ImageFormat::Png).unwrap()
    };
    let glass = |set: u32| {
        let ext = format!(
            r#","extensionsUsed":["KHR_materials_transmission"],"images":[{{"uri":"t.png"}}],"textures":[{{"source":0}}],"materials":[{{"pbrMetallicRoughness":{{"baseColorTexture":{{"index":0}}}},"extensions":{{"KHR_materials_transmission":{{"transmissionFactor":1,"transmissionTexture":{{"index":0,"texCoord":{set}}}}}}}}}]"#
        );
        let bytes = quad_glb(
            &[("POSITION", floats(&QUAD)), ("NORMAL", floats(&UP))],
            r#"{"mesh":0}"#,
            &ext,
        );
        let test = format!("transmission-map-{set}");
        write(&test, "t.png", &png);
        load(&write(&test, "glass.glb", &bytes)).unwrap()
    };
    for set in [0, 1] {
        let model = glass(set);
        assert!(model.warnings.is_empty(), "set {set}: {:?}", model.warnings);
    }
}

/// The model view's picture of the file at `path`, seen and lit head on
/// by one light of 2 and nothing else, no tone map: its centre pixel.
fn lit_head_on(path: std::path::PathBuf) -> [u8; 3] {
    use relief_core::framebuffer::Framebuffer;
    use relief_core::settings::Settings;
    use relief_pipeline::render::Renderer;
    use relief_scene::model_view::{ELEVATION_DEGREES, view_axes};
    use relief_scene::{Built, Light, ModelChoice, SceneKind, build_scene};
    let texture = std::sync::Arc::new(relief_texture::decode::procedural::brick());
    let Ok(Built::Scene(mut scene)) =
        build_scene(SceneKind::Cube, &ModelChoice::File(path), texture, false)
    else {
        panic!("not a scene");
    };
    let [_, _, back] = view_axes();
    scene.lights = vec![Light::new(back * 1e4, Vec3::splat(2.0))];
    scene.ambient = Vec3::ZERO;
    let settings = Settings {
        rotation: Vec3::new(-ELEVATION_DEGREES, 0.0, 0.0),
        tone_map: relief_core::settings::ToneMap::None,
        ..Settings::default()
    };
    let mut fb = Framebuffer::new(120, 90);
    Renderer::new().render(&scene, &settings, &mut fb);
    fb.pixels()[45 * 120 + 60]
}

/// Linear light `x` encoded to an 8-bit sRGB level.
fn srgb8(x: f32) -> i32 {
    let e = if x <= 0.003_130_8 {
        12.92 * x
    } else {
        1.055 * x.powf(1.0 / 2.4) - 0.055
    };
    (e.clamp(0.0, 1.0) * 255.0 + 0.5) as i32
}

/// The unit square facing +Z.
const SQUARE: [[f32; 3]; 4] = [
    [0.0, 0.0, 0.0],
    [1.0, 0.0, 0.0],
    [1.0, 1.0, 0.0],
    [0.0, 1.0, 0.0],
];

/// COLOR_0 is linear, as glTF says: the quad of vertex colour
/// (1, 0.5, 0.25) and no material (glTF's default: white, metal, roughness
/// 1), seen and lit head on under a light of 2 in the model view, gives
/// 2·base/4 = base/2 in linear light (F = F0 = base, D = 1/π, V = 1/4),
/// encoded to sRGB once: the colour is not decoded from sRGB first.
#[test]
fn vertex_colours_are_linear_light() {
    let base = [1.0f32, 0.5, 0.25];
    let colour = Acc {
        bytes: f32s(&[base; 4]),
        ..floats(&[base; 4])
    };
    let bytes = quad_glb(
        &[
            ("POSITION", floats(&SQUARE)),
            ("NORMAL", floats(&UP)),
            ("COLOR_0", colour),
        ],
        r#"{"mesh":0}"#,
        "",
    );
    let got = lit_head_on(write("vertex-colour", "c.glb", &bytes));
    for k in 0..3 {
        let want = srgb8(base[k] / 2.0);
        assert!(
            (got[k] as i32 - want).abs() <= 1,
            "{got:?}: channel {k} want {want}"
        );
    }
}

/// `KHR_materials_ior`, `KHR_materials_specular` and
/// `KHR_materials_clearcoat`: a black dielectric
/// (roughness 1) seen and lit head on by a light of 2 reflects
/// 2·F0·D·V·π = 2·F0/4 = F0/2. glTF's default F0 is 0.04 (0.02 back);
/// with ior 1.33, F0 = (0.33/2.33)² = 0.020059, times the specular colour
/// (1, 0.5, 0.25) and the weight 0.5: (0.01003, 0.005015, 0.002507), half
/// of which comes back.
#[test]
fn the_index_of_refraction_specular_and_clearcoat_factors_set_a_dielectrics_reflection() {
    let material = |ext: &str| {
        format!(
            r#","materials":[{{"pbrMetallicRoughness":{{"baseColorFactor":[0,0,0,1],"metallicFactor":0,"roughnessFactor":1}}{ext}}}]"#
        )
    };
    let quad = |name: &str, ext: &str| {
        let bytes = quad_glb(
            &[("POSITION", floats(&SQUARE)), ("NORMAL", floats(&UP))],
            r#"{"mesh":0}"#,
            &material(ext),
        );
        let bytes = super::models_gltf::json_fix(
            bytes,
            r#""primitives":[{"attributes""#,
            r#""primitives":[{"material":0,"attributes""#,
        );
        write("reflectance", name, &bytes)
    };
    let plain = lit_head_on(quad("plain.glb", ""));
    // KHR_materials_clearcoat (factor 1, roughness 1) over the black
    // dielectric: the layer lets 1 − F(0°) = 0.96 through and reflects
    // 2·0.04/4 = 0.02 itself: 0.96·0.02 + 0.02 = 0.0392. With the base's
    // specular weight 0 only the layer's 0.02 is left.
    let coat = r#""KHR_materials_clearcoat":{"clearcoatFactor":1,"clearcoatRoughnessFactor":1}"#;
    let coated = lit_head_on(quad("coat.glb", &format!(r#","extensions":{{{coat}}}"#)));
    let coat_only =
        format!(r#","extensions":{{{coat},"KHR_materials_specular":{{"specularFactor":0}}}}"#);
    let coat_only = lit_head_on(quad("coat-only.glb", &coat_only));
    for k in 0..3 {
        let want = srgb8(0.96 * 0.02 + 0.02);
        assert!((coated[k] as i32 - want).abs() <= 1, "{coated:?}: {want}");
        let want = srgb8(0.02);
        assert!(
            (coat_only[k] as i32 - want).abs() <= 1,
            "{coat_only:?}: {want}"
        );
    }
    let ext = r#","extensions":{"KHR_materials_ior":{"ior":1.33},"KHR_materials_specular":{"specularFactor":0.5,"specularColorFactor":[1,0.5,0.25]}}"#;
    let path = quad("water.glb", ext);
    assert!(load(&path).unwrap().warnings.is_empty());
    let water = lit_head_on(path);
    let f0 = 0.020_059f32 * 0.5;
    for k in 0..3 {
        let want = srgb8(0.04 / 2.0);
        assert!((plain[k] as i32 - want).abs() <= 1, "{plain:?}: {want}");
        let want = srgb8(f0 * [1.0, 0.5, 0.25][k] / 2.0);
        assert!((water[k] as i32 - want).abs() <= 1, "{water:?}: {want}");
    }
    // The extensions' textures are drawn (tests/render/layers.rs): a file
    // with them says nothing, even when one names no texture (that map is
    // left out, its factor acting alone).
    let ext = r#","extensions":{"KHR_materials_specular":{"specularTexture":{"index":0}},"KHR_materials_clearcoat":{"clearcoatFactor":1,"clearcoatNormalTexture":{"index":0}}}"#;
    let model = load(&quad("textured.glb", ext)).unwrap();
    assert!(model.warnings.is_empty(), "{:?}", model.warnings);
}
