//! The exact pixel frame in strips: over a link too slow to carry it at
//! once, the exact frame follows a picture sized to the link (see
//! [`super::pixel_view`]) as horizontal strips of whole cell rows, each
//! one write of about what the link carries in a preview's frame interval.
//! Input that comes meanwhile preempts the rest: the next picture goes
//! instead and the strips not yet sent are dropped.
//!
//! kitty: each strip is an image of its own ([`kitty::strip_id`]), scaled
//! over its cells above relief's image. sixel: the frame is mapped to its
//! palette once and each strip sends its rows with the entries they use,
//! drawn at the strip's first cell row; sixel has no scaling, so this
//! needs a cell row to be a whole number of pixel rows.

use std::io;
use std::ops::Range;

use super::format::Format;
use super::{kitty, sixel};
use crate::framebuffer::Framebuffer;

/// One strip: its cell rows (from the picture area's top) and the
/// sequence that draws it once the cursor is at the first one's left.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Strip {
    pub rows: Range<u16>,
    pub seq: Vec<u8>,
}

/// `rows` cell rows split into `n` runs of near-equal height (between one
/// run and one per row), top first.
pub fn split_rows(rows: u16, n: usize) -> Vec<Range<u16>> {
    let n = n.clamp(1, usize::from(rows).max(1));
    let rows = usize::from(rows);
    (0..n)
        .map(|k| (k * rows / n) as u16..((k + 1) * rows / n) as u16)
        .collect()
}

/// The pixel rows of the cell rows `cells` in an `h`-pixel-tall picture of
/// `rows` cell rows.
pub fn pixel_rows(cells: &Range<u16>, rows: u16, h: usize) -> Range<usize> {
    let rows = usize::from(rows.max(1));
    usize::from(cells.start) * h / rows..usize::from(cells.end) * h / rows
}

/// Rows `rows` of `fb` as a picture of their own.
pub fn crop_rows(fb: &Framebuffer, rows: Range<usize>) -> Framebuffer {
    let mut out = Framebuffer::new(fb.width(), rows.len());
    let w = fb.width();
    out.pixels_mut()
        .copy_from_slice(&fb.pixels()[rows.start * w..rows.end * w]);
    out
}

/// The strips of `fb` over `cols × rows` cells in `format`: as many as
/// `total` (the whole image's bytes) needs for about `budget` bytes each.
/// `None` where strips cannot show the frame exactly (iTerm2, symbols, a
/// sixel frame whose cell rows are not whole pixel rows).
pub fn strips(
    fb: &Framebuffer,
    format: Format,
    (cols, rows): (u16, u16),
    total: usize,
    budget: f64,
    dither: bool,
) -> io::Result<Option<Vec<Strip>>> {
    let n = (total as f64 / budget.max(1.0)).ceil() as usize;
    let ranges = split_rows(rows, n);
    let h = fb.height();
    let mut out = Vec::with_capacity(ranges.len());
    match format {
        Format::Kitty => {
            for (k, cells) in ranges.into_iter().enumerate() {
                let strip = crop_rows(fb, pixel_rows(&cells, rows, h));
                let mut seq = Vec::new();
                let size = Some((cols, cells.end - cells.start));
                kitty::write_image_as(&strip, size, kitty::strip_id(k), kitty::STRIP_Z, &mut seq)?;
                out.push(Strip { rows: cells, seq });
            }
        }
        Format::Sixels if rows > 0 && h.is_multiple_of(usize::from(rows)) => {
            let q = sixel::Quantized::new(fb, dither);
            for cells in ranges {
                let mut seq = Vec::new();
                sixel::write_strip(&q, pixel_rows(&cells, rows, h), &mut seq)?;
                out.push(Strip { rows: cells, seq });
            }
        }
        _ => return Ok(None),
    }
    Ok(Some(out))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_split_evenly_and_cover_the_picture_once() {
        assert_eq!(split_rows(10, 3), vec![0..3, 3..6, 6..10]);
        // Never more strips than rows, never none.
        assert_eq!(split_rows(4, 100), vec![0..1, 1..2, 2..3, 3..4]);
        assert_eq!(split_rows(5, 0), vec![0..5]);
        assert_eq!(pixel_rows(&(3..6), 10, 160), 48..96);
        // A picture scaled below its cells: the rows in proportion.
        assert_eq!(pixel_rows(&(1..2), 3, 100), 33..66);
    }

    #[test]
    fn a_sixel_frame_of_fractional_cell_rows_is_not_split() {
        let fb = Framebuffer::new(8, 50);
        assert_eq!(
            strips(&fb, Format::Sixels, (1, 3), 100, 10.0, false).unwrap(),
            None
        );
        assert!(
            strips(&fb, Format::Iterm, (1, 5), 100, 10.0, false)
                .unwrap()
                .is_none()
        );
        let s = strips(&fb, Format::Sixels, (1, 5), 100, 10.0, false)
            .unwrap()
            .unwrap();
        assert_eq!(s.len(), 5);
    }
}
