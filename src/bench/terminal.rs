//! What a frame costs over the wire: the bytes the interactive view's
//! terminal encoder (half blocks through the SGR backend, ratatui's diff)
//! writes for a frame after a small rotation of the previous one.

use ratatui::Terminal;

use crate::framebuffer::{Framebuffer, Rgb};
use crate::term::halfblock::cells_for_pixels;
use crate::term::{ColorDepth, HalfBlocks, SgrBackend};

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
}
