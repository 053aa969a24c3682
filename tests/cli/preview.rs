//! `relief render` as a file manager's previewer: `--cells COLSxROWS`
//! fills exactly that many cells, and `-` reads the model or picture from
//! standard input (the same frame as from its path).

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

fn relief(args: &[&str], stdin: Option<&Path>) -> Output {
    let mut command = Command::new(env!("CARGO_BIN_EXE_relief"));
    command.args(args);
    match stdin {
        Some(path) => command.stdin(std::fs::File::open(path).unwrap()),
        None => command.stdin(Stdio::null()),
    };
    command.output().expect("the binary runs")
}

/// A folder of its own in the temporary folder, removed at the end.
struct Folder(PathBuf);

impl Folder {
    fn new(name: &str) -> Folder {
        let dir =
            std::env::temp_dir().join(format!("relief-preview-{}-{name}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        Folder(dir)
    }

    fn write(&self, name: &str, bytes: &[u8]) -> PathBuf {
        let path = self.0.join(name);
        std::fs::write(&path, bytes).unwrap();
        path
    }
}

impl Drop for Folder {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// The text with its escape sequences (CSI, and APC/OSC/DCS strings) taken out.
fn visible(text: &str) -> String {
    let mut out = String::new();
    let mut chars = text.chars().peekable();
    while let Some(c) = chars.next() {
        if c != '\x1b' {
            out.push(c);
            continue;
        }
        if chars.next() == Some('[') {
            for c in chars.by_ref() {
                if ('@'..='~').contains(&c) {
                    break;
                }
            }
        }
    }
    out
}

#[test]
fn cells_give_exactly_rows_lines_of_cols_cells_in_every_symbol_set() {
    for symbols in ["half", "quad", "sextant", "octant"] {
        for (cols, rows) in [(80, 24), (31, 7), (1, 1)] {
            let cells = format!("{cols}x{rows}");
            let o = relief(
                &[
                    "render",
                    "--ansi",
                    "--cells",
                    &cells,
                    "--symbols",
                    symbols,
                    "--model",
                    "sphere",
                ],
                None,
            );
            let err = String::from_utf8_lossy(&o.stderr);
            assert!(o.status.success(), "{symbols} {cells}: {err}");
            let text = String::from_utf8(o.stdout).unwrap();
            let lines: Vec<&str> = text.split_terminator('\n').collect();
            assert_eq!(lines.len(), rows, "{symbols} {cells}");
            for line in lines {
                assert_eq!(visible(line).chars().count(), cols, "{symbols} {cells}");
            }
        }
    }
}

#[test]
fn cells_with_a_pixel_format_fill_the_cells() {
    let o = relief(
        &["render", "--ansi", "--cells", "20x6", "--format", "kitty"],
        None,
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = String::from_utf8(o.stdout).unwrap();
    assert!(text.starts_with("\x1b_Ga=T,f=24,o=z,"), "{text:?}");
    assert!(text.contains(",c=20,r=6"), "placed on 20x6 cells");
    let o = relief(
        &["render", "--ansi", "--cells", "20x6", "--format", "iterm"],
        None,
    );
    let text = String::from_utf8(o.stdout).unwrap();
    assert!(text.contains(";width=20;height=6;"), "{text:?}");
}

fn binary_stl() -> Vec<u8> {
    let tri = |n: [f32; 3], a: [f32; 3], b: [f32; 3], c: [f32; 3]| {
        let mut v = Vec::new();
        for p in [n, a, b, c] {
            for x in p {
                v.extend_from_slice(&x.to_le_bytes());
            }
        }
        v.extend_from_slice(&[0, 0]);
        v
    };
    let mut bytes = vec![b' '; 80];
    bytes.extend_from_slice(&2u32.to_le_bytes());
    bytes.extend(tri(
        [0.0, 0.0, 1.0],
        [0.0; 3],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
    ));
    bytes.extend(tri(
        [1.0, 0.0, 0.0],
        [0.0; 3],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
    ));
    bytes
}

const OBJ: &str =
    "# a tetrahedron\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";

const PLY: &str = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nelement face 4\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";

/// A PNG of `w × h` pixels, a colour gradient.
fn png(w: u32, h: u32) -> Vec<u8> {
    let picture = image::RgbImage::from_fn(w, h, |x, y| {
        image::Rgb([(x * 255 / w) as u8, (y * 255 / h) as u8, 128])
    });
    relief_texture::picture::encode(&picture.into(), image::ImageFormat::Png).unwrap()
}

/// A GLB of one textured quad, its PNG in the binary chunk.
fn textured_glb() -> Vec<u8> {
    let floats = |v: &[f32]| v.iter().flat_map(|f| f.to_le_bytes()).collect::<Vec<u8>>();
    let mut bin = floats(&[
        -1.0, -1.0, 0.0, 1.0, -1.0, 0.0, 1.0, 1.0, 0.0, -1.0, 1.0, 0.0,
    ]);
    bin.extend(floats(&[0.0, 1.0, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0]));
    bin.extend([0u16, 1, 2, 0, 2, 3].iter().flat_map(|i| i.to_le_bytes()));
    let picture = png(96, 64);
    bin.extend_from_slice(&picture);
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0}}],
"meshes":[{{"primitives":[{{"attributes":{{"POSITION":0,"TEXCOORD_0":1}},"indices":2,"material":0}}]}}],
"materials":[{{"pbrMetallicRoughness":{{"baseColorTexture":{{"index":0}}}},"doubleSided":true}}],
"textures":[{{"source":0}}],"images":[{{"bufferView":3,"mimeType":"image/png"}}],
"buffers":[{{"byteLength":{len}}}],
"bufferViews":[{{"buffer":0,"byteOffset":0,"byteLength":48}},{{"buffer":0,"byteOffset":48,"byteLength":32}},
{{"buffer":0,"byteOffset":80,"byteLength":12}},{{"buffer":0,"byteOffset":92,"byteLength":{png}}}],
"accessors":[{{"bufferView":0,"componentType":5126,"count":4,"type":"VEC3","min":[-1,-1,0],"max":[1,1,0]}},
{{"bufferView":1,"componentType":5126,"count":4,"type":"VEC2"}},{{"bufferView":2,"componentType":5123,"count":6,"type":"SCALAR"}}]}}"#,
        len = bin.len(),
        png = picture.len()
    );
    glb(&json, &bin)
}

fn glb(json: &str, bin: &[u8]) -> Vec<u8> {
    let pad = |mut v: Vec<u8>, with: u8| {
        while !v.len().is_multiple_of(4) {
            v.push(with);
        }
        v
    };
    let (json, bin) = (pad(json.as_bytes().to_vec(), b' '), pad(bin.to_vec(), 0));
    let mut out = Vec::new();
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&((28 + json.len() + bin.len()) as u32).to_le_bytes());
    out.extend_from_slice(&(json.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&json);
    out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(&bin);
    out
}

#[test]
fn standard_input_gives_the_bytes_its_path_gives() {
    let dir = Folder::new("same");
    let files = [
        dir.write("model.glb", &textured_glb()),
        dir.write("model.obj", OBJ.as_bytes()),
        dir.write("model.stl", &binary_stl()),
        dir.write("model.ply", PLY.as_bytes()),
        dir.write("picture.png", &png(40, 30)),
    ];
    for file in &files {
        for symbols in ["half", "octant"] {
            let args = ["render", "--ansi", "--cells", "24x8", "--symbols", symbols];
            let by_path = relief(&[&args[..], &[file.to_str().unwrap()]].concat(), None);
            let by_stdin = relief(&[&args[..], &["-"]].concat(), Some(file));
            let name = file.file_name().unwrap().to_string_lossy();
            for o in [&by_path, &by_stdin] {
                let err = String::from_utf8_lossy(&o.stderr);
                assert!(o.status.success(), "{name} {symbols}: {err}");
                assert_eq!(err, "", "{name} {symbols}");
            }
            assert_eq!(by_path.stdout.iter().filter(|&&b| b == b'\n').count(), 8);
            assert!(
                by_path.stdout == by_stdin.stdout,
                "{name} {symbols}: standard input draws another frame"
            );
        }
    }
    // A picture file written by --out: the same pixels too.
    let out = dir.0.join("frame.png");
    let args = ["render", "--cells", "12x5", "--out", out.to_str().unwrap()];
    let o = relief(&[&args[..], &[files[0].to_str().unwrap()]].concat(), None);
    assert!(o.status.success());
    let by_path = std::fs::read(&out).unwrap();
    let o = relief(&[&args[..], &["-"]].concat(), Some(&files[0]));
    assert!(o.status.success());
    assert!(std::fs::read(&out).unwrap() == by_path);
}

#[test]
fn standard_input_without_a_folder_says_what_it_leaves_out() {
    let dir = Folder::new("nofolder");
    // An OBJ naming its MTL: drawn, its materials left out with a warning.
    let obj = dir.write("lib.obj", format!("mtllib lib.mtl\n{OBJ}").as_bytes());
    dir.write("lib.mtl", b"newmtl red\nKd 1 0 0\n");
    let o = relief(&["render", "--ansi", "--cells", "10x4", "-"], Some(&obj));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(
        err.contains("material libraries (mtllib) are not read"),
        "{err}"
    );
    // A glTF whose buffer is a file beside it: refused, saying so.
    let gltf = dir.write(
        "split.gltf",
        br#"{"asset":{"version":"2.0"},"buffers":[{"uri":"split.bin","byteLength":36}]}"#,
    );
    let o = relief(&["render", "--ansi", "--cells", "10x4", "-"], Some(&gltf));
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(
        err.contains("from standard input") && err.contains("'split.bin'"),
        "{err}"
    );
    // Bytes that are neither a model nor a picture, and nothing at all.
    let junk = dir.write("junk.bin", b"hello world\n");
    let o = relief(&["render", "--ansi", "-"], Some(&junk));
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1));
    assert!(err.contains("neither a model nor a picture"), "{err}");
    let o = relief(&["render", "--ansi", "-"], None);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1));
    assert!(err.contains("standard input is empty"), "{err}");
}

#[test]
fn a_model_piped_in_is_drawn() {
    // Through a real pipe, not a file: the reader cannot seek or ask its size.
    let mut child = Command::new(env!("CARGO_BIN_EXE_relief"))
        .args(["render", "--ansi", "--cells", "16x6", "-"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut stdin = child.stdin.take().unwrap();
    stdin.write_all(&binary_stl()).unwrap();
    drop(stdin);
    let o = child.wait_with_output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(o.stdout.iter().filter(|&&b| b == b'\n').count(), 6);
}
