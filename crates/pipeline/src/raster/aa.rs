//! Anti-aliasing (docs/antialiasing.md: SSAA, MSAA).
//!
//! - Supersampling k×k: the frame is drawn at k times the resolution into a
//!   scratch framebuffer, then each pixel is the exact box average of its k²
//!   samples. Every sample is shaded.
//! - Multisampling 4: four coverage samples per pixel on a rotated grid, each
//!   with its own depth; the shader runs once per pixel and triangle, at the
//!   centroid of the covered samples (the pixel centre when all four are
//!   covered, since the pattern is centred), and its colour goes to the
//!   covered samples. A pixel is the average of its four samples.
//!
//! Resolves average the 8-bit values the renderer writes (the same space as
//! every other pixel: no linear-light conversion), rounded to nearest.

use super::alpha::AlphaRule;
use super::backdrop::Backdrop;
use super::fill::fill;
use super::pending::Pending;
use super::scan::{
    Band, OwnedBand, depth_prepass, pixel_setup, raster_owned, raster_triangle, shade_at,
};
use super::setup::{ONE, ScreenTri};
use crate::shade::{PixelShader, ShadeCtx};
use relief_core::framebuffer::{Framebuffer, Rgb};
use relief_core::stats::Counters;

/// Samples per pixel of multisampling.
pub const MSAA_SAMPLES: usize = 4;

/// The rotated-grid pattern, in 1/256 pixel (the rasterizer's fixed point)
/// from the pixel centre: (−1/8, −3/8), (3/8, −1/8), (−3/8, 1/8), (1/8, 3/8).
/// No two samples share a row or a column, and they sum to zero.
pub const MSAA4_OFFSETS: [(i64, i64); MSAA_SAMPLES] = [(-32, -96), (96, -32), (-96, 32), (32, 96)];

/// How far a sample lies from its pixel centre at most, on either axis:
/// the triangle setup's reach for multisampling.
pub const MSAA_REACH: i64 = 96;

// The supersampling factor is a settings decision (the memory budget needs
// it too, and sits below the rasterizer).

/// Box-filters `src` (k times `dst` in each direction) into `dst`.
pub fn resolve_box(src: &Framebuffer, k: usize, dst: &mut Framebuffer) {
    let (w, h) = (dst.width(), dst.height());
    assert!(
        src.width() == w * k && src.height() == h * k,
        "supersampled size"
    );
    let n = (k * k) as u32;
    let src_px = src.pixels();
    let sw = src.width();
    for (y, row) in dst.pixels_mut().chunks_mut(w.max(1)).enumerate().take(h) {
        for (x, out) in row.iter_mut().enumerate() {
            let mut sum = [0u32; 3];
            for sy in y * k..(y + 1) * k {
                for p in &src_px[sy * sw + x * k..sy * sw + (x + 1) * k] {
                    for c in 0..3 {
                        sum[c] += p[c] as u32;
                    }
                }
            }
            *out = sum.map(|s| ((s + n / 2) / n) as u8);
        }
    }
}

/// Averages each pixel's four samples into `dst`.
pub fn resolve_msaa(samples: &[[Rgb; MSAA_SAMPLES]], dst: &mut [Rgb]) {
    for (out, s) in dst.iter_mut().zip(samples) {
        let mut sum = [0u32; 3];
        for p in s {
            for c in 0..3 {
                sum[c] += p[c] as u32;
            }
        }
        *out = sum.map(|v| ((v + 2) / 4) as u8);
    }
}

/// What a triangle is drawn into: a band of pixels, or of samples.
pub trait RasterTarget {
    /// Fills the band with its part of the backdrop.
    fn clear(&mut self, backdrop: &Backdrop);
    /// Draws the part of `tri` inside the band with shader `S`.
    fn raster<S: PixelShader>(
        &mut self,
        tri: &ScreenTri,
        shader: &S,
        ctx: &ShadeCtx,
        counters: &mut Counters,
    );
    /// Whether every triangle's depth is drawn ([`RasterTarget::prepass`])
    /// before any is shaded.
    fn depth_first(&self) -> bool {
        false
    }
    /// The depth pre-pass of `tri`, for a target that draws depth first.
    fn prepass(&mut self, _tri: &ScreenTri, _counters: &mut Counters) {}
    /// The target's deferred pixels (`raster::pending`) with its colours
    /// and depths; none for a target that defers nothing.
    fn pending(&mut self) -> Option<PendingTarget<'_>> {
        None
    }
}

/// A band's deferred pixels and where they are written.
pub struct PendingTarget<'a> {
    pub pending: &'a mut Pending,
    pub color: &'a mut [Rgb],
    /// The depths the pixels are checked against (`pending::write_packet`).
    pub depth: Option<&'a [f32]>,
}

impl RasterTarget for OwnedBand<'_> {
    fn clear(&mut self, backdrop: &Backdrop) {
        self.band.clear(backdrop);
        fill(self.owner, u32::MAX);
    }
    #[inline]
    fn raster<S: PixelShader>(
        &mut self,
        tri: &ScreenTri,
        shader: &S,
        ctx: &ShadeCtx,
        counters: &mut Counters,
    ) {
        raster_owned(tri, shader, ctx, self, counters)
    }
    fn depth_first(&self) -> bool {
        true
    }
    fn prepass(&mut self, tri: &ScreenTri, counters: &mut Counters) {
        depth_prepass(tri, self, counters)
    }
    fn pending(&mut self) -> Option<PendingTarget<'_>> {
        self.band.pending()
    }
}

impl RasterTarget for Band<'_> {
    fn clear(&mut self, backdrop: &Backdrop) {
        backdrop.fill(self.color, self.y0, self.width);
    }
    #[inline]
    fn raster<S: PixelShader>(
        &mut self,
        tri: &ScreenTri,
        shader: &S,
        ctx: &ShadeCtx,
        counters: &mut Counters,
    ) {
        raster_triangle(tri, shader, ctx, self, counters)
    }
    fn pending(&mut self) -> Option<PendingTarget<'_>> {
        Some(PendingTarget {
            pending: &mut self.pending,
            color: self.color,
            depth: self.depth.as_deref(),
        })
    }
}

impl RasterTarget for MsaaBand<'_> {
    fn clear(&mut self, backdrop: &Backdrop) {
        match backdrop {
            Backdrop::Plain(c) => fill(self.samples, [*c; MSAA_SAMPLES]),
            Backdrop::Picture(p) => {
                let start = self.y0 * self.width;
                for (k, s) in self.samples.iter_mut().enumerate() {
                    *s = [p.get(start + k).copied().unwrap_or([0; 3]); MSAA_SAMPLES];
                }
            }
        }
    }
    #[inline]
    fn raster<S: PixelShader>(
        &mut self,
        tri: &ScreenTri,
        shader: &S,
        ctx: &ShadeCtx,
        counters: &mut Counters,
    ) {
        raster_triangle_msaa(tri, shader, ctx, self, counters)
    }
}

/// A band of the multisampled frame owned by one task: four colours (and
/// depths, when depth is on) per pixel.
pub struct MsaaBand<'a> {
    pub y0: usize,
    pub width: usize,
    pub samples: &'a mut [[Rgb; MSAA_SAMPLES]],
    pub depth: Option<&'a mut [[f32; MSAA_SAMPLES]]>,
}

impl MsaaBand<'_> {
    pub fn rows(&self) -> usize {
        self.samples.len().checked_div(self.width).unwrap_or(0)
    }
}

/// Rasterizes the part of `tri` inside `band` with four samples per pixel,
/// shading once per covered pixel.
pub fn raster_triangle_msaa<S: PixelShader>(
    tri: &ScreenTri,
    shader: &S,
    ctx: &ShadeCtx,
    band: &mut MsaaBand,
    counters: &mut Counters,
) {
    let width = band.width;
    let band_last = band.y0 + band.rows();
    // The triangle was set up with the samples' reach (`MSAA_REACH`): its
    // bounds hold every pixel with a sample inside.
    let ya = (tri.y0 as usize).max(band.y0);
    let yb = (tri.y1 as usize + 1).min(band_last);
    if ya >= yb || width == 0 {
        return;
    }
    let xa = tri.x0 as usize;
    let xb = (tri.x1 as usize).min(width - 1);
    let (footprint, inv_area, steps) = pixel_setup(tri, shader, ctx);
    // An alpha mask drops a pixel (all its samples) at its centre; a
    // translucent pixel is composited over each covered sample.
    let alpha = AlphaRule::of(shader, ctx);
    let blends = alpha.blends();
    let delta = sample_edge_offsets(&steps);
    let dz = sample_depth_offsets(tri);
    let cx = xa as i64 * ONE + ONE / 2;
    for py in ya..yb {
        let cy = py as i64 * ONE + ONE / 2;
        let mut e = tri.edges(cx, cy);
        let row = (py - band.y0) * width;
        for px in xa..=xb {
            let mut mask = covered_samples(&e, &delta, &tri.bias);
            let mut opacity = 1.0;
            if mask != 0 && alpha != AlphaRule::Opaque {
                let l = edge_weights(&e, inv_area);
                match alpha.coverage(tri, shader, ctx, l) {
                    Some(a) => opacity = a,
                    None => mask = 0,
                }
            }
            if mask != 0
                && let Some(depth) = band.depth.as_deref_mut()
            {
                let z = (e[0] as f32 * tri.z[0] + e[1] as f32 * tri.z[1] + e[2] as f32 * tri.z[2])
                    * inv_area;
                mask = depth_test_samples(&mut depth[row + px], mask, z, &dz, blends, counters);
            }
            if mask != 0 {
                // Shade at the centroid of the covered samples.
                let l = centroid_weights(&e, &delta, mask, inv_area);
                let color = shade_at(tri, shader, ctx, footprint.as_ref(), l, counters);
                let slots = &mut band.samples[row + px];
                for (s, slot) in slots.iter_mut().enumerate() {
                    if mask & (1 << s) != 0 {
                        *slot = alpha.composite(*slot, color, opacity);
                    }
                }
            }
            e[0] += steps[0].0;
            e[1] += steps[1].0;
            e[2] += steps[2].0;
        }
    }
}

/// The samples of the pixel of edge values `e` that the triangle covers, a
/// bit each: `delta` holds each sample's edge offsets from the centre.
#[inline(always)]
fn covered_samples(e: &[i64; 3], delta: &[[i64; 3]; MSAA_SAMPLES], bias: &[i64; 3]) -> u8 {
    let mut mask = 0u8;
    for (s, d) in delta.iter().enumerate() {
        if (e[0] + d[0] + bias[0]) | (e[1] + d[1] + bias[1]) | (e[2] + d[2] + bias[2]) >= 0 {
            mask |= 1 << s;
        }
    }
    mask
}

/// The samples of `mask` nearer than the depths in `slots` (depth `z` at
/// the centre plus each sample's `dz`), their depths written unless the
/// triangle `blends`.
#[inline(always)]
fn depth_test_samples(
    slots: &mut [f32; MSAA_SAMPLES],
    mut mask: u8,
    z: f32,
    dz: &[f32; MSAA_SAMPLES],
    blends: bool,
    counters: &mut Counters,
) -> u8 {
    for s in 0..MSAA_SAMPLES {
        if mask & (1 << s) != 0 {
            counters.depth_tests += 1;
            let zs = z + dz[s];
            if zs < slots[s] {
                if !blends {
                    slots[s] = zs;
                }
            } else {
                mask &= !(1 << s);
            }
        }
    }
    mask
}

// The helpers below are not generic over the shader: the rasterizer is
// compiled once per kernel, and what it calls that is not generic is not.

/// Edge offsets of each sample from the pixel centre (exact integers).
#[inline(always)]
fn sample_edge_offsets(steps: &[(i64, i64); 3]) -> [[i64; 3]; MSAA_SAMPLES] {
    MSAA4_OFFSETS.map(|(ox, oy)| [0, 1, 2].map(|i| (steps[i].0 * ox + steps[i].1 * oy) / ONE))
}

/// Depth offsets of each sample from the pixel centre.
#[inline(always)]
fn sample_depth_offsets(tri: &ScreenTri) -> [f32; MSAA_SAMPLES] {
    let (lx, ly) = tri.lambda_steps();
    let dz_dx = lx[0] * tri.z[0] + lx[1] * tri.z[1] + lx[2] * tri.z[2];
    let dz_dy = ly[0] * tri.z[0] + ly[1] * tri.z[1] + ly[2] * tri.z[2];
    MSAA4_OFFSETS.map(|(ox, oy)| (dz_dx * ox as f32 + dz_dy * oy as f32) / ONE as f32)
}

/// The edge weights at the pixel centre.
#[inline(always)]
fn edge_weights(e: &[i64; 3], inv_area: f32) -> [f32; 3] {
    [0, 1, 2].map(|i| e[i] as f32 * inv_area)
}

/// The edge weights at the centroid of the covered samples of `mask`.
#[inline(always)]
fn centroid_weights(
    e: &[i64; 3],
    delta: &[[i64; 3]; MSAA_SAMPLES],
    mask: u8,
    inv_area: f32,
) -> [f32; 3] {
    let count = mask.count_ones() as f32;
    let mut sum = [0i64; 3];
    for (s, d) in delta.iter().enumerate() {
        if mask & (1 << s) != 0 {
            for i in 0..3 {
                sum[i] += d[i];
            }
        }
    }
    [0, 1, 2].map(|i| (e[i] as f32 + sum[i] as f32 / count) * inv_area)
}

#[cfg(test)]
mod tests {
    use super::*;
    use relief_core::settings::AntiAlias;
    use relief_core::settings::ssaa_factor;

    #[test]
    fn pattern_is_a_centred_rotated_grid() {
        let (sx, sy) = MSAA4_OFFSETS
            .iter()
            .fold((0, 0), |(a, b), &(x, y)| (a + x, b + y));
        assert_eq!((sx, sy), (0, 0));
        for (i, a) in MSAA4_OFFSETS.iter().enumerate() {
            for b in &MSAA4_OFFSETS[i + 1..] {
                assert!(a.0 != b.0 && a.1 != b.1);
            }
            assert!(a.0.abs() < ONE / 2 && a.1.abs() < ONE / 2);
        }
    }

    #[test]
    fn factor_drops_for_huge_frames() {
        assert_eq!(ssaa_factor(AntiAlias::Ssaa4, 320, 240), 4);
        assert_eq!(ssaa_factor(AntiAlias::Ssaa2, 320, 240), 2);
        assert_eq!(ssaa_factor(AntiAlias::Msaa4, 320, 240), 1);
        assert_eq!(ssaa_factor(AntiAlias::Ssaa4, 2048, 2048), 2);
        assert_eq!(ssaa_factor(AntiAlias::Ssaa4, 16384, 16384), 1);
        assert_eq!(ssaa_factor(AntiAlias::Ssaa4, usize::MAX, 3), 1);
    }

    #[test]
    fn box_resolve_is_the_rounded_mean() {
        let mut src = Framebuffer::new(4, 2);
        src.fill([10, 20, 30]);
        src.set(0, 0, [0, 0, 0]);
        src.set(1, 1, [255, 255, 255]);
        let mut dst = Framebuffer::new(2, 1);
        resolve_box(&src, 2, &mut dst);
        // (0 + 10 + 10 + 255) / 4 = 68.75 → 69; (0 + 20 + 20 + 255) / 4 = 73.75 → 74.
        assert_eq!(dst.get(0, 0), [69, 74, 79]);
        assert_eq!(dst.get(1, 0), [10, 20, 30]);
    }

    #[test]
    fn msaa_resolve_is_the_rounded_mean() {
        let mut out = [[0u8; 3]; 2];
        resolve_msaa(
            &[[[0; 3], [0; 3], [255; 3], [255; 3]], [[7; 3]; 4]],
            &mut out,
        );
        assert_eq!(out, [[128; 3], [7; 3]]);
    }
}
