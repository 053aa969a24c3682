//! The one shading core of the Phong family (docs/shading.md): every
//! per-pixel kernel is the surface at the pixel, a technique's hook, and the
//! one light loop.
//!
//! The core and every hook are written once over the lane type
//! (`shade::lanes`): one pixel (`Vec3`) for the one-pixel loop, eight
//! (`packet::V3`) for the packet loop, bit for bit the same.
//!
//! A technique (Blinn, emboss, dot3, parallax, POM) is a `Hook`: it may move
//! the texture coordinate, perturb the normal, or give its own N·L per light.
//! Everything else, the interpolation, the colour read, the light loop with
//! its attenuation, shadows and highlights, the specular map, the clamping
//! and the counters, is here once. Adding a technique is one file with its
//! hook, plus its enum variant and the arm that picks it.

use glam::{Vec2, Vec3};
use wide::f32x8;

use super::PhongTri;
use super::lanes::{Lanes, Vector};
use super::lighting::{LightSet, facing_cosine, finish, light_lanes};
use super::map_uv::{Coords, map_coords};
use super::material::compose;
use super::packet::{self, LANES, V3};
use super::shader::{PixelShader, ShadeCtx};
use super::specular::{gloss, view_dir};
use super::tangent::{Surface, Tris};
use relief_core::framebuffer::Rgb;
use relief_core::settings::{Filter, HeightDerivative};
use relief_core::stats::Counters;
use relief_texture::sample::filter::{height_gradient, sample};
use relief_texture::sample::mip::Footprint;

/// What a technique decided at one pixel (or eight).
#[derive(Clone, Copy, Debug)]
pub struct HookAt<V: Vector> {
    /// Where the colour (and the specular map) is read.
    pub u: V::L,
    pub v: V::L,
    /// The shading normal: the one the highlights use, and Lambert's.
    pub n: V,
    /// The colour texel at (u, v), when the technique already read it (a
    /// fused read): the core then does not read it again.
    pub texel: Option<V>,
}

/// The pixels a hook works on: the surface at them, their barycentrics,
/// texture footprints (one per lane) and covered lanes (a bit each; 1 for
/// one pixel). Lanes not covered are computed and thrown away, and neither
/// read nor counted where a read is made lane by lane.
pub struct Pixels<'a, V: Vector> {
    /// The triangle (its second texture coordinate set, for the maps that
    /// read it); the first lane's when each lane has its own
    /// ([`shade_surface`]).
    pub tri: &'a PhongTri,
    pub s: Surface<V>,
    pub b: [V::L; 3],
    pub fp: &'a [Footprint],
    pub live: u32,
}

impl<V: Vector> Pixels<'_, V> {
    /// How many pixels are covered.
    #[inline(always)]
    pub fn count(&self) -> u64 {
        self.live.count_ones() as u64
    }

    /// The texture coordinate of lane `i`.
    #[inline(always)]
    pub fn uv(&self, i: usize) -> Vec2 {
        Vec2::new(self.s.u.lane(i), self.s.v.lane(i))
    }
}

/// A technique's part of a Phong-family pixel, written once for one pixel
/// or eight (`shade::lanes`).
pub trait Hook {
    /// What `cosine` needs from `at` (nothing for most techniques).
    type Pixel<V: Vector>;
    /// The technique's work at the pixels `px`; `colour` says the core will
    /// read the colour texel. Counts the technique's own evaluations and reads.
    fn at<V: Vector>(
        &self,
        ctx: &ShadeCtx,
        px: &Pixels<V>,
        colour: bool,
        counters: &mut Counters,
    ) -> (HookAt<V>, Self::Pixel<V>);

    /// N·L of light `i`, `d` away, at pixels whose shading normal is `n`:
    /// Lambert's unless the technique has its own. `None` where the light
    /// is behind every lane; a lane ≤ 0 (or NaN) gets no light.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn cosine<V: Vector>(
        &self,
        _ctx: &ShadeCtx,
        _px: &Pixels<V>,
        _own: &Self::Pixel<V>,
        n: V,
        _i: usize,
        d: V,
        _counters: &mut Counters,
    ) -> Option<V::L> {
        facing_cosine(n, d)
    }
}

/// Phong-family pixels (one or eight): the surface, the technique, the
/// colour read, the light loop, the composition `albedo × light +
/// highlight` with the material's terms, and the environment's reflection
/// in the technique's normal when the plan has one. The colour before
/// quantising. `tex` (the colour texture is read) and `spec` (highlights
/// are added) are constants in the hot kernels, folded away when inlined.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub fn shade<V: Vector, H: Hook>(
    hook: &H,
    tri: &PhongTri,
    ctx: &ShadeCtx,
    b: [V::L; 3],
    fp: &[Footprint],
    live: u32,
    flags: (bool, bool),
    counters: &mut Counters,
) -> V {
    let s = Surface::<V>::at(tri, &b);
    shade_surface(
        hook,
        (Tris::One(tri), s),
        ctx,
        b,
        (fp, live),
        flags,
        counters,
    )
}

/// [`shade`] of the pixels of surface `s` on triangles `tris`: the
/// kernel's own, or one per lane when small triangles' last pixels are
/// shaded together (`raster::pending`). With a triangle per lane, the
/// hook and the specular map's coordinates see the first lane's triangle:
/// only a kernel whose hook reads no triangle and whose maps read no
/// second coordinate set shades such packets (`PhongKernel::defers`).
#[inline(always)]
pub fn shade_surface<V: Vector, H: Hook>(
    hook: &H,
    (tris, s): (Tris, Surface<V>),
    ctx: &ShadeCtx,
    b: [V::L; 3],
    (fp, live): (&[Footprint], u32),
    (tex, spec): (bool, bool),
    counters: &mut Counters,
) -> V {
    let plan = ctx.plan;
    let tri = tris.lane(0);
    let px = Pixels {
        tri,
        s,
        b,
        fp,
        live,
    };
    let count = px.count();
    counters.pixels_shaded += count;
    let (at, own) = hook.at(ctx, &px, tex, counters);
    let s = &px.s;
    let mut albedo = s.albedo;
    if tex {
        counters.texture_samples += count;
        albedo = albedo
            * at.texel
                .unwrap_or_else(|| colour(ctx, at.u, at.v, fp, live));
    }
    let set = LightSet::of(plan);
    counters.light_evals += count * set.lights.len() as u64;
    if spec {
        counters.specular_evals += count * set.lights.len() as u64;
    }
    let cosine = |i, d, counters: &mut Counters| hook.cosine(ctx, &px, &own, at.n, i, d, counters);
    let lit = Lit {
        tri,
        ctx,
        p: s.p,
        n: at.n,
        uv: (at.u, at.v),
        b: &px.b,
        albedo,
        live,
    };
    match ctx.shadow {
        // A frame without a shadow map multiplies by no factor.
        None => lit.light(spec, cosine, |_, _, _| V::L::ONE, counters),
        Some(sh) => {
            // Each lane the shadowed light reaches asks the map once.
            let visibility = |i, reached, counters: &mut Counters| {
                if i != sh.light {
                    return V::L::ONE;
                }
                let lanes = V::L::bits(reached) & live;
                let [seen] = V::L::gather(lanes, 1.0, |lane| {
                    let t = tris.lane(lane);
                    [sh.factor(i, s.p.lane(lane), t.face_normal, t.object, counters)]
                });
                seen
            };
            lit.light(spec, cosine, visibility, counters)
        }
    }
}

/// What the light loop and the composition read at the pixels.
struct Lit<'a, V: Vector> {
    tri: &'a PhongTri,
    ctx: &'a ShadeCtx<'a>,
    p: V,
    n: V,
    uv: (V::L, V::L),
    b: &'a [V::L; 3],
    albedo: V,
    live: u32,
}

impl<V: Vector> Lit<'_, V> {
    /// The light loop with the technique's `cosine` and the shadow's
    /// `visibility`, then the composition.
    #[inline(always)]
    fn light(
        &self,
        spec: bool,
        cosine: impl FnMut(usize, V, &mut Counters) -> Option<V::L>,
        visibility: impl FnMut(usize, <V::L as Lanes>::Mask, &mut Counters) -> V::L,
        counters: &mut Counters,
    ) -> V {
        let (plan, p, n, live) = (self.ctx.plan, self.p, self.n, self.live);
        let set = LightSet::of(plan);
        if spec {
            let view = view_dir(plan.eye, p);
            let (light, mut highlight) =
                light_lanes::<V, true>(&set, p, n, view, cosine, visibility, counters);
            if let Some(map) = gloss_map(self.ctx, self.tri.glossy) {
                let (u, v) = match plan.terms.as_deref() {
                    Some(t) => map_coords(&t.uvs.specular, &self.tri.uv2, self.b, self.uv),
                    None => self.uv,
                };
                highlight = highlight * gloss(map, u, v);
            }
            return compose::<V, true>(
                plan,
                p,
                n,
                Coords {
                    uv: self.uv,
                    b: self.b,
                    uv2: &self.tri.uv2,
                },
                self.albedo,
                light,
                highlight,
                live,
                counters,
            );
        }
        let zero = V::uniform(Vec3::ZERO);
        let (light, _) = light_lanes::<V, false>(&set, p, n, zero, cosine, visibility, counters);
        compose::<V, false>(
            plan,
            p,
            n,
            Coords {
                uv: self.uv,
                b: self.b,
                uv2: &self.tri.uv2,
            },
            self.albedo,
            light,
            zero,
            live,
            counters,
        )
    }
}

/// The colour texels (RGB) at (u, v): for eight bilinear pixels the packet
/// read, else each covered lane's own read (mip level and footprint per
/// pixel), exactly as one pixel reads it.
#[inline(always)]
pub fn colour<V: Vector>(ctx: &ShadeCtx, u: V::L, v: V::L, fp: &[Footprint], live: u32) -> V {
    let plan = ctx.plan;
    if V::WIDTH > 1 && plan.filter == Filter::Bilinear {
        let [r, g, b] = V::L::bilinear(ctx.texture.base(), u, v);
        return V::new(r, g, b);
    }
    V::gather(live, |i| {
        let t = sample(
            ctx.texture,
            plan.filter,
            Vec2::new(u.lane(i), v.lane(i)),
            fp[i],
        );
        Vec3::new(t[0], t[1], t[2])
    })
}

/// The height gradient (∂F/∂u, ∂F/∂v) at (u, v) as the plan reads it: for
/// eight pixels whose filter reads the base level (nearest, bilinear) with
/// the filtered derivative, the packet read; else each covered lane's own.
#[inline(always)]
pub fn gradient<L: Lanes>(ctx: &ShadeCtx, u: L, v: L, fp: &[Footprint], live: u32) -> (L, L) {
    let plan = ctx.plan;
    if L::WIDTH > 1
        && matches!(plan.filter, Filter::Bilinear | Filter::Nearest)
        && plan.height_derivative == HeightDerivative::Filtered
    {
        return L::gradient(ctx.texture.base(), u, v);
    }
    let [fu, fv] = L::gather(live, 0.0, |i| {
        let uv = Vec2::new(u.lane(i), v.lane(i));
        let (fu, fv) = height_gradient(ctx.texture, plan.height_derivative, plan.filter, uv, fp[i]);
        [fu, fv]
    });
    (fu, fv)
}

/// The specular map of the plan, when `glossy` triangles read one.
#[inline]
pub fn gloss_map<'a>(ctx: &ShadeCtx<'a>, glossy: bool) -> Option<&'a relief_texture::Level> {
    if !glossy {
        return None;
    }
    ctx.plan.specular.as_ref()?.map.as_deref()
}

/// A Phong-family triangle drawn with the technique `H`, with or without
/// its colour texture and highlights: one pixel at a time, or eight.
/// Unlike the Phong kernel's, texture and highlights are flags, not type
/// parameters: these techniques' texture reads dwarf a branch per packet,
/// and one kernel per technique instead of four keeps the build short.
pub struct HookKernel<'a, H> {
    pub tri: &'a PhongTri,
    pub hook: H,
    /// Whether the colour texture is read.
    pub textured: bool,
    /// Whether highlights are added.
    pub specular: bool,
}

impl<H: Hook> PixelShader for HookKernel<'_, H> {
    // Every technique reads the height map, so every one has a footprint.
    const SAMPLES_TEXTURE: bool = true;
    #[inline]
    fn shade(&self, ctx: &ShadeCtx, b: Vec3, fp: Footprint, counters: &mut Counters) -> Rgb {
        let b = [b.x, b.y, b.z];
        let flags = (self.textured, self.specular);
        let c = shade::<Vec3, H>(&self.hook, self.tri, ctx, b, &[fp], 1, flags, counters);
        finish(c, counters)
    }
    fn uvs(&self) -> Option<&[Vec2; 3]> {
        Some(&self.tri.uv)
    }
    fn second_uvs(&self) -> Option<&[Vec2; 3]> {
        Some(&self.tri.uv2)
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
        let flags = (self.textured, self.specular);
        let c = shade::<V3, H>(&self.hook, self.tri, ctx, b, fp, live, flags, counters);
        packet::finish(c, live, counters)
    }
}
