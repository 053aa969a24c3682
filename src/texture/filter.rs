//! Texture reads as the shaders see them: one call per sample, whatever the filter.

use glam::Vec2;

use super::{Texture, level::Texel, mip};
use crate::settings::{Filter, HeightDerivative};

/// Screen-space derivatives of the texture coordinates at a pixel
/// (∂(u,v)/∂x and ∂(u,v)/∂y), which size the pixel's footprint in the texture.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Footprint {
    pub dx: Vec2,
    pub dy: Vec2,
}

/// Colour and height at `uv` with the chosen filter. Nearest and bilinear read
/// the base level and ignore the footprint; trilinear and anisotropic size
/// their read from it and touch the mip chain only when the pixel is
/// minified (more than one texel per pixel).
#[inline]
pub fn sample(tex: &Texture, filter: Filter, uv: Vec2, footprint: Footprint) -> Texel {
    match filter {
        Filter::Nearest => tex.base().nearest(uv.x, uv.y),
        Filter::Bilinear => tex.base().bilinear(uv.x, uv.y),
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
        (HeightDerivative::Filtered, Filter::Trilinear) => {
            mip::trilinear_gradient(tex, uv, mip::lod(tex, footprint))
        }
        (HeightDerivative::Filtered, Filter::Anisotropic) => {
            mip::anisotropic_gradient(tex, uv, footprint)
        }
    }
}
