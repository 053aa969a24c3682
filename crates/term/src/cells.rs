//! The framebuffer as cells of any symbol set: half blocks through
//! [`HalfBlocks`] (unchanged), the finer sets by the exact two-colour fit
//! of each cell ([`super::fit`]).

use ratatui::buffer::{Buffer, Cell};
use ratatui::layout::Rect;
use ratatui::style::Color;
use ratatui::widgets::Widget;

use super::color::{ColorDepth, shown_rgb};
use super::fit::{MAX_PIXELS, fit};
use super::halfblock::HalfBlocks;
use super::symbols::Symbols;
use relief_core::framebuffer::{Framebuffer, Rgb};

/// A widget drawing a framebuffer with `symbols`: the framebuffer's top
/// left pixel goes to the area's top-left cell; pixels past the
/// framebuffer's edges count as `pad`.
pub struct SymbolCells<'a> {
    pub fb: &'a Framebuffer,
    pub symbols: Symbols,
    pub depth: ColorDepth,
    /// Ordered dithering of half blocks in 256 and 16 colours; the finer
    /// sets draw each cell's two fitted colours as they are.
    pub dither: bool,
    pub pad: Rgb,
}

impl Widget for SymbolCells<'_> {
    fn render(self, area: Rect, buf: &mut Buffer) {
        self.render_from_row(0, area, buf);
    }
}

impl SymbolCells<'_> {
    /// Draws cell rows `first_row..` of the picture into `area`.
    pub fn render_from_row(&self, first_row: usize, area: Rect, buf: &mut Buffer) {
        if self.symbols == Symbols::Half {
            return HalfBlocks {
                fb: self.fb,
                depth: self.depth,
                dither: self.dither,
                pad: self.pad,
            }
            .render_from_row(first_row, area, buf);
        }
        let area = area.intersection(buf.area);
        if area.is_empty() {
            return;
        }
        let (fb_w, fb_h) = (self.fb.width(), self.fb.height());
        let (cols, rows) = (self.symbols.columns(), self.symbols.rows());
        let n = cols * rows;
        let quantizer = self.depth.quantizer(self.pad);
        let mut space = Cell::EMPTY;
        space.set_char(' ').set_fg(Color::Reset);
        let mut pixels = [[0u8; 3]; MAX_PIXELS];
        for row in 0..area.height as usize {
            let y0 = (first_row + row) * rows;
            let start = buf.index_of(area.x, area.y + row as u16);
            let cells = &mut buf.content[start..start + area.width as usize];
            for (col, cell) in cells.iter_mut().enumerate() {
                let x0 = col * cols;
                for (i, p) in pixels[..n].iter_mut().enumerate() {
                    let (x, y) = (x0 + i % cols, y0 + i / cols);
                    *p = if x < fb_w && y < fb_h {
                        self.fb.get(x, y)
                    } else {
                        self.pad
                    };
                }
                let f = fit(&pixels[..n]);
                let bg = quantizer.pick(f.bg, false, x0, y0);
                let fg = quantizer.pick(f.fg, false, x0, y0);
                if f.mask == 0 || fg == bg {
                    cell.clone_from(&space);
                } else {
                    cell.set_char(self.symbols.glyph(f.mask));
                    cell.fg = fg;
                    cell.modifier = ratatui::style::Modifier::empty();
                }
                cell.bg = bg;
            }
        }
    }
}

/// The picture cells of `symbols` show (xterm's palette values for
/// indexed colours), `width × height` pixels: every cell's glyph and two
/// colours rebuilt into its block of pixels.
pub fn shown_picture(
    buf: &Buffer,
    symbols: Symbols,
    width: usize,
    height: usize,
    pad: Rgb,
) -> Framebuffer {
    let (cols, rows) = (symbols.columns(), symbols.rows());
    let mut masks = std::collections::HashMap::new();
    for m in 0..1u16 << symbols.pixels() {
        masks.insert(symbols.glyph(m as u8), m as u8);
    }
    let mut out = Framebuffer::new(width, height);
    for cy in 0..height.div_ceil(rows) {
        for cx in 0..width.div_ceil(cols) {
            let cell = &buf[(cx as u16, cy as u16)];
            let ch = cell.symbol().chars().next().unwrap_or(' ');
            let mask = masks.get(&ch).copied().unwrap_or(0);
            let (fg, bg) = (shown_rgb(cell.fg, pad), shown_rgb(cell.bg, pad));
            for i in 0..cols * rows {
                let (x, y) = (cx * cols + i % cols, cy * rows + i / cols);
                if x < width && y < height {
                    out.set(x, y, if mask >> i & 1 == 1 { fg } else { bg });
                }
            }
        }
    }
    out
}
