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

use glam::{Vec2, Vec3};

use super::PhongTri;
use super::kernels::{PixelShader, ShadeCtx};
use super::lighting::ATTENUATION_QUADRATIC;
use super::tangent::Surface;
use crate::framebuffer::Rgb;
use crate::plan::strongest_light;
use crate::stats::Counters;
use crate::texture::Level;
use crate::texture::filter::{Footprint, read_heights, sample};

/// The emboss kernel, with or without the colour texture.
pub struct EmbossKernel<'a, const TEX: bool> {
    pub tri: &'a PhongTri,
    /// Index of the embossed light in the plan's lights (`usize::MAX`: none).
    pub strong: usize,
}

impl<'a, const TEX: bool> EmbossKernel<'a, TEX> {
    pub fn new(tri: &'a PhongTri, ctx: &ShadeCtx) -> Self {
        EmbossKernel {
            tri,
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

/// The emboss term for unit light direction `l`: F(uv) − F(uv + Δ), scaled
/// so that on a gentle slope it equals the change of N·L Blinn's formula
/// gives to first order, −k·(|Pv|·F_u·L_T + |Pu|·F_v·L_B). Two height reads
/// per level and tap the filter reads (see `filter::read_heights`).
#[inline]
pub fn emboss_term(
    ctx: &ShadeCtx,
    s: &Surface,
    l: Vec3,
    fp: Footprint,
    counters: &mut Counters,
) -> f32 {
    let frame = s.frame();
    let (lt, lb) = (l.dot(frame.t), l.dot(frame.b));
    let m = frame.len_u.max(frame.len_v);
    // Shift toward the light, weighted like Blinn's cross products.
    let toward = Vec2::new(frame.len_v * lt, frame.len_u * lb);
    let plan = ctx.plan;
    let k = plan.bump_strength;
    counters.texture_samples += 2;
    read_heights(
        ctx.texture,
        plan.height_derivative,
        plan.filter,
        s.uv,
        fp,
        |level, uv| level_difference(level, uv, toward, m, k),
    )
}

impl<const TEX: bool> PixelShader for EmbossKernel<'_, TEX> {
    const SAMPLES_TEXTURE: bool = true;
    #[inline]
    fn shade(&self, ctx: &ShadeCtx, b: Vec3, fp: Footprint, counters: &mut Counters) -> Rgb {
        let plan = ctx.plan;
        counters.pixels_shaded += 1;
        counters.bump_evals += 1;
        let s = Surface::at(self.tri, b);
        let mut albedo = s.albedo;
        if TEX {
            counters.texture_samples += 1;
            let t = sample(ctx.texture, plan.filter, s.uv, fp);
            albedo *= Vec3::new(t[0], t[1], t[2]);
        }
        counters.light_evals += plan.lights.len() as u64;
        // The diffuse sum of `lighting::diffuse`, term for term, with the
        // emboss term added to the strong light's N·L.
        let mut sum = plan.ambient;
        for (i, light) in plan.lights.iter().enumerate() {
            let d = light.position - s.p;
            let ndl = s.n.dot(d);
            if ndl > 0.0 {
                let len2 = d.length_squared();
                if len2 > 0.0 && len2.is_finite() {
                    let len = len2.sqrt();
                    // In the shadow of the embossed light its relief goes
                    // with its light: the whole term is scaled (and in full
                    // shadow the height reads are skipped).
                    let seen = ctx.shadow.map_or(1.0, |sh| {
                        sh.factor(i, s.p, self.tri.face_normal, self.tri.object, counters)
                    });
                    let mut k = ndl / len;
                    if i == self.strong && seen > 0.0 {
                        k = (k + emboss_term(ctx, &s, d / len, fp, counters)).max(0.0);
                    }
                    if plan.attenuation {
                        k /= 1.0 + ATTENUATION_QUADRATIC * len2;
                    }
                    sum += light.color * (k.min(1.0) * seen);
                }
            }
        }
        super::lighting::finish(albedo * sum, counters)
    }
    fn uvs(&self) -> Option<&[Vec2; 3]> {
        Some(&self.tri.uv)
    }
}
