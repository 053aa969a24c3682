//! Box-filter resolve of a supersampled frame: each output pixel is the mean
//! of its `factor × factor` block, summed in f64 and rounded once.
//!
//! Rendering `factor` times larger on both axes keeps the camera's aspect, so
//! the large frame samples the same view on a finer grid and this resolve is
//! exact supersampling.

use relief_core::framebuffer::Framebuffer;

/// Averages `factor × factor` blocks of `large` into a frame `factor` times
/// smaller on both axes. `large`'s size must be a multiple of `factor`.
pub fn box_downsample(large: &Framebuffer, factor: usize) -> Framebuffer {
    assert!(factor >= 1, "factor must be at least 1");
    assert!(
        large.width().is_multiple_of(factor) && large.height().is_multiple_of(factor),
        "{}x{} is not a multiple of {factor}",
        large.width(),
        large.height()
    );
    let (w, h) = (large.width() / factor, large.height() / factor);
    let mut out = Framebuffer::new(w, h);
    let n = (factor * factor) as f64;
    let mut sums = vec![[0.0f64; 3]; w];
    for y in 0..h {
        sums.iter_mut().for_each(|s| *s = [0.0; 3]);
        for row in large
            .pixels()
            .chunks_exact(large.width())
            .skip(y * factor)
            .take(factor)
        {
            for (x, sum) in sums.iter_mut().enumerate() {
                for p in &row[x * factor..(x + 1) * factor] {
                    for c in 0..3 {
                        sum[c] += p[c] as f64;
                    }
                }
            }
        }
        for (x, sum) in sums.iter().enumerate() {
            out.set(x, y, sum.map(|s| (s / n).round().clamp(0.0, 255.0) as u8));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn constant_image_resolves_to_the_same_constant() {
        for factor in [1, 2, 4, 8] {
            let mut large = Framebuffer::new(5 * factor, 3 * factor);
            large.fill([7, 128, 255]);
            let small = box_downsample(&large, factor);
            assert_eq!((small.width(), small.height()), (5, 3));
            assert!(small.pixels().iter().all(|&p| p == [7, 128, 255]));
        }
    }

    #[test]
    fn each_block_becomes_its_rounded_mean() {
        // 2×1 output from a 4×2 image; left block mean (0+1+2+3)/4 = 1.5 → 2,
        // right block half 255 half 0 → 127.5 → 128.
        let mut large = Framebuffer::new(4, 2);
        let left = [[0, 0, 0], [1, 1, 1], [2, 2, 2], [3, 3, 3]];
        large.set(0, 0, left[0]);
        large.set(1, 0, left[1]);
        large.set(0, 1, left[2]);
        large.set(1, 1, left[3]);
        large.set(2, 0, [255, 0, 10]);
        large.set(3, 1, [255, 0, 10]);
        let small = box_downsample(&large, 2);
        assert_eq!(small.get(0, 0), [2, 2, 2]);
        assert_eq!(small.get(1, 0), [128, 0, 5]);
    }
}
