//! Colour mapping on numbers: the reference frame in 256 and 16 colours
//! against the former sRGB-distance mapping, measured in OKLab.
//!
//! `cargo test --release --test suite term::colour:: -- --nocapture` prints the table.

use std::sync::Arc;

use ratatui::style::Color;
use relief_core::framebuffer::Framebuffer;
use relief_core::settings::Settings;
use relief_pipeline::render::Renderer;
use relief_scene::Scene;
use relief_term::ColorDepth;
use relief_term::ansi::{cells, shown_picture};
use relief_term::color::{nearest_16, nearest_256, shown_rgb};
use relief_term::oklab::lab;
use relief_term::palette::{ANSI16, CUBE_LEVELS};

const BACKGROUND: [u8; 3] = relief_scene::BACKGROUND;

/// The former mapping, kept here as the baseline: per-channel rounding to
/// the cube or the grey of the mean, whichever is closer in sRGB.
mod before {
    use super::*;

    fn dist2(a: [u8; 3], b: [u8; 3]) -> u32 {
        a.iter()
            .zip(b)
            .map(|(&p, q)| (p as i32 - q as i32).pow(2) as u32)
            .sum()
    }

    fn step(v: u8) -> usize {
        match v {
            0..=47 => 0,
            48..=114 => 1,
            115..=154 => 2,
            155..=194 => 3,
            195..=234 => 4,
            _ => 5,
        }
    }

    pub fn nearest_256(rgb: [u8; 3]) -> u8 {
        let [r, g, b] = rgb.map(step);
        let cube = [CUBE_LEVELS[r], CUBE_LEVELS[g], CUBE_LEVELS[b]];
        let mean = (rgb[0] as u32 + rgb[1] as u32 + rgb[2] as u32) / 3;
        let grey_step = (mean.saturating_sub(3) / 10).min(23);
        let grey = [(8 + 10 * grey_step) as u8; 3];
        if dist2(rgb, grey) < dist2(rgb, cube) {
            232 + grey_step as u8
        } else {
            (16 + 36 * r + 6 * g + b) as u8
        }
    }

    pub fn nearest_16(rgb: [u8; 3]) -> usize {
        (0..16).min_by_key(|&i| dist2(rgb, ANSI16[i].0)).unwrap()
    }
}

fn reference_frame() -> Framebuffer {
    let scene = Scene::cube(Arc::new(relief_texture::decode::procedural::brick()), false);
    let mut fb = Framebuffer::new(320, 240);
    Renderer::new().render(&scene, &Settings::default(), &mut fb);
    fb
}

fn flat_frame() -> Framebuffer {
    let scene = Scene::cube(Arc::new(relief_texture::decode::procedural::brick()), false);
    let settings = Settings {
        shading: relief_core::settings::Shading::Flat,
        ..Settings::default()
    };
    let mut fb = Framebuffer::new(320, 240);
    Renderer::new().render(&scene, &settings, &mut fb);
    fb
}

/// The picture as the terminal would show it, through the view's widget.
fn shown(fb: &Framebuffer, depth: ColorDepth, dither: bool) -> Framebuffer {
    let buf = cells(fb, depth, dither, BACKGROUND);
    shown_picture(&buf, fb.width(), fb.height(), BACKGROUND)
}

fn mean_error(a: &Framebuffer, b: &Framebuffer) -> f32 {
    let n = a.pixels().len();
    a.pixels()
        .iter()
        .zip(b.pixels())
        .map(|(&p, &q)| lab(p).distance(lab(q)))
        .sum::<f32>()
        / n as f32
}

/// Fraction of the chromatic pixels (OKLab chroma over 0.04) shown as a grey.
fn chromatic_to_grey(a: &Framebuffer, b: &Framebuffer) -> f32 {
    let (mut n, mut grey) = (0, 0);
    for (&p, &q) in a.pixels().iter().zip(b.pixels()) {
        if lab(p).chroma() > 0.04 {
            n += 1;
            if lab(q).chroma() < 0.01 {
                grey += 1;
            }
        }
    }
    grey as f32 / n.max(1) as f32
}

/// Mean hue angle difference in degrees over the chromatic pixels that are
/// shown chromatic.
fn hue_angle_error(a: &Framebuffer, b: &Framebuffer) -> f32 {
    let (mut n, mut sum) = (0, 0.0);
    for (&p, &q) in a.pixels().iter().zip(b.pixels()) {
        let (p, q) = (lab(p), lab(q));
        if p.chroma() > 0.04 && q.chroma() > 0.01 {
            n += 1;
            let d = (p.b.atan2(p.a) - q.b.atan2(q.a)).to_degrees().abs();
            sum += d.min(360.0 - d);
        }
    }
    sum / n.max(1) as f32
}

/// The former mapping applied pixel by pixel (it had no background rule).
fn shown_before(fb: &Framebuffer, depth: ColorDepth) -> Framebuffer {
    let mut out = Framebuffer::new(fb.width(), fb.height());
    for (o, &p) in out.pixels_mut().iter_mut().zip(fb.pixels()) {
        *o = match depth {
            ColorDepth::Palette256 => shown_rgb(Color::Indexed(before::nearest_256(p)), p),
            ColorDepth::Palette16 => ANSI16[before::nearest_16(p)].0,
            ColorDepth::Truecolor => p,
        };
    }
    out
}

#[test]
fn reference_frame_keeps_its_hues_at_the_same_error() {
    let fb = reference_frame();
    println!(
        "{:<38} {:>8} {:>9} {:>9}",
        "reference frame 320x240", "mean ΔE", "hue °", "red→grey"
    );
    for depth in [ColorDepth::Palette256, ColorDepth::Palette16] {
        let old = shown_before(&fb, depth);
        let new = shown(&fb, depth, false);
        let dithered = shown(&fb, depth, true);
        let rows = [
            ("former (sRGB distance)", &old),
            ("OKLab", &new),
            ("OKLab + --dither", &dithered),
        ];
        for (name, pic) in rows {
            println!(
                "{:<38} {:>8.4} {:>9.1} {:>8.1}%",
                format!("{} {name}", depth.label()),
                mean_error(&fb, pic),
                hue_angle_error(&fb, pic),
                100.0 * chromatic_to_grey(&fb, pic)
            );
        }
        let (e_old, e_new) = (mean_error(&fb, &old), mean_error(&fb, &new));
        let (g_old, g_new) = (chromatic_to_grey(&fb, &old), chromatic_to_grey(&fb, &new));
        // The palette bounds the error: the former mapping was already within
        // a few per cent of the nearest entry. The gain is in the hues kept.
        if depth == ColorDepth::Palette256 {
            assert!(e_new <= 1.02 * e_old, "{e_new} vs {e_old}");
            assert!(g_new < 0.6 * g_old, "{g_new} vs {g_old}");
        } else {
            // 16 colours: dark tints now go to black (a grey) rather than to
            // a full primary, so fewer chromatic pixels stay chromatic than
            // in 256 colours, but still fewer go grey than before, and the
            // OKLab error does not grow (0.2042 → 0.2018; in CIELAB, where
            // dark differences weigh more, it halves: see the test below).
            assert!(e_new <= e_old, "{e_new} vs {e_old}");
            assert!(g_new < g_old, "{g_new} vs {g_old}");
        }
    }
}

/// Every pixel that is not the background is shown in another colour than
/// the background; in 16 colours, unless the background's entry (black) is
/// the pixel's nearest in CIELAB (`SUBSTITUTE_RATIO_16`).
fn assert_clear_of_background(fb: &Framebuffer, depth: ColorDepth, dither: bool) {
    let pic = shown(fb, depth, dither);
    let bg = shown_rgb(depth.map(BACKGROUND, false, 0, 0), BACKGROUND);
    let mut lit = 0;
    for (i, (&p, &q)) in fb.pixels().iter().zip(pic.pixels()).enumerate() {
        if p != BACKGROUND {
            lit += 1;
            if depth == ColorDepth::Palette16 && q == bg {
                let d = |e: [u8; 3]| delta_e(cielab(p), cielab(e));
                let others = ANSI16
                    .iter()
                    .filter(|(e, _)| *e != bg)
                    .map(|&(e, _)| d(e))
                    .fold(f64::MAX, f64::min);
                assert!(d(bg) < others, "{depth:?} pixel {i} {p:?}");
                continue;
            }
            assert_ne!(q, bg, "{depth:?} pixel {i} {p:?}");
        } else {
            assert_eq!(q, bg, "{depth:?}: the background is one colour");
        }
    }
    assert!(lit > 5000, "the cube is in the picture");
}

#[test]
fn no_lit_pixel_falls_on_the_background_entry() {
    for fb in [reference_frame(), flat_frame()] {
        for depth in [ColorDepth::Palette256, ColorDepth::Palette16] {
            assert_clear_of_background(&fb, depth, false);
            assert_clear_of_background(&fb, depth, true);
        }
    }
}

#[test]
fn the_flat_shaded_left_face_stays_apart_from_the_background() {
    let fb = flat_frame();
    let face = [39, 18, 19];
    assert!(
        fb.pixels().contains(&face),
        "the dark face is in the flat frame"
    );
    // The former mapping put both on grey 234 / black.
    assert_eq!(before::nearest_256(face), before::nearest_256(BACKGROUND));
    assert_eq!(before::nearest_16(face), before::nearest_16(BACKGROUND));
    let q = ColorDepth::Palette256.quantizer(BACKGROUND);
    assert_ne!(q.pick(face, false, 0, 0), q.pick(BACKGROUND, false, 0, 0));
    // In 16 colours the only entry near it is black, the background's: any
    // other (red 205,0,0 was taken) is 4 to 8 times as far in CIELAB.
    let q = ColorDepth::Palette16.quantizer(BACKGROUND);
    assert_eq!(q.pick(face, false, 0, 0), Color::Black);
}

#[test]
fn dark_tints_and_greys_keep_no_hue_in_16_colours() {
    let q = ColorDepth::Palette16.quantizer(BACKGROUND);
    // Near-black tints: black is nearest in RGB, CIELAB and OKLab alike
    // (they went to blue 0,0,238 and red 205,0,0).
    for dark in [[11, 3, 16], [38, 17, 12], [20, 10, 30], [5, 12, 6]] {
        assert_eq!(ANSI16[nearest_16(dark)].1, Color::Black, "{dark:?}");
        assert_eq!(q.pick(dark, false, 0, 0), Color::Black, "{dark:?}");
    }
    // Every grey goes to a grey entry (169..=190 went to cyan).
    let greys = [Color::Black, Color::DarkGray, Color::Gray, Color::White];
    for v in 0..=255u8 {
        let c = ANSI16[nearest_16([v; 3])].1;
        assert!(greys.contains(&c), "grey {v} -> {c:?}");
        for dither in [false, true] {
            for (x, y) in [(0, 0), (1, 0), (2, 1), (3, 3)] {
                let c = q.pick([v; 3], dither, x, y);
                assert!(greys.contains(&c), "grey {v} -> {c:?}");
            }
        }
    }
    // A real hue stays: the brick reds, a clear blue and green.
    assert_eq!(ANSI16[nearest_16([150, 62, 45])].1, Color::Red);
    let blue = ANSI16[nearest_16([40, 60, 200])].1;
    assert!([Color::Blue, Color::LightBlue].contains(&blue), "{blue:?}");
    assert_eq!(ANSI16[nearest_16([40, 180, 60])].1, Color::Green);
}

/// CIE 1976 L*a*b* (D65) of an sRGB colour: the measure the comparison
/// with other programs used (docs/colour.md).
fn cielab(rgb: [u8; 3]) -> [f64; 3] {
    let lin = rgb.map(|c| {
        let c = c as f64 / 255.0;
        if c <= 0.04045 {
            c / 12.92
        } else {
            ((c + 0.055) / 1.055).powf(2.4)
        }
    });
    let xyz = [
        (0.4124564 * lin[0] + 0.3575761 * lin[1] + 0.1804375 * lin[2]) / 0.95047,
        0.2126729 * lin[0] + 0.7151522 * lin[1] + 0.0721750 * lin[2],
        (0.0193339 * lin[0] + 0.1191920 * lin[1] + 0.9503041 * lin[2]) / 1.08883,
    ];
    let d = 6.0f64 / 29.0;
    let f = xyz.map(|t| {
        if t > d * d * d {
            t.cbrt()
        } else {
            t / (3.0 * d * d) + 4.0 / 29.0
        }
    });
    [
        116.0 * f[1] - 16.0,
        500.0 * (f[0] - f[1]),
        200.0 * (f[1] - f[2]),
    ]
}

/// CIE 1976 ΔE.
fn delta_e(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// Mean CIELAB ΔE between the frame and what a terminal shows, over the
/// pixels that are not the background.
fn object_delta_e(fb: &Framebuffer, pic: &Framebuffer) -> f64 {
    let (mut n, mut sum) = (0usize, 0.0f64);
    for (&p, &q) in fb.pixels().iter().zip(pic.pixels()) {
        if p != BACKGROUND {
            sum += delta_e(cielab(p), cielab(q));
            n += 1;
        }
    }
    sum / n as f64
}

#[test]
fn sixteen_colours_stay_near_the_full_colour_frame() {
    // The frames of the chafa comparison (docs/colour.md), at 160×96.
    let brick = Arc::new(relief_texture::decode::procedural::brick());
    let scenes = [
        ("cube", Scene::cube(brick.clone(), false)),
        (
            "sphere",
            Scene::model(relief_scene::sphere::sphere(), brick),
        ),
    ];
    for (model, scene) in scenes {
        let mut fb = Framebuffer::new(160, 96);
        Renderer::new().render(&scene, &Settings::default(), &mut fb);
        let plain = object_delta_e(&fb, &shown(&fb, ColorDepth::Palette16, false));
        let dithered = object_delta_e(&fb, &shown(&fb, ColorDepth::Palette16, true));
        let full256 = object_delta_e(&fb, &shown(&fb, ColorDepth::Palette256, false));
        println!(
            "{model}: 16 colours ΔE {plain:.1}, with --dither {dithered:.1}; 256 colours {full256:.1}"
        );
        // Measured 26.7 (cube) and 26.9 (sphere), from 63.5 and 68.2 before;
        // chafa -c 16 -p off: 32.5 and 31.7. 256 colours: 15.2 and 17.4.
        assert!(plain < 30.0, "{model}: {plain}");
        assert!(dithered < 32.0, "{model}: {dithered}");
        assert!(full256 < 18.0, "{model}: {full256}");
    }
}

#[test]
fn known_colours_map_to_the_expected_entries() {
    // Cube corners and palette colours map to themselves.
    let corners: [([u8; 3], u8); 8] = [
        ([0, 0, 0], 16),
        ([255, 0, 0], 196),
        ([0, 255, 0], 46),
        ([0, 0, 255], 21),
        ([255, 255, 0], 226),
        ([0, 255, 255], 51),
        ([255, 0, 255], 201),
        ([255, 255, 255], 231),
    ];
    for (c, want) in corners {
        assert_eq!(nearest_256(c), want, "{c:?}");
    }
    // Pure greys go to the grey ramp (or the cube's grey when it is closer).
    for (c, want) in [
        (8, 232),
        (18, 233),
        (128, 244),
        (238, 255),
        (100, 241),
        (135, 102),
    ] {
        assert_eq!(nearest_256([c; 3]), want, "grey {c}");
    }
    // The background is a dark blue grey: the grey of its lightness.
    assert_eq!(nearest_256(BACKGROUND), 234);
    // Brick reds (lit and in shade) stay red: a cube entry with more red
    // than green and blue, not a grey.
    for brick in [[175, 75, 50], [150, 62, 45], [110, 50, 40]] {
        let i = nearest_256(brick) - 16;
        assert!(i < 216, "{brick:?} -> grey {}", i + 16);
        let (r, g, b) = (i / 36, i / 6 % 6, i % 6);
        assert!(r > g && r > b, "{brick:?} -> {}", i + 16);
    }
    // 16 colours: the reds go to red, the background to black.
    assert_eq!(ANSI16[nearest_16([175, 75, 50])].1, Color::Red);
    assert_eq!(ANSI16[nearest_16([250, 10, 10])].1, Color::LightRed);
    assert_eq!(ANSI16[nearest_16(BACKGROUND)].1, Color::Black);
    assert_eq!(ANSI16[nearest_16([120, 125, 130])].1, Color::DarkGray);
}

/// Writes `assets/colour-256-before.png` and `assets/colour-16-before.png`:
/// the reference frame through the former mapping (the README's "before").
/// `cargo test --release --test suite term::colour:: -- --ignored`
#[test]
#[ignore]
fn write_the_before_pictures() {
    let fb = reference_frame();
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets");
    for (depth, name) in [
        (ColorDepth::Palette256, "colour-256-before.png"),
        (ColorDepth::Palette16, "colour-16-before.png"),
    ] {
        shown_before(&fb, depth).save_png(&dir.join(name)).unwrap();
    }
}
