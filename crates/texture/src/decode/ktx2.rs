//! KTX2 textures of Basis Universal data (glTF's `KHR_texture_basisu`):
//! ETC1S (BasisLZ) and UASTC LDR, plain or Zstandard-supercompressed,
//! transcoded to RGBA8 by the `basisu` crate.
//!
//! The header and the level index are read here first (KTX 2.0 §3): the
//! size, the level's place in the file and a Zstandard level's claimed
//! length are checked before the transcoder allocates anything from them.

use basisu::{DecodeFlags, Error, SourceFormat, TargetFormat, Transcoder};

use super::tiff_picture::Refusal;

/// The file identifier every KTX2 file starts with: «KTX 20»\r\n\x1A\n.
pub const IDENTIFIER: [u8; 12] = [
    0xAB, 0x4B, 0x54, 0x58, 0x20, 0x32, 0x30, 0xBB, 0x0D, 0x0A, 0x1A, 0x0A,
];
/// The identifier, the header (9 words) and the index (4 words, 2 longs).
const HEADER_BYTES: usize = 80;
/// One level index entry: byteOffset, byteLength, uncompressedByteLength.
const LEVEL_ENTRY_BYTES: usize = 24;
/// supercompressionScheme: none, Zstandard (1 is BasisLZ, ETC1S's).
const SCHEME_NONE: u32 = 0;
const SCHEME_ZSTD: u32 = 2;
/// The colour model of UASTC data (Khronos Data Format 1.3).
const KHR_DF_MODEL_UASTC: u32 = 166;
/// Bytes of one 4×4 UASTC block.
const UASTC_BLOCK_BYTES: u64 = 16;

/// Whether `bytes` start like a KTX2 file.
pub fn is_ktx2(bytes: &[u8]) -> bool {
    bytes.starts_with(&IDENTIFIER)
}

/// What the header says, checked against the file's length.
#[derive(Clone, Copy, Debug)]
pub struct Header {
    pub width: u32,
    pub height: u32,
    /// levelCount, at least 1 (0 asks a reader to make the mip levels).
    pub levels: u32,
    pub scheme: u32,
}

fn word(bytes: &[u8], at: usize) -> u32 {
    u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap_or_default())
}

fn long(bytes: &[u8], at: usize) -> u64 {
    u64::from_le_bytes(bytes[at..at + 8].try_into().unwrap_or_default())
}

/// The header of a KTX2 file: a 2D texture (glTF allows no other), with
/// its level index inside the file.
pub fn header(bytes: &[u8]) -> Result<Header, Refusal> {
    if bytes.len() < HEADER_BYTES + LEVEL_ENTRY_BYTES {
        return Err(Refusal::Corrupt("ends too early".into()));
    }
    let (depth, layers, faces) = (word(bytes, 28), word(bytes, 32), word(bytes, 36));
    if depth > 1 || layers > 1 || faces != 1 {
        return Err(Refusal::Unsupported(format!(
            "not a 2D texture ({faces} faces, {layers} layers, depth {depth}; glTF reads 2D ones)"
        )));
    }
    let header = Header {
        width: word(bytes, 20),
        height: word(bytes, 24),
        levels: word(bytes, 40).max(1),
        scheme: word(bytes, 44),
    };
    let index_end = HEADER_BYTES as u64 + LEVEL_ENTRY_BYTES as u64 * header.levels as u64;
    if index_end > bytes.len() as u64 {
        return Err(Refusal::Corrupt(format!(
            "its {} levels' index ends past the end of the file ({} bytes)",
            header.levels,
            bytes.len()
        )));
    }
    Ok(header)
}

/// The level to read when pictures are cut to `side` texels (`None`:
/// whole): the largest one within the side, or the smallest there is.
pub fn level_for(header: &Header, side: Option<u32>) -> u32 {
    let Some(side) = side else { return 0 };
    let (mut w, mut h, mut k) = (header.width, header.height, 0);
    while (w > side.max(1) || h > side.max(1)) && k + 1 < header.levels {
        (w, h, k) = ((w / 2).max(1), (h / 2).max(1), k + 1);
    }
    k
}

/// Level `k`'s size (KTX 2.0 §4.1: each level halves, rounding down, to 1).
pub fn level_size(header: &Header, k: u32) -> (u32, u32) {
    ((header.width >> k).max(1), (header.height >> k).max(1))
}

/// Checks level `k`'s data lies in the file and, for a Zstandard level,
/// that it claims the length its blocks take (the transcoder allocates
/// what it claims). Returns the bytes it inflates to (0: none).
pub fn check_level(bytes: &[u8], header: &Header, k: u32) -> Result<u64, Refusal> {
    let at = HEADER_BYTES + LEVEL_ENTRY_BYTES * k as usize;
    let (offset, length, inflated) = (long(bytes, at), long(bytes, at + 8), long(bytes, at + 16));
    if offset
        .checked_add(length)
        .is_none_or(|end| end > bytes.len() as u64)
    {
        return Err(Refusal::Corrupt(format!(
            "level {k} (bytes {offset} + {length}) lies past the end of the file ({} bytes)",
            bytes.len()
        )));
    }
    let (w, h) = level_size(header, k);
    let need = u64::from(w.div_ceil(4)) * u64::from(h.div_ceil(4)) * UASTC_BLOCK_BYTES;
    if header.scheme == SCHEME_ZSTD {
        if inflated != need {
            return Err(Refusal::Corrupt(format!(
                "level {k} claims {inflated} bytes once inflated; its {w}x{h} texels take {need}"
            )));
        }
        return Ok(inflated);
    }
    // Plain UASTC: a level too short for its size is refused before its
    // texels are allocated.
    if header.scheme == SCHEME_NONE
        && colour_model(bytes) == Some(KHR_DF_MODEL_UASTC)
        && length < need
    {
        return Err(Refusal::Corrupt(format!(
            "level {k} holds {length} bytes; its {w}x{h} texels take {need}"
        )));
    }
    Ok(0)
}

/// The Data Format Descriptor's colour model (its basic block's third
/// word, low byte), if the descriptor lies in the file.
fn colour_model(bytes: &[u8]) -> Option<u32> {
    let at = usize::try_from(word(bytes, 48)).ok()?.checked_add(12)?;
    bytes.get(at..at + 4)?;
    Some(word(bytes, at) & 0xFF)
}

/// The name of a block-compressed colour model relief does not read
/// (Khronos Data Format 1.4: BC1–BC7, ETC1, ETC2, ASTC, UASTC HDR), for
/// messages; `None` for ETC1S, UASTC LDR and any other model.
fn unread_model(model: u32) -> Option<&'static str> {
    Some(match model {
        128..=134 => "BC1-BC7",
        160 => "ETC1",
        161 => "ETC2",
        162 => "ASTC",
        167 => "UASTC HDR 4x4",
        168 => "UASTC HDR 6x6",
        _ => return None,
    })
}

/// Whether the texture has alpha (ETC1S's second slice, UASTC's RGBA).
pub fn has_alpha(bytes: &[u8]) -> bool {
    relief_core::contain::contain(|| Transcoder::new(bytes).is_ok_and(|t| t.has_alpha()))
        .unwrap_or(false)
}

/// Level `k` as RGBA8, row by row from the top, written into `out` (4
/// bytes a texel of [`level_size`]); whether it has alpha. The header and
/// the level must have passed [`header`] and [`check_level`].
pub fn transcode(bytes: &[u8], k: u32, out: &mut [u8]) -> Result<bool, Refusal> {
    let texture = Transcoder::new(bytes).map_err(|e| {
        // A codec the transcoder cannot even open, named by its model.
        match colour_model(bytes).and_then(unread_model) {
            Some(name) => {
                Refusal::Unsupported(format!("{name} data is not read (ETC1S and UASTC LDR are)"))
            }
            None => refusal(
                e,
                "not Basis Universal data (ETC1S or UASTC), or its header is damaged",
            ),
        }
    })?;
    match texture.source_format() {
        SourceFormat::Etc1s | SourceFormat::UastcLdr => {}
        other => {
            return Err(Refusal::Unsupported(format!(
                "{} data is not read (ETC1S and UASTC LDR are)",
                source_name(other)
            )));
        }
    }
    if texture.is_video() {
        return Err(Refusal::Unsupported("an ETC1S video is not read".into()));
    }
    texture
        .transcode_into(k, TargetFormat::Rgba32, DecodeFlags::NONE, out)
        .map_err(|e| refusal(e, &format!("level {k}'s data does not decode")))?;
    Ok(texture.has_alpha())
}

/// The transcoder's error in plain words (`damaged`: what the data is
/// said to be when the transcoder only knows it is wrong). Its "feature
/// not implemented" is such a case: the codec and the shape are checked
/// first, and RGBA output is implemented for both codecs read.
fn refusal(e: Error, damaged: &str) -> Refusal {
    match e {
        Error::Truncated => Refusal::Corrupt("ends too early".into()),
        Error::ZstdRequired => Refusal::Unsupported("a Zstandard level".into()),
        Error::Unsupported { source, .. } => Refusal::Unsupported(format!(
            "{} data is not read (ETC1S and UASTC LDR are)",
            source_name(source)
        )),
        _ => Refusal::Corrupt(damaged.into()),
    }
}

/// A codec's name in messages.
fn source_name(source: SourceFormat) -> &'static str {
    match source {
        SourceFormat::Etc1s => "ETC1S",
        SourceFormat::UastcLdr => "UASTC LDR",
        SourceFormat::UastcHdr4x4 | SourceFormat::UastcHdr6x6 => "UASTC HDR",
        SourceFormat::AstcHdr6x6 => "ASTC HDR",
        SourceFormat::AstcLdr(_) => "ASTC",
        SourceFormat::XuastcLdr(_) => "XUASTC",
        _ => "this codec's",
    }
}
