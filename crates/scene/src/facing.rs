//! Each triangle's facet normal in world space and the side of it the
//! camera sees: the per-triangle pass of placing an object
//! ([`super::world`]), most of a big mesh's frame. Four triangles go
//! through it at a time, one per lane of glam's `Vec4` (SSE2 on x86_64),
//! each lane doing the IEEE operations of glam's scalar `Vec3` code in
//! the same order, so every result has the bits of [`Facing::one`], which
//! runs the triangles that do not fit the four-lane path (a facet from
//! the mesh's side table, a corner past the vertices, the last few).
//!
//! When no pass needs every facet (no shadow map is drawn), only the sides
//! are made ([`Facing::run_sides`]): a triangle's side is then decided in
//! model space from its unnormalized cross product and the eye carried
//! back by the inverse model matrix ([`Quick`]), with no square root, no
//! division and no matrix, whenever that sign is sure to be the one
//! [`Facing::one`] computes; the few triangles near edge-on, degenerate or
//! not finite go through [`Facing::one`] itself. Same sides, same bits.

use std::sync::atomic::{AtomicU8, Ordering};

use glam::{DMat3, DMat4, DVec3, DVec4, Mat3, Mat4, Vec3, Vec4};

use super::Mesh;

/// What the facing pass of one object reads.
#[derive(Clone, Copy, Debug)]
pub struct Facing<'a> {
    pub mesh: &'a Mesh,
    /// The mesh's vertices in world space, one per vertex.
    pub positions: &'a [Vec3],
    /// The normal matrix (the inverse transpose of the model's linear part).
    pub normals: Mat3,
    pub eye: Vec3,
    /// Per vertex, set to 1 by [`Facing::run`] when the vertex is a corner
    /// of a triangle the camera sees (side ≠ 0); never cleared here. May
    /// be empty (nothing is marked).
    pub seen: &'a [AtomicU8],
    /// The model-space test of [`Facing::run_sides`], when the model
    /// matrix allows it.
    pub quick: Option<Quick>,
}

/// The model-space side test of one object for one frame.
///
/// [`Facing::one`] takes the sign of F = n̂_w · (e − M a), where n̂_w is the
/// unit facet normal N n̂ / |N n̂| (N the normal matrix, n̂ the unit cross
/// product c / |c| of the edges at corner a) and M a the first corner in
/// world space. In exact arithmetic, with N = L⁻ᵀ (L the model's linear
/// part) and e_m = M⁻¹ e, F has the sign of G = c · (e_m − a): the two
/// normalizations and the matrices cancel. Both start from the same
/// computed c (the same operations), so they differ only by the rounding
/// of what follows, which is bounded by a few units in the last place of
/// the magnitudes involved, times the conditioning of L, plus the
/// measured error Δ = ‖Lᵀ N − I‖ of the normal matrix. When |G| exceeds
/// 16 times that bound (`margin`), F is finite, nonzero and of G's sign.
#[derive(Clone, Copy, Debug)]
pub struct Quick {
    /// The eye in model space.
    eye: Lanes,
    /// The bound on |F − G|-like rounding is |c|₁ (k0 + k1 |a|₁).
    k0: Vec4,
    k1: Vec4,
}

/// Bounds within which the quick test's error analysis holds (no
/// underflow of |c|², no overflow of the world positions).
const CROSS_MIN: f32 = 1e-18;
const CROSS_MAX: f32 = 1e18;
const POSITION_MAX: f32 = 1e15;

impl Quick {
    /// The test for an object placed by `model`, whose normals `normals`
    /// carries, seen from `eye`; `None` when the model matrix is not
    /// affine, not finite, too badly conditioned, or `normals` is not its
    /// inverse transpose (a singular model's fallback): every triangle then
    /// takes the exact path.
    pub fn new(model: Mat4, normals: Mat3, eye: Vec3) -> Option<Quick> {
        let m: DMat4 = model.as_dmat4();
        if m.row(3) != DVec4::new(0.0, 0.0, 0.0, 1.0) || !m.is_finite() {
            return None;
        }
        let l = DMat3::from_mat4(m);
        let n = normals.as_dmat3();
        let frobenius = |a: DMat3| {
            (a.x_axis.length_squared() + a.y_axis.length_squared() + a.z_axis.length_squared())
                .sqrt()
        };
        let (lf, nf) = (frobenius(l), frobenius(n));
        let delta = frobenius(l.transpose() * n - DMat3::IDENTITY);
        let sane = |v: f64| (1e-10..=1e10).contains(&v);
        if !sane(lf) || !sane(nf) || !(0.0..1e-3).contains(&delta) {
            return None;
        }
        let kappa = lf * frobenius(l.inverse());
        let eye_model: DVec3 = m.inverse().transform_point3(eye.as_dvec3());
        let (e, t, em) = (
            eye.as_dvec3().length(),
            m.w_axis.truncate().length(),
            eye_model.length(),
        );
        let u = f64::from(f32::EPSILON) / 2.0;
        let k0 = 16.0 * ((delta + 8.0 * u) * em + (20.0 + 4.0 * kappa) * u * nf * (e + 2.0 * t));
        let k1 = 16.0 * ((delta + 8.0 * u) + (40.0 + 8.0 * kappa) * u * nf * lf);
        let eye_model = eye_model.as_vec3();
        let usable = k0.is_finite()
            && k1.is_finite()
            && kappa < 1e6
            && eye_model.is_finite()
            && eye_model.abs().max_element() <= POSITION_MAX;
        if !usable {
            return None;
        }
        Some(Quick {
            eye: Lanes::splat(eye_model),
            k0: Vec4::splat(k0 as f32),
            k1: Vec4::splat(k1 as f32),
        })
    }
}

impl Facing<'_> {
    /// Triangle `t`'s facet normal carried by the normal matrix (not
    /// normalized) and the side the camera sees: 1 (front), −1 (the back
    /// of an open surface) or 0 (a back face of a closed mesh, edge on,
    /// not finite, or a corner past the vertices).
    #[inline]
    pub fn one(&self, t: usize) -> (Vec3, i8) {
        let facet = self.normals * self.mesh.face_normal(t);
        let indices = self.mesh.triangles[t].indices;
        if !indices.iter().all(|&i| (i as usize) < self.positions.len()) {
            return (facet, 0);
        }
        let facing = facet
            .normalize_or_zero()
            .dot(self.eye - self.positions[indices[0] as usize]);
        (facet, side(facing, self.mesh.closed))
    }

    /// Triangles `start`, `start + 1`, … into `facets` and `sides` (as
    /// many as they hold, the same length), as [`Facing::one`] gives them.
    pub fn run(&self, start: usize, facets: &mut [Vec3], sides: &mut [i8]) {
        for (k, (facets, sides)) in facets.chunks_mut(4).zip(sides.chunks_mut(4)).enumerate() {
            let t = start + 4 * k;
            if facets.len() < 4 || !self.four(t, facets, sides) {
                for (j, (f, s)) in facets.iter_mut().zip(sides.iter_mut()).enumerate() {
                    (*f, *s) = self.one(t + j);
                    if *s != 0 {
                        self.mark(self.mesh.triangles[t + j].indices);
                    }
                }
            }
        }
    }

    /// The sides of triangles `start`, `start + 1`, … into `sides`, as
    /// [`Facing::one`] gives them, without their facets: decided in model
    /// space where [`Quick`] is sure, else by [`Facing::one`].
    pub fn run_sides(&self, start: usize, sides: &mut [i8]) {
        let Some(quick) = self.quick else {
            let mut facets = [Vec3::ZERO; 4];
            for (k, sides) in sides.chunks_mut(4).enumerate() {
                self.run(start + 4 * k, &mut facets[..sides.len()], sides);
            }
            return;
        };
        for (k, sides) in sides.chunks_mut(4).enumerate() {
            let t = start + 4 * k;
            if sides.len() < 4 || !self.four_sides(&quick, t, sides) {
                for (j, s) in sides.iter_mut().enumerate() {
                    *s = self.one(t + j).1;
                    if *s != 0 {
                        self.mark(self.mesh.triangles[t + j].indices);
                    }
                }
            }
        }
    }

    /// The corners of triangles `t` … `t + 3` in model space, a lane per
    /// triangle (its first, second and third corners), and their vertex
    /// indices; `None` unless all four exist and have their facet computed
    /// from their corners, all of them vertices.
    // Always inlined: returned through memory, its 192 bytes cost the
    // 1 M sphere's frame about 7 M instructions (callgrind).
    #[inline(always)]
    fn corners4(&self, t: usize) -> Option<([Lanes; 3], [[u32; 3]; 4])> {
        let mut p = [[Vec3::ZERO; 4]; 3];
        let mut corners = [[0u32; 3]; 4];
        for k in 0..4 {
            let [i, j, l] = self.mesh.computed_corners(t + k)?;
            corners[k] = [i, j, l];
            // In range: `computed_corners` checked them.
            let at = |i: u32| self.mesh.vertices[i as usize].position;
            (p[0][k], p[1][k], p[2][k]) = (at(i), at(j), at(l));
        }
        Some((
            [Lanes::of(&p[0]), Lanes::of(&p[1]), Lanes::of(&p[2])],
            corners,
        ))
    }

    /// The sides of triangles `t` … `t + 3` into `sides` (four), as
    /// [`Facing::one`] gives them; false (nothing written) unless all four
    /// exist and have their facet computed from their corners.
    #[inline]
    fn four_sides(&self, quick: &Quick, t: usize, sides: &mut [i8]) -> bool {
        let Some(([a, b, c], corners)) = self.corners4(t) else {
            return false;
        };
        // The cross product as `triangle_normal` computes it (same bits).
        let cross = b.sub(a).cross(c.sub(a));
        let g = cross.dot(quick.eye.sub(a));
        let norm1 = |v: Lanes| v.x.abs() + v.y.abs() + v.z.abs();
        let (c1, a1) = (norm1(cross), norm1(a));
        let margin = c1 * (quick.k0 + quick.k1 * a1);
        // Every comparison is false on a NaN: such a lane is not sure.
        let fits = c1.cmpge(Vec4::splat(CROSS_MIN))
            & c1.cmple(Vec4::splat(CROSS_MAX))
            & a1.cmple(Vec4::splat(POSITION_MAX));
        let front = (fits & g.cmpgt(margin)).bitmask();
        let back = (fits & g.cmplt(-margin)).bitmask();
        let back_side = if self.mesh.closed { 0 } else { -1 };
        let mut seen = 0;
        for (k, s) in sides.iter_mut().enumerate() {
            *s = if (front >> k) & 1 != 0 {
                1
            } else if (back >> k) & 1 != 0 {
                back_side
            } else {
                self.one(t + k).1
            };
            seen |= u32::from(*s != 0) << k;
        }
        if seen != 0 {
            for (k, corners) in corners.iter().enumerate() {
                if (seen >> k) & 1 != 0 {
                    self.mark(*corners);
                }
            }
        }
        true
    }

    /// Triangles `t` … `t + 3` in four lanes into `facets` and `sides`
    /// (four each), as [`Facing::one`] gives them; false (nothing
    /// written) unless all four exist and have their facet computed from
    /// their corners, all of them vertices.
    #[inline]
    fn four(&self, t: usize, facets: &mut [Vec3], sides: &mut [i8]) -> bool {
        let Some(([a, b, c], corners)) = self.corners4(t) else {
            return false;
        };
        // The first corner of each in world space.
        let mut first = [Vec3::ZERO; 4];
        for (f, corners) in first.iter_mut().zip(&corners) {
            let Some(p) = self.positions.get(corners[0] as usize) else {
                return false;
            };
            *f = *p;
        }
        let first = Lanes::of(&first);
        // `triangle_normal`: (b − a) × (c − a), normalized or zero.
        let normal = b.sub(a).cross(c.sub(a)).normalize_or_zero();
        // `normals * normal` as `Mat3 * Vec3` computes it.
        let m = self.normals;
        let facet = Lanes {
            x: Vec4::splat(m.x_axis.x) * normal.x
                + Vec4::splat(m.y_axis.x) * normal.y
                + Vec4::splat(m.z_axis.x) * normal.z,
            y: Vec4::splat(m.x_axis.y) * normal.x
                + Vec4::splat(m.y_axis.y) * normal.y
                + Vec4::splat(m.z_axis.y) * normal.z,
            z: Vec4::splat(m.x_axis.z) * normal.x
                + Vec4::splat(m.y_axis.z) * normal.y
                + Vec4::splat(m.z_axis.z) * normal.z,
        };
        let to_eye = Lanes::splat(self.eye).sub(first);
        let facing = facet.normalize_or_zero().dot(to_eye);
        // `side` in lanes: a comparison with a NaN is false, so a NaN,
        // an infinity and a zero are on no side.
        let front = (facing.cmpgt(Vec4::ZERO) & facing.cmplt(Vec4::INFINITY)).bitmask();
        let back = if self.mesh.closed {
            0
        } else {
            (facing.cmplt(Vec4::ZERO) & facing.cmpgt(Vec4::NEG_INFINITY)).bitmask()
        };
        let (x, y, z) = (facet.x.to_array(), facet.y.to_array(), facet.z.to_array());
        for (k, (f, s)) in facets.iter_mut().zip(sides.iter_mut()).enumerate() {
            *f = Vec3::new(x[k], y[k], z[k]);
            *s = ((front >> k) & 1) as i8 - ((back >> k) & 1) as i8;
        }
        let seen = front | back;
        if seen != 0 {
            for (k, corners) in corners.iter().enumerate() {
                if (seen >> k) & 1 != 0 {
                    self.mark(*corners);
                }
            }
        }
        true
    }

    /// Marks `corners` as seen (those past `seen` are not).
    #[inline]
    fn mark(&self, corners: [u32; 3]) {
        for i in corners {
            if let Some(s) = self.seen.get(i as usize) {
                s.store(1, Ordering::Relaxed);
            }
        }
    }
}

/// The side the camera sees of a triangle whose unit facet normal dotted
/// with the vector from its first corner to the eye is `facing`.
#[inline]
fn side(facing: f32, closed: bool) -> i8 {
    if !facing.is_finite() || facing == 0.0 || (facing < 0.0 && closed) {
        0
    } else if facing < 0.0 {
        -1
    } else {
        1
    }
}

/// Four `Vec3`s, a lane each.
#[derive(Clone, Copy, Debug)]
struct Lanes {
    x: Vec4,
    y: Vec4,
    z: Vec4,
}

impl Lanes {
    /// Four `Vec3`s, one per lane, built from registers: lanes stored one
    /// float at a time and read back as a vector would stall on the store
    /// forwarding.
    #[inline]
    fn of(q: &[Vec3; 4]) -> Lanes {
        Lanes {
            x: Vec4::new(q[0].x, q[1].x, q[2].x, q[3].x),
            y: Vec4::new(q[0].y, q[1].y, q[2].y, q[3].y),
            z: Vec4::new(q[0].z, q[1].z, q[2].z, q[3].z),
        }
    }

    #[inline]
    fn splat(v: Vec3) -> Lanes {
        Lanes {
            x: Vec4::splat(v.x),
            y: Vec4::splat(v.y),
            z: Vec4::splat(v.z),
        }
    }

    #[inline]
    fn sub(self, o: Lanes) -> Lanes {
        Lanes {
            x: self.x - o.x,
            y: self.y - o.y,
            z: self.z - o.z,
        }
    }

    /// `Vec3::cross`, term for term.
    #[inline]
    fn cross(self, o: Lanes) -> Lanes {
        Lanes {
            x: self.y * o.z - o.y * self.z,
            y: self.z * o.x - o.z * self.x,
            z: self.x * o.y - o.x * self.y,
        }
    }

    /// `Vec3::dot`: (x·x' + y·y') + z·z'.
    #[inline]
    fn dot(self, o: Lanes) -> Vec4 {
        self.x * o.x + self.y * o.y + self.z * o.z
    }

    /// `Vec3::normalize_or_zero`: times 1 / √(v·v) when that is finite
    /// and positive, else zero.
    #[inline]
    fn normalize_or_zero(self) -> Lanes {
        let rcp = Vec4::ONE / sqrt(self.dot(self));
        let keep = rcp.cmpgt(Vec4::ZERO) & rcp.cmplt(Vec4::INFINITY);
        Lanes {
            x: Vec4::select(keep, self.x * rcp, Vec4::ZERO),
            y: Vec4::select(keep, self.y * rcp, Vec4::ZERO),
            z: Vec4::select(keep, self.z * rcp, Vec4::ZERO),
        }
    }
}

/// The square root of each lane (correctly rounded, as `f32::sqrt`).
#[inline]
fn sqrt(v: Vec4) -> Vec4 {
    #[cfg(target_arch = "x86_64")]
    {
        // SAFETY: SSE is part of every x86_64 processor.
        Vec4::from(unsafe { std::arch::x86_64::_mm_sqrt_ps(v.into()) })
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        Vec4::from_array(v.to_array().map(f32::sqrt))
    }
}
