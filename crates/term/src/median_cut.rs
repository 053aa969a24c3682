//! A palette of at most 256 colours chosen for one frame (for sixel), and
//! each pixel's entry.
//!
//! The frame's colours are counted in bins of 6 bits a channel (2¹⁸ bins;
//! a bin keeps the mean of its pixels, so it loses nothing when its pixels
//! are one colour, and at most 4 levels a channel otherwise). The bins are
//! then split into boxes, greedily: each box is cut once along its channel
//! of largest variance, at the place where the two halves' summed squared
//! error is least, and the cut that lowers the error most is taken next
//! (median cut with a variance criterion). A palette entry is a box's mean;
//! each bin goes to its nearest entry (a bin near a box's edge may be
//! nearer another box's mean), so a pixel costs two table reads.

use relief_core::framebuffer::Rgb;

/// Bits per channel of the histogram.
const BITS: u32 = 6;

/// The frame's palette and each pixel's entry in it.
pub struct Quantized {
    pub palette: Vec<Rgb>,
    pub index: Vec<u8>,
}

/// A histogram bin: its pixels' count and channel sums (u64: a frame of
/// any size cannot overflow).
#[derive(Clone, Copy)]
struct Bin {
    count: u64,
    sum: [u64; 3],
}

/// A bin as a weighted point: its mean colour and its pixel count.
#[derive(Clone, Copy)]
struct Point {
    mean: [f64; 3],
    weight: f64,
}

/// Boxes of points: `points[start..end]`, their squared error about their
/// mean and the best cut found for them.
struct Box {
    start: usize,
    end: usize,
    /// Error removed by the cut, and the cut: the channel the points are
    /// sorted by and the first point of the second half.
    gain: f64,
    channel: usize,
    at: usize,
}

fn bin_of(p: Rgb) -> usize {
    let s = 8 - BITS;
    (usize::from(p[0] >> s) << (2 * BITS))
        | (usize::from(p[1] >> s) << BITS)
        | usize::from(p[2] >> s)
}

/// Chooses at most `colours` (1..=256) entries for `pixels` and maps each
/// pixel to its entry. `offset(i)` is added to pixel `i`'s channels before
/// it is mapped (0 for plain nearest-colour mapping; an ordered-dither
/// threshold otherwise); the palette is chosen from the pixels themselves.
pub fn quantize(pixels: &[Rgb], colours: usize, offset: impl Fn(usize) -> i16) -> Quantized {
    assert!((1..=256).contains(&colours));
    // The occupied bins, in order of first appearance, and a table from
    // bin to its place in that list.
    let mut slot = vec![u32::MAX; 1 << (3 * BITS)];
    let mut bins: Vec<Bin> = Vec::new();
    for p in pixels {
        let b = bin_of(*p);
        if slot[b] == u32::MAX {
            slot[b] = bins.len() as u32;
            bins.push(Bin {
                count: 0,
                sum: [0; 3],
            });
        }
        let bin = &mut bins[slot[b] as usize];
        bin.count += 1;
        for (s, &v) in bin.sum.iter_mut().zip(p) {
            *s += u64::from(v);
        }
    }
    let mut points: Vec<Point> = bins
        .iter()
        .map(|b| Point {
            mean: b.sum.map(|s| s as f64 / b.count as f64),
            weight: b.count as f64,
        })
        .collect();
    let palette = split(&mut points, colours);
    let entry_of_bin: Vec<u8> = bins
        .iter()
        .map(|b| {
            let mean = b.sum.map(|s| s as f64 / b.count as f64);
            nearest(&palette, mean)
        })
        .collect();
    // A dithered pixel may land in a bin no pixel is in: its entry is
    // found for the bin's centre the first time (the table then holds
    // entries + 1, 0 for not yet known).
    let mut empty_bins: Vec<u16> = Vec::new();
    let index = pixels
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let d = offset(i);
            if d == 0 {
                return entry_of_bin[slot[bin_of(*p)] as usize];
            }
            let q = p.map(|v| (i16::from(v) + d).clamp(0, 255) as u8);
            let b = bin_of(q);
            match slot[b] {
                u32::MAX => {
                    if empty_bins.is_empty() {
                        empty_bins = vec![0; slot.len()];
                    }
                    if empty_bins[b] == 0 {
                        let half = f64::from(1u32 << (7 - BITS));
                        let centre =
                            q.map(|v| f64::from(v >> (8 - BITS) << (8 - BITS)) + half - 0.5);
                        empty_bins[b] = u16::from(nearest(&palette, centre)) + 1;
                    }
                    (empty_bins[b] - 1) as u8
                }
                s => entry_of_bin[s as usize],
            }
        })
        .collect();
    Quantized { palette, index }
}

/// The entry nearest `c` (squared RGB distance; the first of equals).
pub fn nearest(palette: &[Rgb], c: [f64; 3]) -> u8 {
    let mut best = (f64::INFINITY, 0u8);
    for (i, e) in palette.iter().enumerate() {
        let d: f64 = (0..3).map(|k| (f64::from(e[k]) - c[k]).powi(2)).sum();
        if d < best.0 {
            best = (d, i as u8);
        }
    }
    best.1
}

/// Cuts the points into at most `colours` boxes and returns their means.
fn split(points: &mut [Point], colours: usize) -> Vec<Rgb> {
    let mut boxes = Vec::with_capacity(colours);
    if !points.is_empty() {
        boxes.push(best_cut(points, 0, points.len()));
    }
    while boxes.len() < colours {
        let Some((i, _)) = boxes
            .iter()
            .enumerate()
            .filter(|(_, b)| b.gain > 0.0)
            .max_by(|a, b| a.1.gain.total_cmp(&b.1.gain))
        else {
            break;
        };
        let Box {
            start,
            end,
            channel,
            at,
            ..
        } = boxes[i];
        points[start..end].sort_by(|a, b| a.mean[channel].total_cmp(&b.mean[channel]));
        boxes[i] = best_cut(points, start, at);
        boxes.push(best_cut(points, at, end));
    }
    boxes
        .iter()
        .map(|b| {
            let (w, s) = points[b.start..b.end]
                .iter()
                .fold((0.0, [0.0; 3]), |(w, s), p| {
                    (w + p.weight, [0, 1, 2].map(|c| s[c] + p.weight * p.mean[c]))
                });
            s.map(|v| (v / w).round().clamp(0.0, 255.0) as u8)
        })
        .collect()
}

/// The best cut of `points[start..end]`: along the channel of largest
/// variance, where the halves' squared errors sum least. Sorts the points
/// by that channel (the cut is then a position in that order).
fn best_cut(points: &mut [Point], start: usize, end: usize) -> Box {
    let none = Box {
        start,
        end,
        gain: 0.0,
        channel: 0,
        at: start,
    };
    let pts = &mut points[start..end];
    if pts.len() < 2 {
        return none;
    }
    let (mut w, mut s, mut q) = (0.0, [0.0f64; 3], [0.0f64; 3]);
    for p in pts.iter() {
        w += p.weight;
        for c in 0..3 {
            s[c] += p.weight * p.mean[c];
            q[c] += p.weight * p.mean[c] * p.mean[c];
        }
    }
    let var = [0, 1, 2].map(|c| q[c] - s[c] * s[c] / w);
    let channel = (0..3)
        .max_by(|&a, &b| var[a].total_cmp(&var[b]))
        .unwrap_or(0);
    if var[channel] <= 0.0 {
        return none;
    }
    pts.sort_by(|a, b| a.mean[channel].total_cmp(&b.mean[channel]));
    // Error of a set from its weight and sums: Σq − |s|²/w over channels;
    // Σq is the same split or not, so the cut maximises |s_a|²/w_a + |s_b|²/w_b.
    let whole: f64 = s.iter().map(|v| v * v).sum::<f64>() / w;
    let (mut wa, mut sa) = (0.0, [0.0f64; 3]);
    let mut best = (0.0, start);
    for (k, p) in pts.iter().enumerate().take(pts.len() - 1) {
        wa += p.weight;
        for (s, m) in sa.iter_mut().zip(p.mean) {
            *s += p.weight * m;
        }
        // Cut only between different values of the channel.
        if pts[k + 1].mean[channel] == p.mean[channel] {
            continue;
        }
        let wb = w - wa;
        let a: f64 = sa.iter().map(|v| v * v).sum::<f64>() / wa;
        let b: f64 = (0..3).map(|c| (s[c] - sa[c]).powi(2)).sum::<f64>() / wb;
        let gain = a + b - whole;
        if gain > best.0 {
            best = (gain, start + k + 1);
        }
    }
    Box {
        start,
        end,
        gain: best.0,
        channel,
        at: best.1,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn as_many_colours_as_entries_are_kept_exactly() {
        // 256 colours, each in a bin of its own (red and green tell them
        // apart), several pixels each.
        let colours: Vec<Rgb> = (0..256u32)
            .map(|i| {
                [
                    (i % 64 * 4 + 1) as u8,
                    (i / 64 * 60 + 3) as u8,
                    (i * 13 % 256) as u8,
                ]
            })
            .collect();
        let pixels: Vec<Rgb> = (0..2000).map(|i| colours[(i * 7) % 256]).collect();
        let q = quantize(&pixels, 256, |_| 0);
        for (p, &i) in pixels.iter().zip(&q.index) {
            assert_eq!(q.palette[i as usize], *p);
        }
    }

    #[test]
    fn two_clusters_get_their_means() {
        // 10 pixels at 10 and 12 (mean 11), 30 at 200 and 204 (mean 202).
        let mut pixels = Vec::new();
        for (v, n) in [(10u8, 5), (12, 5), (200, 15), (204, 15)] {
            pixels.extend(std::iter::repeat_n([v, v, v], n));
        }
        let q = quantize(&pixels, 2, |_| 0);
        let mut palette = q.palette.clone();
        palette.sort();
        assert_eq!(palette, vec![[11; 3], [202; 3]]);
        for (p, &i) in pixels.iter().zip(&q.index) {
            let want = if p[0] < 100 { 11 } else { 202 };
            assert_eq!(q.palette[i as usize], [want; 3]);
        }
    }

    #[test]
    fn the_cut_minimises_the_squared_error_not_the_count() {
        // 10 pixels at red 0, 30 at 4, 1 at 100. Halving the count would cut
        // between 0 and 4 (error 30·3.1² + 92.9² ≈ 8 900); the least error
        // cuts before 100 (10·3² + 30·1² = 120), its halves' means 3 and 100.
        let mut pixels = vec![[0, 0, 0]; 10];
        pixels.extend(std::iter::repeat_n([4, 0, 0], 30));
        pixels.push([100, 0, 0]);
        let q = quantize(&pixels, 2, |_| 0);
        let mut palette = q.palette.clone();
        palette.sort();
        assert_eq!(palette, vec![[3, 0, 0], [100, 0, 0]]);
    }

    #[test]
    fn pixels_go_to_their_nearest_entry() {
        let mut seed = 7u32;
        let pixels: Vec<Rgb> = (0..5000)
            .map(|_| {
                seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
                [(seed >> 24) as u8, (seed >> 16) as u8, (seed >> 8) as u8]
            })
            .collect();
        let q = quantize(&pixels, 16, |_| 0);
        assert_eq!(q.palette.len(), 16);
        for (p, &i) in pixels.iter().zip(&q.index) {
            let d = |e: Rgb| {
                (0..3)
                    .map(|k| (i32::from(e[k]) - i32::from(p[k])).pow(2))
                    .sum::<i32>()
            };
            let best = q.palette.iter().map(|&e| d(e)).min().unwrap();
            // Mapped by the bin's mean, at most √27 from the pixel (3 levels a
            // channel): at most twice that worse than the nearest.
            let got = d(q.palette[i as usize]) as f64;
            let slack = (best as f64).sqrt() + 2.0 * 27f64.sqrt();
            assert!(got <= slack * slack, "{p:?}: {got} vs best {best}");
        }
    }
}
