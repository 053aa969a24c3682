//! The pixel kernels: each kernel family's shading of one pixel or eight,
//! over the per-triangle data of `shade::shader`.

use glam::{Vec2, Vec3};
use wide::f32x8;

use super::bump::Blinn;
use super::core::{colour, gloss_map, shade};
use super::lighting::finish;
use super::packet::{self, LANES, V3, Vertices2, Vertices3};
use super::shader::{
    GouraudTri, PhongTri, PixelShader, ShadeCtx, TexturedFlatTri, cuts, opacity_at,
};
use super::specular::gloss;
use crate::plan::Plan;
use relief_core::framebuffer::Rgb;
use relief_core::stats::Counters;
use relief_texture::sample::filter::sample;
use relief_texture::sample::mip::Footprint;

/// Why a frame of `plan` shades one pixel at a time, or `None` when its
/// triangles go through the eight-pixel packets (all but those cut by the
/// near plane, which keep their own barycentric mapping). Mirrors the
/// kernels' `packets` and the rasterizer's conditions.
pub fn one_pixel_reason(plan: &Plan) -> Option<&'static str> {
    use relief_core::settings::{AntiAlias, Display};
    if plan.display != Display::Fill {
        return Some("points and lines are drawn, not shaded");
    }
    if plan.aa == AntiAlias::Msaa4 {
        return Some("MSAA: coverage and depth per sample");
    }
    None
}

#[inline]
fn lerp3(b: Vec3, v: &[Vec3; 3]) -> Vec3 {
    v[0] * b.x + v[1] * b.y + v[2] * b.z
}

#[inline]
fn lerp2(b: Vec3, v: &[Vec2; 3]) -> Vec2 {
    v[0] * b.x + v[1] * b.y + v[2] * b.z
}

#[inline]
fn rgb(t: [f32; 4]) -> Vec3 {
    Vec3::new(t[0], t[1], t[2])
}

impl PixelShader for Rgb {
    const SAMPLES_TEXTURE: bool = false;
    #[inline]
    fn shade(&self, _: &ShadeCtx, _: Vec3, _: Footprint, counters: &mut Counters) -> Rgb {
        counters.pixels_shaded += 1;
        *self
    }
    fn packets(&self, _: &ShadeCtx) -> bool {
        true
    }
    fn solid(&self) -> Option<Rgb> {
        Some(*self)
    }
    #[inline]
    fn shade8(
        &self,
        _: &ShadeCtx,
        _: [f32x8; 3],
        _: &[Footprint; LANES],
        live: u32,
        counters: &mut Counters,
    ) -> [Rgb; LANES] {
        counters.pixels_shaded += live.count_ones() as u64;
        [*self; LANES]
    }
}

/// The textured flat kernel, with its facet's highlight added when `SPEC`
/// (chosen per triangle, so the plain kernel does no extra work).
pub struct FlatTexturedKernel<'a, const SPEC: bool>(pub &'a TexturedFlatTri);

impl<const SPEC: bool> PixelShader for FlatTexturedKernel<'_, SPEC> {
    const SAMPLES_TEXTURE: bool = true;
    #[inline]
    fn shade(&self, ctx: &ShadeCtx, b: Vec3, fp: Footprint, counters: &mut Counters) -> Rgb {
        let tri = self.0;
        counters.pixels_shaded += 1;
        counters.texture_samples += 1;
        let t = sample(ctx.texture, ctx.plan.filter, lerp2(b, &tri.uv), fp);
        if SPEC {
            return finish(tri.lit * rgb(t) + tri.highlight, counters);
        }
        finish(tri.lit * rgb(t), counters)
    }
    fn uvs(&self) -> Option<&[Vec2; 3]> {
        Some(&self.0.uv)
    }
    fn packets(&self, ctx: &ShadeCtx) -> bool {
        // A masked pixel is tested before its depth, one at a time.
        !cuts(ctx)
    }
    fn cutout(&self, ctx: &ShadeCtx) -> bool {
        cuts(ctx)
    }
    fn opacity(&self, ctx: &ShadeCtx, b: Vec3) -> f32 {
        opacity_at(ctx, b, &self.0.uv)
    }
    #[inline]
    fn shade8(
        &self,
        ctx: &ShadeCtx,
        b: [f32x8; 3],
        fp: &[Footprint; LANES],
        live: u32,
        counters: &mut Counters,
    ) -> [Rgb; LANES] {
        let tri = self.0;
        let n = live.count_ones() as u64;
        counters.pixels_shaded += n;
        counters.texture_samples += n;
        let (u, v) = packet::lerp2(&b, &tri.uv);
        let t = colour::<V3>(ctx, u, v, fp, live);
        let lit = V3::splat(tri.lit).times(t);
        if SPEC {
            return packet::finish(lit.plus(V3::splat(tri.highlight)), live, counters);
        }
        packet::finish(lit, live, counters)
    }
}

/// The Gouraud kernel, with or without texture and highlights.
pub struct GouraudKernel<'a, const TEX: bool, const SPEC: bool> {
    tri: &'a GouraudTri,
    /// The vertex values a packet interpolates, broadcast once per
    /// triangle rather than per packet.
    lanes: GouraudLanes,
}

/// A Gouraud triangle's vertex values in eight lanes (the highlights and
/// texture coordinates zero unless the kernel reads them).
struct GouraudLanes {
    color: Vertices3,
    light: Vertices3,
    highlight: Vertices3,
    uv: Vertices2,
}

impl<'a, const TEX: bool, const SPEC: bool> GouraudKernel<'a, TEX, SPEC> {
    pub fn new(tri: &'a GouraudTri) -> Self {
        let lanes = GouraudLanes {
            color: Vertices3::of(&tri.color),
            light: Vertices3::of(&tri.light),
            highlight: Vertices3::of(if SPEC {
                &tri.highlight
            } else {
                &[Vec3::ZERO; 3]
            }),
            uv: Vertices2::of(if TEX { &tri.uv } else { &[Vec2::ZERO; 3] }),
        };
        GouraudKernel { tri, lanes }
    }
}

impl<const TEX: bool, const SPEC: bool> PixelShader for GouraudKernel<'_, TEX, SPEC> {
    const SAMPLES_TEXTURE: bool = TEX;
    #[inline]
    fn shade(&self, ctx: &ShadeCtx, b: Vec3, fp: Footprint, counters: &mut Counters) -> Rgb {
        let tri = self.tri;
        counters.pixels_shaded += 1;
        let mut albedo = lerp3(b, &tri.color);
        if TEX {
            counters.texture_samples += 1;
            albedo *= rgb(sample(ctx.texture, ctx.plan.filter, lerp2(b, &tri.uv), fp));
        }
        if SPEC {
            let mut highlight = lerp3(b, &tri.highlight);
            if let Some(map) = gloss_map(ctx, tri.glossy) {
                let uv = lerp2(b, &tri.gloss_uv);
                highlight *= gloss(map, uv.x, uv.y);
            }
            return finish(albedo * lerp3(b, &tri.light) + highlight, counters);
        }
        finish(albedo * lerp3(b, &tri.light), counters)
    }
    fn uvs(&self) -> Option<&[Vec2; 3]> {
        Some(&self.tri.uv)
    }
    fn packets(&self, ctx: &ShadeCtx) -> bool {
        // A masked pixel is tested before its depth, one at a time.
        !cuts(ctx)
    }
    fn cutout(&self, ctx: &ShadeCtx) -> bool {
        cuts(ctx)
    }
    fn opacity(&self, ctx: &ShadeCtx, b: Vec3) -> f32 {
        opacity_at(ctx, b, &self.tri.uv)
    }
    #[inline]
    fn shade8(
        &self,
        ctx: &ShadeCtx,
        b: [f32x8; 3],
        fp: &[Footprint; LANES],
        live: u32,
        counters: &mut Counters,
    ) -> [Rgb; LANES] {
        let (tri, lanes) = (self.tri, &self.lanes);
        let n = live.count_ones() as u64;
        counters.pixels_shaded += n;
        let mut albedo = lanes.color.lerp(&b);
        if TEX {
            counters.texture_samples += n;
            let (u, v) = lanes.uv.lerp(&b);
            albedo = albedo.times(colour::<V3>(ctx, u, v, fp, live));
        }
        let lit = albedo.times(lanes.light.lerp(&b));
        if SPEC {
            let mut highlight = lanes.highlight.lerp(&b);
            if let Some(map) = gloss_map(ctx, tri.glossy) {
                let (u, v) = packet::lerp2(&b, &tri.gloss_uv);
                highlight = highlight.scale(gloss(map, u, v));
            }
            return packet::finish(lit.plus(highlight), live, counters);
        }
        packet::finish(lit, live, counters)
    }
}

/// The Phong kernel, with or without texture, Blinn bump and highlights:
/// the shading core with Blinn's hook, one pixel or eight at a time.
pub struct PhongKernel<'a, const TEX: bool, const BUMP: bool, const SPEC: bool> {
    tri: &'a PhongTri,
    hook: Blinn<BUMP>,
}

impl<'a, const TEX: bool, const BUMP: bool, const SPEC: bool> PhongKernel<'a, TEX, BUMP, SPEC> {
    /// The kernel of `tri` under the bump strength `k` (of the plan).
    pub fn new(tri: &'a PhongTri, k: f32) -> Self {
        PhongKernel {
            tri,
            hook: Blinn::for_triangle(tri, k),
        }
    }
}

impl<const TEX: bool, const BUMP: bool, const SPEC: bool> PixelShader
    for PhongKernel<'_, TEX, BUMP, SPEC>
{
    const SAMPLES_TEXTURE: bool = TEX || BUMP;
    #[inline]
    fn shade(&self, ctx: &ShadeCtx, b: Vec3, fp: Footprint, counters: &mut Counters) -> Rgb {
        let b = [b.x, b.y, b.z];
        let c = shade::<Vec3, _>(
            &self.hook,
            self.tri,
            ctx,
            b,
            &[fp],
            1,
            (TEX, SPEC),
            counters,
        );
        finish(c, counters)
    }
    fn uvs(&self) -> Option<&[Vec2; 3]> {
        Some(&self.tri.uv)
    }
    fn packets(&self, _: &ShadeCtx) -> bool {
        true
    }
    fn cutout(&self, ctx: &ShadeCtx) -> bool {
        cuts(ctx)
    }
    fn opacity(&self, ctx: &ShadeCtx, b: Vec3) -> f32 {
        opacity_at(ctx, b, &self.tri.uv)
    }
    #[inline(always)]
    fn shade8(
        &self,
        ctx: &ShadeCtx,
        b: [f32x8; 3],
        fp: &[Footprint; LANES],
        live: u32,
        counters: &mut Counters,
    ) -> [Rgb; LANES] {
        let c = shade::<V3, _>(
            &self.hook,
            self.tri,
            ctx,
            b,
            fp,
            live,
            (TEX, SPEC),
            counters,
        );
        packet::finish(c, live, counters)
    }
}
