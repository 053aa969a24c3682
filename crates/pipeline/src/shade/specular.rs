//! Blinn-Phong highlights (docs/specular.md): (N·H)^s with H the unit
//! half-vector between the light and the eye, scaled by a grey specular map.
//!
//! Written once for one point or eight (`shade::lanes`), so packets stay bit
//! for bit equal to the one-pixel kernels; the power is taken lane by lane
//! with the same `powf`, and the specular map read lane by lane.

use glam::Vec3;

use super::lanes::{Lanes, Vector};
use relief_texture::Level;

/// The unit vector from `p` toward the eye (NaN when `p` is the eye: the
/// highlight then adds nothing).
#[inline(always)]
pub fn view_dir<V: Vector>(eye: Vec3, p: V) -> V {
    let e = V::uniform(eye) - p;
    e * (V::L::ONE / e.dot(e).sqrt())
}

/// (N·H)^s for a light `d` away from the point (`len2` = |d|², > 0) and the
/// unit `view`; 0 where N·H ≤ 0 (or is NaN). (Packet lanes a light does
/// not reach are computed and thrown away by the caller: testing each lane
/// costs more than the power it saves, callgrind says.)
#[inline(always)]
pub fn blinn_phong<V: Vector>(n: V, d: V, len2: V::L, view: V, shininess: f32) -> V::L {
    let l = d * (V::L::ONE / len2.sqrt());
    let h = l + view;
    let ndh = n.dot(h) / h.dot(h).sqrt();
    ndh.pow_positive(shininess)
}

/// The specular map at (u, v): its bilinear grey value, at one point or
/// eight.
#[inline(always)]
pub fn gloss<L: Lanes>(map: &Level, u: L, v: L) -> L {
    L::bilinear(map, u, v)[0]
}
