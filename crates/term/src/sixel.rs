//! Sixel: the frame as bands six pixels tall, each colour of a band one
//! run-length-coded row of sixel characters, over a palette of at most
//! 256 colours.
//!
//! The palette is the frame's own colours when it has at most 256 (exact,
//! up to sixel's colour precision of 1 %). A frame with more gets a
//! palette of its own ([`Palette::PerFrame`], by [`median_cut`]) or the
//! fixed 6×7×6 cube ([`Palette::Cube`], a pixel mapped with three
//! multiplications); `dither` adds a 4×4 ordered (Bayer) pattern before
//! the mapping. The per-frame palette is the one sent ([`Palette::CHOSEN`],
//! measured in docs/output-formats.md).

use std::collections::HashMap;
use std::io::{self, Write};

use super::median_cut;
use relief_core::framebuffer::{Framebuffer, Rgb};

/// How the palette of a frame with more than 256 colours is chosen.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Palette {
    /// 256 colours chosen for the frame (median cut).
    PerFrame,
    /// The fixed [`CUBE`].
    Cube,
}

impl Palette {
    /// The palette relief sends, with or without dithering: the per-frame
    /// one. On the reference cube (`relief bench --modes`) it shows the
    /// frame at 44.7 dB against the cube's 23.2 (41 against 21 dithered),
    /// for 2.4 times the cube's bytes undithered (still below kitty's and
    /// iTerm2's) and fewer dithered; the cube stays as the bench's
    /// comparison.
    pub const CHOSEN: Palette = Palette::PerFrame;
}

/// Levels of red, green and blue of the fixed palette (252 entries; the
/// eye is most sensitive to green).
pub const CUBE: [usize; 3] = [6, 7, 6];

/// 4×4 Bayer matrix, thresholds 0..16.
const BAYER: [[u8; 4]; 4] = [[0, 8, 2, 10], [12, 4, 14, 6], [3, 11, 1, 9], [15, 7, 13, 5]];

/// A colour as sixel sends it: each channel in whole percent.
pub fn percent(c: Rgb) -> [u8; 3] {
    c.map(|v| ((u32::from(v) * 100 + 127) / 255) as u8)
}

/// The colour a terminal shows for a palette entry sent as `percent`.
pub fn shown(p: [u8; 3]) -> Rgb {
    p.map(|v| ((u32::from(v) * 255 + 50) / 100) as u8)
}

/// The frame's palette and each pixel's entry.
struct Indexed {
    palette: Vec<Rgb>,
    index: Vec<u8>,
}

/// Spread of the ordered dither over a per-frame palette, in levels: the
/// Bayer thresholds move a pixel by up to half of it either way, so across
/// one histogram bin (4 levels) at most. On the reference cube 4, 8 and 12
/// levels measured 42.4, 41.2 and 37.7 dB (44.7 undithered): a wider
/// spread only adds noise where 256 chosen colours leave no bands.
pub const PER_FRAME_DITHER: f32 = 8.0;

fn index_frame(fb: &Framebuffer, palette_choice: Palette, dither: bool) -> Indexed {
    let mut palette = Vec::new();
    let mut seen: HashMap<Rgb, u8> = HashMap::new();
    let mut index = Vec::with_capacity(fb.pixels().len());
    for p in fb.pixels() {
        let i = match seen.get(p) {
            Some(&i) => i,
            None if palette.len() == 256 => {
                return match palette_choice {
                    Palette::Cube => cube_frame(fb, dither),
                    Palette::PerFrame => per_frame(fb, dither),
                };
            }
            None => {
                let i = palette.len() as u8;
                seen.insert(*p, i);
                palette.push(*p);
                i
            }
        };
        index.push(i);
    }
    Indexed { palette, index }
}

fn per_frame(fb: &Framebuffer, dither: bool) -> Indexed {
    let w = fb.width().max(1);
    let offset = |i: usize| {
        if !dither {
            return 0;
        }
        let t = (f32::from(BAYER[i / w % 4][i % w % 4]) + 0.5) / 16.0 - 0.5;
        (t * PER_FRAME_DITHER).round() as i16
    };
    let q = median_cut::quantize(fb.pixels(), 256, offset);
    Indexed {
        palette: q.palette,
        index: q.index,
    }
}

fn cube_frame(fb: &Framebuffer, dither: bool) -> Indexed {
    let mut palette = Vec::with_capacity(CUBE.iter().product());
    for r in 0..CUBE[0] {
        for g in 0..CUBE[1] {
            for b in 0..CUBE[2] {
                let level = |v: usize, n: usize| ((v * 255 + (n - 1) / 2) / (n - 1)) as u8;
                palette.push([level(r, CUBE[0]), level(g, CUBE[1]), level(b, CUBE[2])]);
            }
        }
    }
    let mut index = Vec::with_capacity(fb.pixels().len());
    for y in 0..fb.height() {
        for x in 0..fb.width() {
            let p = fb.get(x, y);
            // Position within a step, plus the threshold, floored.
            let t = if dither {
                (f32::from(BAYER[y % 4][x % 4]) + 0.5) / 16.0
            } else {
                0.5
            };
            let q = |c: usize| {
                let n = CUBE[c] - 1;
                ((f32::from(p[c]) * n as f32 / 255.0 + t).floor() as usize).min(n)
            };
            index.push(((q(0) * CUBE[1] + q(1)) * CUBE[2] + q(2)) as u8);
        }
    }
    Indexed { palette, index }
}

/// The picture a terminal shows for `fb` sent as sixel with `palette`:
/// each pixel its palette entry at sixel's colour precision (the bench's
/// error).
pub fn shown_frame(fb: &Framebuffer, palette: Palette, dither: bool) -> Framebuffer {
    let Indexed { palette, index } = index_frame(fb, palette, dither);
    let mut out = Framebuffer::new(fb.width(), fb.height());
    for (p, &i) in out.pixels_mut().iter_mut().zip(&index) {
        *p = shown(percent(palette[i as usize]));
    }
    out
}

/// Writes `fb` as one sixel image at the cursor, its palette as
/// [`Palette::CHOSEN`] says.
pub fn write_image(fb: &Framebuffer, dither: bool, out: &mut impl Write) -> io::Result<()> {
    write_image_with(fb, Palette::CHOSEN, dither, out)
}

/// Writes `fb` as one sixel image at the cursor with `palette`.
pub fn write_image_with(
    fb: &Framebuffer,
    palette: Palette,
    dither: bool,
    out: &mut impl Write,
) -> io::Result<()> {
    let indexed = index_frame(fb, palette, dither);
    let all = [0, 0, fb.width(), fb.height()];
    write_pixels(&indexed, fb.width(), all, false, out)
}

/// A frame mapped to its palette once, so that parts of it drawn one by
/// one ([`write_part`]) show exactly what the whole image would: the same
/// palette, the dither pattern in the same phase.
pub struct Quantized {
    indexed: Indexed,
    width: usize,
    height: usize,
}

impl Quantized {
    /// `fb` mapped as [`write_image`] maps it.
    pub fn new(fb: &Framebuffer, dither: bool) -> Self {
        Quantized {
            indexed: index_frame(fb, Palette::CHOSEN, dither),
            width: fb.width(),
            height: fb.height(),
        }
    }

    /// `small` mapped as [`Quantized::new`] maps it, each pixel then
    /// repeated to fill `size` as a nearest-neighbour enlargement does
    /// (`pixel_view::enlarge`): the enlarged picture's image for the cost of
    /// mapping the small one (a preview, a picture sized to the link).
    pub fn enlarged(small: &Framebuffer, dither: bool, size: (usize, usize)) -> Self {
        let q = Quantized::new(small, dither);
        let (sw, sh) = (small.width(), small.height());
        let (w, h) = size;
        if sw == 0 || sh == 0 {
            return Quantized::new(&Framebuffer::new(w, h), false);
        }
        let mut index = Vec::with_capacity(w * h);
        for y in 0..h {
            let row = &q.indexed.index[(y * sh / h).min(sh - 1) * sw..][..sw];
            index.extend((0..w).map(|x| row[(x * sw / w).min(sw - 1)]));
        }
        Quantized {
            indexed: Indexed {
                palette: q.indexed.palette,
                index,
            },
            width: w,
            height: h,
        }
    }

    /// Its pixel size.
    pub fn size(&self) -> (usize, usize) {
        (self.width, self.height)
    }

    /// The colour a terminal shows at pixel (x, y).
    pub fn shown_at(&self, x: usize, y: usize) -> Rgb {
        let i = self.indexed.index[y * self.width + x];
        shown(percent(self.indexed.palette[usize::from(i)]))
    }
}

/// Writes all of `q` as one sixel image at the cursor: the bytes
/// [`write_image`] writes for the frame it was made from.
pub fn write_quantized(q: &Quantized, out: &mut impl Write) -> io::Result<()> {
    let all = [0, 0, q.width, q.height];
    write_pixels(&q.indexed, q.width, all, false, out)
}

/// Writes the pixels `source` (left, top, width, height, within `q`) of
/// `q` as one sixel image at the cursor, with only the palette entries
/// they use (same numbers, same colours as the whole image's).
pub fn write_part(q: &Quantized, source: [usize; 4], out: &mut impl Write) -> io::Result<()> {
    write_pixels(&q.indexed, q.width, source, true, out)
}

/// Writes the pixels `source` of an indexed `stride`-pixel-wide frame as
/// one sixel image: all palette entries, or only those they use.
fn write_pixels(
    indexed: &Indexed,
    stride: usize,
    source: [usize; 4],
    only_used: bool,
    out: &mut impl Write,
) -> io::Result<()> {
    let Indexed { palette, index } = indexed;
    let [x0, y0, w, h] = source;
    let line = |y: usize| &index[(y0 + y) * stride + x0..(y0 + y) * stride + x0 + w];
    // P2 = 1: pixels the image does not set keep their colour.
    write!(out, "\x1bP0;1;0q\"1;1;{w};{h}")?;
    let mut used = [!only_used; 256];
    if only_used {
        for y in 0..h {
            for &i in line(y) {
                used[usize::from(i)] = true;
            }
        }
    }
    for (i, c) in palette.iter().enumerate() {
        if used[i] {
            let [r, g, b] = percent(*c);
            write!(out, "#{i};2;{r};{g};{b}")?;
        }
    }
    // Per band: each colour's slot, in order of first appearance (row by
    // row), and the slots' rows of six-pixel columns, filled in one pass.
    let mut slot = [u16::MAX; 256];
    let mut colours: Vec<u8> = Vec::with_capacity(256);
    let mut bits: Vec<u8> = Vec::new();
    for top in (0..h).step_by(6) {
        let band = top..(top + 6).min(h);
        for &c in &colours {
            slot[usize::from(c)] = u16::MAX;
        }
        colours.clear();
        for y in band.clone() {
            for &i in line(y) {
                if slot[usize::from(i)] == u16::MAX {
                    slot[usize::from(i)] = colours.len() as u16;
                    colours.push(i);
                }
            }
        }
        bits.clear();
        bits.resize(colours.len() * w, 0);
        for (k, y) in band.enumerate() {
            for (x, &i) in line(y).iter().enumerate() {
                bits[usize::from(slot[usize::from(i)]) * w + x] |= 1 << k;
            }
        }
        for (n, (&c, row)) in colours
            .iter()
            .zip(bits.chunks_exact_mut(w.max(1)))
            .enumerate()
        {
            // Trailing empty sixels draw nothing.
            let len = row.iter().rposition(|&b| b != 0).map_or(0, |p| p + 1);
            let row = &mut row[..len];
            row.iter_mut().for_each(|b| *b += 63);
            if n > 0 {
                out.write_all(b"$")?;
            }
            write!(out, "#{c}")?;
            write_runs(row, out)?;
        }
        if top + 6 < h {
            out.write_all(b"-")?;
        }
    }
    out.write_all(b"\x1b\\")
}

/// Sixel characters with runs of four or more as `!count char`.
fn write_runs(row: &[u8], out: &mut impl Write) -> io::Result<()> {
    let mut i = 0;
    while i < row.len() {
        let c = row[i];
        let run = row[i..].iter().take_while(|&&d| d == c).count();
        if run >= 4 {
            write!(out, "!{run}")?;
            out.write_all(&[c])?;
        } else {
            for _ in 0..run {
                out.write_all(&[c])?;
            }
        }
        i += run;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_enlarged_mapping_repeats_the_small_pictures_pixels() {
        // Six colours: the palette is exact.
        let mut small = Framebuffer::new(3, 2);
        for (i, p) in small.pixels_mut().iter_mut().enumerate() {
            *p = [i as u8 * 40, 255 - i as u8 * 40, 7];
        }
        let q = Quantized::enlarged(&small, false, (7, 5));
        assert_eq!(q.size(), (7, 5));
        for y in 0..5 {
            for x in 0..7 {
                let want = shown(percent(small.get(x * 3 / 7, y * 2 / 5)));
                assert_eq!(q.shown_at(x, y), want, "{x},{y}");
            }
        }
    }
}
