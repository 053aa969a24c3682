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
use super::core::{Hook, HookAt, Pixels, gradient};
use super::lanes::{Lanes, Vector};
use super::shader::ShadeCtx;
use super::tangent::Surface;
use relief_core::stats::Counters;
use relief_texture::sample::filter::height_sampler;
use relief_texture::sample::sampler::Sampler;

/// The view's normal component is clamped to this (about 84°) so grazing
/// views cannot throw the coordinate across the texture.
pub const MIN_VIEW_COSINE: f32 = 0.1;
/// Ray-march steps of parallax occlusion mapping, head-on and at grazing.
pub const POM_MIN_STEPS: u32 = 8;
pub const POM_MAX_STEPS: u32 = 32;

/// The view ray through one pixel (or eight), in texture terms: `shift` is
/// how far the texture coordinate moves when the ray sinks from height 1
/// to height 0, and `cosine` the view's (clamped) normal component.
#[derive(Clone, Copy, Debug)]
pub struct ViewRay<L: Lanes = f32> {
    pub shift: (L, L),
    pub cosine: L,
}

impl<L: Lanes> ViewRay<L> {
    /// From the surface, the eye position and the relief depth D in world units.
    #[inline(always)]
    pub fn new<V: Vector<L = L>>(s: &Surface<V>, eye: Vec3, depth: L) -> ViewRay<L> {
        let frame = s.frame();
        let v = frame
            .to_tangent(V::uniform(eye) - s.p)
            .normalize_or(V::uniform(Vec3::Z));
        // f32::max(v_N, the minimum): NaN gives the minimum.
        let least = L::splat(MIN_VIEW_COSINE);
        let cosine = L::select(v.z().gt(least), v.z(), least);
        // Sinking by D along −v moves D·v_T/v_N in the tangent plane; divide
        // by |∂P/∂u|, |∂P/∂v| to get texture coordinates.
        let scale = depth / cosine;
        let shift = (
            (-v.x() / frame.len_u) * scale,
            (-v.y() / frame.len_v) * scale,
        );
        ViewRay { shift, cosine }
    }

    /// The ray of lane `i`.
    #[inline(always)]
    pub fn lane(&self, i: usize) -> ViewRay {
        ViewRay {
            shift: (self.shift.0.lane(i), self.shift.1.lane(i)),
            cosine: self.cosine.lane(i),
        }
    }
}

/// Parallax mapping with scale and bias: uv + (h·s + b)·(−shift) with
/// s = 1, b = −1 in units of the full depth, i.e. uv + (1 − h)·shift, from
/// the height `h` read at `uv`. A zero shift (zero depth) returns `uv`
/// unchanged.
#[inline(always)]
pub fn parallax_offset<L: Lanes>(h: L, (u, v): (L, L), ray: &ViewRay<L>) -> (L, L) {
    let (scale, bias) = (L::ONE, L::splat(-1.0));
    let f = h * scale + bias;
    (u - ray.shift.0 * f, v - ray.shift.1 * f)
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
/// and the number of reads of `height`. (One pixel at a time: each pixel's
/// march has its own length; a packet marches lane by lane.)
#[inline(always)]
pub fn pom_offset(height: impl Fn(Vec2) -> f32, uv: Vec2, ray: &ViewRay) -> (Vec2, u32) {
    let steps = pom_steps(ray.cosine);
    let dz = 1.0 / steps as f32;
    let step = Vec2::new(ray.shift.0, ray.shift.1) * dz;
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

/// The height map read like everything else at a pixel of footprint
/// `fp`: through the pixel's sampler (the base level for bilinear, the
/// footprint's level(s) and taps for the mip filters with the filtered
/// derivative). `march` is given the read, compiled once per kind.
macro_rules! with_heights {
    ($ctx:expr, $fp:expr, $height:ident => $march:expr) => {{
        let plan = $ctx.plan;
        let tex = $ctx.texture;
        let sampler = height_sampler(tex, plan.height_derivative, plan.filter, $fp);
        if sampler == Sampler::BASE {
            // The common case, read straight from the base level.
            let base = tex.base();
            let $height = |p: Vec2| base.bilinear_height(p.x, p.y);
            $march
        } else {
            let $height = |p: Vec2| sampler.read(p, |i, q| tex.level(i).bilinear_height(q.x, q.y));
            $march
        }
    }};
}

/// Parallax for the shading core (parallax occlusion mapping when
/// `OCCLUSION`): the texture coordinate moves along the view ray, and
/// Blinn's normal is read there.
pub struct Parallax<const OCCLUSION: bool> {
    /// The camera position in world space.
    pub eye: Vec3,
}

impl<const OCCLUSION: bool> Hook for Parallax<OCCLUSION> {
    type Pixel<V: Vector> = ();
    #[inline(always)]
    fn at<V: Vector>(
        &self,
        ctx: &ShadeCtx,
        px: &Pixels<V>,
        _colour: bool,
        counters: &mut Counters,
    ) -> (HookAt<V>, ()) {
        let plan = ctx.plan;
        let s = &px.s;
        counters.bump_evals += px.count();
        let k = plan.bump_strength;
        let axes = s.pu.cross(s.pv);
        let depth = V::L::splat(k) * axes.dot(axes).sqrt();
        // The relief is carved into the flat triangle being drawn: the ray
        // crosses it in the triangle's own plane. With vertex normals the
        // interpolated normal leans (a cube's is rounded toward its edges)
        // and would bend the texture on a flat face; it still lights.
        let plane = Surface {
            n: V::uniform(s.face_n),
            ..*s
        };
        let ray = ViewRay::new(&plane, self.eye, depth);
        let (u, v) = if OCCLUSION {
            let [u, v, reads] = V::L::gather(px.live, 0.0, |i| {
                let (uv, reads) = with_heights!(ctx, px.fp[i], height => {
                    pom_offset(height, px.uv(i), &ray.lane(i))
                });
                [uv.x, uv.y, reads as f32]
            });
            counters.texture_samples += (0..V::WIDTH).map(|i| reads.lane(i) as u64).sum::<u64>();
            (u, v)
        } else {
            let [h] = V::L::gather(px.live, 0.0, |i| {
                [with_heights!(ctx, px.fp[i], height => height(px.uv(i)))]
            });
            counters.texture_samples += px.count();
            parallax_offset(h, (s.u, s.v), &ray)
        };
        let (fu, fv) = gradient(ctx, u, v, px.fp, px.live);
        let at = HookAt {
            u,
            v,
            n: blinn(s.n, s.pu, s.pv, fu, fv, k),
            texel: None,
        };
        (at, ())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use relief_texture::Level;

    fn surface() -> Surface {
        Surface {
            p: Vec3::ZERO,
            n: Vec3::Z,
            face_n: Vec3::Z,
            albedo: Vec3::ONE,
            u: 0.5,
            v: 0.5,
            pu: 2.0 * Vec3::X,
            pv: 2.0 * Vec3::Y,
        }
    }

    fn heights(level: &Level) -> impl Fn(Vec2) -> f32 + '_ {
        |p| level.bilinear_height(p.x, p.y)
    }

    /// Parallax's one read of `level` at `uv`, and its offset.
    fn parallax(level: &Level, uv: Vec2, ray: &ViewRay) -> Vec2 {
        let h = level.bilinear_height(uv.x, uv.y);
        let (u, v) = parallax_offset(h, (uv.x, uv.y), ray);
        Vec2::new(u, v)
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
        assert_eq!(ray.shift, (0.0, 0.0));
        let level = ramp();
        let uv = Vec2::new(0.3, 0.7);
        assert_eq!(parallax(&level, uv, &ray), uv);
        assert_eq!(pom_offset(heights(&level), uv, &ray).0, uv);
    }

    #[test]
    fn a_recessed_point_seen_from_plus_u_moves_toward_minus_u() {
        // Eye toward +X (+u): the ray sinking into the face travels toward −u.
        let ray = ViewRay::new(&surface(), Vec3::new(5.0, 0.0, 5.0), 0.1);
        assert!(ray.shift.0 < 0.0 && ray.shift.1 == 0.0);
        // 45°: sinking by D = 0.1 world moves 0.1 world = 0.05 of the face.
        assert!((ray.shift.0 + 0.05).abs() < 1e-6, "{:?}", ray.shift);
        let level = Level::solid(4, 4, [0.5, 0.5, 0.5, 0.25]);
        let uv = Vec2::new(0.5, 0.5);
        let p = parallax(&level, uv, &ray);
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
            let p = parallax(&level, Vec2::new(0.2, 0.9), &ray);
            assert!(q.is_finite() && p.is_finite(), "{eye}: {q} {p}");
        }
    }
}
