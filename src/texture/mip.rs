//! Mipmap filtering: the level of detail from a pixel's footprint, trilinear
//! between two levels, anisotropic as several trilinear taps along the
//! footprint's long axis (docs/filters.md; the EXT_texture_filter_anisotropic rule).
//!
//! A level of detail ≤ 0 means the pixel is not minified: the reads then
//! touch only the base level and never build the chain.

use glam::Vec2;

use super::filter::Footprint;
use super::{Level, Texture, level::Texel};

/// Most trilinear taps an anisotropic sample takes.
pub const MAX_ANISOTROPY: usize = 16;

/// A texture's base-level size in texels.
#[inline]
fn size_of(tex: &Texture) -> Vec2 {
    Vec2::new(tex.width() as f32, tex.height() as f32)
}

/// The footprint's two axes measured in texels of a `size` base level.
#[inline]
fn texel_lengths(size: Vec2, fp: Footprint) -> (f32, f32) {
    ((fp.dx * size).length(), (fp.dy * size).length())
}

/// Isotropic level of detail: log2 of the longer footprint axis in texels
/// (0 = one texel per pixel, 1 = two…). NaN footprints give 0; infinite
/// ones +∞ (the smallest level).
#[inline]
pub fn lod(tex: &Texture, fp: Footprint) -> f32 {
    lod_at(size_of(tex), fp)
}

/// [`lod`] for a map of `size` base texels (a normal map reads its own).
#[inline]
pub fn lod_at(size: Vec2, fp: Footprint) -> f32 {
    // log2 of the squared length, halved: no square roots per pixel.
    let rho2 = (fp.dx * size)
        .length_squared()
        .max((fp.dy * size).length_squared());
    if rho2 > 1.0 { 0.5 * rho2.log2() } else { 0.0 }
}

/// The two levels a level of detail falls between and the blend weight of
/// the second one. `lod` ≤ 0 (or NaN) is level 0 alone, and then the chain
/// is not asked for.
#[inline]
fn levels_for(tex: &Texture, lod: f32) -> Option<(&Level, &Level, f32)> {
    // Written so that NaN also takes the base level.
    if lod.is_nan() || lod <= 0.0 {
        return None;
    }
    let last = tex.mip_levels().len(); // index of the smallest level
    if lod >= last as f32 {
        let smallest = tex.level(last);
        return Some((smallest, smallest, 0.0));
    }
    let l0 = lod.floor();
    let i = l0 as usize;
    Some((tex.level(i), tex.level(i + 1), lod - l0))
}

/// The one level GL's LINEAR_MIPMAP_NEAREST reads at `lod`: level
/// ⌈lod + ½⌉ − 1 (the nearest, halves going to the finer), the base up to
/// ½ (so `lod` ≤ ½ or NaN never builds the chain), clamped to the smallest.
#[inline]
pub fn nearest_level(lod: f32, last: impl FnOnce() -> usize) -> usize {
    // Written so that NaN also takes the base level.
    if lod.is_nan() || lod <= 0.5 {
        return 0;
    }
    let last = last();
    if lod >= last as f32 {
        return last;
    }
    ((lod + 0.5).ceil() as usize - 1).min(last)
}

/// Nearest-mip: bilinear on the single level nearest to `lod` (docs/filters.md).
#[inline]
pub fn nearest_mip(tex: &Texture, uv: Vec2, lod: f32) -> Texel {
    let i = nearest_level(lod, || tex.mip_levels().len());
    tex.level(i).bilinear(uv.x, uv.y)
}

/// The filtered height gradient on the level nearest-mip reads.
#[inline]
pub fn nearest_mip_gradient(tex: &Texture, uv: Vec2, lod: f32) -> (f32, f32) {
    let i = nearest_level(lod, || tex.mip_levels().len());
    tex.level(i).height_gradient_filtered(uv.x, uv.y)
}

/// Trilinear: bilinear on the two levels around `lod`, blended.
#[inline]
pub fn trilinear(tex: &Texture, uv: Vec2, lod: f32) -> Texel {
    match levels_for(tex, lod) {
        None => tex.base().bilinear(uv.x, uv.y),
        Some((a, b, t)) => {
            let ta = a.bilinear(uv.x, uv.y);
            if t == 0.0 {
                return ta;
            }
            let tb = b.bilinear(uv.x, uv.y);
            std::array::from_fn(|c| ta[c] + (tb[c] - ta[c]) * t)
        }
    }
}

/// Height gradient (per unit of texture coordinate) from the level(s)
/// matching `lod`, blended like trilinear; the base level when `lod` ≤ 0.
#[inline]
pub fn trilinear_gradient(tex: &Texture, uv: Vec2, lod: f32) -> (f32, f32) {
    match levels_for(tex, lod) {
        None => tex.base().height_gradient_filtered(uv.x, uv.y),
        Some((a, b, t)) => {
            let ga = a.height_gradient_filtered(uv.x, uv.y);
            if t == 0.0 {
                return ga;
            }
            let gb = b.height_gradient_filtered(uv.x, uv.y);
            (ga.0 + (gb.0 - ga.0) * t, ga.1 + (gb.1 - ga.1) * t)
        }
    }
}

/// The height map as a filter reads it at one level of detail: one level,
/// or two blended like trilinear. The base level (lod ≤ 0 or NaN) never
/// builds the chain.
#[derive(Clone, Copy, Debug)]
pub struct HeightField<'a> {
    fine: &'a Level,
    coarse: &'a Level,
    /// Weight of `coarse`; at 0 only `fine` is read.
    t: f32,
}

impl<'a> HeightField<'a> {
    /// The base level alone.
    #[inline]
    pub fn base(tex: &'a Texture) -> Self {
        HeightField {
            fine: tex.base(),
            coarse: tex.base(),
            t: 0.0,
        }
    }

    /// The level(s) trilinear filtering reads at `lod`.
    #[inline]
    pub fn at_lod(tex: &'a Texture, lod: f32) -> Self {
        match levels_for(tex, lod) {
            None => HeightField::base(tex),
            Some((fine, coarse, t)) => HeightField { fine, coarse, t },
        }
    }

    /// The one level nearest-mip filtering reads at `lod`.
    #[inline]
    pub fn nearest(tex: &'a Texture, lod: f32) -> Self {
        let level = tex.level(nearest_level(lod, || tex.mip_levels().len()));
        HeightField {
            fine: level,
            coarse: level,
            t: 0.0,
        }
    }

    /// `read` on the fine level, blended toward `read` on the coarse one.
    /// `read` gets the level and must treat it as a height field of that
    /// level's resolution (a shift of one texel means one texel of *that*
    /// level). With one level the result is `read(fine)` bit for bit.
    #[inline]
    pub fn blend(&self, read: impl Fn(&Level) -> f32) -> f32 {
        let a = read(self.fine);
        if self.t == 0.0 {
            return a;
        }
        a + (read(self.coarse) - a) * self.t
    }
}

/// How an anisotropic sample is taken: `taps` trilinear reads at `lod`,
/// spread evenly along `axis` (the footprint's long axis in UV units),
/// centred on the pixel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AnisoPlan {
    pub taps: usize,
    pub axis: Vec2,
    pub lod: f32,
}

impl AnisoPlan {
    /// The long axis sets how many taps (its length over the short axis,
    /// at most 16); the short axis sets the level of detail, raised when
    /// the ratio exceeds 16 so that the taps still cover the long axis.
    pub fn new(tex: &Texture, fp: Footprint) -> AnisoPlan {
        AnisoPlan::at(size_of(tex), fp)
    }

    /// The plan for a map of `size` base texels (a normal map reads its own).
    pub fn at(size: Vec2, fp: Footprint) -> AnisoPlan {
        let (lx, ly) = texel_lengths(size, fp);
        let (major, minor, axis) = if lx >= ly {
            (lx, ly, fp.dx)
        } else {
            (ly, lx, fp.dy)
        };
        if major.is_nan() || major <= 1.0 {
            // Magnified (or NaN): one bilinear read of the base level.
            return AnisoPlan {
                taps: 1,
                axis: Vec2::ZERO,
                lod: 0.0,
            };
        }
        if !major.is_finite() {
            return AnisoPlan {
                taps: 1,
                axis: Vec2::ZERO,
                lod: f32::INFINITY,
            };
        }
        let minor = minor.max(major / MAX_ANISOTROPY as f32);
        // Each tap covers max(minor, 1) texels along the axis.
        let taps = (major / minor.max(1.0)).ceil() as usize;
        let taps = taps.clamp(1, MAX_ANISOTROPY);
        let lod = if minor > 1.0 { minor.log2() } else { 0.0 };
        AnisoPlan {
            taps,
            axis: if taps > 1 { axis } else { Vec2::ZERO },
            lod,
        }
    }

    /// Where tap `i` reads: evenly spaced over the axis, centred on `uv`.
    #[inline]
    pub fn tap(&self, uv: Vec2, i: usize) -> Vec2 {
        let t = (i as f32 + 0.5) / self.taps as f32 - 0.5;
        uv + self.axis * t
    }
}

/// Anisotropic: the mean of the plan's trilinear taps.
#[inline]
pub fn anisotropic(tex: &Texture, uv: Vec2, fp: Footprint) -> Texel {
    let plan = AnisoPlan::new(tex, fp);
    if plan.taps == 1 {
        return trilinear(tex, uv, plan.lod);
    }
    let mut acc = [0.0f32; 4];
    for i in 0..plan.taps {
        let t = trilinear(tex, plan.tap(uv, i), plan.lod);
        for c in 0..4 {
            acc[c] += t[c];
        }
    }
    let n = plan.taps as f32;
    acc.map(|a| a / n)
}

/// The height gradient filtered the same way: the mean of the taps'
/// gradients (the derivative of the filtered height field).
#[inline]
pub fn anisotropic_gradient(tex: &Texture, uv: Vec2, fp: Footprint) -> (f32, f32) {
    let plan = AnisoPlan::new(tex, fp);
    if plan.taps == 1 {
        return trilinear_gradient(tex, uv, plan.lod);
    }
    let (mut gu, mut gv) = (0.0, 0.0);
    for i in 0..plan.taps {
        let g = trilinear_gradient(tex, plan.tap(uv, i), plan.lod);
        gu += g.0;
        gv += g.1;
    }
    let n = plan.taps as f32;
    (gu / n, gv / n)
}
