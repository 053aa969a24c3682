//! Reading a stream front to back: every read checked against its end.

use super::error::DecodeError;

/// The unread part of a stream.
pub(super) struct Cursor<'a> {
    rest: &'a [u8],
}

impl<'a> Cursor<'a> {
    pub fn new(bytes: &'a [u8]) -> Self {
        Self { rest: bytes }
    }

    pub fn byte(&mut self) -> Result<u8, DecodeError> {
        let (&first, rest) = self.rest.split_first().ok_or(DecodeError::Short)?;
        self.rest = rest;
        Ok(first)
    }

    /// The next `n` bytes.
    pub fn take(&mut self, n: usize) -> Result<&'a [u8], DecodeError> {
        let (taken, rest) = self.rest.split_at_checked(n).ok_or(DecodeError::Short)?;
        self.rest = rest;
        Ok(taken)
    }

    /// An unsigned LEB128 number of one to five bytes, its bits past the
    /// 32nd dropped (the specification's "varint-7").
    pub fn varint(&mut self) -> Result<u32, DecodeError> {
        let mut value = 0u32;
        for k in 0..5 {
            let b = self.byte()?;
            value |= u32::from(b & 0x7f) << (7 * k);
            if b & 0x80 == 0 {
                return Ok(value);
            }
        }
        Err(DecodeError::LongIndex)
    }

    /// Done: a stream must hold nothing between its data and its tail.
    pub fn finish(self) -> Result<(), DecodeError> {
        match self.rest.len() {
            0 => Ok(()),
            n => Err(DecodeError::LeftOver(n)),
        }
    }
}
