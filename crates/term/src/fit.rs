//! The exact two-colour fit of a cell: which pixels take the foreground,
//! and the two colours, with the least squared error.
//!
//! For a split of the pixels into groups A and B the best colours are the
//! groups' means, and the error is `Σ|p|² − |S_A|²/n_A − |S_B|²/n_B`
//! (`S` a group's sum, `n` its size). So the best split is the one with
//! the largest `|S_A|²/n_A + |S_B|²/n_B`. A split and its complement are
//! the same fit with the colours swapped: the last pixel stays in B, which
//! leaves 2^(n−1) splits. The group sums come from one addition each
//! (a mask's sum is that of the mask without its lowest bit plus that
//! pixel), and the comparison is exact in integers: both terms are scaled
//! by 840, the least common multiple of 1..=8.

use relief_core::framebuffer::Rgb;

/// At most this many pixels in a cell (octants).
pub const MAX_PIXELS: usize = 8;

/// 840 / n for n in 1..=8 (index 0 unused: an empty group adds nothing).
const SCALE: [u64; MAX_PIXELS + 1] = [0, 840, 420, 280, 210, 168, 140, 120, 105];

/// A cell's best two-colour picture.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Fit {
    /// Pixels that take `fg` (bit i = pixel i); never has the last pixel.
    pub mask: u8,
    /// Mean of the masked pixels (meaningless when `mask` is 0).
    pub fg: Rgb,
    /// Mean of the others.
    pub bg: Rgb,
}

/// The fit of `pixels` (1 to [`MAX_PIXELS`] of them).
pub fn fit(pixels: &[Rgb]) -> Fit {
    let n = pixels.len();
    debug_assert!((1..=MAX_PIXELS).contains(&n));
    let mut total = [0u32; 3];
    for p in pixels {
        for c in 0..3 {
            total[c] += u32::from(p[c]);
        }
    }
    // One colour: nothing to split (and the common flat cell, fast).
    if pixels.iter().all(|p| *p == pixels[0]) {
        return Fit {
            mask: 0,
            fg: pixels[0],
            bg: pixels[0],
        };
    }
    let splits = 1usize << (n - 1);
    let mut sums = [[0u32; 3]; 1 << (MAX_PIXELS - 1)];
    let norm = |s: [u32; 3]| -> u64 { s.iter().map(|&v| u64::from(v) * u64::from(v)).sum() };
    // Mask 0 (one group of all pixels) is the baseline every split beats or ties.
    let mut best = (0usize, norm(total) * SCALE[n]);
    for mask in 1..splits {
        let low = mask.trailing_zeros() as usize;
        let rest = sums[mask & (mask - 1)];
        let p = pixels[low];
        let s = [
            rest[0] + u32::from(p[0]),
            rest[1] + u32::from(p[1]),
            rest[2] + u32::from(p[2]),
        ];
        sums[mask] = s;
        let na = mask.count_ones() as usize;
        let other = [total[0] - s[0], total[1] - s[1], total[2] - s[2]];
        let score = norm(s) * SCALE[na] + norm(other) * SCALE[n - na];
        if score > best.1 {
            best = (mask, score);
        }
    }
    let mask = best.0;
    let na = mask.count_ones();
    let s = sums[mask];
    let other = [total[0] - s[0], total[1] - s[1], total[2] - s[2]];
    Fit {
        mask: mask as u8,
        fg: mean(s, na),
        bg: mean(other, n as u32 - na),
    }
}

/// `sum / count` rounded to the nearest level.
fn mean(sum: [u32; 3], count: u32) -> Rgb {
    if count == 0 {
        return [0; 3];
    }
    sum.map(|v| ((v + count / 2) / count) as u8)
}

/// Squared error of showing `pixels` with `mask`, `fg` and `bg`.
pub fn error(pixels: &[Rgb], mask: u8, fg: Rgb, bg: Rgb) -> u64 {
    pixels
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let shown = if mask >> i & 1 == 1 { fg } else { bg };
            (0..3)
                .map(|c| {
                    let d = i64::from(p[c]) - i64::from(shown[c]);
                    (d * d) as u64
                })
                .sum::<u64>()
        })
        .sum()
}
