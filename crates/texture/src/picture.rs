//! Picture files read and written with the `image` crate, for callers
//! outside the texture loader (the `relief render` output, the bench's
//! llvmpipe pictures, the glTF alpha probe, the tests).
//!
//! Why here: `image`'s entry points are generic over the reader or writer,
//! and an optimised build compiles every codec they reach again in each
//! crate that calls them (generic code is not shared between crates at
//! `opt-level` 3), about half a minute of build per caller. These plain
//! functions compile the codecs once, in this crate, for in-memory bytes.

use std::io::Cursor;
use std::path::Path;

use image::{DynamicImage, ImageDecoder, ImageFormat, ImageReader, ImageResult};

/// Decodes `bytes`, the format told by their first bytes.
pub fn decode(bytes: &[u8]) -> ImageResult<DynamicImage> {
    ImageReader::new(Cursor::new(bytes))
        .with_guessed_format()?
        .decode()
}

/// Decodes `bytes` as `format`.
pub fn decode_as(bytes: &[u8], format: ImageFormat) -> ImageResult<DynamicImage> {
    ImageReader::with_format(Cursor::new(bytes), format).decode()
}

/// Reads and decodes the file at `path`: the format its name says, else
/// the one its first bytes tell.
pub fn open(path: impl AsRef<Path>) -> ImageResult<DynamicImage> {
    open_path(path.as_ref())
}

fn open_path(path: &Path) -> ImageResult<DynamicImage> {
    let bytes = std::fs::read(path)?;
    match ImageFormat::from_path(path) {
        Ok(format) => decode_as(&bytes, format),
        Err(_) => decode(&bytes),
    }
}

/// Encodes `picture` as `format`, whole, in memory (some encoders seek).
pub fn encode(picture: &DynamicImage, format: ImageFormat) -> ImageResult<Vec<u8>> {
    let mut out = Cursor::new(Vec::new());
    picture.write_to(&mut out, format)?;
    Ok(out.into_inner())
}

/// Writes `picture` to `path` in the format its name says.
pub fn save(picture: &DynamicImage, path: impl AsRef<Path>) -> ImageResult<()> {
    save_path(picture, path.as_ref())
}

fn save_path(picture: &DynamicImage, path: &Path) -> ImageResult<()> {
    let bytes = encode(picture, ImageFormat::from_path(path)?)?;
    std::fs::write(path, bytes)?;
    Ok(())
}

/// Whether the picture in `bytes` has an alpha channel, by its header
/// alone (false when no decoder takes it).
pub fn has_alpha(bytes: &[u8]) -> bool {
    ImageReader::new(Cursor::new(bytes))
        .with_guessed_format()
        .ok()
        .and_then(|r| r.into_decoder().ok())
        .is_some_and(|d| d.color_type().has_alpha())
}
