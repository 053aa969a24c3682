//! Texture reads as the shaders see them: one call per sample, whatever the filter.

use glam::Vec2;

use super::mip::{AnisoPlan, HeightField};
use super::{Level, NormalMap, Texture, level::Texel, mip};
use crate::settings::{Filter, HeightDerivative};

/// Screen-space derivatives of the texture coordinates at a pixel
/// (∂(u,v)/∂x and ∂(u,v)/∂y), which size the pixel's footprint in the texture.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Footprint {
    pub dx: Vec2,
    pub dy: Vec2,
}

/// Colour and height at `uv` with the chosen filter. Nearest and bilinear read
/// the base level and ignore the footprint; nearest-mip, trilinear and anisotropic size
/// their read from it and touch the mip chain only when the pixel is
/// minified (more than one texel per pixel).
#[inline]
pub fn sample(tex: &Texture, filter: Filter, uv: Vec2, footprint: Footprint) -> Texel {
    match filter {
        Filter::Nearest => tex.base().nearest(uv.x, uv.y),
        Filter::Bilinear => tex.base().bilinear(uv.x, uv.y),
        Filter::NearestMip => mip::nearest_mip(tex, uv, mip::lod(tex, footprint)),
        Filter::Trilinear => mip::trilinear(tex, uv, mip::lod(tex, footprint)),
        Filter::Anisotropic => mip::anisotropic(tex, uv, footprint),
    }
}

/// ∂F/∂u, ∂F/∂v of the height map per unit of texture coordinate.
///
/// `Texel` is the documented per-texel difference on the base level, whatever
/// the filter. `Filtered` differentiates bilinear heights one texel apart on
/// the level the colour filter would read: the base level for nearest and
/// bilinear or when magnified, the footprint's mip level(s) for trilinear,
/// and the mean over the same taps for anisotropic.
#[inline]
pub fn height_gradient(
    tex: &Texture,
    mode: HeightDerivative,
    filter: Filter,
    uv: Vec2,
    footprint: Footprint,
) -> (f32, f32) {
    match (mode, filter) {
        (HeightDerivative::Texel, _) => tex.base().height_gradient_texel(uv.x, uv.y),
        (HeightDerivative::Filtered, Filter::Nearest | Filter::Bilinear) => {
            tex.base().height_gradient_filtered(uv.x, uv.y)
        }
        (HeightDerivative::Filtered, Filter::NearestMip) => {
            mip::nearest_mip_gradient(tex, uv, mip::lod(tex, footprint))
        }
        (HeightDerivative::Filtered, Filter::Trilinear) => {
            mip::trilinear_gradient(tex, uv, mip::lod(tex, footprint))
        }
        (HeightDerivative::Filtered, Filter::Anisotropic) => {
            mip::anisotropic_gradient(tex, uv, footprint)
        }
    }
}

/// A quantity computed from heights, read with the same care as the colour:
/// `read(level, uv)` evaluated on the level(s) and at the taps the filter
/// would read for this pixel, blended and averaged the same way. `read` must
/// work in the level's own texels (a "one texel" shift means one texel of
/// that level), so on a coarser level it sees the filtered height field.
///
/// `Texel` reads the base level whatever the filter (the documented
/// per-texel reads), and so do nearest and bilinear, exactly as before any
/// mip chain existed: `read(base, uv)`. Trilinear reads the footprint's mip
/// level(s), anisotropic its taps; both read only the base level, and never
/// build the chain, while the pixel is magnified.
#[inline]
pub fn read_heights(
    tex: &Texture,
    mode: HeightDerivative,
    filter: Filter,
    uv: Vec2,
    footprint: Footprint,
    read: impl Fn(&Level, Vec2) -> f32,
) -> f32 {
    match (mode, filter) {
        (HeightDerivative::Texel, _) | (_, Filter::Nearest | Filter::Bilinear) => {
            read(tex.base(), uv)
        }
        (HeightDerivative::Filtered, Filter::NearestMip) => {
            HeightField::nearest(tex, mip::lod(tex, footprint)).blend(|level| read(level, uv))
        }
        (HeightDerivative::Filtered, Filter::Trilinear) => {
            HeightField::at_lod(tex, mip::lod(tex, footprint)).blend(|level| read(level, uv))
        }
        (HeightDerivative::Filtered, Filter::Anisotropic) => {
            let plan = AnisoPlan::new(tex, footprint);
            let field = HeightField::at_lod(tex, plan.lod);
            if plan.taps == 1 {
                return field.blend(|level| read(level, uv));
            }
            let mut sum = 0.0;
            for i in 0..plan.taps {
                let at = plan.tap(uv, i);
                sum += field.blend(|level| read(level, at));
            }
            sum / plan.taps as f32
        }
    }
}

/// The dot3 normal map at `uv`, read with the same footprint as the colour.
///
/// `Texel`, nearest and bilinear read the base map bilinearly, exactly as
/// before the map had a mip chain. With the filtered derivative, trilinear
/// reads the footprint's level(s) of the map's chain and anisotropic the mean
/// of the same taps; both read only the base map, and never build its chain,
/// while the pixel is magnified. The result is not renormalised (see
/// `normal_map`): it is shorter than 1 where the normals it averages differ.
#[inline]
pub fn read_normal(
    map: &NormalMap,
    mode: HeightDerivative,
    filter: Filter,
    uv: Vec2,
    footprint: Footprint,
) -> [f32; 3] {
    let size = Vec2::new(map.width as f32, map.height as f32);
    match (mode, filter) {
        (HeightDerivative::Texel, _) | (_, Filter::Nearest | Filter::Bilinear) => {
            map.bilinear(uv.x, uv.y)
        }
        (HeightDerivative::Filtered, Filter::NearestMip) => {
            map.nearest_mip(uv, mip::lod_at(size, footprint))
        }
        (HeightDerivative::Filtered, Filter::Trilinear) => {
            map.trilinear(uv, mip::lod_at(size, footprint))
        }
        (HeightDerivative::Filtered, Filter::Anisotropic) => {
            let plan = AnisoPlan::at(size, footprint);
            if plan.taps == 1 {
                return map.trilinear(uv, plan.lod);
            }
            let mut acc = [0.0f32; 3];
            for i in 0..plan.taps {
                let n = map.trilinear(plan.tap(uv, i), plan.lod);
                for c in 0..3 {
                    acc[c] += n[c];
                }
            }
            let n = plan.taps as f32;
            acc.map(|a| a / n)
        }
    }
}
