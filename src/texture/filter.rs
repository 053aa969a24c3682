//! Texture reads as the shaders see them: one call per sample, whatever the filter.

use glam::Vec2;

use super::{Texture, level::Texel};
use crate::settings::{Filter, HeightDerivative};

/// Screen-space derivatives of the texture coordinates at a pixel
/// (∂(u,v)/∂x and ∂(u,v)/∂y), which size the pixel's footprint in the texture.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Footprint {
    pub dx: Vec2,
    pub dy: Vec2,
}

/// Colour and height at `uv` with the chosen filter. Nearest and bilinear read
/// the base level and ignore the footprint.
#[inline]
pub fn sample(tex: &Texture, filter: Filter, uv: Vec2, footprint: Footprint) -> Texel {
    let _ = footprint;
    match filter {
        Filter::Nearest => tex.base().nearest(uv.x, uv.y),
        Filter::Bilinear | Filter::Trilinear | Filter::Anisotropic => {
            tex.base().bilinear(uv.x, uv.y)
        }
    }
}

/// ∂F/∂u, ∂F/∂v of the height map per unit of texture coordinate.
#[inline]
pub fn height_gradient(
    tex: &Texture,
    mode: HeightDerivative,
    filter: Filter,
    uv: Vec2,
    footprint: Footprint,
) -> (f32, f32) {
    let _ = (filter, footprint);
    match mode {
        HeightDerivative::Texel => tex.base().height_gradient_texel(uv.x, uv.y),
        HeightDerivative::Filtered => tex.base().height_gradient_filtered(uv.x, uv.y),
    }
}
