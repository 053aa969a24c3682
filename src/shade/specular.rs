//! Blinn-Phong highlights (docs/specular.md): (N·H)^s with H the unit
//! half-vector between the light and the eye, scaled by a grey specular map.
//!
//! The one-pixel and eight-pixel forms do the same operations in the same
//! order, so packets stay bit for bit equal to the one-pixel kernels; the
//! power is taken lane by lane with the same `powf`.

use glam::{Vec2, Vec3};
use wide::f32x8;

use super::packet::{self, V3};
use crate::texture::Level;

/// The unit vector from `p` toward the eye (NaN when `p` is the eye: the
/// highlight then adds nothing).
#[inline]
pub fn view_dir(eye: Vec3, p: Vec3) -> Vec3 {
    let e = eye - p;
    e * (1.0 / e.dot(e).sqrt())
}

/// (N·H)^s for a light `d` away from the point (`len2` = |d|², > 0) and the
/// unit `view`; 0 where N·H ≤ 0 (or is NaN).
#[inline]
pub fn blinn_phong(n: Vec3, d: Vec3, len2: f32, view: Vec3, shininess: f32) -> f32 {
    let l = d * (1.0 / len2.sqrt());
    let h = l + view;
    let ndh = n.dot(h) / h.dot(h).sqrt();
    if ndh > 0.0 { ndh.powf(shininess) } else { 0.0 }
}

/// The specular map at `uv`: its bilinear grey value.
#[inline]
pub fn gloss(map: &Level, uv: Vec2) -> f32 {
    map.bilinear(uv.x, uv.y)[0]
}

/// `view_dir` at eight points.
#[inline(always)]
pub fn view_dir8(eye: Vec3, p: V3) -> V3 {
    let e = V3::splat(eye).minus(p);
    e.scale(f32x8::ONE / e.dot(e).sqrt())
}

/// `blinn_phong` at eight points (lanes a light does not reach are
/// computed and thrown away by the caller: testing each lane costs more
/// than the power it saves, callgrind says).
#[inline(always)]
pub fn blinn_phong8(n: V3, d: V3, len2: f32x8, view: V3, shininess: f32) -> f32x8 {
    let l = d.scale(f32x8::ONE / len2.sqrt());
    let h = l.plus(view);
    let ndh = (n.dot(h) / h.dot(h).sqrt()).to_array();
    f32x8::from(ndh.map(|c| if c > 0.0 { c.powf(shininess) } else { 0.0 }))
}

/// `gloss` at eight points (the packet bilinear read is the one-pixel one, lane-wise).
#[inline(always)]
pub fn gloss8(map: &Level, u: f32x8, v: f32x8) -> f32x8 {
    packet::bilinear::<true, false>(map, u, v).color.x
}
