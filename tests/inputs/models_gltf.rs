//! glTF 2.0 models: files written here byte by byte (GLB) and the real
//! files in tests/data/models/gltf, rendered and read back; bad files
//! refused with one line naming the file and the place.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::{Vec2, Vec3, Vec4};
use relief_core::framebuffer::Framebuffer;
use relief_core::settings::Settings;
use relief_core::settings::{Shading, Technique};
use relief_pipeline::render::render_frame;
use relief_scene::corners::FIT_RADIUS;
use relief_scene::gltf::{Model, load};
use relief_scene::{Light, Scene};
use relief_texture::decode::procedural;

const MAGENTA: [u8; 3] = [255, 0, 255];
pub(super) const W: usize = 160;
pub(super) const H: usize = 120;

/// One primitive as written to the file.
#[derive(Clone, Default)]
pub(super) struct Prim {
    pub(super) pos: Vec<[f32; 3]>,
    pub(super) nrm: Vec<[f32; 3]>,
    pub(super) uv: Vec<[f32; 2]>,
    pub(super) tan: Option<Vec<[f32; 4]>>,
    pub(super) idx: Vec<u16>,
    pub(super) material: Option<usize>,
    /// COLOR_0 (RGB), if any.
    pub(super) col: Vec<[f32; 3]>,
    /// The primitive's mode (absent: triangles).
    pub(super) mode: Option<u32>,
}

/// A GLB of one mesh with these primitives, drawn by the nodes in
/// `nodes` (JSON; node 0 is the scene's root) or by one node.
pub(super) struct Doc {
    pub(super) prims: Vec<Prim>,
    pub(super) nodes: String,
    pub(super) materials: String,
    /// PNG files, texture i reading image i.
    pub(super) images: Vec<Vec<u8>>,
    /// A sampler every texture uses (JSON), if any.
    pub(super) sampler: Option<String>,
    pub(super) extra: String,
}

impl Doc {
    pub(super) fn new(prims: Vec<Prim>) -> Self {
        Doc {
            prims,
            nodes: r#"[{"mesh":0}]"#.into(),
            materials: String::new(),
            images: Vec::new(),
            sampler: None,
            extra: String::new(),
        }
    }
}

pub(super) use crate::glb_writer::glb;

pub(super) fn encode(doc: &Doc) -> Vec<u8> {
    let mut bin: Vec<u8> = Vec::new();
    let mut views = Vec::new();
    let mut accessors = Vec::new();
    let mut add =
        |bin: &mut Vec<u8>, bytes: Vec<u8>, count: usize, ty: &str, ct: u32, minmax: &str| {
            while !bin.len().is_multiple_of(4) {
                bin.push(0);
            }
            views.push(format!(
                r#"{{"buffer":0,"byteOffset":{},"byteLength":{}}}"#,
                bin.len(),
                bytes.len()
            ));
            bin.extend_from_slice(&bytes);
            accessors.push(format!(
                r#"{{"bufferView":{},"componentType":{ct},"count":{count},"type":"{ty}"{minmax}}}"#,
                views.len() - 1
            ));
            accessors.len() - 1
        };
    let floats = |v: &[f32]| v.iter().flat_map(|f| f.to_le_bytes()).collect::<Vec<u8>>();
    let mut prims = Vec::new();
    for p in &doc.prims {
        let flat: Vec<f32> = p.pos.iter().flatten().copied().collect();
        let lo = (0..3).map(|k| p.pos.iter().map(|q| q[k]).fold(f32::INFINITY, f32::min));
        let hi = (0..3).map(|k| p.pos.iter().map(|q| q[k]).fold(f32::NEG_INFINITY, f32::max));
        let list = |it: &mut dyn Iterator<Item = f32>| {
            it.map(|f| format!("{f}")).collect::<Vec<_>>().join(",")
        };
        let minmax = format!(
            r#","min":[{}],"max":[{}]"#,
            list(&mut lo.into_iter()),
            list(&mut hi.into_iter())
        );
        let pos = add(&mut bin, floats(&flat), p.pos.len(), "VEC3", 5126, &minmax);
        let mut attrs = format!(r#""POSITION":{pos}"#);
        if !p.nrm.is_empty() {
            let flat: Vec<f32> = p.nrm.iter().flatten().copied().collect();
            let a = add(&mut bin, floats(&flat), p.nrm.len(), "VEC3", 5126, "");
            attrs += &format!(r#","NORMAL":{a}"#);
        }
        if !p.uv.is_empty() {
            let flat: Vec<f32> = p.uv.iter().flatten().copied().collect();
            let a = add(&mut bin, floats(&flat), p.uv.len(), "VEC2", 5126, "");
            attrs += &format!(r#","TEXCOORD_0":{a}"#);
        }
        if !p.col.is_empty() {
            let flat: Vec<f32> = p.col.iter().flatten().copied().collect();
            let a = add(&mut bin, floats(&flat), p.col.len(), "VEC3", 5126, "");
            attrs += &format!(r#","COLOR_0":{a}"#);
        }
        if let Some(t) = &p.tan {
            let flat: Vec<f32> = t.iter().flatten().copied().collect();
            let a = add(&mut bin, floats(&flat), t.len(), "VEC4", 5126, "");
            attrs += &format!(r#","TANGENT":{a}"#);
        }
        let idx: Vec<u8> = p.idx.iter().flat_map(|i| i.to_le_bytes()).collect();
        let i = add(&mut bin, idx, p.idx.len(), "SCALAR", 5123, "");
        let material = p
            .material
            .map_or(String::new(), |m| format!(r#","material":{m}"#));
        let mode = p.mode.map_or(String::new(), |m| format!(r#","mode":{m}"#));
        prims.push(format!(
            r#"{{"attributes":{{{attrs}}},"indices":{i}{material}{mode}}}"#
        ));
    }
    let mut images = Vec::new();
    for png in &doc.images {
        while !bin.len().is_multiple_of(4) {
            bin.push(0);
        }
        views.push(format!(
            r#"{{"buffer":0,"byteOffset":{},"byteLength":{}}}"#,
            bin.len(),
            png.len()
        ));
        bin.extend_from_slice(png);
        images.push(format!(
            r#"{{"bufferView":{},"mimeType":"image/png"}}"#,
            views.len() - 1
        ));
    }
    let mut json = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":{},"meshes":[{{"primitives":[{}]}}],"accessors":[{}],"bufferViews":[{}],"buffers":[{{"byteLength":{}}}]"#,
        doc.nodes,
        prims.join(","),
        accessors.join(","),
        views.join(","),
        bin.len()
    );
    if !doc.materials.is_empty() {
        json += &format!(r#","materials":{}"#, doc.materials);
    }
    if !images.is_empty() {
        let sampler = if doc.sampler.is_some() {
            r#","sampler":0"#
        } else {
            ""
        };
        let textures: Vec<String> = (0..images.len())
            .map(|i| format!(r#"{{"source":{i}{sampler}}}"#))
            .collect();
        if let Some(sampler) = &doc.sampler {
            json += &format!(r#","samplers":[{sampler}]"#);
        }
        json += &format!(
            r#","images":[{}],"textures":[{}]"#,
            images.join(","),
            textures.join(",")
        );
    }
    json += &doc.extra;
    json.push('}');
    glb(&json, &bin)
}

pub(super) fn png(w: u32, h: u32, rgba: impl Fn(u32, u32) -> [u8; 4]) -> Vec<u8> {
    let mut img = image::RgbaImage::new(w, h);
    for (x, y, p) in img.enumerate_pixels_mut() {
        *p = image::Rgba(rgba(x, y));
    }
    relief_texture::picture::encode(&img.into(), image::ImageFormat::Png).unwrap()
}

/// A temporary directory for this test's files.
fn scratch(test: &str) -> PathBuf {
    crate::common::scratch::scratch_dir(&format!("gltf-{test}"))
}

pub(super) fn write(test: &str, name: &str, bytes: &[u8]) -> PathBuf {
    let path = scratch(test).join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

/// An axis-aligned quad in z = 0 facing +Z: corners (x0, y0)–(x1, y1),
/// u from `u0` at x0 to `u1` at x1, v 0 at the top (y1) and 1 at the bottom.
pub(super) fn quad(x0: f32, x1: f32, y0: f32, y1: f32, u0: f32, u1: f32) -> Prim {
    Prim {
        pos: vec![[x0, y1, 0.0], [x0, y0, 0.0], [x1, y0, 0.0], [x1, y1, 0.0]],
        nrm: vec![[0.0, 0.0, 1.0]; 4],
        uv: vec![[u0, 0.0], [u0, 1.0], [u1, 1.0], [u1, 0.0]],
        tan: None,
        idx: if (x1 - x0) * (y1 - y0) > 0.0 {
            vec![0, 1, 2, 0, 2, 3]
        } else {
            vec![0, 2, 1, 0, 3, 2]
        },
        material: None,
        ..Default::default()
    }
}

pub(super) fn scene_of(model: Model) -> Scene {
    let mut scene = Scene::gltf(model, Arc::new(procedural::brick()));
    scene.background = MAGENTA;
    scene
}

/// Seen face-on: no rotation.
pub(super) fn face_on() -> Settings {
    Settings {
        rotation: Vec3::ZERO,
        ..Settings::default()
    }
}

fn px(fb: &Framebuffer, x: usize, y: usize) -> [u8; 3] {
    fb.pixels()[y * fb.width() + x]
}

pub(super) fn covered(fb: &Framebuffer) -> usize {
    fb.pixels().iter().filter(|&&p| p != MAGENTA).count()
}

pub(super) fn render(scene: &Scene, settings: &Settings) -> Framebuffer {
    render_frame(scene, settings, W, H).0
}

/// Pixel area of a polygon in z = 0 seen by the scene's camera (shoelace
/// on the projected corners).
fn projected_area(scene: &Scene, corners: &[Vec3]) -> f32 {
    let vp = scene.camera.projection(W as f32 / H as f32) * scene.camera.view();
    let px: Vec<Vec2> = corners
        .iter()
        .map(|c| {
            let p = vp * c.extend(1.0);
            let ndc = p.truncate() / p.w;
            Vec2::new(
                (ndc.x + 1.0) * 0.5 * W as f32,
                (1.0 - ndc.y) * 0.5 * H as f32,
            )
        })
        .collect();
    let mut twice = 0.0;
    for i in 0..px.len() {
        let (a, b) = (px[i], px[(i + 1) % px.len()]);
        twice += a.x * b.y - b.x * a.y;
    }
    twice.abs() / 2.0
}

pub(super) fn load_ok(path: &Path) -> Model {
    load(path).unwrap_or_else(|e| panic!("{e}"))
}

/// A 2 × 1 quad, turned a quarter about Z by its node (1 × 2), then
/// stretched 2× along X by the parent node: a square. Applied in the
/// wrong order the stretch would come first (4 × 1, turned: 1 × 4).
/// Fitted, the square's half-diagonal is FIT_RADIUS: side 1.5·√2.
#[test]
fn a_node_chain_gives_the_expected_silhouette() {
    let mut doc = Doc::new(vec![quad(-1.0, 1.0, -0.5, 0.5, 0.0, 1.0)]);
    doc.nodes = r#"[{"children":[1],"scale":[2,1,1]},{"mesh":0,"matrix":[0,1,0,0, -1,0,0,0, 0,0,1,0, 0,0,0,1]}]"#.into();
    let path = write("chain", "chain.glb", &encode(&doc));
    let scene = scene_of(load_ok(&path));
    let fb = render(&scene, &face_on());
    let h = FIT_RADIUS / 2f32.sqrt();
    let square = [
        Vec3::new(-h, -h, 0.0),
        Vec3::new(h, -h, 0.0),
        Vec3::new(h, h, 0.0),
        Vec3::new(-h, h, 0.0),
    ];
    let expected = projected_area(&scene, &square);
    let got = covered(&fb) as f32;
    assert!(
        (got - expected).abs() < 0.03 * expected,
        "{got} pixels covered, {expected} expected"
    );
}

/// The strip, fan and list (indexed or not) files of glTF-Asset-Generator
/// draw the same square, the size the fit gives it.
#[test]
fn every_triangle_mode_draws_the_same_square() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/models/gltf/primitive_modes");
    let mut areas = Vec::new();
    for n in ["04", "05", "06", "11", "12", "13"] {
        let path = dir.join(format!("Mesh_PrimitiveMode_{n}.gltf"));
        let scene = scene_of(load_ok(&path));
        let tris: usize = scene.objects.iter().map(|o| o.mesh.triangles.len()).sum();
        assert_eq!(tris, 2, "{n}");
        areas.push((n, covered(&render(&scene, &face_on()))));
    }
    let scene = scene_of(load_ok(&dir.join("Mesh_PrimitiveMode_13.gltf")));
    let h = FIT_RADIUS / 2f32.sqrt();
    let square = [
        Vec3::new(-h, -h, 0.0),
        Vec3::new(h, -h, 0.0),
        Vec3::new(h, h, 0.0),
        Vec3::new(-h, h, 0.0),
    ];
    let expected = projected_area(&scene, &square);
    for (n, a) in areas {
        assert!(
            (a as f32 - expected).abs() < 0.03 * expected,
            "mode file {n}: {a} pixels, {expected} expected"
        );
    }
}

/// A constant normal map tilted towards +u and up the picture:
/// (0.5, 0.5, 0.707), green being up as in glTF.
pub(super) fn tilted_map() -> Vec<u8> {
    png(4, 4, |_, _| [191, 191, 218, 255])
}

pub(super) fn dot3() -> Settings {
    Settings {
        technique: Technique::Dot3,
        shading: Shading::Phong,
        ..face_on()
    }
}

/// One white light straight in front of the seam at x = 0.
fn light_on_seam(scene: &mut Scene) {
    scene.lights = vec![Light::new(Vec3::new(0.0, 0.0, 2.0), Vec3::ONE)];
}

pub(super) fn materials_with_normal(scale: Option<f32>) -> String {
    match scale {
        Some(s) => format!(r#"[{{"normalTexture":{{"index":0,"scale":{s}}}}}]"#),
        None => r#"[{}]"#.into(),
    }
}

/// Two quads side by side, the left one's u mirrored, both normal mapped
/// with the same tilt towards +u and up the picture. Lit from in front of
/// the seam, each half's normals lean away from the seam and upwards
/// alike: the picture is its own mirror image. With a wrong tangent on the
/// mirrored half its normals would lean towards the seam, with a wrong
/// bitangent downwards, and the halves would differ.
fn mirrored_quads(tangents: bool) -> Framebuffer {
    let mut right = quad(0.0, 1.0, -0.5, 0.5, 0.0, 1.0);
    let mut left = quad(0.0, -1.0, -0.5, 0.5, 0.0, 1.0);
    right.material = Some(0);
    left.material = Some(0);
    if tangents {
        // glTF's bitangent w·(N × T) points up the picture (+y here).
        right.tan = Some(vec![[1.0, 0.0, 0.0, 1.0]; 4]);
        left.tan = Some(vec![[-1.0, 0.0, 0.0, -1.0]; 4]);
    }
    let mut doc = Doc::new(vec![right, left]);
    doc.materials = materials_with_normal(Some(1.0));
    doc.images = vec![tilted_map()];
    let path = write("mirror", &format!("mirror{tangents}.glb"), &encode(&doc));
    let mut scene = scene_of(load_ok(&path));
    light_on_seam(&mut scene);
    render(&scene, &dot3())
}

fn assert_mirror_symmetric(fb: &Framebuffer) {
    let mut compared = 0;
    for y in 0..H {
        for x in 0..W / 2 {
            let (a, b) = (px(fb, x, y), px(fb, W - 1 - x, y));
            if a == MAGENTA || b == MAGENTA {
                assert_eq!(a == MAGENTA, b == MAGENTA, "silhouette at ({x}, {y})");
                continue;
            }
            compared += 1;
            for c in 0..3 {
                assert!(
                    (a[c] as i32 - b[c] as i32).abs() <= 3,
                    "({x}, {y}) {a:?} against {b:?}"
                );
            }
        }
    }
    assert!(compared > 500, "{compared} pixel pairs");
}

#[test]
fn a_mirrored_normal_mapped_quad_lights_both_halves_alike() {
    for tangents in [true, false] {
        let fb = mirrored_quads(tangents);
        assert_mirror_symmetric(&fb);
        // Green is up the picture: above the light the normals lean away
        // from it (darker), below it towards it (brighter).
        let sum = |p: [u8; 3]| p.iter().map(|&c| c as u32).sum::<u32>();
        let (x, d) = (W / 2 + W / 10, H / 12);
        let (above, below) = (px(&fb, x, H / 2 - d), px(&fb, x, H / 2 + d));
        assert!(
            sum(above) + 20 < sum(below),
            "tangents {tangents}: {above:?} above, {below:?} below"
        );
        // The map does show: a point a quarter from the seam is darker than
        // the same quad without the map (its normal leans from the light).
        let mut flat = Doc::new(vec![quad(-1.0, 1.0, -0.5, 0.5, 0.0, 1.0)]);
        flat.materials = r#"[{}]"#.into();
        flat.prims[0].material = Some(0);
        let path = write("mirror", "flat.glb", &encode(&flat));
        let mut scene = scene_of(load_ok(&path));
        light_on_seam(&mut scene);
        let plain = render(&scene, &dot3());
        let y = H / 2;
        assert!(
            sum(px(&fb, x, y)) + 20 < sum(px(&plain, x, y)),
            "tangents {tangents}: {:?} mapped, {:?} plain",
            px(&fb, x, y),
            px(&plain, x, y)
        );
    }
}

/// `scale` 0 flattens every normal to (0, 0, 1): the picture is the one
/// of the same file without a normal map.
#[test]
fn normal_texture_scale_zero_draws_what_no_normal_map_draws() {
    let picture = |scale: Option<f32>| {
        let mut q = quad(-1.0, 1.0, -0.5, 0.5, 0.0, 1.0);
        q.material = Some(0);
        let mut doc = Doc::new(vec![q]);
        doc.materials = materials_with_normal(scale);
        doc.images = vec![tilted_map()];
        let path = write("scale0", &format!("s{scale:?}.glb"), &encode(&doc));
        let mut scene = scene_of(load_ok(&path));
        light_on_seam(&mut scene);
        render(&scene, &dot3())
    };
    let none = picture(None);
    assert_eq!(picture(Some(0.0)).pixels(), none.pixels());
    assert_ne!(picture(Some(1.0)).pixels(), none.pixels());
}

/// Two quads, one red-textured and one green-textured: each half shows
/// its own texture, not the scene's (brick) nor the other's.
#[test]
fn each_part_draws_with_its_own_texture() {
    let mut left = quad(-1.0, 0.0, -0.5, 0.5, 0.0, 1.0);
    let mut right = quad(0.0, 1.0, -0.5, 0.5, 0.0, 1.0);
    left.material = Some(0);
    right.material = Some(1);
    let mut doc = Doc::new(vec![left, right]);
    doc.materials = r#"[{"pbrMetallicRoughness":{"baseColorTexture":{"index":0}}},{"pbrMetallicRoughness":{"baseColorTexture":{"index":1}}}]"#.into();
    doc.images = vec![
        png(2, 2, |_, _| [255, 0, 0, 255]),
        png(2, 2, |_, _| [0, 255, 0, 255]),
    ];
    let path = write("multi", "multi.glb", &encode(&doc));
    let model = load_ok(&path);
    assert_eq!(model.parts.len(), 2);
    let mut scene = scene_of(model);
    light_on_seam(&mut scene);
    let fb = render(&scene, &face_on());
    let (l, r) = (px(&fb, W / 2 - W / 8, H / 2), px(&fb, W / 2 + W / 8, H / 2));
    assert!(l[0] > 100 && l[1] == 0 && l[2] == 0, "left {l:?}");
    assert!(r[1] > 100 && r[0] == 0 && r[2] == 0, "right {r:?}");
}

/// The base colour factor multiplies the colour: a quarter-red factor
/// gives half the red of a half-red one.
#[test]
fn base_color_factor_scales_the_colour() {
    let picture = |factor: &str| {
        let mut q = quad(-1.0, 1.0, -0.5, 0.5, 0.0, 1.0);
        q.material = Some(0);
        let mut doc = Doc::new(vec![q]);
        doc.materials = format!(r#"[{{"pbrMetallicRoughness":{{"baseColorFactor":{factor}}}}}]"#);
        let path = write("factor", &format!("f{}.glb", factor.len()), &encode(&doc));
        let mut scene = scene_of(load_ok(&path));
        light_on_seam(&mut scene);
        px(&render(&scene, &face_on()), W / 2, H / 2)
    };
    let full = picture("[0.5,0,0,1]");
    let half = picture("[0.25,0,0,1.0]");
    assert_eq!((full[1], full[2], half[1], half[2]), (0, 0, 0, 0));
    assert!(
        (full[0] as i32 - 2 * half[0] as i32).abs() <= 2,
        "{full:?} {half:?}"
    );
}

/// The GLB with the first `from` of its JSON replaced by `to`.
pub(super) fn json_fix(bytes: Vec<u8>, from: &str, to: &str) -> Vec<u8> {
    let text = String::from_utf8_lossy(&bytes).into_owned();
    assert!(text.contains(from), "{from}");
    let json_len = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    let json = std::str::from_utf8(&bytes[20..20 + json_len])
        .unwrap()
        .replacen(from, to, 1);
    let bin_at = 20 + json_len;
    let bin_len = u32::from_le_bytes(bytes[bin_at..bin_at + 4].try_into().unwrap()) as usize;
    glb(json.trim_end(), &bytes[bin_at + 8..bin_at + 8 + bin_len])
}

pub(super) fn refused(test: &str, bytes: &[u8]) -> String {
    let path = write(test, "bad.glb", bytes);
    let message = match load(&path) {
        Ok(_) => panic!("{test}: loaded"),
        Err(e) => e.to_string(),
    };
    assert!(message.contains("bad.glb"), "{message}");
    assert!(!message.contains('\n'), "{message}");
    message
}

pub(super) fn good() -> Doc {
    Doc::new(vec![quad(-1.0, 1.0, -0.5, 0.5, 0.0, 1.0)])
}

#[test]
fn bad_files_are_refused_with_the_place() {
    // A JSON chunk claiming more bytes than the file has.
    let mut bytes = encode(&good());
    bytes[12..16].copy_from_slice(&100_000u32.to_le_bytes());
    let m = refused("chunk", &bytes);
    assert!(m.contains("chunk 0 at byte 12"), "{m}");

    // The header claiming more than the file.
    let mut bytes = encode(&good());
    bytes[8..12].copy_from_slice(&u32::MAX.to_le_bytes());
    assert!(refused("header", &bytes).contains("byte 8"));

    // An index past the vertices.
    let mut doc = good();
    doc.prims[0].idx[4] = 9;
    let m = refused("index", &encode(&doc));
    assert!(
        m.contains("meshes[0].primitives[0]") && m.contains("index 4 is 9"),
        "{m}"
    );

    // A NaN position.
    let mut doc = good();
    doc.prims[0].pos[2][1] = f32::NAN;
    let m = refused("nan", &encode(&doc));
    assert!(m.contains("POSITION 2"), "{m}");

    // An accessor past its buffer view.
    let mut doc = good();
    doc.extra = String::new();
    let bytes = json_fix(
        encode(&doc),
        r#""count":4,"type":"VEC3""#,
        r#""count":400,"type":"VEC3""#,
    );
    let m = refused("accessor", &bytes);
    assert!(m.contains("accessors[0]"), "{m}");

    // A buffer claiming 4 GB.
    let bytes = encode(&good());
    let len = bytes.len();
    let bytes = json_fix(
        bytes,
        r#""buffers":[{"byteLength":"#,
        r#""buffers":[{"byteLength":4000000000"#,
    );
    let m = refused("huge", &bytes);
    assert!(m.contains("buffers[0]"), "{m} ({len})");

    // A required extension relief cannot do (KHR_texture_basisu it reads:
    // models_gltf_ktx2.rs).
    let mut doc = good();
    doc.extra =
        r#","extensionsUsed":["EXT_texture_avif"],"extensionsRequired":["EXT_texture_avif"]"#
            .into();
    let m = refused("avif", &encode(&doc));
    assert!(
        m.contains("requires the extension 'EXT_texture_avif', which relief does not read"),
        "{m}"
    );
}

/// The real files load: the textured box is one part of 12 textured
/// triangles; the clear-coat test has several materials, some normal mapped.
#[test]
fn real_files_load_with_their_materials() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/models/gltf");
    let boxed = load_ok(&dir.join("BoxTextured.glb"));
    assert_eq!(boxed.parts.len(), 1);
    let mesh = &boxed.parts[0].mesh;
    assert_eq!(mesh.triangles.len(), 12);
    assert!(mesh.triangles.iter().all(|t| t.textured));
    assert!(boxed.parts[0].material.texture.width() > 1);

    let coat = load_ok(&dir.join("ClearCoatTest/ClearCoatTest.gltf"));
    let distinct = coat
        .parts
        .iter()
        .enumerate()
        .filter(|(i, p)| {
            !coat.parts[..*i]
                .iter()
                .any(|q| Arc::ptr_eq(&q.material, &p.material))
        })
        .count();
    assert!(distinct >= 5, "{distinct} materials");
    assert!(coat.parts.iter().any(|p| p.material.normal_map.is_some()));
    let scene = scene_of(coat);
    let fb = render(&scene, &dot3());
    assert!(covered(&fb) > 1000);
    // Tangent frames stay finite.
    for o in &scene.objects {
        for v in &o.mesh.vertices {
            assert!(v.tangent_u.is_finite() && v.tangent_v.is_finite());
            assert!(Vec4::from((v.normal, 0.0)).is_finite());
        }
    }
}

/// One quad with this material (JSON) and these images, seen face-on with
/// highlights off, its pixel at the quad's centre and at `x`.
fn material_picture(
    test: &str,
    material: &str,
    images: Vec<Vec<u8>>,
    scene: impl Fn(&mut Scene),
) -> Framebuffer {
    let mut q = quad(-1.0, 1.0, -0.5, 0.5, 0.0, 1.0);
    q.material = Some(0);
    let mut doc = Doc::new(vec![q]);
    doc.materials = format!("[{material}]");
    doc.images = images;
    let path = write(test, "m.glb", &encode(&doc));
    let mut s = scene_of(load_ok(&path));
    light_on_seam(&mut s);
    scene(&mut s);
    render(&s, &face_on())
}

/// A black material gives off exactly its emissive colour, whatever the
/// light: 0.2, 0.4, 0.6 → 51, 102, 153 (x·255 rounded); the texture
/// multiplies the factor; the strength extension multiplies it too.
#[test]
fn an_emissive_material_on_black_gives_its_emissive_colour() {
    let black = r#""pbrMetallicRoughness":{"baseColorFactor":[0,0,0,1]}"#;
    let factor = material_picture(
        "emit",
        &format!(r#"{{{black},"emissiveFactor":[0.2,0.4,0.6]}}"#),
        vec![],
        |_| {},
    );
    assert_eq!(px(&factor, W / 2, H / 2), [51, 102, 153]);
    assert_eq!(px(&factor, W / 2 + W / 8, H / 2 - H / 20), [51, 102, 153]);
    let strength = material_picture(
        "emit-strength",
        &format!(
            r#"{{{black},"emissiveFactor":[0.1,0.2,0.3],"extensions":{{"KHR_materials_emissive_strength":{{"emissiveStrength":2}}}}}}"#
        ),
        vec![],
        |_| {},
    );
    assert_eq!(px(&strength, W / 2, H / 2), [51, 102, 153]);
    let texture = material_picture(
        "emit-map",
        &format!(r#"{{{black},"emissiveFactor":[1,1,1],"emissiveTexture":{{"index":0}}}}"#),
        vec![png(2, 2, |_, _| [128, 64, 32, 255])],
        |_| {},
    );
    assert_eq!(px(&texture, W / 2, H / 2), [128, 64, 32]);
    // Lights off: still the same colour; the quad's emission is its own.
    let dark = material_picture(
        "emit-dark",
        &format!(r#"{{{black},"emissiveFactor":[0.2,0.4,0.6]}}"#),
        vec![],
        |s| {
            s.lights.clear();
            s.ambient = Vec3::ZERO;
        },
    );
    assert_eq!(px(&dark, W / 2, H / 2), [51, 102, 153]);
}

/// Occlusion strength 0 draws what no occlusion draws; a black occlusion
/// map at strength 1 removes the ambient term: what an ambient of 0 draws.
#[test]
fn occlusion_scales_the_ambient_term_by_its_strength() {
    let black_map = || vec![png(2, 2, |_, _| [0, 0, 0, 255])];
    let grey = r#""pbrMetallicRoughness":{"baseColorFactor":[0.8,0.8,0.8,1]}"#;
    let plain = material_picture("occ-none", &format!("{{{grey}}}"), vec![], |_| {});
    let zero = material_picture(
        "occ-zero",
        &format!(r#"{{{grey},"occlusionTexture":{{"index":0,"strength":0}}}}"#),
        black_map(),
        |_| {},
    );
    assert_eq!(plain.pixels(), zero.pixels());
    let full = material_picture(
        "occ-full",
        &format!(r#"{{{grey},"occlusionTexture":{{"index":0}}}}"#),
        black_map(),
        |_| {},
    );
    let no_ambient = material_picture("occ-ambient", &format!("{{{grey}}}"), vec![], |s| {
        s.ambient = Vec3::ZERO
    });
    assert_ne!(plain.pixels(), full.pixels(), "the occlusion shows");
    for (a, b) in full.pixels().iter().zip(no_ambient.pixels()) {
        for k in 0..3 {
            assert!((a[k] as i32 - b[k] as i32).abs() <= 1, "{a:?} {b:?}");
        }
    }
}

/// A texture red in its left half and green in its right, on a quad whose
/// u runs from 1 to 2: under MIRRORED_REPEAT, u = 1.25 reads u = 0.75
/// (green) and u = 1.75 reads 0.25 (red); under REPEAT the other way round.
#[test]
fn mirrored_repeat_reads_the_mirror_image() {
    let picture = |wrap: u32| {
        let mut q = quad(-1.0, 1.0, -0.5, 0.5, 1.0, 2.0);
        q.material = Some(0);
        let mut doc = Doc::new(vec![q]);
        doc.materials = r#"[{"pbrMetallicRoughness":{"baseColorTexture":{"index":0}}}]"#.into();
        doc.images = vec![png(4, 1, |x, _| {
            if x < 2 {
                [255, 0, 0, 255]
            } else {
                [0, 255, 0, 255]
            }
        })];
        doc.sampler = Some(format!(
            r#"{{"magFilter":9728,"minFilter":9728,"wrapS":{wrap}}}"#
        ));
        let path = write("mirror", &format!("w{wrap}.glb"), &encode(&doc));
        let mut scene = scene_of(load_ok(&path));
        light_on_seam(&mut scene);
        let fb = render(&scene, &face_on());
        let x = |u: f32| {
            // The quad spans the fitted width: u − 1 of the way across it.
            let left = W as f32 / 2.0 - projected_half_width(&scene);
            (left + (u - 1.0) * 2.0 * projected_half_width(&scene)) as usize
        };
        (px(&fb, x(1.25), H / 2), px(&fb, x(1.75), H / 2))
    };
    let (quarter, three_quarters) = picture(33648);
    assert!(
        quarter[1] > 0 && quarter[0] == 0,
        "mirrored 1.25 {quarter:?}"
    );
    assert!(
        three_quarters[0] > 0 && three_quarters[1] == 0,
        "mirrored 1.75 {three_quarters:?}"
    );
    let (quarter, three_quarters) = picture(10497);
    assert!(quarter[0] > 0 && quarter[1] == 0, "repeat 1.25 {quarter:?}");
    assert!(
        three_quarters[1] > 0 && three_quarters[0] == 0,
        "repeat 1.75 {three_quarters:?}"
    );
}

/// Half the projected width of the fitted 2 × 1 quad, in pixels.
fn projected_half_width(scene: &Scene) -> f32 {
    let r = FIT_RADIUS / (1.25f32).sqrt();
    let area = projected_area(
        scene,
        &[
            Vec3::new(-r, -r / 2.0, 0.0),
            Vec3::new(r, -r / 2.0, 0.0),
            Vec3::new(r, r / 2.0, 0.0),
            Vec3::new(-r, r / 2.0, 0.0),
        ],
    );
    // Face-on the quad keeps its 2:1 shape: area = w · w / 2.
    (area * 2.0).sqrt() / 2.0
}

/// KHR_texture_transform's offset moves the texture: an offset of half a
/// texture makes u = 0.25 read 0.75, so the red left half shows green.
#[test]
fn a_texture_transform_offset_moves_the_texture() {
    let picture = |transform: &str| {
        let mut q = quad(-1.0, 1.0, -0.5, 0.5, 0.0, 1.0);
        q.material = Some(0);
        let mut doc = Doc::new(vec![q]);
        doc.materials = format!(
            r#"[{{"pbrMetallicRoughness":{{"baseColorTexture":{{"index":0{transform}}}}}}}]"#
        );
        doc.images = vec![png(4, 1, |x, _| {
            if x < 2 {
                [255, 0, 0, 255]
            } else {
                [0, 255, 0, 255]
            }
        })];
        doc.sampler = Some(r#"{"magFilter":9728,"minFilter":9728}"#.into());
        let path = write(
            "transform",
            &format!("t{}.glb", transform.len()),
            &encode(&doc),
        );
        let mut scene = scene_of(load_ok(&path));
        light_on_seam(&mut scene);
        px(&render(&scene, &face_on()), W / 2 - W / 8, H / 2)
    };
    let plain = picture("");
    assert!(plain[0] > 0 && plain[1] == 0, "{plain:?}");
    let moved = picture(r#","extensions":{"KHR_texture_transform":{"offset":[0.5,0]}}"#);
    assert!(moved[1] > 0 && moved[0] == 0, "{moved:?}");
}

/// alphaMode MASK: a texture whose alpha is 0.2, 0.4, 0.6, 0.8 in its four
/// columns, cutoff 0.5: the quad shows the background over the first two
/// columns and is drawn over the last two; cutoff 0.3 drops only the
/// first; OPAQUE and BLEND drop none. Flat and Gouraud
/// shading cut the same texels as Phong, with the texture shown or not.
#[test]
fn an_alpha_mask_drops_exactly_the_texels_below_the_cutoff() {
    for shading in [Shading::Phong, Shading::Flat, Shading::Gouraud] {
        for texture in [true, false] {
            alpha_mask_in(shading, texture);
        }
    }
}

fn alpha_mask_in(shading: Shading, texture: bool) {
    let drawn = |mode: &str| {
        let mut q = quad(-1.0, 1.0, -0.5, 0.5, 0.0, 1.0);
        q.material = Some(0);
        let mut doc = Doc::new(vec![q]);
        doc.materials =
            format!(r#"[{{"pbrMetallicRoughness":{{"baseColorTexture":{{"index":0}}}}{mode}}}]"#);
        doc.images = vec![png(4, 1, |x, _| [255, 255, 255, 51 * (x as u8 + 1)])];
        doc.sampler = Some(r#"{"magFilter":9728,"minFilter":9728}"#.into());
        let path = write("mask", &format!("m{}.glb", mode.len()), &encode(&doc));
        let mut scene = scene_of(load_ok(&path));
        light_on_seam(&mut scene);
        let settings = Settings {
            shading,
            texture,
            ..face_on()
        };
        let fb = render(&scene, &settings);
        let half = projected_half_width(&scene);
        let left = W as f32 / 2.0 - half;
        [0.125f32, 0.375, 0.625, 0.875]
            .map(|u| px(&fb, (left + u * 2.0 * half) as usize, H / 2) != MAGENTA)
    };
    let mask = r#","alphaMode":"MASK""#;
    assert_eq!(
        drawn(mask),
        [false, false, true, true],
        "{shading:?}, texture {texture}"
    );
    assert_eq!(
        drawn(r#","alphaMode":"MASK","alphaCutoff":0.3"#),
        [false, true, true, true],
        "{shading:?}, texture {texture}"
    );
    assert_eq!(drawn(""), [true; 4], "{shading:?}, texture {texture}");
    // BLEND draws every texel, each with its alpha.
    assert_eq!(
        drawn(r#","alphaMode":"BLEND""#),
        [true; 4],
        "{shading:?}, texture {texture}"
    );
}

/// The pixel where model point `p` (already fitted) lands, face-on.
fn screen_of(scene: &Scene, p: Vec3) -> Vec2 {
    let vp = scene.camera.projection(W as f32 / H as f32) * scene.camera.view();
    let c = vp * p.extend(1.0);
    Vec2::new(
        (c.x / c.w + 1.0) * 0.5 * W as f32,
        (1.0 - c.y / c.w) * 0.5 * H as f32,
    )
}

/// A LINES segment from (−1, 0.1, 0) to (1, 0.1, 0), POINTS at
/// (−0.5, 0.5, 0) and (0.5, 0.5, 0), and an opaque quad at z = 1 over
/// x in 0..1 (nearer the camera): the line shows left of the quad's edge
/// and not behind it, one point shows and the other is hidden. Their
/// colour is the base colour factor (1, 0.5, 1) × COLOR_0 (0.5, 1, 0).
#[test]
fn points_and_lines_are_drawn_and_hidden_behind_nearer_faces() {
    let mut front = quad(0.0, 1.0, -1.0, 1.0, 0.0, 1.0);
    for p in &mut front.pos {
        p[2] = 1.0;
    }
    let colour = [0.5, 1.0, 0.0];
    let line = Prim {
        pos: vec![[-1.0, 0.1, 0.0], [1.0, 0.1, 0.0]],
        col: vec![colour; 2],
        idx: vec![0, 1],
        material: Some(0),
        mode: Some(1),
        ..Default::default()
    };
    let points = Prim {
        pos: vec![[-0.5, 0.5, 0.0], [0.5, 0.5, 0.0]],
        col: vec![colour; 2],
        idx: vec![0, 1],
        material: Some(0),
        mode: Some(0),
        ..Default::default()
    };
    let mut doc = Doc::new(vec![front, line, points]);
    doc.materials = r#"[{"pbrMetallicRoughness":{"baseColorFactor":[1,0.5,1,1]}}]"#.into();
    let model = load_ok(&write("strokes", "strokes.glb", &encode(&doc)));
    assert_eq!(model.strokes.points.len(), 2);
    assert_eq!(model.strokes.lines.len(), 1);
    let scene = scene_of(model);
    let fb = render(&scene, &face_on());
    // The fit: the box x −1..1, y −1..1, z 0..1 centred at (0, 0, 0.5),
    // its farthest points (the quad's corners) at √2.25 = 1.5: scale 1.
    let fitted = |x: f32, y: f32, z: f32| Vec3::new(x, y, z - 0.5);
    let ink = [128, 128, 0];
    let (a, b) = (
        screen_of(&scene, fitted(-1.0, 0.1, 0.0)),
        screen_of(&scene, fitted(1.0, 0.1, 0.0)),
    );
    let row = a.y.floor() as usize;
    assert_eq!(row, b.y.floor() as usize);
    // The quad's left edge (x = 0) is the middle of the picture.
    let edge = W / 2;
    for x in a.x.floor() as usize..=b.x.floor() as usize {
        assert_eq!(px(&fb, x, row) == ink, x < edge, "column {x}");
    }
    let kept = screen_of(&scene, fitted(-0.5, 0.5, 0.0));
    let hidden = screen_of(&scene, fitted(0.5, 0.5, 0.0));
    assert_eq!(px(&fb, kept.x as usize, kept.y as usize), ink);
    assert_ne!(px(&fb, hidden.x as usize, hidden.y as usize), ink);
    // Nothing else has the strokes' colour: the line's visible columns
    // and the one point.
    let inked = fb.pixels().iter().filter(|&&p| p == ink).count();
    assert_eq!(inked, edge - a.x.floor() as usize + 1);
    // Colours off: white strokes.
    let plain = render(
        &scene,
        &Settings {
            colors: false,
            ..face_on()
        },
    );
    assert_eq!(px(&plain, kept.x as usize, kept.y as usize), [255; 3]);
}

/// A square outline drawn as LINE_LOOP (4 corners), LINE_STRIP (5, the
/// last the first again) and LINES (4 pairs) is the same picture; a file
/// of lines only opens.
#[test]
fn every_line_mode_draws_the_same_outline() {
    let corners = vec![
        [-1.0, -1.0, 0.0],
        [1.0, -1.0, 0.0],
        [1.0, 1.0, 0.0],
        [-1.0, 1.0, 0.0],
    ];
    let picture = |mode: u32, idx: Vec<u16>| {
        let prim = Prim {
            pos: corners.clone(),
            idx,
            mode: Some(mode),
            ..Default::default()
        };
        let path = write(
            "line-modes",
            &format!("m{mode}.glb"),
            &encode(&Doc::new(vec![prim])),
        );
        render(&scene_of(load_ok(&path)), &face_on())
    };
    let lines = picture(1, vec![0, 1, 1, 2, 2, 3, 3, 0]);
    assert_eq!(lines.pixels(), picture(2, vec![0, 1, 2, 3]).pixels());
    assert_eq!(lines.pixels(), picture(3, vec![0, 1, 2, 3, 0]).pixels());
    // Four sides of a square of side 1.5·√2 = 2.12 units seen from 5
    // units, 120 rows over 2·5·tan 30° = 5.77 units: 44.1 pixels a side,
    // so 4 × 44 or 45 pixels in all (corners shared), none missing.
    let white = lines.pixels().iter().filter(|&&p| p == [255; 3]).count();
    assert!((174..=184).contains(&white), "{white}");
}

/// The u of the 2 × 1 quad's corners in `quad` order: 0 on the left, 1 on
/// the right; v 0 at the top, 1 at the bottom.
const QUAD_UV: [[f32; 2]; 4] = [[0.0, 0.0], [0.0, 1.0], [1.0, 1.0], [1.0, 0.0]];

/// `QUAD_UV` mirrored: u 1 on the left, 0 on the right.
const QUAD_UV_MIRRORED: [[f32; 2]; 4] = [[1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [0.0, 0.0]];

fn data_uri(mime: &str, bytes: &[u8]) -> String {
    use base64::Engine;
    let b64 = base64::engine::general_purpose::STANDARD.encode(bytes);
    format!("data:{mime};base64,{b64}")
}

/// A .gltf file (JSON, its buffer and images as data URIs) of the 2 × 1
/// quad of `quad(-1, 1, -0.5, 0.5, …)` with texture coordinate sets
/// `sets` (TEXCOORD_0, TEXCOORD_1…), this material and these images, each
/// texture read with the nearest texel.
fn two_set_gltf(test: &str, sets: &[[[f32; 2]; 4]], material: &str, images: &[Vec<u8>]) -> PathBuf {
    let q = quad(-1.0, 1.0, -0.5, 0.5, 0.0, 1.0);
    let mut bin: Vec<u8> = Vec::new();
    let mut views = Vec::new();
    let mut accessors = Vec::new();
    let mut add = |bytes: Vec<u8>, count: usize, ty: &str, ct: u32, extra: &str| {
        views.push(format!(
            r#"{{"buffer":0,"byteOffset":{},"byteLength":{}}}"#,
            bin.len(),
            bytes.len()
        ));
        bin.extend_from_slice(&bytes);
        accessors.push(format!(
            r#"{{"bufferView":{},"componentType":{ct},"count":{count},"type":"{ty}"{extra}}}"#,
            views.len() - 1
        ));
    };
    let floats = |v: &[f32]| v.iter().flat_map(|f| f.to_le_bytes()).collect::<Vec<u8>>();
    add(
        floats(&q.pos.concat()),
        4,
        "VEC3",
        5126,
        r#","min":[-1,-0.5,0],"max":[1,0.5,0]"#,
    );
    add(floats(&q.nrm.concat()), 4, "VEC3", 5126, "");
    let mut attributes = r#""POSITION":0,"NORMAL":1"#.to_string();
    for (k, set) in sets.iter().enumerate() {
        add(floats(&set.concat()), 4, "VEC2", 5126, "");
        attributes += &format!(r#","TEXCOORD_{k}":{}"#, k + 2);
    }
    let indices: Vec<u8> = q.idx.iter().flat_map(|i| i.to_le_bytes()).collect();
    add(indices, q.idx.len(), "SCALAR", 5123, "");
    let images_json: Vec<String> = images
        .iter()
        .map(|png| format!(r#"{{"uri":"{}"}}"#, data_uri("image/png", png)))
        .collect();
    let textures: Vec<String> = (0..images.len())
        .map(|i| format!(r#"{{"source":{i},"sampler":0}}"#))
        .collect();
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},"extensionsUsed":["KHR_texture_transform"],"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0}}],"meshes":[{{"primitives":[{{"attributes":{{{attributes}}},"indices":{},"material":0}}]}}],"accessors":[{}],"bufferViews":[{}],"buffers":[{{"byteLength":{},"uri":"{}"}}],"materials":[{material}],"samplers":[{{"magFilter":9728,"minFilter":9728}}],"images":[{}],"textures":[{}]}}"#,
        accessors.len() - 1,
        accessors.join(","),
        views.join(","),
        bin.len(),
        data_uri("application/octet-stream", &bin),
        images_json.join(","),
        textures.join(","),
    );
    write(test, "quad.gltf", json.as_bytes())
}

/// A 4 × 1 image: red on the left half, green on the right, no blue.
fn red_green() -> Vec<u8> {
    png(4, 1, |x, _| {
        if x < 2 {
            [255, 0, 0, 255]
        } else {
            [0, 255, 0, 255]
        }
    })
}

/// The quad of `two_set_gltf` face-on, lit from in front of its centre,
/// and its pixels at u = 1/8, 3/8, 5/8, 7/8 along its middle row.
fn quarter_pixels(path: &Path) -> [[u8; 3]; 4] {
    let mut scene = scene_of(load_ok(path));
    light_on_seam(&mut scene);
    let fb = render(&scene, &face_on());
    let half = projected_half_width(&scene);
    let left = W as f32 / 2.0 - half;
    [0.125f32, 0.375, 0.625, 0.875].map(|u| px(&fb, (left + u * 2.0 * half) as usize, H / 2))
}

/// The base colour reads TEXCOORD_0 and the emissive map TEXCOORD_1,
/// which runs the other way (u₁ = 1 − u₀), moved by an offset of ¼:
/// the emissive map is read at frac(1 − u₀ + ¼). Its texels give off blue
/// only (0, 85, 170, 255 in its four quarters, emissiveFactor 1) and the
/// base colour has none, so each pixel's blue is its emission exactly:
/// u₀ = ⅛ reads ⅛ (quarter 0: 0), ⅜ reads ⅞ (quarter 3: 255), ⅝ reads ⅝
/// (quarter 2: 170), ⅞ reads ⅜ (quarter 1: 85). (The emissive map is
/// read bilinearly: its 8 texels hold each quarter's value twice, so the
/// reads at the quarters' middles, between two equal texels, are exact.)
/// The base colour still reads TEXCOORD_0 unmoved: red on the left half,
/// green on the right.
#[test]
fn an_emissive_map_on_the_second_set_reads_it_with_its_own_offset() {
    let quarters = || png(8, 1, |x, _| [0, 0, 85 * (x / 2) as u8, 255]);
    let blue = quarters();
    let material = r#"{"pbrMetallicRoughness":{"baseColorTexture":{"index":0}},"emissiveFactor":[1,1,1],"emissiveTexture":{"index":1,"texCoord":1,"extensions":{"KHR_texture_transform":{"offset":[0.25,0]}}}}"#;
    let path = two_set_gltf(
        "emit-set1",
        &[QUAD_UV, QUAD_UV_MIRRORED],
        material,
        &[red_green(), blue],
    );
    let p = quarter_pixels(&path);
    assert_eq!(p.map(|c| c[2]), [0, 255, 170, 85], "{p:?}");
    for (k, c) in p.iter().enumerate() {
        let (base, other) = if k < 2 { (c[0], c[1]) } else { (c[1], c[0]) };
        assert!(base > 0 && other == 0, "quarter {k}: {c:?}");
    }
    // The model keeps the second set, one per vertex; a model whose maps
    // all read one set keeps none.
    let model = load_ok(&path);
    assert_eq!(
        model.parts[0].mesh.uv2().len(),
        model.parts[0].mesh.vertices.len()
    );
    let one = two_set_gltf(
        "emit-set0",
        &[QUAD_UV],
        r#"{"pbrMetallicRoughness":{"baseColorTexture":{"index":0}},"emissiveFactor":[1,1,1],"emissiveTexture":{"index":1}}"#,
        &[red_green(), quarters()],
    );
    let model = load_ok(&one);
    assert!(model.parts[0].mesh.uv2().is_empty());
    assert_eq!(quarter_pixels(&one).map(|c| c[2]), [0, 85, 170, 255]);
}

/// KHR_texture_transform scale 2 on the emissive map alone repeats that
/// map twice across the quad and nothing else: its blue (255 in its left
/// half, 0 in its right; 8 texels, so the bilinear reads below fall
/// between two equal ones) reads u' = 2u, so 255, 0, 255, 0 at u = ⅛, ⅜,
/// ⅝, ⅞, while the base colour, on the same set, stays red then green once.
#[test]
fn a_texture_transform_on_one_map_repeats_that_map_only() {
    let halves = || png(8, 1, |x, _| [0, 0, if x < 4 { 255 } else { 0 }, 255]);
    let blue = halves();
    let material = r#"{"pbrMetallicRoughness":{"baseColorTexture":{"index":0}},"emissiveFactor":[1,1,1],"emissiveTexture":{"index":1,"extensions":{"KHR_texture_transform":{"scale":[2,1]}}}}"#;
    let path = two_set_gltf("scale-one", &[QUAD_UV], material, &[red_green(), blue]);
    let p = quarter_pixels(&path);
    assert_eq!(p.map(|c| c[2]), [255, 0, 255, 0], "{p:?}");
    for (k, c) in p.iter().enumerate() {
        let (base, other) = if k < 2 { (c[0], c[1]) } else { (c[1], c[0]) };
        assert!(base > 0 && other == 0, "quarter {k}: {c:?}");
    }
    // The transform on the base colour instead repeats the base colour,
    // and the emission stays once across.
    let material = r#"{"pbrMetallicRoughness":{"baseColorTexture":{"index":0,"extensions":{"KHR_texture_transform":{"scale":[2,1]}}}},"emissiveFactor":[1,1,1],"emissiveTexture":{"index":1}}"#;
    let blue = halves();
    let path = two_set_gltf("scale-base", &[QUAD_UV], material, &[red_green(), blue]);
    let p = quarter_pixels(&path);
    assert_eq!(p.map(|c| c[2]), [255, 255, 0, 0], "{p:?}");
    for (k, c) in p.iter().enumerate() {
        let (base, other) = if k % 2 == 0 {
            (c[0], c[1])
        } else {
            (c[1], c[0])
        };
        assert!(base > 0 && other == 0, "quarter {k}: {c:?}");
    }
}

/// A normal map on TEXCOORD_1, which runs the other way (u₁ = 1 − u₀),
/// takes its tangents from that set: its tilt towards +u₁ leans every
/// normal towards −x, so lit from in front of the centre the right half
/// (leaning towards the light) is brighter than the left. The picture is
/// the one of the same quad whose TEXCOORD_0 is the mirrored set and whose
/// maps all read it (the base colour is white, so only the normals differ).
#[test]
fn a_normal_map_on_the_second_set_takes_its_tangents_from_it() {
    let white = png(1, 1, |_, _| [255, 255, 255, 255]);
    let picture = |test: &str, sets: &[[[f32; 2]; 4]], set: u32| {
        let material = format!(
            r#"{{"pbrMetallicRoughness":{{"baseColorTexture":{{"index":0}}}},"normalTexture":{{"index":1,"texCoord":{set}}}}}"#
        );
        let path = two_set_gltf(test, sets, &material, &[white.clone(), tilted_map()]);
        let mut scene = scene_of(load_ok(&path));
        light_on_seam(&mut scene);
        render(&scene, &dot3())
    };
    let second = picture("normal-set1", &[QUAD_UV, QUAD_UV_MIRRORED], 1);
    let mirrored = picture("normal-mirrored", &[QUAD_UV_MIRRORED], 0);
    let plain = picture("normal-plain", &[QUAD_UV], 0);
    let sum = |p: [u8; 3]| p.iter().map(|&c| c as i32).sum::<i32>();
    let (l, r) = (W / 2 - W / 10, W / 2 + W / 10);
    let (left, right) = (px(&second, l, H / 2), px(&second, r, H / 2));
    assert!(
        sum(left) + 20 < sum(right),
        "{left:?} left, {right:?} right"
    );
    let (left, right) = (px(&plain, l, H / 2), px(&plain, r, H / 2));
    assert!(
        sum(right) + 20 < sum(left),
        "unmirrored: {left:?} left, {right:?} right"
    );
    for (a, b) in second.pixels().iter().zip(mirrored.pixels()) {
        for k in 0..3 {
            assert!((a[k] as i32 - b[k] as i32).abs() <= 1, "{a:?} {b:?}");
        }
    }
}

/// KHR_texture_transform's rotation turns as the extension's matrix says:
/// R = [[cos, sin], [−sin, cos]] on (u, v), so a quarter turn with an
/// offset of (0, 1) reads v' = 1 − u. The emissive map (1 × 8 texels) gives
/// off blue 255 in its top half (v' < ½) and none below: at u = ⅛, ⅜, ⅝, ⅞
/// it reads v' = ⅞, ⅝, ⅜, ⅛, so 0, 0, 255, 255. (The opposite turn, the
/// one relief used to make, reads v' = 1 + u: 255, 255, 0, 0.)
#[test]
fn a_quarter_turn_reads_the_texels_the_extension_names() {
    let top = png(1, 8, |_, y| [0, 0, if y < 4 { 255 } else { 0 }, 255]);
    let material = r#"{"pbrMetallicRoughness":{"baseColorTexture":{"index":0}},"emissiveFactor":[1,1,1],"emissiveTexture":{"index":1,"extensions":{"KHR_texture_transform":{"rotation":1.5707963,"offset":[0,1]}}}}"#;
    let path = two_set_gltf("quarter-turn", &[QUAD_UV], material, &[red_green(), top]);
    let p = quarter_pixels(&path);
    assert_eq!(p.map(|c| c[2]), [0, 0, 255, 255], "{p:?}");
}

/// CLAMP_TO_EDGE reads the edge texel however far the coordinate is: a
/// texture red in its left half and green in its right, on a quad whose u
/// runs from −3 to 4, is red for every u below ½ and green above, at
/// u = −2.5, −1 and 2, 3.5 too (where a map laid out twice as large with
/// its edges repeated again: −1 read green, 2 and 3.5 red).
#[test]
fn clamp_to_edge_is_exact_at_any_distance() {
    let picture = |wrap: &str| {
        let mut q = quad(-1.0, 1.0, -0.5, 0.5, -3.0, 4.0);
        q.material = Some(0);
        let mut doc = Doc::new(vec![q]);
        doc.materials = r#"[{"pbrMetallicRoughness":{"baseColorTexture":{"index":0}}}]"#.into();
        doc.images = vec![red_green()];
        doc.sampler = Some(format!(r#"{{"magFilter":9728,"minFilter":9728,{wrap}}}"#));
        let path = write("clamp", "far.glb", &encode(&doc));
        let mut scene = scene_of(load_ok(&path));
        light_on_seam(&mut scene);
        let fb = render(&scene, &face_on());
        let half = projected_half_width(&scene);
        let x = move |u: f32| (W as f32 / 2.0 - half + (u + 3.0) / 7.0 * 2.0 * half) as usize;
        move |u: f32| px(&fb, x(u), H / 2)
    };
    let red = |c: [u8; 3]| c[0] > 0 && c[1] == 0;
    let green = |c: [u8; 3]| c[1] > 0 && c[0] == 0;
    let at = picture(r#""wrapS":33071,"wrapT":33071"#);
    for u in [-2.5, -1.0, 0.25] {
        assert!(red(at(u)), "u = {u}: {:?}", at(u));
    }
    for u in [0.75, 2.0, 3.5] {
        assert!(green(at(u)), "u = {u}: {:?}", at(u));
    }
    // S repeating beside a clamped T: u = −2.75 and 2.25 read ¼ (red),
    // −0.25 and 3.75 read ¾ (green).
    let at = picture(r#""wrapS":10497,"wrapT":33071"#);
    for u in [-2.75, 2.25] {
        assert!(red(at(u)), "repeat u = {u}: {:?}", at(u));
    }
    for u in [-0.25, 3.75] {
        assert!(green(at(u)), "repeat u = {u}: {:?}", at(u));
    }
}

/// A glTF file's parts all have metallic-roughness materials (the default
/// material is one): the model view shades it physically, and its notes
/// say so (the view refuses the Phong-only keys); a built-in model's do not.
#[test]
fn a_gltf_file_is_noted_as_shaded_physically() {
    use relief_scene::{Built, ModelChoice, SceneKind, build_scene_noting};
    let path = write(
        "physical",
        "quad.glb",
        &encode(&Doc::new(vec![quad(-1.0, 1.0, -1.0, 1.0, 0.0, 1.0)])),
    );
    let texture = Arc::new(procedural::brick());
    let build = |choice: &ModelChoice| {
        let (built, notes) = build_scene_noting(SceneKind::Cube, choice, texture.clone(), false)
            .unwrap_or_else(|e| panic!("{e}"));
        let Built::Scene(scene) = built else {
            panic!("a 3D scene")
        };
        assert_eq!(scene.all_physical(), notes.physical);
        assert_eq!(scene.texture_reach(), notes.texture_reach);
        notes.physical
    };
    assert!(build(&ModelChoice::File(path.clone())));
    assert!(!build(&ModelChoice::Sphere));
    // Its parts have their own material (white without a map): the
    // scene's texture never goes on them, and `t` is not refused.
    let (_, notes) =
        build_scene_noting(SceneKind::Cube, &ModelChoice::File(path), texture, false).unwrap();
    assert_eq!(
        notes.texture_reach,
        Some(relief_scene::model_view::TextureReach::Own)
    );
}

/// `--colors off` drops a file's vertex colours (COLOR_0), not its
/// material's own colour: a quad with COLOR_0 and a `baseColorFactor`
/// drawn without colours is the same quad without COLOR_0, and not white.
#[test]
fn colours_off_keeps_the_base_colour_factor() {
    let factor = r#"[{"pbrMetallicRoughness":{"baseColorFactor":[1.0,0.5,0.25,1.0]}}]"#;
    let file = |test: &str, col: Vec<[f32; 3]>| {
        let mut doc = Doc::new(vec![Prim {
            col,
            material: Some(0),
            ..quad(-1.0, 1.0, -1.0, 1.0, 0.0, 1.0)
        }]);
        doc.materials = factor.into();
        let path = write(test, "quad.glb", &encode(&doc));
        scene_of(load_ok(&path))
    };
    let coloured = file("colours_off", vec![[0.2, 1.0, 0.2]; 4]);
    let plain = file("colours_plain", Vec::new());
    let off = Settings {
        colors: false,
        ..face_on()
    };
    let (a, b) = (render(&coloured, &off), render(&plain, &face_on()));
    assert_eq!(a.pixels(), b.pixels(), "colours off: the factor alone");
    let on = render(&coloured, &face_on());
    assert_ne!(on.pixels(), a.pixels(), "colours on: COLOR_0 shows");
    let centre = a.pixels()[(H / 2) * W + W / 2];
    assert!(centre[0] > centre[1] && centre[1] > centre[2], "{centre:?}");
}
