//! One image level: storage, wrapping and the nearest / bilinear reads.

use super::texels::Texel;
use super::texels::{Builder, Fetch, MipKind, Texels};
use super::wrap::Wrap;
use crate::with_fetch;

/// A `width × height` grid of texels, the picture's top row first: row `y`
/// holds texture coordinate v in [y, y + 1) / height, so v = 0 is the top of
/// the image, as in the other renderers relief is compared with.
#[derive(Clone, Debug, PartialEq)]
pub struct Level {
    pub width: usize,
    pub height: usize,
    pub texels: Texels,
    /// How coordinates outside 0..1 read it, per axis (repeat unless a
    /// model's sampler says otherwise).
    pub wrap: Wrap,
}

/// Storage indices i − 1 ..= i + 2 of a bilinear 4-tap footprint's
/// neighbourhood, wrapped into 0..n. Indices reach at most 2 past either
/// end: one add or subtract wraps them, except on a 1-texel axis where every
/// index is 0.
#[inline]
pub fn around(i: i64, n: usize) -> [usize; 4] {
    let n = n as i64;
    if i >= 1 && i + 2 < n {
        // Away from the borders (nearly every read): no wrapping.
        let i = i as usize;
        return [i - 1, i, i + 1, i + 2];
    }
    [i - 1, i, i + 1, i + 2].map(|k| {
        if n == 1 {
            0
        } else if k < 0 {
            (k + n) as usize
        } else if k >= n {
            (k - n) as usize
        } else {
            k as usize
        }
    })
}

/// Wraps an integer texel index into 0..n (repeat), for any i including negatives.
#[inline]
fn wrap(i: i64, n: usize) -> usize {
    i.rem_euclid(n as i64) as usize
}

/// The fractional part of t in [0, 1), without a libm `floor` call (baseline
/// x86-64 has no rounding instruction). NaN and infinities map to 0; huge
/// values (no fraction left) also map to 0.
#[inline]
fn fract01(t: f32) -> f32 {
    if t.is_nan() || t.abs() >= 8_388_608.0 {
        // |t| ≥ 2^23 has no fractional bits; NaN fails the comparison too.
        return 0.0;
    }
    // SAFETY: |t| < 2^23 (checked above), so t truncates to an in-range i32;
    // the unchecked cast skips the saturating checks in the hottest path.
    let f = t - unsafe { t.to_int_unchecked::<i32>() } as f32;
    let f = if f < 0.0 { f + 1.0 } else { f };
    // f + 1.0 can round up to exactly 1.0 for tiny negative fractions.
    if f >= 1.0 { 0.0 } else { f }
}

/// Turns a texture coordinate into a texel-space position in [0, n),
/// robust to any float.
#[inline]
fn to_texel_space(t: f32, n: usize) -> f32 {
    // Keep only the fraction first so that huge t does not lose every bit of
    // position once multiplied by n.
    let x = fract01(t) * n as f32;
    if x < n as f32 { x } else { 0.0 }
}

/// floor(x) for −1 ≤ x < 2^23 (texel-space positions), as an integer, without libm.
#[inline]
fn floor_small(x: f32) -> i64 {
    debug_assert!((-1.0..8_388_608.0).contains(&x));
    if x < 0.0 {
        -1
    } else if x < 8_388_608.0 {
        // SAFETY: 0 ≤ x < 2^23 fits an i32.
        (unsafe { x.to_int_unchecked::<i32>() }) as i64
    } else {
        0
    }
}

/// The bilinear neighbourhood of (u, v) in a `w × h` grid read with `wrap`:
/// the storage indices of the texel columns x0 − 1 .. x0 + 2 and row starts
/// y0 − 1 .. y0 + 2 (wrapped), where (x0, y0) is the texel centre just
/// below-left of the point, and the fractions (fx, fy) between x0 and
/// x0 + 1, y0 and y0 + 1. No division: the coordinate is already reduced to
/// one period.
#[inline(always)]
pub(crate) fn neighbourhood(
    wrap: &Wrap,
    w: usize,
    h: usize,
    u: f32,
    v: f32,
) -> ([usize; 4], [usize; 4], f32, f32) {
    if !wrap.repeats() {
        let (cols, fx) = wrap.s.around(u, w);
        let (rows, fy) = wrap.t.around(v, h);
        return (cols, rows.map(|r| r * w), fx, fy);
    }
    let x = to_texel_space(u, w) - 0.5;
    let y = to_texel_space(v, h) - 0.5;
    // x lies in [−0.5, w − 0.5), so its floor is −1 ..= w − 1.
    let xi = floor_small(x).min(w as i64 - 1);
    let yi = floor_small(y).min(h as i64 - 1);
    let (xf, yf) = (xi as f32, yi as f32);
    let cols = around(xi, w);
    let rows = around(yi, h).map(|r| r * w);
    (cols, rows, x - xf, y - yf)
}

impl Level {
    /// A level with every texel equal to `texel`. Sizes of 0 become 1.
    pub fn solid(width: usize, height: usize, texel: Texel) -> Self {
        let (width, height) = (width.max(1), height.max(1));
        Level {
            wrap: Default::default(),
            width,
            height,
            texels: Texels::F32(vec![texel; width * height]),
        }
    }

    /// A level of these f32 texels (kept as f32).
    pub fn from_texels(width: usize, height: usize, texels: Vec<Texel>) -> Self {
        assert_eq!(texels.len(), width * height, "one texel per cell");
        Level {
            wrap: Default::default(),
            width,
            height,
            texels: Texels::F32(texels),
        }
    }

    /// From 8-bit RGBA rows stored top row first (as images are), kept in
    /// that order. A texture made in memory (the built-in ones) keeps f32
    /// texels and mip levels, so its pictures are those it always gave;
    /// pictures read from files are kept at their own precision (`load`).
    pub fn from_rgba8_top_down(width: usize, height: usize, rgba: &[u8]) -> Self {
        assert_eq!(rgba.len(), width * height * 4, "RGBA buffer size");
        assert!(width > 0 && height > 0, "a texture has at least one texel");
        let texels = rgba
            .chunks_exact(4)
            .map(|px| [px[0], px[1], px[2], px[3]].map(|c| c as f32 / 255.0))
            .collect();
        Level {
            wrap: Default::default(),
            width,
            height,
            texels: Texels::F32(texels),
        }
    }

    /// The level read with these wrap modes (mip levels made from it
    /// inherit them).
    pub fn with_wrap(mut self, wrap: Wrap) -> Self {
        self.wrap = wrap;
        self
    }

    /// The texel at integer coordinates, wrapped.
    #[inline]
    pub fn texel(&self, x: i64, y: i64) -> Texel {
        if !self.wrap.repeats() {
            let x = self.wrap.s.index(x, self.width);
            return self
                .texels
                .at(self.wrap.t.index(y, self.height) * self.width + x);
        }
        self.texels
            .at(wrap(y, self.height) * self.width + wrap(x, self.width))
    }

    /// The texel that contains (u, v), wrapped.
    #[inline]
    pub fn nearest(&self, u: f32, v: f32) -> Texel {
        if !self.wrap.repeats() {
            let x = self.wrap.s.nearest(u, self.width);
            return self
                .texels
                .at(self.wrap.t.nearest(v, self.height) * self.width + x);
        }
        let x = (to_texel_space(u, self.width) as usize).min(self.width - 1);
        let y = (to_texel_space(v, self.height) as usize).min(self.height - 1);
        self.texels.at(y * self.width + x)
    }

    /// The bilinear neighbourhood of (u, v) in this level ([`neighbourhood`]).
    #[inline(always)]
    fn neighbourhood(&self, u: f32, v: f32) -> ([usize; 4], [usize; 4], f32, f32) {
        neighbourhood(&self.wrap, self.width, self.height, u, v)
    }

    /// Bilinear interpolation between the four texel centres around (u, v),
    /// wrapping at the borders.
    #[inline]
    pub fn bilinear(&self, u: f32, v: f32) -> Texel {
        let (cols, rows, fx, fy) = self.neighbourhood(u, v);
        with_fetch!(&self.texels, t => bilinear_in(t, &cols, &rows, fx, fy))
    }

    /// Bilinear height alone (channel 3).
    #[inline]
    pub fn bilinear_height(&self, u: f32, v: f32) -> f32 {
        let (cols, rows, fx, fy) = self.neighbourhood(u, v);
        with_fetch!(&self.texels, t => height_quad(t, &cols, &rows, 1, 1, fx, fy))
    }

    /// ∂F/∂u and ∂F/∂v per unit of texture coordinate, exactly as the
    /// documented software renderer computes them: the texel under (u, v),
    /// its two neighbours clamped at the border (not wrapped), and
    /// (next − previous) / 2 · size.
    pub fn height_gradient_texel(&self, u: f32, v: f32) -> (f32, f32) {
        let (w, h) = (self.width, self.height);
        let x = (to_texel_space(u, w) as usize).min(w - 1);
        let y = (to_texel_space(v, h) as usize).min(h - 1);
        let at = |x: usize, y: usize| self.texels.at(y * w + x)[3];
        let (xp, xn) = (x.saturating_sub(1), (x + 1).min(w - 1));
        let (yp, yn) = (y.saturating_sub(1), (y + 1).min(h - 1));
        let du = (at(xn, y) - at(xp, y)) * 0.5 * w as f32;
        let dv = (at(x, yn) - at(x, yp)) * 0.5 * h as f32;
        (du, dv)
    }

    /// ∂F/∂u and ∂F/∂v per unit of texture coordinate from bilinear heights
    /// one texel either side: (F(u+δ) − F(u−δ)) / 2δ with δ = one texel.
    /// Continuous in (u, v), so a magnified bump map shades smoothly. The
    /// four bilinear reads share one neighbourhood (12 texels).
    #[inline]
    pub fn height_gradient_filtered(&self, u: f32, v: f32) -> (f32, f32) {
        let (cols, rows, fx, fy) = self.neighbourhood(u, v);
        let size = (self.width as f32, self.height as f32);
        with_fetch!(&self.texels, t => gradient_in(t, &cols, &rows, fx, fy, size))
    }

    /// Bilinear colour and the filtered height gradient at one point, from
    /// one shared neighbourhood: what a textured, bumped pixel reads.
    /// Identical to `bilinear` and `height_gradient_filtered` called apart.
    #[inline]
    pub fn bilinear_with_gradient(&self, u: f32, v: f32) -> (Texel, (f32, f32)) {
        let (cols, rows, fx, fy) = self.neighbourhood(u, v);
        let size = (self.width as f32, self.height as f32);
        with_fetch!(&self.texels, t => (
            bilinear_in(t, &cols, &rows, fx, fy),
            gradient_in(t, &cols, &rows, fx, fy, size),
        ))
    }

    /// Halves the level (box filter, odd sizes handled by weighting the
    /// border texels), down to 1×1.
    pub fn build_chain(&self) -> Vec<Level> {
        let mut chain: Vec<Level> = Vec::new();
        let mut current = self;
        while current.width > 1 || current.height > 1 {
            let next = current.downsample().with_wrap(self.wrap);
            chain.push(next);
            current = chain.last().expect("just pushed");
        }
        chain
    }

    /// One level down: each output texel is the area-weighted mean of the
    /// input texels it covers, so odd sizes keep the average colour exactly.
    fn downsample(&self) -> Level {
        let kind = self.texels.mip_kind();
        with_fetch!(&self.texels, t => downsample_from(t, self.width, self.height, kind))
    }
}

/// Bilinear blend of texels cols[1], cols[2] × rows[1], rows[2].
#[inline(always)]
fn bilinear_in<F: Fetch>(t: F, cols: &[usize; 4], rows: &[usize; 4], fx: f32, fy: f32) -> Texel {
    let (t00, t10) = (t.at(rows[1] + cols[1]), t.at(rows[1] + cols[2]));
    let (t01, t11) = (t.at(rows[2] + cols[1]), t.at(rows[2] + cols[2]));
    let mut out = [0.0; 4];
    for c in 0..4 {
        let top = t00[c] + (t10[c] - t00[c]) * fx;
        let bottom = t01[c] + (t11[c] - t01[c]) * fx;
        out[c] = top + (bottom - top) * fy;
    }
    out
}

/// Bilinear height between columns cols[i], cols[i+1] and rows rows[j], rows[j+1].
#[inline(always)]
fn height_quad<F: Fetch>(
    t: F,
    cols: &[usize; 4],
    rows: &[usize; 4],
    i: usize,
    j: usize,
    fx: f32,
    fy: f32,
) -> f32 {
    let h00 = t.height(rows[j] + cols[i]);
    let h10 = t.height(rows[j] + cols[i + 1]);
    let h01 = t.height(rows[j + 1] + cols[i]);
    let h11 = t.height(rows[j + 1] + cols[i + 1]);
    let top = h00 + (h10 - h00) * fx;
    let bottom = h01 + (h11 - h01) * fx;
    top + (bottom - top) * fy
}

/// The filtered height gradient from a neighbourhood (see
/// [`Level::height_gradient_filtered`]); `size` is the level's in texels.
#[inline(always)]
fn gradient_in<F: Fetch>(
    t: F,
    cols: &[usize; 4],
    rows: &[usize; 4],
    fx: f32,
    fy: f32,
    size: (f32, f32),
) -> (f32, f32) {
    let east = height_quad(t, cols, rows, 2, 1, fx, fy);
    let west = height_quad(t, cols, rows, 0, 1, fx, fy);
    let north = height_quad(t, cols, rows, 1, 2, fx, fy);
    let south = height_quad(t, cols, rows, 1, 0, fx, fy);
    ((east - west) * 0.5 * size.0, (north - south) * 0.5 * size.1)
}

/// The level below a `w × h` grid read through `t`, stored as `kind`: each
/// output texel the area-weighted mean of the input texels it covers.
pub(crate) fn downsample_from<F: Fetch>(t: F, w: usize, h: usize, kind: MipKind) -> Level {
    let nw = (w / 2).max(1);
    let nh = (h / 2).max(1);
    let sx = w as f32 / nw as f32;
    let sy = h as f32 / nh as f32;
    let mut out = Builder::new(kind, nw * nh);
    for oy in 0..nh {
        let (y0, y1) = (oy as f32 * sy, (oy + 1) as f32 * sy);
        for ox in 0..nw {
            let (x0, x1) = (ox as f32 * sx, (ox + 1) as f32 * sx);
            let mut acc = [0.0f32; 4];
            let mut total = 0.0;
            for iy in y0.floor() as usize..(y1.ceil() as usize).min(h) {
                let wy = (y1.min(iy as f32 + 1.0) - y0.max(iy as f32)).max(0.0);
                for ix in x0.floor() as usize..(x1.ceil() as usize).min(w) {
                    let wx = (x1.min(ix as f32 + 1.0) - x0.max(ix as f32)).max(0.0);
                    let weight = wx * wy;
                    let texel = t.at(iy * w + ix);
                    for c in 0..4 {
                        acc[c] += texel[c] * weight;
                    }
                    total += weight;
                }
            }
            out.push(acc.map(|a| a / total));
        }
    }
    Level {
        wrap: Default::default(),
        width: nw,
        height: nh,
        texels: out.finish(),
    }
}
