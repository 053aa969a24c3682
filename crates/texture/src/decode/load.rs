//! Pictures from disk (or memory) into textures: every format the `image`
//! crate decodes, plus XPM, with limits so a hostile file costs nothing.
//!
//! RGB is the colour; the height (bump map) is the alpha channel, or the
//! mean of R, G and B when the picture has no alpha ([000] §3.2.4, docs/sources.md).

use std::fs::File;
use std::io::{Cursor, Read};
use std::path::Path;

use image::{DynamicImage, ImageDecoder, ImageError, ImageFormat, ImageReader, Limits};

use super::tiff_picture::Refusal;
use super::{ktx2, resample, tiff_samples, variants, xpm};
use crate::Texture;
use crate::sample::level::Level;
use crate::sample::texels::{Texels, pack_rgb8, to_unorm16};
use relief_core::budget::{self, Precision, Reservation};
use relief_core::sanitize;

/// Largest width or height accepted.
pub const MAX_DIMENSION: u32 = 16_384;
/// Largest number of texels accepted (4 to 16 bytes each once loaded, see
/// `texels`), e.g. 4096×4096 or 16384×1024.
pub const MAX_TEXELS: u64 = 1 << 24;
/// Largest file read (compressed pictures that big are beyond any texture).
pub const MAX_FILE_BYTES: u64 = 256 << 20;
/// Memory the decoder may use beside its output.
const MAX_DECODER_ALLOC: u64 = 512 << 20;
/// Longest decoder message kept in an error.
const MAX_REASON_CHARS: usize = 160;

/// Why a picture could not become a texture. Every message is one line,
/// names the file, and holds no control character.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum TextureError {
    #[error("{file}: no such file")]
    NotFound { file: String },
    #[error("{file}: is a directory, not an image")]
    Directory { file: String },
    #[error("{file}: not a regular file")]
    NotAFile { file: String },
    #[error("{file}: cannot read: {reason}")]
    Unreadable { file: String, reason: String },
    #[error("{file}: file too large ({size} bytes; limit {limit})")]
    FileTooLarge { file: String, size: u64, limit: u64 },
    #[error("{file}: empty file")]
    Empty { file: String },
    #[error("{file}: not an image in a known format")]
    UnknownFormat { file: String },
    #[error(
        "{file}: picture too large ({detail}; limit {MAX_DIMENSION} pixels per side and {MAX_TEXELS} pixels in all)"
    )]
    TooLarge { file: String, detail: String },
    #[error("{file}: empty picture ({width}x{height})")]
    ZeroSize {
        file: String,
        width: u32,
        height: u32,
    },
    #[error("{file}: corrupt or truncated {format} file: {reason}")]
    Corrupt {
        file: String,
        format: String,
        reason: String,
    },
    #[error("{file}: unsupported {format} file: {reason}")]
    Unsupported {
        file: String,
        format: String,
        reason: String,
    },
    #[error("{file}: bad XPM file: {reason}")]
    Xpm { file: String, reason: String },
    #[error("{file}: {reason}")]
    OverBudget { file: String, reason: String },
}

impl TextureError {
    /// The file the error is about (sanitised).
    pub fn file(&self) -> &str {
        match self {
            TextureError::NotFound { file }
            | TextureError::Directory { file }
            | TextureError::NotAFile { file }
            | TextureError::Unreadable { file, .. }
            | TextureError::FileTooLarge { file, .. }
            | TextureError::Empty { file }
            | TextureError::UnknownFormat { file }
            | TextureError::TooLarge { file, .. }
            | TextureError::ZeroSize { file, .. }
            | TextureError::Corrupt { file, .. }
            | TextureError::Unsupported { file, .. }
            | TextureError::Xpm { file, .. }
            | TextureError::OverBudget { file, .. } => file,
        }
    }
}

/// External text made fit for a one-line message: whitespace runs become
/// one space, control characters `?`, and long text is cut.
fn one_line(text: &str) -> String {
    let joined = text.split_whitespace().collect::<Vec<_>>().join(" ");
    let mut clean = sanitize::clean(&joined);
    if clean.chars().count() > MAX_REASON_CHARS {
        clean = clean.chars().take(MAX_REASON_CHARS).collect::<String>() + "…";
    }
    clean
}

/// What a float picture's values (Radiance, OpenEXR, float TIFF) are kept
/// as; other pictures hold 0..=1 whatever this says.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Range {
    /// A texture's colours and heights: clamped to 0..=1.
    Unit,
    /// An environment's radiance: as the file has it, negatives 0 and at
    /// most 65504 (the largest half float).
    Radiance,
}

/// Loads a picture file as a texture (height = alpha, or mean of RGB).
pub fn load_texture(path: &Path) -> Result<Texture, TextureError> {
    load_picture(path, Range::Unit)
}

/// Loads a picture file with its float values kept in `range`: a texture
/// (`Range::Unit`, as [`load_texture`]) or an environment's radiance.
pub fn load_picture(path: &Path, range: Range) -> Result<Texture, TextureError> {
    let bytes = read_file(path)?;
    let name = sanitize::display_path(path);
    let (level, held) = decode_level(&bytes, &name, format_hint(path), range)?;
    Ok(Texture::new(name, level).holding(held))
}

/// Loads a colour picture and takes its height from a second picture: that
/// picture's alpha, or the mean of its RGB when it has no alpha. A height map
/// of another size is resampled to the colour picture's size (box filter
/// where it shrinks, bilinear where it grows, repeating at the borders).
pub fn load_texture_with_height(color: &Path, height: &Path) -> Result<Texture, TextureError> {
    let color_tex = load_texture(color)?;
    let height_tex = load_texture(height)?;
    with_height_map(color_tex, &height_tex)
}

/// Like [`load_texture`] from bytes already in memory; `name` is used in
/// messages and its extension (`.tga`, `.xpm`…) helps when the content does
/// not say its format.
pub fn load_texture_from_bytes(name: &str, bytes: &[u8]) -> Result<Texture, TextureError> {
    let clean = sanitize::clean(name);
    if bytes.len() as u64 > MAX_FILE_BYTES {
        return Err(TextureError::FileTooLarge {
            file: clean,
            size: bytes.len() as u64,
            limit: MAX_FILE_BYTES,
        });
    }
    let (level, held) = decode_level(bytes, &clean, format_hint(Path::new(name)), Range::Unit)?;
    Ok(Texture::new(clean, level).holding(held))
}

/// Whether the picture in `bytes` has an alpha channel, by its header
/// (false when no decoder takes it): a KTX2 texture's, or any other's.
pub fn has_alpha(bytes: &[u8]) -> bool {
    if ktx2::is_ktx2(bytes) {
        return ktx2::has_alpha(bytes);
    }
    crate::picture::has_alpha(bytes)
}

/// Like [`load_texture_with_height`] from bytes in memory.
pub fn load_texture_with_height_from_bytes(
    color_name: &str,
    color: &[u8],
    height_name: &str,
    height: &[u8],
) -> Result<Texture, TextureError> {
    let color_tex = load_texture_from_bytes(color_name, color)?;
    let height_tex = load_texture_from_bytes(height_name, height)?;
    with_height_map(color_tex, &height_tex)
}

/// The colour of `color` with the height of `height` (resampled to the
/// colour's size when they differ). Named "colour + height". The new
/// texture and the resize reserve their memory first.
pub fn with_height_map(color: Texture, height: &Texture) -> Result<Texture, TextureError> {
    let base = color.base();
    let (w, h) = (base.width, base.height);
    let name = format!("{} + {}", color.name, height.name);
    let from = (height.width() as u64, height.height() as u64);
    let to = (w as u64, h as u64);
    let over = |e: budget::BudgetError| TextureError::OverBudget {
        file: height.name.clone(),
        reason: e.to_string(),
    };
    let held = budget::reserve(
        &format!("a {}x{} texture with its height map", w, h),
        budget::texture_bytes(to.0, to.1),
    )
    .map_err(over)?;
    let resize = budget::reserve(
        &format!(
            "resizing a {}x{} height map to {}x{}",
            from.0, from.1, to.0, to.1
        ),
        budget::resize_bytes(from, to),
    )
    .map_err(over)?;
    let heights = resample::grid(
        &height
            .base()
            .texels
            .iter()
            .map(|t| t[3])
            .collect::<Vec<_>>(),
        (height.width(), height.height()),
        (w, h),
    );
    let texels = base
        .texels
        .iter()
        .zip(heights)
        .map(|(t, hgt)| [t[0], t[1], t[2], hgt])
        .collect::<Texels>();
    drop(resize);
    Ok(Texture::new(
        name,
        Level {
            wrap: Default::default(),
            width: w,
            height: h,
            texels,
        },
    )
    .holding(held))
}

/// What the texture for a view is: the picture at `image` (or the built-in
/// brick when there is none), with its height taken from `height_map` when
/// one is given. This is what `--height-map` and `IMAGE` arguments mean.
pub fn load_for_view(
    image: Option<&Path>,
    height_map: Option<&Path>,
) -> Result<Texture, TextureError> {
    let color = match image {
        Some(path) => load_texture(path)?,
        None => super::procedural::brick(),
    };
    match height_map {
        Some(path) => with_height_map(color, &load_texture(path)?),
        None => Ok(color),
    }
}

/// The format a file name suggests, for content without a signature (TGA).
fn format_hint(path: &Path) -> Option<ImageFormat> {
    ImageFormat::from_path(path).ok()
}

/// Reads a whole file after checking what it is and how big.
fn read_file(path: &Path) -> Result<Vec<u8>, TextureError> {
    let file = sanitize::display_path(path);
    let io_error = |e: std::io::Error, file: String| match e.kind() {
        std::io::ErrorKind::NotFound => TextureError::NotFound { file },
        std::io::ErrorKind::IsADirectory => TextureError::Directory { file },
        _ => TextureError::Unreadable {
            file,
            reason: one_line(&e.to_string()),
        },
    };
    let meta = std::fs::metadata(path).map_err(|e| io_error(e, file.clone()))?;
    if meta.is_dir() {
        return Err(TextureError::Directory { file });
    }
    if !meta.is_file() {
        return Err(TextureError::NotAFile { file });
    }
    if meta.len() > MAX_FILE_BYTES {
        return Err(TextureError::FileTooLarge {
            file,
            size: meta.len(),
            limit: MAX_FILE_BYTES,
        });
    }
    let handle = File::open(path).map_err(|e| io_error(e, file.clone()))?;
    let mut bytes = Vec::with_capacity(meta.len() as usize);
    // `take` bounds the read even if the file grows after the check.
    handle
        .take(MAX_FILE_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| io_error(e, file.clone()))?;
    if bytes.len() as u64 > MAX_FILE_BYTES {
        return Err(TextureError::FileTooLarge {
            file,
            size: bytes.len() as u64,
            limit: MAX_FILE_BYTES,
        });
    }
    Ok(bytes)
}

fn too_large(file: &str, width: u64, height: u64) -> TextureError {
    TextureError::TooLarge {
        file: file.to_owned(),
        detail: format!("{width}x{height}"),
    }
}

fn check_size(file: &str, width: u32, height: u32) -> Result<(), TextureError> {
    if width == 0 || height == 0 {
        return Err(TextureError::ZeroSize {
            file: file.to_owned(),
            width,
            height,
        });
    }
    if width > MAX_DIMENSION || height > MAX_DIMENSION || width as u64 * height as u64 > MAX_TEXELS
    {
        return Err(too_large(file, width as u64, height as u64));
    }
    Ok(())
}

/// Decodes any supported picture into a level (top row first).
fn decode_level(
    bytes: &[u8],
    file: &str,
    hint: Option<ImageFormat>,
    range: Range,
) -> Result<(Level, Reservation), TextureError> {
    if bytes.is_empty() {
        return Err(TextureError::Empty {
            file: file.to_owned(),
        });
    }
    if ktx2::is_ktx2(bytes) {
        return ktx2_level(bytes, file);
    }
    if xpm::looks_like_xpm(bytes) || file.to_ascii_lowercase().ends_with(".xpm") {
        return decode_xpm(bytes, file);
    }
    // The decoders are third-party code fed untrusted bytes: a panic in one
    // is this file's error, not the program's end.
    let first = contained_decode(bytes, file, hint, range);
    // Valid variants the crate refuses (docs/textures.md): decoded again,
    // rewritten into the form it reads; files it reads are never rewritten.
    match first {
        Err(TextureError::Corrupt { .. } | TextureError::Unsupported { .. }) => {
            match variants::rewrite(bytes) {
                Some((fixed, format)) => {
                    contained_decode(&fixed, file, Some(format), range).or(first)
                }
                None if bytes.starts_with(b"II*\0") || bytes.starts_with(b"MM\0*") => {
                    relief_core::contain::contain(|| tiff_level(bytes, file, range))
                        .ok()
                        .and_then(|r| r.transpose())
                        .unwrap_or(first)
                }
                None => first,
            }
        }
        other => other,
    }
}

/// A TIFF through the `tiff` crate's own samples ([`tiff_samples`]):
/// `Ok(None)` when it cannot decode it either.
fn tiff_level(
    bytes: &[u8],
    file: &str,
    range: Range,
) -> Result<Option<(Level, Reservation)>, TextureError> {
    let Some((width, height)) = tiff_samples::dimensions(bytes) else {
        return Ok(None);
    };
    check_size(file, width, height)?;
    let held = reserve_texture(file, width as usize, height as usize, Precision::Float)?;
    let p = match tiff_samples::decode(bytes, MAX_DECODER_ALLOC as usize) {
        Ok(Some(p)) => p,
        Ok(None) => return Ok(None),
        Err(refusal) => return Err(refused(file, "TIFF", refusal)),
    };
    let level = level_from_rows(p.width, p.height, p.has_alpha, range, |x, y| {
        p.rgba[y * p.width + x]
    });
    Ok(Some((level, held)))
}

/// A KTX2 texture's level: the first, or under a size cap the largest
/// within it (then halved further if none is), checked and reserved
/// before the transcoder allocates.
fn ktx2_level(bytes: &[u8], file: &str) -> Result<(Level, Reservation), TextureError> {
    let as_error = |refusal| refused(file, "KTX2", refusal);
    let header = ktx2::header(bytes).map_err(as_error)?;
    check_size(file, header.width, header.height)?;
    let k = ktx2::level_for(&header, super::size_cap::max_side());
    let (w, h) = ktx2::level_size(&header, k);
    let inflated = ktx2::check_level(bytes, &header, k).map_err(as_error)?;
    let mut held = reserve_texture(file, w as usize, h as usize, Precision::Unorm8)?;
    // The transcoder's own buffers beside the texture: the inflated
    // Zstandard level, and the RGBA it writes before it becomes texels.
    let scratch = budget::reserve(
        &format!("transcoding a {w}x{h} KTX2 level"),
        inflated + 4 * w as u64 * h as u64,
    )
    .map_err(|e| TextureError::OverBudget {
        file: file.to_owned(),
        reason: e.to_string(),
    })?;
    let mut rgba = image::RgbaImage::new(w, h);
    let has_alpha = relief_core::contain::contain(|| ktx2::transcode(bytes, k, &mut rgba))
        .unwrap_or_else(|_| {
            Err(Refusal::Corrupt(
                "the transcoder stopped on data it does not expect".into(),
            ))
        })
        .map_err(as_error)?;
    let image = match has_alpha {
        true => DynamicImage::ImageRgba8(rgba),
        false => DynamicImage::ImageRgb8(DynamicImage::ImageRgba8(rgba).into_rgb8()),
    };
    let image = super::size_cap::reduced(image);
    drop(scratch);
    let kept = budget::texture_bytes_at(
        image.width() as u64,
        image.height() as u64,
        Precision::Unorm8,
    );
    held.shrink(held.bytes().saturating_sub(kept));
    // 8-bit RGBA: 0..=1 whatever the range.
    Ok((level_from_image(image, Range::Unit), held))
}

/// The error of `file`, of `format`, that one of relief's own decoders
/// refused.
fn refused(file: &str, format: &str, refusal: Refusal) -> TextureError {
    let (file, format) = (file.to_owned(), format.to_owned());
    match refusal {
        Refusal::Unsupported(reason) => TextureError::Unsupported {
            file,
            format,
            reason,
        },
        Refusal::Corrupt(reason) => TextureError::Corrupt {
            file,
            format,
            reason,
        },
    }
}

/// [`decode_image`] with a decoder panic turned into this file's error (its
/// text is the decoder's internals, not a reason a user can act on).
fn contained_decode(
    bytes: &[u8],
    file: &str,
    hint: Option<ImageFormat>,
    range: Range,
) -> Result<(Level, Reservation), TextureError> {
    relief_core::contain::contain(|| decode_image(bytes, file, hint, range)).unwrap_or_else(|_| {
        Err(TextureError::Corrupt {
            file: file.to_owned(),
            format: format_name(bytes, hint),
            reason: "the decoder stopped on data it does not expect".into(),
        })
    })
}

/// The format's name for messages ("PNG"), from the content or the hint.
fn format_name(bytes: &[u8], hint: Option<ImageFormat>) -> String {
    image::guess_format(bytes)
        .ok()
        .or(hint)
        .map(|f| format!("{f:?}").to_uppercase())
        .unwrap_or_else(|| "image".into())
}

/// The `image` crate's part of [`decode_level`].
fn decode_image(
    bytes: &[u8],
    file: &str,
    hint: Option<ImageFormat>,
    range: Range,
) -> Result<(Level, Reservation), TextureError> {
    let mut reader = ImageReader::new(Cursor::new(bytes))
        .with_guessed_format()
        .map_err(|e| TextureError::Unreadable {
            file: file.to_owned(),
            reason: one_line(&e.to_string()),
        })?;
    if reader.format().is_none() {
        match hint {
            Some(format) => reader.set_format(format),
            None => {
                return Err(TextureError::UnknownFormat {
                    file: file.to_owned(),
                });
            }
        }
    }
    let format = reader
        .format()
        .map(|f| format!("{f:?}").to_uppercase())
        .unwrap_or_else(|| "image".into());
    let mut limits = Limits::default();
    limits.max_image_width = Some(MAX_DIMENSION);
    limits.max_image_height = Some(MAX_DIMENSION);
    limits.max_alloc = Some(MAX_DECODER_ALLOC);
    reader.limits(limits);
    let image_error = |e: ImageError| convert_error(e, file, &format);
    // The header alone first: its size is checked before any pixel buffer exists.
    let decoder = reader.into_decoder().map_err(image_error)?;
    let (width, height) = decoder.dimensions();
    check_size(file, width, height)?;
    let precision = precision_of(decoder.color_type());
    let held = reserve_texture(file, width as usize, height as usize, precision)?;
    let whole = super::size_cap::max_side().is_none_or(|side| width.max(height) <= side);
    if whole && let Some(texels) = eight_bit_texels(decoder.color_type(), width, height) {
        let texels = read_into(decoder, texels).map_err(image_error)?;
        let level = Level {
            wrap: Default::default(),
            width: width as usize,
            height: height as usize,
            texels: texels.widened_if_small(),
        };
        return Ok((level, held));
    }
    let image = DynamicImage::from_decoder(decoder).map_err(image_error)?;
    // A frame that needs less detail gets a smaller copy (`size_cap`), and
    // the budget the whole picture would have held is given back.
    let image = super::size_cap::reduced(image);
    let mut held = held;
    let kept = budget::texture_bytes_at(image.width() as u64, image.height() as u64, precision);
    held.shrink(held.bytes().saturating_sub(kept));
    Ok((level_from_image(image, range), held))
}

fn convert_error(e: ImageError, file: &str, format: &str) -> TextureError {
    let file = file.to_owned();
    let format = format.to_owned();
    match e {
        ImageError::Limits(l) => TextureError::TooLarge {
            file,
            detail: one_line(&l.to_string()),
        },
        ImageError::Unsupported(u) => TextureError::Unsupported {
            file,
            format,
            reason: one_line(&u.to_string()),
        },
        ImageError::IoError(io) if io.kind() == std::io::ErrorKind::UnexpectedEof => {
            TextureError::Corrupt {
                file,
                format,
                reason: "ends too early".into(),
            }
        }
        // The bytes are in memory: any other I/O error a decoder reports is
        // about the data (an LZW stream that does not decode), not the disk.
        ImageError::IoError(io) => TextureError::Corrupt {
            file,
            format,
            reason: plain_reason(&io.to_string()),
        },
        ImageError::Decoding(d) => TextureError::Corrupt {
            file,
            format,
            reason: plain_reason(&d.to_string()),
        },
        ImageError::Parameter(p) => TextureError::Unsupported {
            file,
            format,
            reason: plain_reason(&p.to_string()),
        },
        other => TextureError::Corrupt {
            file,
            format,
            reason: plain_reason(&other.to_string()),
        },
    }
}

/// A decoder's message in plain words: the "Format error decoding Png:"
/// prefix (the line already names the format) and any debug dump of the
/// decoder's internals (`ChunkType { type: IHDR, … }`) dropped.
fn plain_reason(message: &str) -> String {
    let mut text = message.trim();
    // zune's "I/O errors Not enough bytes, expected 64 but found 6".
    if text.contains("Not enough bytes") || text.contains("nexpected end of file") {
        return "ends too early".into();
    }
    let lower = text.to_ascii_lowercase();
    if lower.contains("lzw") {
        return "its LZW-compressed data does not decode".into();
    }
    if lower.contains("deflate") {
        return "its deflate-compressed data does not decode".into();
    }
    if let Some(rest) = text.strip_prefix("Format error") {
        // "Format error decoding Png: …" or "Format error: …"
        text = rest.split_once(':').map_or("", |(_, r)| r).trim();
    }
    // `ChunkType { type: IHDR, critical: true, … }` → `IHDR chunk`; other
    // braces and their contents go.
    let mut plain = String::new();
    let mut rest = text;
    while let Some(open) = rest.find('{') {
        let head = rest[..open].trim_end();
        // A chunk name with a control byte prints as `A\u{1}bc` inside the
        // dump: its end is the `}` after the last field, not the first one.
        let from = if head.ends_with("ChunkType") {
            rest[open..].find("safecopy").map_or(open, |i| open + i)
        } else {
            open
        };
        let close = rest[from..].find('}').map_or(rest.len(), |i| from + i + 1);
        let inside = &rest[open + 1..close.saturating_sub(1).max(open + 1)];
        match (
            head.strip_suffix("ChunkType"),
            inside.trim().strip_prefix("type:"),
        ) {
            (Some(before), Some(kind)) => {
                plain.push_str(before);
                let kind = kind.split(", critical").next().unwrap_or("").trim();
                plain.push_str(&escapes_as_marks(kind));
                if !rest[close..].trim_start().starts_with("chunk") {
                    plain.push_str(" chunk");
                }
            }
            _ => plain.push_str(head),
        }
        rest = &rest[close..];
    }
    plain.push_str(rest);
    let plain: Vec<&str> = plain.split(' ').filter(|w| !is_type_name(w)).collect();
    let reason = one_line(plain.join(" ").trim().trim_end_matches([':', ',']));
    if reason.is_empty() {
        "the data does not decode".into()
    } else {
        reason
    }
}

/// A word that is a decoder's type or variant name (`BadCodeLengthHuffmanTree`):
/// capitalised, with another capital after a small letter, letters only.
fn is_type_name(word: &str) -> bool {
    let word = word.trim_end_matches(['.', ',', ':', ')']);
    let mut chars = word.chars();
    let starts_upper = chars.next().is_some_and(|c| c.is_ascii_uppercase());
    let letters = word.chars().all(|c| c.is_ascii_alphabetic());
    let camel = word
        .as_bytes()
        .windows(2)
        .any(|w| w[0].is_ascii_lowercase() && w[1].is_ascii_uppercase());
    starts_upper && letters && camel
}

/// `\u{1}` escapes of a `Debug` string as `?`.
fn escapes_as_marks(text: &str) -> String {
    let mut out = String::new();
    let mut rest = text;
    while let Some(i) = rest.find("\\u{") {
        out.push_str(&rest[..i]);
        out.push('?');
        rest = rest[i..].find('}').map_or("", |j| &rest[i + j + 1..]);
    }
    out.push_str(rest);
    out
}

/// Holds the budget for a `width × height` texture's worst case at `precision`.
fn reserve_texture(
    file: &str,
    width: usize,
    height: usize,
    precision: Precision,
) -> Result<Reservation, TextureError> {
    budget::reserve(
        &format!("a {width}x{height} picture"),
        budget::texture_bytes_at(width as u64, height as u64, precision),
    )
    .map_err(|e| TextureError::OverBudget {
        file: file.to_owned(),
        reason: e.to_string(),
    })
}

/// The XPM reader builds its pixels before the texture exists: it may make
/// no more than the budget has room for.
fn xpm_texel_limit() -> usize {
    let room = budget::BUDGET_BYTES.saturating_sub(budget::in_use());
    let texels = (room as f64 / budget::TEXTURE_BYTES_PER_TEXEL) as u64;
    texels.min(MAX_TEXELS) as usize
}

fn decode_xpm(bytes: &[u8], file: &str) -> Result<(Level, Reservation), TextureError> {
    let image = xpm::decode(bytes, xpm_texel_limit()).map_err(|e| TextureError::Xpm {
        file: file.to_owned(),
        reason: one_line(&e.0),
    })?;
    let (w, h) = (image.width, image.height);
    if w > MAX_DIMENSION as usize || h > MAX_DIMENSION as usize {
        return Err(too_large(file, w as u64, h as u64));
    }
    let held = reserve_texture(file, w, h, Precision::Float)?;
    let level = level_from_rows(w, h, image.has_alpha, Range::Unit, |x, y| {
        image.rgba[y * w + x]
    });
    Ok((level, held))
}

/// A level from a pixel reader `px(x, y)` (y = 0 the top row, RGBA, kept
/// in `range`; not a number reads 0): rows kept top first (v = 0 is the top
/// of the picture), height = alpha or mean of RGB.
fn level_from_rows(
    width: usize,
    height: usize,
    has_alpha: bool,
    range: Range,
    px: impl Fn(usize, usize) -> [f32; 4],
) -> Level {
    let top = match range {
        Range::Unit => 1.0,
        Range::Radiance => 65504.0,
    };
    let mut texels = Vec::with_capacity(width * height);
    for y in 0..height {
        for x in 0..width {
            let [r, g, b, a] = px(x, y).map(|c| {
                if c.is_finite() {
                    c.clamp(0.0, top)
                } else {
                    0.0
                }
            });
            // In f64 so that a grey texel's height is exactly its grey.
            let h = if has_alpha {
                a
            } else {
                ((r as f64 + g as f64 + b as f64) / 3.0) as f32
            };
            texels.push([r, g, b, h]);
        }
    }
    Level {
        wrap: Default::default(),
        width,
        height,
        texels: Texels::F32(texels),
    }
}

/// The precision a picture of `color` is kept at: its channels' bits.
fn precision_of(color: image::ColorType) -> Precision {
    match color.bytes_per_pixel() as usize * 8 / color.channel_count() as usize {
        8 => Precision::Unorm8,
        16 => Precision::Unorm16,
        _ => Precision::Float,
    }
}

/// The storage an 8-bit RGB or RGBA picture is decoded straight into, at
/// its final size (`None`: any other picture).
fn eight_bit_texels(color: image::ColorType, width: u32, height: u32) -> Option<Texels> {
    let n = width as usize * height as usize;
    match color {
        image::ColorType::Rgba8 => Some(Texels::Rgba8(vec![[0; 4]; n])),
        image::ColorType::Rgb8 => Some(Texels::Rgb8(vec![[0; 4]; n])),
        _ => None,
    }
}

/// Decodes into `texels`' own memory: no decoder buffer beside the level
/// (a 4096² picture's 48 to 64 MiB). RGB is decoded into the first three
/// quarters and spread to four bytes a texel from the end, where each
/// texel's bytes are read before anything is written over them.
fn read_into(decoder: impl ImageDecoder, mut texels: Texels) -> Result<Texels, ImageError> {
    match &mut texels {
        Texels::Rgba8(v) => decoder.read_image(v.as_flattened_mut())?,
        Texels::Rgb8(v) => {
            let n = v.len();
            decoder.read_image(&mut v.as_flattened_mut()[..3 * n])?;
            let bytes = v.as_flattened_mut();
            for i in (0..n).rev() {
                let (r, g, b) = (bytes[3 * i], bytes[3 * i + 1], bytes[3 * i + 2]);
                bytes[4 * i..4 * i + 4].copy_from_slice(&pack_rgb8(r, g, b));
            }
        }
        _ => unreachable!("made by eight_bit_texels"),
    }
    Ok(texels)
}

/// RGBA bytes as texels, in the same allocation when its size allows.
fn rgba_texels(raw: Vec<u8>) -> Vec<[u8; 4]> {
    bytemuck::allocation::try_cast_vec(raw).unwrap_or_else(|(_, raw)| {
        raw.chunks_exact(4)
            .map(|p| [p[0], p[1], p[2], p[3]])
            .collect()
    })
}

/// 8-bit pictures are kept in 8 bits (they read as k / 255, as
/// `Level::from_rgba8_top_down` does, so a PNG of a generated texture gives
/// back the same texels), 16-bit ones in 16 bits, float ones as floats.
fn level_from_image(image: DynamicImage, range: Range) -> Level {
    let (w, h) = (image.width() as usize, image.height() as usize);
    let color = image.color();
    let has_alpha = color.has_alpha();
    match precision_of(color) {
        Precision::Unorm8 => {
            // RGB and RGBA pictures straight from the decoder's buffer: no
            // RGBA copy beside it (a 4096² picture's 64 MiB).
            let texels = match image {
                DynamicImage::ImageRgba8(buf) => Texels::Rgba8(rgba_texels(buf.into_raw())),
                DynamicImage::ImageRgb8(buf) => Texels::Rgb8(
                    buf.as_raw()
                        .chunks_exact(3)
                        .map(|p| pack_rgb8(p[0], p[1], p[2]))
                        .collect(),
                ),
                other if has_alpha => Texels::Rgba8(rgba_texels(other.into_rgba8().into_raw())),
                other => Texels::Rgb8(
                    other
                        .into_rgba8()
                        .pixels()
                        .map(|p| pack_rgb8(p[0], p[1], p[2]))
                        .collect(),
                ),
            };
            Level {
                wrap: Default::default(),
                width: w,
                height: h,
                texels: texels.widened_if_small(),
            }
        }
        Precision::Unorm16 => {
            let buf = image.into_rgba16();
            let texels = buf
                .pixels()
                .map(|p| {
                    let [r, g, b, a] = p.0;
                    if has_alpha {
                        [r, g, b, a]
                    } else {
                        // The mean as computed from floats, to the nearest step.
                        let c = |k: u16| (k as f32 / 65535.0) as f64;
                        let mean = ((c(r) + c(g) + c(b)) / 3.0) as f32;
                        [r, g, b, to_unorm16(mean)]
                    }
                })
                .collect();
            Level {
                wrap: Default::default(),
                width: w,
                height: h,
                texels: Texels::Rgba16(texels).widened_if_small(),
            }
        }
        Precision::Float => {
            let buf = image.into_rgba32f();
            level_from_rows(w, h, has_alpha, range, |x, y| {
                buf.get_pixel(x as u32, y as u32).0
            })
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decoder_messages_in_plain_words() {
        assert_eq!(
            plain_reason("Format error decoding Png: ChunkType { type: IHDR, critical: true }"),
            "IHDR chunk"
        );
        assert_eq!(
            plain_reason(
                "Format error decoding Png: CRC error: expected 0x1 have 0x2 while decoding ChunkType { type: IDAT, critical: true } chunk."
            ),
            "CRC error: expected 0x1 have 0x2 while decoding IDAT chunk."
        );
        assert_eq!(
            plain_reason("Format error decoding Bmp: {}"),
            "the data does not decode"
        );
        assert_eq!(plain_reason("bad\nheader"), "bad header");
        assert_eq!(
            plain_reason("Corrupt deflate stream. BadCodeLengthHuffmanTree"),
            "its deflate-compressed data does not decode"
        );
        assert_eq!(
            plain_reason("Format error decoding Gif: bad block SomeVariantName."),
            "bad block"
        );
        assert_eq!(
            plain_reason(
                "Format error decoding Png: Unrecognized critical chunk: ChunkType { type: A\\u{1}bc, critical: true, private: false, reserved: true, safecopy: true }"
            ),
            "Unrecognized critical chunk: A?bc chunk"
        );
        assert_eq!(
            plain_reason(
                "Format error decoding Jpeg: I/O errors Not enough bytes, expected 64 but found 6"
            ),
            "ends too early"
        );
        assert_eq!(
            plain_reason("invalid code in LZW stream"),
            "its LZW-compressed data does not decode"
        );
    }
}
