//! Latitude–longitude (equirectangular) coordinates of directions, the
//! layout of every environment (docs/environment.md).

use std::f32::consts::{PI, TAU};

use glam::{Vec2, Vec3};

/// The latitude–longitude coordinates of direction `d`: u in [0, 1] (0 and
/// 1 are the same meridian, +Z), v in [0, 1] (0 straight up). Never NaN: a
/// pole has any u, and a zero or non-finite `d` maps to the front (1/2, 1/2).
#[inline]
pub fn lat_long(d: Vec3) -> Vec2 {
    let len = d.length();
    if !(len > 0.0 && len.is_finite()) {
        return Vec2::splat(0.5);
    }
    let u = 0.5 + d.x.atan2(-d.z) / TAU;
    let v = (d.y / len).clamp(-1.0, 1.0).acos() / PI;
    Vec2::new(u, v)
}

/// The unit direction at latitude–longitude coordinates `uv` (the inverse
/// of [`lat_long`]).
#[inline]
pub fn direction(uv: Vec2) -> Vec3 {
    let phi = (uv.x - 0.5) * TAU;
    let theta = uv.y * PI;
    let (sin_t, cos_t) = theta.sin_cos();
    let (sin_p, cos_p) = phi.sin_cos();
    Vec3::new(sin_t * sin_p, cos_t, -sin_t * cos_p)
}
