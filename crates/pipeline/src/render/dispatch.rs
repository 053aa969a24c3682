//! Which kernel draws a triangle: chosen once per triangle from its shader
//! and the plan, so no pixel tests what its triangle needs.

use crate::raster::aa::{PendingTarget, RasterTarget};
use crate::raster::pending::write_packet;
use crate::raster::scan::OwnedBand;
use crate::raster::{Band, ScreenTri};
use crate::shade::core::{Hook, HookKernel};
use crate::shade::dot3::Dot3;
use crate::shade::emboss::Emboss;
use crate::shade::kernels::{FlatTexturedKernel, GouraudKernel, PhongKernel};
use crate::shade::packet::LANES;
use crate::shade::parallax::Parallax;
use crate::shade::pbr::{EnvLight, PbrKernel};
use crate::shade::{PhongTri, ShadeCtx, TriShader};
use relief_core::framebuffer::Rgb;
use relief_core::settings::{LightVector, Technique};
use relief_core::stats::Counters;
use relief_texture::sample::mip::Footprint;
use wide::f32x8;

/// `$body` with `$k` the metallic-roughness kernel of triangle `$s` under
/// `$ctx`'s plan, in the variant its colour texture and normal map choose;
/// `None` when the plan has no physical material.
macro_rules! with_pbr_kernel {
    ($ctx:expr, $s:expr, |$k:ident| $body:expr) => {{
        let plan = $ctx.plan;
        let s: &PhongTri = $s;
        if let (Some(physical), Some(terms)) = (plan.physical.as_ref(), plan.terms.as_deref())
            && let Some(pbr) = terms.pbr.as_ref()
        {
            let light = physical
                .environment
                .as_deref()
                .map(|e| EnvLight::of(e, physical));
            let plain = PbrKernel::<false, false> {
                tri: s,
                terms,
                pbr,
                physical,
                light,
            };
            Some(match (s.textured, s.bumped && pbr.normal.is_some()) {
                (true, true) => {
                    let $k = plain.variant::<true, true>();
                    $body
                }
                (true, false) => {
                    let $k = plain.variant::<true, false>();
                    $body
                }
                (false, true) => {
                    let $k = plain.variant::<false, true>();
                    $body
                }
                (false, false) => {
                    let $k = plain;
                    $body
                }
            })
        } else {
            None
        }
    }};
}

/// Runs the pixel loop monomorphised for the triangle's kernel. This and
/// [`draw_owned_triangle`] are not generic, so a crate that calls them
/// (the tests) does not compile every kernel again.
pub fn draw_triangle(
    tri: &ScreenTri,
    shader: &TriShader,
    ctx: &ShadeCtx,
    band: &mut Band,
    counters: &mut Counters,
) {
    draw_into(tri, shader, ctx, band, counters)
}

/// [`draw_triangle`] over a band whose depth was drawn first: only the
/// pixels the triangle owns are shaded.
pub fn draw_owned_triangle(
    tri: &ScreenTri,
    shader: &TriShader,
    ctx: &ShadeCtx,
    band: &mut OwnedBand,
    counters: &mut Counters,
) {
    draw_into(tri, shader, ctx, band, counters)
}

/// The kernel dispatch, for any raster target (plain or multisampled):
/// each triangle's kernel is chosen here, once, so no pixel tests what its
/// triangle needs.
pub(crate) fn draw_into<T: RasterTarget>(
    tri: &ScreenTri,
    shader: &TriShader,
    ctx: &ShadeCtx,
    target: &mut T,
    counters: &mut Counters,
) {
    let spec = ctx.plan.specular.is_some();
    match shader {
        TriShader::Solid(color) => target.raster(tri, color, ctx, counters),
        TriShader::FlatTextured(s) if spec => {
            target.raster(tri, &FlatTexturedKernel::<true>(s), ctx, counters)
        }
        TriShader::FlatTextured(s) => {
            target.raster(tri, &FlatTexturedKernel::<false>(s), ctx, counters)
        }
        TriShader::Gouraud(s) => match (s.textured, spec) {
            (true, true) => target.raster(tri, &GouraudKernel::<true, true>::new(s), ctx, counters),
            (true, false) => {
                target.raster(tri, &GouraudKernel::<true, false>::new(s), ctx, counters)
            }
            (false, true) => {
                target.raster(tri, &GouraudKernel::<false, true>::new(s), ctx, counters)
            }
            (false, false) => {
                target.raster(tri, &GouraudKernel::<false, false>::new(s), ctx, counters)
            }
        },
        TriShader::Phong(s) if physical(ctx) => draw_physical(tri, s, ctx, target, counters),
        TriShader::Phong(s) if s.bumped => draw_bumped(tri, s, ctx, target, counters),
        TriShader::Phong(s) => phong::<T, false>(tri, s, ctx, target, counters),
    }
}

/// Whether the plan shades its material physically (the model view's
/// metallic-roughness materials).
fn physical(ctx: &ShadeCtx) -> bool {
    let plan = ctx.plan;
    plan.physical.is_some() && plan.terms.as_ref().is_some_and(|t| t.pbr.is_some())
}

/// A metallic-roughness triangle, with or without its colour texture and
/// normal map.
fn draw_physical<T: RasterTarget>(
    tri: &ScreenTri,
    s: &PhongTri,
    ctx: &ShadeCtx,
    target: &mut T,
    counters: &mut Counters,
) {
    with_pbr_kernel!(ctx, s, |k| target.raster(tri, &k, ctx, counters));
}

/// `$body` with `$k` the Phong kernel of triangle `$s` under `$ctx`'s plan,
/// with Blinn's bump when `$bump`, in the variant its colour texture and
/// the plan's highlights choose. The kernel is made per triangle: Blinn's
/// axes of a flat facet once.
macro_rules! with_phong_kernel {
    ($ctx:expr, $s:expr, $bump:tt, |$k:ident| $body:expr) => {{
        let s: &PhongTri = $s;
        let k = $ctx.plan.bump_strength;
        match (s.textured, $ctx.plan.specular.is_some()) {
            (true, true) => {
                let $k = PhongKernel::<true, $bump, true>::new(s, k);
                $body
            }
            (true, false) => {
                let $k = PhongKernel::<true, $bump, false>::new(s, k);
                $body
            }
            (false, true) => {
                let $k = PhongKernel::<false, $bump, true>::new(s, k);
                $body
            }
            (false, false) => {
                let $k = PhongKernel::<false, $bump, false>::new(s, k);
                $body
            }
        }
    }};
}

/// Plain Phong (`BUMP` false) or Blinn's bump, with or without its colour
/// texture and highlights.
fn phong<T: RasterTarget, const BUMP: bool>(
    tri: &ScreenTri,
    s: &PhongTri,
    ctx: &ShadeCtx,
    target: &mut T,
    counters: &mut Counters,
) {
    with_phong_kernel!(ctx, s, BUMP, |k| target.raster(tri, &k, ctx, counters))
}

/// A bumped Phong triangle, drawn with the plan's technique: the shading
/// core (`shade::core`) with the technique's hook, eight pixels at a time
/// where the rasterizer can. A new technique is one arm.
fn draw_bumped<T: RasterTarget>(
    tri: &ScreenTri,
    s: &PhongTri,
    ctx: &ShadeCtx,
    target: &mut T,
    counters: &mut Counters,
) {
    let plan = ctx.plan;
    let eye = plan.eye;
    match (plan.technique, plan.normal_map.as_deref()) {
        (Technique::Emboss, _) => with_hook(tri, s, Emboss::new(ctx), ctx, target, counters),
        (Technique::Dot3, Some(map)) => match plan.light_vector {
            LightVector::Pixel => {
                let hook = Dot3::<true>::new(s, map, ctx);
                with_hook(tri, s, hook, ctx, target, counters)
            }
            LightVector::Vertex => {
                let hook = Dot3::<false>::new(s, map, ctx);
                with_hook(tri, s, hook, ctx, target, counters)
            }
        },
        (Technique::Parallax, _) => {
            with_hook(tri, s, Parallax::<false> { eye }, ctx, target, counters)
        }
        (Technique::Pom, _) => with_hook(tri, s, Parallax::<true> { eye }, ctx, target, counters),
        // Blinn, and dot3 without its map (the plan builds one whenever dot3
        // runs): the packet kernel.
        (Technique::Blinn | Technique::Dot3, _) => phong::<T, true>(tri, s, ctx, target, counters),
    }
}

/// A bumped triangle through the shading core with the technique `hook`:
/// with or without its colour texture and highlights.
fn with_hook<T: RasterTarget, H: Hook>(
    tri: &ScreenTri,
    s: &PhongTri,
    hook: H,
    ctx: &ShadeCtx,
    target: &mut T,
    counters: &mut Counters,
) {
    let kernel = HookKernel {
        tri: s,
        hook,
        textured: s.textured,
        specular: ctx.plan.specular.is_some(),
    };
    target.raster(tri, &kernel, ctx, counters)
}

/// Shades the first packet of a band's deferred pixels (eight, or the
/// last few) with the kernel of their kind under `ctx`, the context of
/// their material, and writes them (`raster::pending`).
pub(crate) fn shade_pending(
    q: &mut PendingTarget,
    shaders: &[TriShader],
    ctx: &ShadeCtx,
    counters: &mut Counters,
) {
    let pixels = q.pending.packet();
    let phong = |k: u32| match &shaders[k as usize] {
        TriShader::Phong(s) => Some(s),
        _ => None,
    };
    let tris = pixels.first().and_then(|first| {
        let mut tris = [phong(first.shader)?; LANES];
        for (t, p) in tris.iter_mut().zip(pixels) {
            *t = phong(p.shader)?;
        }
        Some(tris)
    });
    let lane = |k: usize| {
        f32x8::from(std::array::from_fn(|i| {
            pixels.get(i).map_or(0.0, |p| p.b[k])
        }))
    };
    let b = [lane(0), lane(1), lane(2)];
    let fp: [Footprint; LANES] =
        std::array::from_fn(|i| pixels.get(i).map_or_else(Footprint::default, |p| p.fp));
    let live = (1u32 << pixels.len()) - 1;
    if let Some(colours) = tris.and_then(|t| shade_each(ctx, &t, b, &fp, live, counters)) {
        write_packet(pixels, &colours, q.color, q.depth);
        counters.packet_pixels += pixels.len() as u64;
    }
    q.pending.drop_packet();
}

/// Eight pixels of triangles `tris` of one kind (see `PbrKernel::kind`
/// and `PhongKernel::defers`), each on its own triangle: the
/// metallic-roughness kernel where the plan shades physically (as
/// `draw_into` chooses), else the Phong kernel without bump.
fn shade_each(
    ctx: &ShadeCtx,
    tris: &[&PhongTri; LANES],
    b: [f32x8; 3],
    fp: &[Footprint; LANES],
    live: u32,
    counters: &mut Counters,
) -> Option<[Rgb; LANES]> {
    if physical(ctx) {
        return with_pbr_kernel!(ctx, tris[0], |k| k.shade_each(
            ctx,
            (tris, b),
            fp,
            live,
            counters
        ));
    }
    Some(with_phong_kernel!(ctx, tris[0], false, |k| k.shade_each(
        ctx,
        (tris, b),
        fp,
        live,
        counters
    )))
}
