//! glTF's `KHR_texture_basisu`: KTX2 textures of UASTC blocks written here
//! (tests/common/ktx2_writer.rs) decode to exactly their blocks' colours,
//! draw as their PNG twins do, win over a PNG fallback, and damaged ones
//! are refused with one line naming the image.

use relief_texture::Texture;
use relief_texture::decode::load::load_texture_from_bytes;
use relief_texture::decode::size_cap;

use super::models_gltf::{
    Doc, encode, good, json_fix, load_ok, png, quad, refused, render, scene_of, write,
};
use crate::ktx2_writer::{
    HEIGHT_AT, LEVEL_INDEX_AT, Level, Uastc, WIDTH_AT, four_blocks, uastc_solid,
};
use relief_core::settings::Settings;

const RED: [u8; 4] = [255, 0, 0, 255];
const GREEN: [u8; 4] = [0, 200, 0, 255];
const BLUE: [u8; 4] = [10, 20, 230, 255];
const GREY: [u8; 4] = [90, 90, 90, 255];
/// Top left, top right, bottom left, bottom right.
const QUARTERS: [[u8; 4]; 4] = [RED, GREEN, BLUE, GREY];

/// The colour of the quarter texel (x, y) of an 8×8 picture lies in.
fn quarter(x: usize, y: usize) -> [u8; 4] {
    QUARTERS[(y / 4) * 2 + x / 4]
}

/// The texture's texels as 8-bit RGBA (its reads are k / 255).
fn rgba8(texture: &Texture) -> Vec<[u8; 4]> {
    texture
        .base()
        .texels
        .iter()
        .map(|t| t.map(|c| (c * 255.0).round() as u8))
        .collect()
}

fn decoded(name: &str, bytes: &[u8]) -> Texture {
    load_texture_from_bytes(name, bytes).unwrap_or_else(|e| panic!("{e}"))
}

/// Every texel is its block's colour; with alpha, alpha is the height;
/// without, the height is the mean of R, G and B, as for a PNG.
#[test]
fn uastc_blocks_decode_to_exactly_their_colours() {
    for alpha in [false, true] {
        let mut file = four_blocks(QUARTERS.map(|[r, g, b, _]| [r, g, b, 40]));
        file.alpha = alpha;
        let texture = decoded("t.ktx2", &file.encode());
        assert_eq!((texture.width(), texture.height()), (8, 8));
        for (i, got) in rgba8(&texture).into_iter().enumerate() {
            let [r, g, b, _] = quarter(i % 8, i / 8);
            let mean = ((r as f32 + g as f32 + b as f32) / 3.0).round() as u8;
            let height = if alpha { 40 } else { mean };
            assert_eq!(got, [r, g, b, height], "texel {i}, alpha {alpha}");
        }
    }
}

/// A Zstandard-supercompressed level decodes to the same texels, and
/// a linear transfer function changes nothing (the material slot says
/// how colours are read).
#[test]
fn a_zstandard_level_and_a_linear_file_decode_alike() {
    let plain = rgba8(&decoded("p.ktx2", &four_blocks(QUARTERS).encode()));
    let mut zstd = four_blocks(QUARTERS);
    zstd.zstd = true;
    assert_eq!(rgba8(&decoded("z.ktx2", &zstd.encode())), plain);
    let mut linear = four_blocks(QUARTERS);
    linear.srgb = false;
    assert_eq!(rgba8(&decoded("l.ktx2", &linear.encode())), plain);
}

/// Under a size cap the largest level within it is read: of a 16×16
/// file with an 8×8 and a 4×4 level, a 4-texel cap reads the 4×4 one.
#[test]
fn a_size_cap_reads_the_level_it_needs() {
    let mut file = Uastc::new(16, 16, vec![uastc_solid(RED); 16]);
    file.levels.push(Level {
        blocks: vec![uastc_solid(GREEN); 4],
    });
    file.levels.push(Level {
        blocks: vec![uastc_solid(BLUE)],
    });
    let bytes = file.encode();
    let whole = decoded("m.ktx2", &bytes);
    assert_eq!(whole.width(), 16);
    assert_eq!(rgba8(&whole)[0][..3], RED[..3]);
    let capped = size_cap::with_max_side(Some(4), || decoded("m.ktx2", &bytes));
    assert_eq!((capped.width(), capped.height()), (4, 4));
    assert_eq!(rgba8(&capped)[0][..3], BLUE[..3]);
    let between = size_cap::with_max_side(Some(8), || decoded("m.ktx2", &bytes));
    assert_eq!(between.width(), 8);
    assert_eq!(rgba8(&between)[0][..3], GREEN[..3]);
}

/// A GLB of one face-on quad whose base colour reads texture 0; its
/// images `images`, the first `ktx2` of them KTX2, and `textures` (JSON).
pub(super) fn quad_glb(images: Vec<Vec<u8>>, ktx2: usize, textures: &str, extra: &str) -> Vec<u8> {
    let mut q = quad(-1.0, 1.0, -0.5, 0.5, 0.0, 1.0);
    q.material = Some(0);
    let mut doc = Doc::new(vec![q]);
    doc.materials =
        r#"[{"pbrMetallicRoughness":{"baseColorTexture":{"index":0},"metallicFactor":0}}]"#.into();
    let count = images.len();
    doc.images = images;
    doc.sampler = Some(r#"{"magFilter":9728,"minFilter":9728}"#.into());
    doc.extra = extra.into();
    let mut bytes = encode(&doc);
    for _ in 0..ktx2 {
        bytes = json_fix(bytes, r#""image/png""#, r#""image/ktx2""#);
    }
    let all: Vec<String> = (0..count)
        .map(|i| format!(r#"{{"source":{i},"sampler":0}}"#))
        .collect();
    json_fix(
        bytes,
        &format!(r#""textures":[{}]"#, all.join(",")),
        &format!(r#""textures":{textures}"#),
    )
}

pub(super) fn drawn(test: &str, glb: &[u8]) -> Vec<[u8; 3]> {
    let path = write(test, "k.glb", glb);
    let scene = scene_of(load_ok(&path));
    let settings = Settings {
        rotation: glam::Vec3::ZERO,
        ..Settings::default()
    };
    render(&scene, &settings).pixels().to_vec()
}

pub(super) const REQUIRED: &str =
    r#","extensionsUsed":["KHR_texture_basisu"],"extensionsRequired":["KHR_texture_basisu"]"#;
const USED: &str = r#","extensionsUsed":["KHR_texture_basisu"]"#;

/// Required (no fallback `source`), the KTX2 texture draws exactly as the
/// same picture as a PNG does; with a PNG fallback of another colour, the
/// KTX2 one is drawn (and the file says nothing is left out).
#[test]
fn a_basisu_texture_draws_as_its_png_twin_and_wins_over_the_fallback() {
    let ktx2 = four_blocks(QUARTERS).encode();
    let twin = png(8, 8, |x, y| quarter(x as usize, y as usize));
    let from_png = drawn(
        "png",
        &quad_glb(vec![twin], 0, r#"[{"source":0,"sampler":0}]"#, ""),
    );
    let only = r#"[{"sampler":0,"extensions":{"KHR_texture_basisu":{"source":0}}}]"#;
    let required = drawn("required", &quad_glb(vec![ktx2.clone()], 1, only, REQUIRED));
    assert_eq!(required, from_png);
    // The centre pixel is where the four quarters meet: one of them, lit.
    let (w, h) = (super::models_gltf::W, super::models_gltf::H);
    assert_ne!(required[h / 2 * w + w / 2], [255, 0, 255]);

    let fallback = png(8, 8, |_, _| [255, 255, 0, 255]);
    let both = r#"[{"source":1,"sampler":0,"extensions":{"KHR_texture_basisu":{"source":0}}}]"#;
    let glb = quad_glb(vec![ktx2, fallback], 1, both, USED);
    assert_eq!(drawn("fallback", &glb), from_png);
    let path = write("fallback", "note.glb", &glb);
    assert_eq!(load_ok(&path).warnings, Vec::<String>::new());
}

/// `bytes` at `at` replaced by `value`'s little-endian bytes.
fn patched(mut bytes: Vec<u8>, at: usize, value: &[u8]) -> Vec<u8> {
    bytes[at..at + value.len()].copy_from_slice(value);
    bytes
}

/// Damaged KTX2 data is refused with one plain line naming the image
/// (`images[0].ktx2`) and saying why; nothing panics, and a huge claimed
/// size is refused before anything of that size is allocated.
#[test]
fn damaged_ktx2_images_are_refused_naming_the_image() {
    let good_file = four_blocks(QUARTERS).encode();
    let only = r#"[{"sampler":0,"extensions":{"KHR_texture_basisu":{"source":0}}}]"#;
    let refuse = |test: &str, ktx2: Vec<u8>, why: &str| {
        let m = refused(test, &quad_glb(vec![ktx2], 1, only, REQUIRED));
        assert!(m.contains("images[0].ktx2"), "{test}: {m}");
        assert!(m.contains(why), "{test}: {m}");
        for internal in ["panicked", "unwrap", "index out of", "overflow"] {
            assert!(!m.contains(internal), "{test}: {m}");
        }
    };
    refuse("truncated", good_file[..60].to_vec(), "ends too early");
    let mut cut = good_file.clone();
    cut.truncate(good_file.len() - 10);
    refuse("cut", cut, "past the end of the file");
    refuse(
        "identifier",
        patched(good_file.clone(), 1, b"XYZ"),
        "not an image in a known format",
    );
    let past = (good_file.len() as u64 * 2).to_le_bytes();
    refuse(
        "level past the end",
        patched(good_file.clone(), LEVEL_INDEX_AT, &past),
        "past the end of the file",
    );
    let wrapping = patched(good_file.clone(), LEVEL_INDEX_AT, &u64::MAX.to_le_bytes());
    refuse("offset wraps", wrapping, "past the end of the file");
    let huge = patched(good_file.clone(), WIDTH_AT, &1_000_000u32.to_le_bytes());
    refuse(
        "huge",
        patched(huge, HEIGHT_AT, &1_000_000u32.to_le_bytes()),
        "too large",
    );
    // Within the size limit but with 64 bytes for 4096² texels.
    let big = patched(good_file.clone(), WIDTH_AT, &4096u32.to_le_bytes());
    refuse(
        "short level",
        patched(big, HEIGHT_AT, &4096u32.to_le_bytes()),
        "take",
    );
    refuse(
        "zero",
        patched(good_file.clone(), WIDTH_AT, &0u32.to_le_bytes()),
        "empty",
    );
    let mut zstd = four_blocks(QUARTERS);
    zstd.zstd = true;
    let inflated_at = LEVEL_INDEX_AT + 16;
    let claim = patched(zstd.encode(), inflated_at, &(1u64 << 40).to_le_bytes());
    refuse("zstd claim", claim, "once inflated");
    // The Zstandard frame's magic number damaged.
    let stream = zstd.encode();
    let level_at = u64::from_le_bytes(stream[LEVEL_INDEX_AT..][..8].try_into().unwrap());
    refuse(
        "zstd stream",
        patched(stream, level_at as usize, &[0]),
        "level 0's data does not decode",
    );
    // Not Basis Universal data: a colour model the transcoder does not know.
    let dfd_at = u32::from_le_bytes(good_file[48..52].try_into().unwrap()) as usize;
    refuse(
        "model",
        patched(good_file.clone(), dfd_at + 12, &[1]),
        "not Basis Universal data",
    );
    // A later Basis Universal codec (as its encoder writes desk.ktx2), or
    // another block codec, is named.
    for (model, name) in [
        (167, "UASTC HDR 4x4"),
        (168, "UASTC HDR 6x6"),
        (162, "ASTC"),
    ] {
        let file = patched(good_file.clone(), dfd_at + 12, &[model]);
        refuse(name, file, &format!("{name} data is not read"));
    }
}

/// The file that requires the extension and has no texture at all loads.
#[test]
fn a_file_requiring_basisu_loads() {
    let mut doc = good();
    doc.extra = REQUIRED.into();
    let path = write("requires", "r.glb", &encode(&doc));
    assert_eq!(load_ok(&path).parts.len(), 1);
}
