//! `relief render` flags that cannot apply say so on stderr; outputs that
//! are not regular files are refused; `--out` writes the format its
//! extension names.

use crate::hostile;

use hostile::relief;

fn stderr(o: &std::process::Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn outputs_are_regular_files_in_the_format_named() {
    let dir = hostile::scratch("flags-out");
    let p = |n: &str| dir.join(n).to_str().unwrap().to_owned();
    // A FIFO is refused at once (it would block forever).
    let fifo = p("fifo");
    let made = std::process::Command::new("mkfifo").arg(&fifo).status();
    if made.map(|s| s.success()).unwrap_or(false) {
        let o = relief(&["render", "--out", &fifo]);
        assert_eq!(o.status.code(), Some(1));
        assert!(stderr(&o).contains("not a regular file"), "{}", stderr(&o));
    } else {
        eprintln!("mkfifo not available: FIFO case skipped");
    }
    let o = relief(&["render", "--out", &p("sub")]);
    assert!(o.status.success());
    std::fs::create_dir(p("adir.png")).unwrap();
    let o = relief(&["render", "--out", &p("adir.png")]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    // The extension names the format.
    for (name, format) in [
        ("x.jpg", image::ImageFormat::Jpeg),
        ("x.BMP", image::ImageFormat::Bmp),
        ("x.png", image::ImageFormat::Png),
    ] {
        let o = relief(&[
            "render",
            "--width",
            "16",
            "--height",
            "8",
            "--out",
            &p(name),
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        let bytes = std::fs::read(p(name)).unwrap();
        assert_eq!(image::guess_format(&bytes).unwrap(), format, "{name}");
    }
    let o = relief(&["render", "--out", &p("x.xyz")]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("unknown picture extension"));
    assert!(!std::path::Path::new(&p("x.xyz")).exists());
    // No temporary file is left behind.
    let left: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().ends_with(".tmp"))
        .collect();
    assert!(left.is_empty(), "{left:?}");
    // Text and a picture at once is refused.
    let o = relief(&["render", "--ansi", "--out", &p("p.png")]);
    assert_eq!(o.status.code(), Some(2));
    assert!(!std::path::Path::new(&p("p.png")).exists());
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn flags_that_do_not_apply_are_named_on_stderr() {
    let dir = hostile::scratch("flags-notes");
    let out = dir.join("a.png").to_str().unwrap().to_owned();
    let cube = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/cube.obj");
    for (scene, model) in [("plasma", "missing.obj"), ("shadow", cube)] {
        let o = relief(&[
            "render", "--width", "32", "--height", "24", "--scene", scene, "--model", model,
            "--out", &out,
        ]);
        let err = stderr(&o);
        assert!(o.status.success(), "{err}");
        assert!(
            err.contains("--model") && err.contains("is ignored"),
            "{err}"
        );
    }
    let o = relief(&[
        "render", "--aa", "4x4", "--width", "2000", "--height", "1200", "--out", &out,
    ]);
    let err = stderr(&o);
    assert!(o.status.success(), "{err}");
    assert!(
        err.contains("--aa 4x4 falls back to 2x2 at 2000x1200"),
        "{err}"
    );
    let o = relief(&[
        "render", "--aa", "4x4", "--width", "64", "--height", "48", "--out", &out,
    ]);
    assert!(stderr(&o).is_empty(), "{}", stderr(&o));
    let _ = std::fs::remove_dir_all(dir);
}
