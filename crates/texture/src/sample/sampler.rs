//! One sampler for every filtered read (docs/filters.md): which mip levels a
//! pixel's filter reads, with which weight, at which taps, decided once
//! from the filter and the pixel's footprint. Colour, heights, height
//! differences and normals are all read through it, each with its own read
//! of one level at one point, so a quantity read for a pixel always sees the
//! same part of its texture as the colour.

use glam::Vec2;

use super::mip::{AnisoPlan, Footprint, lod_at, nearest_level};
use relief_core::settings::Filter;

/// A value the filters blend: colour texels, heights, gradients, normals.
pub trait Blend: Copy {
    /// `self + (other − self)·t`.
    fn lerp(self, other: Self, t: f32) -> Self;
    fn plus(self, other: Self) -> Self;
    /// `self / n`.
    fn over(self, n: f32) -> Self;
}

impl Blend for f32 {
    #[inline(always)]
    fn lerp(self, other: f32, t: f32) -> f32 {
        self + (other - self) * t
    }
    #[inline(always)]
    fn plus(self, other: f32) -> f32 {
        self + other
    }
    #[inline(always)]
    fn over(self, n: f32) -> f32 {
        self / n
    }
}

impl Blend for (f32, f32) {
    #[inline(always)]
    fn lerp(self, other: Self, t: f32) -> Self {
        (self.0.lerp(other.0, t), self.1.lerp(other.1, t))
    }
    #[inline(always)]
    fn plus(self, other: Self) -> Self {
        (self.0 + other.0, self.1 + other.1)
    }
    #[inline(always)]
    fn over(self, n: f32) -> Self {
        (self.0 / n, self.1 / n)
    }
}

impl<const N: usize> Blend for [f32; N] {
    #[inline(always)]
    fn lerp(self, other: Self, t: f32) -> Self {
        std::array::from_fn(|c| self[c].lerp(other[c], t))
    }
    #[inline(always)]
    fn plus(self, other: Self) -> Self {
        std::array::from_fn(|c| self[c] + other[c])
    }
    #[inline(always)]
    fn over(self, n: f32) -> Self {
        self.map(|a| a / n)
    }
}

/// Where one pixel's filter reads: level `fine`, blended toward `coarse` by
/// `t` (trilinear), at `taps` points spread along `axis` (anisotropic) and
/// averaged. Level 0 is the base; a magnified pixel reads only the base.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sampler {
    pub fine: usize,
    pub coarse: usize,
    pub t: f32,
    pub taps: usize,
    pub axis: Vec2,
}

impl Sampler {
    /// One read of the base level: nearest and bilinear, a magnified pixel,
    /// and the documented per-texel derivative.
    pub const BASE: Sampler = Sampler {
        fine: 0,
        coarse: 0,
        t: 0.0,
        taps: 1,
        axis: Vec2::ZERO,
    };

    /// The reads of `filter` for a pixel of footprint `fp` on a texture
    /// whose base level is `size` texels; `last()` is the index of its
    /// smallest level, asked (and the chain built) only for a minified pixel.
    #[inline(always)]
    pub fn new(filter: Filter, fp: Footprint, size: Vec2, last: impl FnOnce() -> usize) -> Sampler {
        match filter {
            Filter::Nearest | Filter::Bilinear => Sampler::BASE,
            Filter::NearestMip => {
                let i = nearest_level(lod_at(size, fp), last);
                Sampler {
                    fine: i,
                    coarse: i,
                    ..Sampler::BASE
                }
            }
            Filter::Trilinear => Sampler::at_lod(lod_at(size, fp), last),
            Filter::Anisotropic => {
                let plan = AnisoPlan::at(size, fp);
                Sampler {
                    taps: plan.taps,
                    axis: plan.axis,
                    ..Sampler::at_lod(plan.lod, last)
                }
            }
        }
    }

    /// The two levels around level of detail `lod` and the blend between
    /// them (the smallest level alone past the end of the chain).
    #[inline]
    pub fn at_lod(lod: f32, last: impl FnOnce() -> usize) -> Sampler {
        // Written so that NaN also takes the base level.
        if lod.is_nan() || lod <= 0.0 {
            return Sampler::BASE;
        }
        let last = last();
        if lod >= last as f32 {
            return Sampler {
                fine: last,
                coarse: last,
                ..Sampler::BASE
            };
        }
        let l0 = lod.floor();
        let i = l0 as usize;
        Sampler {
            fine: i,
            coarse: i + 1,
            t: lod - l0,
            ..Sampler::BASE
        }
    }

    /// Where tap `i` reads: evenly spaced over the axis, centred on `uv`.
    #[inline]
    fn tap(&self, uv: Vec2, i: usize) -> Vec2 {
        let t = (i as f32 + 0.5) / self.taps as f32 - 0.5;
        uv + self.axis * t
    }

    /// The filtered value of a quantity at `uv`, from `read(level, point)`:
    /// one level's value at one point.
    #[inline(always)]
    pub fn read<T: Blend>(&self, uv: Vec2, read: impl Fn(usize, Vec2) -> T) -> T {
        let blended = |at: Vec2| {
            let a = read(self.fine, at);
            if self.t == 0.0 {
                return a;
            }
            a.lerp(read(self.coarse, at), self.t)
        };
        if self.taps <= 1 {
            return blended(uv);
        }
        let mut sum = blended(self.tap(uv, 0));
        for i in 1..self.taps {
            sum = sum.plus(blended(self.tap(uv, i)));
        }
        sum.over(self.taps as f32)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fp(texels: f32, size: f32) -> Footprint {
        Footprint {
            dx: Vec2::new(texels / size, 0.0),
            dy: Vec2::new(0.0, texels / size),
        }
    }

    #[test]
    fn magnified_pixels_read_the_base_level_without_asking_for_the_chain() {
        for filter in [Filter::NearestMip, Filter::Trilinear, Filter::Anisotropic] {
            let s = Sampler::new(filter, fp(0.5, 64.0), Vec2::splat(64.0), || {
                panic!("the chain is not needed")
            });
            assert_eq!(s, Sampler::BASE, "{filter:?}");
        }
    }

    #[test]
    fn trilinear_blends_the_two_levels_around_the_lod() {
        // Three texels per pixel: lod log2(3) ≈ 1.585, levels 1 and 2.
        let s = Sampler::new(Filter::Trilinear, fp(3.0, 64.0), Vec2::splat(64.0), || 6);
        assert_eq!((s.fine, s.coarse, s.taps), (1, 2, 1));
        assert!((s.t - (3f32.log2() - 1.0)).abs() < 1e-6);
        let v = s.read(Vec2::ZERO, |level, _| level as f32 * 10.0);
        assert!((v - (10.0 + 10.0 * s.t)).abs() < 1e-5);
        // Past the end of the chain: the smallest level alone.
        let s = Sampler::new(Filter::Trilinear, fp(1e6, 64.0), Vec2::splat(64.0), || 6);
        assert_eq!((s.fine, s.coarse, s.t), (6, 6, 0.0));
    }

    #[test]
    fn anisotropic_averages_taps_along_the_long_axis() {
        let f = Footprint {
            dx: Vec2::new(8.0 / 64.0, 0.0),
            dy: Vec2::new(0.0, 1.0 / 64.0),
        };
        let s = Sampler::new(Filter::Anisotropic, f, Vec2::splat(64.0), || 6);
        assert_eq!((s.fine, s.t, s.taps), (0, 0.0, 8));
        // The mean of u over the taps is the centre; their spread covers dx.
        let mean = s.read(Vec2::new(0.5, 0.5), |_, at| at.x);
        assert!((mean - 0.5).abs() < 1e-6);
        let first = s.tap(Vec2::new(0.5, 0.5), 0).x;
        let last = s.tap(Vec2::new(0.5, 0.5), 7).x;
        assert!((last - first - 7.0 / 64.0).abs() < 1e-6);
    }

    #[test]
    fn nearest_mip_reads_one_level() {
        let s = Sampler::new(Filter::NearestMip, fp(3.0, 64.0), Vec2::splat(64.0), || 6);
        assert_eq!((s.fine, s.coarse, s.t, s.taps), (2, 2, 0.0, 1));
    }
}
