//! The three codecs and four filters behind one call each, by the names
//! the extension's JSON gives them.

use super::error::DecodeError;
use super::{filter, index, vertex};

/// How a stream is coded: the extension's `mode`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    /// The vertex codec: any elements of a stride of 4–256 bytes.
    Attributes,
    /// The triangle index codec: 16- or 32-bit triangle lists.
    Triangles,
    /// The index sequence codec: any 16- or 32-bit indices.
    Indices,
}

impl Mode {
    /// The mode a file names (`"ATTRIBUTES"`, `"TRIANGLES"`, `"INDICES"`).
    pub fn parse(name: &str) -> Option<Self> {
        match name {
            "ATTRIBUTES" => Some(Self::Attributes),
            "TRIANGLES" => Some(Self::Triangles),
            "INDICES" => Some(Self::Indices),
            _ => None,
        }
    }
}

/// What is done to attributes after decoding: the extension's `filter`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Filter {
    None,
    Octahedral,
    Quaternion,
    Exponential,
    Color,
}

impl Filter {
    /// The filter a file names (`"NONE"`, `"OCTAHEDRAL"`, …).
    pub fn parse(name: &str) -> Option<Self> {
        match name {
            "NONE" => Some(Self::None),
            "OCTAHEDRAL" => Some(Self::Octahedral),
            "QUATERNION" => Some(Self::Quaternion),
            "EXPONENTIAL" => Some(Self::Exponential),
            "COLOR" => Some(Self::Color),
            _ => None,
        }
    }
}

/// Decodes a meshopt stream into `count` elements of `stride` bytes.
///
/// `source` is exactly the stream (the extension's `byteLength` bytes).
/// A stream that is cut, padded, or otherwise not one the specification
/// allows is an error; nothing panics, and nothing larger than
/// `count × stride` bytes (plus 8 KiB of scratch) is allocated, and that
/// only once the stream is long enough to hold `count` elements at all.
pub fn decode(
    mode: Mode,
    count: usize,
    stride: usize,
    source: &[u8],
) -> Result<Vec<u8>, DecodeError> {
    match mode {
        Mode::Attributes => vertex::decode(source, count, stride),
        Mode::Triangles => index::decode_triangles(source, count, stride),
        Mode::Indices => index::decode_sequence(source, count, stride),
    }
}

/// Applies `which` filter in place to decoded attributes of `stride`
/// bytes (`data.len()` a multiple of it); a stride the filter does not
/// take is an error.
pub fn apply_filter(which: Filter, data: &mut [u8], stride: usize) -> Result<(), DecodeError> {
    match which {
        Filter::None => Ok(()),
        Filter::Octahedral => filter::octahedral(data, stride),
        Filter::Quaternion => filter::quaternion(data, stride),
        Filter::Exponential => filter::exponential(data, stride),
        Filter::Color => filter::color(data, stride),
    }
}
