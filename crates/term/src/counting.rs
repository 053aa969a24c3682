//! A writer that counts what passes through it: bytes and write calls.

use std::io::{self, Write};

/// Passes writes to `inner`, counting bytes and `write` calls.
#[derive(Debug, Default)]
pub struct CountingWriter<W> {
    pub inner: W,
    pub bytes: u64,
    pub writes: u64,
}

impl<W> CountingWriter<W> {
    pub fn new(inner: W) -> Self {
        CountingWriter {
            inner,
            bytes: 0,
            writes: 0,
        }
    }
}

impl<W: Write> Write for CountingWriter<W> {
    fn write(&mut self, data: &[u8]) -> io::Result<usize> {
        let n = self.inner.write(data)?;
        self.bytes += n as u64;
        self.writes += 1;
        Ok(n)
    }

    fn flush(&mut self) -> io::Result<()> {
        self.inner.flush()
    }
}
