//! The framebuffer as half-block cells: `▀` with fg = upper pixel, bg = lower pixel.

use ratatui::buffer::{Buffer, Cell};
use ratatui::layout::Rect;
use ratatui::style::Color;
use ratatui::widgets::Widget;

use super::color::ColorDepth;
use relief_core::framebuffer::{Framebuffer, Rgb};

/// Upper half block: the foreground paints the upper pixel.
pub const UPPER_HALF: char = '▀';

/// A widget drawing a framebuffer two pixel rows per terminal row.
///
/// Cells are written in place (no allocation per cell). The framebuffer's
/// top-left pixel goes to the area's top-left cell; cells the framebuffer does
/// not reach, and the lower half of the last row when the pixel height is
/// odd, show `pad`.
pub struct HalfBlocks<'a> {
    pub fb: &'a Framebuffer,
    pub depth: ColorDepth,
    /// Ordered dithering (256 and 16 colours only), where it lowers the
    /// error and never on flat areas.
    pub dither: bool,
    /// Colour of whatever the framebuffer does not cover.
    pub pad: Rgb,
}

/// Cells needed to show `width × height` pixels.
pub fn cells_for_pixels(width: usize, height: usize) -> (usize, usize) {
    (width, height.div_ceil(2))
}

impl Widget for HalfBlocks<'_> {
    fn render(self, area: Rect, buf: &mut Buffer) {
        self.render_from_row(0, area, buf);
    }
}

impl HalfBlocks<'_> {
    /// Draws cell rows `first_row..` of the picture into `area` (a band of a
    /// picture taller than one buffer should hold); dithering and its
    /// flat-area test still see the whole framebuffer.
    pub fn render_from_row(&self, first_row: usize, area: Rect, buf: &mut Buffer) {
        let area = area.intersection(buf.area);
        if area.is_empty() {
            return;
        }
        let (fb_w, fb_h) = (self.fb.width(), self.fb.height());
        // Two template cells, copied in place: no symbol is rebuilt per cell.
        let mut block = Cell::EMPTY;
        block.set_char(UPPER_HALF);
        let mut space = Cell::EMPTY;
        space.set_char(' ').set_fg(Color::Reset);
        let pad = self.pad;
        let pixel = |x: usize, y: usize| {
            if x < fb_w && y < fb_h {
                self.fb.get(x, y)
            } else {
                pad
            }
        };
        let quantizer = self.depth.quantizer(pad);
        // Dithering only off flat areas: a pixel equal to its four
        // neighbours (the background, a flat-shaded face) keeps one colour.
        // The picture's border counts as flat (neighbours clamp to it).
        let dithers = |x: usize, y: usize, c: Rgb| {
            if !self.dither || x >= fb_w || y >= fb_h {
                return false;
            }
            let at = |x: usize, y: usize| self.fb.get(x.min(fb_w - 1), y.min(fb_h - 1));
            at(x + 1, y) != c
                || at(x, y + 1) != c
                || at(x.saturating_sub(1), y) != c
                || at(x, y.saturating_sub(1)) != c
        };
        let map = |x: usize, y: usize| {
            let c = pixel(x, y);
            quantizer.pick(c, dithers(x, y, c), x, y)
        };
        for row in 0..area.height as usize {
            let (top_y, bottom_y) = (2 * (first_row + row), 2 * (first_row + row) + 1);
            let start = buf.index_of(area.x, area.y + row as u16);
            let cells = &mut buf.content[start..start + area.width as usize];
            for (col, cell) in cells.iter_mut().enumerate() {
                let fg = map(col, top_y);
                let bg = map(col, bottom_y);
                if fg == bg {
                    // Both pixels alike: a space with a background says it in fewer bytes.
                    cell.clone_from(&space);
                } else {
                    cell.clone_from(&block);
                    cell.fg = fg;
                }
                cell.bg = bg;
            }
        }
    }
}
