//! Parallax mapping and parallax occlusion mapping (docs/bump-parallax.md): the texture
//! coordinate moves along the view direction in tangent space, as if the
//! height map were carved into the face.
//!
//! Height 1 is the polygon's surface and lower heights lie below it, down to
//! the depth D = k·|∂P/∂u × ∂P/∂v| at height 0: the displacement Blinn's k
//! stands for (its normal is the true normal of that relief, to first
//! order), so parallax shows the same relief that Blinn shades. At the
//! reference k and cube this is 0.012 of a face: about three texels of a
//! 256-texel map. Both techniques then light with Blinn's normal at the
//! displaced coordinate, and read the colour there.

use glam::{Vec2, Vec3};

use super::bump::blinn;
use super::core::{Hook, HookAt};
use super::kernels::ShadeCtx;
use super::tangent::Surface;
use crate::stats::Counters;
use crate::texture::filter::{Footprint, height_gradient, height_sampler};
use crate::texture::sampler::Sampler;

/// The view's normal component is clamped to this (about 84°) so grazing
/// views cannot throw the coordinate across the texture.
pub const MIN_VIEW_COSINE: f32 = 0.1;
/// Ray-march steps of parallax occlusion mapping, head-on and at grazing.
pub const POM_MIN_STEPS: u32 = 8;
pub const POM_MAX_STEPS: u32 = 32;

/// The view ray through one pixel, in texture terms: `shift` is how far the
/// texture coordinate moves when the ray sinks from height 1 to height 0,
/// and `cosine` the view's (clamped) normal component.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ViewRay {
    pub shift: Vec2,
    pub cosine: f32,
}

impl ViewRay {
    /// From the surface, the eye position and the relief depth D in world units.
    #[inline]
    pub fn new(s: &Surface, eye: Vec3, depth: f32) -> ViewRay {
        let frame = s.frame();
        let v = frame.to_tangent(eye - s.p).normalize_or(Vec3::Z);
        let cosine = v.z.max(MIN_VIEW_COSINE);
        // Sinking by D along −v moves D·v_T/v_N in the tangent plane; divide
        // by |∂P/∂u|, |∂P/∂v| to get texture coordinates.
        let shift = Vec2::new(-v.x / frame.len_u, -v.y / frame.len_v) * (depth / cosine);
        ViewRay { shift, cosine }
    }
}

/// Parallax mapping with scale and bias: uv + (h·s + b)·(−shift) with
/// s = 1, b = −1 in units of the full depth, i.e. uv + (1 − h)·shift, from
/// one read of `height(uv)`. A zero shift (zero depth) returns `uv` unchanged.
#[inline(always)]
pub fn parallax_offset(height: impl Fn(Vec2) -> f32, uv: Vec2, ray: &ViewRay) -> Vec2 {
    let h = height(uv);
    let (scale, bias) = (1.0, -1.0);
    uv - ray.shift * (h * scale + bias)
}

/// The displaced coordinate and the number of height reads: parallax's one
/// read, or occlusion mapping's march.
#[inline(always)]
fn offset<const OCCLUSION: bool>(
    height: impl Fn(Vec2) -> f32,
    uv: Vec2,
    ray: &ViewRay,
) -> (Vec2, u32) {
    if OCCLUSION {
        pom_offset(height, uv, ray)
    } else {
        (parallax_offset(height, uv, ray), 1)
    }
}

/// Steps for a view of this cosine: 8 head-on, up to 32 at grazing.
#[inline]
pub fn pom_steps(cosine: f32) -> u32 {
    let grazing = (1.0 - cosine).clamp(0.0, 1.0);
    POM_MIN_STEPS + ((POM_MAX_STEPS - POM_MIN_STEPS) as f32 * grazing).round() as u32
}

/// Parallax occlusion mapping: march the ray down through the height field
/// in equal depth steps until it is below the surface, then place the hit
/// by intersecting the two last segments linearly. Returns the coordinate
/// and the number of reads of `height`.
#[inline(always)]
pub fn pom_offset(height: impl Fn(Vec2) -> f32, uv: Vec2, ray: &ViewRay) -> (Vec2, u32) {
    let steps = pom_steps(ray.cosine);
    let dz = 1.0 / steps as f32;
    let step = ray.shift * dz;
    let mut reads = 1;
    // Depth below the surface: of the ray, and of the relief under it.
    let mut ray_depth = 0.0f32;
    let mut cur = uv;
    let mut relief = 1.0 - height(cur);
    if relief <= 0.0 {
        return (uv, reads);
    }
    for i in 1..=steps {
        let prev = (cur, ray_depth, relief);
        cur = uv + step * i as f32;
        ray_depth = dz * i as f32;
        relief = 1.0 - height(cur);
        reads += 1;
        if ray_depth >= relief {
            // Above by `a` at the previous step, below by `b` now.
            let a = prev.2 - prev.1;
            let b = ray_depth - relief;
            let t = if a + b > 0.0 { a / (a + b) } else { 0.0 };
            return (prev.0 + step * t, reads);
        }
    }
    // Unreachable for heights in 0..1 (the ray ends at depth 1); keep the last point.
    (cur, reads)
}

/// Parallax for the shading core (parallax occlusion mapping when
/// `OCCLUSION`): the texture coordinate moves along the view ray, and
/// Blinn's normal is read there.
pub struct Parallax<const OCCLUSION: bool> {
    /// The camera position in world space.
    pub eye: Vec3,
}

impl<const OCCLUSION: bool> Hook for Parallax<OCCLUSION> {
    type Pixel = ();
    #[inline(always)]
    fn at(
        &self,
        ctx: &ShadeCtx,
        s: &Surface,
        _b: Vec3,
        fp: Footprint,
        _colour: bool,
        counters: &mut Counters,
    ) -> (HookAt, ()) {
        let plan = ctx.plan;
        counters.bump_evals += 1;
        let k = plan.bump_strength;
        let depth = k * s.pu.cross(s.pv).length();
        // The relief is carved into the flat triangle being drawn: the ray
        // crosses it in the triangle's own plane. With vertex normals the
        // interpolated normal leans (a cube's is rounded toward its edges)
        // and would bend the texture on a flat face; it still lights.
        let plane = Surface { n: s.face_n, ..*s };
        let ray = ViewRay::new(&plane, self.eye, depth);
        // The heights are read like everything else: through the pixel's
        // sampler (the base level for bilinear, the footprint's level(s)
        // and taps for the mip filters with the filtered derivative).
        let tex = ctx.texture;
        let sampler = height_sampler(tex, plan.height_derivative, plan.filter, fp);
        let (uv, reads) = if sampler == Sampler::BASE {
            // The common case, read straight from the base level.
            let base = tex.base();
            offset::<OCCLUSION>(
                #[inline(always)]
                |p| base.bilinear_height(p.x, p.y),
                s.uv,
                &ray,
            )
        } else {
            let height = |p: Vec2| sampler.read(p, |i, q| tex.level(i).bilinear_height(q.x, q.y));
            offset::<OCCLUSION>(height, s.uv, &ray)
        };
        counters.texture_samples += reads as u64;
        let (fu, fv) = height_gradient(ctx.texture, plan.height_derivative, plan.filter, uv, fp);
        let at = HookAt {
            uv,
            n: blinn(s.n, s.pu, s.pv, fu, fv, k),
            texel: None,
        };
        (at, ())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::texture::Level;

    fn surface() -> Surface {
        Surface {
            p: Vec3::ZERO,
            n: Vec3::Z,
            face_n: Vec3::Z,
            albedo: Vec3::ONE,
            uv: Vec2::new(0.5, 0.5),
            pu: 2.0 * Vec3::X,
            pv: 2.0 * Vec3::Y,
        }
    }

    fn heights(level: &Level) -> impl Fn(Vec2) -> f32 + '_ {
        |p| level.bilinear_height(p.x, p.y)
    }

    fn ramp() -> Level {
        let mut level = Level::solid(64, 64, [0.5; 4]);
        for (i, t) in level.texels.iter_mut().enumerate() {
            t[3] = (i % 64) as f32 / 64.0;
        }
        level
    }

    #[test]
    fn zero_depth_changes_nothing() {
        let eye = Vec3::new(3.0, -2.0, 1.0);
        let ray = ViewRay::new(&surface(), eye, 0.0);
        assert_eq!(ray.shift, Vec2::ZERO);
        let level = ramp();
        let uv = Vec2::new(0.3, 0.7);
        assert_eq!(parallax_offset(heights(&level), uv, &ray), uv);
        assert_eq!(pom_offset(heights(&level), uv, &ray).0, uv);
    }

    #[test]
    fn a_recessed_point_seen_from_plus_u_moves_toward_minus_u() {
        // Eye toward +X (+u): the ray sinking into the face travels toward −u.
        let ray = ViewRay::new(&surface(), Vec3::new(5.0, 0.0, 5.0), 0.1);
        assert!(ray.shift.x < 0.0 && ray.shift.y == 0.0);
        // 45°: sinking by D = 0.1 world moves 0.1 world = 0.05 of the face.
        assert!((ray.shift.x + 0.05).abs() < 1e-6, "{:?}", ray.shift);
        let level = Level::solid(4, 4, [0.5, 0.5, 0.5, 0.25]);
        let uv = Vec2::new(0.5, 0.5);
        let p = parallax_offset(heights(&level), uv, &ray);
        assert!((p.x - (0.5 - 0.75 * 0.05)).abs() < 1e-6, "{p}");
        // A flat floor at depth 0.75: POM finds exactly the same point.
        let (q, reads) = pom_offset(heights(&level), uv, &ray);
        assert!((q - p).length() < 1e-6, "{q} vs {p}");
        assert!(reads >= 2);
    }

    #[test]
    fn step_count_adapts_to_the_view() {
        assert_eq!(pom_steps(1.0), POM_MIN_STEPS);
        assert_eq!(pom_steps(0.0), POM_MAX_STEPS);
        assert!(pom_steps(0.5) > POM_MIN_STEPS && pom_steps(0.5) < POM_MAX_STEPS);
        assert_eq!(pom_steps(f32::NAN), POM_MIN_STEPS);
    }

    #[test]
    fn grazing_and_bad_input_stay_finite() {
        let level = ramp();
        for eye in [
            Vec3::new(100.0, 0.0, 0.0),
            Vec3::new(0.0, 5.0, -5.0),
            Vec3::ZERO,
            Vec3::NAN,
        ] {
            let ray = ViewRay::new(&surface(), eye, 0.5);
            let (q, _) = pom_offset(heights(&level), Vec2::new(0.2, 0.9), &ray);
            let p = parallax_offset(heights(&level), Vec2::new(0.2, 0.9), &ray);
            assert!(q.is_finite() && p.is_finite(), "{eye}: {q} {p}");
        }
    }
}
