//! Environment mapping (docs/environment.md): the surface mirrors the
//! environment in R = 2(N·V)N − V, V the unit vector toward the eye and N the
//! final (bumped) normal, all in world space, so the environment stays put
//! while the model turns. The lit colour and the reflection are mixed:
//! c = (1 − k)·lit + k·env(R), k the plan's reflectivity.
//!
//! The one-pixel and eight-pixel forms do the same operations in the same
//! order (packets stay bit for bit equal to the one-pixel kernels); the
//! environment is read lane by lane with the one-pixel lookup.

use glam::Vec3;
use wide::f32x8;

use super::packet::{LANES, V3};
use super::specular::{view_dir, view_dir8};
use crate::plan::Plan;
use crate::stats::Counters;

/// The mirror direction of the unit `view` (toward the eye) about the unit
/// normal `n`: reflect(−V, N) = 2(N·V)N − V.
#[inline]
pub fn reflect(view: Vec3, n: Vec3) -> Vec3 {
    n * (2.0 * n.dot(view)) - view
}

/// `lit` with the plan's environment mixed in at the point `p` of normal
/// `n`; `lit` itself when the plan has no environment.
#[inline(always)]
pub fn mirror(plan: &Plan, p: Vec3, n: Vec3, lit: Vec3, counters: &mut Counters) -> Vec3 {
    let Some(env) = &plan.environment else {
        return lit;
    };
    counters.env_lookups += 1;
    let r = reflect(view_dir(plan.eye, p), n);
    let k = env.reflectivity;
    lit * (1.0 - k) + env.map.lookup(r) * k
}

/// `reflect` at eight points.
#[inline(always)]
pub fn reflect8(view: V3, n: V3) -> V3 {
    n.scale(f32x8::splat(2.0) * n.dot(view)).minus(view)
}

/// `mirror` at eight points (`live` has a bit per covered lane: only those
/// are read and counted).
#[inline(always)]
pub fn mirror8(plan: &Plan, p: V3, n: V3, lit: V3, live: u32, counters: &mut Counters) -> V3 {
    let Some(env) = &plan.environment else {
        return lit;
    };
    counters.env_lookups += live.count_ones() as u64;
    let r = reflect8(view_dir8(plan.eye, p), n);
    let (x, y, z) = (r.x.to_array(), r.y.to_array(), r.z.to_array());
    let mut seen = [[0.0f32; LANES]; 3];
    for lane in (0..LANES).filter(|l| live & (1 << l) != 0) {
        let c = env.map.lookup(Vec3::new(x[lane], y[lane], z[lane]));
        (seen[0][lane], seen[1][lane], seen[2][lane]) = (c.x, c.y, c.z);
    }
    let [x, y, z] = seen.map(f32x8::from);
    let k = env.reflectivity;
    lit.scale(f32x8::splat(1.0 - k))
        .plus(V3 { x, y, z }.scale(f32x8::splat(k)))
}
