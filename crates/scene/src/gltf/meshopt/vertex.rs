//! Mode 0, `ATTRIBUTES`: the vertex codec, version 0 (first byte `0xa0`,
//! the only one of `EXT_meshopt_compression`) and version 1 (`0xa1`, added
//! by `KHR_meshopt_compression`).
//!
//! A stream is its first byte, attribute blocks, then a tail: padding, the
//! baseline element and (version 1) one mode byte per 4-byte channel. Each
//! block holds the deltas of up to 256 elements, byte position by byte
//! position, in groups of 16 whose 2-bit headers give the bit width of
//! their deltas; each element is its predecessor plus its deltas.

use super::cursor::Cursor;
use super::error::DecodeError;

/// Elements per group: one 2-bit header field covers them, and a block
/// always holds whole groups (the last one padded).
const GROUP: usize = 16;
/// A block's elements times the stride never exceed this.
const BLOCK_BYTES: usize = 8192;
/// The fewest bytes from the padding to the stream's end (version 0, 1).
const MIN_TAIL: [usize; 2] = [32, 24];

/// How one byte position of the element is stored within a block.
#[derive(Clone, Copy)]
enum ByteCoding {
    /// Each group's header picks one of these delta widths in bits; 0 is
    /// "all deltas zero", 8 is "16 plain bytes".
    Groups([u8; 4]),
    /// Every delta is zero: nothing is stored (version 1).
    Zero,
    /// Every delta is a plain byte, one per element of the block, without
    /// headers (version 1).
    Literal,
}

/// Version 0 has one coding for every byte.
const VERSION_0: ByteCoding = ByteCoding::Groups([0, 2, 4, 8]);
/// Version 1 gives each byte position a 2-bit control mode per block.
const CONTROL: [ByteCoding; 4] = [
    ByteCoding::Groups([0, 1, 2, 4]),
    ByteCoding::Groups([1, 2, 4, 8]),
    ByteCoding::Zero,
    ByteCoding::Literal,
];

/// How a 4-byte channel adds its deltas to the previous element.
#[derive(Clone, Copy)]
enum Channel {
    /// Four zigzag byte deltas (all of version 0).
    Bytes,
    /// Two zigzag 16-bit little-endian deltas.
    Halves,
    /// One 32-bit XOR with the previous value, stored rotated left by
    /// this many bits (the appendix's `rotate`), so read rotated right.
    Xor(u32),
}

/// Decodes `count` elements of `stride` bytes.
pub(super) fn decode(source: &[u8], count: usize, stride: usize) -> Result<Vec<u8>, DecodeError> {
    if !(4..=256).contains(&stride) || !stride.is_multiple_of(4) {
        return Err(DecodeError::Stride {
            stride,
            what: "attributes",
        });
    }
    let size = count.checked_mul(stride).ok_or(DecodeError::Size(count))?;
    let (&first, rest) = source.split_first().ok_or(DecodeError::Short)?;
    let version = match first {
        0xa0 => 0,
        0xa1 => 1,
        other => return Err(DecodeError::Header(other)),
    };
    let modes = if version == 1 { stride / 4 } else { 0 };
    let tail_len = (stride + modes).max(MIN_TAIL[version]);
    let body_len = rest.len().checked_sub(tail_len).ok_or(DecodeError::Short)?;
    let (body, tail) = rest.split_at(body_len);
    let (baseline, mode_bytes) = tail[tail_len - stride - modes..].split_at(stride);
    let channels = channels(mode_bytes, stride)?;
    let block_elements = ((BLOCK_BYTES / stride) & !(GROUP - 1)).min(256);
    check_room(
        body.len(),
        count,
        block_elements,
        [stride, stride / 4][version],
    )?;

    let mut out = vec![0; size];
    let mut previous = [0u8; 256];
    previous[..stride].copy_from_slice(baseline);
    let mut deltas = vec![0u8; BLOCK_BYTES];
    let mut cursor = Cursor::new(body);
    for block in out.chunks_mut(block_elements * stride) {
        let elements = block.len() / stride;
        let deltas = &mut deltas[..elements.next_multiple_of(GROUP) * stride];
        read_block(&mut cursor, version == 1, elements, deltas)?;
        add_deltas(block, deltas, &channels, &mut previous[..stride]);
    }
    cursor.finish()?;
    Ok(out)
}

/// Each channel's way of adding deltas: version 1 names it in the tail,
/// version 0 (no mode bytes) always adds bytes.
fn channels(mode_bytes: &[u8], stride: usize) -> Result<Vec<Channel>, DecodeError> {
    if mode_bytes.is_empty() {
        return Ok(vec![Channel::Bytes; stride / 4]);
    }
    let channel = |&m: &u8| match (m & 0x0f, m >> 4) {
        (0, 0) => Ok(Channel::Bytes),
        (1, 0) => Ok(Channel::Halves),
        (2, rotation) => Ok(Channel::Xor(u32::from(rotation))),
        _ => Err(DecodeError::ChannelMode(m)),
    };
    mode_bytes.iter().map(channel).collect()
}

/// Refuses, before the output is allocated, a body too short for the
/// blocks `count` elements need: each block takes at least `per_block`
/// bytes (version 0: a header byte per byte position; version 1: the
/// control bytes).
fn check_room(
    body: usize,
    count: usize,
    block_elements: usize,
    per_block: usize,
) -> Result<(), DecodeError> {
    let blocks = count.div_ceil(block_elements);
    match body >= blocks.saturating_mul(per_block) {
        true => Ok(()),
        false => Err(DecodeError::Short),
    }
}

/// One block's deltas, byte position after byte position: `deltas` holds
/// a column per byte of the element, each of the block's `elements`
/// rounded up to whole groups.
fn read_block(
    cursor: &mut Cursor,
    version_1: bool,
    elements: usize,
    deltas: &mut [u8],
) -> Result<(), DecodeError> {
    let column_len = elements.next_multiple_of(GROUP);
    let stride = deltas.len() / column_len;
    let control = match version_1 {
        true => Some(cursor.take(stride / 4)?),
        false => None,
    };
    for (k, column) in deltas.chunks_exact_mut(column_len).enumerate() {
        let coding = match control {
            Some(control) => CONTROL[usize::from(control[k / 4] >> (k % 4 * 2) & 3)],
            None => VERSION_0,
        };
        read_column(cursor, coding, elements, column)?;
    }
    Ok(())
}

/// The deltas of one byte position within a block of `elements`.
fn read_column(
    cursor: &mut Cursor,
    coding: ByteCoding,
    elements: usize,
    column: &mut [u8],
) -> Result<(), DecodeError> {
    match coding {
        ByteCoding::Zero => column.fill(0),
        // One byte per element: the padding of the last group is not stored.
        ByteCoding::Literal => column[..elements].copy_from_slice(cursor.take(elements)?),
        ByteCoding::Groups(widths) => {
            let headers = cursor.take((column.len() / GROUP).div_ceil(4))?;
            for (g, group) in column.chunks_exact_mut(GROUP).enumerate() {
                let width = widths[usize::from(headers[g / 4] >> (g % 4 * 2) & 3)];
                read_group(cursor, width, group)?;
            }
        }
    }
    Ok(())
}

/// Sixteen deltas of `width` bits.
fn read_group(cursor: &mut Cursor, width: u8, group: &mut [u8]) -> Result<(), DecodeError> {
    match width {
        0 => group.fill(0),
        1 => read_packed::<1>(cursor, group)?,
        2 => read_packed::<2>(cursor, group)?,
        4 => read_packed::<4>(cursor, group)?,
        _ => group.copy_from_slice(cursor.take(GROUP)?),
    }
    Ok(())
}

/// Sixteen packed deltas of `W` bits; a delta of all ones (the sentinel)
/// stands for a whole byte stored after the group's packed bits. 1-bit
/// deltas fill a byte from its lowest bit, 2- and 4-bit ones from its
/// highest.
fn read_packed<const W: u8>(cursor: &mut Cursor, group: &mut [u8]) -> Result<(), DecodeError> {
    let per_byte = usize::from(8 / W);
    let sentinel = (1u8 << W) - 1;
    let packed = cursor.take(GROUP / per_byte)?;
    for (j, delta) in group.iter_mut().enumerate() {
        let slot = (j % per_byte) as u8;
        let shift = if W == 1 { slot } else { 8 - W * (slot + 1) };
        let value = (packed[j / per_byte] >> shift) & sentinel;
        *delta = if value == sentinel {
            cursor.byte()?
        } else {
            value
        };
    }
    Ok(())
}

/// Writes the block's elements: each is the one before it (the baseline
/// for the stream's first) plus its deltas, channel by channel.
fn add_deltas(block: &mut [u8], deltas: &[u8], channels: &[Channel], previous: &mut [u8]) {
    let stride = previous.len();
    let column_len = deltas.len() / stride;
    for (i, element) in block.chunks_exact_mut(stride).enumerate() {
        for (c, &channel) in channels.iter().enumerate() {
            let at = 4 * c;
            let delta: [u8; 4] = std::array::from_fn(|b| deltas[(at + b) * column_len + i]);
            let before = &mut previous[at..at + 4];
            let value = next_value(channel, [before[0], before[1], before[2], before[3]], delta);
            before.copy_from_slice(&value);
            element[at..at + 4].copy_from_slice(&value);
        }
    }
}

/// A channel's value from the one before it and its deltas.
fn next_value(channel: Channel, before: [u8; 4], delta: [u8; 4]) -> [u8; 4] {
    match channel {
        Channel::Bytes => std::array::from_fn(|b| before[b].wrapping_add(unzigzag_8(delta[b]))),
        Channel::Halves => {
            let half = |k: usize| {
                let old = u16::from_le_bytes([before[k], before[k + 1]]);
                old.wrapping_add(unzigzag_16(u16::from_le_bytes([delta[k], delta[k + 1]])))
            };
            let [a, b] = half(0).to_le_bytes();
            let [c, d] = half(2).to_le_bytes();
            [a, b, c, d]
        }
        Channel::Xor(rotation) => {
            let xor = u32::from_le_bytes(delta).rotate_right(rotation);
            (u32::from_le_bytes(before) ^ xor).to_le_bytes()
        }
    }
}

/// Zigzag: even codes are 0, 1, 2…, odd ones -1, -2, -3…
fn unzigzag_8(v: u8) -> u8 {
    (v >> 1) ^ 0u8.wrapping_sub(v & 1)
}

fn unzigzag_16(v: u16) -> u16 {
    (v >> 1) ^ 0u16.wrapping_sub(v & 1)
}
