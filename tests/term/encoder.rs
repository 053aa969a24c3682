//! The framebuffer → cell encoders (half blocks and the finer symbol sets) and the colour-depth mapping.

use ratatui::buffer::Buffer;
use ratatui::layout::Rect;
use ratatui::style::Color;
use ratatui::widgets::Widget;
use relief_core::framebuffer::Framebuffer;
use relief_term::color::{nearest_16, nearest_256};
use relief_term::palette::ANSI16;
use relief_term::{ColorDepth, HalfBlocks};

const PAD: [u8; 3] = [16, 24, 32];

fn rgb(c: [u8; 3]) -> Color {
    Color::Rgb(c[0], c[1], c[2])
}

fn encode(fb: &Framebuffer, area: Rect, depth: ColorDepth) -> Buffer {
    let mut buf = Buffer::empty(area);
    HalfBlocks {
        fb,
        depth,
        dither: false,
        pad: PAD,
    }
    .render(area, &mut buf);
    buf
}

/// A 3×4 framebuffer with distinct pixels, except column 1 whose rows 0 and 1 match.
fn known_fb(height: usize) -> Framebuffer {
    let mut fb = Framebuffer::new(3, height);
    for y in 0..height {
        for x in 0..3 {
            fb.set(x, y, [10 * x as u8 + 1, 40 * y as u8 + 2, 7]);
        }
    }
    fb.set(1, 1, fb.get(1, 0));
    fb
}

#[test]
fn every_cell_has_upper_pixel_as_fg_and_lower_as_bg() {
    let fb = known_fb(4);
    let buf = encode(&fb, Rect::new(0, 0, 3, 2), ColorDepth::Truecolor);
    for row in 0..2u16 {
        for col in 0..3u16 {
            let cell = &buf[(col, row)];
            let upper = fb.get(col as usize, 2 * row as usize);
            let lower = fb.get(col as usize, 2 * row as usize + 1);
            if upper == lower {
                assert_eq!(cell.symbol(), " ", "({col},{row})");
                assert_eq!(cell.bg, rgb(lower));
            } else {
                assert_eq!(cell.symbol(), "▀", "({col},{row})");
                assert_eq!(cell.fg, rgb(upper));
                assert_eq!(cell.bg, rgb(lower));
            }
        }
    }
    // Column 1, row 0 is the equal pair: a space with the shared colour.
    assert_eq!(buf[(1, 0)].symbol(), " ");
    assert_eq!(buf[(1, 0)].bg, rgb(fb.get(1, 0)));
}

#[test]
fn odd_height_leaves_the_last_lower_half_as_background() {
    let fb = known_fb(3);
    let buf = encode(&fb, Rect::new(0, 0, 3, 2), ColorDepth::Truecolor);
    for col in 0..3u16 {
        let cell = &buf[(col, 1)];
        assert_eq!(cell.symbol(), "▀");
        assert_eq!(cell.fg, rgb(fb.get(col as usize, 2)));
        assert_eq!(cell.bg, rgb(PAD));
    }
}

#[test]
fn cells_beyond_the_framebuffer_are_background_and_offsets_are_respected() {
    let fb = known_fb(2);
    let area = Rect::new(2, 1, 5, 2);
    let mut buf = Buffer::empty(Rect::new(0, 0, 8, 4));
    HalfBlocks {
        fb: &fb,
        depth: ColorDepth::Truecolor,
        dither: false,
        pad: PAD,
    }
    .render(area, &mut buf);
    assert_eq!(buf[(2, 1)].fg, rgb(fb.get(0, 0)));
    assert_eq!(buf[(4, 1)].bg, rgb(fb.get(2, 1)));
    for (x, y) in [(5, 1), (6, 1), (2, 2), (6, 2)] {
        assert_eq!(buf[(x, y)].symbol(), " ");
        assert_eq!(buf[(x, y)].bg, rgb(PAD));
    }
    // Outside the area nothing was touched.
    assert_eq!(buf[(0, 0)], ratatui::buffer::Cell::default());
    assert_eq!(buf[(7, 3)], ratatui::buffer::Cell::default());
}

#[test]
fn empty_framebuffer_and_empty_area_do_not_panic() {
    let fb = Framebuffer::new(0, 0);
    let buf = encode(&fb, Rect::new(0, 0, 2, 1), ColorDepth::Palette256);
    assert_eq!(buf[(1, 0)].symbol(), " ");
    let fb = known_fb(4);
    let _ = encode(&fb, Rect::new(0, 0, 0, 0), ColorDepth::Truecolor);
}

#[test]
fn known_colours_map_to_their_xterm_256_index() {
    let cases: [([u8; 3], u8); 12] = [
        ([0, 0, 0], 16),
        ([255, 255, 255], 231),
        ([255, 0, 0], 196),
        ([0, 255, 0], 46),
        ([0, 0, 255], 21),
        ([95, 135, 175], 67),
        ([128, 128, 128], 244),
        ([8, 8, 8], 232),
        ([238, 238, 238], 255),
        ([100, 100, 100], 241),
        ([255, 135, 0], 208),
        ([16, 24, 32], 234),
    ];
    for (c, want) in cases {
        assert_eq!(nearest_256(c), want, "{c:?}");
    }
}

#[test]
fn palette_256_cells_use_indexed_colours() {
    let mut fb = Framebuffer::new(1, 2);
    fb.set(0, 0, [255, 0, 0]);
    fb.set(0, 1, [0, 0, 255]);
    let buf = encode(&fb, Rect::new(0, 0, 1, 1), ColorDepth::Palette256);
    assert_eq!(buf[(0, 0)].fg, Color::Indexed(196));
    assert_eq!(buf[(0, 0)].bg, Color::Indexed(21));
    // Two colours that round to the same index make a space.
    fb.set(0, 1, [250, 5, 5]);
    let buf = encode(&fb, Rect::new(0, 0, 1, 1), ColorDepth::Palette256);
    assert_eq!(buf[(0, 0)].symbol(), " ");
    assert_eq!(buf[(0, 0)].bg, Color::Indexed(196));
}

#[test]
fn sixteen_colours_pick_the_nearest_ansi_colour() {
    assert_eq!(ANSI16[nearest_16([250, 10, 10])].1, Color::LightRed);
    assert_eq!(ANSI16[nearest_16([0, 0, 0])].1, Color::Black);
    assert_eq!(ANSI16[nearest_16([120, 125, 130])].1, Color::DarkGray);
    assert_eq!(
        ColorDepth::Palette16.map([0, 200, 210], false, 0, 0),
        Color::Cyan
    );
}

#[test]
fn dithering_mixes_palette_colours_on_gradients_only() {
    // A dark blue between black and the first cube blue: the table gives it
    // a dither partner, and ordered dithering uses both entries.
    let c = [0, 0, 50];
    let seen: std::collections::HashSet<_> = (0..4)
        .flat_map(|y| (0..4).map(move |x| ColorDepth::Palette256.map(c, true, x, y)))
        .collect();
    assert!(seen.len() >= 2, "{seen:?}");
    let plain: std::collections::HashSet<_> = (0..4)
        .flat_map(|y| (0..4).map(move |x| ColorDepth::Palette256.map(c, false, x, y)))
        .collect();
    assert_eq!(plain.len(), 1);
    // Through the widget: a flat area of that colour stays one colour even
    // with dithering on; a gradient through it is dithered.
    let colours = |fb: &Framebuffer| {
        let area = Rect::new(0, 0, fb.width() as u16, fb.height().div_ceil(2) as u16);
        let mut buf = Buffer::empty(area);
        HalfBlocks {
            fb,
            depth: ColorDepth::Palette256,
            dither: true,
            pad: [16, 24, 32],
        }
        .render(area, &mut buf);
        buf.content
            .iter()
            .flat_map(|c| [c.fg, c.bg])
            .filter(|&c| c != Color::Reset)
            .collect::<std::collections::HashSet<_>>()
    };
    let mut flat = Framebuffer::new(16, 16);
    flat.pixels_mut().fill(c);
    assert_eq!(colours(&flat).len(), 1);
    let mut ramp = Framebuffer::new(16, 16);
    for y in 0..16 {
        for x in 0..16 {
            ramp.set(x, y, [0, 0, 40 + x as u8]);
        }
    }
    assert!(colours(&ramp).len() >= 2);
}

#[test]
fn depth_detection_reads_colorterm_then_term() {
    use ColorDepth::*;
    assert_eq!(
        ColorDepth::detect(Some("truecolor"), Some("xterm")),
        Truecolor
    );
    assert_eq!(ColorDepth::detect(Some("24bit"), None), Truecolor);
    assert_eq!(ColorDepth::detect(None, Some("xterm-direct")), Truecolor);
    assert_eq!(ColorDepth::detect(None, Some("xterm-256color")), Palette256);
    assert_eq!(
        ColorDepth::detect(Some(""), Some("tmux-256color")),
        Palette256
    );
    assert_eq!(ColorDepth::detect(None, Some("linux")), Palette16);
    assert_eq!(ColorDepth::detect(None, None), Palette256);
}

// ---- Sub-cell symbol sets -------------------------------------------------

use relief_term::Symbols;
use relief_term::cells::shown_picture;
use relief_term::fit::{error, fit};

/// Fine rows of a cell in the name checks: 12 is a multiple of 2, 3 and 4.
const FINE: usize = 12;

/// The picture a Unicode block character name describes, on a 2 × 12 grid
/// (`[column][fine row]`), built from the words of the name alone.
fn picture_of_name(name: &str) -> [[bool; FINE]; 2] {
    let mut g = [[false; FINE]; 2];
    let mut fill = |cols: &[usize], rows: std::ops::Range<usize>| {
        for &c in cols {
            for r in rows.clone() {
                g[c][r] = true;
            }
        }
    };
    let both = [0, 1];
    if let Some(digits) = name.strip_prefix("BLOCK SEXTANT-") {
        for d in digits.bytes().map(|b| (b - b'1') as usize) {
            fill(&[d % 2], d / 2 * 4..d / 2 * 4 + 4);
        }
    } else if let Some(digits) = name.strip_prefix("BLOCK OCTANT-") {
        for d in digits.bytes().map(|b| (b - b'1') as usize) {
            fill(&[d % 2], d / 2 * 3..d / 2 * 3 + 3);
        }
    } else if let Some(parts) = name.strip_prefix("QUADRANT ") {
        for part in parts.split(" AND ") {
            let rows = if part.starts_with("UPPER") {
                0..6
            } else {
                6..12
            };
            let col = usize::from(part.ends_with("RIGHT"));
            fill(&[col], rows);
        }
    } else {
        let (cols, rows): (&[usize], _) = match name {
            "FULL BLOCK" => (&both, 0..12),
            "UPPER HALF BLOCK" => (&both, 0..6),
            "LOWER HALF BLOCK" => (&both, 6..12),
            "LEFT HALF BLOCK" => (&[0], 0..12),
            "RIGHT HALF BLOCK" => (&[1], 0..12),
            "UPPER ONE QUARTER BLOCK" => (&both, 0..3),
            "LOWER ONE QUARTER BLOCK" => (&both, 9..12),
            "UPPER THREE QUARTERS BLOCK" => (&both, 0..9),
            "LOWER THREE QUARTERS BLOCK" => (&both, 3..12),
            "MIDDLE LEFT ONE QUARTER BLOCK" => (&[0], 3..9),
            "MIDDLE RIGHT ONE QUARTER BLOCK" => (&[1], 3..9),
            "LEFT HALF UPPER ONE QUARTER BLOCK" => (&[0], 0..3),
            "RIGHT HALF UPPER ONE QUARTER BLOCK" => (&[1], 0..3),
            "LEFT HALF LOWER ONE QUARTER BLOCK" => (&[0], 9..12),
            "RIGHT HALF LOWER ONE QUARTER BLOCK" => (&[1], 9..12),
            other => panic!("no picture for {other}"),
        };
        fill(cols, rows);
    }
    g
}

/// The picture a mask of `symbols` stands for on the same grid (a
/// one-column set covers both columns).
fn picture_of_mask(symbols: Symbols, mask: u8) -> [[bool; FINE]; 2] {
    let mut g = [[false; FINE]; 2];
    let (cols, rows) = (symbols.columns(), symbols.rows());
    for (c, column) in g.iter_mut().enumerate() {
        for (r, fine) in column.iter_mut().enumerate() {
            let pixel = (r / (FINE / rows)) * cols + c.min(cols - 1);
            *fine = mask >> pixel & 1 == 1;
        }
    }
    g
}

#[test]
fn every_glyph_draws_the_picture_its_unicode_name_describes() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/unicode/block-glyphs.txt"
    ))
    .unwrap();
    let names: std::collections::HashMap<char, &str> = text
        .lines()
        .filter(|l| !l.starts_with('#'))
        .map(|l| {
            let (cp, name) = l.split_once(';').unwrap();
            (
                char::from_u32(u32::from_str_radix(cp, 16).unwrap()).unwrap(),
                name,
            )
        })
        .collect();
    let mut checked = 0;
    for symbols in Symbols::ALL {
        for mask in 0..1u16 << symbols.pixels() {
            let mask = mask as u8;
            let glyph = symbols.glyph(mask);
            let drawn = if glyph == ' ' {
                [[false; FINE]; 2]
            } else {
                let name = names
                    .get(&glyph)
                    .unwrap_or_else(|| panic!("{glyph:?} unnamed"));
                picture_of_name(name)
            };
            assert_eq!(
                drawn,
                picture_of_mask(symbols, mask),
                "{symbols:?} {mask:#04x} {glyph:?}"
            );
            checked += 1;
        }
    }
    assert_eq!(checked, 4 + 16 + 64 + 256);
    // The octant block proper: 230 characters, the sextants 60.
    assert_eq!(
        names
            .values()
            .filter(|n| n.starts_with("BLOCK OCTANT-"))
            .count(),
        230
    );
    assert_eq!(
        names
            .values()
            .filter(|n| n.starts_with("BLOCK SEXTANT-"))
            .count(),
        60
    );
}

/// The least error over every two-colour picture of `pixels`: each of the
/// 2^n masks with both colours at their exact (real) means, rounded.
fn brute_force_error(pixels: &[[u8; 3]]) -> u64 {
    let n = pixels.len();
    (0..1u32 << n)
        .map(|mask| {
            let mean = |set: bool| {
                let group: Vec<_> = (0..n).filter(|&i| (mask >> i & 1 == 1) == set).collect();
                let mut m = [0u8; 3];
                if !group.is_empty() {
                    for (c, v) in m.iter_mut().enumerate() {
                        let s: u32 = group.iter().map(|&i| u32::from(pixels[i][c])).sum();
                        *v = ((s as f64 / group.len() as f64).round()) as u8;
                    }
                }
                m
            };
            error(pixels, mask as u8, mean(true), mean(false))
        })
        .min()
        .unwrap()
}

#[test]
fn the_fit_is_as_good_as_trying_every_mask() {
    // Hand-made cells: an edge, a diagonal, a lone highlight, three
    // colours, noise from a fixed LCG, and flat.
    let a = [200, 40, 30];
    let b = [10, 20, 90];
    let mut cells: Vec<Vec<[u8; 3]>> = vec![
        vec![a, a, b, b],
        vec![a, b, b, a, a, b],
        vec![b, b, b, b, b, [255, 255, 255], b, b],
        vec![a, b, [120, 120, 120], a, b, [128, 128, 128], a, b],
        vec![a; 8],
        vec![a, b],
    ];
    let mut seed = 12345u32;
    for n in [2, 4, 6, 8, 8, 8, 6, 4] {
        cells.push(
            (0..n)
                .map(|_| {
                    [0; 3].map(|_: u8| {
                        seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
                        (seed >> 24) as u8
                    })
                })
                .collect(),
        );
    }
    for cell in &cells {
        let f = fit(cell);
        let got = error(cell, f.mask, f.fg, f.bg);
        let best = brute_force_error(cell);
        // Rounding the means to levels can cost at most ¼ level² a channel.
        assert!(
            got <= best + cell.len() as u64 * 3 / 4 + 1,
            "{cell:?}: {got} vs {best}"
        );
        assert_eq!(
            f.mask >> (cell.len() - 1),
            0,
            "the last pixel is background"
        );
    }
    // A clean two-colour cell is reproduced exactly, with the right split.
    let f = fit(&[a, a, b, b, a, b]);
    assert_eq!((f.mask, f.fg, f.bg), (0b010011, a, b));
    assert_eq!(error(&[a, a, b, b, a, b], f.mask, f.fg, f.bg), 0);
}

#[test]
fn a_rendered_frame_rebuilds_the_fitted_blocks() {
    // A frame whose cells are each exactly two colours: the cells must
    // show it pixel for pixel, for every set.
    for symbols in Symbols::ALL {
        let (w, h) = (4 * symbols.columns() + 1, 3 * symbols.rows() + 1);
        let mut fb = Framebuffer::new(w, h);
        let mut seed = 7u32;
        for y in 0..h {
            for x in 0..w {
                seed = seed.wrapping_mul(1_103_515_245).wrapping_add(12345);
                let cell = (x / symbols.columns() + 5 * (y / symbols.rows())) as u8;
                let on = seed >> 16 & 1 == 1;
                fb.set(
                    x,
                    y,
                    if on {
                        [cell * 20, 200, 9]
                    } else {
                        [3, cell * 10, 250]
                    },
                );
            }
        }
        // The ragged last column and row of cells mix in the pad: fitted too.
        let buf = relief_term::ansi::symbol_cells(&fb, symbols, ColorDepth::Truecolor, false, PAD);
        assert_eq!(
            (buf.area.width as usize, buf.area.height as usize),
            (5, 4),
            "{symbols:?}"
        );
        let shown = shown_picture(&buf, symbols, w, h, PAD);
        for y in 0..h {
            for x in 0..w {
                let full_cell = x < 4 * symbols.columns() && y < 3 * symbols.rows();
                if full_cell {
                    assert_eq!(shown.get(x, y), fb.get(x, y), "{symbols:?} at {x},{y}");
                }
            }
        }
        // Each cell is the fit of its pixels: colours and glyph.
        for cy in 0..4 {
            for cx in 0..5 {
                let mut px = Vec::new();
                for i in 0..symbols.pixels() {
                    let (x, y) = (
                        cx * symbols.columns() + i % symbols.columns(),
                        cy * symbols.rows() + i / symbols.columns(),
                    );
                    px.push(if x < w && y < h { fb.get(x, y) } else { PAD });
                }
                let f = fit(&px);
                let cell = &buf[(cx as u16, cy as u16)];
                assert_eq!(cell.bg, rgb(f.bg));
                if f.mask != 0 {
                    assert_eq!(cell.symbol(), symbols.glyph(f.mask).to_string());
                    assert_eq!(cell.fg, rgb(f.fg));
                }
            }
        }
    }
}

#[test]
fn symbol_text_has_lf_rows_and_one_cell_per_glyph() {
    let mut fb = Framebuffer::new(8, 8);
    for y in 0..8 {
        for x in 0..8 {
            fb.set(x, y, [(x * 30) as u8, (y * 30) as u8, ((x ^ y) * 20) as u8]);
        }
    }
    for symbols in Symbols::ALL {
        let mut out = Vec::new();
        relief_term::ansi::write_symbol_text(
            &fb,
            symbols,
            ColorDepth::Truecolor,
            false,
            PAD,
            b"\n",
            &mut out,
        )
        .unwrap();
        let text = String::from_utf8(out).unwrap();
        assert!(!text.contains('\r'), "{symbols:?}");
        let (cols, rows) = symbols.cells_for_pixels(8, 8);
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), rows, "{symbols:?}");
        for line in lines {
            // Strip SGR sequences; what remains is one glyph per cell.
            let mut glyphs = 0;
            let mut chars = line.chars();
            while let Some(c) = chars.next() {
                if c == '\x1b' {
                    for c in chars.by_ref() {
                        if c.is_ascii_alphabetic() {
                            break;
                        }
                    }
                } else {
                    assert!(symbols.mask_of(c).is_some(), "{c:?}");
                    glyphs += 1;
                }
            }
            assert_eq!(glyphs, cols, "{symbols:?} {line:?}");
        }
    }
}

// ---- Pixel formats: decode what was encoded -------------------------------

use relief_term::{kitty, sixel};

/// A frame of pseudo-random pixels; `colours` distinct values at most
/// (0: any).
fn noisy_fb(w: usize, h: usize, colours: u32) -> Framebuffer {
    let mut fb = Framebuffer::new(w, h);
    let mut seed = 99u32;
    for y in 0..h {
        for x in 0..w {
            seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            let v = if colours == 0 {
                seed
            } else {
                (seed >> 8) % colours
            };
            let c = if colours == 0 {
                [(v >> 24) as u8, (v >> 16) as u8, (v >> 8) as u8]
            } else {
                [(v * 37 % 256) as u8, (v * 11 % 256) as u8, (v * 5) as u8]
            };
            fb.set(x, y, c);
        }
    }
    fb
}

#[test]
fn kitty_payload_decodes_to_the_frame() {
    use base64::Engine;
    use std::io::Read;
    let fb = noisy_fb(70, 50, 0);
    let mut out = Vec::new();
    kitty::write_image(&fb, Some((35, 12)), &mut out).unwrap();
    let text = String::from_utf8(out).unwrap();
    let mut payload = String::new();
    let commands: Vec<&str> = text.split("\x1b_G").skip(1).collect();
    assert!(commands.len() > 2, "a 10 kB frame takes several chunks");
    for (i, command) in commands.iter().enumerate() {
        let body = command
            .strip_suffix("\x1b\\")
            .expect("each chunk ends with ST");
        let (keys, data) = body.split_once(';').unwrap();
        assert!(data.len() <= kitty::CHUNK);
        let more = if i + 1 < commands.len() { "m=1" } else { "m=0" };
        assert!(keys.split(',').any(|k| k == more), "{keys}");
        if i == 0 {
            for k in ["a=T", "f=24", "o=z", "s=70", "v=50", "c=35", "r=12", "C=1"] {
                assert!(keys.split(',').any(|x| x == k), "{k} in {keys}");
            }
            assert!(keys.contains(&format!("i={}", kitty::IMAGE_ID)));
        }
        payload.push_str(data);
    }
    let packed = base64::engine::general_purpose::STANDARD
        .decode(payload)
        .unwrap();
    let mut raw = Vec::new();
    flate2::read::ZlibDecoder::new(&packed[..])
        .read_to_end(&mut raw)
        .unwrap();
    let want: Vec<u8> = fb.pixels().iter().flatten().copied().collect();
    assert_eq!(raw, want);
}

/// A small sixel decoder: the image's size and its pixels (`None` where
/// nothing was drawn), colours as the terminal shows the percentages.
pub fn decode_sixel(data: &[u8]) -> (usize, usize, Vec<Option<[u8; 3]>>) {
    let start = data.windows(2).position(|w| w == b"\x1bP").unwrap();
    let q = start + data[start..].iter().position(|&b| b == b'q').unwrap();
    let end = data.windows(2).position(|w| w == b"\x1b\\").unwrap();
    let body = &data[q + 1..end];
    let mut i = 0;
    let number = |i: &mut usize| {
        let s = *i;
        while *i < body.len() && body[*i].is_ascii_digit() {
            *i += 1;
        }
        std::str::from_utf8(&body[s..*i])
            .unwrap()
            .parse::<usize>()
            .unwrap()
    };
    let numbers = |i: &mut usize| {
        let mut v = vec![number(i)];
        while *i < body.len() && body[*i] == b';' {
            *i += 1;
            v.push(number(i));
        }
        v
    };
    let (mut w, mut h, mut pixels) = (0, 0, Vec::new());
    let mut palette = std::collections::HashMap::new();
    let (mut x, mut y, mut colour) = (0usize, 0usize, 0usize);
    while i < body.len() {
        let b = body[i];
        i += 1;
        match b {
            b'"' => {
                let v = numbers(&mut i);
                (w, h) = (v[2], v[3]);
                pixels = vec![None; w * h];
            }
            b'#' => {
                let v = numbers(&mut i);
                colour = v[0];
                if v.len() == 5 {
                    assert_eq!(v[1], 2, "RGB colour space");
                    palette.insert(v[0], sixel::shown([v[2] as u8, v[3] as u8, v[4] as u8]));
                }
            }
            b'$' => x = 0,
            b'-' => {
                x = 0;
                y += 6;
            }
            b'!' | 63..=126 => {
                let (count, c) = if b == b'!' {
                    let n = number(&mut i);
                    i += 1;
                    (n, body[i - 1])
                } else {
                    (1, b)
                };
                for _ in 0..count {
                    for k in 0..6 {
                        if (c - 63) >> k & 1 == 1 {
                            assert!(x < w && y + k < h, "draws inside the raster");
                            pixels[(y + k) * w + x] = Some(palette[&colour]);
                        }
                    }
                    x += 1;
                }
            }
            other => panic!("unexpected byte {other}"),
        }
    }
    (w, h, pixels)
}

#[test]
fn sixel_decodes_to_the_frame_when_the_palette_is_exact() {
    // 200 colours in a frame whose height is not a multiple of six.
    let fb = noisy_fb(37, 29, 200);
    let mut out = Vec::new();
    sixel::write_image(&fb, false, &mut out).unwrap();
    let (w, h, pixels) = decode_sixel(&out);
    assert_eq!((w, h), (37, 29));
    for y in 0..h {
        for x in 0..w {
            let want = sixel::shown(sixel::percent(fb.get(x, y)));
            assert_eq!(pixels[y * w + x], Some(want), "at {x},{y}");
        }
    }
    // Sixel's 1 % steps lose at most 1.3 levels.
    for c in 0..=255u8 {
        let back = sixel::shown(sixel::percent([c; 3]))[0];
        assert!(back.abs_diff(c) <= 2, "{c} -> {back}");
    }
}

#[test]
fn sixel_with_the_cube_comes_back_within_half_a_step() {
    let fb = noisy_fb(40, 13, 0);
    for dither in [false, true] {
        let mut out = Vec::new();
        sixel::write_image_with(&fb, sixel::Palette::Cube, dither, &mut out).unwrap();
        let (w, h, pixels) = decode_sixel(&out);
        assert_eq!((w, h), (40, 13));
        for y in 0..h {
            for x in 0..w {
                let got = pixels[y * w + x].expect("every pixel drawn");
                for (c, &g) in got.iter().enumerate() {
                    let step = 255.0 / (sixel::CUBE[c] - 1) as f32;
                    // Nearest level without dithering, one of the two
                    // around it with; plus sixel's rounding.
                    let bound = if dither { step } else { step / 2.0 } + 2.0;
                    let d = (f32::from(g) - f32::from(fb.get(x, y)[c])).abs();
                    assert!(d <= bound, "{x},{y} channel {c}: {d} > {bound}");
                }
            }
        }
    }
}

#[test]
fn sixel_with_a_per_frame_palette_decodes_to_the_quantised_frame() {
    // Any colours (far more than 256), a height not a multiple of six.
    let fb = noisy_fb(53, 23, 0);
    for dither in [false, true] {
        let mut out = Vec::new();
        sixel::write_image(&fb, dither, &mut out).unwrap();
        let (w, h, pixels) = decode_sixel(&out);
        assert_eq!((w, h), (53, 23));
        let want = sixel::shown_frame(&fb, sixel::Palette::PerFrame, dither);
        for y in 0..h {
            for x in 0..w {
                assert_eq!(pixels[y * w + x], Some(want.get(x, y)), "at {x},{y}");
            }
        }
        let palette_entries = String::from_utf8_lossy(&out).matches(";2;").count();
        assert_eq!(
            palette_entries, 256,
            "a full palette for a frame of many colours"
        );
    }
}

#[test]
fn sixel_per_frame_palette_keeps_frames_of_few_bins_within_a_bin() {
    // Every grey level 0..=255 and 44 reds: 300 colours (so not the exact
    // palette), but only 64 + 44 histogram bins of 4 levels a channel,
    // each of which gets an entry: a pixel is at most 3 levels from its
    // bin's mean, plus sixel's 1 % rounding (2). The cube is 25 off.
    let mut fb = Framebuffer::new(60, 5);
    for i in 0..300 {
        let c = if i < 256 {
            [i as u8; 3]
        } else {
            [(i - 256) as u8 * 4 + 80, 0, 0]
        };
        fb.set(i % 60, i / 60, c);
    }
    let mut out = Vec::new();
    sixel::write_image(&fb, false, &mut out).unwrap();
    let (w, _, pixels) = decode_sixel(&out);
    let mut worst_cube = 0;
    let cube = sixel::shown_frame(&fb, sixel::Palette::Cube, false);
    for i in 0..300 {
        let (x, y) = (i % 60, i / 60);
        let got = pixels[y * w + x].unwrap();
        for c in 0..3 {
            let d = got[c].abs_diff(fb.get(x, y)[c]);
            assert!(d <= 5, "{x},{y}: {got:?} for {:?}", fb.get(x, y));
            worst_cube = worst_cube.max(cube.get(x, y)[c].abs_diff(fb.get(x, y)[c]));
        }
    }
    assert!(worst_cube >= 20, "the cube is coarser: {worst_cube}");
}
