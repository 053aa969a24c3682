//! The pixel kernels: each kernel family's shading of one pixel or eight,
//! over the per-triangle data of `shade::shader`.

use glam::{Vec2, Vec3};
use wide::f32x8;

use super::bump::Blinn;
use super::core::{colour, gloss_map, shade, shade_surface};
use super::interpolate::{Corners2, Corners3, lerp2};
use super::lanes::Vector;
use super::lighting::finish;
use super::packet::{self, LANES, V3};
use super::shader::{
    GouraudTri, PHONG_KIND, PendingKey, PhongTri, PixelShader, ShadeCtx, TexturedFlatTri, cuts,
    pending_key,
};
use super::specular::gloss;
use super::tangent::{Surface, Tris};
use crate::plan::Plan;
use relief_core::framebuffer::Rgb;
use relief_core::stats::Counters;
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

impl PixelShader for Rgb {
    const SAMPLES_TEXTURE: bool = false;
    #[inline]
    fn shade(&self, _: &ShadeCtx, _: Vec3, _: Footprint, counters: &mut Counters) -> Rgb {
        counters.pixels_shaded += 1;
        *self
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

impl<const SPEC: bool> FlatTexturedKernel<'_, SPEC> {
    /// The colour at pixels of barycentrics `b`, one or eight.
    #[inline(always)]
    fn colour<V: Vector>(
        &self,
        ctx: &ShadeCtx,
        b: &[V::L; 3],
        fp: &[Footprint],
        live: u32,
        counters: &mut Counters,
    ) -> V {
        let tri = self.0;
        let n = live.count_ones() as u64;
        counters.pixels_shaded += n;
        counters.texture_samples += n;
        let (u, v) = lerp2(b, &tri.uv);
        let lit = V::uniform(tri.lit) * colour::<V>(ctx, u, v, fp, live);
        if SPEC {
            return lit + V::uniform(tri.highlight);
        }
        lit
    }
}

impl<const SPEC: bool> PixelShader for FlatTexturedKernel<'_, SPEC> {
    const SAMPLES_TEXTURE: bool = true;
    #[inline]
    fn shade(&self, ctx: &ShadeCtx, b: Vec3, fp: Footprint, counters: &mut Counters) -> Rgb {
        let c = self.colour::<Vec3>(ctx, &b.to_array(), &[fp], 1, counters);
        finish(c, counters)
    }
    fn uvs(&self) -> Option<&[Vec2; 3]> {
        Some(&self.0.uv)
    }
    fn packets(&self, ctx: &ShadeCtx) -> bool {
        // A masked pixel is tested before its depth, one at a time.
        !cuts(ctx)
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
        let c = self.colour::<V3>(ctx, &b, fp, live, counters);
        packet::finish(c, live, counters)
    }
}

/// The Gouraud kernel, with or without texture and highlights.
pub struct GouraudKernel<'a, const TEX: bool, const SPEC: bool> {
    tri: &'a GouraudTri,
    /// The vertex values a packet interpolates, broadcast once per
    /// triangle rather than per packet.
    lanes: GouraudCorners<V3>,
}

/// A Gouraud triangle's vertex values in the lanes of `V` (the highlights
/// and texture coordinates zero unless the kernel reads them).
struct GouraudCorners<V: Vector> {
    color: Corners3<V>,
    light: Corners3<V>,
    highlight: Corners3<V>,
    uv: Corners2<V::L>,
}

impl<V: Vector> GouraudCorners<V> {
    #[inline(always)]
    fn of(tri: &GouraudTri, tex: bool, spec: bool) -> Self {
        GouraudCorners {
            color: Corners3::of(&tri.color),
            light: Corners3::of(&tri.light),
            highlight: Corners3::of(if spec {
                &tri.highlight
            } else {
                &[Vec3::ZERO; 3]
            }),
            uv: Corners2::of(if tex { &tri.uv } else { &[Vec2::ZERO; 3] }),
        }
    }
}

impl<'a, const TEX: bool, const SPEC: bool> GouraudKernel<'a, TEX, SPEC> {
    pub fn new(tri: &'a GouraudTri) -> Self {
        let lanes = GouraudCorners::of(tri, TEX, SPEC);
        GouraudKernel { tri, lanes }
    }

    /// The colour at pixels of barycentrics `b`, one or eight, from the
    /// vertex values `at` in their lanes.
    #[inline(always)]
    fn colour<V: Vector>(
        &self,
        at: &GouraudCorners<V>,
        ctx: &ShadeCtx,
        b: &[V::L; 3],
        fp: &[Footprint],
        live: u32,
        counters: &mut Counters,
    ) -> V {
        let tri = self.tri;
        let n = live.count_ones() as u64;
        counters.pixels_shaded += n;
        let mut albedo = at.color.at(b);
        if TEX {
            counters.texture_samples += n;
            let (u, v) = at.uv.at(b);
            albedo = albedo * colour::<V>(ctx, u, v, fp, live);
        }
        let lit = albedo * at.light.at(b);
        if SPEC {
            let mut highlight = at.highlight.at(b);
            if let Some(map) = gloss_map(ctx, tri.glossy) {
                let (u, v) = lerp2(b, &tri.gloss_uv);
                highlight = highlight * gloss(map, u, v);
            }
            return lit + highlight;
        }
        lit
    }
}

impl<const TEX: bool, const SPEC: bool> PixelShader for GouraudKernel<'_, TEX, SPEC> {
    const SAMPLES_TEXTURE: bool = TEX;
    #[inline]
    fn shade(&self, ctx: &ShadeCtx, b: Vec3, fp: Footprint, counters: &mut Counters) -> Rgb {
        let at = GouraudCorners::<Vec3>::of(self.tri, TEX, SPEC);
        let c = self.colour(&at, ctx, &b.to_array(), &[fp], 1, counters);
        finish(c, counters)
    }
    fn uvs(&self) -> Option<&[Vec2; 3]> {
        Some(&self.tri.uv)
    }
    fn packets(&self, ctx: &ShadeCtx) -> bool {
        // A masked pixel is tested before its depth, one at a time.
        !cuts(ctx)
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
        let c = self.colour(&self.lanes, ctx, &b, fp, live, counters);
        packet::finish(c, live, counters)
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

    /// Eight pixels of triangles `tris` of this kernel's kind (see
    /// `defers`), one per lane, at their barycentrics `b`: bit for bit
    /// what each triangle's own kernel shades there.
    pub fn shade_each(
        &self,
        ctx: &ShadeCtx,
        (tris, b): (&[&PhongTri; LANES], [f32x8; 3]),
        fp: &[Footprint; LANES],
        live: u32,
        counters: &mut Counters,
    ) -> [Rgb; LANES] {
        // Without Blinn's bump no pixel reads ∂P/∂u, ∂P/∂v.
        let s = Surface::each(tris, &b, BUMP);
        let surface = (Tris::Each(tris), s);
        let c: V3 = shade_surface(
            &self.hook,
            surface,
            ctx,
            b,
            (fp, live),
            (TEX, SPEC),
            counters,
        );
        packet::finish(c, live, counters)
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
    // Shading a packet of this kernel costs about what gathering three
    // lanes' triangles does: a longer last packet is shaded at once
    // (measured with 1 to 8: 3 lost least at 640×480 and gained most at
    // terminal sizes, docs/bench.md).
    const MOST_DEFERRED: usize = 3;
    /// Without Blinn's bump, a pixel needs of its triangle only what
    /// `shade_each` takes per lane, unless a map reads the second
    /// coordinate set; the triangles of one kind also agree on whether
    /// they read the specular map.
    fn defers(&self, ctx: &ShadeCtx) -> Option<PendingKey> {
        let second = (ctx.plan.terms.as_deref()).is_some_and(|t| t.uvs.reads_second_set());
        (!BUMP && !second).then(|| {
            let variant = u32::from(TEX) | u32::from(SPEC) << 1 | u32::from(self.tri.glossy) << 2;
            pending_key(ctx, PHONG_KIND | variant)
        })
    }
}
