//! relief's meshopt decoder (`relief_scene::gltf::meshopt`), written from
//! the specifications, against the streams of tests/data/meshopt, which
//! `tools/meshopt-streams` made with the meshoptimizer-rs encoders: each
//! stream decodes to its raw bytes exactly, each filter's output follows
//! the specification's formula and the encoders' own decoding within a
//! unit, the specification's examples decode as it says, and cut, padded
//! or mutated streams are refused without a panic.

use std::path::PathBuf;

use proptest::prelude::*;
use relief_scene::gltf::meshopt::{DecodeError, Filter, Mode, apply_filter, decode};

/// One committed stream and what it decodes to.
pub(super) struct Committed {
    pub name: String,
    pub mode_name: String,
    pub filter_name: String,
    pub mode: Mode,
    pub filter: Filter,
    pub count: usize,
    pub stride: usize,
    pub stream: Vec<u8>,
    /// The codec's output, before the filter.
    pub raw: Vec<u8>,
    /// The encoders' library's filter output, for a filtered stream.
    pub filtered: Option<Vec<u8>>,
}

fn folder() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/meshopt")
}

fn read(name: &str) -> Vec<u8> {
    std::fs::read(folder().join(name)).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// Every stream `streams.txt` lists.
pub(super) fn committed() -> Vec<Committed> {
    let list = String::from_utf8(read("streams.txt")).unwrap();
    let lines = list
        .lines()
        .filter(|l| !l.starts_with('#') && !l.is_empty());
    lines.map(committed_line).collect()
}

/// The committed stream of that name.
pub(super) fn named(name: &str) -> Committed {
    committed().into_iter().find(|c| c.name == name).unwrap()
}

/// A line of `streams.txt`: name, mode, filter, count, stride, raw.
fn committed_line(line: &str) -> Committed {
    let f: Vec<&str> = line.split_whitespace().collect();
    let [name, mode, filter, count, stride, raw] = f[..] else {
        panic!("streams.txt: {line}");
    };
    let filtered = (filter != "NONE").then(|| read(&format!("{name}.out")));
    Committed {
        name: name.into(),
        mode_name: mode.into(),
        filter_name: filter.into(),
        mode: Mode::parse(mode).unwrap(),
        filter: Filter::parse(filter).unwrap(),
        count: count.parse().unwrap(),
        stride: stride.parse().unwrap(),
        stream: read(&format!("{name}.bin")),
        raw: read(&format!("{raw}.raw")),
        filtered,
    }
}

fn decode_committed(c: &Committed, stream: &[u8]) -> Result<Vec<u8>, DecodeError> {
    decode(c.mode, c.count, c.stride, stream)
}

#[test]
fn every_committed_stream_decodes_to_its_raw_bytes() {
    let all = committed();
    assert!(all.len() >= 30, "{}", all.len());
    for c in &all {
        let decoded = decode_committed(c, &c.stream).unwrap_or_else(|e| panic!("{}: {e}", c.name));
        assert!(decoded == c.raw, "{}", c.name);
    }
}

/// Stride 2 keeps each index's low 16 bits.
#[test]
fn narrow_indices_wrap_to_16_bits() {
    for name in ["grid_indices32", "scattered_sequence32"] {
        let c = named(name);
        let narrow = decode(c.mode, c.count, 2, &c.stream).unwrap();
        let low: Vec<u8> = c.raw.chunks(4).flat_map(|w| [w[0], w[1]]).collect();
        assert!(narrow == low, "{name}");
    }
}

/// The components of one element: signed or unsigned, 1 or 2 bytes each.
fn components(element: &[u8], signed: bool) -> Vec<i64> {
    match element.len() {
        4 if signed => element.iter().map(|&b| i64::from(b as i8)).collect(),
        4 => element.iter().map(|&b| i64::from(b)).collect(),
        _ => element
            .chunks(2)
            .map(|h| u16::from_le_bytes([h[0], h[1]]))
            .map(|h| {
                if signed {
                    i64::from(h as i16)
                } else {
                    i64::from(h)
                }
            })
            .collect(),
    }
}

/// The specification's filter formula for one element (Appendix B), in
/// f64: what relief's f32 results must match to within one unit.
fn formula(filter: Filter, input: &[u8]) -> Vec<f64> {
    match filter {
        Filter::Octahedral => {
            let v = components(input, true);
            let max = if input.len() == 4 { 127.0 } else { 32767.0 };
            let one = v[2] as f64;
            let (mut x, mut y) = (v[0] as f64 / one, v[1] as f64 / one);
            let z = 1.0 - x.abs() - y.abs();
            let t = z.min(0.0);
            x -= t.copysign(x);
            y -= t.copysign(y);
            let l = (x * x + y * y + z * z).sqrt();
            vec![
                (x / l * max).round(),
                (y / l * max).round(),
                (z / l * max).round(),
                v[3] as f64,
            ]
        }
        Filter::Quaternion => {
            let v = components(input, true);
            let one = (v[3] | 3) as f64;
            let [x, y, z] = [0, 1, 2].map(|k| v[k] as f64 / one / 2f64.sqrt());
            let w = (1.0 - x * x - y * y - z * z).max(0.0).sqrt();
            let m = (v[3] & 3) as usize;
            let mut out = vec![0.0; 4];
            for (k, c) in [w, x, y, z].into_iter().enumerate() {
                out[(m + k) % 4] = (c * 32767.0).round();
            }
            out
        }
        Filter::Exponential => input
            .chunks(4)
            .map(|w| {
                let v = i32::from_le_bytes([w[0], w[1], w[2], w[3]]);
                (2f64.powi(v >> 24) * f64::from((v << 8) >> 8)) as f32 as f64
            })
            .collect(),
        Filter::Color => color_formula(input),
        Filter::None => unreachable!(),
    }
}

fn color_formula(input: &[u8]) -> Vec<f64> {
    let u = components(input, false);
    let s = components(input, true);
    let max = if input.len() == 4 { 255.0 } else { 65535.0 };
    let msb = 63 - (u[3] as u64).leading_zeros() as i64;
    let scale = (1i64 << (msb + 1)) - 1;
    let (y, co, cg) = (u[0], s[1], s[2]);
    let a = u[3] & (scale >> 1);
    let a = (a << 1) | (a & 1);
    let ss = max / scale as f64;
    [y + co - cg, y + cg, y - co - cg, a]
        .map(|c| (c as f64 * ss).round())
        .to_vec()
}

/// An element's filtered values as numbers: components, or floats.
fn values(filter: Filter, element: &[u8]) -> Vec<f64> {
    match filter {
        Filter::Exponential => element
            .chunks(4)
            .map(|w| f64::from(f32::from_le_bytes([w[0], w[1], w[2], w[3]])))
            .collect(),
        Filter::Color => components(element, false)
            .into_iter()
            .map(|c| c as f64)
            .collect(),
        _ => components(element, true)
            .into_iter()
            .map(|c| c as f64)
            .collect(),
    }
}

/// Whether two filtered elements agree: exactly for the exponential
/// filter (the specification asks it), else within one unit.
fn agree(filter: Filter, a: &[f64], b: &[f64]) -> bool {
    let tolerance = if filter == Filter::Exponential {
        0.0
    } else {
        1.0
    };
    a.iter().zip(b).all(|(x, y)| (x - y).abs() <= tolerance)
}

#[test]
fn filters_follow_the_specification_and_the_encoders_decoding() {
    let mut checked = 0;
    for c in committed().iter().filter(|c| c.filter != Filter::None) {
        let mut data = c.raw.clone();
        apply_filter(c.filter, &mut data, c.stride).unwrap();
        let theirs = c.filtered.as_ref().unwrap();
        let elements = data.chunks(c.stride).zip(c.raw.chunks(c.stride));
        for (k, ((ours, input), theirs)) in elements.zip(theirs.chunks(c.stride)).enumerate() {
            let ours = values(c.filter, ours);
            let spec = formula(c.filter, input);
            assert!(
                agree(c.filter, &ours, &spec),
                "{} {k}: {ours:?} {spec:?}",
                c.name
            );
            let theirs = values(c.filter, theirs);
            assert!(
                agree(c.filter, &ours, &theirs),
                "{} {k}: {ours:?} {theirs:?}",
                c.name
            );
            checked += 1;
        }
    }
    assert!(checked > 3000, "{checked}");
}

/// A filter refuses a stride it does not take.
#[test]
fn filters_refuse_other_strides() {
    let mut data = vec![0; 48];
    for (filter, stride) in [
        (Filter::Octahedral, 12),
        (Filter::Quaternion, 4),
        (Filter::Color, 16),
        (Filter::Exponential, 6),
    ] {
        let e = apply_filter(filter, &mut data, stride).unwrap_err();
        assert!(matches!(e, DecodeError::Stride { .. }), "{filter:?}: {e}");
    }
}

/// A vertex stream of 16 elements of 4 bytes: `block` is its one
/// attribute block, then the tail: padding, an all-zero baseline and, in
/// version 1, `channel_modes`.
fn vertex_stream(version: u8, block: &[u8], channel_modes: &[u8]) -> Vec<u8> {
    let tail = 4 + channel_modes.len();
    let mut s = vec![0xa0 + version];
    s.extend(block);
    s.resize(s.len() + [32, 24][usize::from(version)] - tail, 0);
    s.extend([0; 4]);
    s.extend(channel_modes);
    s
}

/// Appendix A's example: ten bytes holding 16 four-bit deltas, two of
/// them sentinels whose bytes follow.
const EXAMPLE_GROUP: [u8; 10] = [0x17, 0x5f, 0xf0, 0xbc, 0x77, 0xa9, 0x21, 0x00, 0x34, 0xb5];
const EXAMPLE_DELTAS: [i32; 16] = [-1, -4, -3, 26, -91, 0, -6, 6, -4, -4, 5, -5, 1, -1, 0, 0];

/// The first byte of each element: the running sum of `deltas` (mod 256).
fn running_sum(deltas: &[i32]) -> Vec<u8> {
    let mut value = 0u8;
    deltas
        .iter()
        .map(|&d| {
            value = value.wrapping_add(d as u8);
            value
        })
        .collect()
}

fn first_bytes(decoded: &[u8]) -> Vec<u8> {
    decoded.chunks(4).map(|e| e[0]).collect()
}

#[test]
fn the_specifications_delta_example_decodes_as_it_says() {
    let want = running_sum(&EXAMPLE_DELTAS);
    // Version 0: the first byte's group has header 2 (4-bit deltas), the
    // three other bytes header 0 (all zero).
    let mut block = vec![2];
    block.extend(EXAMPLE_GROUP);
    block.extend([0, 0, 0]);
    let decoded = decode(Mode::Attributes, 16, 4, &vertex_stream(0, &block, &[])).unwrap();
    assert_eq!(first_bytes(&decoded), want);
    assert!(decoded.chunks(4).all(|e| e[1..] == [0, 0, 0]));
    // Version 1: control 0 for the first byte (header 3 is 4 bits), 2
    // (nothing stored) for the others.
    let mut block = vec![0b1010_1000, 3];
    block.extend(EXAMPLE_GROUP);
    let decoded = decode(Mode::Attributes, 16, 4, &vertex_stream(1, &block, &[0])).unwrap();
    assert_eq!(first_bytes(&decoded), want);
}

/// Version 1's 1-bit deltas fill a byte from its lowest bit; its literal
/// control stores plain bytes; its channel modes add 16-bit zigzag
/// deltas or XOR rotated words.
#[test]
fn version_1_codings_and_channel_modes_decode_as_specified() {
    // 1-bit deltas: delta 1 is the sentinel, its byte (zigzag 5: -3) follows.
    let block = [0b1010_1000, 1, 0b0000_0010, 0, 5];
    let decoded = decode(Mode::Attributes, 16, 4, &vertex_stream(1, &block, &[0])).unwrap();
    assert_eq!(
        first_bytes(&decoded),
        running_sum(&[0, -3])
            .into_iter()
            .chain([253; 14])
            .collect::<Vec<_>>()
    );
    // Every byte literal; the first element's deltas only.
    let mut block = vec![0xff];
    for first in [0x03, 0x01, 0x01, 0x00] {
        block.push(first);
        block.extend([0; 15]);
    }
    // Two 16-bit halves: 0x0103 is zigzag for -0x82, 0x0001 for -1.
    let halves = decode(Mode::Attributes, 16, 4, &vertex_stream(1, &block, &[0x01])).unwrap();
    let want = [
        (0u16.wrapping_sub(0x82)).to_le_bytes(),
        0xffffu16.to_le_bytes(),
    ]
    .concat();
    assert!(halves.chunks(4).all(|e| e == want), "{:?}", &halves[..4]);
    // One XOR word: the stream holds rotate(v ^ previous, 5), the
    // appendix's left rotation, so it decodes rotated right.
    let xor = decode(Mode::Attributes, 16, 4, &vertex_stream(1, &block, &[0x52])).unwrap();
    let want = 0x0001_0103u32.rotate_right(5).to_le_bytes();
    assert!(xor.chunks(4).all(|e| e == want), "{:?}", &xor[..4]);
    for bad in [0x03, 0x11, 0x0f] {
        let e = decode(Mode::Attributes, 16, 4, &vertex_stream(1, &block, &[bad])).unwrap_err();
        assert_eq!(e, DecodeError::ChannelMode(bad));
    }
}

/// A triangle stream: its codes, its extra data, its 16-byte table.
fn triangle_stream(codes: &[u8], data: &[u8], table: [u8; 16]) -> Vec<u8> {
    [&[0xe1][..], codes, data, &table].concat()
}

fn words(bytes: &[u8]) -> Vec<u32> {
    bytes
        .chunks(4)
        .map(|w| u32::from_le_bytes([w[0], w[1], w[2], w[3]]))
        .collect()
}

/// Each kind of triangle code, worked by hand from Appendix A: a table
/// triangle of three fresh indices, a recent edge with the next index, with
/// `last + 1` and `last - 1`, with a recent vertex, with an explicit
/// index; a restart of the fresh indices; explicit and recent corners.
#[test]
fn every_kind_of_triangle_code_decodes_as_specified() {
    let codes = [0xf0, 0x00, 0x1e, 0x0d, 0x02, 0x0f, 0xfe, 0xff];
    let data = [10, 0x00, 0x1f, 3, 2];
    let stream = triangle_stream(&codes, &data, [0; 16]);
    let decoded = decode(Mode::Triangles, 24, 4, &stream).unwrap();
    let want = [
        0, 1, 2, 0, 2, 3, 3, 2, 1, 3, 1, 0, 3, 0, 3, 3, 3, 5, 0, 1, 2, 3, 2, 4,
    ];
    assert_eq!(words(&decoded), want);
    // An edge or vertex never seen, a table against the rules, data left over.
    let unseen = triangle_stream(&[0x00], &[], [0; 16]);
    assert_eq!(
        decode(Mode::Triangles, 3, 4, &unseen),
        Err(DecodeError::Unseen)
    );
    let bad = triangle_stream(&[0xf0], &[], [0x20; 16]);
    assert_eq!(
        decode(Mode::Triangles, 3, 4, &bad),
        Err(DecodeError::CodeTable)
    );
    let mut table = [0; 16];
    table[0] = 0x20;
    let unseen = triangle_stream(&[0xf0], &[], table);
    assert_eq!(
        decode(Mode::Triangles, 3, 4, &unseen),
        Err(DecodeError::Unseen)
    );
    table[3] = 0x0f;
    let bad = triangle_stream(&[0xf0], &[], table);
    assert_eq!(
        decode(Mode::Triangles, 3, 4, &bad),
        Err(DecodeError::CodeTable)
    );
    let over = triangle_stream(&codes, &[data.as_slice(), &[7]].concat(), [0; 16]);
    assert_eq!(
        decode(Mode::Triangles, 24, 4, &over),
        Err(DecodeError::LeftOver(1))
    );
    assert_eq!(
        decode(Mode::Triangles, 23, 4, &stream),
        Err(DecodeError::Count(23))
    );
}

/// Appendix A's LEB128 examples as index sequence deltas, a five-byte
/// number whose bits past 32 are dropped, and a six-byte one refused.
/// (The appendix's third example, `0xff 0xa0 0x05 => 0x1fd005`, lists the
/// bytes of `0x1fd005` most significant first; as LEB128, the form its
/// text and every encoded stream use, they are `0x85 0xa0 0x7f`.)
#[test]
fn index_sequences_decode_as_specified() {
    let data = [
        0x7f, 0x81, 0x04, 0x85, 0xa0, 0x7f, 0xff, 0xff, 0xff, 0xff, 0x7f, 0x02,
    ];
    let stream = [&[0xd1][..], &data, &[0; 4]].concat();
    let mut baselines = [0u32; 2];
    let want: Vec<u32> = [0x7f, 0x201, 0x1f_d005, 0xffff_ffff, 0x02]
        .iter()
        .map(|&v: &u32| {
            let delta = if v & 2 != 0 { !(v >> 2) } else { v >> 2 };
            let b = &mut baselines[(v & 1) as usize];
            *b = b.wrapping_add(delta);
            *b
        })
        .collect();
    assert_eq!(words(&decode(Mode::Indices, 5, 4, &stream).unwrap()), want);
    let narrow = decode(Mode::Indices, 5, 2, &stream).unwrap();
    let low: Vec<u8> = want
        .iter()
        .flat_map(|&v| (v as u16).to_le_bytes())
        .collect();
    assert_eq!(narrow, low);
    let long = [&[0xd1][..], &[0x80; 5], &[0x01], &[0; 4]].concat();
    assert_eq!(
        decode(Mode::Indices, 1, 4, &long),
        Err(DecodeError::LongIndex)
    );
}

/// A count far beyond what the stream can hold is refused before the
/// output is allocated.
#[test]
fn a_huge_count_is_refused_before_allocating() {
    for name in [
        "walk32_v0",
        "walk32_v1",
        "grid_indices32",
        "scattered_sequence32",
    ] {
        let c = named(name);
        for count in [c.count * 1000, 3 << 40, usize::MAX / 3 * 3] {
            assert!(
                decode(c.mode, count, c.stride, &c.stream).is_err(),
                "{name} {count}"
            );
        }
    }
}

#[test]
fn every_cut_or_lengthened_stream_is_refused() {
    for c in committed() {
        for end in 0..c.stream.len() {
            let cut = decode_committed(&c, &c.stream[..end]);
            assert!(cut.is_err(), "{} cut at {end}", c.name);
        }
        let longer = [c.stream.as_slice(), &[0]].concat();
        assert!(decode_committed(&c, &longer).is_err(), "{}", c.name);
    }
}

/// A small deterministic generator (SplitMix64) for the mutations.
struct Random(u64);

impl Random {
    fn next(&mut self) -> usize {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let z = (self.0 ^ (self.0 >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        let z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        (z ^ (z >> 31)) as usize
    }
}

/// One random change: a byte replaced, inserted or removed, or a stretch
/// cut out.
fn mutate(stream: &mut Vec<u8>, random: &mut Random) {
    let at = random.next() % stream.len().max(1);
    let byte = random.next() as u8;
    match random.next() % 4 {
        0 if !stream.is_empty() => stream[at] = byte,
        1 => stream.insert(at.min(stream.len()), byte),
        2 if !stream.is_empty() => drop(stream.remove(at)),
        _ => drop(stream.drain(at.min(stream.len())..(at + 8).min(stream.len()))),
    }
}

/// Decoding, then filtering, a mutated stream gives an error or output
/// of exactly count × stride bytes; it never panics.
fn decode_anything(c: &Committed, stream: &[u8]) {
    if let Ok(mut data) = decode_committed(c, stream) {
        assert_eq!(data.len(), c.count * c.stride, "{}", c.name);
        let _ = apply_filter(c.filter, &mut data, c.stride);
    }
}

#[test]
fn mutated_streams_never_panic() {
    let mut random = Random(7);
    for c in committed() {
        for _ in 0..300 {
            let mut stream = c.stream.clone();
            for _ in 0..1 + random.next() % 3 {
                mutate(&mut stream, &mut random);
            }
            decode_anything(&c, &stream);
        }
    }
}

proptest! {
    /// Any bytes after any of the codecs' first bytes, at any count and
    /// stride, decode or are refused; none panics.
    #[test]
    fn arbitrary_streams_never_panic(
        header in prop::sample::select(vec![0xa0u8, 0xa1, 0xe1, 0xd1]),
        body in prop::collection::vec(any::<u8>(), 0..400),
        count in 0usize..600,
        stride in prop::sample::select(vec![2usize, 4, 8, 12, 16, 64, 256]),
    ) {
        let stream = [&[header][..], &body].concat();
        for mode in [Mode::Attributes, Mode::Triangles, Mode::Indices] {
            if let Ok(mut data) = decode(mode, count, stride, &stream) {
                prop_assert_eq!(data.len(), count * stride);
                for filter in [Filter::Octahedral, Filter::Quaternion, Filter::Exponential, Filter::Color] {
                    let _ = apply_filter(filter, &mut data, stride);
                }
            }
        }
    }
}
