//! ETC1S (BasisLZ) KTX2 files made by the Basis Universal encoder
//! (tests/data/ktx2/, written by tools/etc1s-ktx2 from the pictures of
//! etc1s_pictures.rs): they decode to their pictures within the codec's
//! error, alpha slice as alpha, the level a size cap asks for; in a GLB
//! they draw as their texels do; damaged, they are read or refused in one
//! line, never by a panic.

use std::path::Path;

use relief_texture::Texture;
use relief_texture::decode::load::{has_alpha, load_texture_from_bytes};
use relief_texture::decode::{ktx2, size_cap};

use super::etc1s_pictures::{LEVEL_BLUE, PICTURES, Picture, level, level_size};
use super::models_gltf::{json_fix, png, refused};
use super::models_gltf_ktx2::{REQUIRED, drawn, quad_glb};

fn file(picture: &Picture) -> Vec<u8> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/ktx2");
    std::fs::read(path.join(picture.file)).unwrap()
}

/// The texture's texels as 8-bit RGBA (its reads are k / 255).
fn rgba8(texture: &Texture) -> Vec<[u8; 4]> {
    let texels = &texture.base().texels;
    texels
        .iter()
        .map(|t| t.map(|c| (c * 255.0).round() as u8))
        .collect()
}

/// The texels of `picture` loaded under a size cap of `side` texels.
fn decoded(picture: &Picture, side: Option<u32>) -> (usize, usize, Vec<[u8; 4]>) {
    let bytes = file(picture);
    let load = || load_texture_from_bytes(picture.file, &bytes);
    let texture = size_cap::with_max_side(side, load).unwrap_or_else(|e| panic!("{e}"));
    (texture.width(), texture.height(), rgba8(&texture))
}

/// Per channel, the mean and the largest difference between two pictures.
#[derive(Debug)]
struct Error {
    mean: [f32; 4],
    max: [u8; 4],
}

fn error(got: &[[u8; 4]], want: &[[u8; 4]]) -> Error {
    assert_eq!(got.len(), want.len());
    let (mut sum, mut max) = ([0u32; 4], [0u8; 4]);
    for (g, w) in got.iter().zip(want) {
        for c in 0..4 {
            let d = g[c].abs_diff(w[c]);
            sum[c] += u32::from(d);
            max[c] = max[c].max(d);
        }
    }
    let mean = sum.map(|s| s as f32 / got.len() as f32);
    Error { mean, max }
}

/// ETC1S's error on these pictures, per channel, over every level: measured
/// at most 4.25 on average and 10 at most (tools/etc1s-ktx2 encodes at its
/// highest quality), bounded a little above. A flip, a swap of two channels, alpha lost or another
/// level's blue is off by tens (see the test of the bound).
const MEAN_BOUND: f32 = 5.0;
const MAX_BOUND: u8 = 12;

fn within(e: &Error) -> bool {
    e.mean.iter().all(|&m| m <= MEAN_BOUND) && e.max.iter().all(|&m| m <= MAX_BOUND)
}

/// The decoded texels against level `k` of `picture`; an opaque picture's
/// fourth channel is the height, the mean of the decoded R, G and B (as
/// for a PNG), which is checked exactly instead.
fn error_from(picture: &Picture, k: u32, got: &[[u8; 4]]) -> Error {
    let mut want = level(picture, k);
    if !picture.alpha {
        for (w, g) in want.iter_mut().zip(got) {
            let mean = (f32::from(g[0]) + f32::from(g[1]) + f32::from(g[2])) / 3.0;
            assert_eq!(g[3], mean.round() as u8, "{}: height", picture.file);
            w[3] = g[3];
        }
    }
    error(got, &want)
}

/// Each file decodes to its picture's level 0 within the bound, at its
/// size (the 30×22 one cut from its 8×6 blocks); the alpha slice is the
/// texture's alpha, and only that file says it has alpha; the levels are
/// those the encoder was given.
#[test]
fn etc1s_files_decode_to_their_pictures_within_the_codec_error() {
    for picture in &PICTURES {
        let (w, h, got) = decoded(picture, None);
        assert_eq!((w, h), (picture.width, picture.height), "{}", picture.file);
        let e = error_from(picture, 0, &got);
        assert!(within(&e), "{}: {e:?}", picture.file);
        assert_eq!(has_alpha(&file(picture)), picture.alpha, "{}", picture.file);
        let levels = ktx2::header(&file(picture)).unwrap().levels;
        assert_eq!(levels, picture.levels, "{}", picture.file);
    }
}

/// `texels` (`w` wide) changed texel by texel, with their place.
fn remapped(
    texels: &[[u8; 4]],
    w: usize,
    f: impl Fn(usize, usize, [u8; 4]) -> [u8; 4],
) -> Vec<[u8; 4]> {
    let at = |i: usize| (i % w, i / w);
    (0..texels.len())
        .map(|i| f(at(i).0, at(i).1, texels[i]))
        .collect()
}

/// The bound fails what a wrong read would give: the picture flipped
/// either way, two channels swapped, alpha lost (255, or the mean of RGB
/// as for an opaque file), another level's blue.
#[test]
fn the_bound_fails_a_flip_a_swap_lost_alpha_and_another_level() {
    let picture = &PICTURES[1];
    let (w, h, got) = decoded(picture, None);
    let want = level(picture, 0);
    let at = |x: usize, y: usize| want[y * w + x];
    let mut wrong = vec![
        (
            "flipped upside down",
            remapped(&want, w, |x, y, _| at(x, h - 1 - y)),
        ),
        ("mirrored", remapped(&want, w, |x, y, _| at(w - 1 - x, y))),
        (
            "alpha 255",
            remapped(&want, w, |_, _, [r, g, b, _]| [r, g, b, 255]),
        ),
    ];
    let mean = |[r, g, b, _]: [u8; 4]| ((u16::from(r) + u16::from(g) + u16::from(b)) / 3) as u8;
    wrong.push((
        "alpha the mean",
        remapped(&want, w, |_, _, t| [t[0], t[1], t[2], mean(t)]),
    ));
    for (i, j) in [(0, 1), (0, 2), (1, 2), (0, 3), (1, 3), (2, 3)] {
        let swap = |_, _, mut t: [u8; 4]| {
            t.swap(i, j);
            t
        };
        wrong.push(("channels swapped", remapped(&want, w, swap)));
    }
    for blue in &LEVEL_BLUE[1..] {
        let shift = i32::from(*blue) - i32::from(LEVEL_BLUE[0]);
        let moved = |c: u8| (i32::from(c) + shift).clamp(0, 255) as u8;
        let other = |_, _, [r, g, b, a]: [u8; 4]| [r, g, moved(b), a];
        wrong.push(("another level's blue", remapped(&want, w, other)));
    }
    assert!(within(&error(&got, &want)));
    for (what, texels) in wrong {
        let e = error(&got, &texels);
        assert!(!within(&e), "{what}: {e:?}");
    }
}

/// Of the mip chain, 32×32 down to 1×1, a size cap reads the largest level
/// within it, and that level is its own picture (its blue is its own).
#[test]
fn a_size_cap_reads_the_etc1s_level_it_needs() {
    let picture = &PICTURES[2];
    // (cap, level read): 31 takes level 1 (16×16), 3 level 4 (2×2).
    let caps = [(None, 0), (Some(32), 0), (Some(31), 1), (Some(16), 1)];
    let smaller = [
        (Some(9), 2),
        (Some(4), 3),
        (Some(3), 4),
        (Some(2), 4),
        (Some(1), 5),
    ];
    for (side, k) in caps.into_iter().chain(smaller) {
        let (w, h, got) = decoded(picture, side);
        assert_eq!((w, h), level_size(picture, k), "cap {side:?}");
        let e = error_from(picture, k, &got);
        assert!(within(&e), "cap {side:?}, level {k}: {e:?}");
    }
}

/// A GLB of one quad whose base colour is the file through
/// `KHR_texture_basisu` (required: no fallback), `blend` with alphaMode BLEND.
fn etc1s_glb(ktx2: Vec<u8>, blend: bool) -> Vec<u8> {
    let only = r#"[{"sampler":0,"extensions":{"KHR_texture_basisu":{"source":0}}}]"#;
    with_blend(quad_glb(vec![ktx2], 1, only, REQUIRED), blend)
}

fn with_blend(glb: Vec<u8>, blend: bool) -> Vec<u8> {
    match blend {
        true => json_fix(
            glb,
            r#""metallicFactor":0}"#,
            r#""metallicFactor":0},"alphaMode":"BLEND""#,
        ),
        false => glb,
    }
}

/// In a GLB each file draws exactly as a PNG of the texels it decodes to
/// (the mip chain's level 0); blended, the alpha slice is the quad's
/// coverage, as the PNG's alpha is, and the quad draws otherwise than opaque.
#[test]
fn etc1s_textures_in_a_glb_draw_as_their_texels() {
    for picture in &PICTURES {
        let (w, h, texels) = decoded(picture, None);
        // An opaque file's fourth channel is its height, not alpha.
        let alpha = |t: [u8; 4]| if picture.alpha { t[3] } else { 255 };
        let twin = png(w as u32, h as u32, |x, y| {
            let t = texels[y as usize * w + x as usize];
            [t[0], t[1], t[2], alpha(t)]
        });
        let png_texture = r#"[{"source":0,"sampler":0}]"#;
        for blend in [false, true] {
            let name = format!("etc1s-{}-{blend}", picture.file);
            let ktx2 = drawn(&name, &etc1s_glb(file(picture), blend));
            let png_glb = with_blend(quad_glb(vec![twin.clone()], 0, png_texture, ""), blend);
            assert_eq!(ktx2, drawn(&format!("{name}-png"), &png_glb), "{name}");
        }
        let [plain, blended] =
            [false, true].map(|b| drawn("etc1s-again", &etc1s_glb(file(picture), b)));
        assert_eq!(plain != blended, picture.alpha, "{}", picture.file);
    }
}

/// A refusal as every loader gives it: one line naming the file, saying
/// why in words, not the decoder's internals.
fn one_line(message: &str, file: &str, what: &str) {
    assert!(
        message.starts_with(&format!("{file}: ")),
        "{what}: {message}"
    );
    assert!(!message.chars().any(char::is_control), "{what}: {message}");
    assert!(message.chars().count() <= 200, "{what}: {message}");
    for internal in ["panicked", "unwrap", "index out of", "overflow"] {
        assert!(!message.contains(internal), "{what}: {message}");
    }
}

/// Every truncation of each file is refused in one line, and by the
/// checks made before the transcoder (the levels come last, so each cut
/// leaves a level past the end): none reaches a transcoder panic.
#[test]
fn every_truncation_of_an_etc1s_file_is_refused_in_one_line() {
    for picture in &PICTURES {
        let bytes = file(picture);
        for len in 0..bytes.len() {
            let what = format!("{} cut to {len} bytes", picture.file);
            let Err(e) = load_texture_from_bytes(picture.file, &bytes[..len]) else {
                panic!("{what}: read");
            };
            let message = e.to_string();
            one_line(&message, picture.file, &what);
            assert!(!message.contains("does not expect"), "{what}: {message}");
        }
    }
    // In a GLB, cut inside the global data: refused naming the image.
    let rgba = file(&PICTURES[1]);
    let message = refused("etc1s-cut", &etc1s_glb(rgba[..300].to_vec(), false));
    assert!(message.contains("images[0].ktx2"), "{message}");
    assert!(message.contains("past the end of the file"), "{message}");
}

/// Each byte of each file changed in turn (all its bits flipped, or set
/// to 0): the file is read or refused in one line, through the codebooks,
/// the Huffman tables and the slices alike, and the transcoder never
/// panics (a contained panic would be refused as data it "does not expect").
#[test]
fn each_byte_of_an_etc1s_file_damaged_is_read_or_refused_in_one_line() {
    let (mut read, mut refused) = (0, 0);
    for picture in &PICTURES {
        let bytes = file(picture);
        for (at, value) in (0..bytes.len()).flat_map(|at| [(at, !bytes[at]), (at, 0)]) {
            let mut damaged = bytes.clone();
            damaged[at] = value;
            let what = format!("{} with byte {at} {value:#04x}", picture.file);
            let Err(e) = load_texture_from_bytes(picture.file, &damaged) else {
                read += 1;
                continue;
            };
            let message = e.to_string();
            one_line(&message, picture.file, &what);
            assert!(!message.contains("does not expect"), "{what}: {message}");
            refused += 1;
        }
    }
    // Both answers are reached: damage in a slice mostly decodes to
    // other texels, damage in the header is refused.
    assert!(read > 0 && refused > 0, "read {read}, refused {refused}");
}
