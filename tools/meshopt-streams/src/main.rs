//! Writes into the folder it is given (tests/data/meshopt) the meshopt
//! streams the decoder tests read, each made by the meshoptimizer-rs
//! encoders: `NAME.bin` the stream, `RAW.raw` the bytes its codec decodes
//! to (shared by the streams of one buffer), `NAME.out` (filtered streams
//! only) the bytes after the filter, and `streams.txt`, one line per
//! stream: name, mode, filter, count, stride, raw.
//!
//! The octahedron's streams are those of tests/inputs/models_gltf_meshopt.rs;
//! the others reach what the octahedron does not: several blocks, every
//! delta width and mode of both vertex codec versions, 16- and 32-bit
//! indices, and each filter at several precisions.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use meshoptimizer_rs::codec::{self, ExpMode, IndexEncoding, VertexEncoding};
use meshoptimizer_rs::{Limits, Workspace};

#[path = "../../../tests/inputs/octahedron.rs"]
mod octahedron;
use octahedron::{FACES, POINTS, uv};

/// One written stream.
struct Stream {
    name: String,
    mode: &'static str,
    filter: &'static str,
    count: usize,
    stride: usize,
    encoded: Vec<u8>,
    /// What the codec decodes the stream to, before any filter.
    raw: Vec<u8>,
    /// After the filter, for a filtered stream.
    filtered: Option<Vec<u8>>,
}

fn main() {
    let dir = PathBuf::from(std::env::args().nth(1).expect("usage: meshopt-streams DIR"));
    std::fs::create_dir_all(&dir).unwrap();
    let mut streams = octahedron_streams();
    streams.extend(vertex_streams());
    streams.extend(index_streams());
    streams.extend(filter_streams());
    write_all(&dir, &streams);
}

fn work() -> Workspace {
    Workspace::new(Limits::default())
}

fn floats(v: &[f32]) -> Vec<u8> {
    v.iter().flat_map(|f| f.to_le_bytes()).collect()
}

/// Attributes by the vertex codec (`version`, `level`), checked to decode
/// back to themselves.
fn attributes(name: &str, raw: Vec<u8>, stride: usize, version: u8, level: u8) -> Stream {
    let count = raw.len() / stride;
    let encoding = VertexEncoding::new(version, level).unwrap();
    let encoded = codec::encode_vertex_buffer(&raw, count, stride, encoding, &mut work()).unwrap();
    let back = codec::decode_vertex_buffer(count, stride, &encoded, &mut work()).unwrap();
    assert_eq!(back, raw, "{name}");
    Stream {
        name: name.into(),
        mode: "ATTRIBUTES",
        filter: "NONE",
        count,
        stride,
        encoded,
        raw,
        filtered: None,
    }
}

/// The octahedron's positions, octahedral normals (8 bits, stride 4) and
/// texture coordinates by both vertex codec versions, and its indices.
fn octahedron_streams() -> Vec<Stream> {
    let flat: Vec<f32> = POINTS.iter().flatten().copied().collect();
    let with_w: Vec<f32> = POINTS
        .iter()
        .flat_map(|p| [p[0], p[1], p[2], 0.0])
        .collect();
    let normals = codec::encode_filter_oct(POINTS.len(), 4, 8, &with_w, &mut work()).unwrap();
    let uvs: Vec<f32> = POINTS.iter().flat_map(|&p| uv(p)).collect();
    let mut out = Vec::new();
    for version in [0, 1] {
        out.push(attributes(
            &format!("octahedron_positions_v{version}"),
            floats(&flat),
            12,
            version,
            2,
        ));
        let mut n = attributes(
            &format!("octahedron_normals_v{version}"),
            normals.clone(),
            4,
            version,
            2,
        );
        filter(&mut n, "OCTAHEDRAL");
        out.push(n);
        out.push(attributes(
            &format!("octahedron_uvs_v{version}"),
            floats(&uvs),
            8,
            version,
            2,
        ));
    }
    let indices: Vec<u32> = FACES.iter().flatten().copied().collect();
    out.push(triangles("octahedron_indices", &indices, 2));
    out
}

/// A small deterministic generator (SplitMix64).
struct Random(u64);

impl Random {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in [-1, 1).
    fn signed(&mut self) -> f32 {
        (self.next() >> 40) as f32 / (1u64 << 23) as f32 - 1.0
    }

    /// Uniform in [-amplitude, amplitude].
    fn step(&mut self, amplitude: u32) -> i32 {
        (self.next() % (2 * u64::from(amplitude) + 1)) as i32 - amplitude as i32
    }
}

/// How far a byte moves from one element to the next in element `i`'s
/// group: a schedule that cycles through every delta width, shifted per
/// byte position so that each block mixes them.
fn amplitude(i: usize, position: usize) -> u32 {
    [0, 1, 2, 6, 40, 255, 0, 3][(i / 16 + position) % 8]
}

/// Elements of `stride` bytes: float coordinates walking at changing
/// speeds, two 16-bit counters, a constant float, random bytes, a word
/// whose middle bits alone change, and byte walks whose steps cycle
/// through every width.
fn varied(count: usize, stride: usize, seed: u64) -> Vec<u8> {
    let mut random = Random(seed);
    let mut position = [0f32; 3];
    let mut walks = vec![0u8; stride];
    let mut out = Vec::with_capacity(count * stride);
    for i in 0..count {
        let speed = [0.0, 1e-4, 1e-2, 1.0][(i / 32) % 4];
        for p in &mut position {
            *p += random.signed() * speed;
        }
        out.extend(floats(&position));
        let counters = [(i * 3) as u16, (i as u16).wrapping_mul(257) ^ 0x5a5a];
        out.extend(counters.iter().flat_map(|c| c.to_le_bytes()));
        out.extend(1.0f32.to_le_bytes());
        out.extend((0..4).map(|_| random.next() as u8));
        // Eight random bits at 12..20 across the halves: an XOR rotated by 12
        // holds them in one byte.
        out.extend((0x3f80_0000 | (random.next() as u32 & 0xff) << 12).to_le_bytes());
        for (k, walk) in walks.iter_mut().enumerate().take(stride).skip(28) {
            *walk = walk.wrapping_add(random.step(amplitude(i, k)) as u8);
            out.push(*walk);
        }
    }
    out
}

/// Several blocks of varied elements by both versions, version 1 at three
/// levels (the higher ones try the 16-bit and XOR channel modes); a stride
/// of 100 (80 elements a block); and an empty buffer.
fn vertex_streams() -> Vec<Stream> {
    let walk = varied(600, 32, 1);
    let wide = varied(170, 100, 2);
    let mut out = vec![
        attributes("walk32_v0", walk.clone(), 32, 0, 2),
        attributes("walk32_v1", walk.clone(), 32, 1, 2),
        attributes("walk32_v1_level0", walk.clone(), 32, 1, 0),
        attributes("walk32_v1_level3", walk, 32, 1, 3),
        attributes("wide100_v0", wide.clone(), 100, 0, 2),
        attributes("wide100_v1", wide, 100, 1, 3),
    ];
    for version in [0, 1] {
        out.push(attributes(
            &format!("empty_v{version}"),
            Vec::new(),
            12,
            version,
            2,
        ));
    }
    out
}

/// A triangle list by the index codec (version 1, the specification's):
/// the raw bytes are the crate's decoding, which may rotate each
/// triangle's corners; checked to be the same triangles.
fn triangles(name: &str, indices: &[u32], stride: usize) -> Stream {
    let encoded = codec::encode_index_buffer(indices, IndexEncoding::DEFAULT, &mut work()).unwrap();
    let raw = codec::decode_index_buffer(indices.len(), stride, &encoded, &mut work()).unwrap();
    let back = words(&raw, stride);
    for (t, (a, b)) in indices.chunks(3).zip(back.chunks(3)).enumerate() {
        let a: Vec<u32> = a
            .iter()
            .map(|&v| if stride == 2 { v & 0xffff } else { v })
            .collect();
        let rotated = (0..3).any(|r| (0..3).all(|k| a[k] == b[(k + r) % 3]));
        assert!(rotated, "{name}: triangle {t}: {a:?} {b:?}");
    }
    Stream {
        name: name.into(),
        mode: "TRIANGLES",
        filter: "NONE",
        count: indices.len(),
        stride,
        encoded,
        raw,
        filtered: None,
    }
}

/// Little-endian words of 2 or 4 bytes.
fn words(bytes: &[u8], stride: usize) -> Vec<u32> {
    let word = |c: &[u8]| match stride {
        2 => u32::from(u16::from_le_bytes([c[0], c[1]])),
        _ => u32::from_le_bytes([c[0], c[1], c[2], c[3]]),
    };
    bytes.chunks_exact(stride).map(word).collect()
}

fn index_bytes(indices: &[u32], stride: usize) -> Vec<u8> {
    let bytes = |&v: &u32| match stride {
        2 => (v as u16).to_le_bytes().to_vec(),
        _ => v.to_le_bytes().to_vec(),
    };
    indices.iter().flat_map(bytes).collect()
}

/// A grid of 24 × 24 points as triangles, in order, then a stretch
/// shuffled (explicit and recent-vertex codes) and a stretch reversed.
fn grid(random: &mut Random) -> Vec<u32> {
    let mut tris = Vec::new();
    for y in 0..23u32 {
        for x in 0..23u32 {
            let p = y * 24 + x;
            tris.push([p, p + 1, p + 24]);
            tris.push([p + 1, p + 25, p + 24]);
        }
    }
    for k in (300..500).rev() {
        let j = 300 + (random.next() % (k - 299)) as usize;
        tris.swap(k as usize, j);
    }
    tris[700..800].reverse();
    tris.into_iter().flatten().collect()
}

/// The same triangles with their vertices numbered in order of first
/// use (as a mesh optimised for the codec has them: fresh indices and the
/// table codes), then 20 triangles of three new vertices each.
fn first_use_order(indices: &[u32]) -> Vec<u32> {
    let mut number = std::collections::HashMap::new();
    let mut out: Vec<u32> = indices
        .iter()
        .map(|v| {
            let next = number.len() as u32;
            *number.entry(*v).or_insert(next)
        })
        .collect();
    let first_free = number.len() as u32;
    out.extend(first_free..first_free + 60);
    out
}

/// Triangles with 16- and 32-bit indices (the 32-bit ones far apart and
/// near 2^32, so deltas wrap), and index sequences of both widths.
fn index_streams() -> Vec<Stream> {
    let mut random = Random(3);
    let small = grid(&mut random);
    let mut large = small.clone();
    for (k, v) in large.iter_mut().enumerate() {
        match (k / 300) % 3 {
            0 => *v += 100_000,
            1 => *v = v.wrapping_mul(7_919).wrapping_sub(5_000),
            _ => *v = u32::MAX - *v,
        }
    }
    let mut out = vec![
        triangles("ordered_indices16", &first_use_order(&small), 2),
        triangles("grid_indices16", &small, 2),
        triangles("grid_indices32", &large, 4),
    ];
    // Two interleaved runs (as a strip's), with jumps.
    let strip: Vec<u32> = (0..600u32)
        .map(|i| match i % 2 {
            0 => i / 2 + if i > 300 { 20_000 } else { 0 },
            _ => 40_000 - i / 2,
        })
        .collect();
    // Two interleaved walks below 2^30 (so that any delta is within the
    // codec's ±2^30, whichever baseline the encoder picks), with steps of
    // up to 2^29, 2^20 or 2^6 either way, wrapping at 2^30.
    let mut walks = [5_000u32, 1 << 29];
    let scattered: Vec<u32> = (0..300)
        .map(|i| {
            let step = random.next() as u32 >> [3, 12, 26][i % 3];
            let walk = &mut walks[(i / 2) % 2];
            *walk = match random.next() % 2 {
                0 => walk.wrapping_add(step),
                _ => walk.wrapping_sub(step),
            } & ((1 << 30) - 1);
            *walk
        })
        .collect();
    out.push(sequence("strip_sequence16", &strip, 2));
    out.push(sequence("scattered_sequence32", &scattered, 4));
    out
}

/// An index sequence by the index sequence codec.
fn sequence(name: &str, indices: &[u32], stride: usize) -> Stream {
    let encoded =
        codec::encode_index_sequence(indices, IndexEncoding::DEFAULT, &mut work()).unwrap();
    let raw = index_bytes(indices, stride);
    let back = codec::decode_index_sequence(indices.len(), stride, &encoded, &mut work()).unwrap();
    if back != raw {
        let (a, b) = (words(&back, stride), words(&raw, stride));
        let k = a.iter().zip(&b).position(|(x, y)| x != y).unwrap();
        panic!(
            "{name}: {k}: {:?} {:?}",
            &a[k.saturating_sub(3)..k + 2],
            &b[k.saturating_sub(3)..k + 2]
        );
    }
    Stream {
        name: name.into(),
        mode: "INDICES",
        filter: "NONE",
        count: indices.len(),
        stride,
        encoded,
        raw,
        filtered: None,
    }
}

/// Names the stream's filter and records what the crate's filter decoder
/// makes of its raw bytes.
fn filter(stream: &mut Stream, name: &'static str) {
    let mut data = stream.raw.clone();
    let (n, stride, w) = (stream.count, stream.stride, &mut work());
    match name {
        "OCTAHEDRAL" => codec::decode_filter_oct(&mut data, n, stride, w),
        "QUATERNION" => codec::decode_filter_quat(&mut data, n, stride, w),
        "EXPONENTIAL" => codec::decode_filter_exp(&mut data, n, stride, w),
        _ => codec::decode_filter_color(&mut data, n, stride, w),
    }
    .unwrap();
    stream.filter = name;
    stream.filtered = Some(data);
}

/// `count` random vectors of four floats, normalised over the first
/// `unit` components (3: a direction with w ±1, 4: a quaternion).
fn unit_vectors(random: &mut Random, count: usize, unit: usize) -> Vec<f32> {
    let mut out = Vec::new();
    for i in 0..count {
        let mut v = [
            random.signed(),
            random.signed(),
            random.signed(),
            random.signed(),
        ];
        if i % 7 == 0 {
            // Exactly on an axis, and on the negative hemisphere's edge.
            v = [0.0, 0.0, 0.0, 0.0];
            v[i % unit] = if i % 2 == 0 { 1.0 } else { -1.0 };
        }
        let length = v[..unit]
            .iter()
            .map(|c| c * c)
            .sum::<f32>()
            .sqrt()
            .max(1e-6);
        v[..unit].iter_mut().for_each(|c| *c /= length);
        if unit == 3 {
            v[3] = if i % 3 == 0 { -1.0 } else { 1.0 };
        }
        out.extend(v);
    }
    out
}

/// Each filter at several precisions, its input by the vertex codec.
fn filter_streams() -> Vec<Stream> {
    let mut random = Random(4);
    let mut out = Vec::new();
    let mut add = |name: &str, filter_name, stride, raw: Vec<u8>| {
        let mut s = attributes(name, raw, stride, 1, 2);
        filter(&mut s, filter_name);
        out.push(s);
    };
    let w = &mut work();
    for (name, stride, bits) in [
        ("octahedral8", 4, 8),
        ("octahedral5", 4, 5),
        ("octahedral16", 8, 16),
        ("octahedral11", 8, 11),
    ] {
        let v = unit_vectors(&mut random, 300, 3);
        add(
            name,
            "OCTAHEDRAL",
            stride,
            codec::encode_filter_oct(300, stride, bits, &v, w).unwrap(),
        );
    }
    for (name, bits) in [("quaternion16", 16), ("quaternion9", 9)] {
        let v = unit_vectors(&mut random, 300, 4);
        add(
            name,
            "QUATERNION",
            8,
            codec::encode_filter_quat(300, 8, bits, &v, w).unwrap(),
        );
    }
    let magnitudes: Vec<f32> = (0..600)
        .map(|i| match i % 9 {
            0 => 0.0,
            _ => random.signed() * 10f32.powi((i % 17) - 8),
        })
        .collect();
    let exp = [
        ("exponential_separate", 12, 15, ExpMode::Separate),
        ("exponential_vector", 16, 23, ExpMode::SharedVector),
        ("exponential_component", 8, 10, ExpMode::SharedComponent),
        ("exponential_clamped", 4, 12, ExpMode::Clamped),
    ];
    for (name, stride, bits, mode) in exp {
        let n = 600 * 4 / stride;
        let v = &magnitudes[..n * stride / 4];
        add(
            name,
            "EXPONENTIAL",
            stride,
            codec::encode_filter_exp(n, stride, bits, v, mode, w).unwrap(),
        );
    }
    for (name, stride, bits) in [
        ("color8", 4, 8),
        ("color6", 4, 6),
        ("color16", 8, 16),
        ("color12", 8, 12),
    ] {
        let v: Vec<f32> = (0..1200).map(|_| (random.signed() + 1.0) / 2.0).collect();
        add(
            name,
            "COLOR",
            stride,
            codec::encode_filter_color(300, stride, bits, &v, w).unwrap(),
        );
    }
    out
}

/// Writes every stream's files and the list; equal raw bytes (one buffer
/// by several codec versions) are written once, under the first name.
fn write_all(dir: &Path, streams: &[Stream]) {
    let mut list = String::from(
        "# Written by tools/meshopt-streams: name, mode, filter, count, stride, raw.\n\
         # NAME.bin is the stream, RAW.raw what it decodes to, NAME.out that after the filter.\n",
    );
    let mut raws: Vec<(&[u8], &str)> = Vec::new();
    for s in streams {
        let raw = match raws.iter().find(|(bytes, _)| *bytes == s.raw) {
            Some(&(_, name)) => name,
            None => {
                std::fs::write(dir.join(format!("{}.raw", s.name)), &s.raw).unwrap();
                raws.push((&s.raw, &s.name));
                &s.name
            }
        };
        let (name, mode, filter, count, stride) = (&s.name, s.mode, s.filter, s.count, s.stride);
        writeln!(list, "{name} {mode} {filter} {count} {stride} {raw}").unwrap();
        std::fs::write(dir.join(format!("{name}.bin")), &s.encoded).unwrap();
        if let Some(out) = &s.filtered {
            std::fs::write(dir.join(format!("{name}.out")), out).unwrap();
        }
    }
    std::fs::write(dir.join("streams.txt"), list).unwrap();
}
