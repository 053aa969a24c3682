//! Loading textures: every format against its PNG, the whole PngSuite,
//! hostile files, height rules, built-in assets and the texture list.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use relief::app::texture_list::{ListError, TextureList};
use relief_texture::decode::builtin::{builtins, write_assets};
use relief_texture::decode::load::{
    TextureError, load_for_view, load_texture, load_texture_from_bytes, load_texture_with_height,
    load_texture_with_height_from_bytes,
};
use relief_texture::decode::procedural;
use relief_texture::decode::xpm;
use relief_texture::{Level, Texture};

fn data(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(rel)
}

/// A fresh scratch directory for one test.
fn scratch(name: &str) -> PathBuf {
    crate::common::scratch::fresh_scratch_dir(&format!("tex-{name}"))
}

/// Texel at column x, row y counted from the top (as in the image file).
fn at(tex: &Texture, x: usize, y: usize) -> [f32; 4] {
    let l = tex.base();
    l.texels.at(y * l.width + x)
}

fn png_rgba(path: &Path) -> image::RgbaImage {
    relief_texture::picture::open(path).unwrap().to_rgba8()
}

fn srgb(v: u8) -> f32 {
    let x = v as f32 / 255.0;
    let y = if x <= 0.003_130_8 {
        12.92 * x
    } else {
        1.055 * x.powf(1.0 / 2.4) - 0.055
    };
    (y * 255.0).round() / 255.0
}

fn luma709(p: [u8; 4]) -> f32 {
    (0.2126 * p[0] as f32 + 0.7152 * p[1] as f32 + 0.0722 * p[2] as f32) / 255.0
}

/// The height of a picture without alpha: the mean of R, G, B.
fn mean_rgb(t: [f32; 4]) -> f32 {
    ((t[0] as f64 + t[1] as f64 + t[2] as f64) / 3.0) as f32
}

fn assert_clean_one_line(msg: &str) {
    assert!(
        !msg.chars().any(char::is_control),
        "control char in {msg:?}"
    );
}

const STEMS: [&str; 5] = ["basn0g08", "basn2c08", "basn3p08", "basn6a08", "tbrn2c08"];

/// BMP holds the same pixels (RGB and alpha) as the PNG: identical texels.
#[test]
fn bmp_equals_png_exactly() {
    for stem in STEMS {
        let png = load_texture(&data(&format!("formats/{stem}.png"))).unwrap();
        let bmp = load_texture(&data(&format!("formats/{stem}.bmp"))).unwrap();
        assert_eq!(png.base(), bmp.base(), "{stem}.bmp");
    }
}

/// ImageMagick wrote the PPM and TGA files after converting the PngSuite's
/// linear (gAMA 1.0) pixels to sRGB, and its TGA rows top-first while the
/// header says bottom-left origin (relief follows the header, as the TGA
/// specification says). So: PPM = sRGB(PNG) and TGA = sRGB(PNG) upside
/// down, exactly, on every pixel the PNG has opaque. PPM has no alpha, so
/// its height is the mean of RGB; TGA keeps alpha, so its height is alpha.
#[test]
fn ppm_and_tga_equal_the_png_after_imagemagicks_srgb_conversion() {
    for stem in STEMS {
        let png = png_rgba(&data(&format!("formats/{stem}.png")));
        let ppm = load_texture(&data(&format!("formats/{stem}.ppm"))).unwrap();
        let tga = load_texture(&data(&format!("formats/{stem}.tga"))).unwrap();
        let png_has_alpha = png.pixels().any(|p| p.0[3] != 255);
        let mut opaque = 0;
        for (x, y, p) in png.enumerate_pixels() {
            let (x, y) = (x as usize, y as usize);
            let t = at(&ppm, x, y);
            assert_eq!(t[3], mean_rgb(t), "{stem}.ppm height");
            let g = at(&tga, x, 31 - y);
            if png_has_alpha {
                assert_eq!(g[3], p.0[3] as f32 / 255.0, "{stem}.tga alpha at {x},{y}");
            }
            if p.0[3] != 255 {
                continue;
            }
            opaque += 1;
            for c in 0..3 {
                assert_eq!(t[c], srgb(p.0[c]), "{stem}.ppm at {x},{y}");
                assert_eq!(g[c], srgb(p.0[c]), "{stem}.tga at {x},{y}");
            }
        }
        assert!(opaque >= 32, "{stem}: compared {opaque} pixels");
    }
}

/// PGM is grey: ImageMagick's Rec. 709 luma of the PNG, within one level
/// (rounding); all three channels and the height equal that grey.
#[test]
fn pgm_is_the_pngs_luma() {
    for stem in STEMS {
        let png = png_rgba(&data(&format!("formats/{stem}.png")));
        let pgm = load_texture(&data(&format!("formats/{stem}.pgm"))).unwrap();
        for (x, y, p) in png.enumerate_pixels() {
            let t = at(&pgm, x as usize, y as usize);
            assert!(t[0] == t[1] && t[1] == t[2] && t[3] == t[0]);
            assert!(
                (t[0] - luma709(p.0)).abs() <= 1.0 / 255.0 + 1e-6,
                "{stem}.pgm at {x},{y}: {} vs {}",
                t[0] * 255.0,
                luma709(p.0) * 255.0
            );
        }
    }
}

/// PBM is 1-bit and ImageMagick dithers: every texel is black or white,
/// and the mean over each 8×8 block follows the PNG's luma there.
#[test]
fn pbm_is_a_dithered_bilevel_picture_of_the_png() {
    for stem in STEMS {
        let png = png_rgba(&data(&format!("formats/{stem}.png")));
        let pbm = load_texture(&data(&format!("formats/{stem}.pbm"))).unwrap();
        assert_eq!((pbm.width(), pbm.height()), (32, 32));
        let mut worst = 0.0f32;
        for by in 0..4 {
            for bx in 0..4 {
                let (mut a, mut b) = (0.0, 0.0);
                for y in by * 8..by * 8 + 8 {
                    for x in bx * 8..bx * 8 + 8 {
                        let t = at(&pbm, x, y);
                        assert!(t[0] == 0.0 || t[0] == 1.0, "{stem}.pbm not bilevel");
                        assert!(t[0] == t[1] && t[1] == t[2] && t[3] == t[0]);
                        a += t[0] / 64.0;
                        b += luma709(png.get_pixel(x as u32, y as u32).0) / 64.0;
                    }
                }
                worst = worst.max((a - b).abs());
            }
        }
        assert!(worst < 0.3, "{stem}.pbm: block means differ by {worst}");
    }
}

/// XPM against ImageMagick's files: where ImageMagick kept every colour
/// the texels are identical to the PNG's; the `None` entry marks the
/// transparent pixels (alpha below one half) and makes alpha the height;
/// where ImageMagick reduced the colours, RGB stays within that reduction.
#[test]
fn xpm_matches_the_png() {
    for stem in ["basn0g08", "basn3p08"] {
        let png = load_texture(&data(&format!("formats/{stem}.png"))).unwrap();
        let xpm = load_texture(&data(&format!("formats/{stem}.xpm"))).unwrap();
        assert_eq!(png.base(), xpm.base(), "{stem}.xpm");
    }
    // (stem, largest RGB error in levels after sRGB) — basn6a08 kept all of
    // its opaque colours; basn2c08 has 125 and tbrn2c08 170 table entries.
    for (stem, tolerance) in [("basn6a08", 0.0), ("basn2c08", 8.0), ("tbrn2c08", 19.0)] {
        let png = png_rgba(&data(&format!("formats/{stem}.png")));
        let bytes = std::fs::read(data(&format!("formats/{stem}.xpm"))).unwrap();
        let raw = xpm::decode(&bytes, 1 << 20).unwrap();
        let tex = load_texture(&data(&format!("formats/{stem}.xpm"))).unwrap();
        assert_eq!(raw.has_alpha, stem != "basn2c08");
        for (x, y, p) in png.enumerate_pixels() {
            let (x, y) = (x as usize, y as usize);
            let r = raw.rgba[y * 32 + x];
            let t = at(&tex, x, y);
            if raw.has_alpha {
                assert_eq!(r[3] == 0.0, p.0[3] < 128, "{stem}.xpm None at {x},{y}");
                assert_eq!(t[3], r[3], "{stem}.xpm height = alpha");
            } else {
                assert_eq!(t[3], mean_rgb(t));
            }
            if p.0[3] == 255 {
                for (got, want) in r.iter().zip(p.0).take(3) {
                    let err = (got - srgb(want)).abs() * 255.0;
                    assert!(err <= tolerance + 1e-3, "{stem}.xpm at {x},{y}: {err}");
                }
            }
        }
    }
}

/// An icon written the way real ones are: X11 names in any case and with
/// blanks, symbolic names, no ',' before the first row, one row too many.
#[test]
fn xpm_with_x11_names_and_real_icon_quirks_loads() {
    let path = data("xpm/icon_names.xpm");
    let raw = xpm::decode(&std::fs::read(&path).unwrap(), 1 << 20).unwrap();
    assert_eq!((raw.width, raw.height, raw.has_alpha), (4, 3, true));
    let px = |x: usize, y: usize| raw.rgba[y * 4 + x].map(|c| (c * 255.0).round() as u8);
    assert_eq!(px(0, 0), [0, 0, 0, 0]);
    assert_eq!(px(1, 0), [99, 184, 255, 255]);
    assert_eq!(px(2, 0), [238, 221, 130, 255]);
    assert_eq!(px(3, 0), [85, 107, 47, 255]);
    assert_eq!(px(0, 1), [0, 0, 0, 255]);
    assert_eq!(px(1, 1), [255, 255, 255, 255]);
    assert_eq!(px(2, 1), [70, 130, 180, 255]);
    assert_eq!(px(3, 1), [245, 222, 179, 255]);
    assert_eq!(px(0, 2), px(3, 1));
    let tex = load_texture(&path).unwrap();
    assert_eq!((tex.base().width, tex.base().height), (4, 3));
}

fn pngsuite_files() -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(data("pngsuite"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "png"))
        .collect();
    files.sort();
    assert!(files.len() > 170, "PngSuite incomplete: {}", files.len());
    files
}

#[test]
fn pngsuite_corrupt_files_are_refused_with_a_clear_error() {
    let mut refused = 0;
    for path in pngsuite_files() {
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        if !name.starts_with('x') {
            continue;
        }
        let err = load_texture(&path).expect_err(&name);
        let msg = err.to_string();
        assert!(msg.contains(&name), "{msg}");
        assert_clean_one_line(&msg);
        refused += 1;
    }
    assert_eq!(refused, 14);
}

#[test]
fn pngsuite_valid_files_all_load_in_range() {
    let mut loaded = 0;
    for path in pngsuite_files() {
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        if name.starts_with('x') {
            continue;
        }
        let tex = load_texture(&path).unwrap_or_else(|e| panic!("{e}"));
        let picture = relief_texture::picture::open(&path).unwrap();
        let (w, h) = (picture.width(), picture.height());
        assert_eq!(
            (tex.width(), tex.height()),
            (w as usize, h as usize),
            "{name}"
        );
        assert!(
            tex.base()
                .texels
                .iter()
                .flatten()
                .all(|c| (0.0..=1.0).contains(&c)),
            "{name}"
        );
        loaded += 1;
    }
    assert_eq!(loaded, 161);
}

/// Interlaced files hold the same pixels as their non-interlaced twins.
#[test]
fn interlaced_equals_progressive() {
    for path in pngsuite_files() {
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        let twin = if let Some(rest) = name.strip_prefix("basi") {
            format!("basn{rest}")
        } else if name.starts_with('s') && name.as_bytes()[3] == b'i' {
            format!("{}n{}", &name[..3], &name[4..])
        } else {
            continue;
        };
        let a = load_texture(&path).unwrap();
        let b = load_texture(&data(&format!("pngsuite/{twin}"))).unwrap();
        assert_eq!(a.base(), b.base(), "{name} vs {twin}");
    }
}

#[test]
fn sixteen_bit_keeps_its_precision_and_odd_sizes_load() {
    let tex = load_texture(&data("pngsuite/basn0g16.png")).unwrap();
    let off_grid = tex
        .base()
        .texels
        .iter()
        .filter(|t| ((t[0] * 255.0) - (t[0] * 255.0).round()).abs() > 1e-3)
        .count();
    assert!(
        off_grid > 100,
        "16-bit values rounded to 8 bits ({off_grid})"
    );
    // 1×1 and 9×9 pictures, palette, 1 bit.
    assert_eq!(
        load_texture(&data("pngsuite/s01n3p01.png"))
            .unwrap()
            .width(),
        1
    );
    assert_eq!(
        load_texture(&data("pngsuite/s09n3p02.png"))
            .unwrap()
            .height(),
        9
    );
}

/// Without alpha the height is the mean of R, G, B; with alpha it is alpha.
#[test]
fn height_is_alpha_or_the_mean_of_rgb() {
    let rgb = load_texture(&data("pngsuite/basn2c08.png")).unwrap();
    for t in &rgb.base().texels {
        assert_eq!(t[3], mean_rgb(t));
    }
    let rgba = load_texture(&data("pngsuite/basn6a08.png")).unwrap();
    let png = png_rgba(&data("pngsuite/basn6a08.png"));
    for (x, y, p) in png.enumerate_pixels() {
        assert_eq!(at(&rgba, x as usize, y as usize)[3], p.0[3] as f32 / 255.0);
    }
}

fn encode_png(w: u32, h: u32, rgba: &[u8]) -> Vec<u8> {
    let picture = image::RgbaImage::from_raw(w, h, rgba.to_vec()).unwrap();
    relief_texture::picture::encode(&picture.into(), image::ImageFormat::Png).unwrap()
}

#[test]
fn separate_height_map_same_size_and_resampled() {
    // Same size: colour of one file, height = mean RGB of the other (no alpha).
    let tex =
        load_texture_with_height(&data("formats/basn2c08.png"), &data("formats/basn0g08.png"))
            .unwrap();
    let colour = load_texture(&data("formats/basn2c08.png")).unwrap();
    let grey = load_texture(&data("formats/basn0g08.png")).unwrap();
    for ((t, c), g) in tex
        .base()
        .texels
        .iter()
        .zip(&colour.base().texels)
        .zip(&grey.base().texels)
    {
        assert_eq!(t[..3], c[..3]);
        assert_eq!(t[3], g[0]);
    }
    assert!(tex.name.contains("basn2c08.png") && tex.name.contains("basn0g08.png"));

    // Height 2×1 (alpha 0, 255) onto colour 4×1: bilinear between centres, repeating.
    let colour = encode_png(4, 1, &[9; 16]);
    let height = encode_png(2, 1, &[0, 0, 0, 0, 0, 0, 0, 255]);
    let t = load_texture_with_height_from_bytes("c.png", &colour, "h.png", &height).unwrap();
    let hs: Vec<f32> = t.base().texels.iter().map(|t| t[3]).collect();
    assert_eq!(hs, vec![0.25, 0.25, 0.75, 0.75]);
    // Height 4×2 onto colour 2×1: box means of 2×2 blocks.
    let height = encode_png(
        4,
        2,
        &[
            0, 0, 0, 0, 0, 0, 0, 255, 0, 0, 0, 255, 0, 0, 0, 255, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
            0, 0, 0, 0, 255,
        ],
    );
    let colour = encode_png(2, 1, &[9; 8]);
    let t = load_texture_with_height_from_bytes("c.png", &colour, "h.png", &height).unwrap();
    let hs: Vec<f32> = t.base().texels.iter().map(|t| t[3]).collect();
    assert_eq!(hs, vec![0.25, 0.75]);
}

#[test]
fn load_for_view_defaults_to_the_brick() {
    let brick = load_for_view(None, None).unwrap();
    assert_eq!(brick.base(), procedural::brick().base());
    let bumped = load_for_view(None, Some(&data("formats/basn0g08.png"))).unwrap();
    assert_eq!(bumped.width(), 256);
    assert!(load_for_view(Some(&data("nope.png")), None).is_err());
    assert!(load_for_view(None, Some(&data("nope.png"))).is_err());
}

/// A tiny PNG whose IHDR claims `w × h`: a valid header, a few bytes of
/// compressed data, and the end chunk.
fn png_claiming(w: u32, h: u32) -> Vec<u8> {
    let mut ihdr = Vec::new();
    ihdr.extend_from_slice(&w.to_be_bytes());
    ihdr.extend_from_slice(&h.to_be_bytes());
    ihdr.extend_from_slice(&[8, 6, 0, 0, 0]);
    let mut png = b"\x89PNG\r\n\x1a\n".to_vec();
    for (kind, body) in [
        (&b"IHDR"[..], &ihdr[..]),
        (b"IDAT", &[0x78, 0x9c, 0x63, 0, 0, 0, 1, 0, 1][..]),
        (b"IEND", &[][..]),
    ] {
        png.extend_from_slice(&(body.len() as u32).to_be_bytes());
        let mut chunk = kind.to_vec();
        chunk.extend_from_slice(body);
        png.extend_from_slice(&chunk);
        png.extend_from_slice(&crc32(&chunk).to_be_bytes());
    }
    png
}

fn crc32(bytes: &[u8]) -> u32 {
    let mut crc = !0u32;
    for &b in bytes {
        crc ^= b as u32;
        for _ in 0..8 {
            crc = if crc & 1 != 0 {
                (crc >> 1) ^ 0xEDB8_8320
            } else {
                crc >> 1
            };
        }
    }
    !crc
}

#[test]
fn hostile_inputs_get_clear_errors() {
    let dir = scratch("hostile");
    let good = std::fs::read(data("pngsuite/basn2c08.png")).unwrap();

    let truncated = dir.join("truncated.png");
    std::fs::write(&truncated, &good[..good.len() / 2]).unwrap();
    let e = load_texture(&truncated).unwrap_err();
    assert!(matches!(e, TextureError::Corrupt { .. }), "{e}");

    let empty = dir.join("empty.png");
    std::fs::write(&empty, b"").unwrap();
    assert!(matches!(
        load_texture(&empty),
        Err(TextureError::Empty { .. })
    ));

    for (w, h) in [
        (100_000, 100_000),
        (16_000, 16_000),
        (16_385, 1),
        (u32::MAX, u32::MAX),
    ] {
        let huge = dir.join(format!("huge-{w}.png"));
        let bytes = png_claiming(w, h);
        assert!(bytes.len() < 100);
        std::fs::write(&huge, bytes).unwrap();
        let e = load_texture(&huge).unwrap_err();
        assert!(matches!(e, TextureError::TooLarge { .. }), "{w}x{h}: {e}");
    }
    let e = load_texture_from_bytes("huge.ppm", b"P6\n20000 20000\n255\n\0\0\0").unwrap_err();
    assert!(matches!(e, TextureError::TooLarge { .. }), "{e}");
    let e = load_texture_from_bytes(
        "huge.xpm",
        b"/* XPM */\nstatic char *x[] = {\n\"100000 100000 1 1\",\n\"a c #000\",\n\"a\"};",
    )
    .unwrap_err();
    assert!(
        matches!(e, TextureError::Xpm { .. }) && e.to_string().contains("too large"),
        "{e}"
    );
    // Zero-size pictures.
    let e = load_texture_from_bytes("zero.ppm", b"P6\n0 0\n255\n").unwrap_err();
    assert!(e.to_string().contains("zero.ppm"), "{e}");

    assert!(matches!(
        load_texture(&dir),
        Err(TextureError::Directory { .. })
    ));
    assert!(matches!(
        load_texture(&dir.join("missing.png")),
        Err(TextureError::NotFound { .. })
    ));

    let text = dir.join("notes.txt");
    std::fs::write(&text, "hello, not a picture\n").unwrap();
    assert!(matches!(
        load_texture(&text),
        Err(TextureError::UnknownFormat { .. })
    ));
    let fake = dir.join("fake.png");
    std::fs::write(&fake, "hello, not a picture\n").unwrap();
    assert!(load_texture(&fake).is_err());

    let mut corrupt = good.clone();
    let mid = corrupt.len() / 2;
    corrupt[mid] ^= 0xff;
    let e = load_texture_from_bytes("flipped.png", &corrupt).unwrap_err();
    assert!(matches!(e, TextureError::Corrupt { .. }), "{e}");

    #[cfg(unix)]
    {
        let sock = dir.join("socket.png");
        let _listener = std::os::unix::net::UnixListener::bind(&sock).unwrap();
        assert!(matches!(
            load_texture(&sock),
            Err(TextureError::NotAFile { .. })
        ));
    }

    // A name made to move the cursor and change colours.
    let evil = dir.join("evil\x1b[31m\x07\u{9b}2J.png");
    std::fs::write(&evil, b"garbage").unwrap();
    for e in [
        load_texture(&evil).unwrap_err(),
        load_texture(&dir.join("gone\x1b]0;x\x07.png")).unwrap_err(),
    ] {
        let msg = e.to_string();
        assert_clean_one_line(&msg);
        assert_clean_one_line(e.file());
        assert!(msg.contains("?[31m") || msg.contains("?]0;x?"), "{msg}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn every_error_names_its_file_on_one_line() {
    let bad: &[(&str, &[u8])] = &[
        ("a.png", b""),
        ("b.png", b"\x89PNG\r\n\x1a\n"),
        ("c.bmp", b"BM\0\0"),
        ("d.gif", b"GIF89a\x01"),
        ("e.jpg", b"\xff\xd8\xff\xe0\0\x10JFIF"),
        ("f.tga", b"\0\0\x02\0\0\0\0\0\0\0\0\0\x20\0\x20\0\x20\x08"),
        ("g.xpm", b"/* XPM */ static char *g[] = { \"1 1 1 1\",\n"),
        ("h.pgm", b"P5\n2 2\n255\n\x01"),
        ("i", b"\x00\x01\x02\x03"),
    ];
    for (name, bytes) in bad {
        let e = load_texture_from_bytes(name, bytes).unwrap_err();
        let msg = e.to_string();
        assert!(msg.starts_with(name), "{msg}");
        assert_clean_one_line(&msg);
        assert!(msg.len() < 300, "{msg}");
    }
}

#[test]
fn from_bytes_uses_the_name_when_the_content_has_no_signature() {
    let tga = std::fs::read(data("formats/basn2c08.tga")).unwrap();
    assert!(load_texture_from_bytes("x.tga", &tga).is_ok());
    assert!(matches!(
        load_texture_from_bytes("x", &tga),
        Err(TextureError::UnknownFormat { .. })
    ));
}

#[test]
fn shipped_assets_are_exactly_what_the_generators_draw() {
    let list = builtins();
    assert_eq!(list[0].name, "brick");
    for b in &list {
        let (w, h, rgba) = (b.generate)();
        let tex = b.load().unwrap();
        assert_eq!(
            tex.base(),
            &Level::from_rgba8_top_down(w, h, &rgba),
            "{}",
            b.file
        );
        // Relief worth showing: heights span more than half the range.
        let (lo, hi) = tex
            .base()
            .texels
            .iter()
            .fold((1.0f32, 0.0f32), |(lo, hi), t| (lo.min(t[3]), hi.max(t[3])));
        assert!(hi - lo > 0.5, "{}: heights {lo}..{hi}", b.name);
    }
    assert_eq!(list[0].load().unwrap().base(), procedural::brick().base());
    // write_assets writes files that decode the same.
    let dir = scratch("assets");
    let written = write_assets(&dir).unwrap();
    assert_eq!(written.len(), list.len());
    for (path, b) in written.iter().zip(&list) {
        assert_eq!(load_texture(path).unwrap().base(), b.load().unwrap().base());
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn reference_brick_loads_with_its_alpha_as_height() {
    let path = data("reference-brick.png");
    let reference = load_texture(&path).unwrap();
    assert_eq!((reference.width(), reference.height()), (256, 256));
    let png = png_rgba(&path);
    for (x, y, p) in png.enumerate_pixels() {
        let t = at(&reference, x as usize, y as usize);
        let want = p.0.map(|c| c as f32 / 255.0);
        assert_eq!(t, want, "{x},{y}");
    }
    assert!(png.pixels().any(|p| p.0[3] != png.get_pixel(0, 0).0[3]));
}

// ---- the texture list ----

#[test]
fn list_starts_with_the_built_ins_and_selects() {
    let mut list = TextureList::new();
    assert_eq!(list.len(), builtins().len());
    assert_eq!(list.current(), 0);
    assert!(list.texture().name.contains("brick"));
    assert_eq!(list.summary(), "1/3 brick (built-in)");
    let g0 = list.generation();
    list.select(1).unwrap();
    assert!(list.texture().name.contains("tiles"));
    assert_eq!(list.summary(), "2/3 tiles (built-in)");
    assert!(list.generation() > g0);
    let (before, g1) = (Arc::clone(list.texture()), list.generation());
    let e = list.select(99).unwrap_err();
    assert!(matches!(e, ListError::NoEntry { index: 99, .. }));
    assert!(Arc::ptr_eq(&before, list.texture()));
    assert_eq!((list.current(), list.generation()), (1, g1));
}

#[test]
fn list_adds_dedupes_and_keeps_state_on_errors() {
    let dir = scratch("list");
    let a = dir.join("a b.png");
    std::fs::copy(data("formats/basn2c08.png"), &a).unwrap();
    let mut list = TextureList::new();
    let n0 = list.len();
    let i = list.add_path(&a, None).unwrap();
    assert_eq!((i, list.len(), list.current()), (n0, n0 + 1, n0));
    // Another spelling of the same file: not added twice.
    let again = dir.join(".").join("a b.png");
    assert_eq!(list.add_path(&again, None).unwrap(), n0);
    assert_eq!(list.len(), n0 + 1);

    // Failures change nothing.
    let before = Arc::clone(list.texture());
    let labels: Vec<String> = list.entries().iter().map(|e| e.label.clone()).collect();
    for bad in [dir.join("missing.png"), dir.clone()] {
        assert!(list.add_path(&bad, None).is_err());
        assert!(Arc::ptr_eq(&before, list.texture()));
        assert_eq!(list.current(), n0);
        let now: Vec<String> = list.entries().iter().map(|e| e.label.clone()).collect();
        assert_eq!(now, labels);
    }

    // Reload reads the file again; a broken file keeps the old texture.
    std::fs::copy(data("formats/basn0g08.png"), &a).unwrap();
    list.reload().unwrap();
    let grey = load_texture(&data("formats/basn0g08.png")).unwrap();
    assert_eq!(list.texture().base(), grey.base());
    let kept = Arc::clone(list.texture());
    std::fs::write(&a, b"broken").unwrap();
    assert!(list.reload().is_err());
    assert!(Arc::ptr_eq(&kept, list.texture()));
    assert_eq!(list.len(), n0 + 1);

    // Cycling steps over the broken entry on the next press.
    assert!(list.cycle(true).is_ok()); // wraps to the brick
    assert_eq!(list.current(), 0);
    assert!(list.cycle(false).is_err()); // the broken file
    assert_eq!(list.current(), 0);
    assert!(list.cycle(false).is_ok()); // moves on past it
    assert_eq!(list.current(), n0 - 1);

    // A paste of a quoted path with a space, and one of a file:// URI.
    std::fs::copy(data("formats/basn3p08.png"), &a).unwrap();
    let quoted = format!("'{}'\n", a.display());
    assert!(list.add_paste(&quoted).is_empty());
    assert_eq!(list.current(), n0);
    let b = dir.join("b.png");
    std::fs::copy(data("formats/basn6a08.png"), &b).unwrap();
    let uri = format!("file://{}", b.display());
    assert!(list.add_paste(&uri).is_empty());
    assert_eq!(list.len(), n0 + 2);
    assert_eq!(list.add_paste("  "), vec![ListError::NoPath]);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn list_pairs_the_current_texture_with_a_height_map() {
    let mut list = TextureList::new();
    let n0 = list.len();
    let before = Arc::clone(list.texture());
    assert!(list.set_height_map(Some(&data("missing.png"))).is_err());
    assert!(Arc::ptr_eq(&before, list.texture()) && list.len() == n0);
    let i = list
        .set_height_map(Some(&data("formats/basn0g08.png")))
        .unwrap();
    assert_eq!((i, list.current(), list.len()), (n0, n0, n0 + 1));
    assert!(
        list.current_entry()
            .label
            .starts_with("brick (built-in) + ")
    );
    // Same colours as the brick, other heights.
    let brick = procedural::brick();
    let now = list.texture().base();
    assert!(
        now.texels
            .iter()
            .zip(&brick.base().texels)
            .all(|(a, b)| a[..3] == b[..3])
    );
    assert_ne!(now, brick.base());
    // Back to its own heights: the plain brick entry, not a new one.
    assert_eq!(list.set_height_map(None).unwrap(), 0);
    assert_eq!(list.len(), n0 + 1);
}

#[test]
fn list_from_command_line_arguments() {
    let images = vec![
        data("formats/basn2c08.xpm"),
        data("missing.png"),
        data("formats/basn0g08.pgm"),
    ];
    let (list, errors) = TextureList::from_args(&images, Some(&data("formats/basn0g08.png")));
    assert_eq!(errors.len(), 1);
    assert!(errors[0].to_string().contains("missing.png"));
    assert_eq!(list.len(), builtins().len() + 2);
    assert_eq!(list.current(), builtins().len());
    assert!(list.current_entry().label.contains("basn2c08.xpm + "));
    let grey = load_texture(&data("formats/basn0g08.png")).unwrap();
    for (t, g) in list.texture().base().texels.iter().zip(&grey.base().texels) {
        assert_eq!(t[3], g[0]);
    }
    let (list, errors) = TextureList::from_args(&[], None);
    assert!(errors.is_empty() && list.current() == 0);
}

/// The other formats the `image` crate decodes: a PngSuite picture encoded
/// by the crate itself, read back through the loader. Lossless formats give
/// the same texels; GIF (palette), JPEG and Radiance HDR come back close.
#[test]
fn every_other_decoded_format_round_trips() {
    use image::{DynamicImage, ImageFormat};
    let path = data("formats/basn6a08.png");
    let png = load_texture(&path).unwrap();
    let img = relief_texture::picture::open(&path).unwrap();
    let rgba8 = DynamicImage::ImageRgba8(img.to_rgba8());
    let rgb8 = DynamicImage::ImageRgb8(img.to_rgb8());
    let cases: Vec<(&str, ImageFormat, DynamicImage, f32)> = vec![
        ("t.tiff", ImageFormat::Tiff, rgba8.clone(), 0.0),
        ("t.qoi", ImageFormat::Qoi, rgba8.clone(), 0.0),
        ("t.webp", ImageFormat::WebP, rgba8.clone(), 0.0),
        (
            "t.ff",
            ImageFormat::Farbfeld,
            DynamicImage::ImageRgba16(img.to_rgba16()),
            0.0,
        ),
        ("t.ico", ImageFormat::Ico, rgba8.clone(), 0.0),
        (
            "t.exr",
            ImageFormat::OpenExr,
            DynamicImage::ImageRgba32F(img.to_rgba32f()),
            1e-6,
        ),
        ("t.gif", ImageFormat::Gif, rgba8.clone(), 0.1),
        ("t.jpg", ImageFormat::Jpeg, rgb8.clone(), 0.1),
        (
            "t.hdr",
            ImageFormat::Hdr,
            DynamicImage::ImageRgb32F(img.to_rgb32f()),
            0.02,
        ),
    ];
    for (name, format, picture, tolerance) in cases {
        let bytes = relief_texture::picture::encode(&picture, format).unwrap();
        let tex = load_texture_from_bytes(name, &bytes).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!((tex.width(), tex.height()), (32, 32), "{name}");
        let has_alpha = picture.color().has_alpha();
        let mut worst = 0.0f32;
        for (t, p) in tex.base().texels.iter().zip(&png.base().texels) {
            // Colour where the original is opaque enough to be seen.
            if p[3] > 0.5 || !has_alpha {
                for c in 0..3 {
                    worst = worst.max((t[c] - p[c]).abs());
                }
            }
            if has_alpha && format != ImageFormat::Gif {
                worst = worst.max((t[3] - p[3]).abs());
            }
        }
        assert!(worst <= tolerance, "{name}: off by {worst}");
    }
}

/// Texels of two textures agree within `tolerance`.
fn assert_same_texels(a: &Texture, b: &Texture, tolerance: f32, what: &str) {
    assert_eq!((a.width(), a.height()), (b.width(), b.height()), "{what}");
    for (t, u) in a.base().texels.iter().zip(&b.base().texels) {
        for c in 0..4 {
            assert!((t[c] - u[c]).abs() <= tolerance, "{what}: {t:?} vs {u:?}");
        }
    }
}

fn encoded(picture: &image::DynamicImage, format: image::ImageFormat) -> Vec<u8> {
    relief_texture::picture::encode(picture, format).unwrap()
}

#[test]
fn valid_variants_the_decoder_refuses_load_as_their_plain_form() {
    use image::{DynamicImage, ImageFormat};
    let img = relief_texture::picture::open(data("formats/basn2c08.png")).unwrap();

    // HDR signed `#?RGBE` instead of `#?RADIANCE`: the same picture.
    let hdr = encoded(
        &DynamicImage::ImageRgb32F(img.to_rgb32f()),
        ImageFormat::Hdr,
    );
    let plain = load_texture_from_bytes("a.hdr", &hdr).unwrap();
    assert!(hdr.starts_with(b"#?RADIANCE\n"));
    let rgbe = [b"#?RGBE".as_slice(), &hdr[10..]].concat();
    let tex = load_texture_from_bytes("b.hdr", &rgbe).unwrap_or_else(|e| panic!("{e}"));
    assert_same_texels(&tex, &plain, 0.0, "#?RGBE");
    // The small file made byte by byte: pixel (1, 1) is (60, 100, 160) / 255
    // within RGBE's 8-bit mantissa.
    let small = load_texture(&data("variants/rgbe.hdr")).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!((small.width(), small.height()), (4, 3));
    let t = small.base().texels.at(4 + 1);
    for (c, want) in [60.0f32, 100.0, 160.0].iter().enumerate() {
        assert!((t[c] - want / 255.0).abs() < 0.01, "{t:?}");
    }

    // GIF with an extension block of an unknown label after the colour
    // table: skipped, the picture is the same.
    let gif = encoded(&DynamicImage::ImageRgba8(img.to_rgba8()), ImageFormat::Gif);
    let plain = load_texture_from_bytes("a.gif", &gif).unwrap();
    let table = if gif[10] & 0x80 != 0 {
        3 << ((gif[10] & 7) + 1)
    } else {
        0
    };
    let at = 13 + table;
    let unknown = [&gif[..at], b"\x21\x99\x03abc\x02xy\x00", &gif[at..]].concat();
    assert!(
        relief_texture::picture::decode(&unknown).is_err(),
        "the crate refuses it"
    );
    let tex = load_texture_from_bytes("b.gif", &unknown).unwrap_or_else(|e| panic!("{e}"));
    assert_same_texels(&tex, &plain, 0.0, "GIF extension");

    // OS/2 2.x BMP: the 40-byte header grown to 64 (24 bytes of OS/2
    // fields, zero), offsets moved.
    let bmp = encoded(&DynamicImage::ImageRgb8(img.to_rgb8()), ImageFormat::Bmp);
    let plain = load_texture_from_bytes("a.bmp", &bmp).unwrap();
    assert_eq!(u32::from_le_bytes(bmp[14..18].try_into().unwrap()), 40);
    let mut os2 = [&bmp[..54], &[0u8; 24], &bmp[54..]].concat();
    os2[14..18].copy_from_slice(&64u32.to_le_bytes());
    let size = os2.len() as u32;
    os2[2..6].copy_from_slice(&size.to_le_bytes());
    let offset = u32::from_le_bytes(bmp[10..14].try_into().unwrap()) + 24;
    os2[10..14].copy_from_slice(&offset.to_le_bytes());
    assert!(
        relief_texture::picture::decode(&os2).is_err(),
        "the crate refuses it"
    );
    let tex = load_texture_from_bytes("b.bmp", &os2).unwrap_or_else(|e| panic!("{e}"));
    assert_same_texels(&tex, &plain, 0.0, "OS/2 BMP");

    // ICO holding grey and RGB PNGs (as Pillow writes them): the largest
    // PNG's picture.
    for (name, picture) in [
        ("grey", DynamicImage::ImageLuma8(img.to_luma8())),
        ("rgb", DynamicImage::ImageRgb8(img.to_rgb8())),
    ] {
        let png = encoded(&picture, ImageFormat::Png);
        let small = encoded(&picture.thumbnail(16, 16), ImageFormat::Png);
        let mut ico = vec![0, 0, 1, 0, 2, 0];
        let first = 6 + 2 * 16;
        for (side, data, at) in [(16u8, &small, first), (32, &png, first + small.len())] {
            ico.extend_from_slice(&[side, side, 0, 0, 1, 0, 32, 0]);
            ico.extend_from_slice(&(data.len() as u32).to_le_bytes());
            ico.extend_from_slice(&(at as u32).to_le_bytes());
        }
        ico.extend_from_slice(&small);
        ico.extend_from_slice(&png);
        assert!(
            relief_texture::picture::decode(&ico).is_err(),
            "the crate refuses it"
        );
        let tex = load_texture_from_bytes("b.ico", &ico).unwrap_or_else(|e| panic!("{e}"));
        let plain = load_texture_from_bytes("a.png", &png).unwrap();
        assert_same_texels(&tex, &plain, 0.0, name);
    }
    // The files Pillow wrote (32×32, from a 16×8 ramp).
    for name in ["grey.ico", "rgb.ico"] {
        let tex =
            load_texture(&data(&format!("variants/{name}"))).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!((tex.width(), tex.height()), (32, 32), "{name}");
    }
}

#[test]
fn decoder_internals_stay_out_of_messages() {
    let dir = scratch("internals");
    // A critical chunk whose name holds a control byte.
    let good = std::fs::read(data("pngsuite/basn2c08.png")).unwrap();
    let mut chunk = b"\0\0\0\x02A\x01bcxx".to_vec();
    let crc = crc32(&chunk[4..]);
    chunk.extend_from_slice(&crc.to_be_bytes());
    let png = [&good[..33], &chunk, &good[33..]].concat();
    let path = dir.join("control.png");
    std::fs::write(&path, png).unwrap();
    let msg = load_texture(&path).unwrap_err().to_string();
    assert_clean_one_line(&msg);
    assert!(msg.contains("control.png") && msg.contains("A?bc"), "{msg}");
    assert!(
        !msg.contains("critical: true") && !msg.contains("ChunkType"),
        "{msg}"
    );

    // A JPEG cut short: zune's "I/O errors Not enough bytes".
    let img = relief_texture::picture::open(data("formats/basn2c08.png")).unwrap();
    let jpg = encoded(
        &image::DynamicImage::ImageRgb8(img.to_rgb8()),
        image::ImageFormat::Jpeg,
    );
    let e = load_texture_from_bytes("cut.jpg", &jpg[..jpg.len() / 2]).unwrap_err();
    assert_eq!(
        e.to_string(),
        "cut.jpg: corrupt or truncated JPEG file: ends too early"
    );

    // A GIF whose LZW data are scrambled: about the data, not the disk
    // ("invalid code in LZW stream" came as "cannot read: …").
    let gif = encoded(
        &image::DynamicImage::ImageRgba8(img.to_rgba8()),
        image::ImageFormat::Gif,
    );
    let start = gif.iter().rposition(|&b| b == 0x2C).unwrap();
    let mut bad = gif.clone();
    let end = bad.len() - 2;
    for b in &mut bad[start + 12..end] {
        *b ^= 0x5A;
    }
    let e = load_texture_from_bytes("bad.gif", &bad).unwrap_err();
    assert_eq!(
        e.to_string(),
        "bad.gif: corrupt or truncated GIF file: its LZW-compressed data does not decode"
    );
}

#[test]
fn tiff_twelve_bit_and_fax3_load() {
    // 12-bit samples, packed most significant bit first, rows padded to a
    // byte: grey 7×5 holds (587·i) mod 4096 at i = 16y + x; RGB 5×3 holds
    // (587·i, 1193·i + 100, 4095 − 331·i) mod 4096 (tests/data/variants/README.md).
    let v = |k: usize| (k % 4096) as f32 / 4095.0;
    let tex = load_texture(&data("variants/grey12.tif")).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!((tex.width(), tex.height()), (7, 5));
    for y in 0..5 {
        for x in 0..7 {
            let t = at(&tex, x, y);
            let g = v(587 * (16 * y + x));
            assert!((0..3).all(|c| (t[c] - g).abs() < 1e-6), "({x},{y}): {t:?}");
        }
    }
    let tex = load_texture(&data("variants/rgb12.tif")).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!((tex.width(), tex.height()), (5, 3));
    for y in 0..3 {
        for x in 0..5 {
            let i = 16 * y + x;
            let want = [v(587 * i), v(1193 * i + 100), 1.0 - v(331 * i)];
            let t = at(&tex, x, y);
            assert!(
                (0..3).all(|c| (t[c] - want[c]).abs() < 1e-6),
                "({x},{y}): {t:?}"
            );
        }
    }
    // CCITT group 3, 1-D, black is zero (Pillow's default): black where
    // (⌊x/5⌋ + ⌊y/4⌋) is even or x = y, white elsewhere, on all 23 rows.
    let tex = load_texture(&data("variants/fax3.tif")).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!((tex.width(), tex.height()), (37, 23));
    for y in 0..23 {
        for x in 0..37 {
            let black = (x / 5 + y / 4) % 2 == 0 || x == y;
            let t = at(&tex, x, y);
            assert_eq!(t[0], if black { 0.0 } else { 1.0 }, "({x},{y})");
        }
    }
    // The 2-D coded form is refused in a plain sentence.
    let e = load_texture(&data("variants/fax3_2d.tif")).unwrap_err();
    assert!(
        e.to_string()
            .ends_with("2-D coded CCITT group 3 fax data is not supported"),
        "{e}"
    );
}

#[test]
fn tiff_samples_the_decoder_library_refuses_load() {
    let g = |x: usize, y: usize| ((13 * (16 * y + x)) % 256) as f32 / 255.0;
    // Float grey holds g / 255; signed 8-bit g − 128, shown as 0..255.
    for (name, tolerance) in [("float.tif", 1e-6), ("signed8.tif", 1e-6)] {
        let tex =
            load_texture(&data(&format!("variants/{name}"))).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!((tex.width(), tex.height()), (16, 8), "{name}");
        for y in 0..8 {
            for x in 0..16 {
                let t = at(&tex, x, y);
                for c in 0..4 {
                    assert!(
                        (t[c] - g(x, y)).abs() <= tolerance,
                        "{name} ({x},{y}): {t:?}"
                    );
                }
            }
        }
    }
    // A palette picture: the colour map's entries, as Pillow reads them.
    let tex = load_texture(&data("variants/palette.tif")).unwrap_or_else(|e| panic!("{e}"));
    for ((x, y), rgb) in [
        ((0, 0), [5, 12, 19]),
        ((5, 3), [88, 95, 102]),
        ((15, 7), [104, 111, 118]),
    ] {
        let t = at(&tex, x, y);
        for c in 0..3 {
            // Pillow stores v·256 in the 16-bit map: within half a level.
            assert!(
                (t[c] - rgb[c] as f32 / 255.0).abs() < 0.5 / 255.0,
                "({x},{y}): {t:?}"
            );
        }
    }
}

/// Bytes a loaded texture ends up holding with every derived map built:
/// the base level, its mip chain, the dot3 normal map and that map's chain.
fn allocated_bytes(tex: &Texture) -> usize {
    let level_bytes = |l: &Level| l.texels.len() * l.texels.bytes_per_texel();
    let (map, _) = tex.normal_map(1.0);
    level_bytes(tex.base())
        + tex.mip_levels().iter().map(level_bytes).sum::<usize>()
        + map.normals.len() * map.normals.bytes_per_texel()
        + map.mip_levels().iter().map(level_bytes).sum::<usize>()
}

/// Pictures are kept at their precision, and what the budget reserves for
/// one covers what it allocates without reserving much more (the decoder's
/// buffers, freed before the derived maps exist, fit inside): 8-bit RGB
/// and RGBA, 16-bit and float pictures, each read back as loaded.
#[test]
fn reservation_matches_what_a_texture_allocates() {
    use image::{ImageFormat, Rgb, Rgb32FImage, RgbImage, Rgba, RgbaImage};
    let (w, h) = (96u32, 64u32);
    let encode =
        |img: image::DynamicImage, format| relief_texture::picture::encode(&img, format).unwrap();
    let rgb8 = RgbImage::from_fn(w, h, |x, y| Rgb([x as u8 * 2, y as u8 * 3, (x ^ y) as u8]));
    let rgba8 = RgbaImage::from_fn(w, h, |x, y| Rgba([x as u8, y as u8, 7, (x + y) as u8]));
    let rgb16 = image::ImageBuffer::<Rgb<u16>, _>::from_fn(w, h, |x, y| {
        Rgb([x as u16 * 600, y as u16 * 1000, 65535 - x as u16])
    });
    let float = Rgb32FImage::from_fn(w, h, |x, y| Rgb([x as f32 / 96.0, y as f32 / 64.0, 0.5]));
    // Past 64 K texels an 8-bit picture keeps 4 bytes a texel; below, its
    // base level also keeps an f32 copy for reading (16 more).
    let large = RgbImage::from_fn(257, 256, |x, y| Rgb([x as u8, y as u8, 9]));
    let cases = [
        ("rgb8.png", encode(rgb8.into(), ImageFormat::Png), 4 + 16),
        ("rgba8.png", encode(rgba8.into(), ImageFormat::Png), 4 + 16),
        ("large.png", encode(large.into(), ImageFormat::Png), 4),
        ("rgb16.png", encode(rgb16.into(), ImageFormat::Png), 8 + 16),
        ("float.exr", encode(float.into(), ImageFormat::OpenExr), 16),
    ];
    for (name, bytes, base_bytes) in cases {
        let tex = load_texture_from_bytes(name, &bytes).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(tex.base().texels.bytes_per_texel(), base_bytes, "{name}");
        let allocated = allocated_bytes(&tex) as u64;
        let reserved = tex.reserved_bytes();
        assert!(
            allocated <= reserved && reserved <= allocated + allocated / 4,
            "{name}: allocated {allocated}, reserved {reserved}"
        );
    }
    // An 8-bit picture's derived maps are 16-bit: 4 + 8/3 + 6 + 6/3 bytes
    // a texel, where f32 storage took 16 + 16/3 + 12 + 16/3.
    let per_texel = relief_core::budget::Precision::Unorm8.bytes_per_texel();
    assert!((per_texel - (4.0 + 8.0 / 3.0 + 6.0 + 2.0)).abs() < 1e-9);
    assert_eq!(
        relief_core::budget::texture_bytes_at(4096, 4096, relief_core::budget::Precision::Unorm8)
            >> 20,
        234
    );
}
