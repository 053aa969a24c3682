//! TIFF pictures the `tiff` crate reads the header of but not the samples:
//! depths between 2 and 15 bits other than 8 (12-bit scans), which it leaves
//! packed, and CCITT group 3 fax strips (1-D coded, as fax software and
//! libtiff write them by default). The strips are read straight from the
//! file; the crate only supplies the tags.

use std::io::{Cursor, Read};

use tiff::decoder::Decoder;
use tiff::tags::Tag;

use super::tiff_picture::{Picture, Refusal};

/// TIFF compression codes this reader handles.
const NONE: u16 = 1;
const FAX3: u16 = 3;
const LZW: u16 = 5;
const DEFLATE: u16 = 8;
const DEFLATE_OLD: u16 = 32946;

/// Tag 292 (T4Options): bit 0 set means some rows are 2-D coded.
const T4_OPTIONS: u16 = 292;

use Refusal::{Corrupt, Unsupported};

/// Whether this reader, not the crate, should decode the picture.
pub fn wanted(compression: u16, bits: u16) -> bool {
    compression == FAX3 || (bits > 1 && bits < 16 && bits != 8)
}

/// Decodes the first picture. `Err` is a plain sentence for a picture this
/// reader recognises but cannot draw (it replaces the crate's message).
pub fn decode(bytes: &[u8], max_bytes: usize) -> Result<Picture, Refusal> {
    let mut decoder =
        Decoder::new(Cursor::new(bytes)).map_err(|_| Corrupt("not a TIFF file".into()))?;
    let (w, h) = decoder
        .dimensions()
        .map_err(|_| Corrupt("its size tags are missing".into()))?;
    let (width, height) = (w as usize, h as usize);
    let tags = Tags::read(&mut decoder, height);
    let bits = tags.bits;
    if decoder.find_tag(Tag::TileOffsets).ok().flatten().is_some() {
        return Err(Unsupported(format!(
            "{bits}-bit samples in tiles are not supported"
        )));
    }
    let strips = strips(&mut decoder, bytes)?;
    if strips.len() < height.div_ceil(tags.rows_per_strip) {
        return Err(Corrupt("it has fewer strips than its rows need".into()));
    }
    let channels = tags.channels()?;
    if tags.spp < channels || tags.planar != 1 {
        return Err(Unsupported(
            "samples stored plane by plane are not supported at this depth".into(),
        ));
    }
    let values = width
        .checked_mul(height)
        .and_then(|n| n.checked_mul(tags.spp))
        .filter(|&n| n.saturating_mul(4) <= max_bytes)
        .ok_or_else(|| Unsupported("it is larger than the memory budget allows".into()))?;
    let samples = tags.samples(&strips, width, height)?;
    debug_assert_eq!(samples.len(), values);
    Ok(Picture::from_samples(
        width,
        height,
        &samples,
        tags.spp,
        channels,
        tags.photometric == 0,
    ))
}

/// The tags that say how the strips are laid out and coded.
struct Tags {
    compression: u16,
    photometric: u16,
    /// Samples per pixel.
    spp: usize,
    planar: u16,
    predictor: u16,
    fill_order: u16,
    /// The tag clamped to 1..=height (1 for an empty picture), or the
    /// height without the tag.
    rows_per_strip: usize,
    /// Bits of the first sample.
    bits: usize,
    /// T4Options (fax 3 only).
    t4: u32,
}

impl Tags {
    /// The tags of the first picture, the specification's default for each
    /// that is missing or unreadable.
    fn read(decoder: &mut Decoder<Cursor<&[u8]>>, height: usize) -> Tags {
        let compression = tag_u16(decoder, Tag::Compression, NONE);
        let photometric = tag_u16(decoder, Tag::PhotometricInterpretation, 1);
        let spp = tag_u16(decoder, Tag::SamplesPerPixel, 1) as usize;
        let planar = tag_u16(decoder, Tag::PlanarConfiguration, 1);
        let predictor = tag_u16(decoder, Tag::Predictor, 1);
        let fill_order = tag_u16(decoder, Tag::FillOrder, 1);
        let rows_per_strip = decoder
            .find_tag_unsigned::<u32>(Tag::RowsPerStrip)
            .ok()
            .flatten()
            .map_or(height, |r| (r as usize).clamp(1, height.max(1)));
        let bits = decoder
            .find_tag_unsigned_vec::<u16>(Tag::BitsPerSample)
            .ok()
            .flatten()
            .and_then(|b| b.first().copied())
            .unwrap_or(1) as usize;
        let t4 = decoder
            .find_tag_unsigned::<u32>(Tag::Unknown(T4_OPTIONS))
            .ok()
            .flatten()
            .unwrap_or(0);
        Tags {
            compression,
            photometric,
            spp,
            planar,
            predictor,
            fill_order,
            rows_per_strip,
            bits,
            t4,
        }
    }

    /// Colour channels of the photometric interpretation: grey or RGB.
    fn channels(&self) -> Result<usize, Refusal> {
        let bits = self.bits;
        match self.photometric {
            0 | 1 => Ok(1),
            2 => Ok(3),
            _ => Err(Unsupported(format!(
                "{bits}-bit samples in this colour space are not supported"
            ))),
        }
    }

    /// Every sample of the strips, row by row, in 0..1.
    fn samples(&self, strips: &[&[u8]], width: usize, height: usize) -> Result<Vec<f32>, Refusal> {
        let bits = self.bits;
        if self.compression == FAX3 {
            if self.t4 & 1 != 0 {
                return Err(Unsupported(
                    "2-D coded CCITT group 3 fax data is not supported".into(),
                ));
            }
            if bits != 1 || self.spp != 1 {
                return Err(Corrupt(
                    "fax data with more than one bit per pixel is not valid".into(),
                ));
            }
            let reversed_bits = self.fill_order == 2;
            fax3_samples(strips, width, height, self.rows_per_strip, reversed_bits).map_err(Corrupt)
        } else {
            if self.predictor != 1 {
                return Err(Unsupported(format!(
                    "{bits}-bit samples with a predictor are not supported"
                )));
            }
            packed_samples(
                strips,
                self.compression,
                bits,
                width * self.spp,
                height,
                self.rows_per_strip,
            )
        }
    }
}

/// A one-value SHORT tag, or `default` when it is missing or unreadable.
fn tag_u16(decoder: &mut Decoder<Cursor<&[u8]>>, tag: Tag, default: u16) -> u16 {
    decoder
        .find_tag_unsigned::<u16>(tag)
        .ok()
        .flatten()
        .unwrap_or(default)
}

/// Each strip's bytes in the file, as the offset and size tags place them.
fn strips<'a>(
    decoder: &mut Decoder<Cursor<&[u8]>>,
    bytes: &'a [u8],
) -> Result<Vec<&'a [u8]>, Refusal> {
    let offsets = decoder
        .get_tag_u64_vec(Tag::StripOffsets)
        .map_err(|_| Corrupt("its strip offsets are missing".into()))?;
    let counts = decoder
        .get_tag_u64_vec(Tag::StripByteCounts)
        .map_err(|_| Corrupt("its strip sizes are missing".into()))?;
    offsets
        .iter()
        .zip(&counts)
        .map(|(&at, &n)| {
            let end = at.checked_add(n).filter(|&e| e <= bytes.len() as u64);
            end.map(|end| &bytes[at as usize..end as usize])
        })
        .collect::<Option<_>>()
        .ok_or_else(|| Corrupt("a strip lies past the end of the file".into()))
}

/// A strip's bytes decompressed.
fn expand(strip: &[u8], compression: u16, expected: usize) -> Result<Vec<u8>, Refusal> {
    match compression {
        NONE => Ok(strip.to_vec()),
        LZW => {
            let mut out = Vec::with_capacity(expected);
            let mut lzw = weezl::decode::Decoder::with_tiff_size_switch(weezl::BitOrder::Msb, 8);
            let result = lzw.into_vec(&mut out).decode(strip);
            // A stream cut before its end code still holds whole rows.
            match result.status {
                Ok(_) => Ok(out),
                Err(_) => Err(Corrupt("its LZW-compressed data does not decode".into())),
            }
        }
        DEFLATE | DEFLATE_OLD => {
            let mut out = Vec::with_capacity(expected);
            flate2::read::ZlibDecoder::new(strip)
                .take(expected as u64)
                .read_to_end(&mut out)
                .map_err(|_| Corrupt("its Deflate-compressed data does not decode".into()))?;
            Ok(out)
        }
        other => Err(Unsupported(format!(
            "samples of this depth with compression {other} are not supported"
        ))),
    }
}

/// Samples of `bits` bits, most significant bit first, each row starting on
/// a byte boundary, scaled to 0..1.
fn packed_samples(
    strips: &[&[u8]],
    compression: u16,
    bits: usize,
    per_row: usize,
    height: usize,
    rows_per_strip: usize,
) -> Result<Vec<f32>, Refusal> {
    let row_bytes = (per_row * bits).div_ceil(8);
    let max = ((1u32 << bits) - 1) as f32;
    let mut out = Vec::with_capacity(per_row * height);
    for (s, strip) in strips.iter().enumerate() {
        let rows = rows_per_strip.min(height.saturating_sub(s * rows_per_strip));
        if rows == 0 {
            break;
        }
        let data = expand(strip, compression, rows * row_bytes)?;
        if data.len() < rows * row_bytes {
            return Err(Corrupt("ends too early".into()));
        }
        for row in data.chunks_exact(row_bytes).take(rows) {
            out.extend((0..per_row).map(|i| read_bits(row, i * bits, bits) as f32 / max));
        }
    }
    Ok(out)
}

/// The `n`-bit big-endian value starting `at` bits into `row` (n ≤ 16).
fn read_bits(row: &[u8], at: usize, n: usize) -> u32 {
    let first = at / 8;
    // Three bytes hold any 16-bit field that starts inside the first.
    let window = (0..3).fold(0u32, |acc, k| {
        acc << 8 | u32::from(row.get(first + k).copied().unwrap_or(0))
    });
    let shift = 24 - (at % 8) - n;
    (window >> shift) & ((1 << n) - 1)
}

/// CCITT group 3 (1-D) strips as 0/1 samples: 1 where the fax code says
/// black, which is dark under "white is zero" and light under "black is zero".
fn fax3_samples(
    strips: &[&[u8]],
    width: usize,
    height: usize,
    rows_per_strip: usize,
    reversed_bits: bool,
) -> Result<Vec<f32>, String> {
    let line_width =
        u16::try_from(width).map_err(|_| "a fax row wider than 65535 pixels is not valid")?;
    let mut out = Vec::with_capacity(width * height);
    for (s, strip) in strips.iter().enumerate() {
        let rows = rows_per_strip.min(height.saturating_sub(s * rows_per_strip));
        if rows == 0 {
            break;
        }
        let mut data: Vec<u8> = if reversed_bits {
            strip.iter().map(|b| b.reverse_bits()).collect()
        } else {
            strip.to_vec()
        };
        // The decoder hands a row over once it sees the next end-of-line
        // code; writers end the strip without one, so one is added.
        data.extend_from_slice(&[0x00, 0x01]);
        let mut decoded = 0;
        fax::decoder::decode_g3(data.into_iter(), |changes| {
            if decoded < rows {
                out.extend(
                    fax::decoder::pels(changes, line_width)
                        .map(|c| if c == fax::Color::Black { 1.0 } else { 0.0 }),
                );
                decoded += 1;
            }
        });
        if decoded < rows {
            return Err("its fax data ends too early".into());
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::read_bits;

    #[test]
    fn twelve_bit_fields_read_across_byte_boundaries() {
        // 0xABC, 0xDEF, 0x123 packed: AB CD EF 12 3_.
        let row = [0xAB, 0xCD, 0xEF, 0x12, 0x30];
        assert_eq!(read_bits(&row, 0, 12), 0xABC);
        assert_eq!(read_bits(&row, 12, 12), 0xDEF);
        assert_eq!(read_bits(&row, 24, 12), 0x123);
        assert_eq!(read_bits(&row, 4, 3), 0b101);
    }
}
