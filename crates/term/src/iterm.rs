//! iTerm2 inline images (also WezTerm's): the frame as a base64 PNG in
//! one OSC 1337 sequence.

use std::io::{self, Write};

use base64::Engine;

use relief_core::framebuffer::Framebuffer;

/// Writes `fb` as one inline image at the cursor; `cells` stretches it to
/// that many columns × rows when given.
pub fn write_image(
    fb: &Framebuffer,
    cells: Option<(u16, u16)>,
    out: &mut impl Write,
) -> io::Result<()> {
    // RGB rows, top first: the framebuffer's own bytes.
    let raw = fb.pixels().as_flattened();
    let mut png = Vec::new();
    image::ImageEncoder::write_image(
        image::codecs::png::PngEncoder::new_with_quality(
            &mut png,
            image::codecs::png::CompressionType::Fast,
            image::codecs::png::FilterType::Adaptive,
        ),
        raw,
        fb.width() as u32,
        fb.height() as u32,
        image::ExtendedColorType::Rgb8,
    )
    .map_err(io::Error::other)?;
    write!(out, "\x1b]1337;File=inline=1;size={}", png.len())?;
    if let Some((c, r)) = cells {
        write!(out, ";width={c};height={r};preserveAspectRatio=0")?;
    }
    out.write_all(b":")?;
    out.write_all(
        base64::engine::general_purpose::STANDARD
            .encode(&png)
            .as_bytes(),
    )?;
    out.write_all(b"\x07")
}
