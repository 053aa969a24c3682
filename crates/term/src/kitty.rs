//! The kitty graphics protocol: the frame as 24-bit RGB, zlib-compressed,
//! base64 in chunks of at most [`CHUNK`] bytes, under one image id that
//! every frame reuses (a new frame replaces the last in place). Strips of
//! an exact frame sent after a smaller picture are images of their own
//! ([`strip_id`]), placed above it ([`STRIP_Z`]).

use std::io::{self, Write};

use base64::Engine;
use flate2::Compression;
use flate2::write::ZlibEncoder;

use relief_core::framebuffer::Framebuffer;

/// The id of relief's image: each frame is sent under it, so it replaces
/// the previous one, and one delete removes it.
pub const IMAGE_ID: u32 = 0x72_6C66; // "rlf"

/// Largest base64 payload of one escape sequence (the protocol's limit).
pub const CHUNK: usize = 4096;

/// The id of strip `k` of an exact frame sent in strips: each strip is an
/// image of its own, drawn over relief's image ([`STRIP_Z`]).
pub fn strip_id(k: usize) -> u32 {
    IMAGE_ID + 1 + k as u32
}

/// Strips are drawn above the image they refine.
pub const STRIP_Z: i32 = 1;

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

/// Sends `fb` as image `id` without showing it (`a=t`): the placements
/// written after it ([`write_placement`]) show parts of it. A new image
/// under the id replaces the old one and its placements.
pub fn write_data(fb: &Framebuffer, id: u32, out: &mut impl Write) -> io::Result<()> {
    let keys = format!("a=t,f=24,o=z,s={},v={},i={id},q=2", fb.width(), fb.height());
    write_chunks(fb, &keys, out)
}

/// A rectangle of the image's pixels: left, top, width, height.
pub type Source = [usize; 4];

/// Where a placement goes: the image, the placement's number (the same
/// again replaces it), its z-index.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PlacementId {
    pub image: u32,
    pub placement: u32,
    pub z: i32,
}

/// Shows `source` of an image already sent, at the cursor, scaled to
/// `cells` (columns × rows); the cursor stays (`C=1`). No pixels are sent.
pub fn write_placement(
    id: PlacementId,
    source: Source,
    cells: (u16, u16),
    out: &mut impl Write,
) -> io::Result<()> {
    let [x, y, w, h] = source;
    let PlacementId {
        image,
        placement,
        z,
    } = id;
    write!(
        out,
        "\x1b_Ga=p,i={image},p={placement},x={x},y={y},w={w},h={h},c={},r={},C=1,q=2",
        cells.0, cells.1
    )?;
    if z != 0 {
        write!(out, ",z={z}")?;
    }
    out.write_all(b"\x1b\\")
}

/// The frame as 24-bit RGB, zlib-compressed, base64 in chunks; `keys`
/// go with the first chunk.
fn write_chunks(fb: &Framebuffer, keys: &str, out: &mut impl Write) -> io::Result<()> {
    // RGB rows, top first: the framebuffer's own bytes.
    let raw = fb.pixels().as_flattened();
    // Fast compression: the link is what is slow, but a frame must still
    // be encoded within the frame interval.
    let mut zlib = ZlibEncoder::new(Vec::new(), Compression::fast());
    zlib.write_all(raw)?;
    let packed = zlib.finish()?;
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

/// Deletes image `id` and frees its data ([`DELETE`] for relief's).
pub fn delete(id: u32) -> Vec<u8> {
    format!("\x1b_Ga=d,d=I,i={id},q=2\x1b\\").into_bytes()
}

/// Deletes every placement of image `id`, its data kept
/// ([`DELETE_PLACEMENTS`] for relief's).
pub fn delete_placements(id: u32) -> Vec<u8> {
    format!("\x1b_Ga=d,d=i,i={id},q=2\x1b\\").into_bytes()
}

#[cfg(test)]
mod tests {
    #[test]
    fn delete_names_the_image_id() {
        let text = std::str::from_utf8(super::DELETE).unwrap();
        assert!(text.contains(&format!("i={},", super::IMAGE_ID)));
        let text = std::str::from_utf8(super::DELETE_PLACEMENTS).unwrap();
        assert!(text.contains(&format!("d=i,i={},", super::IMAGE_ID)));
        assert_eq!(super::delete(super::IMAGE_ID), super::DELETE);
        assert_eq!(
            super::delete_placements(super::IMAGE_ID),
            super::DELETE_PLACEMENTS
        );
    }
}
