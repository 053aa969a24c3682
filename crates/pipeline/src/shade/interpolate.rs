//! Values across a triangle: the perspective-correct barycentrics of a
//! pixel, and a vertex value interpolated at them. Written once over the
//! lane type (`shade::lanes`), for one pixel and for eight, in the order
//! glam's `v0 * b.x + v1 * b.y + v2 * b.z` adds.

use glam::{Vec2, Vec3};

use super::lanes::{Lanes, Vector};

/// A pixel's weights from its screen-space barycentrics `l` on a triangle
/// whose vertices have the reciprocal depths `q`: `w` the weights before
/// normalising, `sum` their sum (the pixel's reciprocal depth, up to a
/// constant) and `b` the perspective-correct barycentrics.
#[derive(Clone, Copy, Debug)]
pub struct Perspective<L> {
    pub w: [L; 3],
    pub sum: L,
    pub b: [L; 3],
}

#[inline(always)]
pub fn perspective<L: Lanes>(l: [L; 3], q: [f32; 3]) -> Perspective<L> {
    let w = [
        l[0] * L::splat(q[0]),
        l[1] * L::splat(q[1]),
        l[2] * L::splat(q[2]),
    ];
    let sum = w[0] + w[1] + w[2];
    let inv = L::ONE / sum;
    Perspective {
        w,
        sum,
        b: [w[0] * inv, w[1] * inv, w[2] * inv],
    }
}

/// A triangle's three vertex vectors, each in every lane: made once per
/// triangle, a packet's interpolation reads them without broadcasting again.
#[derive(Clone, Copy, Debug)]
pub struct Corners3<V>(pub [V; 3]);

impl<V: Vector> Corners3<V> {
    #[inline(always)]
    pub fn of(v: &[Vec3; 3]) -> Self {
        Corners3([V::uniform(v[0]), V::uniform(v[1]), V::uniform(v[2])])
    }

    /// The value at barycentrics `b`.
    #[inline(always)]
    pub fn at(&self, b: &[V::L; 3]) -> V {
        let [v0, v1, v2] = self.0;
        v0 * b[0] + v1 * b[1] + v2 * b[2]
    }
}

/// A triangle's three texture coordinates, each component in every lane.
#[derive(Clone, Copy, Debug)]
pub struct Corners2<L>(pub [[L; 2]; 3]);

impl<L: Lanes> Corners2<L> {
    #[inline(always)]
    pub fn of(v: &[Vec2; 3]) -> Self {
        let splat = |v: Vec2| [L::splat(v.x), L::splat(v.y)];
        Corners2([splat(v[0]), splat(v[1]), splat(v[2])])
    }

    /// The coordinate (u, v) at barycentrics `b`.
    #[inline(always)]
    pub fn at(&self, b: &[L; 3]) -> (L, L) {
        let [v0, v1, v2] = self.0;
        let c = |k: usize| v0[k] * b[0] + v1[k] * b[1] + v2[k] * b[2];
        (c(0), c(1))
    }
}

/// The vertex vectors `v` at barycentrics `b`.
#[inline(always)]
pub fn lerp3<V: Vector>(b: &[V::L; 3], v: &[Vec3; 3]) -> V {
    Corners3::<V>::of(v).at(b)
}

/// The vertex coordinates `v` at barycentrics `b`.
#[inline(always)]
pub fn lerp2<L: Lanes>(b: &[L; 3], v: &[Vec2; 3]) -> (L, L) {
    Corners2::<L>::of(v).at(b)
}

/// `lerp3` at one pixel's barycentrics.
#[inline(always)]
pub fn lerp3_at(b: Vec3, v: &[Vec3; 3]) -> Vec3 {
    lerp3::<Vec3>(&b.to_array(), v)
}

/// `lerp2` at one pixel's barycentrics.
#[inline(always)]
pub fn lerp2_at(b: Vec3, v: &[Vec2; 3]) -> Vec2 {
    let (x, y) = lerp2::<f32>(&b.to_array(), v);
    Vec2::new(x, y)
}
