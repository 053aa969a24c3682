//! What a frame costs over the wire: the bytes the interactive view's
//! terminal encoder (half blocks through the SGR backend, ratatui's diff)
//! writes for a frame after a small rotation of the previous one; and per
//! output mode (symbol sets, kitty, sixel, iTerm2 images) the bytes of a
//! first frame and of a turn, the encode time, and what the terminal shows
//! against the full-resolution frame.

use std::time::{Duration, Instant};

use ratatui::Terminal;
use ratatui::widgets::Widget;

use relief_core::framebuffer::{Framebuffer, Rgb};
use relief_term::halfblock::cells_for_pixels;
use relief_term::sixel::{self, Palette};
use relief_term::{ColorDepth, Format, HalfBlocks, SgrBackend, SymbolCells, Symbols, pixel_view};

/// Rotation between the two frames, degrees about Y: one step of a slow drag.
pub const STEP_DEGREES: f32 = 2.0;

/// Colour tolerance of the encoder: the interactive view's default
/// (`--color-tolerance 2`).
pub const TOLERANCE: u8 = 2;

/// Bytes written for `after` on a terminal that already shows `before`
/// (same size), at colour depth `depth`, without dithering: the picture only,
/// one frame (synchronized-output marks included), no status line.
pub fn bytes_after(
    before: &Framebuffer,
    after: &Framebuffer,
    depth: ColorDepth,
    background: Rgb,
) -> anyhow::Result<u64> {
    let (cols, rows) = cells_for_pixels(after.width(), after.height());
    let cols = u16::try_from(cols)?;
    let rows = u16::try_from(rows)?;
    let mut backend = SgrBackend::with_size(std::io::sink(), cols, rows);
    backend.set_tolerance(TOLERANCE);
    let mut terminal = Terminal::new(backend)?;
    let mut bytes = 0;
    for fb in [before, after] {
        terminal.backend_mut().begin_frame()?;
        terminal.draw(|frame| {
            frame.render_widget(
                HalfBlocks {
                    fb,
                    depth,
                    dither: false,
                    pad: background,
                },
                frame.area(),
            )
        })?;
        bytes = terminal.backend_mut().end_frame()?;
    }
    Ok(bytes)
}

// ---- Output modes: what each costs and loses ------------------------------

/// The terminal of the output-mode rows: cells of the picture and the
/// pixels of a cell (a common 8×16 font).
pub const MODE_CELLS: (u16, u16) = (100, 30);
pub const MODE_CELL_PIXELS: (usize, usize) = (8, 16);

/// An output mode of the view: text cells of a symbol set, or pixels.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    Text(Symbols),
    Pixels(Format),
    /// Sixel with a given palette, with or without ordered dithering (the
    /// choices side by side, in one sitting).
    Sixel(Palette, bool),
}

/// Every output mode, in the order of the rows.
pub const MODES: [Mode; 10] = [
    Mode::Text(Symbols::Half),
    Mode::Text(Symbols::Quad),
    Mode::Text(Symbols::Sextant),
    Mode::Text(Symbols::Octant),
    Mode::Pixels(Format::Kitty),
    Mode::Pixels(Format::Sixels),
    Mode::Sixel(Palette::Cube, false),
    Mode::Sixel(Palette::PerFrame, true),
    Mode::Sixel(Palette::Cube, true),
    Mode::Pixels(Format::Iterm),
];

impl Mode {
    pub fn name(self) -> &'static str {
        match self {
            Mode::Text(s) => s.name(),
            Mode::Pixels(f) => f.name(),
            Mode::Sixel(Palette::PerFrame, false) => "sixels per-frame",
            Mode::Sixel(Palette::PerFrame, true) => "sixels per-frame dither",
            Mode::Sixel(Palette::Cube, false) => "sixels cube",
            Mode::Sixel(Palette::Cube, true) => "sixels cube dither",
        }
    }

    /// The frame's size for `cells` of `cell` pixels.
    pub fn frame_size(self, cells: (u16, u16), cell: (usize, usize)) -> (usize, usize) {
        let (c, r) = (usize::from(cells.0), usize::from(cells.1));
        match self {
            Mode::Text(s) => (c * s.columns(), r * s.rows()),
            Mode::Pixels(_) | Mode::Sixel(..) => (c * cell.0, r * cell.1),
        }
    }

    /// Width / height of one of the frame's pixels on a cell twice as tall
    /// as wide (what the renderer corrects its projection by).
    pub fn pixel_aspect(self) -> f32 {
        match self {
            Mode::Text(s) => s.pixel_aspect(),
            Mode::Pixels(_) | Mode::Sixel(..) => 1.0,
        }
    }
}

/// One row: a mode's bytes, encode time and error.
#[derive(Clone, Debug)]
pub struct ModeRow {
    pub mode: Mode,
    /// The frame's pixels.
    pub size: (usize, usize),
    /// Bytes of the first frame on a blank screen.
    pub first_bytes: u64,
    /// Bytes of the frame after a [`STEP_DEGREES`] turn.
    pub change_bytes: u64,
    /// Time to encode that frame (median of the orientations).
    pub encode: Duration,
    /// What the terminal shows against the full-resolution frame, at the
    /// cells' pixel size: PSNR (dB) and mean SSIM of luma.
    pub psnr: f64,
    pub ssim: f64,
}

/// The text frames of `fb` drawn in `symbols` on a `cells` terminal:
/// bytes of `before` on a blank screen, then of `after`, and the time
/// `after` took to encode.
fn text_bytes(
    before: &Framebuffer,
    after: &Framebuffer,
    symbols: Symbols,
    cells: (u16, u16),
    background: Rgb,
) -> anyhow::Result<(u64, u64, Duration)> {
    let mut backend = SgrBackend::with_size(std::io::sink(), cells.0, cells.1);
    backend.set_tolerance(TOLERANCE);
    let mut terminal = Terminal::new(backend)?;
    let mut bytes = [0u64; 2];
    let mut time = Duration::ZERO;
    for (i, fb) in [before, after].into_iter().enumerate() {
        let start = Instant::now();
        terminal.backend_mut().begin_frame()?;
        terminal.draw(|frame| {
            frame.render_widget(
                SymbolCells {
                    fb,
                    symbols,
                    depth: ColorDepth::Truecolor,
                    dither: false,
                    pad: background,
                },
                frame.area(),
            )
        })?;
        bytes[i] = terminal.backend_mut().end_frame()?;
        time = start.elapsed();
    }
    Ok((bytes[0], bytes[1], time))
}

/// What a terminal with `cell`-pixel cells shows for `fb` drawn as
/// `symbols` text: each cell's glyph in its two colours, at full size.
pub fn shown_text(
    fb: &Framebuffer,
    symbols: Symbols,
    cells: (u16, u16),
    cell: (usize, usize),
    background: Rgb,
) -> Framebuffer {
    let area = ratatui::layout::Rect::new(0, 0, cells.0, cells.1);
    let mut buf = ratatui::buffer::Buffer::empty(area);
    SymbolCells {
        fb,
        symbols,
        depth: ColorDepth::Truecolor,
        dither: false,
        pad: background,
    }
    .render(area, &mut buf);
    let rgb = |c: ratatui::style::Color| match c {
        ratatui::style::Color::Rgb(r, g, b) => [r, g, b],
        _ => background,
    };
    let (sc, sr) = (symbols.columns(), symbols.rows());
    let mut out = Framebuffer::new(usize::from(cells.0) * cell.0, usize::from(cells.1) * cell.1);
    for cy in 0..cells.1 {
        for cx in 0..cells.0 {
            let c = &buf[(cx, cy)];
            let ch = c.symbol().chars().next().unwrap_or(' ');
            let mask = symbols.mask_of(ch).unwrap_or(0);
            let (fg, bg) = (rgb(c.fg), rgb(c.bg));
            for py in 0..cell.1 {
                // The sub-cell row under this pixel's centre.
                let row = (2 * py + 1) * sr / (2 * cell.1);
                for px in 0..cell.0 {
                    let col = (2 * px + 1) * sc / (2 * cell.0);
                    let on = mask >> (row * sc + col) & 1 == 1;
                    out.set(
                        usize::from(cx) * cell.0 + px,
                        usize::from(cy) * cell.1 + py,
                        if on { fg } else { bg },
                    );
                }
            }
        }
    }
    out
}

/// Measures every mode over `rotations`: `render` draws the scene at a
/// rotation into a frame of the given size with the given pixel aspect.
pub fn measure_modes(
    rotations: &[glam::Vec3],
    background: Rgb,
    mut render: impl FnMut(glam::Vec3, f32, &mut Framebuffer),
) -> anyhow::Result<Vec<ModeRow>> {
    let cells = MODE_CELLS;
    let cell = MODE_CELL_PIXELS;
    let step = glam::Vec3::new(0.0, STEP_DEGREES, 0.0);
    let mut rows = Vec::new();
    for mode in MODES {
        let (w, h) = mode.frame_size(cells, cell);
        let (fw, fh) = Mode::Pixels(Format::Kitty).frame_size(cells, cell);
        let (mut first, mut change) = (0u64, 0u64);
        let mut times = Vec::new();
        let mut squared = crate::metrics::SquaredError::default();
        let mut ssim = 0.0;
        for &rotation in rotations {
            let mut a = Framebuffer::new(w, h);
            let mut b = Framebuffer::new(w, h);
            let mut full = Framebuffer::new(fw, fh);
            render(rotation, mode.pixel_aspect(), &mut a);
            render(rotation + step, mode.pixel_aspect(), &mut b);
            render(rotation, 1.0, &mut full);
            let shown = match mode {
                Mode::Text(symbols) => {
                    let (f, c, t) = text_bytes(&a, &b, symbols, cells, background)?;
                    first += f;
                    change += c;
                    times.push(t);
                    shown_text(&a, symbols, cells, cell, background)
                }
                Mode::Pixels(format) => {
                    let area = ratatui::layout::Rect::new(0, 0, cells.0, cells.1);
                    first += pixel_view::image_bytes(&a, format, area, false, false)?.len() as u64;
                    let start = Instant::now();
                    change += pixel_view::image_bytes(&b, format, area, false, false)?.len() as u64;
                    times.push(start.elapsed());
                    match format {
                        Format::Sixels => sixel::shown_frame(&a, Palette::CHOSEN, false),
                        _ => a.clone(),
                    }
                }
                Mode::Sixel(palette, dither) => {
                    let mut bytes = Vec::new();
                    sixel::write_image_with(&a, palette, dither, &mut bytes)?;
                    first += bytes.len() as u64;
                    bytes.clear();
                    let start = Instant::now();
                    sixel::write_image_with(&b, palette, dither, &mut bytes)?;
                    times.push(start.elapsed());
                    change += bytes.len() as u64;
                    sixel::shown_frame(&a, palette, dither)
                }
            };
            squared.add(shown.pixels(), full.pixels());
            ssim += crate::metrics::ssim(shown.pixels(), full.pixels(), fw, fh);
        }
        times.sort();
        let n = rotations.len().max(1) as u64;
        rows.push(ModeRow {
            mode,
            size: (w, h),
            first_bytes: first / n,
            change_bytes: change / n,
            encode: times.get(times.len() / 2).copied().unwrap_or_default(),
            psnr: squared.psnr(),
            ssim: ssim / n as f64,
        });
    }
    Ok(rows)
}

/// The rows as an aligned text table (Markdown when `markdown`).
pub fn modes_table(rows: &[ModeRow], markdown: bool) -> String {
    let head = [
        "mode",
        "pixels",
        "first frame B",
        "2° turn B",
        "encode ms",
        "PSNR dB",
        "SSIM",
    ];
    let lines: Vec<[String; 7]> = rows
        .iter()
        .map(|r| {
            [
                r.mode.name().to_string(),
                format!("{}x{}", r.size.0, r.size.1),
                r.first_bytes.to_string(),
                r.change_bytes.to_string(),
                crate::figures::ms(r.encode),
                crate::figures::db(r.psnr),
                format!("{:.4}", r.ssim),
            ]
        })
        .collect();
    let mut out = String::new();
    if markdown {
        out.push_str(&format!("| {} |\n", head.join(" | ")));
        out.push_str(&format!("|{}\n", "---|".repeat(head.len())));
        for l in &lines {
            out.push_str(&format!("| {} |\n", l.join(" | ")));
        }
        return out;
    }
    let width: Vec<usize> = (0..head.len())
        .map(|i| {
            lines
                .iter()
                .map(|l| l[i].len())
                .chain([head[i].len()])
                .max()
                .unwrap_or(0)
        })
        .collect();
    let row = |cells: Vec<&str>| {
        let parts: Vec<String> = cells
            .iter()
            .enumerate()
            .map(|(i, c)| {
                if i == 0 {
                    format!("{c:<w$}", w = width[i])
                } else {
                    format!("{c:>w$}", w = width[i])
                }
            })
            .collect();
        parts.join("  ").trim_end().to_string() + "\n"
    };
    out.push_str(&row(head.to_vec()));
    for l in &lines {
        out.push_str(&row(l.iter().map(String::as_str).collect()));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_unchanged_frame_costs_little_and_a_changed_one_more() {
        let mut a = Framebuffer::new(16, 8);
        a.fill([10, 20, 30]);
        let mut b = a.clone();
        for x in 0..16 {
            b.set(x, 3, [200, (x * 10) as u8, 40]);
        }
        for depth in [ColorDepth::Truecolor, ColorDepth::Palette256] {
            let same = bytes_after(&a, &a, depth, [0, 0, 0]).unwrap();
            let changed = bytes_after(&a, &b, depth, [0, 0, 0]).unwrap();
            // Only the sync marks (and cursor handling) when nothing changed.
            assert!(same < 40, "{depth:?}: {same} bytes for an unchanged frame");
            assert!(
                changed > same + 16 * 3,
                "{depth:?}: {changed} bytes for a changed row"
            );
        }
        // 256 colours name a colour in fewer bytes than 24-bit.
        let mut c = a.clone();
        for (i, p) in c.pixels_mut().iter_mut().enumerate() {
            *p = [(i * 37) as u8, (i * 91) as u8, (i * 13) as u8];
        }
        let tc = bytes_after(&a, &c, ColorDepth::Truecolor, [0, 0, 0]).unwrap();
        let p256 = bytes_after(&a, &c, ColorDepth::Palette256, [0, 0, 0]).unwrap();
        assert!(p256 < tc, "256: {p256}, truecolor: {tc}");
    }

    #[test]
    fn text_shown_at_full_size_is_each_cells_glyph_in_its_two_colours() {
        // Quadrants: every cell's 2×2 pixels in two colours is drawn exactly.
        let (cells, cell) = ((3u16, 2u16), (4usize, 8usize));
        let mut fb = Framebuffer::new(6, 4);
        for y in 0..4 {
            for x in 0..6 {
                let on = (x * 7 + y * 3) % 5 < 2;
                fb.set(
                    x,
                    y,
                    if on {
                        [200, 10, 10]
                    } else {
                        [10, 10, 90 + (x / 2) as u8]
                    },
                );
            }
        }
        let shown = shown_text(&fb, Symbols::Quad, cells, cell, [0, 0, 0]);
        assert_eq!((shown.width(), shown.height()), (12, 16));
        for y in 0..16 {
            for x in 0..12 {
                // A quadrant pixel covers 2×4 screen pixels.
                assert_eq!(shown.get(x, y), fb.get(x / 2, y / 4), "{x},{y}");
            }
        }
    }

    #[test]
    fn every_mode_is_measured_and_pixels_lose_least() {
        // One-pixel stripes in full-resolution coordinates: text cannot
        // show them, kitty and iTerm2 send them exactly.
        let (fw, _) = Mode::Pixels(Format::Kitty).frame_size(MODE_CELLS, MODE_CELL_PIXELS);
        let rows = measure_modes(&[glam::Vec3::ZERO], [0, 0, 0], |rotation, _, fb| {
            let w = fb.width();
            for y in 0..fb.height() {
                for x in 0..w {
                    let on = (x * fw / w) % 2 == 0;
                    let v = if on { 250 } else { 20 + rotation.y as u8 };
                    fb.set(x, y, [v, v / 2, 40]);
                }
            }
        })
        .unwrap();
        assert_eq!(rows.len(), MODES.len());
        let row = |m| rows.iter().find(|r| r.mode == m).unwrap();
        let kitty = row(Mode::Pixels(Format::Kitty));
        assert!(kitty.psnr.is_infinite() && (kitty.ssim - 1.0).abs() < 1e-9);
        assert!(row(Mode::Pixels(Format::Iterm)).psnr.is_infinite());
        let half = row(Mode::Text(Symbols::Half));
        assert!(half.psnr < 20.0, "{}", half.psnr);
        assert_eq!(half.size, (100, 60));
        for r in &rows {
            assert!(r.first_bytes > 0 && r.change_bytes > 0, "{r:?}");
        }
        let table = modes_table(&rows, true);
        assert_eq!(table.lines().count(), 2 + MODES.len());
        assert!(table.contains("| sextant |"));
    }
}
