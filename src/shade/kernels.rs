//! The pixel kernels and the per-triangle data they read.

use glam::{Vec2, Vec3};
use wide::f32x8;

use super::bump::Blinn;
use super::bump::blinn;
use super::core::{gloss_map, shade_pixel};
use super::lanes::Vector;
use super::lighting::{LightSet, facing_cosine, finish, light_lanes};
use super::material::compose;
use super::packet::{self, LANES, V3};
use super::specular::{gloss, view_dir};
use crate::framebuffer::Rgb;
use crate::plan::Plan;
use crate::settings::{Filter, HeightDerivative};
use crate::shadow::Shadow;
use crate::stats::Counters;
use crate::texture::Texture;
use crate::texture::filter::{Footprint, height_gradient, sample};

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
    use crate::settings::{AntiAlias, Display, Shading, Technique};
    let bumped = plan.bump && plan.shading == Shading::Phong;
    if plan.display != Display::Fill {
        return Some("points and lines are drawn, not shaded");
    }
    if plan.aa == AntiAlias::Msaa4 {
        return Some("MSAA: coverage and depth per sample");
    }
    if bumped && plan.technique != Technique::Blinn {
        return Some("emboss, dot3, parallax and POM have no packet kernel yet");
    }
    None
}

/// The colour texels of eight pixels (RGB): the bilinear packet read, or
/// for the other filters each live lane's own read (mip level and
/// footprint per pixel), exactly as the one-pixel kernels read them.
#[inline(always)]
fn colour8(ctx: &ShadeCtx, u: f32x8, v: f32x8, fp: &[Footprint; LANES], live: u32) -> V3 {
    if bilinear_colour(ctx.plan) {
        return packet::bilinear::<true, false>(ctx.texture.base(), u, v).color;
    }
    let mut c = [[0.0f32; LANES]; 3];
    let (ua, va) = (u.to_array(), v.to_array());
    for lane in (0..LANES).filter(|l| live & (1 << l) != 0) {
        let t = sample(
            ctx.texture,
            ctx.plan.filter,
            Vec2::new(ua[lane], va[lane]),
            fp[lane],
        );
        (c[0][lane], c[1][lane], c[2][lane]) = (t[0], t[1], t[2]);
    }
    let [x, y, z] = c.map(f32x8::from);
    V3 { x, y, z }
}

/// A bilinear read that a packet can make: the plan's filter is bilinear.
#[inline]
fn bilinear_colour(plan: &Plan) -> bool {
    plan.filter == Filter::Bilinear
}

/// The filtered height gradient on the base level, as packets read it.
#[inline]
fn bilinear_gradient(plan: &Plan) -> bool {
    matches!(plan.filter, Filter::Bilinear | Filter::Nearest)
        && plan.height_derivative == HeightDerivative::Filtered
}

/// The light loop at eight points of `tri` (`light_lanes`), with each
/// covered lane's shadow when the frame has a shadow map (a loop of its
/// own, so a frame without one multiplies by no factor).
#[inline(always)]
fn light8<const SPEC: bool>(
    ctx: &ShadeCtx,
    tri: &PhongTri,
    p: V3,
    n: V3,
    view: V3,
    live: u32,
    counters: &mut Counters,
) -> (V3, V3) {
    let set = LightSet::of(ctx.plan);
    let cosine = |_, d, _: &mut Counters| facing_cosine(n, d);
    match ctx.shadow {
        None => light_lanes::<V3, SPEC>(&set, p, n, view, cosine, |_, _, _| f32x8::ONE, counters),
        Some(sh) => {
            let visibility = |i, reached: f32x8, counters: &mut Counters| {
                if i == sh.light {
                    shadow8(sh, p, tri, reached.to_bitmask() & live, counters)
                } else {
                    f32x8::ONE
                }
            };
            light_lanes::<V3, SPEC>(&set, p, n, view, cosine, visibility, counters)
        }
    }
}

/// The shadow factor of the shadowed light at the `lanes` of `p` (a bit
/// per lane it reaches among the covered ones; 1 in the others): each
/// lane's one lookup, as the one-pixel kernel makes it.
#[inline(always)]
fn shadow8(sh: Shadow, p: V3, tri: &PhongTri, lanes: u32, counters: &mut Counters) -> f32x8 {
    let (x, y, z) = (p.x.to_array(), p.y.to_array(), p.z.to_array());
    let mut seen = [1.0f32; LANES];
    for lane in (0..LANES).filter(|l| lanes & (1 << l) != 0) {
        let p = Vec3::new(x[lane], y[lane], z[lane]);
        seen[lane] = sh.factor(sh.light, p, tri.face_normal, tri.object, counters);
    }
    f32x8::from(seen)
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
        let t = colour8(ctx, u, v, fp, live);
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
            albedo = albedo.times(colour8(ctx, u, v, fp, live));
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

/// The Phong kernel, with or without texture, Blinn bump and highlights.
pub struct PhongKernel<'a, const TEX: bool, const BUMP: bool, const SPEC: bool>(pub &'a PhongTri);

impl<const TEX: bool, const BUMP: bool, const SPEC: bool> PixelShader
    for PhongKernel<'_, TEX, BUMP, SPEC>
{
    const SAMPLES_TEXTURE: bool = TEX || BUMP;
    #[inline]
    fn shade(&self, ctx: &ShadeCtx, b: Vec3, fp: Footprint, counters: &mut Counters) -> Rgb {
        shade_pixel::<Blinn<BUMP>, TEX, SPEC>(&Blinn, self.0, ctx, b, fp, counters)
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
        let tri = self.0;
        let plan = ctx.plan;
        let count = live.count_ones() as u64;
        counters.pixels_shaded += count;
        let p = packet::lerp3(&b, &tri.position);
        let mut n = if tri.smooth {
            packet::lerp3(&b, &tri.normal).normalize_or(tri.face_normal)
        } else {
            V3::splat(tri.face_normal)
        };
        let mut albedo = packet::lerp3(&b, &tri.color);
        if TEX || BUMP {
            let (u, v) = packet::lerp2(&b, &tri.uv);
            let t = if (!TEX || bilinear_colour(plan)) && (!BUMP || bilinear_gradient(plan)) {
                packet::bilinear::<TEX, BUMP>(ctx.texture.base(), u, v)
            } else {
                // Mip levels, footprints and per-texel differences: each
                // lane reads as the one-pixel kernel does, except the
                // filtered derivative on the base level, which is a packet read.
                let color = if TEX {
                    colour8(ctx, u, v, fp, live)
                } else {
                    V3::splat(Vec3::ZERO)
                };
                let (mut fu, mut fv) = (f32x8::ZERO, f32x8::ZERO);
                if BUMP && bilinear_gradient(plan) {
                    let g = packet::bilinear::<false, true>(ctx.texture.base(), u, v);
                    (fu, fv) = (g.fu, g.fv);
                } else if BUMP {
                    let mut g = [[0.0f32; LANES]; 2];
                    let (ua, va) = (u.to_array(), v.to_array());
                    let (d, f) = (plan.height_derivative, plan.filter);
                    for lane in (0..LANES).filter(|l| live & (1 << l) != 0) {
                        let uv = Vec2::new(ua[lane], va[lane]);
                        (g[0][lane], g[1][lane]) = height_gradient(ctx.texture, d, f, uv, fp[lane]);
                    }
                    (fu, fv) = (f32x8::from(g[0]), f32x8::from(g[1]));
                }
                packet::TexelPacket { color, fu, fv }
            };
            if TEX {
                counters.texture_samples += count;
                albedo = albedo.times(t.color);
            }
            if BUMP {
                counters.bump_evals += count;
                let (pu, pv) = if tri.uniform_tangents {
                    (V3::splat(tri.tangent_u[0]), V3::splat(tri.tangent_v[0]))
                } else {
                    (
                        packet::lerp3(&b, &tri.tangent_u),
                        packet::lerp3(&b, &tri.tangent_v),
                    )
                };
                n = blinn(n, pu, pv, t.fu, t.fv, plan.bump_strength);
            }
        }
        counters.light_evals += count * plan.lights.len() as u64;
        let uv = packet::lerp2(&b, &tri.uv);
        if SPEC && plan.specular.is_some() {
            counters.specular_evals += count * plan.lights.len() as u64;
            let view = view_dir(plan.eye, p);
            let (light, mut highlight) = light8::<true>(ctx, tri, p, n, view, live, counters);
            if let Some(map) = gloss_map(ctx, tri.glossy) {
                highlight = highlight.scale(gloss(map, uv.0, uv.1));
            }
            let c = compose::<V3, true>(plan, p, n, uv, albedo, light, highlight, live, counters);
            return packet::finish(c, live, counters);
        }
        let zero = V3::splat(Vec3::ZERO);
        let (light, _) = light8::<false>(ctx, tri, p, n, zero, live, counters);
        let c = compose::<V3, false>(plan, p, n, uv, albedo, light, zero, live, counters);
        packet::finish(c, live, counters)
    }
}
