//! Terminal output at 200×60 cells: filling ratatui's buffer from the
//! framebuffer, diffing and encoding a frame, and the bytes it takes —
//! relief's backend against ratatui's stock crossterm backend.
//!
//! `cargo bench --bench term` prints the byte table first, then criterion's timings.

use std::hint::black_box;
use std::io::{self, Write};
use std::sync::Arc;

use criterion::Criterion;
use ratatui::backend::{Backend, CrosstermBackend};
use ratatui::buffer::Buffer;
use ratatui::layout::Rect;
use ratatui::widgets::Widget;
use ratatui::{Terminal, TerminalOptions, Viewport};
use relief_core::framebuffer::Framebuffer;
use relief_core::settings::Settings;
use relief_pipeline::render::Renderer;
use relief_scene::Scene;
use relief_term::palette::Palette;
use relief_term::{ColorDepth, HalfBlocks, SgrBackend};

const W: u16 = 200;
const H: u16 = 60;

/// Counts bytes, keeps nothing.
struct Count(Arc<std::sync::atomic::AtomicU64>);

impl Write for Count {
    fn write(&mut self, d: &[u8]) -> io::Result<usize> {
        self.0
            .fetch_add(d.len() as u64, std::sync::atomic::Ordering::Relaxed);
        Ok(d.len())
    }
    fn flush(&mut self) -> io::Result<()> {
        Ok(())
    }
}

fn cube(rotation_y: f32) -> Framebuffer {
    let scene = Scene::cube(Arc::new(relief_texture::decode::procedural::brick()), false);
    let settings = Settings {
        rotation: glam::Vec3::new(25.0, rotation_y, 0.0),
        ..Settings::default()
    };
    let mut fb = Framebuffer::new(W as usize, 2 * H as usize);
    Renderer::new().render(&scene, &settings, &mut fb);
    fb
}

fn noise(seed: u32) -> Framebuffer {
    let mut fb = Framebuffer::new(W as usize, 2 * H as usize);
    let mut s = seed.wrapping_mul(2654435761) | 1;
    for p in fb.pixels_mut() {
        s ^= s << 13;
        s ^= s >> 17;
        s ^= s << 5;
        *p = [s as u8, (s >> 8) as u8, (s >> 16) as u8];
    }
    fb
}

fn gradient(shift: usize) -> Framebuffer {
    let mut fb = Framebuffer::new(W as usize, 2 * H as usize);
    for y in 0..fb.height() {
        for x in 0..fb.width() {
            fb.set(
                x,
                y,
                [
                    (x + shift) as u8,
                    (y * 2 + shift) as u8,
                    ((x + y) / 2) as u8,
                ],
            );
        }
    }
    fb
}

fn cells(fb: &Framebuffer, depth: ColorDepth) -> Buffer {
    cells_dithered(fb, depth, false)
}

fn cells_dithered(fb: &Framebuffer, depth: ColorDepth, dither: bool) -> Buffer {
    let area = Rect::new(0, 0, W, H);
    let mut buf = Buffer::empty(area);
    HalfBlocks {
        fb,
        depth,
        dither,
        pad: [16, 24, 32],
    }
    .render(area, &mut buf);
    buf
}

/// Bytes of the frame `next` drawn over `prev` by a backend.
fn bytes_with<B: Backend>(
    mut term: Terminal<B>,
    frame: impl Fn(&mut Terminal<B>),
    prev: &Buffer,
    next: &Buffer,
    count: &Arc<std::sync::atomic::AtomicU64>,
) -> u64 {
    let _ = &mut term;
    term.draw(|f| f.buffer_mut().clone_from(prev)).ok();
    frame(&mut term);
    let before = count.load(std::sync::atomic::Ordering::Relaxed);
    term.draw(|f| f.buffer_mut().clone_from(next)).ok();
    frame(&mut term);
    count.load(std::sync::atomic::Ordering::Relaxed) - before
}

fn ours(prev: &Buffer, next: &Buffer, tolerance: u8) -> u64 {
    let mut backend = SgrBackend::with_size(io::sink(), W, H);
    backend.set_tolerance(tolerance);
    let mut term = Terminal::new(backend).unwrap();
    term.draw(|f| f.buffer_mut().clone_from(prev)).unwrap();
    term.backend_mut().begin_frame().unwrap();
    term.draw(|f| f.buffer_mut().clone_from(next)).unwrap();
    term.backend_mut().end_frame().unwrap()
}

fn stock(prev: &Buffer, next: &Buffer) -> u64 {
    let count = Arc::new(std::sync::atomic::AtomicU64::new(0));
    let backend = CrosstermBackend::new(Count(count.clone()));
    let term = Terminal::with_options(
        backend,
        TerminalOptions {
            viewport: Viewport::Fixed(Rect::new(0, 0, W, H)),
        },
    )
    .unwrap();
    bytes_with(term, |_| {}, prev, next, &count)
}

fn byte_table() {
    let blank = Buffer::empty(Rect::new(0, 0, W, H));
    let t = ColorDepth::Truecolor;
    let cases = [
        (
            "noise → other noise (every cell, both colours)",
            cells(&noise(1), t),
            cells(&noise(2), t),
        ),
        (
            "gradient → shifted gradient (every cell)",
            cells(&gradient(0), t),
            cells(&gradient(1), t),
        ),
        (
            "blank → cube (first frame, every cell)",
            blank.clone(),
            cells(&cube(35.0), t),
        ),
        (
            "cube → cube turned 5° (a drag step)",
            cells(&cube(35.0), t),
            cells(&cube(40.0), t),
        ),
        (
            "cube 256 colours → turned 5°",
            cells(&cube(35.0), ColorDepth::Palette256),
            cells(&cube(40.0), ColorDepth::Palette256),
        ),
        (
            "blank → cube, 256 colours",
            blank.clone(),
            cells(&cube(35.0), ColorDepth::Palette256),
        ),
        (
            "blank → cube, 256 colours, --dither",
            blank.clone(),
            cells_dithered(&cube(35.0), ColorDepth::Palette256, true),
        ),
        (
            "blank → cube, 16 colours",
            blank.clone(),
            cells(&cube(35.0), ColorDepth::Palette16),
        ),
        (
            "blank → cube, 16 colours, --dither",
            blank,
            cells_dithered(&cube(35.0), ColorDepth::Palette16, true),
        ),
    ];
    println!("bytes per frame at {W}x{H} cells (ours includes the 16 bytes of sync brackets)");
    println!(
        "{:<50} {:>8} {:>8} {:>6} {:>8} {:>6} {:>8} {:>6}",
        "frame", "stock", "exact", "ratio", "tol 2", "ratio", "tol 4", "ratio"
    );
    for (name, prev, next) in &cases {
        let s = stock(prev, next);
        let r = |o: u64| s as f64 / o as f64;
        let (o0, o2, o4) = (
            ours(prev, next, 0),
            ours(prev, next, 2),
            ours(prev, next, 4),
        );
        println!(
            "{name:<50} {s:>8} {o0:>8} {:>5.2}x {o2:>8} {:>5.2}x {o4:>8} {:>5.2}x",
            r(o0),
            r(o2),
            r(o4)
        );
    }
}

fn benches(c: &mut Criterion) {
    let fb = cube(35.0);
    let area = Rect::new(0, 0, W, H);
    let mut buf = Buffer::empty(area);
    c.bench_function("fill 200x60 cells from the framebuffer (truecolor)", |b| {
        b.iter(|| {
            HalfBlocks {
                fb: black_box(&fb),
                depth: ColorDepth::Truecolor,
                dither: false,
                pad: [16, 24, 32],
            }
            .render(area, &mut buf)
        })
    });
    c.bench_function(
        "fill 200x60 cells from the framebuffer (256 colours)",
        |b| {
            b.iter(|| {
                HalfBlocks {
                    fb: black_box(&fb),
                    depth: ColorDepth::Palette256,
                    dither: false,
                    pad: [16, 24, 32],
                }
                .render(area, &mut buf)
            })
        },
    );

    c.bench_function(
        "fill 200x60 cells from the framebuffer (256 colours, --dither)",
        |b| {
            b.iter(|| {
                HalfBlocks {
                    fb: black_box(&fb),
                    depth: ColorDepth::Palette256,
                    dither: true,
                    pad: [16, 24, 32],
                }
                .render(area, &mut buf)
            })
        },
    );

    // Diff and encode a frame where every cell changes: alternate two noise frames.
    let frames = [
        cells(&noise(1), ColorDepth::Truecolor),
        cells(&noise(2), ColorDepth::Truecolor),
    ];
    let mut term = Terminal::new(SgrBackend::with_size(io::sink(), W, H)).unwrap();
    let mut i = 0;
    c.bench_function("relief backend: diff+encode, every cell changes", |b| {
        b.iter(|| {
            i ^= 1;
            term.backend_mut().begin_frame().unwrap();
            term.draw(|f| f.buffer_mut().clone_from(&frames[i]))
                .unwrap();
            term.backend_mut().end_frame().unwrap()
        })
    });
    let mut stock_term = Terminal::with_options(
        CrosstermBackend::new(io::BufWriter::with_capacity(1 << 20, io::sink())),
        TerminalOptions {
            viewport: Viewport::Fixed(area),
        },
    )
    .unwrap();
    c.bench_function("stock backend: diff+encode, every cell changes", |b| {
        b.iter(|| {
            i ^= 1;
            stock_term
                .draw(|f| f.buffer_mut().clone_from(&frames[i]))
                .unwrap();
        })
    });
}

/// Maps every pixel of `fb` with `palette`'s table, as a frame's cells do.
fn map_frame(palette: &Palette, fb: &Framebuffer) -> usize {
    fb.pixels()
        .iter()
        .map(|&p| usize::from(palette.pick(p).best))
        .sum()
}

/// Maps each of the 2²⁴ colours (every bin of the table).
fn map_all(palette: &Palette) -> usize {
    let mut sum = 0;
    for r in 0..=255u8 {
        for g in 0..=255u8 {
            for b in 0..=255u8 {
                sum += usize::from(palette.pick(black_box([r, g, b])).best);
            }
        }
    }
    sum
}

/// The first frame in 256 and 16 colours: a palette with a new table, then
/// the frame mapped (the cost panel's `encode` of the first frame), and the
/// worst cases: a frame whose every pixel is its own colour, and every
/// colour (all the table's bins).
fn table_benches(c: &mut Criterion) {
    let fb = cube(35.0);
    let busy = noise(3);
    let mut g = c.benchmark_group("colour table");
    g.sample_size(10);
    for (name, new) in [
        ("256", Palette::new_xterm256 as fn() -> Palette),
        ("16", Palette::new_ansi16),
    ] {
        g.bench_function(
            format!("{name} colours: new table + first 200x120 cube frame"),
            |b| b.iter(|| map_frame(&new(), black_box(&fb))),
        );
        g.bench_function(
            format!("{name} colours: new table + 200x120 noise frame"),
            |b| b.iter(|| map_frame(&new(), black_box(&busy))),
        );
        g.bench_function(
            format!("{name} colours: new table + every 24-bit colour"),
            |b| b.iter(|| map_all(&new())),
        );
    }
    g.finish();
}

fn main() {
    byte_table();
    let mut c = Criterion::default().configure_from_args();
    benches(&mut c);
    table_benches(&mut c);
    c.final_summary();
}
