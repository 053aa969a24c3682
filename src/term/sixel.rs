//! Sixel: the frame as bands six pixels tall, each colour of a band one
//! run-length-coded row of sixel characters, over a palette of at most
//! 256 colours.
//!
//! The palette is the frame's own colours when it has at most 256 (exact,
//! up to sixel's colour precision of 1 %), else the fixed 6×7×6 cube
//! ([`CUBE`]): choosing 256 colours per frame (median cut) would cost a
//! histogram and a nearest-colour search per frame, while the cube maps a
//! pixel with three multiplications; `dither` then spreads the cube's
//! steps with a 4×4 ordered (Bayer) pattern.

use std::collections::HashMap;
use std::io::{self, Write};

use crate::framebuffer::{Framebuffer, Rgb};

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

fn index_frame(fb: &Framebuffer, dither: bool) -> Indexed {
    let mut palette = Vec::new();
    let mut seen: HashMap<Rgb, u8> = HashMap::new();
    let mut index = Vec::with_capacity(fb.pixels().len());
    for p in fb.pixels() {
        let i = match seen.get(p) {
            Some(&i) => i,
            None if palette.len() == 256 => return cube_frame(fb, dither),
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

/// The picture a terminal shows for `fb` sent as sixel: each pixel its
/// palette entry at sixel's colour precision (the bench's error).
pub fn shown_frame(fb: &Framebuffer, dither: bool) -> Framebuffer {
    let Indexed { palette, index } = index_frame(fb, dither);
    let mut out = Framebuffer::new(fb.width(), fb.height());
    for (p, &i) in out.pixels_mut().iter_mut().zip(&index) {
        *p = shown(percent(palette[i as usize]));
    }
    out
}

/// Writes `fb` as one sixel image at the cursor.
pub fn write_image(fb: &Framebuffer, dither: bool, out: &mut impl Write) -> io::Result<()> {
    let (w, h) = (fb.width(), fb.height());
    let Indexed { palette, index } = index_frame(fb, dither);
    // P2 = 1: pixels the image does not set keep their colour.
    write!(out, "\x1bP0;1;0q\"1;1;{w};{h}")?;
    for (i, c) in palette.iter().enumerate() {
        let [r, g, b] = percent(*c);
        write!(out, "#{i};2;{r};{g};{b}")?;
    }
    let mut used = vec![false; palette.len()];
    let mut row = Vec::with_capacity(w);
    for y0 in (0..h).step_by(6) {
        let rows = (h - y0).min(6);
        used.iter_mut().for_each(|u| *u = false);
        let mut colours = Vec::new();
        for &i in &index[y0 * w..(y0 + rows) * w] {
            if !used[i as usize] {
                used[i as usize] = true;
                colours.push(i);
            }
        }
        for (n, &c) in colours.iter().enumerate() {
            row.clear();
            for x in 0..w {
                let mut bits = 0u8;
                for k in 0..rows {
                    if index[(y0 + k) * w + x] == c {
                        bits |= 1 << k;
                    }
                }
                row.push(63 + bits);
            }
            // Trailing empty sixels draw nothing.
            while row.last() == Some(&63) {
                row.pop();
            }
            if n > 0 {
                out.write_all(b"$")?;
            }
            write!(out, "#{c}")?;
            write_runs(&row, out)?;
        }
        if y0 + 6 < h {
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
