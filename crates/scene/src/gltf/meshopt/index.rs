//! Mode 1, `TRIANGLES` (first byte `0xe1`): a triangle list coded by the
//! edges and vertices of the triangles before it; and mode 2, `INDICES`
//! (`0xd1`): any index sequence as deltas from one of two baselines.
//! Both emit 32-bit indices (stride 4) or their low 16 bits (stride 2).

use super::cursor::Cursor;
use super::error::DecodeError;

/// The triangle codec's table of codes `0xf0`–`0xfd`, at the stream's end.
const TABLE_LEN: usize = 16;
/// The index sequence's tail: four bytes of padding.
const SEQUENCE_TAIL: usize = 4;

/// Decodes `count` indices (whole triangles) of `stride` bytes.
pub(super) fn decode_triangles(
    source: &[u8],
    count: usize,
    stride: usize,
) -> Result<Vec<u8>, DecodeError> {
    let wide = is_wide(stride, "triangles")?;
    if !count.is_multiple_of(3) {
        return Err(DecodeError::Count(count));
    }
    let (codes, data, table) = triangle_parts(source, count / 3)?;
    let mut state = Triangles::new(data);
    let mut out = Indices::with_room(count, wide)?;
    for &code in codes {
        for index in state.triangle(code, table)? {
            out.push(index);
        }
    }
    state.data.finish()?;
    Ok(out.bytes)
}

/// Decodes `count` indices of `stride` bytes.
pub(super) fn decode_sequence(
    source: &[u8],
    count: usize,
    stride: usize,
) -> Result<Vec<u8>, DecodeError> {
    let wide = is_wide(stride, "indices")?;
    let rest = match source.split_first() {
        Some((0xd1, rest)) => rest,
        Some((&other, _)) => return Err(DecodeError::Header(other)),
        None => return Err(DecodeError::Short),
    };
    let body_len = rest.len().checked_sub(SEQUENCE_TAIL);
    let body = &rest[..body_len.ok_or(DecodeError::Short)?];
    // Every index takes at least one byte.
    if body.len() < count {
        return Err(DecodeError::Short);
    }
    let mut data = Cursor::new(body);
    let mut out = Indices::with_room(count, wide)?;
    let mut baselines = [0u32; 2];
    for _ in 0..count {
        // The low bit picks the baseline; the rest is a zigzag delta from it.
        let code = data.varint()?;
        let baseline = &mut baselines[(code & 1) as usize];
        *baseline = baseline.wrapping_add(unzigzag(code >> 1));
        out.push(*baseline);
    }
    data.finish()?;
    Ok(out.bytes)
}

/// Whether indices take 4 bytes (else 2); no other stride is allowed.
fn is_wide(stride: usize, what: &'static str) -> Result<bool, DecodeError> {
    match stride {
        2 => Ok(false),
        4 => Ok(true),
        _ => Err(DecodeError::Stride { stride, what }),
    }
}

/// The triangle stream's codes (one byte a triangle), its extra data and
/// its table, after checking the first byte and the table's rules.
fn triangle_parts(
    source: &[u8],
    triangles: usize,
) -> Result<(&[u8], Cursor<'_>, &[u8; TABLE_LEN]), DecodeError> {
    let rest = match source.split_first() {
        Some((0xe1, rest)) => rest,
        Some((&other, _)) => return Err(DecodeError::Header(other)),
        None => return Err(DecodeError::Short),
    };
    let data_end = rest
        .len()
        .checked_sub(TABLE_LEN)
        .ok_or(DecodeError::Short)?;
    let (body, table) = rest.split_at(data_end);
    let (codes, data) = body.split_at_checked(triangles).ok_or(DecodeError::Short)?;
    let table: &[u8; TABLE_LEN] = table.try_into().map_err(|_| DecodeError::Short)?;
    let nibble_f = |b: &u8| b & 0x0f == 0x0f || b >> 4 == 0x0f;
    if table[14] != 0 || table[15] != 0 || table.iter().any(nibble_f) {
        return Err(DecodeError::CodeTable);
    }
    Ok((codes, Cursor::new(data), table))
}

/// The output indices, 16 or 32 bits each, little-endian.
struct Indices {
    bytes: Vec<u8>,
    wide: bool,
}

impl Indices {
    fn with_room(count: usize, wide: bool) -> Result<Self, DecodeError> {
        let size = count.checked_mul(if wide { 4 } else { 2 });
        Ok(Self {
            bytes: Vec::with_capacity(size.ok_or(DecodeError::Size(count))?),
            wide,
        })
    }

    fn push(&mut self, index: u32) {
        match self.wide {
            true => self.bytes.extend_from_slice(&index.to_le_bytes()),
            false => self.bytes.extend_from_slice(&(index as u16).to_le_bytes()),
        }
    }
}

/// The last 16 values pushed, newest first by age; reading one never
/// pushed is an error (the stream is invalid).
struct Fifo<T> {
    items: [T; 16],
    head: usize,
    filled: usize,
}

impl<T: Copy + Default> Fifo<T> {
    fn new() -> Self {
        Self {
            items: [T::default(); 16],
            head: 0,
            filled: 0,
        }
    }

    fn push(&mut self, item: T) {
        self.items[self.head] = item;
        self.head = (self.head + 1) % 16;
        self.filled = (self.filled + 1).min(16);
    }

    /// The item pushed `age` pushes ago (0: the newest).
    fn get(&self, age: usize) -> Result<T, DecodeError> {
        match age < self.filled {
            true => Ok(self.items[(self.head + 15 - age) % 16]),
            false => Err(DecodeError::Unseen),
        }
    }
}

/// The triangle decoder's state, as the specification names it.
struct Triangles<'a> {
    /// The next index never used yet (the high-water mark).
    next: u32,
    /// The last index coded explicitly or next to the previous one.
    last: u32,
    edges: Fifo<[u32; 2]>,
    vertices: Fifo<u32>,
    data: Cursor<'a>,
}

impl<'a> Triangles<'a> {
    fn new(data: Cursor<'a>) -> Self {
        Self {
            next: 0,
            last: 0,
            edges: Fifo::new(),
            vertices: Fifo::new(),
            data,
        }
    }

    /// The triangle of one code byte: `0xXY` with `X < 0xf` reuses edge X;
    /// `0xfY` starts afresh, from the table (`Y < 0xe`) or the data.
    fn triangle(&mut self, code: u8, table: &[u8; TABLE_LEN]) -> Result<[u32; 3], DecodeError> {
        let (high, low) = (code >> 4, code & 0x0f);
        match (high, low) {
            (0..=14, _) => self.on_edge(usize::from(high), low),
            (_, 0..=13) => self.fresh(table[usize::from(low)], false),
            _ => {
                let byte = self.data.byte()?;
                if byte == 0 {
                    // Restarts the fresh indices (streams joined end to end).
                    self.next = 0;
                }
                self.fresh(byte, low == 0x0f)
            }
        }
    }

    /// A triangle on a recent edge (a, b) and a third vertex c coded by `y`.
    fn on_edge(&mut self, edge: usize, y: u8) -> Result<[u32; 3], DecodeError> {
        let [a, b] = self.edges.get(edge)?;
        let c = match y {
            0 => self.take_next(),
            1..=12 => self.vertices.get(usize::from(y))?,
            13 => self.step_last(u32::wrapping_sub),
            14 => self.step_last(u32::wrapping_add),
            _ => self.explicit()?,
        };
        self.edges.push([c, b]);
        self.edges.push([a, c]);
        if y == 0 || y >= 13 {
            self.vertices.push(c);
        }
        Ok([a, b, c])
    }

    /// A triangle sharing no recent edge: `a` the next fresh index (or
    /// explicit), b and c coded by the nibbles of `zw`: 0 fresh, 1–14 a
    /// recent vertex, 15 explicit.
    fn fresh(&mut self, zw: u8, explicit_a: bool) -> Result<[u32; 3], DecodeError> {
        let a = match explicit_a {
            true => self.explicit()?,
            false => self.take_next(),
        };
        let (z, w) = (zw >> 4, zw & 0x0f);
        let b = self.corner(z)?;
        let c = self.corner(w)?;
        self.edges.push([b, a]);
        self.edges.push([c, b]);
        self.edges.push([a, c]);
        self.vertices.push(a);
        for (index, nibble) in [(b, z), (c, w)] {
            if nibble == 0 || nibble == 0x0f {
                self.vertices.push(index);
            }
        }
        Ok([a, b, c])
    }

    fn corner(&mut self, nibble: u8) -> Result<u32, DecodeError> {
        match nibble {
            0 => Ok(self.take_next()),
            0x0f => self.explicit(),
            _ => self.vertices.get(usize::from(nibble) - 1),
        }
    }

    fn take_next(&mut self) -> u32 {
        let index = self.next;
        self.next = self.next.wrapping_add(1);
        index
    }

    /// `last` one up or down: the index is also the new `last`.
    fn step_last(&mut self, step: fn(u32, u32) -> u32) -> u32 {
        self.last = step(self.last, 1);
        self.last
    }

    /// An index stored in the data as a zigzag delta from `last`.
    fn explicit(&mut self) -> Result<u32, DecodeError> {
        let code = self.data.varint()?;
        self.last = self.last.wrapping_add(unzigzag(code));
        Ok(self.last)
    }
}

/// Zigzag over 32 bits: even codes are 0, 1, 2…, odd ones -1, -2, -3…
/// (as a wrapping addend).
fn unzigzag(code: u32) -> u32 {
    (code >> 1) ^ 0u32.wrapping_sub(code & 1)
}
