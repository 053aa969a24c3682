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
    write_image_as(fb, cells, IMAGE_ID, 0, out)
}

/// The id of strip `k` of an exact frame sent in strips: each strip is an
/// image of its own, drawn over relief's image ([`STRIP_Z`]).
pub fn strip_id(k: usize) -> u32 {
    IMAGE_ID + 1 + k as u32
}

/// Strips are drawn above the image they refine.
pub const STRIP_Z: i32 = 1;

/// Writes `fb` as image `id` at z-index `z` (see [`write_image`]).
pub fn write_image_as(
    fb: &Framebuffer,
    cells: Option<(u16, u16)>,
    id: u32,
    z: i32,
    out: &mut impl Write,
) -> io::Result<()> {
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
            write!(
                out,
                "\x1b_Ga=T,f=24,o=z,s={},v={},i={id},p=1,q=2,C=1",
                fb.width(),
                fb.height()
            )?;
            if z != 0 {
                write!(out, ",z={z}")?;
            }
            if let Some((c, r)) = cells {
                write!(out, ",c={c},r={r}")?;
            }
            write!(out, ",m={more};")?;
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

/// Deletes image `id` and frees its data.
pub fn delete(id: u32, out: &mut Vec<u8>) {
    let _ = write!(out, "\x1b_Ga=d,d=I,i={id},q=2\x1b\\");
}

#[cfg(test)]
mod tests {
    #[test]
    fn delete_names_the_image_id() {
        let text = std::str::from_utf8(super::DELETE).unwrap();
        assert!(text.contains(&format!("i={},", super::IMAGE_ID)));
        let mut one = Vec::new();
        super::delete(super::IMAGE_ID, &mut one);
        assert_eq!(one, super::DELETE);
    }
}
