//! The pixel kernels and the per-triangle data they read.

use glam::{Vec2, Vec3};
use wide::f32x8;

use super::bump::Blinn;
use super::core::{colour, gloss_map, shade};
use super::lighting::finish;
use super::packet::{self, LANES, V3};
use super::specular::gloss;
use crate::framebuffer::Rgb;
use crate::plan::Plan;
use crate::shadow::Shadow;
use crate::stats::Counters;
use crate::texture::Texture;
use crate::texture::filter::{Footprint, sample};

/// What every kernel reads besides its triangle.
pub struct ShadeCtx<'a> {
    pub plan: &'a Plan,
    pub texture: &'a Texture,
    /// The shadow map of `plan.shadow_light`, when the plan asked for one.
    pub shadow: Option<Shadow<'a>>,
}

/// One pixel's colour from the barycentric coordinates `b` of the pixel
/// centre in the *source* triangle (perspective-correct, summing to 1).
pub trait PixelShader {
    /// Whether the kernel reads the texture (and so may want a footprint).
    const SAMPLES_TEXTURE: bool;
    fn shade(&self, ctx: &ShadeCtx, b: Vec3, fp: Footprint, counters: &mut Counters) -> Rgb;
    /// Texture coordinates at the source triangle's vertices, for footprints.
    fn uvs(&self) -> Option<&[Vec2; 3]> {
        None
    }
    /// Whether `shade8` shades this triangle under this plan (bit for bit
    /// as `shade` would).
    fn packets(&self, _ctx: &ShadeCtx) -> bool {
        false
    }
    /// Whether this triangle's pixels may be cut out by an alpha mask
    /// (asked once per triangle; then `opaque` once per covered pixel,
    /// before its depth test).
    fn cutout(&self, _ctx: &ShadeCtx) -> bool {
        false
    }
    /// Whether the pixel at barycentrics `b` of the source triangle is drawn.
    fn opaque(&self, _ctx: &ShadeCtx, _b: Vec3) -> bool {
        true
    }
    /// The one colour of every pixel, for a kernel that has one: its rows
    /// are filled, not shaded.
    fn solid(&self) -> Option<Rgb> {
        None
    }
    /// Eight pixels of a row at once, from their perspective-correct
    /// barycentrics and (when the plan wants them) texture footprints;
    /// `live` has a bit per covered lane (the others are computed and
    /// thrown away, and not counted).
    fn shade8(
        &self,
        _ctx: &ShadeCtx,
        _b: [f32x8; 3],
        _fp: &[Footprint; LANES],
        _live: u32,
        _counters: &mut Counters,
    ) -> [Rgb; LANES] {
        unreachable!("shade8 runs only where packets() said yes")
    }
}

/// Why a frame of `plan` shades one pixel at a time, or `None` when its
/// triangles go through the eight-pixel packets (all but those cut by the
/// near plane, which keep their own barycentric mapping). Mirrors the
/// kernels' `packets` and the rasterizer's conditions.
pub fn one_pixel_reason(plan: &Plan) -> Option<&'static str> {
    use crate::settings::{AntiAlias, Display};
    if plan.display != Display::Fill {
        return Some("points and lines are drawn, not shaded");
    }
    if plan.aa == AntiAlias::Msaa4 {
        return Some("MSAA: coverage and depth per sample");
    }
    None
}

/// Whether the plan's material has an alpha mask.
#[inline]
pub(crate) fn cuts(ctx: &ShadeCtx) -> bool {
    ctx.plan.terms.as_ref().is_some_and(|t| t.cutout.is_some())
}

/// Whether the plan's alpha mask draws the pixel at `uv`.
#[inline]
pub(crate) fn opaque_at(ctx: &ShadeCtx, uv: Vec2) -> bool {
    match ctx.plan.terms.as_ref().and_then(|t| t.cutout.as_ref()) {
        Some(c) => c.opaque(uv),
        None => true,
    }
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

/// Per-triangle shading data, one variant per kernel family.
#[derive(Clone, Debug)]
pub enum TriShader {
    /// Flat without texture: the whole triangle is one colour.
    Solid(Rgb),
    FlatTextured(TexturedFlatTri),
    Gouraud(GouraudTri),
    Phong(PhongTri),
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

/// Flat lighting, textured: the facet's lit colour times the texel.
#[derive(Clone, Debug)]
pub struct TexturedFlatTri {
    pub lit: Vec3,
    pub uv: [Vec2; 3],
    /// The facet's highlight (zero when specular is off), added after the texel.
    pub highlight: Vec3,
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
    fn opaque(&self, ctx: &ShadeCtx, b: Vec3) -> bool {
        opaque_at(ctx, lerp2(b, &self.0.uv))
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

/// Gouraud: light computed at the vertices, interpolated with the albedo.
#[derive(Clone, Debug)]
pub struct GouraudTri {
    pub light: [Vec3; 3],
    /// The highlights at the vertices (zero when specular is off), added
    /// after the albedo.
    pub highlight: [Vec3; 3],
    pub color: [Vec3; 3],
    pub uv: [Vec2; 3],
    pub textured: bool,
    /// The plan's specular map scales the highlight (the triangle has UVs).
    pub glossy: bool,
}

/// The Gouraud kernel, with or without texture and highlights.
pub struct GouraudKernel<'a, const TEX: bool, const SPEC: bool>(pub &'a GouraudTri);

impl<const TEX: bool, const SPEC: bool> PixelShader for GouraudKernel<'_, TEX, SPEC> {
    const SAMPLES_TEXTURE: bool = TEX;
    #[inline]
    fn shade(&self, ctx: &ShadeCtx, b: Vec3, fp: Footprint, counters: &mut Counters) -> Rgb {
        let tri = self.0;
        counters.pixels_shaded += 1;
        let mut albedo = lerp3(b, &tri.color);
        if TEX {
            counters.texture_samples += 1;
            albedo *= rgb(sample(ctx.texture, ctx.plan.filter, lerp2(b, &tri.uv), fp));
        }
        if SPEC {
            let mut highlight = lerp3(b, &tri.highlight);
            if let Some(map) = gloss_map(ctx, tri.glossy) {
                let uv = lerp2(b, &tri.uv);
                highlight *= gloss(map, uv.x, uv.y);
            }
            return finish(albedo * lerp3(b, &tri.light) + highlight, counters);
        }
        finish(albedo * lerp3(b, &tri.light), counters)
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
    fn opaque(&self, ctx: &ShadeCtx, b: Vec3) -> bool {
        opaque_at(ctx, lerp2(b, &self.0.uv))
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
        let mut albedo = packet::lerp3(&b, &tri.color);
        if TEX {
            counters.texture_samples += n;
            let (u, v) = packet::lerp2(&b, &tri.uv);
            albedo = albedo.times(colour::<V3>(ctx, u, v, fp, live));
        }
        let lit = albedo.times(packet::lerp3(&b, &tri.light));
        if SPEC {
            let mut highlight = packet::lerp3(&b, &tri.highlight);
            if let Some(map) = gloss_map(ctx, tri.glossy) {
                let (u, v) = packet::lerp2(&b, &tri.uv);
                highlight = highlight.scale(gloss(map, u, v));
            }
            return packet::finish(lit.plus(highlight), live, counters);
        }
        packet::finish(lit, live, counters)
    }
}

/// Phong: normal, position and albedo interpolated; lighting per pixel.
#[derive(Clone, Debug)]
pub struct PhongTri {
    pub position: [Vec3; 3],
    /// Vertex normals, or three copies of the facet normal.
    pub normal: [Vec3; 3],
    /// The facet normal: used as is for face normals, and as the fallback
    /// when interpolated normals cancel out.
    pub face_normal: Vec3,
    pub smooth: bool,
    pub color: [Vec3; 3],
    pub uv: [Vec2; 3],
    /// ∂P/∂u and ∂P/∂v at the vertices (equal on a flat cube face).
    pub tangent_u: [Vec3; 3],
    pub tangent_v: [Vec3; 3],
    /// The three vertex tangents are the same: skip interpolating them.
    pub uniform_tangents: bool,
    pub textured: bool,
    pub bumped: bool,
    /// The plan's specular map scales the highlight (the triangle has UVs).
    pub glossy: bool,
    /// Index of the object in the scene (whose own shadow a convex one ignores).
    pub object: u32,
}

/// The Phong kernel, with or without texture, Blinn bump and highlights:
/// the shading core with Blinn's hook, one pixel or eight at a time.
pub struct PhongKernel<'a, const TEX: bool, const BUMP: bool, const SPEC: bool>(pub &'a PhongTri);

impl<const TEX: bool, const BUMP: bool, const SPEC: bool> PixelShader
    for PhongKernel<'_, TEX, BUMP, SPEC>
{
    const SAMPLES_TEXTURE: bool = TEX || BUMP;
    #[inline]
    fn shade(&self, ctx: &ShadeCtx, b: Vec3, fp: Footprint, counters: &mut Counters) -> Rgb {
        let b = [b.x, b.y, b.z];
        let c = shade::<Vec3, Blinn<BUMP>, TEX, SPEC>(&Blinn, self.0, ctx, b, &[fp], 1, counters);
        finish(c, counters)
    }
    fn uvs(&self) -> Option<&[Vec2; 3]> {
        Some(&self.0.uv)
    }
    fn packets(&self, _: &ShadeCtx) -> bool {
        true
    }
    fn cutout(&self, ctx: &ShadeCtx) -> bool {
        cuts(ctx)
    }
    fn opaque(&self, ctx: &ShadeCtx, b: Vec3) -> bool {
        opaque_at(ctx, lerp2(b, &self.0.uv))
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
        let c = shade::<V3, Blinn<BUMP>, TEX, SPEC>(&Blinn, self.0, ctx, b, fp, live, counters);
        packet::finish(c, live, counters)
    }
}
