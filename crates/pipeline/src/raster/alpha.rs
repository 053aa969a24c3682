//! How a material's opacity decides a triangle's pixels: drawn whole, cut
//! out below a threshold (an alpha mask), or composited over what is
//! already there (translucency, glTF BLEND).
//!
//! A blended triangle tests the depth buffer but does not write it, and
//! the frame draws blended triangles after every opaque one, far to near
//! (`order_blended`), so each lands over what is behind it. Compositing
//! is in the frame's display values, as an 8-bit render target does.

use super::setup::ScreenTri;
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
    /// Each pixel composited with its opacity.
    Blend,
}

impl AlphaRule {
    /// The rule of `shader`'s triangles under `ctx`'s material.
    pub fn of<S: PixelShader>(shader: &S, ctx: &ShadeCtx) -> Self {
        if !shader.cutout(ctx) {
            return AlphaRule::Opaque;
        }
        match ctx.plan.terms.as_ref().and_then(|t| t.cutout.as_ref()) {
            None => AlphaRule::Opaque,
            Some(c) if c.blend => AlphaRule::Blend,
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
            AlphaRule::Blend => {
                let a = opacity_of(tri, shader, ctx, l);
                // NaN is not drawn.
                (a >= BLEND_MIN_OPACITY).then_some(a.min(1.0))
            }
        }
    }

    pub fn blends(self) -> bool {
        self == AlphaRule::Blend
    }
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
}
