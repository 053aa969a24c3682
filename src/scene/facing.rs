//! Each triangle's facet normal in world space and the side of it the
//! camera sees: the per-triangle pass of placing an object
//! ([`super::world`]), most of a big mesh's frame. Four triangles go
//! through it at a time, one per lane of glam's `Vec4` (SSE2 on x86_64),
//! each lane doing the IEEE operations of glam's scalar `Vec3` code in
//! the same order, so every result has the bits of [`Facing::one`], which
//! runs the triangles that do not fit the four-lane path (a facet from
//! the mesh's side table, a corner past the vertices, the last few).

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
                }
            }
        }
    }

    /// Triangles `t` … `t + 3` in four lanes into `facets` and `sides`
    /// (four each), as [`Facing::one`] gives them; false (nothing
    /// written) unless all four exist and have their facet computed from
    /// their corners, all of them vertices.
    #[inline]
    #[allow(clippy::needless_range_loop)] // the lanes are transposed
    fn four(&self, t: usize, facets: &mut [Vec3], sides: &mut [i8]) -> bool {
        let vertices = &self.mesh.vertices;
        // Corner c's coordinate i of lane k at [3 * c + i][k]; then the
        // first corner in world space.
        let mut lanes = [[0.0f32; 4]; 12];
        for k in 0..4 {
            let Some(indices) = self.mesh.computed_corners(t + k) else {
                return false;
            };
            let Some(first) = self.positions.get(indices[0] as usize) else {
                return false;
            };
            for c in 0..3 {
                let p = vertices[indices[c] as usize].position;
                lanes[3 * c][k] = p.x;
                lanes[3 * c + 1][k] = p.y;
                lanes[3 * c + 2][k] = p.z;
            }
            lanes[9][k] = first.x;
            lanes[10][k] = first.y;
            lanes[11][k] = first.z;
        }
        let at = |i: usize| Lanes {
            x: Vec4::from_array(lanes[i]),
            y: Vec4::from_array(lanes[i + 1]),
            z: Vec4::from_array(lanes[i + 2]),
        };
        let (a, b, c, first) = (at(0), at(3), at(6), at(9));
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
        let facing = facet.normalize_or_zero().dot(to_eye).to_array();
        let (x, y, z) = (facet.x.to_array(), facet.y.to_array(), facet.z.to_array());
        let closed = self.mesh.closed;
        for k in 0..4 {
            facets[k] = Vec3::new(x[k], y[k], z[k]);
            sides[k] = side(facing[k], closed);
        }
        true
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
