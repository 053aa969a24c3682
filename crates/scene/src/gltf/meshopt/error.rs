//! Why a meshopt stream cannot be decoded: one sentence each, shown inside
//! "bufferViews[N]: its meshopt data cannot be decoded (...)".

use thiserror::Error;

/// A stream, or its count and stride, that the specification does not allow.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum DecodeError {
    #[error("a byte stride of {stride} does not suit {what}")]
    Stride { stride: usize, what: &'static str },
    #[error("a count of {0} indices is not whole triangles")]
    Count(usize),
    #[error("{0} elements of that stride do not fit in memory")]
    Size(usize),
    #[error("its first byte, 0x{0:02x}, names no codec version relief reads")]
    Header(u8),
    #[error("the stream ends before its data does")]
    Short,
    #[error("{0} bytes are left over before its tail")]
    LeftOver(usize),
    #[error("its channel mode 0x{0:02x} is not one of the format's")]
    ChannelMode(u8),
    #[error("its table of triangle codes breaks the format's rules")]
    CodeTable,
    #[error("a triangle names an edge or a vertex not yet seen")]
    Unseen,
    #[error("an index runs past five bytes")]
    LongIndex,
}
