//! Where `relief render` writes, and what it says when it cannot: every
//! `--out` extension the help lists, standard output closed, full, or
//! read by a reader that goes away.

use std::process::{Command, Stdio};

fn relief() -> Command {
    Command::new(env!("CARGO_BIN_EXE_relief"))
}

fn assert_plain(err: &str) {
    assert!(!err.contains("os error"), "{err}");
    assert!(!err.contains("panicked"), "{err}");
}

#[test]
fn every_listed_out_extension_writes_a_picture_of_the_frame() {
    let dir = crate::common::scratch::scratch_dir("out-ext");
    for ext in ["png", "jpg", "bmp", "tga", "tif", "ppm", "qoi", "ff"] {
        let out = dir.join(format!("frame.{ext}"));
        let o = relief()
            .args(["render", "--width", "24", "--height", "16", "--out"])
            .arg(&out)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(o.status.success(), ".{ext}: {err}");
        let format = image::ImageFormat::from_extension(ext).unwrap();
        let bytes = std::fs::read(&out).unwrap();
        let picture = relief_texture::picture::decode_as(&bytes, format)
            .unwrap_or_else(|e| panic!(".{ext}: {e}"));
        assert_eq!((picture.width(), picture.height()), (24, 16), ".{ext}");
        if ext == "ppm" {
            // A binary PPM, not the PAM (P7) a .ppm reader refuses.
            assert!(bytes.starts_with(b"P6\n24 16 255\n"), "{:?}", &bytes[..12]);
        }
    }
    // The other PNM names are not written as something they are not.
    for ext in ["pgm", "pbm", "pam"] {
        let out = dir.join(format!("frame.{ext}"));
        let o = relief()
            .args(["render", "--out"])
            .arg(&out)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), ".{ext}: {err}");
        assert!(err.contains("unknown picture extension"), ".{ext}: {err}");
        assert!(!out.exists());
    }
    // Farbfeld holds the frame's 8-bit values exactly (k × 257 in 16 bits).
    let png = relief_texture::picture::open(dir.join("frame.png"))
        .unwrap()
        .to_rgb8();
    let ff = relief_texture::picture::open(dir.join("frame.ff"))
        .unwrap()
        .to_rgb8();
    assert_eq!(png, ff);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `relief render ARGS` with standard output closed (as `>&-` does).
fn with_stdout_closed(args: &[&str]) -> std::process::Output {
    use std::os::unix::process::CommandExt;
    let mut command = relief();
    command.args(args).stderr(Stdio::piped());
    // SAFETY: close(2) is async-signal-safe, as pre_exec requires.
    unsafe {
        command.pre_exec(|| {
            libc::close(1);
            Ok(())
        });
    }
    command.output().unwrap()
}

#[test]
#[cfg(target_os = "linux")]
fn a_closed_standard_output_is_an_error_that_says_so() {
    for args in [
        &["render", "--out", "-", "--width", "8", "--height", "8"][..],
        &["render", "--ansi", "--width", "8", "--height", "8"][..],
    ] {
        let o = with_stdout_closed(args);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {err}");
        assert!(err.contains("standard output is closed"), "{args:?}: {err}");
        assert_plain(&err);
    }
    // Redirected to /dev/null is not closed, opened write-only (a shell's
    // `>`) or read-write (what the runtime puts in place of a closed one).
    for read in [false, true] {
        let null = std::fs::OpenOptions::new()
            .read(read)
            .write(true)
            .open("/dev/null")
            .unwrap();
        let o = relief()
            .args(["render", "--ansi", "--width", "8", "--height", "8"])
            .stdout(null)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
}

#[test]
#[cfg(target_os = "linux")]
fn a_full_device_is_named_as_standard_output_in_plain_words() {
    for args in [
        &["render", "--ansi", "--width", "64", "--height", "64"][..],
        &["render", "--out", "-", "--width", "64", "--height", "64"][..],
    ] {
        let full = std::fs::OpenOptions::new()
            .write(true)
            .open("/dev/full")
            .unwrap();
        let o = relief().args(args).stdout(full).output().unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {err}");
        assert_eq!(
            err.trim_end(),
            "relief: cannot write to standard output: no space left on device",
            "{args:?}"
        );
    }
}

#[test]
fn a_reader_that_closes_the_pipe_ends_relief_quietly() {
    for args in [
        &["render", "--ansi", "--width", "64", "--height", "64"][..],
        &["render", "--out", "-", "--width", "64", "--height", "64"][..],
    ] {
        // The reading end is closed before relief starts: its first write
        // meets a pipe nobody reads.
        let (reader, writer) = std::io::pipe().unwrap();
        drop(reader);
        let o = relief()
            .args(args)
            .stdout(writer)
            .stderr(Stdio::piped())
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(0), "{args:?}: {err}");
        assert_eq!(err, "", "{args:?}");
    }
}
