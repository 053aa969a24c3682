//! Texture reads as the shaders see them: one call per sample, whatever the filter.

use glam::Vec2;

use super::level::Level;
use super::mip::Footprint;
use super::normal_map::NormalMap;
use super::sampler::Sampler;
use super::texels::Texel;
use super::texture::Texture;
use relief_core::settings::{Filter, HeightDerivative};

/// Colour and height at `uv` with the chosen filter. Nearest and bilinear read
/// the base level and ignore the footprint; nearest-mip, trilinear and anisotropic size
/// their read from it and touch the mip chain only when the pixel is
/// minified (more than one texel per pixel).
#[inline]
pub fn sample(tex: &Texture, filter: Filter, uv: Vec2, footprint: Footprint) -> Texel {
    match filter {
        Filter::Nearest => tex.base().nearest(uv.x, uv.y),
        Filter::Bilinear => tex.base().bilinear(uv.x, uv.y),
        _ => sampler(tex, filter, footprint).read(uv, |i, at| tex.level(i).bilinear(at.x, at.y)),
    }
}

/// The texture's sampler for one pixel.
#[inline]
fn sampler(tex: &Texture, filter: Filter, footprint: Footprint) -> Sampler {
    let size = Vec2::new(tex.width() as f32, tex.height() as f32);
    Sampler::new(filter, footprint, size, || tex.mip_levels().len())
}

/// ∂F/∂u, ∂F/∂v of the height map per unit of texture coordinate.
///
/// `Texel` is the documented per-texel difference on the base level, whatever
/// the filter. `Filtered` differentiates bilinear heights one texel apart on
/// the level(s) and at the taps the colour filter reads (the derivative of
/// the filtered height field).
#[inline]
pub fn height_gradient(
    tex: &Texture,
    mode: HeightDerivative,
    filter: Filter,
    uv: Vec2,
    footprint: Footprint,
) -> (f32, f32) {
    match mode {
        HeightDerivative::Texel => tex.base().height_gradient_texel(uv.x, uv.y),
        HeightDerivative::Filtered => sampler(tex, filter, footprint).read(uv, |i, at| {
            tex.level(i).height_gradient_filtered(at.x, at.y)
        }),
    }
}

/// The sampler heights are read through at a pixel: the base level for the
/// documented per-texel derivative, else the colour filter's.
#[inline]
pub fn height_sampler(
    tex: &Texture,
    mode: HeightDerivative,
    filter: Filter,
    footprint: Footprint,
) -> Sampler {
    match mode {
        HeightDerivative::Texel => Sampler::BASE,
        HeightDerivative::Filtered => sampler(tex, filter, footprint),
    }
}

/// A quantity computed from heights, read with the same care as the colour:
/// `read(level, uv)` evaluated on the level(s) and at the taps the filter
/// would read for this pixel, blended and averaged the same way. `read` must
/// work in the level's own texels (a "one texel" shift means one texel of
/// that level), so on a coarser level it sees the filtered height field.
///
/// `Texel` reads the base level whatever the filter (the documented
/// per-texel reads), and so do nearest and bilinear: `read(base, uv)`.
/// The others read only the base level, and never build the chain, while
/// the pixel is magnified.
#[inline]
pub fn read_heights(
    tex: &Texture,
    mode: HeightDerivative,
    filter: Filter,
    uv: Vec2,
    footprint: Footprint,
    read: impl Fn(&Level, Vec2) -> f32,
) -> f32 {
    match mode {
        HeightDerivative::Texel => read(tex.base(), uv),
        HeightDerivative::Filtered => {
            sampler(tex, filter, footprint).read(uv, |i, at| read(tex.level(i), at))
        }
    }
}

/// Whether [`read_normal`] reads the base map bilinearly whatever the
/// footprint: with `Texel`, nearest and bilinear (so eight pixels can be
/// read together, `shade::packet::normal_bilinear`).
#[inline]
pub fn normal_reads_base(mode: HeightDerivative, filter: Filter) -> bool {
    mode == HeightDerivative::Texel || matches!(filter, Filter::Nearest | Filter::Bilinear)
}

/// The dot3 normal map at `uv`, read with the same footprint as the colour
/// (the map's own size and mip chain: a file's map may differ in size).
///
/// `Texel`, nearest and bilinear read the base map bilinearly. With the
/// filtered derivative, the other filters read the map's level(s) and taps
/// as the colour's; they read only the base map, and never build its chain,
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
    if normal_reads_base(mode, filter) {
        return map.bilinear(uv.x, uv.y);
    }
    let size = Vec2::new(map.width as f32, map.height as f32);
    Sampler::new(filter, footprint, size, || map.mip_levels().len())
        .read(uv, |i, at| map.level_bilinear(i, at))
}
