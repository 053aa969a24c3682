//! Resizing a grid of scalars (a height map to its colour texture's size).
//!
//! Separable, one axis then the other. Where an axis shrinks, each output
//! cell is the area-weighted mean of the input cells it covers (no aliasing,
//! the mean kept); where it grows, linear interpolation between cell centres,
//! repeating at the borders as texture coordinates do.

/// `src` is `size.0 × size.1`, row-major; the result is `to.0 × to.1`.
/// Sizes of 0 are treated as 1 (an empty source reads as 0).
///
/// The axis that shrinks the grid more goes first, so the intermediate grid
/// is never larger than the larger of source and result (a 1×16384 map onto
/// 16384×1 passes through 1×1, not 16384×16384).
pub fn grid(src: &[f32], size: (usize, usize), to: (usize, usize)) -> Vec<f32> {
    let (sw, sh) = (size.0.max(1), size.1.max(1));
    let (dw, dh) = (to.0.max(1), to.1.max(1));
    let at = |i: usize| src.get(i).copied().unwrap_or(0.0);
    let source: Vec<f32> = (0..sw * sh).map(at).collect();
    if dw.saturating_mul(sh) <= sw.saturating_mul(dh) {
        // Rows first (sw → dw), then columns (sh → dh).
        let rows = along_rows(&source, sw, sh, dw);
        along_columns(&rows, dw, sh, dh)
    } else {
        let columns = along_columns(&source, sw, sh, dh);
        along_rows(&columns, sw, dh, dw)
    }
}

/// Each of the `h` rows of a `w`-wide grid resampled to `to` cells.
fn along_rows(src: &[f32], w: usize, h: usize, to: usize) -> Vec<f32> {
    let mut result = Vec::with_capacity(to * h);
    let mut out = vec![0.0; to];
    for row in src.chunks(w).take(h) {
        axis(row, &mut out);
        result.extend_from_slice(&out);
    }
    result
}

/// Each of the `w` columns of a `h`-tall grid resampled to `to` cells.
fn along_columns(src: &[f32], w: usize, h: usize, to: usize) -> Vec<f32> {
    let mut result = vec![0.0; w * to];
    let mut column = vec![0.0; h];
    let mut out = vec![0.0; to];
    for x in 0..w {
        for (y, v) in column.iter_mut().enumerate() {
            *v = src[y * w + x];
        }
        axis(&column, &mut out);
        for (y, v) in out.iter().enumerate() {
            result[y * w + x] = *v;
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

    #[test]
    fn either_axis_order_gives_the_same_grid() {
        // 3×2 → 2×5 (rows first) and 2×5 → 3×2 (columns first): each equals
        // resampling one axis then the other by hand.
        let src = [0.0, 0.5, 1.0, 0.25, 0.75, 0.5];
        let by_hand = |src: &[f32], (sw, sh): (usize, usize), (dw, dh): (usize, usize)| {
            let cols = along_columns(src, sw, sh, dh);
            along_rows(&cols, sw, dh, dw)
        };
        for (from, to) in [((3, 2), (2, 5)), ((3, 2), (7, 1)), ((1, 6), (6, 1))] {
            let src = &src[..from.0 * from.1];
            let got = grid(src, from, to);
            let want = by_hand(src, from, to);
            for (g, w) in got.iter().zip(&want) {
                assert!((g - w).abs() < 1e-5, "{from:?}->{to:?}: {got:?} {want:?}");
            }
        }
        let tall: Vec<f32> = (0..16384).map(|i| (i % 7) as f32 / 7.0).collect();
        let wide = grid(&tall, (1, 16384), (16384, 1));
        assert_eq!(wide.len(), 16384);
        let mean = tall.iter().sum::<f32>() / 16384.0;
        assert!(wide.iter().all(|v| (v - mean).abs() < 1e-3));
    }
}
