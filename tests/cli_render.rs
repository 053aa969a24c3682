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
                        let img = image::open(&out).expect("a PNG").to_rgb8();
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
    let img = image::open(&out).unwrap().to_rgb8();
    let ansi: Vec<[u8; 3]> = relief::term::color::ANSI16.iter().map(|c| c.0).collect();
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
