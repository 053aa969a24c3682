//! Mipmap filtering: the level of detail from a pixel's footprint, trilinear
//! between two levels, anisotropic as several trilinear taps along the
//! footprint's long axis (docs/filters.md; the EXT_texture_filter_anisotropic rule).
//!
//! A level of detail ≤ 0 means the pixel is not minified: the reads then
//! touch only the base level and never build the chain.

use glam::Vec2;

use super::texture::Texture;

/// Screen-space derivatives of the texture coordinates at a pixel
/// (∂(u,v)/∂x and ∂(u,v)/∂y), which size the pixel's footprint in the texture.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Footprint {
    pub dx: Vec2,
    pub dy: Vec2,
}

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
}
