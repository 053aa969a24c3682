//! `EXT_meshopt_compression` and `KHR_meshopt_compression`: a bufferView
//! whose bytes are a meshoptimizer stream in another buffer (attributes
//! by the vertex codec, indices by the index codec, then an optional
//! filter). Each such view is decoded before the file is read, into a new
//! buffer the view then points at, so that everything after reads
//! ordinary bytes.
//!
//! The decoder is relief's own, written from the bitstream and filter
//! appendices of the two extensions' specifications (`vertex`: the vertex
//! codec, versions 0 and 1; `index`: the triangle and index sequence
//! codecs; `filter`: the four filters). `decode` and `apply_filter` are
//! public for the tests.
//!
//! The fallback buffer such files declare (no data, or data relief does
//! not need) is never read.

mod codec;
mod cursor;
mod error;
mod filter;
mod index;
mod vertex;

pub use codec::{Filter, Mode, apply_filter, decode};
pub use error::DecodeError;

use ::gltf::json;
use json::Value;
use json::validation::USize64;

use super::data::Problem;
use super::reading::{hold, push_buffer};
use relief_core::budget::Reservation;

/// The two names of the extension, as files write them.
pub(super) const NAMES: [&str; 2] = ["EXT_meshopt_compression", "KHR_meshopt_compression"];

/// Whether a buffer is only the fallback of compressed views: its bytes
/// are not needed (and often not there).
pub(super) fn is_fallback(buffer: &json::Buffer) -> bool {
    let Some(ext) = buffer.extensions.as_ref() else {
        return false;
    };
    NAMES.iter().any(|n| {
        ext.others
            .get(*n)
            .and_then(|e| e.get("fallback"))
            .and_then(Value::as_bool)
            == Some(true)
    })
}

/// What a compressed view's extension object says.
struct Stream {
    buffer: usize,
    offset: usize,
    length: usize,
    stride: usize,
    count: usize,
    mode: Mode,
    filter: String,
}

/// Decodes every compressed bufferView of `root` into a new buffer
/// appended to `buffers` (and to `root.buffers`) and points the view at it.
pub(super) fn unpack(
    root: &mut json::Root,
    buffers: &mut Vec<Vec<u8>>,
    (name, held): (&str, &mut Reservation),
) -> Result<(), Problem> {
    for v in 0..root.buffer_views.len() {
        let place = format!("bufferViews[{v}]");
        let Some(stream) = stream_of(&root.buffer_views[v], &place)? else {
            continue;
        };
        let bytes = stream.count.saturating_mul(stream.stride);
        hold(held, name, "the decoded meshopt data", bytes as u64)?;
        let decoded = decode_view(buffers, &stream)
            .map_err(|e| format!("{place}: its meshopt data cannot be decoded ({e})"))?;
        let view = &mut root.buffer_views[v];
        view.buffer = json::Index::new(buffers.len() as u32);
        view.byte_offset = None;
        view.byte_length = USize64(decoded.len() as u64);
        push_buffer(root, buffers, decoded);
    }
    Ok(())
}

/// The view's meshopt extension, if it has one.
fn stream_of(view: &json::buffer::View, place: &str) -> Result<Option<Stream>, Problem> {
    let Some((ext_name, ext)) = view.extensions.as_ref().and_then(|e| {
        NAMES
            .iter()
            .find_map(|n| e.others.get(*n).map(|value| (*n, value)))
    }) else {
        return Ok(None);
    };
    let bad = |what: &str| format!("{place}: its {ext_name} object {what}");
    let number = |key: &str, default: Option<u64>| {
        ext.get(key)
            .map(|v| v.as_u64())
            .unwrap_or(default)
            .and_then(|n| usize::try_from(n).ok())
            .ok_or_else(|| bad(&format!("has no valid {key}")))
    };
    let text = |key: &str, default: &str| {
        ext.get(key)
            .map_or(Some(default), Value::as_str)
            .map(str::to_owned)
            .ok_or_else(|| bad(&format!("has no valid {key}")))
    };
    let mode = Mode::parse(&text("mode", "")?).ok_or_else(|| bad("names no known mode"))?;
    Ok(Some(Stream {
        buffer: number("buffer", None)?,
        offset: number("byteOffset", Some(0))?,
        length: number("byteLength", None)?,
        stride: number("byteStride", None)?,
        count: number("count", None)?,
        mode,
        filter: text("filter", "NONE")?,
    }))
}

/// The stream's decoded bytes: `count` elements of `stride` bytes.
fn decode_view(buffers: &[Vec<u8>], s: &Stream) -> Result<Vec<u8>, String> {
    let source = buffers
        .get(s.buffer)
        .and_then(|b| b.get(s.offset..s.offset.checked_add(s.length)?))
        .ok_or("its bytes are not inside their buffer")?;
    let mut data = decode(s.mode, s.count, s.stride, source).map_err(|e| e.to_string())?;
    let filter = match (s.mode, Filter::parse(&s.filter)) {
        (_, Some(Filter::None)) => Filter::None,
        (Mode::Attributes, Some(filter)) => filter,
        _ => {
            return Err(format!(
                "the filter '{}' is not one relief reads here",
                relief_core::sanitize::clean(&s.filter)
            ));
        }
    };
    apply_filter(filter, &mut data, s.stride).map_err(|e| e.to_string())?;
    Ok(data)
}
