//! The framebuffer as half-block cells: `▀` with fg = upper pixel, bg = lower pixel.

use ratatui::buffer::Buffer;
use ratatui::layout::Rect;
use ratatui::style::{Color, Modifier};
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
        let (fb_w, fb_h) = (self.fb.width(), self.fb.height());
        for row in 0..area.height as usize {
            let top_y = 2 * row;
            let bottom_y = top_y + 1;
            let y = area.y + row as u16;
            for col in 0..area.width as usize {
                let inside = col < fb_w;
                let upper = if inside && top_y < fb_h {
                    self.fb.get(col, top_y)
                } else {
                    self.pad
                };
                let lower = if inside && bottom_y < fb_h {
                    self.fb.get(col, bottom_y)
                } else {
                    self.pad
                };
                let fg = self.depth.map(upper, self.dither, col, top_y);
                let bg = self.depth.map(lower, self.dither, col, bottom_y);
                let cell = &mut buf[(area.x + col as u16, y)];
                cell.modifier = Modifier::empty();
                if fg == bg {
                    // Both pixels alike: a space with a background says it in fewer bytes.
                    cell.set_char(' ').set_fg(Color::Reset).set_bg(bg);
                } else {
                    cell.set_char(UPPER_HALF).set_fg(fg).set_bg(bg);
                }
            }
        }
    }
}
