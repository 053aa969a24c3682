//! `relief render` as a user runs it: every mode combination writes a PNG,
//! bad input gives one clear line on stderr and a non-zero exit.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn relief(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_relief"))
        .args(args)
        .output()
        .expect("the binary runs")
}

/// An output path in the temporary folder, removed when the test is done
/// with it.
struct Scratch(PathBuf);

impl std::ops::Deref for Scratch {
    type Target = Path;
    fn deref(&self) -> &Path {
        &self.0
    }
}

impl AsRef<Path> for Scratch {
    fn as_ref(&self) -> &Path {
        &self.0
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.0);
    }
}

fn scratch(name: &str) -> Scratch {
    Scratch(std::env::temp_dir().join(format!("relief-cli-{}-{name}", std::process::id())))
}

#[test]
fn every_mode_combination_writes_a_png() {
    let mut images = Vec::new();
    for normals in ["vertex", "face"] {
        for shading in ["flat", "gouraud", "phong"] {
            for texture in ["on", "off"] {
                for colors in ["on", "off"] {
                    for bump in ["on", "off"] {
                        let out = scratch(&format!(
                            "{normals}-{shading}-{texture}-{colors}-{bump}.png"
                        ));
                        let o = relief(&[
                            "render",
                            "--out",
                            out.to_str().unwrap(),
                            "--normals",
                            normals,
                            "--shading",
                            shading,
                            "--texture",
                            texture,
                            "--colors",
                            colors,
                            "--bump",
                            bump,
                        ]);
                        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
                        let img = relief_texture::picture::open(&out)
                            .expect("a PNG")
                            .to_rgb8();
                        assert_eq!(img.dimensions(), (320, 240));
                        let bg = image::Rgb([16, 24, 32]);
                        assert_eq!(img.pixels().filter(|&&p| p != bg).count(), 11_741);
                        images.push(img.into_raw());
                    }
                }
            }
        }
    }
    assert_eq!(images.len(), 48);
    // Bump only shows in Phong: 48 combinations, 8 of which repeat another
    // (bump on = bump off in flat and Gouraud, for each normals × texture × colours
    // … and flat ignores the normals switch): count the distinct pictures.
    let mut distinct = images.clone();
    distinct.sort();
    distinct.dedup();
    // Phong: 2 normals × 2 × 2 × 2 = 16; Gouraud: 2 × 2 × 2 = 8; flat: 2 × 2 = 4.
    assert_eq!(distinct.len(), 28);
}

#[test]
fn ansi_output_is_one_line_per_two_pixel_rows() {
    let o = relief(&["render", "--ansi", "--width", "40", "--height", "25"]);
    assert!(o.status.success());
    let text = String::from_utf8(o.stdout).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 13);
    // Every cell is a half block or a space (the view's encoder picks the shorter).
    for l in &lines {
        let cells = l.matches(['▀', '▄', ' ']).count();
        assert_eq!(cells, 40, "{l:?}");
    }
    assert!(text.contains("48;2;16;24;32m"));
    assert!(
        !text.contains("\x1b[H"),
        "no absolute cursor move in a file"
    );
}

#[test]
fn color_flag_writes_the_picture_a_palette_terminal_shows() {
    let o = relief(&[
        "render", "--ansi", "--width", "40", "--height", "24", "--color", "256",
    ]);
    assert!(o.status.success());
    let text = String::from_utf8(o.stdout).unwrap();
    assert!(
        text.contains(";5;") && !text.contains(";2;"),
        "indexed colours only"
    );
    let out = scratch("c16.png");
    let o = relief(&[
        "render",
        "--out",
        out.to_str().unwrap(),
        "--width",
        "40",
        "--height",
        "24",
        "--color",
        "16",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let img = relief_texture::picture::open(&out).unwrap().to_rgb8();
    let ansi: Vec<[u8; 3]> = relief_term::palette::ANSI16.iter().map(|c| c.0).collect();
    assert!(
        img.pixels().all(|p| ansi.contains(&p.0)),
        "only the 16 colours"
    );
    let distinct: std::collections::HashSet<_> = img.pixels().map(|p| p.0).collect();
    assert!(distinct.len() >= 3, "{distinct:?}");
}

fn fails_with(args: &[&str], needle: &str) {
    let o = relief(args);
    assert!(!o.status.success(), "{args:?} should fail");
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains(needle), "{args:?}: {err}");
    assert!(!err.contains("panicked"));
    assert!(!err.bytes().any(|b| b == 0x1b), "raw escape in the error");
}

#[test]
fn bad_input_gives_a_clear_error_and_a_non_zero_exit() {
    let out = scratch("never.png");
    let out = out.to_str().unwrap();
    fails_with(&["render", "--out", out, "--width", "0"], "width");
    fails_with(&["render", "--out", out, "--shading", "wobbly"], "wobbly");
    fails_with(&["render", "--out", out, "--rotate", "1,2"], "three angles");
    fails_with(&["render", "--out", out, "--rotate", "1,nan,2"], "finite");
    fails_with(
        &["render", "--out", out, "--bump-strength", "-1"],
        "bump strength",
    );
    fails_with(
        &["render", "--out", out, "no-such-file.png"],
        "no-such-file.png",
    );
    fails_with(&["render", "--out", out, "."], "");
    fails_with(
        &["render", "--out", out, "bad\x1b[31mname.png"],
        "bad?[31mname.png",
    );
    fails_with(&["render"], "--out");
    let dir = std::env::temp_dir();
    fails_with(&["render", "--out", dir.to_str().unwrap()], "cannot write");
}

#[test]
fn negative_angles_are_accepted() {
    let out = scratch("negative.png");
    let o = relief(&[
        "render",
        "--out",
        out.to_str().unwrap(),
        "--rotate",
        "-25,-35,-10",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

/// A fresh empty folder in the temporary folder, removed at the end.
struct ScratchDir(PathBuf);

impl Drop for ScratchDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

fn scratch_dir(name: &str) -> ScratchDir {
    let dir = std::env::temp_dir().join(format!("relief-cli-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    ScratchDir(dir)
}

fn mode_of(path: &Path) -> u32 {
    use std::os::unix::fs::PermissionsExt;
    std::fs::metadata(path).unwrap().permissions().mode() & 0o7777
}

fn set_mode(path: &Path, mode: u32) {
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(path, std::fs::Permissions::from_mode(mode)).unwrap();
}

#[test]
fn out_refuses_a_read_only_file_and_keeps_it() {
    let dir = scratch_dir("readonly");
    let file = dir.0.join("kept.png");
    std::fs::write(&file, b"not to be replaced").unwrap();
    set_mode(&file, 0o444);
    let o = relief(&["render", "--out", file.to_str().unwrap()]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.contains("read-only (mode 444)"), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert_eq!(std::fs::read(&file).unwrap(), b"not to be replaced");
    assert_eq!(mode_of(&file), 0o444);
    // Nothing else was left in the folder (no temporary file).
    assert_eq!(std::fs::read_dir(&dir.0).unwrap().count(), 1);
}

#[test]
fn out_writes_through_a_symbolic_link() {
    let dir = scratch_dir("symlink");
    let real = dir.0.join("real.png");
    std::fs::write(&real, b"old").unwrap();
    set_mode(&real, 0o640);
    let link = dir.0.join("link.png");
    std::os::unix::fs::symlink("real.png", &link).unwrap();
    // A link to a link, too.
    let link2 = dir.0.join("link2.png");
    std::os::unix::fs::symlink(&link, &link2).unwrap();
    let o = relief(&["render", "--out", link2.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for l in [&link, &link2] {
        assert!(
            std::fs::symlink_metadata(l)
                .unwrap()
                .file_type()
                .is_symlink()
        );
    }
    let img = relief_texture::picture::open(&real).expect("the file behind the link is a PNG");
    assert_eq!((img.width(), img.height()), (320, 240));
    // The file keeps its permissions.
    assert_eq!(mode_of(&real), 0o640);
    // A link whose file does not exist yet: the file is made.
    let dangling = dir.0.join("dangling.png");
    std::os::unix::fs::symlink("made.png", &dangling).unwrap();
    let o = relief(&["render", "--out", dangling.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(
        std::fs::symlink_metadata(&dangling)
            .unwrap()
            .file_type()
            .is_symlink()
    );
    assert!(relief_texture::picture::open(dir.0.join("made.png")).is_ok());
    // A loop of links is refused with a sentence.
    let a = dir.0.join("a.png");
    std::os::unix::fs::symlink("b.png", &a).unwrap();
    std::os::unix::fs::symlink("a.png", dir.0.join("b.png")).unwrap();
    let o = relief(&["render", "--out", a.to_str().unwrap()]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.contains("too many levels of symbolic links"), "{err}");
}

#[test]
fn out_dash_is_standard_output() {
    let dir = scratch_dir("dash");
    let o = Command::new(env!("CARGO_BIN_EXE_relief"))
        .args(["render", "--out", "-", "--width", "40", "--height", "30"])
        .current_dir(&dir.0)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let img = relief_texture::picture::decode_as(&o.stdout, image::ImageFormat::Png)
        .expect("a PNG on stdout");
    assert_eq!((img.width(), img.height()), (40, 30));
    assert!(!dir.0.join("-").exists(), "no file named -");
    assert_eq!(std::fs::read_dir(&dir.0).unwrap().count(), 0);
}

#[test]
fn ansi_text_lines_end_with_lf() {
    let o = relief(&["render", "--ansi", "--width", "40", "--height", "100"]);
    assert!(o.status.success());
    // 100 pixel rows are 50 cell rows (more than one band of 32).
    assert!(!o.stdout.contains(&b'\r'), "no carriage return");
    assert_eq!(o.stdout.iter().filter(|&&b| b == b'\n').count(), 50);
}

#[test]
fn ansi_writes_every_symbol_set_and_pixel_format_with_lf_rows() {
    for (symbols, rows) in [("half", 5), ("quad", 5), ("sextant", 4), ("octant", 3)] {
        let o = relief(&[
            "render",
            "--ansi",
            "--width",
            "20",
            "--height",
            "10",
            "--symbols",
            symbols,
        ]);
        assert!(o.status.success());
        let text = String::from_utf8(o.stdout).unwrap();
        assert!(!text.contains('\r'), "{symbols}: LF only");
        assert_eq!(text.lines().count(), rows, "{symbols}");
    }
    let o = relief(&[
        "render", "--ansi", "--width", "20", "--height", "10", "--format", "kitty",
    ]);
    assert!(o.status.success());
    let text = String::from_utf8(o.stdout).unwrap();
    assert!(
        text.starts_with("\x1b_Ga=T,f=24,o=z,s=20,v=10,"),
        "{text:?}"
    );
    assert!(text.ends_with("\x1b\\\n"));
    let o = relief(&[
        "render", "--ansi", "--width", "20", "--height", "10", "--format", "sixels",
    ]);
    let text = String::from_utf8(o.stdout).unwrap();
    assert!(text.starts_with("\x1bP0;1;0q\"1;1;20;10#0;2;"), "{text:?}");
    assert!(text.ends_with("\x1b\\\n"));
    let o = relief(&[
        "render", "--ansi", "--width", "20", "--height", "10", "--format", "iterm",
    ]);
    let text = String::from_utf8(o.stdout).unwrap();
    assert!(
        text.starts_with("\x1b]1337;File=inline=1;size="),
        "{text:?}"
    );
    assert!(text.ends_with("\x07\n"));
}

#[test]
fn ansi_rows_each_end_with_a_reset() {
    // A row that ends on a coloured cell leaves no colour set for the rest
    // of a wider line, whatever the symbols and the depth.
    for symbols in ["half", "quad", "sextant", "octant"] {
        for color in ["truecolor", "256", "16"] {
            let o = relief(&[
                "render",
                "--ansi",
                "--width",
                "24",
                "--height",
                "24",
                "--symbols",
                symbols,
                "--color",
                color,
            ]);
            assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
            let text = String::from_utf8(o.stdout).unwrap();
            for (k, line) in text.lines().enumerate() {
                assert!(
                    line.contains("\x1b["),
                    "{symbols} {color} row {k}: coloured"
                );
                assert!(
                    line.ends_with("\x1b[0m"),
                    "{symbols} {color} row {k}: {line:?}"
                );
            }
        }
    }
}

#[test]
fn a_missing_model_is_not_found_in_every_format() {
    let dir = scratch_dir("missing-model");
    let out = dir.0.join("x.png");
    for ext in ["glb", "gltf", "obj", "stl", "ply", "GLB"] {
        let model = dir.0.join(format!("none.{ext}"));
        let shown = model.to_str().unwrap();
        for args in [
            vec!["render", "--out", out.to_str().unwrap(), "--model", shown],
            vec!["render", "--out", out.to_str().unwrap(), shown],
            vec!["render", "--ansi", shown],
        ] {
            let o = relief(&args);
            let err = String::from_utf8_lossy(&o.stderr);
            assert_eq!(o.status.code(), Some(1), "{args:?}: {err}");
            assert_eq!(
                err.trim_end(),
                format!("relief: model {shown} not found"),
                "{args:?}"
            );
        }
    }
}

/// `relief render MODEL` draws a model that names no material plain (the
/// same picture as with `--texture off`); naming a picture with it
/// (`relief render IMAGE --model MODEL`) lays that picture on it.
#[test]
fn a_model_without_material_is_plain_unless_a_picture_is_named() {
    let model = scratch("bare.obj");
    std::fs::write(
        &model,
        "v -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\nf 1 2 3\nf 1 3 4\n",
    )
    .unwrap();
    let brick = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/reference-brick.png");
    let draw = |name: &str, extra: &[&str]| {
        let out = scratch(name);
        let mut args = vec!["render", "--width", "96", "--height", "72", "--out"];
        args.push(out.to_str().unwrap());
        args.extend_from_slice(extra);
        let o = relief(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        std::fs::read(&*out).unwrap()
    };
    let m = model.to_str().unwrap();
    let plain = draw("plain.png", &[m]);
    assert_eq!(draw("off.png", &[m, "--texture", "off"]), plain);
    let dressed = draw("dressed.png", &[brick.to_str().unwrap(), "--model", m]);
    assert_ne!(dressed, plain);
}

/// `relief render FILE.stl` stands the model Z up (STL's convention), as
/// `--up z` does; `--up y` still stands it as the file's Y axis says.
#[test]
fn an_stl_is_drawn_z_up_unless_up_says_otherwise() {
    let model = scratch("tall.stl");
    // A box 0.4 × 0.4 × 2 along Z: upright, it is taller than it is wide.
    let mut text = String::from("solid tall\n");
    let (lo, hi) = ([-0.2, -0.2, -1.0], [0.2, 0.2, 1.0]);
    let corner = |i: usize| {
        let pick = |bit: usize, k: usize| if i & bit != 0 { hi[k] } else { lo[k] };
        [pick(1, 0), pick(2, 1), pick(4, 2)]
    };
    for q in [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
    ] {
        for t in [[q[0], q[1], q[2]], [q[0], q[2], q[3]]] {
            text += "facet normal 0 0 0\nouter loop\n";
            for v in t {
                let p = corner(v);
                text += &format!("vertex {} {} {}\n", p[0], p[1], p[2]);
            }
            text += "endloop\nendfacet\n";
        }
    }
    text += "endsolid tall\n";
    std::fs::write(&model, text).unwrap();
    let m = model.to_str().unwrap();
    let draw = |name: &str, extra: &[&str]| {
        let out = scratch(name);
        let mut args = vec!["render", m, "--width", "96", "--height", "72", "--out"];
        args.push(out.to_str().unwrap());
        args.extend_from_slice(extra);
        let o = relief(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        std::fs::read(&*out).unwrap()
    };
    let default = draw("default.ppm", &[]);
    assert_eq!(draw("z.ppm", &["--up", "z"]), default);
    let y = draw("y.ppm", &["--up", "y"]);
    assert_ne!(y, default);
    // Upright, the model's covered rows outnumber its covered columns.
    let (w, h) = (96usize, 72usize);
    let extent = |ppm: &[u8]| {
        let pixels = &ppm[ppm.len() - w * h * 3..];
        let bg = &pixels[0..3];
        let (mut cols, mut rows) = (vec![false; w], vec![false; h]);
        for y in 0..h {
            for x in 0..w {
                if &pixels[(y * w + x) * 3..(y * w + x) * 3 + 3] != bg {
                    cols[x] = true;
                    rows[y] = true;
                }
            }
        }
        let count = |v: &[bool]| v.iter().filter(|&&b| b).count();
        (count(&cols), count(&rows))
    };
    let (cols, rows) = extent(&default);
    assert!(rows > 2 * cols, "upright: {cols} columns, {rows} rows");
    let (cols, rows) = extent(&y);
    assert!(cols > rows, "lying: {cols} columns, {rows} rows");
}
