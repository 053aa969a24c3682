//! Cell rectangles of the picture on screen, and the bytes that send one
//! of them again: the one notion behind both a panel over a pixel image
//! (the picture around it; the cells it leaves when it closes) and the
//! exact frame sent in strips over a slow link (a strip is a rectangle of
//! whole cell rows).
//!
//! The picture is kept ([`Kept`]) as it was sent: sixel's mapped to its
//! palette once, so a rectangle of it has the whole frame's palette and
//! dither pattern (no seam where it meets the rest); kitty's and iTerm2's
//! as RGB. A sixel rectangle is the image's own pixels under its cells;
//! kitty and iTerm2 stretch a rectangle's pixels over its cells.

use std::io;

use ratatui::layout::Rect;

use super::format::Format;
use super::{iterm, kitty, sixel};
use relief_core::framebuffer::Framebuffer;

/// Exact tiling of the cells of `area` whose flag in `cells` (row by row)
/// is `which`, by rectangles: each row's runs, a run extending the
/// rectangle above it when it spans the same columns. A panel over the
/// picture leaves at most four.
pub fn rectangles(cells: &[bool], area: Rect, which: bool) -> Vec<Rect> {
    let (w, h) = (usize::from(area.width), usize::from(area.height));
    let mut done = Vec::new();
    // Rectangles reaching the row above.
    let mut open: Vec<Rect> = Vec::new();
    for y in 0..h {
        let row = &cells[y * w..(y + 1) * w];
        let mut next = Vec::new();
        let mut x = 0;
        while x < w {
            if row[x] != which {
                x += 1;
                continue;
            }
            let start = x;
            while x < w && row[x] == which {
                x += 1;
            }
            let (left, width) = (area.x + start as u16, (x - start) as u16);
            match open.iter().position(|r| r.x == left && r.width == width) {
                Some(i) => {
                    let mut r = open.swap_remove(i);
                    r.height += 1;
                    next.push(r);
                }
                None => next.push(Rect::new(left, area.y + y as u16, width, 1)),
            }
        }
        done.append(&mut open);
        open = next;
    }
    done.append(&mut open);
    done.sort_by_key(|r| (r.y, r.x));
    done
}

/// The rectangles of `open` within `part`, clipped to it.
pub fn within(open: &[Rect], part: Rect) -> Vec<Rect> {
    open.iter()
        .map(|r| r.intersection(part))
        .filter(|r| !r.is_empty())
        .collect()
}

/// `rows` cell rows from `area`'s top split into `n` full-width strips of
/// near-equal height (between one strip and one per row), top first.
pub fn strips(area: Rect, n: usize) -> Vec<Rect> {
    let rows = usize::from(area.height);
    let n = n.clamp(1, rows.max(1));
    (0..n)
        .map(|k| {
            let (y0, y1) = (k * rows / n, (k + 1) * rows / n);
            Rect::new(area.x, area.y + y0 as u16, area.width, (y1 - y0) as u16)
        })
        .filter(|r| !r.is_empty())
        .collect()
}

/// The pixels of an `image` stretched over `area` under the cells `r`:
/// left, top, width, height (at least one pixel each way, within the
/// image; neighbouring cells share their edges, so a tiling of cells is a
/// tiling of pixels).
pub fn source_rect(image: (usize, usize), area: Rect, r: Rect) -> kitty::Source {
    let (w, h) = (image.0.max(1), image.1.max(1));
    let (cols, rows) = (
        usize::from(area.width.max(1)),
        usize::from(area.height.max(1)),
    );
    let edge = |cell: u16, origin: u16, cells: usize, size: usize| {
        (usize::from(cell - origin) * size / cells).min(size - 1)
    };
    let x0 = edge(r.x, area.x, cols, w);
    let y0 = edge(r.y, area.y, rows, h);
    let x1 = (usize::from(r.right() - area.x) * w / cols).max(x0 + 1);
    let y1 = (usize::from(r.bottom() - area.y) * h / rows).max(y0 + 1);
    [x0, y0, x1 - x0, y1 - y0]
}

/// The pixels under the cells `r` of an image shown at its own size from
/// `area`'s top-left, `cell` pixels a cell, clipped to the image (`size`):
/// sixel's rectangles (possibly empty).
pub fn own_pixels(
    size: (usize, usize),
    cell: (usize, usize),
    area: Rect,
    r: Rect,
) -> kitty::Source {
    let x0 = (usize::from(r.x - area.x) * cell.0).min(size.0);
    let y0 = (usize::from(r.y - area.y) * cell.1).min(size.1);
    let x1 = (usize::from(r.right() - area.x) * cell.0).min(size.0);
    let y1 = (usize::from(r.bottom() - area.y) * cell.1).min(size.1);
    [x0, y0, x1 - x0, y1 - y0]
}

/// The pixels `source` of `fb` as a picture of their own.
pub fn crop(fb: &Framebuffer, source: kitty::Source) -> Framebuffer {
    let [x, y, w, h] = source;
    let mut part = Framebuffer::new(w, h);
    for row in 0..h {
        part.pixels_mut()[row * w..(row + 1) * w].copy_from_slice(&fb.row(y + row)[x..x + w]);
    }
    part
}

/// The picture the cells show, as it was sent, kept so that any cell
/// rectangle of it can be sent again.
pub enum Kept {
    /// Nothing yet (or text).
    None,
    /// kitty and iTerm2: the RGB frame.
    Rgb(Framebuffer),
    /// sixel: the frame mapped to its palette.
    Indexed(sixel::Quantized),
    /// sixel: the frame not mapped yet (`dither` or not): an exact frame
    /// that goes in strips is mapped for the first one, after the picture
    /// sized to the link has gone.
    Unmapped(Framebuffer, bool),
}

impl Kept {
    /// `fb` kept for `format` (sixel: to be mapped to its palette, `dither`
    /// or not, when first needed), as a copy.
    pub fn keep(&mut self, fb: &Framebuffer, format: Format, dither: bool) {
        *self = match format {
            Format::Sixels => Kept::Unmapped(fb.clone(), dither),
            Format::Kitty | Format::Iterm => Kept::Rgb(fb.clone()),
            Format::Auto | Format::Symbols => Kept::None,
        };
    }

    /// A sixel frame mapped to its palette, if it was not yet.
    pub fn map(&mut self) {
        if let Kept::Unmapped(fb, dither) = self {
            *self = Kept::Indexed(sixel::Quantized::new(fb, *dither));
        }
    }

    /// Its pixel size.
    pub fn size(&self) -> (usize, usize) {
        match self {
            Kept::None => (0, 0),
            Kept::Rgb(fb) | Kept::Unmapped(fb, _) => (fb.width(), fb.height()),
            Kept::Indexed(q) => q.size(),
        }
    }

    /// The sixel or iTerm2 image of the cells `r` of `area` (sixel at its
    /// own pixels, `cell` pixels a cell; iTerm2 stretched over `r`'s
    /// cells), to draw at `r`'s top-left; empty when `r` holds no pixel
    /// of it. kitty's rectangles are placements ([`kitty_layer`]).
    pub fn part(&mut self, area: Rect, cell: (usize, usize), r: Rect) -> io::Result<Vec<u8>> {
        self.map();
        let mut seq = Vec::new();
        match self {
            Kept::Indexed(q) => {
                let source = own_pixels(q.size(), cell, area, r);
                if source[2] > 0 && source[3] > 0 {
                    sixel::write_part(q, source, &mut seq)?;
                }
            }
            Kept::Rgb(fb) => {
                let part = crop(fb, source_rect((fb.width(), fb.height()), area, r));
                iterm::write_image(&part, Some((r.width, r.height)), &mut seq)?;
            }
            Kept::None | Kept::Unmapped(..) => {}
        }
        Ok(seq)
    }
}

/// A kitty image shown over cells: relief's picture over the whole area,
/// or a strip of the exact frame over its rows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Layer {
    pub id: u32,
    pub z: i32,
    /// The cells it is stretched over.
    pub cells: Rect,
    /// Its pixel size.
    pub image: (usize, usize),
}

/// kitty placements of `layer` over the cells `open` (clipped to its
/// cells), numbered from 1, each as (cursor move, sequence).
pub fn kitty_layer(layer: Layer, open: &[Rect]) -> io::Result<Vec<(Rect, Vec<u8>)>> {
    let mut out = Vec::new();
    for (i, r) in within(open, layer.cells).into_iter().enumerate() {
        let mut seq = Vec::new();
        let id = kitty::PlacementId {
            image: layer.id,
            placement: i as u32 + 1,
            z: layer.z,
        };
        let source = source_rect(layer.image, layer.cells, r);
        kitty::write_placement(id, source, (r.width, r.height), &mut seq)?;
        out.push((r, seq));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The cells of `area` (row by row) inside any of `panels`.
    fn mask(area: Rect, panels: &[Rect]) -> Vec<bool> {
        let mut m = Vec::new();
        for y in area.top()..area.bottom() {
            for x in area.left()..area.right() {
                m.push(panels.iter().any(|p| p.contains((x, y).into())));
            }
        }
        m
    }

    #[test]
    fn rectangles_tile_exactly_the_cells_asked_for() {
        let area = Rect::new(2, 1, 20, 10);
        // A centred panel: the band above, left, right and the band below.
        let help = Rect::new(7, 4, 8, 3);
        let m = mask(area, &[help]);
        let open = rectangles(&m, area, false);
        assert_eq!(
            open,
            vec![
                Rect::new(2, 1, 20, 3),
                Rect::new(2, 4, 5, 3),
                Rect::new(15, 4, 7, 3),
                Rect::new(2, 7, 20, 4),
            ]
        );
        assert_eq!(rectangles(&m, area, true), vec![help]);
        // Two panels, one at a corner and one overlapping it: every cell
        // of the area once, in a rectangle of its own kind.
        let panels = [Rect::new(10, 1, 12, 5), Rect::new(4, 3, 9, 6)];
        let m = mask(area, &panels);
        let mut seen = vec![0; m.len()];
        for which in [false, true] {
            for r in rectangles(&m, area, which) {
                for y in r.top()..r.bottom() {
                    for x in r.left()..r.right() {
                        let i = usize::from(y - area.y) * 20 + usize::from(x - area.x);
                        assert_eq!(m[i], which, "{r:?}");
                        seen[i] += 1;
                    }
                }
            }
        }
        assert!(seen.iter().all(|&n| n == 1));
        assert!(rectangles(&[false; 200], area, true).is_empty());
        assert_eq!(rectangles(&[false; 200], area, false), vec![area]);
        // Clipped to a strip of rows 5..7: the left and right of the panel
        // (rows 5, 6) and the band below's first row.
        let strip = Rect::new(2, 5, 20, 3);
        assert_eq!(
            within(&open, strip),
            vec![
                Rect::new(2, 5, 5, 2),
                Rect::new(15, 5, 7, 2),
                Rect::new(2, 7, 20, 1)
            ]
        );
    }

    #[test]
    fn strips_split_the_rows_evenly_and_cover_the_area_once() {
        let area = Rect::new(3, 2, 40, 10);
        let rows =
            |s: Vec<Rect>| -> Vec<(u16, u16)> { s.iter().map(|r| (r.y, r.height)).collect() };
        assert_eq!(rows(strips(area, 3)), [(2, 3), (5, 3), (8, 4)]);
        assert!(strips(area, 3).iter().all(|r| r.x == 3 && r.width == 40));
        // Never more strips than rows, never none.
        assert_eq!(strips(area, 100).len(), 10);
        assert_eq!(strips(area, 0), vec![area]);
    }

    #[test]
    fn source_rectangles_follow_the_cells_and_share_their_edges() {
        let area = Rect::new(0, 0, 60, 12);
        // 8×16 pixels a cell: whole cells of pixels.
        assert_eq!(
            source_rect((480, 192), area, Rect::new(16, 2, 44, 10)),
            [128, 32, 352, 160]
        );
        // A preview of 100 × 30 pixels stretched over the cells: edges at
        // ⌊cell · 100 / 60⌋ and ⌊cell · 30 / 12⌋; neighbours meet.
        let left = source_rect((100, 30), area, Rect::new(0, 0, 16, 12));
        let right = source_rect((100, 30), area, Rect::new(16, 0, 44, 5));
        let below = source_rect((100, 30), area, Rect::new(16, 5, 44, 7));
        assert_eq!(left, [0, 0, 26, 30]);
        assert_eq!(right, [26, 0, 74, 12]);
        assert_eq!(below, [26, 12, 74, 18]);
        // Never empty (kitty reads a width of 0 as the whole image).
        assert_eq!(
            source_rect((30, 6), area, Rect::new(1, 1, 1, 1)),
            [0, 0, 1, 1]
        );
        // At its own size, clipped: an image of 470 × 190 over 8 × 16
        // cells ends inside its last column and row.
        assert_eq!(
            own_pixels((470, 190), (8, 16), area, Rect::new(58, 11, 2, 1)),
            [464, 176, 6, 14]
        );
    }

    #[test]
    fn a_kitty_layer_is_placed_over_the_open_cells_within_it_only() {
        // A strip of rows 4..8 of a 20 × 10 area, its own 160 × 64 pixels,
        // a panel over columns 5..10 of rows 2..6.
        let area = Rect::new(0, 0, 20, 10);
        let panel = Rect::new(5, 2, 5, 4);
        let mut m = vec![false; 200];
        for y in 2..6 {
            for x in 5..10 {
                m[y * 20 + x] = true;
            }
        }
        let open = rectangles(&m, area, false);
        let layer = Layer {
            id: kitty::strip_id(0),
            z: kitty::STRIP_Z,
            cells: Rect::new(0, 4, 20, 4),
            image: (160, 64),
        };
        let placed = kitty_layer(layer, &open).unwrap();
        let cells: Vec<Rect> = placed.iter().map(|(r, _)| *r).collect();
        assert_eq!(
            cells,
            [
                Rect::new(0, 4, 5, 2),
                Rect::new(10, 4, 10, 2),
                Rect::new(0, 6, 20, 2)
            ]
        );
        assert!(cells.iter().all(|r| r.intersection(panel).is_empty()));
        let text = String::from_utf8(placed[1].1.clone()).unwrap();
        let id = kitty::strip_id(0);
        assert_eq!(
            text,
            format!("\x1b_Ga=p,i={id},p=2,x=80,y=0,w=80,h=32,c=10,r=2,C=1,q=2,z=1\x1b\\")
        );
    }
}
