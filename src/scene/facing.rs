//! Each triangle's facet normal in world space and the side of it the
//! camera sees: the per-triangle pass of placing an object
//! ([`super::world`]), most of a big mesh's frame. Four triangles go
//! through it at a time, one per lane of glam's `Vec4` (SSE2 on x86_64),
//! each lane doing the IEEE operations of glam's scalar `Vec3` code in
//! the same order, so every result has the bits of [`Facing::one`], which
//! runs the triangles that do not fit the four-lane path (a facet from
//! the mesh's side table, a corner past the vertices, the last few).

use std::sync::atomic::{AtomicU8, Ordering};

use glam::{Mat3, Vec3, Vec4};

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

    /// Triangles `t` … `t + 3` in four lanes into `facets` and `sides`
    /// (four each), as [`Facing::one`] gives them; false (nothing
    /// written) unless all four exist and have their facet computed from
    /// their corners, all of them vertices.
    #[inline]
    fn four(&self, t: usize, facets: &mut [Vec3], sides: &mut [i8]) -> bool {
        // Per lane: the three corners in model space, then the first one
        // in world space.
        let mut p = [[Vec3::ZERO; 4]; 4];
        let mut corners = [[0u32; 3]; 4];
        for k in 0..4 {
            let Some([i, j, l]) = self.mesh.computed_corners(t + k) else {
                return false;
            };
            corners[k] = [i, j, l];
            let corner = |i: u32| self.mesh.vertices.get(i as usize).map(|v| v.position);
            let (Some(a), Some(b), Some(c), Some(first)) = (
                corner(i),
                corner(j),
                corner(l),
                self.positions.get(i as usize),
            ) else {
                return false;
            };
            (p[0][k], p[1][k], p[2][k], p[3][k]) = (a, b, c, *first);
        }
        // Built from registers: lanes stored one float at a time and read
        // back as a vector would stall on the store forwarding.
        let at = |c: usize| {
            let q = &p[c];
            Lanes {
                x: Vec4::new(q[0].x, q[1].x, q[2].x, q[3].x),
                y: Vec4::new(q[0].y, q[1].y, q[2].y, q[3].y),
                z: Vec4::new(q[0].z, q[1].z, q[2].z, q[3].z),
            }
        };
        let (a, b, c, first) = (at(0), at(1), at(2), at(3));
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
#[derive(Clone, Copy)]
struct Lanes {
    x: Vec4,
    y: Vec4,
    z: Vec4,
}

impl Lanes {
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
