//! How a material's opacity decides a triangle's pixels: drawn whole, cut
//! out below a threshold (an alpha mask), or composited over what is
//! already there (translucency, glTF BLEND).
//!
//! A blended triangle tests the depth buffer but does not write it, and
//! the frame draws blended triangles after every opaque one, far to near
//! (`order_blended`), so each lands over what is behind it. Compositing
//! is in the frame's display values, as an 8-bit render target does; a
//! transmitting material's tint multiplies what shows through in those
//! values too (its base colour factor encoded as the frame encodes light:
//! for a power-law curve the encoding of a product is the product of the
//! encodings, and sRGB is within a level or two of one).

use super::setup::ScreenTri;
use crate::shade::brdf::linear_to_srgb;
use crate::shade::interpolate::perspective;
use crate::shade::{PixelShader, ShadeCtx};
use relief_core::framebuffer::Rgb;
use relief_scene::terms::BLEND_MIN_OPACITY;

/// What a triangle's opacity does to its pixels.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AlphaRule {
    /// Every covered pixel drawn.
    Opaque,
    /// A pixel below this opacity is not drawn.
    Mask(f32),
    /// Each pixel composited with its opacity, what shows through
    /// multiplied by this display-encoded tint (white: none).
    Blend([f32; 3]),
}

impl AlphaRule {
    /// The rule of `shader`'s triangles under `ctx`'s material.
    pub fn of<S: PixelShader>(shader: &S, ctx: &ShadeCtx) -> Self {
        if !shader.cutout(ctx) {
            return AlphaRule::Opaque;
        }
        match ctx.plan.terms.as_ref().and_then(|t| t.cutout.as_ref()) {
            None => AlphaRule::Opaque,
            Some(c) if c.blend => AlphaRule::Blend(display_tint(c.tint)),
            Some(c) => AlphaRule::Mask(c.cutoff),
        }
    }

    /// The opacity the pixel at screen-space barycentrics `l` of `tri` is
    /// drawn with, or `None` when it is not drawn (1 for a drawn pixel of
    /// an opaque or masked triangle).
    #[inline]
    pub fn coverage<S: PixelShader>(
        self,
        tri: &ScreenTri,
        shader: &S,
        ctx: &ShadeCtx,
        l: [f32; 3],
    ) -> Option<f32> {
        match self {
            AlphaRule::Opaque => Some(1.0),
            AlphaRule::Mask(cutoff) => (opacity_of(tri, shader, ctx, l) >= cutoff).then_some(1.0),
            AlphaRule::Blend(_) => {
                let a = opacity_of(tri, shader, ctx, l);
                // NaN is not drawn.
                (a >= BLEND_MIN_OPACITY).then_some(a.min(1.0))
            }
        }
    }

    pub fn blends(self) -> bool {
        matches!(self, AlphaRule::Blend(_))
    }

    /// `src` over `dst` with opacity `a`, as this rule composites (for a
    /// rule that does not blend, `src`).
    #[inline]
    pub fn composite(self, dst: Rgb, src: Rgb, a: f32) -> Rgb {
        match self {
            AlphaRule::Blend(tint) => over_tinted(dst, src, a, tint),
            _ => src,
        }
    }
}

/// The display-encoded tint of linear colour `tint` (each channel held to
/// 0..=1; not finite is white).
fn display_tint(tint: glam::Vec3) -> [f32; 3] {
    tint.to_array().map(|c| {
        if c.is_finite() {
            linear_to_srgb(c.clamp(0.0, 1.0))
        } else {
            1.0
        }
    })
}

/// `src` over `dst` tinted by `tint`: a·src + (1 − a)·tint·dst, rounded
/// per channel (`over` when the tint is white).
#[inline]
pub fn over_tinted(dst: Rgb, src: Rgb, a: f32, tint: [f32; 3]) -> Rgb {
    if tint == [1.0; 3] {
        return over(dst, src, a);
    }
    if a >= 1.0 {
        return src;
    }
    std::array::from_fn(|i| {
        let v = f32::from(src[i]) * a + f32::from(dst[i]) * tint[i] * (1.0 - a);
        v.round().clamp(0.0, 255.0) as u8
    })
}

/// `src` over `dst` with opacity `a` (0 to 1), rounded per channel.
#[inline]
pub fn over(dst: Rgb, src: Rgb, a: f32) -> Rgb {
    if a >= 1.0 {
        return src;
    }
    std::array::from_fn(|i| {
        let v = f32::from(dst[i]) + (f32::from(src[i]) - f32::from(dst[i])) * a;
        v.round().clamp(0.0, 255.0) as u8
    })
}

/// The shader's opacity at the point with screen-space barycentrics `l`
/// (the source triangle's weights, as the shading finds them).
#[inline]
fn opacity_of<S: PixelShader>(tri: &ScreenTri, shader: &S, ctx: &ShadeCtx, l: [f32; 3]) -> f32 {
    let b = tri.source_barycentrics(perspective(l, tri.q).b);
    shader.opacity(ctx, b)
}

/// Moves the triangles `blended` says yes to after the others, far to near
/// by their mean depth (the others keep their order; so do blended ones at
/// equal depth). Returns where the blended ones start.
pub fn order_blended(tris: &mut [ScreenTri], blended: impl Fn(&ScreenTri) -> bool) -> usize {
    let depth = |t: &ScreenTri| t.z[0] + t.z[1] + t.z[2];
    // A stable sort on (blended, −depth for the blended).
    tris.sort_by(|a, b| {
        let (ba, bb) = (blended(a), blended(b));
        ba.cmp(&bb).then_with(|| {
            if ba && bb {
                depth(b).total_cmp(&depth(a))
            } else {
                std::cmp::Ordering::Equal
            }
        })
    });
    tris.iter().position(&blended).unwrap_or(tris.len())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn over_mixes_by_opacity_and_keeps_the_ends() {
        assert_eq!(over([0, 100, 200], [200, 100, 0], 0.5), [100, 100, 100]);
        assert_eq!(over([10, 20, 30], [200, 100, 0], 1.0), [200, 100, 0]);
        assert_eq!(over([10, 20, 30], [200, 100, 0], 0.0), [10, 20, 30]);
        // 0.25 of the way: 255·0.25 = 63.75 → 64.
        assert_eq!(over([0, 0, 0], [255, 255, 255], 0.25), [64, 64, 64]);
    }

    #[test]
    fn a_tint_multiplies_only_what_shows_through() {
        let red = [1.0, 0.0, 0.0];
        // 0.25·(0, 0, 40) + 0.75·(200, 100, 0)·(1, 0, 0) = (150, 0, 10).
        assert_eq!(
            over_tinted([200, 100, 0], [0, 0, 40], 0.25, red),
            [150, 0, 10]
        );
        assert_eq!(over_tinted([200, 100, 0], [0, 0, 40], 1.0, red), [0, 0, 40]);
        let white = [1.0; 3];
        let (dst, src) = ([10, 20, 30], [200, 100, 0]);
        assert_eq!(over_tinted(dst, src, 0.3, white), over(dst, src, 0.3));
        // Linear 0.5 is sRGB 0.735 (188 of 255).
        let half = display_tint(glam::Vec3::splat(0.5));
        assert!((half[0] - 0.7354).abs() < 2e-3, "{half:?}");
    }
}
