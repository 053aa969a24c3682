//! The tangent frame T, B, N at a pixel (docs/bump-dot3.md), and the
//! interpolated surface the bump techniques start from.
//!
//! The frame is orthonormal: T is ∂P/∂u made perpendicular to N, and
//! B = ±N × T with the sign of ∂P/∂v (so mirrored UVs keep their
//! orientation). An orthonormal frame keeps lengths: a light vector
//! projected into it and divided by its world length is a unit vector, and
//! a tangent-space normal (0, 0, 1) lights exactly like N.

use glam::{Vec2, Vec3};

use super::PhongTri;
use crate::scene::mesh::any_perpendicular;

/// An orthonormal tangent frame, plus the lengths of ∂P/∂u and ∂P/∂v
/// (world units per unit of texture coordinate) for converting tangent
/// offsets into texture-coordinate offsets.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    pub t: Vec3,
    pub b: Vec3,
    pub n: Vec3,
    pub len_u: f32,
    pub len_v: f32,
}

/// Smallest tangent length trusted; below it the UVs give no direction.
const MIN_TANGENT: f32 = 1e-12;

impl Frame {
    /// From a unit normal `n` and the texture axes `pu` = ∂P/∂u, `pv` = ∂P/∂v.
    /// Degenerate or non-finite axes fall back to any frame around `n`.
    #[inline]
    pub fn new(n: Vec3, pu: Vec3, pv: Vec3) -> Frame {
        let along_u = pu - n * n.dot(pu);
        let along_v = pv - n * n.dot(pv);
        let t = if along_u.length_squared() > MIN_TANGENT && along_u.is_finite() {
            along_u.normalize()
        } else if along_v.length_squared() > MIN_TANGENT && along_v.is_finite() {
            // No usable u axis: T is a quarter turn from the v axis.
            along_v
                .normalize()
                .cross(n)
                .normalize_or(any_perpendicular(n))
        } else {
            any_perpendicular(n)
        };
        let mut b = n.cross(t);
        if b.dot(pv) < 0.0 {
            b = -b;
        }
        let len = |a: Vec3| {
            let l = a.length();
            if l.is_finite() && l > 1e-6 { l } else { 1.0 }
        };
        Frame {
            t,
            b,
            n,
            len_u: len(pu),
            len_v: len(pv),
        }
    }

    /// A world vector in tangent coordinates (x along T, y along B, z along N).
    #[inline]
    pub fn to_tangent(&self, d: Vec3) -> Vec3 {
        Vec3::new(d.dot(self.t), d.dot(self.b), d.dot(self.n))
    }
}

/// What every bump technique interpolates at a pixel, computed exactly as the
/// Phong kernel does (so a technique with nothing to perturb gives the same bits).
#[derive(Clone, Copy, Debug)]
pub struct Surface {
    pub p: Vec3,
    pub n: Vec3,
    /// The triangle's facet normal (its plane).
    pub face_n: Vec3,
    pub albedo: Vec3,
    pub uv: Vec2,
    pub pu: Vec3,
    pub pv: Vec3,
}

#[inline]
pub(crate) fn lerp3(b: Vec3, v: &[Vec3; 3]) -> Vec3 {
    v[0] * b.x + v[1] * b.y + v[2] * b.z
}

#[inline]
pub(crate) fn lerp2(b: Vec3, v: &[Vec2; 3]) -> Vec2 {
    v[0] * b.x + v[1] * b.y + v[2] * b.z
}

impl Surface {
    #[inline]
    pub fn at(tri: &PhongTri, b: Vec3) -> Surface {
        let n = if tri.smooth {
            lerp3(b, &tri.normal).normalize_or(tri.face_normal)
        } else {
            tri.face_normal
        };
        let (pu, pv) = if tri.uniform_tangents {
            (tri.tangent_u[0], tri.tangent_v[0])
        } else {
            (lerp3(b, &tri.tangent_u), lerp3(b, &tri.tangent_v))
        };
        Surface {
            p: lerp3(b, &tri.position),
            n,
            face_n: tri.face_normal,
            albedo: lerp3(b, &tri.color),
            uv: lerp2(b, &tri.uv),
            pu,
            pv,
        }
    }

    #[inline]
    pub fn frame(&self) -> Frame {
        Frame::new(self.n, self.pu, self.pv)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn assert_orthonormal(f: &Frame) {
        for (a, b) in [(f.t, f.b), (f.b, f.n), (f.t, f.n)] {
            assert!(a.dot(b).abs() < 1e-5);
        }
        for v in [f.t, f.b, f.n] {
            assert!((v.length() - 1.0).abs() < 1e-5);
        }
    }

    #[test]
    fn reference_face_frame_is_its_texture_axes() {
        let f = Frame::new(Vec3::Z, 2.0 * Vec3::X, 2.0 * Vec3::Y);
        assert_eq!((f.t, f.b, f.n), (Vec3::X, Vec3::Y, Vec3::Z));
        assert_eq!((f.len_u, f.len_v), (2.0, 2.0));
    }

    #[test]
    fn mirrored_v_flips_the_binormal() {
        let f = Frame::new(Vec3::Z, Vec3::X, -Vec3::Y);
        assert_eq!(f.b, -Vec3::Y);
        assert_orthonormal(&f);
    }

    #[test]
    fn skewed_and_degenerate_axes_still_give_an_orthonormal_frame() {
        let n = Vec3::new(1.0, 1.0, 1.0).normalize();
        for (pu, pv) in [
            (Vec3::X * 2.0, Vec3::Y * 2.0),
            (Vec3::ZERO, Vec3::Y),
            (Vec3::ZERO, Vec3::ZERO),
            (n * 3.0, n),
            (Vec3::NAN, Vec3::INFINITY),
        ] {
            let f = Frame::new(n, pu, pv);
            assert_orthonormal(&f);
            assert!(f.len_u.is_finite() && f.len_v.is_finite());
        }
    }

    #[test]
    fn projection_keeps_length() {
        let f = Frame::new(Vec3::new(0.3, -0.5, 0.8).normalize(), Vec3::X, Vec3::Z);
        let d = Vec3::new(3.0, 4.0, -2.0);
        assert!((f.to_tangent(d).length() - d.length()).abs() < 1e-5);
    }
}
