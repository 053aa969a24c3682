//! What the backend sends: checked by replaying it on a small terminal model,
//! and counted against ratatui's stock crossterm backend.

use ratatui::backend::CrosstermBackend;
use ratatui::buffer::Buffer;
use ratatui::layout::Rect;
use ratatui::style::Color;

use crate::screen::Screen;
use ratatui::widgets::Widget;
use ratatui::{Terminal, TerminalOptions, Viewport};
use relief_core::framebuffer::Framebuffer;
use relief_term::backend::{BEGIN_SYNC, END_SYNC};
use relief_term::{ColorDepth, HalfBlocks, SgrBackend};

const PAD: [u8; 3] = [16, 24, 32];

fn expected(buf: &Buffer, x: u16, y: u16) -> (char, Color, Color) {
    let cell = &buf[(x, y)];
    match cell.symbol() {
        "▀" => ('■', cell.fg, cell.bg),
        " " => ('■', cell.bg, cell.bg),
        s => (s.chars().next().unwrap(), cell.fg, cell.bg),
    }
}

/// A deterministic picture: gradients, noise and flat areas.
fn picture(w: usize, h: usize, seed: u32) -> Framebuffer {
    let mut fb = Framebuffer::new(w, h);
    let mut s = seed.wrapping_mul(2654435761).wrapping_add(1);
    for y in 0..h {
        for x in 0..w {
            s ^= s << 13;
            s ^= s >> 17;
            s ^= s << 5;
            let c = if x < w / 4 {
                PAD
            } else if x < w / 2 {
                [(x * 5) as u8, (y * 7) as u8, 90]
            } else {
                [s as u8, (s >> 8) as u8, (s >> 16) as u8]
            };
            fb.set(x, y, c);
        }
    }
    fb
}

struct Harness {
    term: Terminal<SgrBackend<Vec<u8>>>,
}

impl Harness {
    fn new(w: u16, h: u16) -> Self {
        Harness {
            term: Terminal::new(SgrBackend::with_size(Vec::new(), w, h)).unwrap(),
        }
    }

    /// Draws one frame; returns its bytes and the buffer drawn.
    fn frame(&mut self, fb: &Framebuffer, depth: ColorDepth, text: &str) -> (Vec<u8>, Buffer) {
        let start = self.term.backend().writer().len();
        self.term.backend_mut().begin_frame().unwrap();
        let done = self
            .term
            .draw(|f| {
                let area = f.area();
                let pic = Rect {
                    height: area.height.saturating_sub(1),
                    ..area
                };
                HalfBlocks {
                    fb,
                    depth,
                    dither: false,
                    pad: PAD,
                }
                .render(pic, f.buffer_mut());
                let line = Rect::new(0, area.height - 1, area.width, 1);
                ratatui::widgets::Paragraph::new(text)
                    .style(ratatui::style::Style::new().reversed())
                    .render(line, f.buffer_mut());
            })
            .unwrap()
            .buffer
            .clone();
        let n = self.term.backend_mut().end_frame().unwrap();
        let out = self.term.backend().writer()[start..].to_vec();
        assert_eq!(n as usize, out.len());
        (out, done)
    }
}

fn check_screen(screen: &Screen, buf: &Buffer) {
    for y in 0..buf.area.height {
        for x in 0..buf.area.width {
            assert_eq!(
                screen.seen(x as usize, y as usize),
                expected(buf, x, y),
                "cell ({x},{y})"
            );
        }
    }
}

#[test]
fn replayed_output_shows_exactly_the_drawn_frames() {
    for depth in [
        ColorDepth::Truecolor,
        ColorDepth::Palette256,
        ColorDepth::Palette16,
    ] {
        let (w, h) = (40u16, 13u16);
        let mut harness = Harness::new(w, h);
        let mut screen = Screen::new(w as usize, h as usize);
        for (seed, text) in [(1, "first frame"), (2, "second"), (2, "second"), (3, "x")] {
            let fb = picture(w as usize, 2 * (h as usize - 1), seed);
            let (out, buf) = harness.frame(&fb, depth, text);
            assert!(out.starts_with(BEGIN_SYNC) && out.ends_with(END_SYNC));
            screen.feed(&out);
            check_screen(&screen, &buf);
        }
    }
}

#[test]
fn identical_frame_writes_only_the_frame_brackets() {
    let mut harness = Harness::new(30, 8);
    let fb = picture(30, 14, 7);
    let (first, _) = harness.frame(&fb, ColorDepth::Truecolor, "status");
    assert!(first.len() > 1000);
    let writes = harness.term.backend().write_calls();
    let (second, _) = harness.frame(&fb, ColorDepth::Truecolor, "status");
    assert_eq!(second, [BEGIN_SYNC, END_SYNC].concat());
    // One write call per frame.
    assert_eq!(harness.term.backend().write_calls(), writes + 1);
}

#[test]
fn a_resize_clears_and_redraws_everything() {
    let mut harness = Harness::new(30, 8);
    let fb = picture(30, 14, 7);
    harness.frame(&fb, ColorDepth::Truecolor, "big");
    harness.term.backend_mut().set_fixed_size(12, 5);
    let fb = picture(12, 8, 9);
    let (out, buf) = harness.frame(&fb, ColorDepth::Truecolor, "small");
    assert!(out.windows(4).any(|w| w == b"\x1b[2J"));
    let mut screen = Screen::new(12, 5);
    screen.feed(&out);
    check_screen(&screen, &buf);
    // Down to one cell.
    harness.term.backend_mut().set_fixed_size(1, 1);
    let fb = picture(1, 2, 3);
    let _ = harness.frame(&fb, ColorDepth::Truecolor, "");
}

#[test]
fn colour_tolerance_saves_bytes_and_stays_within_bounds() {
    let (w, h) = (60u16, 13u16);
    // A smooth picture: neighbours one or two levels apart.
    let mut fb = Framebuffer::new(w as usize, 24);
    for y in 0..24 {
        for x in 0..w as usize {
            fb.set(x, y, [x as u8 * 2, 100 + y as u8, 50]);
        }
    }
    let mut sizes = Vec::new();
    for tolerance in [0u8, 3] {
        let mut harness = Harness::new(w, h);
        harness.term.backend_mut().set_tolerance(tolerance);
        let (out, buf) = harness.frame(&fb, ColorDepth::Truecolor, "status");
        let mut screen = Screen::new(w as usize, h as usize);
        screen.feed(&out);
        for y in 0..h {
            for x in 0..w {
                let (c, up, lo) = screen.seen(x as usize, y as usize);
                let (wc, wup, wlo) = expected(&buf, x, y);
                assert_eq!(c, wc, "({x},{y})");
                for (got, want) in [(up, wup), (lo, wlo)] {
                    match (got, want) {
                        (Color::Rgb(a, b, c), Color::Rgb(d, e, f)) => {
                            for (p, q) in [(a, d), (b, e), (c, f)] {
                                assert!(p.abs_diff(q) <= tolerance, "({x},{y}) {got:?} {want:?}");
                            }
                        }
                        _ => assert_eq!(got, want, "({x},{y})"),
                    }
                }
            }
        }
        sizes.push(out.len());
    }
    assert!(sizes[1] * 2 < sizes[0], "{sizes:?}");
}

/// Bytes ratatui's stock crossterm backend writes for the same buffer.
fn stock_bytes(prev: &Buffer, next: &Buffer) -> u64 {
    let area = next.area;
    let count = std::rc::Rc::new(std::cell::Cell::new(0u64));
    let backend = CrosstermBackend::new(Tally(count.clone()));
    let mut term = Terminal::with_options(
        backend,
        TerminalOptions {
            viewport: Viewport::Fixed(area),
        },
    )
    .unwrap();
    term.draw(|f| f.buffer_mut().clone_from(prev)).unwrap();
    let before = count.get();
    term.draw(|f| f.buffer_mut().clone_from(next)).unwrap();
    count.get() - before
}

/// Counts bytes into a shared cell (the stock backend keeps its writer private).
struct Tally(std::rc::Rc<std::cell::Cell<u64>>);

impl std::io::Write for Tally {
    fn write(&mut self, data: &[u8]) -> std::io::Result<usize> {
        self.0.set(self.0.get() + data.len() as u64);
        Ok(data.len())
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

#[test]
fn fewer_bytes_than_the_stock_backend() {
    if std::env::var_os("NO_COLOR").is_some() {
        eprintln!("NO_COLOR is set: crossterm would send no colours, comparison skipped");
        return;
    }
    let (w, h) = (80u16, 25u16);
    let mut harness = Harness::new(w, h);
    let a = picture(w as usize, 48, 1);
    let b = picture(w as usize, 48, 2);
    let (_, buf_a) = harness.frame(&a, ColorDepth::Truecolor, "a");
    let (out_b, buf_b) = harness.frame(&b, ColorDepth::Truecolor, "b");
    let stock = stock_bytes(&buf_a, &buf_b);
    assert!(
        (out_b.len() as u64) < stock,
        "ours {} stock {stock}",
        out_b.len()
    );
}

/// Text as a terminal receives it when it is printed (`cat`): the tty's
/// output translation (onlcr) sends each LF as CR LF.
fn as_printed(text: &[u8]) -> Vec<u8> {
    let mut out = Vec::with_capacity(text.len() + text.len() / 16);
    for &b in text {
        if b == b'\n' {
            out.push(b'\r');
        }
        out.push(b);
    }
    out
}

#[test]
fn ansi_file_text_replays_to_the_same_cells_in_a_bounded_size() {
    use relief_term::ansi::{cells, frame_text};
    for depth in [
        ColorDepth::Truecolor,
        ColorDepth::Palette256,
        ColorDepth::Palette16,
    ] {
        for (h, dither) in [(21, false), (151, false), (151, true)] {
            // Odd height: the last row's lower half is the background; 151
            // pixel rows are 76 cell rows, streamed in several bands.
            let fb = picture(37, h, 5);
            let text = frame_text(&fb, depth, dither, PAD).unwrap();
            let buf = cells(&fb, depth, dither, PAD);
            let mut screen = Screen::new(37, h.div_ceil(2));
            assert!(!text.contains(&b'\r'), "a file's lines end with LF alone");
            screen.feed(&as_printed(&text));
            check_screen(&screen, &buf);
            assert!(text.ends_with(b"\x1b[0m\n"));
        }
    }
    // The reference frame at 160x120 pixels: timg writes 61 kB for it; the
    // former per-cell truecolor text took 338 kB.
    let scene = relief_scene::Scene::cube(
        std::sync::Arc::new(relief_texture::decode::procedural::brick()),
        false,
    );
    let mut fb = Framebuffer::new(160, 120);
    relief_pipeline::render::Renderer::new().render(
        &scene,
        &relief_core::settings::Settings::default(),
        &mut fb,
    );
    let text = frame_text(&fb, ColorDepth::Truecolor, false, PAD).unwrap();
    let mut screen = Screen::new(160, 60);
    screen.feed(&as_printed(&text));
    check_screen(&screen, &cells(&fb, ColorDepth::Truecolor, false, PAD));
    println!("160x120 reference frame as text: {} bytes", text.len());
    assert!(text.len() <= 61_000, "{}", text.len());
}
