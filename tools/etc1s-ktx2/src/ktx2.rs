//! A KTX2 file of BasisLZ (ETC1S) data, from the KTX 2.0 specification:
//! the header and index, the level index, the Data Format Descriptor's
//! basic block, one key/value pair, the BasisLZ global data (§3.12.2),
//! then the levels, smallest first, as Basis Universal writes them.

use crate::basis::Parts;
use crate::etc1s_pictures::Picture;

/// «KTX 20»\r\n\x1A\n.
const IDENTIFIER: [u8; 12] = [
    0xAB, 0x4B, 0x54, 0x58, 0x20, 0x32, 0x30, 0xBB, 0x0D, 0x0A, 0x1A, 0x0A,
];
/// The identifier, the header (9 words) and the index (4 words, 2 longs).
const HEADER_BYTES: usize = 80;
/// One level index entry: byteOffset, byteLength, uncompressedByteLength.
const LEVEL_ENTRY_BYTES: usize = 24;
const SCHEME_BASISLZ: u32 = 1;
/// Khronos Data Format 1.3: version 2 of the basic block; colour model
/// ETC1S, BT.709 primaries, the sRGB transfer function.
const KHR_DF_VERSION: u32 = 2;
const KHR_DF_MODEL_ETC1S: u32 = 163;
const KHR_DF_PRIMARIES_BT709: u32 = 1;
const KHR_DF_TRANSFER_SRGB: u32 = 2;
/// The ETC1S sample channels: the RGB slice, the alpha slice.
const KHR_DF_CHANNEL_ETC1S_RGB: u32 = 0;
const KHR_DF_CHANNEL_ETC1S_AAA: u32 = 15;
const WRITER: &str = "relief tools/etc1s-ktx2: Basis Universal 1.16 (basis-universal 0.3.1)";

fn words(out: &mut Vec<u8>, values: &[u32]) {
    out.extend(values.iter().flat_map(|v| v.to_le_bytes()));
}

/// The whole file.
pub fn write(picture: &Picture, parts: &Parts) -> Vec<u8> {
    let levels = picture.levels as usize;
    let (data, descs) = level_data(parts, levels);
    let dfd = dfd(picture.alpha);
    let kvd = key_value("KTXwriter", WRITER);
    let sgd = global_data(parts, &descs);
    let dfd_at = HEADER_BYTES + LEVEL_ENTRY_BYTES * levels;
    let kvd_at = dfd_at + dfd.len();
    // The global data starts on 8 bytes.
    let sgd_at = (kvd_at + kvd.len()).next_multiple_of(8);
    let mut out = IDENTIFIER.to_vec();
    let size = [picture.width as u32, picture.height as u32];
    // vkFormat undefined, typeSize 1, the size, depth 0, no layers, 1 face.
    words(&mut out, &[0, 1, size[0], size[1], 0, 0, 1]);
    words(&mut out, &[levels as u32, SCHEME_BASISLZ]);
    words(&mut out, &[dfd_at as u32, dfd.len() as u32]);
    words(&mut out, &[kvd_at as u32, kvd.len() as u32]);
    out.extend((sgd_at as u64).to_le_bytes());
    out.extend((sgd.len() as u64).to_le_bytes());
    out.resize(dfd_at, 0);
    out.extend(dfd);
    out.extend(kvd);
    out.resize(sgd_at, 0);
    out.extend(sgd);
    for (k, level) in data.iter().enumerate().rev() {
        let entry = HEADER_BYTES + LEVEL_ENTRY_BYTES * k;
        // uncompressedByteLength is 0 under BasisLZ.
        let index = [out.len() as u64, level.len() as u64, 0];
        let index: Vec<u8> = index.iter().flat_map(|v| v.to_le_bytes()).collect();
        out[entry..entry + LEVEL_ENTRY_BYTES].copy_from_slice(&index);
        out.extend(level);
    }
    out
}

/// Each level's data (its RGB slice, then its alpha slice) and its image
/// description: flags, RGB slice offset and length, alpha slice's.
fn level_data(parts: &Parts, levels: usize) -> (Vec<Vec<u8>>, Vec<[u32; 5]>) {
    let mut data = vec![Vec::new(); levels];
    let mut descs = vec![[0; 5]; levels];
    for slice in &parts.slices {
        let k = slice.level as usize;
        let at = if slice.alpha { 3 } else { 1 };
        descs[k][at] = data[k].len() as u32;
        descs[k][at + 1] = slice.data.len() as u32;
        data[k].extend(slice.data);
    }
    (data, descs)
}

/// The Data Format Descriptor: its length, then the basic block with one
/// 64-bit sample per slice.
fn dfd(alpha: bool) -> Vec<u8> {
    let samples: &[u32] = match alpha {
        true => &[KHR_DF_CHANNEL_ETC1S_RGB, KHR_DF_CHANNEL_ETC1S_AAA],
        false => &[KHR_DF_CHANNEL_ETC1S_RGB],
    };
    let block = 24 + 16 * samples.len() as u32;
    let model = KHR_DF_MODEL_ETC1S | KHR_DF_PRIMARIES_BT709 << 8 | KHR_DF_TRANSFER_SRGB << 16;
    let mut out = Vec::new();
    // vendorId and descriptorType 0; texel blocks of 4×4; bytesPlane all 0
    // (supercompressed).
    words(
        &mut out,
        &[4 + block, 0, KHR_DF_VERSION | block << 16, model],
    );
    words(&mut out, &[3 | 3 << 8, 0, 0]);
    for (i, channel) in samples.iter().enumerate() {
        // bitOffset, bitLength − 1, channel; position 0; lower 0, upper all ones.
        let bit_offset = 64 * i as u32;
        words(
            &mut out,
            &[bit_offset | 63 << 16 | channel << 24, 0, 0, u32::MAX],
        );
    }
    out
}

/// One key/value pair: its length, the key and the value NUL-ended, padded
/// to 4 bytes.
fn key_value(key: &str, value: &str) -> Vec<u8> {
    let mut pair = Vec::new();
    for text in [key, value] {
        pair.extend(text.as_bytes());
        pair.push(0);
    }
    let mut out = (pair.len() as u32).to_le_bytes().to_vec();
    out.extend(pair);
    out.resize(out.len().next_multiple_of(4), 0);
    out
}

/// The BasisLZ global data: the counts and lengths, one image description
/// a level, the codebooks, the tables (no extended data).
fn global_data(parts: &Parts, descs: &[[u32; 5]]) -> Vec<u8> {
    let mut out = Vec::new();
    out.extend(parts.endpoint_count.to_le_bytes());
    out.extend(parts.selector_count.to_le_bytes());
    let lengths = [parts.endpoints, parts.selectors, parts.tables].map(|p| p.len() as u32);
    words(&mut out, &lengths);
    words(&mut out, &[0]);
    for desc in descs {
        words(&mut out, desc);
    }
    out.extend(parts.endpoints);
    out.extend(parts.selectors);
    out.extend(parts.tables);
    out
}
