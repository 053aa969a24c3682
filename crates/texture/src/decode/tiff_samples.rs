//! TIFF files the `image` crate refuses although the `tiff` crate under it
//! decodes their samples: floating-point grey, signed integers, and
//! palette pictures (their indices read
//! as grey, then looked up in the `ColorMap` tag). Depths the crate leaves
//! packed and fax 3 strips go to [`tiff_strips`]. Tried only after the
//! `image` crate has refused the file.

use std::io::Cursor;

use tiff::decoder::{Decoder, DecodingResult, Limits};
use tiff::tags::Tag;

use super::tiff_picture::{Picture, Refusal};
use super::tiff_strips;

/// The picture's size from its header, when the `tiff` crate reads it.
pub fn dimensions(bytes: &[u8]) -> Option<(u32, u32)> {
    Decoder::new(Cursor::new(bytes)).ok()?.dimensions().ok()
}

/// Photometric interpretation "RGB palette".
const PALETTE: u16 = 3;

/// Decodes the first picture: `Ok(None)` when this reader cannot either,
/// `Err` when [`tiff_strips`] recognises the picture but refuses it.
pub fn decode(bytes: &[u8], max_bytes: usize) -> Result<Option<Picture>, Refusal> {
    let mut decoder = match Decoder::new(Cursor::new(bytes)) {
        Ok(d) => d,
        Err(_) => return Ok(None),
    };
    let compression = decoder
        .find_tag_unsigned::<u16>(Tag::Compression)
        .ok()
        .flatten()
        .unwrap_or(1);
    let bits = decoder
        .find_tag_unsigned_vec::<u16>(Tag::BitsPerSample)
        .ok()
        .flatten()
        .and_then(|b| b.first().copied())
        .unwrap_or(1);
    if tiff_strips::wanted(compression, bits) {
        return tiff_strips::decode(bytes, max_bytes).map(Some);
    }
    Ok(crate_samples(bytes, max_bytes))
}

/// The samples as the `tiff` crate decodes them.
fn crate_samples(bytes: &[u8], max_bytes: usize) -> Option<Picture> {
    let mut decoder = Decoder::new(Cursor::new(bytes))
        .ok()?
        .with_limits(limits(max_bytes));
    let (w, h) = decoder.dimensions().ok()?;
    let (width, height) = (w as usize, h as usize);
    let photometric = decoder
        .find_tag_unsigned::<u16>(Tag::PhotometricInterpretation)
        .ok()??;
    let bits = decoder
        .find_tag_unsigned_vec::<u16>(Tag::BitsPerSample)
        .ok()
        .flatten()
        .and_then(|b| b.first().copied())
        .unwrap_or(1);
    if photometric == PALETTE {
        let map = decoder.get_tag_u16_vec(Tag::ColorMap).ok()?;
        return palette_picture(bytes, max_bytes, &map, bits, width, height);
    }
    let channels = match photometric {
        // White is zero / black is zero.
        0 | 1 => 1,
        2 => 3,
        _ => return None,
    };
    let white_is_zero = photometric == 0;
    let samples = scaled(decoder.read_image().ok()?, bits)?;
    let per_pixel = samples.len() / (width * height).max(1);
    if per_pixel < channels || samples.len() != per_pixel * width * height {
        return None;
    }
    Some(Picture::from_samples(
        width,
        height,
        &samples,
        per_pixel,
        channels,
        white_is_zero,
    ))
}

/// The decoder's limits: no buffer larger than `max_bytes`.
fn limits(max_bytes: usize) -> Limits {
    let mut limits = Limits::default();
    limits.decoding_buffer_size = max_bytes;
    limits.intermediate_buffer_size = max_bytes;
    limits
}

/// A palette picture: its indices, of `bits` bits, looked up in `map` (the
/// `ColorMap` tag: all reds, then all greens, then all blues).
fn palette_picture(
    bytes: &[u8],
    max_bytes: usize,
    map: &[u16],
    bits: u16,
    width: usize,
    height: usize,
) -> Option<Picture> {
    // The samples are indices: read them as grey.
    let grey = as_grey(bytes)?;
    let mut decoder = Decoder::new(Cursor::new(grey))
        .ok()?
        .with_limits(limits(max_bytes));
    let indices: Vec<usize> = match decoder.read_image().ok()? {
        DecodingResult::U8(v) => v.into_iter().map(usize::from).collect(),
        DecodingResult::U16(v) => v.into_iter().map(usize::from).collect(),
        _ => return None,
    };
    let n = 1usize << bits.min(16);
    if map.len() != 3 * n || indices.len() != width * height {
        return None;
    }
    let rgba = indices
        .iter()
        .map(|&i| {
            let i = i.min(n - 1);
            let c = |k: usize| map[k * n + i] as f32 / 65535.0;
            [c(0), c(1), c(2), 1.0]
        })
        .collect();
    Some(Picture {
        width,
        height,
        rgba,
        has_alpha: false,
    })
}

/// Decoded samples in 0..1 (floating-point ones as they are); `None` for
/// a sample type this reader does not scale.
fn scaled(result: DecodingResult, bits: u16) -> Option<Vec<f32>> {
    Some(match result {
        DecodingResult::F32(v) => v,
        DecodingResult::F64(v) => v.into_iter().map(|x| x as f32).collect(),
        // Signed samples: −max..max onto 0..1.
        DecodingResult::I8(v) => v.into_iter().map(|x| (x as f32 + 128.0) / 255.0).collect(),
        DecodingResult::I16(v) => v
            .into_iter()
            .map(|x| (x as f32 + 32768.0) / 65535.0)
            .collect(),
        // Unsigned samples of `bits` bits (12-bit ones arrive as u16).
        DecodingResult::U8(v) => {
            let max = ((1u32 << bits.clamp(1, 8)) - 1) as f32;
            v.into_iter().map(|x| x as f32 / max).collect()
        }
        DecodingResult::U16(v) => {
            let max = ((1u32 << bits.clamp(1, 16)) - 1) as f32;
            v.into_iter().map(|x| x as f32 / max).collect()
        }
        _ => return None,
    })
}

/// The file with its first directory's photometric interpretation set to
/// "black is zero", so the palette indices decode as grey samples.
fn as_grey(bytes: &[u8]) -> Option<Vec<u8>> {
    let little = match bytes.get(..4)? {
        b"II*\0" => true,
        b"MM\0*" => false,
        _ => return None,
    };
    let u16_at = |at: usize| -> Option<u16> {
        let b: [u8; 2] = bytes.get(at..at + 2)?.try_into().ok()?;
        Some(if little {
            u16::from_le_bytes(b)
        } else {
            u16::from_be_bytes(b)
        })
    };
    let u32_at = |at: usize| -> Option<u32> {
        let b: [u8; 4] = bytes.get(at..at + 4)?.try_into().ok()?;
        Some(if little {
            u32::from_le_bytes(b)
        } else {
            u32::from_be_bytes(b)
        })
    };
    let ifd = u32_at(4)? as usize;
    let count = u16_at(ifd)? as usize;
    for i in 0..count {
        let entry = ifd + 2 + 12 * i;
        // Tag 262, type SHORT (3), one value held in the entry.
        if u16_at(entry)? == 262 && u16_at(entry + 2)? == 3 {
            let mut out = bytes.to_vec();
            let one = if little { [1, 0] } else { [0, 1] };
            out.get_mut(entry + 8..entry + 10)?.copy_from_slice(&one);
            return Some(out);
        }
    }
    None
}
