//! Environment mapping (docs/environment.md): the surface mirrors the
//! environment in R = 2(N·V)N − V, V the unit vector toward the eye and N the
//! final (bumped) normal, all in world space, so the environment stays put
//! while the model turns. The lit colour and the reflection are mixed:
//! c = (1 − k)·lit + k·env(R), k the plan's reflectivity.
//!
//! Written once for one point or eight (`shade::lanes`), so packets stay bit
//! for bit equal to the one-pixel kernels; the environment is read lane by
//! lane with the one-pixel lookup.

use super::lanes::{Lanes, Vector};
use super::specular::view_dir;
use crate::plan::Plan;
use relief_core::stats::Counters;

/// The mirror direction of the unit `view` (toward the eye) about the unit
/// normal `n`: reflect(−V, N) = 2(N·V)N − V.
#[inline(always)]
pub fn reflect<V: Vector>(view: V, n: V) -> V {
    n * (V::L::splat(2.0) * n.dot(view)) - view
}

/// `lit` with the plan's environment mixed in at the point(s) `p` of normal
/// `n`; `lit` itself when the plan has no environment. `live` has a bit per
/// covered lane: only those are read and counted (1 for one pixel).
#[inline(always)]
pub fn mirror<V: Vector>(plan: &Plan, p: V, n: V, lit: V, live: u32, counters: &mut Counters) -> V {
    let Some(env) = &plan.environment else {
        return lit;
    };
    counters.env_lookups += live.count_ones() as u64;
    let r = reflect(view_dir(plan.eye, p), n);
    let k = env.reflectivity;
    let seen = r.each_live(live, |r| env.map.lookup(r));
    lit * V::L::splat(1.0 - k) + seen * V::L::splat(k)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn reflection_of_a_head_on_view_is_the_view() {
        assert_eq!(reflect(Vec3::Z, Vec3::Z), Vec3::Z);
    }

    #[test]
    fn reflection_keeps_the_normal_part_and_flips_the_rest() {
        // 45° onto the +Z plane: the tangent part flips, the normal part stays.
        let v = Vec3::new(1.0, 0.0, 1.0).normalize();
        let r = reflect(v, Vec3::Z);
        assert!((r - Vec3::new(-v.x, 0.0, v.z)).length() < 1e-6, "{r}");
    }
}
