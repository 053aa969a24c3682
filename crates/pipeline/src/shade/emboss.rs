//! Emboss bump mapping (docs/bump-emboss.md): the height map shifted toward the
//! light in texture space and subtracted from itself.
//!
//! F(uv) − F(uv + Δ), with Δ about one texel along the light's direction in
//! the tangent plane, is a first-order estimate of how much the relief turns
//! toward the light; scaled to Blinn's k it is added to N·L of the strongest
//! light. Its documented limits show as they are: one light only (the others
//! light the smooth surface), no relief when the light is straight above
//! (the tangent part of L is zero, so is the shift), and no renormalisation —
//! steep slopes and grazing light over- or under-brighten, and features
//! narrower than the shift get doubled edges. In the shadow of the
//! embossed light the relief fades with that light (the term is part of its
//! N·L, and the shadow scales the whole); the other lights still light the
//! smooth surface there.
//!
//! The heights are read like the colour (`filter::read_heights`): on a
//! minified pixel, trilinear and anisotropic difference the footprint's mip
//! level(s) and shift by one texel *of that level*, so a far or grazing
//! surface shows the relief it has at the pixel's scale instead of aliased
//! base-level texels. Magnified, or with nearest/bilinear or the `texel`
//! derivative, it is the base level and one base texel, as documented.

use glam::Vec2;

use super::core::{Hook, HookAt, Pixels};
use super::lanes::{Lanes, Vector};
use super::shader::ShadeCtx;
use crate::plan::strongest_light;
use relief_core::stats::Counters;
use relief_texture::Level;
use relief_texture::sample::filter::read_heights;

/// Emboss for the shading core: the strongest light's N·L gets the term.
pub struct Emboss {
    /// Index of the embossed light in the plan's lights (`usize::MAX`: none).
    pub strong: usize,
}

impl Emboss {
    pub fn new(ctx: &ShadeCtx) -> Self {
        Emboss {
            strong: strongest_light(&ctx.plan.lights).unwrap_or(usize::MAX),
        }
    }
}

/// The emboss term of strength `k` on one level: F(uv) − F(uv + Δ) with Δ
/// one texel of that level (of its larger side) along `toward`, divided by
/// that texel, so levels of any size give terms on the same scale.
#[inline]
fn level_difference(level: &Level, uv: Vec2, toward: Vec2, m: f32, k: f32) -> f32 {
    let texel = 1.0 / level.width.max(level.height) as f32;
    let shift = toward * (texel / m);
    let here = level.bilinear_height(uv.x, uv.y);
    let there = level.bilinear_height(uv.x + shift.x, uv.y + shift.y);
    (here - there) * (k * m / texel)
}

/// The emboss term for unit light direction `l` at the `lanes` of `px`
/// (0 in the others): F(uv) − F(uv + Δ), scaled so that on a gentle slope
/// it equals the change of N·L Blinn's formula gives to first order,
/// −k·(|Pv|·F_u·L_T + |Pu|·F_v·L_B). Two height reads per level and tap
/// the filter reads (see `filter::read_heights`), lane by lane.
#[inline(always)]
pub fn emboss_term<V: Vector>(
    ctx: &ShadeCtx,
    px: &Pixels<V>,
    l: V,
    lanes: u32,
    counters: &mut Counters,
) -> V::L {
    let frame = px.s.frame();
    let (lt, lb) = (l.dot(frame.t), l.dot(frame.b));
    // f32::max of two lengths (finite and positive).
    let m = V::L::select(frame.len_u.lt(frame.len_v), frame.len_v, frame.len_u);
    // Shift toward the light, weighted like Blinn's cross products.
    let toward = (frame.len_v * lt, frame.len_u * lb);
    let plan = ctx.plan;
    let k = plan.bump_strength;
    counters.texture_samples += 2 * lanes.count_ones() as u64;
    let [term] = V::L::gather(lanes, 0.0, |i| {
        let toward = Vec2::new(toward.0.lane(i), toward.1.lane(i));
        let m = m.lane(i);
        [read_heights(
            ctx.texture,
            plan.height_derivative,
            plan.filter,
            px.uv(i),
            px.fp[i],
            |level, uv| level_difference(level, uv, toward, m, k),
        )]
    });
    term
}

impl Hook for Emboss {
    type Pixel<V: Vector> = ();
    #[inline(always)]
    fn at<V: Vector>(
        &self,
        _ctx: &ShadeCtx,
        px: &Pixels<V>,
        _colour: bool,
        counters: &mut Counters,
    ) -> (HookAt<V>, ()) {
        counters.bump_evals += px.count();
        let s = &px.s;
        let at = HookAt {
            u: s.u,
            v: s.v,
            n: s.n,
            texel: None,
        };
        (at, ())
    }

    /// The smooth surface's N·L, plus the term for the embossed light where
    /// that light faces the surface (clamped at 0 like any cosine).
    #[inline(always)]
    fn cosine<V: Vector>(
        &self,
        ctx: &ShadeCtx,
        px: &Pixels<V>,
        _own: &(),
        n: V,
        i: usize,
        d: V,
        counters: &mut Counters,
    ) -> Option<V::L> {
        let ndl = n.dot(d);
        // Not behind (NaN included, whose term is read and then clamped away).
        let facing = !ndl.le(V::L::ZERO);
        if V::L::none(facing) {
            return None;
        }
        let len = d.dot(d).sqrt();
        let k = ndl / len;
        if i != self.strong {
            return Some(k);
        }
        let lanes = V::L::bits(facing) & px.live;
        let e = k + emboss_term(ctx, px, d / len, lanes, counters);
        Some(V::L::select(e.gt(V::L::ZERO), e, V::L::ZERO))
    }
}
