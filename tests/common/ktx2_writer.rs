//! KTX2 files of UASTC blocks written byte by byte for the tests, from the
//! KTX 2.0 specification (identifier, header, index, level index, the
//! Data Format Descriptor's basic block) and the UASTC block format (mode
//! 8, a solid colour). Optionally Zstandard-supercompressed, as a frame of
//! raw blocks (RFC 8878 §3.1.1): the container's path without an encoder.
#![allow(dead_code)]

/// «KTX 20»\r\n\x1A\n.
pub const IDENTIFIER: [u8; 12] = [
    0xAB, 0x4B, 0x54, 0x58, 0x20, 0x32, 0x30, 0xBB, 0x0D, 0x0A, 0x1A, 0x0A,
];
/// Where header fields lie: pixelWidth, pixelHeight, levelCount.
pub const WIDTH_AT: usize = 20;
pub const HEIGHT_AT: usize = 24;
pub const LEVEL_COUNT_AT: usize = 40;
/// The first level index entry: byteOffset, byteLength, uncompressedByteLength.
pub const LEVEL_INDEX_AT: usize = 80;
/// Khronos Data Format: colour model UASTC, BT.709 primaries.
const KHR_DF_MODEL_UASTC: u32 = 166;
const KHR_DF_PRIMARIES_BT709: u32 = 1;
const KHR_DF_TRANSFER_LINEAR: u32 = 1;
const KHR_DF_TRANSFER_SRGB: u32 = 2;
/// The UASTC sample's channel: RGB or RGBA.
const UASTC_RGB: u32 = 0;
const UASTC_RGBA: u32 = 3;

/// A 4×4 UASTC block of one colour: mode 8, whose 5-bit code 0x17 fills
/// the first bits (least significant first), then R, G, B, A in 8 bits
/// each; the ETC1 hints after them are left 0 (they only serve ETC1 output).
pub fn uastc_solid(rgba: [u8; 4]) -> [u8; 16] {
    let [r, g, b, a] = rgba.map(u128::from);
    (0x17 | r << 5 | g << 13 | b << 21 | a << 29).to_le_bytes()
}

/// One mip level: its blocks, row by row from the top.
pub struct Level {
    pub blocks: Vec<[u8; 16]>,
}

/// What the file holds.
pub struct Uastc {
    pub width: u32,
    pub height: u32,
    /// Level 0 first (the largest), each half the one before.
    pub levels: Vec<Level>,
    pub srgb: bool,
    pub alpha: bool,
    pub zstd: bool,
}

impl Uastc {
    /// One level of `width × height` texels of these blocks.
    pub fn new(width: u32, height: u32, blocks: Vec<[u8; 16]>) -> Self {
        Uastc {
            width,
            height,
            levels: vec![Level { blocks }],
            srgb: true,
            alpha: false,
            zstd: false,
        }
    }

    /// The KTX2 file.
    pub fn encode(&self) -> Vec<u8> {
        let payloads: Vec<(Vec<u8>, u64)> = self
            .levels
            .iter()
            .map(|l| {
                let raw = l.blocks.concat();
                let len = raw.len() as u64;
                (if self.zstd { zstd_raw(&raw) } else { raw }, len)
            })
            .collect();
        let index_end = LEVEL_INDEX_AT + 24 * payloads.len();
        let dfd = self.dfd();
        let dfd_at = index_end;
        let mut at = dfd_at + dfd.len();
        // Levels are stored smallest first, each aligned to 16 bytes (the
        // block size) when not supercompressed (KTX 2.0 §3.9.7).
        let mut placed = vec![(0u64, 0u64, 0u64); payloads.len()];
        for (k, (data, len)) in payloads.iter().enumerate().rev() {
            at = at.next_multiple_of(if self.zstd { 1 } else { 16 });
            placed[k] = (at as u64, data.len() as u64, *len);
            at += data.len();
        }
        let mut f = IDENTIFIER.to_vec();
        let scheme = if self.zstd { 2 } else { 0 };
        let count = self.levels.len() as u32;
        for v in [0, 1, self.width, self.height, 0, 0, 1, count, scheme] {
            f.extend_from_slice(&v.to_le_bytes());
        }
        for v in [dfd_at as u32, dfd.len() as u32, 0, 0] {
            f.extend_from_slice(&v.to_le_bytes());
        }
        f.extend_from_slice(&[0; 16]); // no supercompression global data
        for (offset, length, inflated) in &placed {
            for v in [offset, length, inflated] {
                f.extend_from_slice(&v.to_le_bytes());
            }
        }
        f.extend_from_slice(&dfd);
        for (k, (data, _)) in payloads.iter().enumerate().rev() {
            f.resize(placed[k].0 as usize, 0);
            f.extend_from_slice(data);
        }
        f
    }

    /// The Data Format Descriptor: its total size, then one basic block of
    /// 24 bytes and one 16-byte sample (128 bits of UASTC).
    fn dfd(&self) -> Vec<u8> {
        let transfer = if self.srgb {
            KHR_DF_TRANSFER_SRGB
        } else {
            KHR_DF_TRANSFER_LINEAR
        };
        let channel = if self.alpha { UASTC_RGBA } else { UASTC_RGB };
        let words = [
            44,
            0,              // vendor 0 (Khronos), descriptor type 0 (basic)
            2 | (40 << 16), // version 2, block size 24 + 16
            KHR_DF_MODEL_UASTC | (KHR_DF_PRIMARIES_BT709 << 8) | (transfer << 16),
            3 | (3 << 8), // texel block 4×4 (each dimension less one)
            16,           // bytesPlane0: a block's bytes
            0,
            (127 << 16) | (channel << 24), // bit offset 0, length 128 (less one)
            0,                             // sample position
            0,                             // sampleLower
            u32::MAX,                      // sampleUpper
        ];
        words.iter().flat_map(|w| w.to_le_bytes()).collect()
    }
}

/// A Zstandard frame of `data` in raw blocks: magic, a single-segment
/// frame header with a 4-byte content size, blocks of at most 128 KiB.
pub fn zstd_raw(data: &[u8]) -> Vec<u8> {
    let mut f = 0xFD2F_B528u32.to_le_bytes().to_vec();
    f.push(0b1010_0000); // content size in 4 bytes, single segment
    f.extend_from_slice(&(data.len() as u32).to_le_bytes());
    let chunks: Vec<&[u8]> = if data.is_empty() {
        vec![&[]]
    } else {
        data.chunks(128 << 10).collect()
    };
    for (i, chunk) in chunks.iter().enumerate() {
        let last = u32::from(i + 1 == chunks.len());
        let header = last | ((chunk.len() as u32) << 3); // block type 0: raw
        f.extend_from_slice(&header.to_le_bytes()[..3]);
        f.extend_from_slice(chunk);
    }
    f
}

/// An 8×8 texture of four solid 4×4 blocks: top left, top right, bottom
/// left, bottom right.
pub fn four_blocks(colours: [[u8; 4]; 4]) -> Uastc {
    Uastc::new(8, 8, colours.map(uastc_solid).to_vec())
}
