//! The one shading core of the Phong family (docs/shading.md): every
//! per-pixel kernel is the surface at the pixel, a technique's hook, and the
//! one light loop.
//!
//! A technique (Blinn, emboss, dot3, parallax, POM) is a `Hook`: it may move
//! the texture coordinate, perturb the normal, or give its own N·L per light.
//! Everything else, the interpolation, the colour read, the light loop with
//! its attenuation, shadows and highlights, the specular map, the clamping
//! and the counters, is here once. Adding a technique is one file with its
//! hook, plus its enum variant and the arm that picks it.

use glam::{Vec2, Vec3};

use super::PhongTri;
use super::kernels::{PixelShader, ShadeCtx};
use super::lighting::{LightSet, finish, lambert, light_with};
use super::material::compose;
use super::specular::{gloss, view_dir};
use super::tangent::Surface;
use crate::framebuffer::Rgb;
use crate::stats::Counters;
use crate::texture::filter::{Footprint, sample};

/// What a technique decided at one pixel.
#[derive(Clone, Copy, Debug)]
pub struct HookAt {
    /// Where the colour (and the specular map) is read.
    pub uv: Vec2,
    /// The shading normal: the one the highlights use, and Lambert's.
    pub n: Vec3,
    /// The colour texel at `uv`, when the technique already read it (a
    /// fused read): the core then does not read it again.
    pub texel: Option<Vec3>,
}

/// A technique's part of a Phong-family pixel.
pub trait Hook {
    /// What `cosine` needs from `at` (nothing for most techniques).
    type Pixel;
    /// The technique's work at the pixel with surface `s` (barycentrics `b`,
    /// footprint `fp`); `colour` says the core will read the colour texel.
    /// Counts the technique's own evaluations and reads.
    fn at(
        &self,
        ctx: &ShadeCtx,
        s: &Surface,
        b: Vec3,
        fp: Footprint,
        colour: bool,
        counters: &mut Counters,
    ) -> (HookAt, Self::Pixel);

    /// N·L of light `i`, `d` away, at a pixel whose shading normal is `n`:
    /// Lambert's unless the technique has its own (≤ 0, or NaN: no light).
    #[inline(always)]
    fn cosine(
        &self,
        _ctx: &ShadeCtx,
        _px: &Self::Pixel,
        n: Vec3,
        _i: usize,
        d: Vec3,
        _counters: &mut Counters,
    ) -> f32 {
        lambert(n, d)
    }
}

/// One Phong-family pixel: the surface, the technique, the colour read, the
/// light loop, the composition `albedo × light + highlight`, and the
/// environment's reflection in the technique's normal when the plan has one.
#[inline(always)]
pub fn shade_pixel<H: Hook, const TEX: bool, const SPEC: bool>(
    hook: &H,
    tri: &PhongTri,
    ctx: &ShadeCtx,
    b: Vec3,
    fp: Footprint,
    counters: &mut Counters,
) -> Rgb {
    let plan = ctx.plan;
    counters.pixels_shaded += 1;
    let s = Surface::at(tri, b);
    let (at, px) = hook.at(ctx, &s, b, fp, TEX, counters);
    let mut albedo = s.albedo;
    if TEX {
        counters.texture_samples += 1;
        albedo *= at.texel.unwrap_or_else(|| {
            let t = sample(ctx.texture, plan.filter, at.uv, fp);
            Vec3::new(t[0], t[1], t[2])
        });
    }
    let set = LightSet::of(plan);
    let shadow = ctx.shadow;
    let visibility = |i, counters: &mut Counters| {
        shadow.map_or(1.0, |sh| {
            sh.factor(i, s.p, tri.face_normal, tri.object, counters)
        })
    };
    let cosine = |i, d, counters: &mut Counters| hook.cosine(ctx, &px, at.n, i, d, counters);
    let uv = (at.uv.x, at.uv.y);
    if SPEC {
        let view = view_dir(plan.eye, s.p);
        let (light, mut highlight) =
            light_with::<true>(&set, s.p, at.n, view, cosine, visibility, counters);
        if let Some(map) = gloss_map(ctx, tri.glossy) {
            highlight *= gloss(map, at.uv.x, at.uv.y);
        }
        let c = compose::<Vec3, true>(plan, s.p, at.n, uv, albedo, light, highlight, 1, counters);
        return finish(c, counters);
    }
    let (light, _) = light_with::<false>(&set, s.p, at.n, Vec3::ZERO, cosine, visibility, counters);
    let c = compose::<Vec3, false>(plan, s.p, at.n, uv, albedo, light, Vec3::ZERO, 1, counters);
    finish(c, counters)
}

/// The specular map of the plan, when `glossy` triangles read one.
#[inline]
pub fn gloss_map<'a>(ctx: &ShadeCtx<'a>, glossy: bool) -> Option<&'a crate::texture::Level> {
    if !glossy {
        return None;
    }
    ctx.plan.specular.as_ref()?.map.as_deref()
}

/// A bumped triangle drawn one pixel at a time with the technique `H`, with
/// or without its colour texture and highlights.
pub struct HookKernel<'a, H, const TEX: bool, const SPEC: bool> {
    pub tri: &'a PhongTri,
    pub hook: H,
}

impl<H: Hook, const TEX: bool, const SPEC: bool> PixelShader for HookKernel<'_, H, TEX, SPEC> {
    // Every technique reads the height map, so every one has a footprint.
    const SAMPLES_TEXTURE: bool = true;
    #[inline]
    fn shade(&self, ctx: &ShadeCtx, b: Vec3, fp: Footprint, counters: &mut Counters) -> Rgb {
        shade_pixel::<H, TEX, SPEC>(&self.hook, self.tri, ctx, b, fp, counters)
    }
    fn uvs(&self) -> Option<&[Vec2; 3]> {
        Some(&self.tri.uv)
    }
    fn cutout(&self, ctx: &ShadeCtx) -> bool {
        super::kernels::cuts(ctx)
    }
    fn opaque(&self, ctx: &ShadeCtx, b: Vec3) -> bool {
        let uv = self.tri.uv[0] * b.x + self.tri.uv[1] * b.y + self.tri.uv[2] * b.z;
        super::kernels::opaque_at(ctx, uv)
    }
}
