//! One frame as text for a file or a pipe (`relief render --ansi`), and as
//! the picture a terminal would show (`relief render --color 256`).
//!
//! The text goes through the view's own widget and backend: colours are sent
//! only when they change within a row, a half-block cell is `▀`, `▄` or a
//! space whichever takes fewer bytes (the finer symbol sets write their
//! fitted glyph), each row ends with an attribute reset (the rest of a
//! wider line keeps the terminal's own background), and rows are joined by
//! `\r\n` (or `\n` for a file, [`write_symbol_text`]). It starts where the
//! cursor is (no absolute move, no alternate screen, no synchronized-output
//! brackets).

use std::io;

use ratatui::backend::Backend;
use ratatui::buffer::Buffer;
use ratatui::layout::Rect;
use ratatui::widgets::Widget;

use super::color::shown_rgb;
use super::halfblock::UPPER_HALF;
use super::{ColorDepth, SgrBackend, SymbolCells, Symbols};
use relief_core::framebuffer::{Framebuffer, Rgb};

/// The half-block cells of `fb` at `depth` over the background `pad`.
pub fn cells(fb: &Framebuffer, depth: ColorDepth, dither: bool, pad: Rgb) -> Buffer {
    symbol_cells(fb, Symbols::Half, depth, dither, pad)
}

/// The cells of `fb` drawn with `symbols`.
pub fn symbol_cells(
    fb: &Framebuffer,
    symbols: Symbols,
    depth: ColorDepth,
    dither: bool,
    pad: Rgb,
) -> Buffer {
    let (w, h) = symbols.cells_for_pixels(fb.width(), fb.height());
    let area = Rect::new(
        0,
        0,
        w.min(u16::MAX as usize) as u16,
        h.min(u16::MAX as usize) as u16,
    );
    let mut buf = Buffer::empty(area);
    SymbolCells {
        fb,
        symbols,
        depth,
        dither,
        pad,
    }
    .render(area, &mut buf);
    buf
}

/// Cell rows drawn at a time by [`write_frame_text`]: the text of a large
/// frame is streamed band by band, never held whole.
const BAND_ROWS: usize = 32;

/// The frame as text: every cell, ending with an attribute reset and a newline.
pub fn frame_text(
    fb: &Framebuffer,
    depth: ColorDepth,
    dither: bool,
    pad: Rgb,
) -> io::Result<Vec<u8>> {
    let mut text = Vec::new();
    write_frame_text(fb, depth, dither, pad, &mut text)?;
    Ok(text)
}

/// Writes [`frame_text`] to `out`, a band of [`BAND_ROWS`] cell rows at a
/// time; each row starts from the default pen and ends with a reset, and
/// rows end with LF, as a file's lines do.
pub fn write_frame_text(
    fb: &Framebuffer,
    depth: ColorDepth,
    dither: bool,
    pad: Rgb,
    out: &mut impl io::Write,
) -> io::Result<()> {
    write_symbol_text(fb, Symbols::Half, depth, dither, pad, b"\n", out)
}

/// The frame as text drawn with `symbols`, rows joined by `newline`
/// (`\r\n` for a terminal in raw mode, `\n` for a file), each row ending
/// with an attribute reset when it set any.
pub fn write_symbol_text(
    fb: &Framebuffer,
    symbols: Symbols,
    depth: ColorDepth,
    dither: bool,
    pad: Rgb,
    newline: &[u8],
    out: &mut impl io::Write,
) -> io::Result<()> {
    let (w, h) = symbols.cells_for_pixels(fb.width(), fb.height());
    let w = w.min(u16::MAX as usize) as u16;
    let widget = SymbolCells {
        fb,
        symbols,
        depth,
        dither,
        pad,
    };
    let mut text = Vec::new();
    for first in (0..h).step_by(BAND_ROWS) {
        let rows = BAND_ROWS.min(h - first) as u16;
        let area = Rect::new(0, 0, w, rows);
        let mut buf = Buffer::empty(area);
        widget.render_from_row(first, area, &mut buf);
        for (y, row) in buf.content.chunks(w.max(1) as usize).enumerate() {
            if first + y > 0 {
                out.write_all(newline)?;
            }
            text = row_text(row, w, text)?;
            out.write_all(&text)?;
            text.clear();
        }
    }
    out.write_all(b"\n")
}

/// One row of cells as text, from the default pen and ending with an
/// attribute reset: a terminal wider than the row, or one that scrolls,
/// paints the rest of the line with the default background, not the last
/// cell's. `text` is the buffer to write into (given back filled).
fn row_text(row: &[ratatui::buffer::Cell], w: u16, text: Vec<u8>) -> io::Result<Vec<u8>> {
    let mut backend = SgrBackend::with_size(text, w, 1);
    let cells = row.iter().enumerate().map(|(x, c)| (x as u16, 0, c));
    // Each draw starts from the default pen and ends with a reset.
    backend.draw(cells)?;
    Backend::flush(&mut backend)?;
    let mut text = std::mem::take(backend.writer_mut());
    // The backend places the row's first cell with an absolute move to the
    // top left; the text goes on where the cursor is.
    if text.starts_with(b"\x1b[H") {
        text.drain(..3);
    }
    Ok(text)
}

/// The picture the cells show (xterm's palette values), `width × height` pixels.
pub fn shown_picture(buf: &Buffer, width: usize, height: usize, pad: Rgb) -> Framebuffer {
    let mut out = Framebuffer::new(width, height);
    for y in 0..height {
        for x in 0..width {
            let cell = &buf[(x as u16, (y / 2) as u16)];
            let upper = cell.symbol().starts_with(UPPER_HALF);
            let c = if upper && y % 2 == 0 {
                cell.fg
            } else {
                cell.bg
            };
            out.set(x, y, shown_rgb(c, pad));
        }
    }
    out
}
