//! The framebuffer as half-block cells: `▀` with fg = upper pixel, bg = lower pixel.

use ratatui::buffer::{Buffer, Cell};
use ratatui::layout::Rect;
use ratatui::style::Color;
use ratatui::widgets::Widget;

use super::color::ColorDepth;
use crate::framebuffer::{Framebuffer, Rgb};

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
    /// Ordered dithering (256 and 16 colours only).
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
        for row in 0..area.height as usize {
            let (top_y, bottom_y) = (2 * row, 2 * row + 1);
            let start = buf.index_of(area.x, area.y + row as u16);
            let cells = &mut buf.content[start..start + area.width as usize];
            for (col, cell) in cells.iter_mut().enumerate() {
                let fg = self.depth.map(pixel(col, top_y), self.dither, col, top_y);
                let bg = self
                    .depth
                    .map(pixel(col, bottom_y), self.dither, col, bottom_y);
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
