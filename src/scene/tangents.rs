//! Tangent frames: ∂P/∂u and ∂P/∂v per face from positions and UVs, then
//! accumulated per vertex and renormalised (docs/bump-dot3.md, from [004] §III-C).
//!
//! Both axes are kept, never rebuilt as N × T, so mirrored UVs keep their
//! handedness: a face whose texture is flipped gets Pu × Pv pointing inward,
//! and the bump built from Pu and Pv tilts the right way on it.

use glam::{Vec2, Vec3};
use rayon::prelude::*;

use super::mesh::{Mesh, any_perpendicular, triangle_tangents};

/// The texture axes of one face.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FaceFrame {
    /// ∂P/∂u, in model units per unit of u.
    pub tangent_u: Vec3,
    /// ∂P/∂v.
    pub tangent_v: Vec3,
    /// False when the UVs were degenerate (zero determinant) and the frame
    /// was made up from the normal alone.
    pub from_uv: bool,
}

impl FaceFrame {
    /// +1 for a right-handed frame (Pu × Pv along the normal), −1 for mirrored UVs.
    pub fn handedness(&self, normal: Vec3) -> f32 {
        if self.tangent_u.cross(self.tangent_v).dot(normal) < 0.0 {
            -1.0
        } else {
            1.0
        }
    }
}

/// A unit frame in the plane perpendicular to `normal`, right-handed
/// (tangent_u × tangent_v = normal): what a face or vertex gets when its UVs
/// say nothing.
pub fn frame_from_normal(normal: Vec3) -> FaceFrame {
    let n = normal.normalize_or(Vec3::Z);
    let tangent_u = any_perpendicular(n);
    FaceFrame {
        tangent_u,
        tangent_v: n.cross(tangent_u),
        from_uv: false,
    }
}

/// The frame of one triangle: ∂P/∂u, ∂P/∂v from its UVs, or, when the UV
/// determinant is zero, a unit frame built from the face normal.
pub fn face_frame(p: [Vec3; 3], uv: [Vec2; 3], normal: Vec3) -> FaceFrame {
    match triangle_tangents(p, uv) {
        Some((tangent_u, tangent_v)) => FaceFrame {
            tangent_u,
            tangent_v,
            from_uv: true,
        },
        None => frame_from_normal(normal),
    }
}

/// `v` with its component along unit `n` removed, or `None` when nothing is left.
fn in_plane(v: Vec3, n: Vec3) -> Option<Vec3> {
    let t = v - n * n.dot(v);
    // Relative test: an accumulated sum that (nearly) cancelled carries no direction.
    (t.length_squared() > 1e-8 * v.length_squared().max(1e-30) && t.is_finite()).then_some(t)
}

/// Per-vertex tangents from the triangles that use each vertex.
///
/// As in [004] (docs/sources.md): each face's Pu and Pv are normalised and summed at its
/// three vertices, then the sums are renormalised. Here they are also made
/// perpendicular to the vertex normal (the shading frame must lie in the
/// tangent plane) and given back a length, the mean of the faces' |Pu| and
/// |Pv|, because the renderer reads ∂P/∂u, not a unit vector. Faces with
/// degenerate UVs do not vote; a vertex left without a usable direction
/// (no votes, or votes that cancel) gets a frame from its normal, at the
/// mean length of its faces' axes, or 1.
pub fn accumulate(mesh: &mut Mesh) {
    #[derive(Clone, Copy, Default)]
    struct Sum {
        dir_u: Vec3,
        dir_v: Vec3,
        len_u: f32,
        len_v: f32,
        votes: u32,
        handedness: f32,
    }
    let mut sums = vec![Sum::default(); mesh.vertices.len()];
    for (t, tri) in mesh.triangles.iter().enumerate() {
        let face_normal = mesh.face_normal(t);
        let idx = tri.indices.map(|i| i as usize);
        if idx.iter().any(|&i| i >= mesh.vertices.len()) {
            continue;
        }
        let p = idx.map(|i| mesh.vertices[i].position);
        let uv = idx.map(|i| mesh.vertices[i].uv);
        let frame = face_frame(p, uv, face_normal);
        if !frame.from_uv {
            continue;
        }
        let (lu, lv) = (frame.tangent_u.length(), frame.tangent_v.length());
        let hand = frame.handedness(face_normal);
        for i in idx {
            let s = &mut sums[i];
            s.dir_u += frame.tangent_u / lu;
            s.dir_v += frame.tangent_v / lv;
            s.len_u += lu;
            s.len_v += lv;
            s.votes += 1;
            s.handedness += hand;
        }
    }
    // Each vertex is finished from its own sums alone: in parallel.
    mesh.vertices
        .par_iter_mut()
        .zip(&sums)
        .for_each(|(vertex, s)| {
            let n = vertex.normal.normalize_or(Vec3::Z);
            let (len_u, len_v) = if s.votes > 0 {
                (s.len_u / s.votes as f32, s.len_v / s.votes as f32)
            } else {
                (1.0, 1.0)
            };
            let u = in_plane(s.dir_u, n).map(Vec3::normalize);
            let v = in_plane(s.dir_v, n).map(Vec3::normalize);
            // Mirrored faces were counted with −1: the sign of the sum says
            // which way Pv turns from Pu when one of the two has to be rebuilt.
            let hand = if s.handedness < 0.0 { -1.0 } else { 1.0 };
            let (tu, tv) = match (u, v) {
                (Some(u), Some(v)) if u.cross(v).length_squared() > 1e-6 => (u, v),
                (Some(u), _) => (u, hand * n.cross(u)),
                (None, Some(v)) => (hand * v.cross(n), v),
                (None, None) => {
                    let f = frame_from_normal(n);
                    (f.tangent_u, f.tangent_v)
                }
            };
            vertex.tangent_u = tu * len_u;
            vertex.tangent_v = tv * len_v;
        });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_from_normal_is_right_handed_and_unit() {
        for n in [Vec3::X, Vec3::NEG_Y, Vec3::new(1.0, 2.0, -3.0), Vec3::ZERO] {
            let f = frame_from_normal(n);
            let n = n.normalize_or(Vec3::Z);
            assert!((f.tangent_u.length() - 1.0).abs() < 1e-5);
            assert!((f.tangent_v.length() - 1.0).abs() < 1e-5);
            assert!((f.tangent_u.cross(f.tangent_v) - n).length() < 1e-5);
            assert!(!f.from_uv);
        }
    }
}
