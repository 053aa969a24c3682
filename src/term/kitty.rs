//! The kitty graphics protocol: the frame as 24-bit RGB, zlib-compressed,
//! base64 in chunks of at most [`CHUNK`] bytes, under one image id that
//! every frame reuses (a new frame replaces the last in place).

use std::io::{self, Write};

use base64::Engine;
use flate2::Compression;
use flate2::write::ZlibEncoder;

use crate::framebuffer::Framebuffer;

/// The id of relief's image: each frame is sent under it, so it replaces
/// the previous one, and one delete removes it.
pub const IMAGE_ID: u32 = 0x72_6C66; // "rlf"

/// Largest base64 payload of one escape sequence (the protocol's limit).
pub const CHUNK: usize = 4096;

/// Writes `fb` as one kitty image at the cursor, the cursor left where it
/// was (`C=1`); `cells` scales it to that many columns × rows when given
/// (the view's picture area), else it shows at its own pixel size.
pub fn write_image(
    fb: &Framebuffer,
    cells: Option<(u16, u16)>,
    out: &mut impl Write,
) -> io::Result<()> {
    let mut keys = format!(
        "a=T,f=24,o=z,s={},v={},i={IMAGE_ID},p=1,q=2,C=1",
        fb.width(),
        fb.height()
    );
    if let Some((c, r)) = cells {
        keys.push_str(&format!(",c={c},r={r}"));
    }
    write_chunks(fb, &keys, out)
}

/// Sends `fb` under relief's image id without showing it (`a=t`): the
/// placements written after it ([`write_placement`]) show parts of it.
/// A new image under the id replaces the old one and its placements.
pub fn write_data(fb: &Framebuffer, out: &mut impl Write) -> io::Result<()> {
    let keys = format!(
        "a=t,f=24,o=z,s={},v={},i={IMAGE_ID},q=2",
        fb.width(),
        fb.height()
    );
    write_chunks(fb, &keys, out)
}

/// A rectangle of the image's pixels: left, top, width, height.
pub type Source = [usize; 4];

/// Shows `source` of the image already sent, at the cursor, scaled to
/// `cells` (columns × rows), as placement `placement` (the same id again
/// replaces it); the cursor stays (`C=1`). No pixels are sent.
pub fn write_placement(
    placement: u32,
    source: Source,
    cells: (u16, u16),
    out: &mut impl Write,
) -> io::Result<()> {
    let [x, y, w, h] = source;
    write!(
        out,
        "\x1b_Ga=p,i={IMAGE_ID},p={placement},x={x},y={y},w={w},h={h},c={},r={},C=1,q=2\x1b\\",
        cells.0, cells.1
    )
}

/// The frame as 24-bit RGB, zlib-compressed, base64 in chunks; `keys`
/// go with the first chunk.
fn write_chunks(fb: &Framebuffer, keys: &str, out: &mut impl Write) -> io::Result<()> {
    // RGB rows, top first: the framebuffer's own bytes.
    let raw = fb.pixels().as_flattened();
    // Fast compression: the link is what is slow, but a frame must still
    // be encoded within the frame interval.
    let mut z = ZlibEncoder::new(Vec::new(), Compression::fast());
    z.write_all(raw)?;
    let packed = z.finish()?;
    let text = base64::engine::general_purpose::STANDARD.encode(&packed);
    let chunks: Vec<&[u8]> = text.as_bytes().chunks(CHUNK).collect();
    let last = chunks.len().saturating_sub(1);
    for (i, chunk) in chunks.iter().enumerate() {
        let more = u8::from(i < last);
        if i == 0 {
            write!(out, "\x1b_G{keys},m={more};")?;
        } else {
            write!(out, "\x1b_Gm={more};")?;
        }
        out.write_all(chunk)?;
        out.write_all(b"\x1b\\")?;
    }
    Ok(())
}

/// Deletes relief's image and frees its data (leaving the mode, exit).
pub const DELETE: &[u8] = b"\x1b_Ga=d,d=I,i=7498854,q=2\x1b\\";

/// Deletes every placement of relief's image and keeps its data (lower
/// case `d=i`): the image can be placed again without being sent again.
pub const DELETE_PLACEMENTS: &[u8] = b"\x1b_Ga=d,d=i,i=7498854,q=2\x1b\\";

#[cfg(test)]
mod tests {
    #[test]
    fn delete_names_the_image_id() {
        let text = std::str::from_utf8(super::DELETE).unwrap();
        assert!(text.contains(&format!("i={},", super::IMAGE_ID)));
        let text = std::str::from_utf8(super::DELETE_PLACEMENTS).unwrap();
        assert!(text.contains(&format!("d=i,i={},", super::IMAGE_ID)));
    }
}
