//! The tangent frame T, B, N at a pixel (docs/bump-dot3.md), and the
//! interpolated surface the bump techniques start from.
//!
//! The frame is orthonormal: T is ∂P/∂u made perpendicular to N, and
//! B = ±N × T with the sign of ∂P/∂v (so mirrored UVs keep their
//! orientation). An orthonormal frame keeps lengths: a light vector
//! projected into it and divided by its world length is a unit vector, and
//! a tangent-space normal (0, 0, 1) lights exactly like N.

use glam::Vec3;

use super::PhongTri;
use super::interpolate::{Corners2, Corners3, lerp2, lerp3};
use super::lanes::{Lanes, Vector};
use super::packet::{LANES, V3};
use relief_scene::face_frame::any_perpendicular;
use wide::f32x8;

/// An orthonormal tangent frame, plus the lengths of ∂P/∂u and ∂P/∂v
/// (world units per unit of texture coordinate) for converting tangent
/// offsets into texture-coordinate offsets; at one point or eight
/// (`shade::lanes`).
#[derive(Clone, Copy, Debug)]
pub struct Frame<V: Vector = Vec3> {
    pub t: V,
    pub b: V,
    pub n: V,
    pub len_u: V::L,
    pub len_v: V::L,
}

/// Smallest tangent length trusted; below it the UVs give no direction.
const MIN_TANGENT: f32 = 1e-12;

/// An axis the UVs give a direction with: long enough and finite.
#[inline(always)]
fn usable<V: Vector>(a: V) -> <V::L as Lanes>::Mask {
    V::L::both(a.dot(a).gt(V::L::splat(MIN_TANGENT)), || a.finite())
}

/// T where ∂P/∂u gives no direction: a quarter turn from the v axis, or
/// any tangent when that gives none either (made lane by lane: rare).
#[inline(never)]
fn tangent_without_u(n: Vec3, along_v: Vec3) -> Vec3 {
    if usable(along_v) {
        along_v
            .normalize()
            .cross(n)
            .normalize_or(any_perpendicular(n))
    } else {
        any_perpendicular(n)
    }
}

impl<V: Vector> Frame<V> {
    /// From a unit normal `n` and the texture axes `pu` = ∂P/∂u, `pv` = ∂P/∂v.
    /// Degenerate or non-finite axes fall back to any frame around `n`.
    #[inline(always)]
    pub fn new(n: V, pu: V, pv: V) -> Frame<V> {
        let along_u = pu - n * n.dot(pu);
        let along_v = pv - n * n.dot(pv);
        let has_u = usable(along_u);
        // glam's `normalize`: times the reciprocal of the length.
        let mut t = along_u * (V::L::ONE / along_u.dot(along_u).sqrt());
        if !V::L::none(!has_u) {
            let others = V::gather(V::L::bits(!has_u), |i| {
                tangent_without_u(n.lane(i), along_v.lane(i))
            });
            t = V::select(has_u, t, others);
        }
        let b = n.cross(t);
        let b = V::select(b.dot(pv).lt(V::L::ZERO), -b, b);
        let len = |a: V| {
            let l = a.dot(a).sqrt();
            let finite = l.abs().lt(V::L::splat(f32::INFINITY));
            V::L::select(V::L::both(finite, || l.gt(V::L::splat(1e-6))), l, V::L::ONE)
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
    #[inline(always)]
    pub fn to_tangent(&self, d: V) -> V {
        V::new(d.dot(self.t), d.dot(self.b), d.dot(self.n))
    }
}

/// What every bump technique interpolates at a pixel (or eight), computed
/// exactly as the Phong kernel does (so a technique with nothing to perturb
/// gives the same bits).
#[derive(Clone, Copy, Debug)]
pub struct Surface<V: Vector = Vec3> {
    pub p: V,
    pub n: V,
    /// The triangle's facet normal (its plane).
    pub face_n: Vec3,
    pub albedo: V,
    /// The texture coordinate.
    pub u: V::L,
    pub v: V::L,
    pub pu: V,
    pub pv: V,
}

impl<V: Vector> Surface<V> {
    #[inline(always)]
    pub fn at(tri: &PhongTri, b: &[V::L; 3]) -> Surface<V> {
        let face = V::uniform(tri.face_normal);
        let n = if tri.smooth {
            lerp3::<V>(b, &tri.normal).normalize_or(face)
        } else {
            face
        };
        let (pu, pv) = if tri.uniform_tangents {
            (V::uniform(tri.tangent_u[0]), V::uniform(tri.tangent_v[0]))
        } else {
            (lerp3(b, &tri.tangent_u), lerp3(b, &tri.tangent_v))
        };
        let (u, v) = lerp2(b, &tri.uv);
        Surface {
            p: lerp3(b, &tri.position),
            n,
            face_n: tri.face_normal,
            albedo: lerp3(b, &tri.color),
            u,
            v,
            pu,
            pv,
        }
    }

    #[inline(always)]
    pub fn frame(&self) -> Frame<V> {
        Frame::new(self.n, self.pu, self.pv)
    }
}

/// The triangles of a packet's pixels: the kernel's own, or one per lane
/// (small triangles' last pixels shaded together, `raster::pending`).
#[derive(Clone, Copy)]
pub enum Tris<'a> {
    One(&'a PhongTri),
    Each(&'a [&'a PhongTri; LANES]),
}

impl Tris<'_> {
    /// Lane `i`'s triangle.
    #[inline(always)]
    pub fn lane(&self, i: usize) -> &PhongTri {
        match self {
            Tris::One(t) => t,
            Tris::Each(t) => t[i],
        }
    }
}

impl Surface<V3> {
    /// Each lane's surface on its own triangle `tris[i]` at barycentrics
    /// `b`: lane i is `Surface::<Vec3>::at` of its triangle, bit for bit
    /// (the one-pixel and eight-pixel forms agree, and each choice a
    /// triangle makes is made per lane). The facet normal is the first
    /// triangle's. The corners are gathered into lanes and interpolated
    /// once, not eight times one lane at a time. Without `tangents` (a
    /// kernel that builds no tangent frame) ∂P/∂u and ∂P/∂v are left zero:
    /// gathering them was a fifth of such a packet's time.
    #[inline(always)]
    pub fn each(tris: &[&PhongTri; LANES], b: &[f32x8; 3], tangents: bool) -> Surface<V3> {
        const ALL: u32 = (1 << LANES) - 1;
        let lanes = |f: fn(&PhongTri) -> Vec3| V3::gather(ALL, |i| f(tris[i]));
        let corners = |f: fn(&PhongTri) -> &[Vec3; 3]| {
            let corner = |k: usize| V3::gather(ALL, |i| f(tris[i])[k]);
            Corners3([corner(0), corner(1), corner(2)])
        };
        let mask = |f: fn(&PhongTri) -> bool| {
            let [m] = f32x8::gather(ALL, 0.0, |i| [f32::from(u8::from(f(tris[i])))]);
            m.gt(f32x8::ZERO)
        };
        let face = lanes(|t| t.face_normal);
        let smooth = corners(|t| &t.normal).at(b).normalize_or(face);
        let n = V3::select(mask(|t| t.smooth), smooth, face);
        let (pu, pv) = if tangents {
            let uniform = mask(|t| t.uniform_tangents);
            let pu = lanes(|t| t.tangent_u[0]);
            let pv = lanes(|t| t.tangent_v[0]);
            (
                V3::select(uniform, pu, corners(|t| &t.tangent_u).at(b)),
                V3::select(uniform, pv, corners(|t| &t.tangent_v).at(b)),
            )
        } else {
            (V3::uniform(Vec3::ZERO), V3::uniform(Vec3::ZERO))
        };
        let uv = |k: usize| {
            let [u, v] = f32x8::gather(ALL, 0.0, |i| tris[i].uv[k].to_array());
            [u, v]
        };
        let (u, v) = Corners2([uv(0), uv(1), uv(2)]).at(b);
        Surface {
            p: corners(|t| &t.position).at(b),
            n,
            face_n: tris[0].face_normal,
            albedo: corners(|t| &t.color).at(b),
            u,
            v,
            pu,
            pv,
        }
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
