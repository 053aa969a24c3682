//! Valid files the `image` crate refuses, rewritten into the form it reads.
//!
//! Each rewrite is tried only after the crate has refused the file, so a
//! file it reads is never touched. Every rewrite checks its bounds and gives
//! up (`None`) on anything it does not expect: the crate's own error stands.
//!
//! - Radiance HDR whose signature is `#?RGBE` (the crate wants `#?RADIANCE`;
//!   both are written by common tools, the header is otherwise the same).
//! - GIF with an extension block of a label the crate does not know: the GIF
//!   spec lets a decoder skip any extension (its data are length-prefixed
//!   sub-blocks), so it is dropped.
//! - OS/2 2.x BMP (`BITMAPINFOHEADER2`, 16 to 64 bytes): its first 40 bytes
//!   have the Windows `BITMAPINFOHEADER` layout, the rest (units, halftoning)
//!   do not change the pixels; the header becomes a 40-byte one.
//! - ICO whose largest picture is a PNG the crate's ICO reader refuses (it
//!   wants RGBA; Pillow writes grey and RGB PNGs): that PNG itself.

use image::ImageFormat;

/// The file rewritten, and the format of the result; `None` when no rewrite
/// applies.
pub fn rewrite(bytes: &[u8]) -> Option<(Vec<u8>, ImageFormat)> {
    hdr_rgbe(bytes)
        .map(|b| (b, ImageFormat::Hdr))
        .or_else(|| gif_without_unknown_extensions(bytes).map(|b| (b, ImageFormat::Gif)))
        .or_else(|| bmp_os2_v2(bytes).map(|b| (b, ImageFormat::Bmp)))
        .or_else(|| ico_png(bytes).map(|b| (b, ImageFormat::Png)))
}

fn u16_le(bytes: &[u8], at: usize) -> Option<u16> {
    Some(u16::from_le_bytes(bytes.get(at..at + 2)?.try_into().ok()?))
}

fn u32_le(bytes: &[u8], at: usize) -> Option<u32> {
    Some(u32::from_le_bytes(bytes.get(at..at + 4)?.try_into().ok()?))
}

/// `#?RGBE` → `#?RADIANCE`.
fn hdr_rgbe(bytes: &[u8]) -> Option<Vec<u8>> {
    let rest = bytes.strip_prefix(b"#?RGBE")?;
    if !rest.starts_with(b"\n") && !rest.starts_with(b"\r\n") {
        return None;
    }
    let mut out = b"#?RADIANCE".to_vec();
    out.extend_from_slice(rest);
    Some(out)
}

/// Extension labels the `gif` crate reads: graphic control, comment, plain
/// text, application.
const KNOWN_GIF_EXTENSIONS: [u8; 4] = [0xF9, 0xFE, 0x01, 0xFF];

/// The GIF without its extensions of unknown labels (`None` if it has none).
fn gif_without_unknown_extensions(bytes: &[u8]) -> Option<Vec<u8>> {
    if !(bytes.starts_with(b"GIF87a") || bytes.starts_with(b"GIF89a")) {
        return None;
    }
    let colour_table = |flags: u8| {
        if flags & 0x80 != 0 {
            3usize << ((flags & 7) + 1)
        } else {
            0
        }
    };
    // Skips data sub-blocks from `at`; the position after the terminator.
    let sub_blocks = |mut at: usize| -> Option<usize> {
        loop {
            let len = *bytes.get(at)? as usize;
            at += 1 + len;
            if len == 0 {
                return Some(at);
            }
        }
    };
    let mut at = 13 + colour_table(*bytes.get(10)?);
    let mut out = bytes.get(..at)?.to_vec();
    let mut dropped = false;
    loop {
        match *bytes.get(at)? {
            0x21 => {
                let label = *bytes.get(at + 1)?;
                let end = sub_blocks(at + 2)?;
                if KNOWN_GIF_EXTENSIONS.contains(&label) {
                    out.extend_from_slice(bytes.get(at..end)?);
                } else {
                    dropped = true;
                }
                at = end;
            }
            0x2C => {
                // Descriptor (10 bytes), local table, LZW code size, data.
                let table = colour_table(*bytes.get(at + 9)?);
                let end = sub_blocks(at + 10 + table + 1)?;
                out.extend_from_slice(bytes.get(at..end)?);
                at = end;
            }
            0x3B => {
                out.extend_from_slice(&bytes[at..]);
                break;
            }
            _ => return None,
        }
    }
    dropped.then_some(out)
}

/// An OS/2 2.x BMP with its info header made the 40-byte Windows one.
fn bmp_os2_v2(bytes: &[u8]) -> Option<Vec<u8>> {
    if !bytes.starts_with(b"BM") {
        return None;
    }
    let size = u32_le(bytes, 14)? as usize;
    // 12 is OS/2 1.x and 40/52/56/108/124 Windows: all read by the crate.
    if !(16..=64).contains(&size) || [40, 52, 56].contains(&size) {
        return None;
    }
    // OS/2 compressions 3 (Huffman 1D) and 4 (RLE24) mean other things in
    // Windows files: only uncompressed, RLE8 and RLE4 carry over.
    let compression = if size >= 20 { u32_le(bytes, 30)? } else { 0 };
    if compression > 2 {
        return None;
    }
    let header_end = 14 + size;
    let offset = u32_le(bytes, 10)? as usize;
    if offset < header_end || bytes.len() < header_end {
        return None;
    }
    let mut info = bytes[14..header_end.min(14 + 40)].to_vec();
    info.resize(40, 0);
    info[..4].copy_from_slice(&40u32.to_le_bytes());
    let new_offset = offset + 40 - size;
    let mut out = Vec::with_capacity(bytes.len() + 40);
    out.extend_from_slice(b"BM");
    out.extend_from_slice(&((bytes.len() + 40 - size) as u32).to_le_bytes());
    out.extend_from_slice(&bytes[6..10]);
    out.extend_from_slice(&(new_offset as u32).to_le_bytes());
    out.extend_from_slice(&info);
    out.extend_from_slice(&bytes[header_end..]);
    Some(out)
}

/// The PNG of an ICO's largest picture, when that picture is a PNG.
fn ico_png(bytes: &[u8]) -> Option<Vec<u8>> {
    if u16_le(bytes, 0)? != 0 || u16_le(bytes, 2)? != 1 {
        return None;
    }
    let count = u16_le(bytes, 4)? as usize;
    let mut best: Option<(u32, &[u8])> = None;
    for i in 0..count {
        let entry = 6 + 16 * i;
        // A stored 0 means 256.
        let side = |b: u8| if b == 0 { 256 } else { b as u32 };
        let area = side(*bytes.get(entry)?) * side(*bytes.get(entry + 1)?);
        let len = u32_le(bytes, entry + 8)? as usize;
        let at = u32_le(bytes, entry + 12)? as usize;
        let data = bytes.get(at..at.checked_add(len)?)?;
        if best.is_none_or(|(a, _)| area > a) {
            best = Some((area, data));
        }
    }
    let (_, data) = best?;
    data.starts_with(b"\x89PNG\r\n\x1a\n")
        .then(|| data.to_vec())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn files_the_crate_reads_are_left_alone() {
        assert!(rewrite(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n").is_none());
        assert!(rewrite(b"GIF89a").is_none());
        assert!(rewrite(b"").is_none());
        // A Windows BMP header (40 bytes).
        let mut bmp = b"BM".to_vec();
        bmp.extend_from_slice(&[0; 12]);
        bmp.extend_from_slice(&40u32.to_le_bytes());
        assert!(rewrite(&bmp).is_none());
    }

    #[test]
    fn hdr_signature() {
        let (out, format) = rewrite(b"#?RGBE\n-Y 1 +X 1\n").unwrap();
        assert_eq!(out, b"#?RADIANCE\n-Y 1 +X 1\n");
        assert_eq!(format, ImageFormat::Hdr);
    }

    #[test]
    fn truncated_variants_give_up() {
        assert!(
            gif_without_unknown_extensions(b"GIF89a\x01\x00\x01\x00\x00\x00\x00\x21\x99\x05ab")
                .is_none()
        );
        assert!(
            ico_png(&[
                0, 0, 1, 0, 1, 0, 16, 16, 0, 0, 1, 0, 32, 0, 0xff, 0xff, 0, 0, 22, 0, 0, 0
            ])
            .is_none()
        );
    }
}
