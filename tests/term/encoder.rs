//! The framebuffer → half-block encoder and the colour-depth mapping.

use ratatui::buffer::Buffer;
use ratatui::layout::Rect;
use ratatui::style::Color;
use ratatui::widgets::Widget;
use relief::Framebuffer;
use relief::term::color::{ANSI16, nearest_16, nearest_256};
use relief::term::{ColorDepth, HalfBlocks};

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
