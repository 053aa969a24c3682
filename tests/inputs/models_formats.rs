//! Model files of every format: OBJ with its MTL, STL (binary and ASCII),
//! PLY (ASCII, binary little and big endian); real files from public test
//! corpora (tests/data/models) and files the tests write; hostile files
//! refused with one line that says where.

use std::path::{Path, PathBuf};

use glam::Vec3;
use relief_scene::loaded_model::LoadedModel;
use relief_scene::model_file;
use relief_scene::{Mesh, ModelChoice};

fn data(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/models")
        .join(path)
}

fn load(path: &Path) -> LoadedModel {
    model_file::load(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn refused(path: &Path) -> String {
    let e = model_file::load(path).expect_err("refused");
    let text = e.to_string();
    assert!(!text.contains('\n'), "one line: {text}");
    text
}

/// A fresh directory for files a test writes.
fn temp_dir(name: &str) -> PathBuf {
    crate::common::scratch::fresh_scratch_dir(&format!("formats-{name}"))
}

fn write(dir: &Path, name: &str, bytes: impl AsRef<[u8]>) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

// ---- a cube, written in every format ------------------------------------------

/// The unit cube's 8 corners and its 12 triangles, counter-clockwise from outside.
fn cube() -> (Vec<Vec3>, Vec<[u32; 3]>) {
    let p: Vec<Vec3> = (0..8)
        .map(|i| Vec3::new((i & 1) as f32, ((i >> 1) & 1) as f32, ((i >> 2) & 1) as f32))
        .collect();
    let quads = [
        [0, 2, 3, 1], // z = 0, facing −z
        [4, 5, 7, 6], // z = 1
        [0, 1, 5, 4], // y = 0
        [2, 6, 7, 3], // y = 1
        [0, 4, 6, 2], // x = 0
        [1, 3, 7, 5], // x = 1
    ];
    let tris = quads
        .iter()
        .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
        .collect();
    (p, tris)
}

fn facet_normal(p: &[Vec3], t: [u32; 3]) -> Vec3 {
    let [a, b, c] = t.map(|i| p[i as usize]);
    (b - a).cross(c - a).normalize()
}

/// A binary STL of the cube with its facet normals; `header` starts the 80 bytes.
fn binary_stl(header: &[u8]) -> Vec<u8> {
    let (p, tris) = cube();
    let mut out = vec![0u8; 80];
    out[..header.len()].copy_from_slice(header);
    out.extend((tris.len() as u32).to_le_bytes());
    for t in tris {
        let n = facet_normal(&p, t);
        for v in [n, p[t[0] as usize], p[t[1] as usize], p[t[2] as usize]] {
            for x in v.to_array() {
                out.extend(x.to_le_bytes());
            }
        }
        out.extend([0, 0]);
    }
    out
}

fn ascii_stl() -> String {
    let (p, tris) = cube();
    let mut out = String::from("solid cube\n");
    for t in tris {
        let n = facet_normal(&p, t);
        out += &format!("facet normal {} {} {}\n outer loop\n", n.x, n.y, n.z);
        for i in t {
            let v = p[i as usize];
            out += &format!("  vertex {} {} {}\n", v.x, v.y, v.z);
        }
        out += " endloop\nendfacet\n";
    }
    out + "endsolid cube\n"
}

/// The cube as PLY in `format` (ascii, binary_little_endian, binary_big_endian),
/// with uchar colours and a uchar/int face list.
fn ply(format: &str) -> Vec<u8> {
    let (p, tris) = cube();
    let mut out = format!(
        "ply\nformat {format} 1.0\ncomment a cube\nelement vertex {}\nproperty float x\nproperty float y\nproperty float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\nelement face {}\nproperty list uchar int vertex_indices\nend_header\n",
        p.len(),
        tris.len()
    )
    .into_bytes();
    let color = |v: Vec3| [(v.x * 255.0) as u8, 128, 0];
    let big = format == "binary_big_endian";
    let f32_bytes = |x: f32| {
        if big {
            x.to_be_bytes()
        } else {
            x.to_le_bytes()
        }
    };
    let i32_bytes = |x: i32| {
        if big {
            x.to_be_bytes()
        } else {
            x.to_le_bytes()
        }
    };
    for &v in &p {
        let c = color(v);
        if format == "ascii" {
            out.extend(format!("{} {} {} {} {} {}\n", v.x, v.y, v.z, c[0], c[1], c[2]).bytes());
        } else {
            for x in v.to_array() {
                out.extend(f32_bytes(x));
            }
            out.extend(c);
        }
    }
    for t in &tris {
        if format == "ascii" {
            out.extend(format!("3 {} {} {}\n", t[0], t[1], t[2]).bytes());
        } else {
            out.push(3);
            for &i in t {
                out.extend(i32_bytes(i as i32));
            }
        }
    }
    out
}

// ---- STL --------------------------------------------------------------------------

#[test]
fn stl_facet_normals_make_hard_edges() {
    let dir = temp_dir("stl-hard");
    let path = write(&dir, "cube.stl", binary_stl(b"made by a test"));
    let mesh = load(&path).merged();
    assert_eq!(mesh.triangles.len(), 12);
    // Every corner keeps its facet's normal: 4 vertices per side.
    assert_eq!(mesh.vertices.len(), 24);
    for t in &mesh.faces() {
        for &i in &t.indices {
            let n = mesh.vertices[i as usize].normal;
            assert!(
                (n - t.face_normal).length() < 1e-6,
                "{n} vs {}",
                t.face_normal
            );
        }
    }
    let axes: Vec<Vec3> = mesh.faces().iter().map(|t| t.face_normal).collect();
    for axis in [Vec3::X, Vec3::Y, Vec3::Z] {
        assert_eq!(
            axes.iter().filter(|n| (**n - axis).length() < 1e-6).count(),
            2
        );
        assert_eq!(
            axes.iter().filter(|n| (**n + axis).length() < 1e-6).count(),
            2
        );
    }
    assert!(mesh.closed);
}

#[test]
fn a_binary_stl_beginning_with_solid_is_read_as_binary() {
    let dir = temp_dir("stl-solid");
    let binary = write(
        &dir,
        "solid.stl",
        binary_stl(b"solid exported by a CAD tool"),
    );
    let ascii = write(&dir, "ascii.stl", ascii_stl());
    let from_binary = load(&binary).merged();
    let from_ascii = load(&ascii).merged();
    assert_eq!(from_binary.triangles.len(), 12);
    assert_eq!(from_binary, from_ascii);
}

#[test]
fn stl_colours_follow_the_viscam_convention() {
    let dir = temp_dir("stl-colour");
    let mut bytes = binary_stl(b"coloured");
    // Facet 0: bit 15 set, red = 31 in bits 10..15 (VisCAM: blue in the low bits).
    let attribute: u16 = 0x8000 | (31 << 10);
    bytes[84 + 48..84 + 50].copy_from_slice(&attribute.to_le_bytes());
    let mesh = load(&write(&dir, "c.stl", bytes)).merged();
    let colours: Vec<Vec3> = mesh.faces().iter().map(|t| t.facet_color).collect();
    assert!(colours.contains(&Vec3::X), "{colours:?}");
    // The others are white.
    assert_eq!(colours.iter().filter(|c| **c == Vec3::ONE).count(), 11);
}

#[test]
fn assimp_stl_files_load() {
    for (file, triangles) in [("triangle.stl", 1), ("triangle_with_two_solids.stl", 2)] {
        let mesh = load(&data(&format!("assimp/{file}"))).merged();
        assert_eq!(mesh.triangles.len(), triangles, "{file}");
    }
    // A binary file: its facets with an area, counted here from the bytes.
    let bytes = std::fs::read(data("assimp/Spider_binary.stl")).unwrap();
    let count = u32::from_le_bytes(bytes[80..84].try_into().unwrap()) as usize;
    assert_eq!(bytes.len(), 84 + 50 * count);
    let with_area = bytes[84..]
        .chunks_exact(50)
        .filter(|f| {
            let v = |o: usize| {
                Vec3::from_array(std::array::from_fn(|k| {
                    f32::from_le_bytes(f[o + 4 * k..o + 4 * k + 4].try_into().unwrap())
                }))
            };
            let (a, b, c) = (v(12), v(24), v(36));
            (b - a).cross(c - a).normalize_or_zero() != Vec3::ZERO
        })
        .count();
    assert!(with_area > 1000);
    let mesh = load(&data("assimp/Spider_binary.stl")).merged();
    assert_eq!(mesh.triangles.len(), with_area);
    assert!(
        load(&data("assimp/sphereWithHole.stl"))
            .merged()
            .triangles
            .len()
            > 100
    );
}

// ---- PLY ---------------------------------------------------------------------------

#[test]
fn ply_ascii_and_binary_of_the_same_cube_give_the_same_mesh() {
    let dir = temp_dir("ply-cube");
    let meshes: Vec<Mesh> = ["ascii", "binary_little_endian", "binary_big_endian"]
        .iter()
        .map(|f| load(&write(&dir, &format!("{f}.ply"), ply(f))).merged())
        .collect();
    assert_eq!(meshes[0].triangles.len(), 12);
    assert!(meshes[0].closed);
    assert_eq!(meshes[0], meshes[1]);
    assert_eq!(meshes[0], meshes[2]);
    // uchar colours are divided by 255: x = 1 corners are (1, 128/255, 0).
    let green = 128.0 / 255.0;
    assert!(
        meshes[0]
            .vertices
            .iter()
            .any(|v| (v.color - Vec3::new(1.0, green, 0.0)).length() < 1e-6)
    );
}

/// Blender 2.47 wrote a header line that is not a `comment` ("Created by
/// Blender3D 247 - www.blender.org, source file: …"): it is skipped with a
/// warning naming its line, and the cube is the same as without it. A
/// line that begins with a PLY keyword but cannot be read still refuses.
#[test]
fn a_ply_header_line_of_unknown_words_is_skipped_with_a_warning() {
    let plain = ply("binary_little_endian");
    let line = b"Created by Blender3D 247 - www.blender.org, source file: 'wuson.blend'\n";
    let mut blender = plain[..4].to_vec();
    blender.extend_from_slice(line);
    blender.extend_from_slice(&plain[4..]);
    let with = relief_scene::ply::parse("blender.ply", &blender).unwrap();
    let without = relief_scene::ply::parse("plain.ply", &plain).unwrap();
    assert_eq!(with.merged(), without.merged());
    assert_eq!(with.warnings.len(), 1, "{:?}", with.warnings);
    let w = &with.warnings[0];
    assert!(
        w.contains("line 2") && w.contains("Created by Blender3D"),
        "{w}"
    );

    let text = String::from_utf8_lossy(&plain).replacen("element face 12", "element face", 1);
    let Err(e) = relief_scene::ply::parse("bad.ply", text.as_bytes()) else {
        panic!("a malformed element line was read");
    };
    assert!(e.to_string().contains("cannot read header line"), "{e}");
}

#[test]
fn assimp_ply_files_load() {
    let count = |f: &str| load(&data(&format!("assimp/{f}"))).merged().triangles.len();
    // Six quads, split in two.
    assert_eq!(count("cube.ply"), 12);
    assert_eq!(count("cube_binary.ply"), 12);
    assert_eq!(count("cube_binary_header_with_RN_newline.ply"), 12);
    assert_eq!(count("cube_uv.ply"), 12);
    // Float colours are taken as they are.
    let mesh = load(&data("assimp/float-color.ply")).merged();
    assert!(mesh.vertices.iter().all(|v| v.color == Vec3::Z));
    // s, t are texture coordinates: the file's, not a projection.
    let mesh = load(&data("assimp/cube_uv.ply")).merged();
    assert!(
        mesh.vertices
            .iter()
            .any(|v| v.uv == glam::Vec2::new(1.0, 1.0))
    );
}

#[test]
fn a_ply_without_faces_is_a_point_cloud() {
    let model = load(&data("assimp/points.ply"));
    assert!(model.points);
    let mesh = model.merged();
    assert_eq!(mesh.vertices.len(), 4);
    assert!(
        mesh.triangles
            .iter()
            .all(|t| t.indices[0] == t.indices[1] && t.indices[1] == t.indices[2])
    );
    // uchar colours: (255, 0, 255) is magenta.
    assert!(
        mesh.vertices
            .iter()
            .any(|v| v.color == Vec3::new(1.0, 0.0, 1.0))
    );
}

// ---- OBJ and MTL -------------------------------------------------------------------

#[test]
fn out_of_range_texture_coordinates_are_dropped_with_a_warning() {
    let dir = temp_dir("obj-vt");
    let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n\
                f 1/1 2/2 3/3\nf 2/9 4/2 3/3\n";
    let model = load(&write(&dir, "vt.obj", text));
    assert_eq!(model.merged().triangles.len(), 2);
    assert_eq!(model.warnings.len(), 1, "{:?}", model.warnings);
    let w = &model.warnings[0];
    assert!(w.contains("vt.obj, line 9"), "{w}");
    assert!(w.contains("texture coordinate index out of range"), "{w}");
    // The first face keeps the file's UVs.
    let mesh = model.merged();
    let first: Vec<[f32; 2]> = mesh.triangles[0]
        .indices
        .iter()
        .map(|&i| mesh.vertices[i as usize].uv.to_array())
        .collect();
    assert_eq!(first, vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]);
}

#[test]
fn tinyobjloader_files_load_with_their_warnings() {
    // 32 quads, each two triangles.
    let model = load(&data("tinyobjloader/catmark_torus_creases0.obj"));
    assert_eq!(model.merged().triangles.len(), 64);
    assert!(
        model
            .warnings
            .iter()
            .any(|w| w.contains("normal index out of range"))
    );
    // A quad and a triangle.
    let model = load(&data("tinyobjloader/smoothing-group-two-squares.obj"));
    assert_eq!(model.merged().triangles.len(), 3);
    // A missing texture is a warning; the model opens.
    let model = load(&data("tinyobjloader/texture-filename-with-whitespace.obj"));
    assert!(
        model
            .warnings
            .iter()
            .any(|w| w.contains("map_Kd 'texture 01.png'") && w.contains("not found")),
        "{:?}",
        model.warnings
    );
    // A part per material, with its description.
    let names: Vec<&str> = model
        .parts
        .iter()
        .filter_map(|p| p.material.as_ref().map(|m| m.name.as_str()))
        .collect();
    assert_eq!(names, vec!["white", "red", "green"]);
    // Four faces are white: eight triangles.
    assert_eq!(model.parts[0].mesh.triangles.len(), 8);
    let red = model.parts[1].material.as_ref().unwrap();
    assert_eq!(red.diffuse, Some(Vec3::X));
    assert_eq!(red.bump_multiplier, 2.0);
    assert_eq!(red.bump_map.as_ref().unwrap().written, "bump 01.png");
    // Kd colours the part's vertices.
    assert!(
        model.parts[1]
            .mesh
            .vertices
            .iter()
            .all(|v| v.color == Vec3::X)
    );
    // norm with its options.
    let model = load(&data("tinyobjloader/norm-texopt.obj"));
    let m = model.parts[0].material.as_ref().unwrap();
    assert_eq!(m.normal_map.as_ref().unwrap().written, "normalmap.jpg");
}

#[test]
fn numbers_and_encodings_as_tinyobjloader_reads_them() {
    let dir = temp_dir("obj-numbers");
    let model = load(&write(
        &dir,
        "e.obj",
        "v 0 0 0\nv 3.1+e2 0 0\nv 0 1 0\nf 1 2 3\n",
    ));
    assert!(model.warnings[0].contains("line 2"), "{:?}", model.warnings);
    // 3.1, not 310: the triangle's aspect says which (x extent 3.1, y extent 1).
    let mesh = model.merged();
    let xs: Vec<f32> = mesh.vertices.iter().map(|v| v.position.x).collect();
    let ys: Vec<f32> = mesh.vertices.iter().map(|v| v.position.y).collect();
    let span = |v: &[f32]| {
        v.iter().cloned().fold(f32::MIN, f32::max) - v.iter().cloned().fold(f32::MAX, f32::min)
    };
    assert!((span(&xs) / span(&ys) - 3.1).abs() < 1e-4);

    // UTF-16, little and big endian, with the byte-order mark.
    let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    let mut le = vec![0xFF, 0xFE];
    let mut be = vec![0xFE, 0xFF];
    for u in text.encode_utf16() {
        le.extend(u.to_le_bytes());
        be.extend(u.to_be_bytes());
    }
    let plain = load(&write(&dir, "plain.obj", text)).merged();
    assert_eq!(load(&write(&dir, "le.obj", le)).merged(), plain);
    assert_eq!(load(&write(&dir, "be.obj", be)).merged(), plain);
}

/// A 4×4 RGBA PNG: colour `rgb`, alpha (the height) `heights`.
fn png(path: &Path, rgb: [u8; 3], heights: [u8; 16]) {
    let mut buf = image::RgbaImage::new(4, 4);
    for (i, px) in buf.pixels_mut().enumerate() {
        *px = image::Rgba([rgb[0], rgb[1], rgb[2], heights[i]]);
    }
    relief_texture::picture::save(&buf.into(), path).unwrap();
}

const QUAD: &str = "mtllib quad.mtl\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\n\
                    vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nusemtl brick\nf 1/1 2/2 3/3 4/4\n";

#[test]
fn bump_multiplier_scales_the_heights_and_maps_reach_the_scene() {
    let dir = temp_dir("mtl-bump");
    std::fs::create_dir_all(dir.join("Maps")).unwrap();
    let heights: [u8; 16] = std::array::from_fn(|i| (i * 8) as u8);
    png(&dir.join("Maps/Colour.png"), [200, 100, 50], [255; 16]);
    png(&dir.join("Maps/height map.png"), [0, 0, 0], heights);
    png(&dir.join("Maps/normal.png"), [128, 128, 255], [255; 16]);
    let obj = write(&dir, "quad.obj", QUAD);
    let heights_of = |bm: &str| {
        // Backslashes, another case, a name with spaces after options.
        let mtl = format!(
            "newmtl brick\nKd 1 1 1\nmap_Kd maps\\colour.png\nbump {bm} -clamp on Maps/height map.png\nnorm -bm 1 Maps/normal.png\n"
        );
        write(&dir, "quad.mtl", mtl);
        let model = load(&obj);
        assert!(model.warnings.is_empty(), "{:?}", model.warnings);
        assert!(model.maps.normal_map.is_some());
        let texture = model.maps.texture.expect("map_Kd is the scene's texture");
        assert!(model.parts[0].mesh.triangles.iter().all(|t| t.textured));
        texture
            .base()
            .texels
            .iter()
            .map(|t| t[3])
            .collect::<Vec<f32>>()
    };
    let once = heights_of("");
    let twice = heights_of("-bm 2");
    assert!(once.iter().any(|h| *h > 0.1));
    for (a, b) in once.iter().zip(&twice) {
        assert!((b - 2.0 * a).abs() < 1e-6, "{a} → {b}");
    }
}

#[test]
fn a_missing_material_library_is_a_warning() {
    let dir = temp_dir("mtl-missing");
    let model = load(&write(&dir, "quad.obj", QUAD));
    assert_eq!(model.merged().triangles.len(), 2);
    assert!(
        model
            .warnings
            .iter()
            .any(|w| w.contains("'quad.mtl' not found"))
    );
}

// ---- hostile files -----------------------------------------------------------------

#[test]
fn hostile_files_are_refused_before_allocating() {
    let dir = temp_dir("hostile");
    // A PLY element count of 2^31 in a tiny binary file.
    let ply = b"ply\nformat binary_little_endian 1.0\nelement vertex 2147483648\nproperty float x\nproperty float y\nproperty float z\nend_header\n\0\0\0\0";
    let e = refused(&write(&dir, "count.ply", ply));
    // The body starts after the 124 bytes of the header.
    assert!(e.contains("count.ply, byte 124"), "{e}");
    assert!(e.contains("2147483648 vertex items"), "{e}");
    // The same in ASCII.
    let ply =
        b"ply\nformat ascii 1.0\nelement vertex 2147483648\nproperty float x\nend_header\n0\n";
    let e = refused(&write(&dir, "count_ascii.ply", ply));
    assert!(e.contains("count_ascii.ply, line 6"), "{e}");
    // A binary STL claiming 4 G triangles.
    let mut stl = vec![0u8; 80];
    stl.extend(u32::MAX.to_le_bytes());
    stl.extend([0u8; 50]);
    let e = refused(&write(&dir, "huge.stl", stl));
    assert!(
        e.contains("huge.stl, byte 80: the header claims 4294967295 triangles"),
        "{e}"
    );
    // NaN and infinite positions, in every format.
    let mut stl = binary_stl(b"nan");
    stl[84 + 50 + 24..84 + 50 + 28].copy_from_slice(&f32::NAN.to_le_bytes());
    let e = refused(&write(&dir, "nan.stl", stl));
    assert!(e.contains("nan.stl, byte 158: triangle 2"), "{e}");
    let e = refused(&write(
        &dir,
        "inf.obj",
        "v 0 0 0\nv inf 0 0\nv 0 1 0\nf 1 2 3\n",
    ));
    assert!(e.contains("inf.obj, line 2"), "{e}");
    let e = refused(&write(
        &dir,
        "big.obj",
        "v 0 0 0\nv 1e39 0 0\nv 0 1 0\nf 1 2 3\n",
    ));
    assert!(e.contains("big.obj, line 2"), "{e}");
    let mut ply = ply_bytes_with_nan();
    let e = refused(&write(&dir, "nan.ply", std::mem::take(&mut ply)));
    assert!(e.contains("nan.ply, line 9: vertex 2"), "{e}");
    // A face index out of range.
    let ply = b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n";
    let e = refused(&write(&dir, "index.ply", ply));
    assert!(
        e.contains("index.ply, line 13: face 1: vertex index 7 is out of range"),
        "{e}"
    );
    // A PLY whose header misdeclares its elements (assimp's issue623).
    let e = refused(&data("assimp/issue623.ply"));
    // Its vertices declare a list: the first list length is line 15's first number.
    assert!(
        e.contains("issue623.ply, line 15: '7.941797' is not a uchar number"),
        "{e}"
    );
    // A GLB cut short after its magic goes to the glTF reader, which names
    // the file and the byte where it ends.
    let path = write(&dir, "scene.glb", b"glTF");
    let Err(e) = relief_scene::gltf::load(&path) else {
        panic!("a 4-byte GLB is refused");
    };
    let e = e.to_string();
    assert!(e.contains("scene.glb"), "{e}");
    assert_eq!(e.lines().count(), 1, "{e}");
}

fn ply_bytes_with_nan() -> Vec<u8> {
    b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\nnan 0 0\n0 1 0\n"
        .to_vec()
}

#[test]
fn a_bad_model_keeps_the_scene_shown() {
    use relief_scene::SceneKind;
    let dir = temp_dir("stage");
    let good = write(&dir, "good.ply", ply("ascii"));
    let bad = write(&dir, "bad.stl", [0u8; 10]);
    let texture = std::sync::Arc::new(relief_texture::decode::procedural::brick());
    let mut stage =
        relief::app::stage::Stage::new(SceneKind::Cube, &ModelChoice::File(good), texture, false)
            .unwrap();
    let state = relief::app::State::new(
        relief_core::settings::Settings::default(),
        relief_term::ColorDepth::Truecolor,
    );
    let picture = |stage: &mut relief::app::stage::Stage| {
        let mut fb = relief_core::framebuffer::Framebuffer::new(32, 24);
        stage.render(
            &mut relief_pipeline::render::Renderer::new(),
            &state,
            &mut fb,
        );
        fb
    };
    let before = picture(&mut stage);
    let e = stage
        .build(SceneKind::Cube, &ModelChoice::File(bad))
        .expect_err("refused");
    assert!(e.contains("bad.stl, byte 0"), "{e}");
    // The good model is still the one drawn.
    assert_eq!(picture(&mut stage), before);
}

#[test]
fn render_opens_a_positional_model_file() {
    let dir = temp_dir("cli");
    let model = write(&dir, "cube.ply", ply("binary_big_endian"));
    let out = dir.join("x.png");
    let status = std::process::Command::new(env!("CARGO_BIN_EXE_relief"))
        .args(["render", "--width", "64", "--height", "48"])
        .arg(&model)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    assert!(
        status.status.success(),
        "{}",
        String::from_utf8_lossy(&status.stderr)
    );
    let picture = relief_texture::picture::open(&out).unwrap().to_rgb8();
    // The cube covers the middle of the picture: not the background there.
    let mid = picture.get_pixel(32, 24).0;
    assert_ne!(mid, relief_scene::BACKGROUND);
}

#[test]
fn each_material_draws_with_its_own_texture() {
    use relief_pipeline::render::render_frame;
    use relief_scene::{Built, SceneKind, build_scene};
    use relief_texture::decode::procedural;
    let dir = temp_dir("mtl-two");
    png(&dir.join("red.png"), [220, 0, 0], [255; 16]);
    png(&dir.join("blue.png"), [0, 0, 220], [255; 16]);
    png(&dir.join("green.png"), [0, 220, 0], [255; 16]);
    // Two quads side by side, each with its material; white Kd so only the
    // texture colours them.
    let obj = "mtllib two.mtl\n\
               v -2 -1 0\nv -0.2 -1 0\nv -0.2 1 0\nv -2 1 0\n\
               v 0.2 -1 0\nv 2 -1 0\nv 2 1 0\nv 0.2 1 0\n\
               vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n\
               usemtl red\nf 1/1 2/2 3/3 4/4\nusemtl blue\nf 5/1 6/2 7/3 8/4\n";
    write(
        &dir,
        "two.mtl",
        "newmtl red\nKd 1 1 1\nmap_Kd red.png\nnewmtl blue\nKd 1 1 1\nmap_Kd blue.png\n",
    );
    let path = write(&dir, "two.obj", obj);
    let model = load(&path);
    assert!(model.warnings.is_empty(), "{:?}", model.warnings);
    // The first textured material is the scene's; the other keeps its own.
    assert!(model.parts[0].own_maps.is_none());
    assert!(model.parts[1].own_maps.is_some());
    let Ok(Built::Scene(scene)) = build_scene(
        SceneKind::Cube,
        &ModelChoice::File(path.clone()),
        std::sync::Arc::new(procedural::brick()),
        false,
    ) else {
        panic!("the model builds a scene");
    };
    let mut settings = relief_core::settings::Settings {
        rotation: Vec3::ZERO,
        ..Default::default()
    };
    settings.bump = false;
    let (w, h) = (160, 120);
    let (fb, _) = render_frame(&scene, &settings, w, h);
    // Fitted to radius 1.5 the quads span x = ±(0.13..1.34); a 160×120
    // frame shows about 21 pixels a unit there, so 15 pixels either side
    // of the middle is inside each.
    let (left, right) = (fb.get(w / 2 - 15, h / 2), fb.get(w / 2 + 15, h / 2));
    assert!(left[0] > 2 * left[2] && left[0] > 40, "left {left:?}");
    assert!(right[2] > 2 * right[0] && right[2] > 40, "right {right:?}");
    // Changing the scene's texture (the `x` key's job) leaves the blue
    // part's own material alone.
    let mut scene = *scene;
    scene.material.texture = std::sync::Arc::new(
        relief_texture::decode::load::load_texture(&dir.join("green.png")).unwrap(),
    );
    let (fb, _) = render_frame(&scene, &settings, w, h);
    let (left, right) = (fb.get(w / 2 - 15, h / 2), fb.get(w / 2 + 15, h / 2));
    assert!(left[1] > 2 * left[0] && left[1] > 40, "left {left:?}");
    assert!(right[2] > 2 * right[1] && right[2] > 40, "right {right:?}");
}

/// The highlight alone (black `Kd`, one white light in front, no
/// attenuation) of a quad whose material has these `Ks` and `Ns` lines.
fn highlight_picture(name: &str, mtl: &str) -> relief_core::framebuffer::Framebuffer {
    use relief_pipeline::render::render_frame;
    use relief_scene::{Built, Light, SceneKind, build_scene};
    let dir = temp_dir(name);
    write(&dir, "q.mtl", format!("newmtl m\nKd 0 0 0\n{mtl}\n"));
    let obj = "mtllib q.mtl\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nusemtl m\nf 1 2 3 4\n";
    let path = write(&dir, "q.obj", obj);
    let Ok(Built::Scene(scene)) = build_scene(
        SceneKind::Cube,
        &ModelChoice::File(path),
        std::sync::Arc::new(relief_texture::decode::procedural::brick()),
        false,
    ) else {
        panic!("the model builds a scene");
    };
    // The Blinn-Phong highlight of the reference view (the model view
    // reads the material as metallic-roughness: tests/render/pbr.rs).
    let mut scene = (*scene).into_reference_view();
    scene.lights = vec![Light::new(Vec3::new(0.4, 0.3, 3.0), Vec3::ONE)];
    let settings = relief_core::settings::Settings {
        rotation: Vec3::ZERO,
        specular: true,
        shininess: 10.0,
        attenuation: false,
        bump: false,
        ..Default::default()
    };
    render_frame(&scene, &settings, 160, 120).0
}

/// `Ks` multiplies the highlight per channel and `Ns` is its exponent:
/// with (N·H)^s, Ns 20 gives the square of what Ns 10 gives at each pixel;
/// Ks 1 0.5 0.25 gives the white highlight's half and quarter in G and B.
#[test]
fn mtl_ks_and_ns_shape_the_highlight() {
    let plain = highlight_picture("ks-plain", "Ks 1 1 1\nNs 10");
    let tinted = highlight_picture("ks-tinted", "Ks 1 0.5 0.25\nNs 10");
    let sharper = highlight_picture("ns-sharper", "Ks 1 1 1\nNs 20");
    let unset = highlight_picture("ks-unset", "");
    // Without Ks and Ns the view's exponent (10 here) and a white highlight.
    assert_eq!(unset.pixels(), plain.pixels());
    let mut checked = 0;
    for ((p, t), s) in plain
        .pixels()
        .iter()
        .zip(tinted.pixels())
        .zip(sharper.pixels())
    {
        let h = p[0] as f32;
        if !(20.0..250.0).contains(&h) || p[1] != p[0] {
            continue;
        }
        checked += 1;
        assert_eq!(t[0], p[0]);
        assert!((t[1] as f32 - h * 0.5).abs() <= 1.0, "{p:?} {t:?}");
        assert!((t[2] as f32 - h * 0.25).abs() <= 1.0, "{p:?} {t:?}");
        let squared = 255.0 * (h / 255.0).powi(2);
        assert!(
            (s[0] as f32 - squared).abs() <= 2.0,
            "{p:?} {s:?} {squared}"
        );
    }
    assert!(checked > 50, "only {checked} pixels in the highlight");
}

/// MTL opacity as a mask at 0.5: `d 0.4` (or `Tr 0.6`) hides the quad,
/// `d 0.6` draws it, and a `map_d` black on its left half and white on its
/// right cuts the left half out.
#[test]
fn mtl_opacity_below_one_half_is_cut_out() {
    use relief_pipeline::render::render_frame;
    use relief_scene::{BACKGROUND, Built, SceneKind, build_scene};
    let picture = |name: &str, mtl: &str| {
        let dir = temp_dir(name);
        let mut img = image::RgbImage::new(4, 4);
        for (x, _, p) in img.enumerate_pixels_mut() {
            *p = if x < 2 {
                image::Rgb([0, 0, 0])
            } else {
                image::Rgb([255, 255, 255])
            };
        }
        relief_texture::picture::save(&img.into(), dir.join("d.png")).unwrap();
        write(&dir, "q.mtl", format!("newmtl m\nKd 1 1 1\n{mtl}\n"));
        let obj = "mtllib q.mtl\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\n\
                   vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nusemtl m\nf 1/1 2/2 3/3 4/4\n";
        let path = write(&dir, "q.obj", obj);
        let Ok(Built::Scene(scene)) = build_scene(
            SceneKind::Cube,
            &ModelChoice::File(path),
            std::sync::Arc::new(relief_texture::decode::procedural::brick()),
            false,
        ) else {
            panic!("the model builds a scene");
        };
        let settings = relief_core::settings::Settings {
            rotation: Vec3::ZERO,
            ..Default::default()
        };
        let (fb, _) = render_frame(&scene, &settings, 160, 120);
        // A quarter of the quad's width either side of the middle.
        (
            fb.get(80 - 15, 60) != BACKGROUND,
            fb.get(80 + 15, 60) != BACKGROUND,
        )
    };
    assert_eq!(picture("d-opaque", ""), (true, true));
    assert_eq!(picture("d-low", "d 0.4"), (false, false));
    assert_eq!(picture("tr-high", "Tr 0.6"), (false, false));
    assert_eq!(picture("d-high", "d 0.6"), (true, true));
    assert_eq!(picture("map-d", "map_d d.png"), (false, true));
}

/// The README's model (assets/models): its MTL's texture and normal map
/// load from beside it, and the torus has its 48 × 24 quads.
#[test]
fn the_readme_torus_loads_with_its_texture_and_normal_map() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/models/torus.obj");
    let model = load(&path);
    assert!(model.warnings.is_empty(), "{:?}", model.warnings);
    assert_eq!(model.merged().triangles.len(), 2 * 48 * 24);
    let texture = model.maps.texture.as_ref().expect("map_Kd");
    // The texture is assets/brick.png, at its own size.
    let brick = relief_texture::picture::open(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/brick.png"),
    )
    .unwrap();
    assert_eq!(
        (texture.width() as u32, texture.height() as u32),
        (brick.width(), brick.height())
    );
    assert!(model.maps.normal_map.is_some(), "norm");
    let m = model.parts[0].material.as_ref().unwrap();
    assert_eq!(m.specular, Some(Vec3::splat(0.6)));
    assert_eq!(m.shininess, Some(40.0));
}
