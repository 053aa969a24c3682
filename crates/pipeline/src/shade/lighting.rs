//! Diffuse lighting: ambient + Σ colour · max(0, N·L); with highlights,
//! also Σ colour · (N·H)^s (docs/specular.md).

use glam::Vec3;

use super::brdf::saturate;
use super::lanes::{Lanes, Vector};
use super::specular::blinn_phong;
use crate::plan::{ActiveLight, Plan};
use relief_core::stats::Counters;
use relief_scene::light::Falloff;

/// Distance attenuation 1 / (1 + c·d²); c keeps the reference scene readable
/// (about 0.6 at the white light's distance).
pub const ATTENUATION_QUADRATIC: f32 = 0.01;

/// The share of a glTF light's intensity that reaches a point `d` from it
/// (`len2` = |d|²): 1 / d², brought to zero at its range by
/// (1 − (d / range)⁴) clamped to 0…1, times a spot's cone t², t = cos θ ·
/// scale + offset clamped to 0…1 (KHR_lights_punctual's recommended
/// falloff). 1 for any other light (the caller applies the setting's).
#[inline(always)]
pub fn physical_falloff<V: Vector>(falloff: Falloff, d: V, len2: V::L) -> V::L {
    let Falloff::InverseSquare { range, cone } = falloff else {
        return V::L::ONE;
    };
    let mut fall = V::L::ONE / len2;
    if range.is_finite() {
        let x = len2 * V::L::splat(1.0 / (range * range));
        fall = fall * saturate(V::L::ONE - x * x);
    }
    if let Some(cone) = cone {
        // d runs from the point to the light: the light shines along −d.
        let cos = (V::L::ZERO - d.dot(V::uniform(cone.axis))) / len2.sqrt();
        let t = saturate(cos * V::L::splat(cone.scale) + V::L::splat(cone.offset));
        fall = fall * t * t;
    }
    fall
}

/// The light reaching a point `p` with unit normal `n` (RGB, not clamped),
/// at one point or eight (no shadows, nothing counted).
/// A light exactly at `p` (distance 0) has no direction and adds nothing.
#[inline(always)]
pub fn diffuse<V: Vector>(
    lights: &[ActiveLight],
    ambient: Vec3,
    p: V,
    n: V,
    attenuation: bool,
) -> V {
    let set = LightSet {
        lights,
        ambient,
        attenuation,
        shininess: 0.0,
    };
    let mut unused = Counters::default();
    light_lanes::<V, false>(
        &set,
        p,
        n,
        V::uniform(Vec3::ZERO),
        |_, d, _| facing_cosine(n, d),
        |_, _, _| V::L::ONE,
        &mut unused,
    )
    .0
}

/// The lights of a frame as the light loop reads them.
#[derive(Clone, Copy)]
pub struct LightSet<'a> {
    pub lights: &'a [ActiveLight],
    pub ambient: Vec3,
    /// Distance attenuation on.
    pub attenuation: bool,
    /// The exponent s of (N·H)^s (read only with highlights).
    pub shininess: f32,
}

impl<'a> LightSet<'a> {
    #[inline]
    pub fn of(plan: &'a Plan) -> Self {
        LightSet {
            lights: &plan.lights,
            ambient: plan.ambient,
            attenuation: plan.attenuation,
            shininess: plan.specular.as_ref().map_or(0.0, |s| s.shininess),
        }
    }
}

/// Lambert's cosine N·L for a light `d` away, or 0 where the light is
/// behind (as `facing_cosine`, for one point).
#[inline(always)]
pub fn lambert(n: Vec3, d: Vec3) -> f32 {
    facing_cosine(n, d).unwrap_or(0.0)
}

/// Lambert's cosine at one point or eight: `None` where the light is
/// behind every lane, else N·L in the lanes it faces and a value ≤ 0 (or
/// NaN) in the others. The sign is tested before normalising, so most
/// back-lit points (and packets) stop at one dot product. (A zero or
/// non-finite `d` gives 0 or NaN, which the light loop skips.)
#[inline(always)]
pub fn facing_cosine<V: Vector>(n: V, d: V) -> Option<V::L> {
    let ndl = n.dot(d);
    if V::L::none(ndl.gt(V::L::ZERO)) {
        return None;
    }
    Some(ndl / d.dot(d).sqrt())
}

/// The one light loop, for every kernel: ambient plus, for each light that
/// reaches `p`, its colour × cosine (clamped to 1), and when `SPEC` the
/// Blinn-Phong highlight (N·H)^s of the normal `n` seen from the unit
/// direction `view` (docs/specular.md). `cosine(i, d, counters)` is
/// the technique's N·L for light `i` at `d` = light − p: Lambert's for
/// most, emboss and dot3 have their own. A light adds only
/// where its cosine is positive, both terms scaled by the same attenuation
/// and by `visibility(i)` (its shadow, asked once). Counts one light
/// evaluation per light, and one highlight per light with `SPEC`.
#[inline(always)]
pub fn light_with<const SPEC: bool>(
    set: &LightSet,
    p: Vec3,
    n: Vec3,
    view: Vec3,
    mut cosine: impl FnMut(usize, Vec3, &mut Counters) -> f32,
    mut visibility: impl FnMut(usize, &mut Counters) -> f32,
    counters: &mut Counters,
) -> (Vec3, Vec3) {
    counters.light_evals += set.lights.len() as u64;
    if SPEC {
        counters.specular_evals += set.lights.len() as u64;
    }
    let cosine = |i, d, counters: &mut Counters| Some(cosine(i, d, counters));
    let visibility = |i, _reached: bool, counters: &mut Counters| visibility(i, counters);
    light_lanes::<Vec3, SPEC>(set, p, n, view, cosine, visibility, counters)
}

/// `light_with` at one point or eight (`V`), without its counts (a packet
/// counts its live lanes). `cosine` gives `None` when light `i` is behind
/// every lane (see `facing_cosine`). `visibility(i, reached, counters)` is asked once
/// per light that reaches some lane, with the mask of the lanes it reaches.
#[inline(always)]
pub fn light_lanes<V: Vector, const SPEC: bool>(
    set: &LightSet,
    p: V,
    n: V,
    view: V,
    mut cosine: impl FnMut(usize, V, &mut Counters) -> Option<V::L>,
    mut visibility: impl FnMut(usize, <V::L as Lanes>::Mask, &mut Counters) -> V::L,
    counters: &mut Counters,
) -> (V, V) {
    let zero = V::L::ZERO;
    let mut sum = V::uniform(set.ambient);
    let mut highlight = V::uniform(Vec3::ZERO);
    for (i, light) in set.lights.iter().enumerate() {
        let d = V::uniform(light.position) - p;
        let Some(mut k) = cosine(i, d, counters) else {
            continue;
        };
        // A light at the point, or out of range, has no direction: nothing.
        let len2 = d.dot(d);
        let inf = V::L::splat(f32::INFINITY);
        let reached = V::L::both(k.gt(zero), || V::L::both(len2.gt(zero), || len2.lt(inf)));
        if V::L::skips(reached) {
            continue;
        }
        let mut ks = if SPEC {
            blinn_phong(n, d, len2, view, set.shininess)
        } else {
            zero
        };
        match light.falloff {
            Falloff::Setting if set.attenuation => {
                let fall = V::L::ONE + V::L::splat(ATTENUATION_QUADRATIC) * len2;
                k = k / fall;
                if SPEC {
                    ks = ks / fall;
                }
            }
            Falloff::Setting | Falloff::None => {}
            falloff @ Falloff::InverseSquare { .. } => {
                let fall = physical_falloff(falloff, d, len2);
                k = k * fall;
                if SPEC {
                    ks = ks * fall;
                }
            }
        }
        let seen = visibility(i, reached, counters);
        // A lane the light does not reach adds +0, which leaves its sum as it was.
        let color = V::uniform(light.color);
        sum = sum + color * V::L::select(reached, k.min(V::L::ONE) * seen, zero);
        if SPEC {
            highlight = highlight + color * V::L::select(reached, ks.min(V::L::ONE) * seen, zero);
        }
    }
    (sum, highlight)
}

/// Quantises a shaded colour, counting any non-finite one (tests assert
/// the count stays 0; the pixel still gets a defined value).
#[inline]
pub fn finish(c: Vec3, counters: &mut Counters) -> [u8; 3] {
    if !c.is_finite() {
        counters.nonfinite += 1;
    }
    to_rgb8(c)
}

/// Clamps to 0..1 and rounds to 8 bits. NaN becomes 0 (`max` drops NaN,
/// which `clamp` would keep).
#[inline]
pub fn to_rgb8(c: Vec3) -> [u8; 3] {
    #[allow(clippy::manual_clamp)]
    let q = |x: f32| (x.max(0.0).min(1.0) * 255.0 + 0.5) as u8;
    [q(c.x), q(c.y), q(c.z)]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn light(p: Vec3) -> ActiveLight {
        ActiveLight {
            position: p,
            color: Vec3::ONE,
            falloff: relief_scene::light::Falloff::Setting,
        }
    }

    use relief_scene::light::{Cone, Falloff};

    fn falloff_at(falloff: Falloff, d: Vec3) -> f32 {
        physical_falloff(falloff, d, d.dot(d))
    }

    #[test]
    fn a_point_light_falls_off_as_the_inverse_square_within_its_range() {
        let endless = Falloff::InverseSquare {
            range: f32::INFINITY,
            cone: None,
        };
        assert_eq!(falloff_at(endless, Vec3::new(0.0, 2.0, 0.0)), 0.25);
        // At half its range: 1 − (1/2)⁴ = 15/16 of 1/4.
        let ranged = Falloff::InverseSquare {
            range: 4.0,
            cone: None,
        };
        let half = falloff_at(ranged, Vec3::new(0.0, 0.0, 2.0));
        assert!((half - 15.0 / 64.0).abs() < 1e-6, "{half}");
        assert_eq!(falloff_at(ranged, Vec3::new(0.0, 0.0, 4.0)), 0.0);
        assert_eq!(falloff_at(ranged, Vec3::new(0.0, 5.0, 0.0)), 0.0);
        // Directional lights and the setting's lights are not changed here.
        assert_eq!(falloff_at(Falloff::None, Vec3::splat(3.0)), 1.0);
        assert_eq!(falloff_at(Falloff::Setting, Vec3::splat(3.0)), 1.0);
    }

    #[test]
    fn a_spot_lights_cone_is_full_inside_dark_outside_and_smooth_between() {
        // Pointing down −Z, inner 30°, outer 45°, the point 1 away (1/d² = 1).
        let spot = Falloff::InverseSquare {
            range: f32::INFINITY,
            cone: Some(Cone::new(
                Vec3::NEG_Z,
                30f32.to_radians(),
                45f32.to_radians(),
            )),
        };
        // d runs from the point to the light, which is above it.
        let at = |deg: f32| {
            let r = deg.to_radians();
            falloff_at(spot, -Vec3::new(r.sin(), 0.0, -r.cos()))
        };
        assert!((at(0.0) - 1.0).abs() < 1e-6);
        assert!((at(29.0) - 1.0).abs() < 1e-6);
        assert_eq!(at(46.0), 0.0);
        assert_eq!(at(90.0), 0.0);
        // 40°: t = (cos 40° − cos 45°) / (cos 30° − cos 45°) = 0.3708.
        let t = (40f32.to_radians().cos() - 45f32.to_radians().cos())
            / (30f32.to_radians().cos() - 45f32.to_radians().cos());
        assert!((t - 0.3708).abs() < 1e-3);
        assert!((at(40.0) - t * t).abs() < 1e-5, "{}", at(40.0));
        // Lanes give what one point gives.
        let d = -Vec3::new(40f32.to_radians().sin(), 0.0, -40f32.to_radians().cos());
        let v = <crate::shade::packet::V3 as Vector>::uniform(d);
        let lanes = physical_falloff(spot, v, v.dot(v)).to_array();
        assert!(lanes.iter().all(|&l| (l - t * t).abs() < 1e-5), "{lanes:?}");
    }

    #[test]
    fn head_on_light_gives_full_colour() {
        let l = [light(Vec3::new(0.0, 0.0, 10.0))];
        let c = diffuse(&l, Vec3::splat(0.1), Vec3::ZERO, Vec3::Z, false);
        assert!((c - Vec3::splat(1.1)).length() < 1e-6);
    }

    #[test]
    fn light_at_the_point_and_behind_adds_nothing() {
        let l = [light(Vec3::ZERO), light(Vec3::new(0.0, 0.0, -3.0))];
        assert_eq!(
            diffuse(&l, Vec3::ZERO, Vec3::ZERO, Vec3::Z, false),
            Vec3::ZERO
        );
    }

    #[test]
    fn grazing_light_is_zero_and_finite() {
        let l = [light(Vec3::new(5.0, 0.0, 0.0))];
        let c = diffuse(&l, Vec3::ZERO, Vec3::ZERO, Vec3::Z, false);
        assert_eq!(c, Vec3::ZERO);
    }

    #[test]
    fn quantisation_rounds_clamps_and_drops_nan() {
        assert_eq!(to_rgb8(Vec3::new(0.5, 2.0, -1.0)), [128, 255, 0]);
        assert_eq!(
            to_rgb8(Vec3::new(f32::NAN, f32::INFINITY, f32::NEG_INFINITY)),
            [0, 255, 0]
        );
    }
}
