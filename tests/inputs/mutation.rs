//! Mutation tests: the files of tests/data, damaged the way fuzzers damage
//! them (bit flips, truncation, a chunk repeated, bytes inserted or
//! overwritten), fed to each parser: the texture loader (every format), the
//! XPM reader and the OBJ reader. Whatever the bytes, the answer is a value
//! or an error of one clean line; a panic fails the case (a hang would
//! never finish).
//!
//! The number of cases per parser is `RELIEF_MUTATION_CASES` (default 2000,
//! kept small for CI); run longer with e.g. `RELIEF_MUTATION_CASES=20000`.

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use proptest::prelude::*;
use proptest::sample::Index;
use proptest::test_runner::{Config, FileFailurePersistence};
use relief_scene::obj;
use relief_texture::decode::load::load_texture_from_bytes;
use relief_texture::decode::xpm;

fn data() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data")
}

/// The files of `dirs` (under tests/data) whose names end with one of `exts`.
fn seeds(dirs: &[&str], exts: &[&str]) -> Vec<(String, Vec<u8>)> {
    let mut out = Vec::new();
    for dir in dirs {
        let mut paths: Vec<PathBuf> = std::fs::read_dir(data().join(dir))
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| {
                let name = p.file_name().unwrap().to_string_lossy().to_string();
                exts.iter().any(|e| name.ends_with(e))
            })
            .collect();
        paths.sort();
        for p in paths {
            let name = p.file_name().unwrap().to_string_lossy().to_string();
            out.push((name, std::fs::read(&p).unwrap()));
        }
    }
    assert!(!out.is_empty(), "no seeds in {dirs:?}");
    out
}

fn texture_seeds() -> &'static [(String, Vec<u8>)] {
    static SEEDS: OnceLock<Vec<(String, Vec<u8>)>> = OnceLock::new();
    SEEDS.get_or_init(|| {
        let mut s = seeds(
            &["formats"],
            &[".png", ".bmp", ".pbm", ".pgm", ".ppm", ".tga"],
        );
        // A few PNGs of other kinds: interlaced, 16-bit, palette with
        // transparency, odd sizes.
        let suite = [
            "basi0g16.png",
            "basi3p02.png",
            "basn4a16.png",
            "tbbn3p08.png",
            "s09i3p02.png",
            "g04n2c08.png",
        ];
        for name in suite {
            let bytes = std::fs::read(data().join("pngsuite").join(name)).unwrap();
            s.push((name.to_string(), bytes));
        }
        // KTX2: UASTC written here (plain with alpha, Zstandard, with two
        // levels) and ETC1S made by the Basis Universal encoder.
        s.extend(ktx2_seeds());
        s.extend(seeds(&["ktx2"], &[".ktx2"]));
        s
    })
}

fn ktx2_seeds() -> Vec<(String, Vec<u8>)> {
    use crate::ktx2_writer::{Level, four_blocks, uastc_solid};
    let colours = [
        [255, 0, 0, 255],
        [0, 255, 0, 9],
        [0, 0, 255, 255],
        [1, 2, 3, 4],
    ];
    let mut alpha = four_blocks(colours);
    alpha.alpha = true;
    let mut zstd = four_blocks(colours);
    zstd.zstd = true;
    let mut levels = four_blocks(colours);
    levels.levels.push(Level {
        blocks: vec![uastc_solid([7, 7, 7, 7])],
    });
    [("alpha", alpha), ("zstd", zstd), ("levels", levels)]
        .map(|(name, file)| (format!("{name}.ktx2"), file.encode()))
        .to_vec()
}

fn xpm_seeds() -> &'static [(String, Vec<u8>)] {
    static SEEDS: OnceLock<Vec<(String, Vec<u8>)>> = OnceLock::new();
    SEEDS.get_or_init(|| {
        let mut s = seeds(&["formats", "xpm"], &[".xpm"]);
        s.sort_by_key(|(_, b)| b.len());
        s
    })
}

fn obj_seeds() -> &'static [(String, Vec<u8>)] {
    static SEEDS: OnceLock<Vec<(String, Vec<u8>)>> = OnceLock::new();
    SEEDS.get_or_init(|| seeds(&[".", "obj"], &[".obj"]))
}

/// Bytes that mean something to one of the parsers.
const TOKENS: &[&[u8]] = &[
    b"\0",
    b"\xff",
    b"\x80",
    b"\xef\xbb\xbf",
    b"\n",
    b"\r",
    b" ",
    b"\t",
    b"\"",
    b",",
    b"/",
    b"//",
    b"#",
    b"*/",
    b"/*",
    b"-1",
    b"0",
    b"-0",
    b"65535",
    b"4294967295",
    b"99999999999999999999",
    b"-9223372036854775808",
    b"1e39",
    b"nan",
    b"inf",
    b"f 1 2 3",
    b"f -1 -1 -1 -1",
    b"v 0 0 0 1 1 1",
    b"vt 1",
    b"usemtl",
    b"None",
    b"c ",
    b"#fff",
    b"light goldenrod",
    b"\xe9",
    b"\x1b[2J",
];

#[derive(Clone, Debug)]
enum Mutation {
    FlipBit(Index, u8),
    Overwrite(Index, u8),
    Truncate(Index),
    Duplicate(Index, u16, Index),
    Insert(Index, usize),
    InsertRandom(Index, Vec<u8>),
    Remove(Index, u16),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        4 => (any::<Index>(), 0u8..8).prop_map(|(i, b)| Mutation::FlipBit(i, b)),
        2 => (any::<Index>(), prop_oneof![Just(0u8), Just(0xff), Just(0x7f), Just(0x80), any::<u8>()])
            .prop_map(|(i, v)| Mutation::Overwrite(i, v)),
        1 => any::<Index>().prop_map(Mutation::Truncate),
        1 => (any::<Index>(), 1u16..512, any::<Index>())
            .prop_map(|(a, n, b)| Mutation::Duplicate(a, n, b)),
        2 => (any::<Index>(), 0..TOKENS.len()).prop_map(|(i, t)| Mutation::Insert(i, t)),
        1 => (any::<Index>(), prop::collection::vec(any::<u8>(), 1..16))
            .prop_map(|(i, b)| Mutation::InsertRandom(i, b)),
        1 => (any::<Index>(), 1u16..64).prop_map(|(i, n)| Mutation::Remove(i, n)),
    ]
}

fn apply(bytes: &mut Vec<u8>, m: &Mutation) {
    let len = bytes.len();
    let at = |i: &Index| if len == 0 { 0 } else { i.index(len) };
    match m {
        Mutation::FlipBit(i, bit) if len > 0 => bytes[at(i)] ^= 1 << bit,
        Mutation::Overwrite(i, v) if len > 0 => bytes[at(i)] = *v,
        Mutation::Truncate(i) => bytes.truncate(at(i)),
        Mutation::Duplicate(from, n, to) if len > 0 => {
            let start = at(from);
            let end = (start + *n as usize).min(len);
            let chunk = bytes[start..end].to_vec();
            let dest = at(to);
            bytes.splice(dest..dest, chunk);
        }
        Mutation::Insert(i, t) => {
            let dest = at(i);
            bytes.splice(dest..dest, TOKENS[*t].iter().copied());
        }
        Mutation::InsertRandom(i, b) => {
            let dest = at(i);
            bytes.splice(dest..dest, b.iter().copied());
        }
        Mutation::Remove(i, n) if len > 0 => {
            let start = at(i);
            let end = (start + *n as usize).min(len);
            bytes.drain(start..end);
        }
        _ => {}
    }
}

/// A seed (by index) and the mutations applied to it in order.
fn mutant(seeds: &'static [(String, Vec<u8>)]) -> impl Strategy<Value = (String, Vec<u8>)> {
    (0..seeds.len(), prop::collection::vec(mutation(), 1..6)).prop_map(move |(k, ms)| {
        let (name, seed) = &seeds[k];
        let mut bytes = seed.clone();
        for m in &ms {
            apply(&mut bytes, m);
        }
        (name.clone(), bytes)
    })
}

fn cases() -> u32 {
    std::env::var("RELIEF_MUTATION_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(2000)
}

fn config() -> Config {
    Config {
        cases: cases(),
        failure_persistence: Some(Box::new(FileFailurePersistence::WithSource(
            "proptest-regressions",
        ))),
        ..Config::default()
    }
}

/// An error message as every parser must give it: one line, no control
/// characters, not empty, not a wall of text.
fn check_message(text: &str) -> Result<(), TestCaseError> {
    prop_assert!(!text.trim().is_empty(), "empty message");
    prop_assert!(
        !text.chars().any(|c| c.is_control()),
        "control character in {:?}",
        text
    );
    prop_assert!(
        text.chars().count() <= 400,
        "{} chars: {:?}",
        text.len(),
        text
    );
    Ok(())
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn mutated_pictures_load_or_say_why_in_one_line((name, bytes) in mutant(texture_seeds())) {
        if let Err(e) = load_texture_from_bytes(&name, &bytes) {
            check_message(&e.to_string())?;
        }
    }

    #[test]
    fn mutated_xpm_files_load_or_say_why_in_one_line((name, bytes) in mutant(xpm_seeds())) {
        // Through the loader (size limits, budget) and the reader alone.
        if let Err(e) = load_texture_from_bytes(&name, &bytes) {
            check_message(&e.to_string())?;
        }
        match xpm::decode(&bytes, 1 << 16) {
            Ok(img) => prop_assert_eq!(img.rgba.len(), img.width * img.height),
            Err(e) => check_message(&e.to_string())?,
        }
    }

    #[test]
    fn mutated_obj_files_load_or_say_why_in_one_line((name, bytes) in mutant(obj_seeds())) {
        match obj::parse(&name, &bytes) {
            Ok(mesh) => {
                prop_assert!(!mesh.triangles.is_empty());
                prop_assert!(mesh.vertices.iter().all(|v| v.position.is_finite()
                    && v.normal.is_finite()
                    && v.uv.is_finite()
                    && v.color.is_finite()));
            }
            Err(e) => check_message(&e.to_string())?,
        }
    }
}
