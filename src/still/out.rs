//! Where `relief render` writes its picture: the `--out` target checked
//! before rendering, and the file replaced whole at the end.

use std::io::Write;

use anyhow::Context;

use relief_core::framebuffer::Framebuffer;
use relief_core::sanitize::{clean, io_reason};

/// Where `--out` writes.
#[derive(Debug)]
pub enum OutTarget {
    /// `--out -`: the picture goes to standard output.
    Stdout,
    /// This file: the one a symbolic link (or a chain of them) names, so
    /// the link stays and the file it points at is written.
    File(std::path::PathBuf),
}

/// Links followed before `--out` gives up (as the kernel's own limit).
const MAX_LINKS: usize = 40;

/// What `--out` names, checked: `-` is standard output (refused when it is
/// a terminal); a link is followed to its file; an existing file must be a
/// regular file the user may write (a read-only file is refused, not
/// replaced behind the user's back).
pub fn out_target(out: &std::path::Path) -> anyhow::Result<OutTarget> {
    use std::io::IsTerminal;
    let shown = relief_core::sanitize::display_path(out);
    if out.as_os_str() == "-" {
        if std::io::stdout().is_terminal() {
            anyhow::bail!(
                "--out - writes the picture to standard output, which is a terminal here: redirect it (--out - > frame.png) or use --ansi"
            );
        }
        return Ok(OutTarget::Stdout);
    }
    output_format(out)?;
    let mut target = out.to_path_buf();
    for _ in 0..=MAX_LINKS {
        let Ok(link) = std::fs::read_link(&target) else {
            break;
        };
        target = match target.parent() {
            Some(dir) if link.is_relative() => dir.join(link),
            _ => link,
        };
    }
    if std::fs::symlink_metadata(&target).is_ok_and(|m| m.file_type().is_symlink()) {
        anyhow::bail!("cannot write {shown}: too many levels of symbolic links");
    }
    // The target's own extension decides nothing: the user named `out`.
    if let Ok(meta) = std::fs::metadata(&target) {
        if !meta.is_file() {
            anyhow::bail!(
                "cannot write {shown}: not a regular file (only a new or regular file is replaced)"
            );
        }
        let mode = std::os::unix::fs::PermissionsExt::mode(&meta.permissions()) & 0o7777;
        if meta.permissions().readonly() {
            anyhow::bail!(
                "cannot write {shown}: the file is read-only (mode {mode:o}); make it writable (chmod u+w) or remove it to replace it"
            );
        }
        // Opened without truncating: only asks whether writing is allowed.
        if let Err(e) = std::fs::OpenOptions::new().write(true).open(&target) {
            anyhow::bail!("cannot write {shown} (mode {mode:o}): {}", io_reason(&e));
        }
    }
    Ok(OutTarget::File(target))
}

/// The picture format `--out`'s extension names (PNG when it has none).
/// Of the PNM family only `.ppm` is written (as binary PPM, P6).
pub fn output_format(out: &std::path::Path) -> anyhow::Result<image::ImageFormat> {
    use image::ImageFormat as F;
    let Some(ext) = out.extension() else {
        return Ok(F::Png);
    };
    let ppm = ext.eq_ignore_ascii_case("ppm");
    match F::from_extension(ext) {
        Some(F::Pnm) if ppm => Ok(F::Pnm),
        Some(f @ (F::Png | F::Jpeg | F::Bmp | F::Tga | F::Tiff | F::Qoi | F::Farbfeld)) => Ok(f),
        _ => anyhow::bail!(
            "{}: unknown picture extension (use .png, .jpg, .bmp, .tga, .tif, .ppm, .qoi or .ff)",
            relief_core::sanitize::display_path(out)
        ),
    }
}

/// Encodes the frame in `format`: 8-bit RGB, or 16-bit RGBA for Farbfeld
/// (the only layout it has, each value the 8-bit one × 257), and PNM as
/// binary PPM (P6), where the encoder's own choice for RGB is a PAM (P7)
/// that a `.ppm` reader does not take. Encoded whole, in memory: some
/// encoders seek, which a pipe cannot.
fn encode(fb: &Framebuffer, format: image::ImageFormat) -> image::ImageResult<Vec<u8>> {
    use image::codecs::pnm::{PnmEncoder, PnmSubtype, SampleEncoding};
    let rgb = image::DynamicImage::ImageRgb8(fb.to_image());
    match format {
        image::ImageFormat::Farbfeld => relief_texture::picture::encode(
            &image::DynamicImage::ImageRgba16(rgb.into_rgba16()),
            format,
        ),
        image::ImageFormat::Pnm => {
            let mut out = Vec::new();
            rgb.write_with_encoder(
                PnmEncoder::new(&mut out).with_subtype(PnmSubtype::Pixmap(SampleEncoding::Binary)),
            )?;
            Ok(out)
        }
        _ => relief_texture::picture::encode(&rgb, format),
    }
}

/// Writes the frame in `format` to standard output, or to a file through a
/// temporary file in the same directory renamed over it at the end: a
/// reader never sees half a picture, and nothing but a regular file is
/// ever opened for writing (a FIFO would block forever).
pub fn write_picture(
    fb: &Framebuffer,
    out: &OutTarget,
    format: image::ImageFormat,
) -> anyhow::Result<()> {
    if fb.width() == 0 || fb.height() == 0 {
        anyhow::bail!("cannot write an empty {}x{} image", fb.width(), fb.height());
    }
    let out = match out {
        OutTarget::File(path) => path,
        OutTarget::Stdout => {
            let bytes = encode(fb, format)?;
            let mut stdout = std::io::stdout().lock();
            return stdout
                .write_all(&bytes)
                .and_then(|()| stdout.flush())
                .map_err(super::stdout::write_error);
        }
    };
    let shown = relief_core::sanitize::display_path(out);
    // A file replaced keeps its permissions.
    let permissions = std::fs::metadata(out).ok().map(|m| m.permissions());
    let dir = match out.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => std::path::PathBuf::from("."),
    };
    let name = out.file_name().context("--out needs a file name")?;
    let mut temp_name = std::ffi::OsString::from(".");
    temp_name.push(name);
    temp_name.push(format!(".{}.tmp", std::process::id()));
    let temp = dir.join(temp_name);
    let written = (|| -> anyhow::Result<()> {
        let mut file = std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&temp)?;
        // Encoded whole first, so one write: no buffer in between.
        file.write_all(&encode(fb, format)?)?;
        if let Some(p) = permissions {
            std::fs::set_permissions(&temp, p)?;
        }
        std::fs::rename(&temp, out)?;
        Ok(())
    })();
    if let Err(e) = written {
        let _ = std::fs::remove_file(&temp);
        anyhow::bail!("cannot write {shown}: {}", plain_reason(&e));
    }
    Ok(())
}

/// A failed write in plain words: an I/O error (of the file, or met by the
/// encoder) without its "(os error N)".
fn plain_reason(e: &anyhow::Error) -> String {
    let io = e.downcast_ref::<std::io::Error>().or_else(|| {
        match e.downcast_ref::<image::ImageError>() {
            Some(image::ImageError::IoError(io)) => Some(io),
            _ => None,
        }
    });
    io.map_or_else(|| clean(&e.to_string()), io_reason)
}
