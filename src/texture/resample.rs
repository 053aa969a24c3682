//! Resizing a grid of scalars (a height map to its colour texture's size).
//!
//! Separable, one axis then the other. Where an axis shrinks, each output
//! cell is the area-weighted mean of the input cells it covers (no aliasing,
//! the mean kept); where it grows, linear interpolation between cell centres,
//! repeating at the borders as texture coordinates do.

/// `src` is `size.0 × size.1`, row-major; the result is `to.0 × to.1`.
/// Sizes of 0 are treated as 1 (an empty source reads as 0).
pub fn grid(src: &[f32], size: (usize, usize), to: (usize, usize)) -> Vec<f32> {
    let (sw, sh) = (size.0.max(1), size.1.max(1));
    let (dw, dh) = (to.0.max(1), to.1.max(1));
    let at = |i: usize| src.get(i).copied().unwrap_or(0.0);
    // Rows first: sw → dw.
    let mut rows = Vec::with_capacity(dw * sh);
    let mut line = vec![0.0; sw];
    let mut out = vec![0.0; dw];
    for y in 0..sh {
        for (x, v) in line.iter_mut().enumerate() {
            *v = at(y * sw + x);
        }
        axis(&line, &mut out);
        rows.extend_from_slice(&out);
    }
    // Then columns: sh → dh.
    let mut result = vec![0.0; dw * dh];
    let mut column = vec![0.0; sh];
    let mut out = vec![0.0; dh];
    for x in 0..dw {
        for (y, v) in column.iter_mut().enumerate() {
            *v = rows[y * dw + x];
        }
        axis(&column, &mut out);
        for (y, v) in out.iter().enumerate() {
            result[y * dw + x] = *v;
        }
    }
    result
}

/// One line of `src.len()` cells resampled into `dst.len()` cells.
fn axis(src: &[f32], dst: &mut [f32]) {
    let (n, m) = (src.len(), dst.len());
    if n == m {
        dst.copy_from_slice(src);
    } else if m < n {
        // Output cell i covers [i·s, (i+1)·s) in input cells, s = n/m > 1.
        let s = n as f64 / m as f64;
        for (i, d) in dst.iter_mut().enumerate() {
            let (a, b) = (i as f64 * s, (i + 1) as f64 * s);
            let mut acc = 0.0f64;
            for (j, v) in src
                .iter()
                .enumerate()
                .take((b.ceil() as usize).min(n))
                .skip(a.floor() as usize)
            {
                let w = (b.min(j as f64 + 1.0) - a.max(j as f64)).max(0.0);
                acc += *v as f64 * w;
            }
            *d = (acc / s) as f32;
        }
    } else {
        // Output centre i sits at input position (i + ½)·n/m − ½.
        let s = n as f64 / m as f64;
        for (i, d) in dst.iter_mut().enumerate() {
            let p = (i as f64 + 0.5) * s - 0.5;
            let p0 = p.floor();
            let f = (p - p0) as f32;
            let i0 = (p0 as i64).rem_euclid(n as i64) as usize;
            let i1 = (i0 + 1) % n;
            *d = src[i0] + (src[i1] - src[i0]) * f;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shrinking_averages_and_keeps_the_mean() {
        // 4×1 → 2×1: pairs averaged.
        assert_eq!(grid(&[0.0, 1.0, 0.5, 0.5], (4, 1), (2, 1)), vec![0.5, 0.5]);
        // 3×1 → 2×1: cell 0 = (a + b/2)/1.5.
        let out = grid(&[0.0, 0.6, 0.3], (3, 1), (2, 1));
        assert!(
            (out[0] - 0.2).abs() < 1e-6 && (out[1] - 0.4).abs() < 1e-6,
            "{out:?}"
        );
    }

    #[test]
    fn growing_interpolates_and_wraps() {
        // 2×1 → 4×1: centres at −¼, ¼, ¾, 1¼ of an input cell.
        let out = grid(&[0.0, 1.0], (2, 1), (4, 1));
        let want = [0.25, 0.25, 0.75, 0.75];
        for (o, w) in out.iter().zip(want) {
            assert!((o - w).abs() < 1e-6, "{out:?}");
        }
        // Same size: untouched; and along y.
        assert_eq!(grid(&[0.1, 0.2], (1, 2), (1, 2)), vec![0.1, 0.2]);
        assert_eq!(grid(&[0.3], (1, 1), (2, 3)), vec![0.3; 6]);
    }
}
