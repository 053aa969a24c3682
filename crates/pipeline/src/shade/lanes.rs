//! The lane types the shading formulas are written over: one pixel (`f32`,
//! glam's `Vec3`) or eight (`f32x8`, `packet::V3`) (docs/shading.md).
//!
//! Each lighting and bump formula is written once, generic over `Vector`,
//! the way an ispc kernel is written once for its gang: arithmetic is lane
//! by lane, a condition is a mask that `select` applies, and a step no lane
//! needs is skipped (`none`). The one-pixel kernels instantiate the formulas
//! with `f32`, where a mask is a `bool` and the skip an ordinary branch; the
//! packet kernels with `f32x8`. Both do the same IEEE adds,
//! multiplies, divides, square roots and comparisons in the same order (Rust
//! never fuses a multiply and an add behind our back), and the power is
//! `f32::powf` lane by lane, so a packet gives the very bits of eight pixels.

use std::fmt::Debug;
use std::ops::{Add, BitAnd, Div, Mul, Neg, Not, Sub};

use glam::Vec3;
use wide::f32x8;

use crate::shade::packet::{self, LANES, V3};
use relief_texture::{Level, NormalMap};

/// One value per lane: `f32` (one pixel) or `f32x8` (eight).
pub trait Lanes:
    Copy
    + Debug
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    /// A condition per lane.
    type Mask: Copy + BitAnd<Output = Self::Mask> + Not<Output = Self::Mask>;
    /// Pixels per value.
    const WIDTH: usize;
    const ZERO: Self;
    const ONE: Self;
    fn splat(v: f32) -> Self;
    /// The value of lane `i`.
    fn lane(self, i: usize) -> f32;
    /// `f(i)` in each lane i whose bit is set in `lanes`, `or` in the
    /// others: a step made lane by lane (a texel read, a shadow lookup),
    /// giving N values per lane.
    fn gather<const N: usize>(lanes: u32, or: f32, f: impl FnMut(usize) -> [f32; N]) -> [Self; N];
    /// A bit per lane set in `mask`.
    fn bits(mask: Self::Mask) -> u32;
    fn sqrt(self) -> Self;
    fn abs(self) -> Self;
    fn gt(self, o: Self) -> Self::Mask;
    fn lt(self, o: Self) -> Self::Mask;
    fn le(self, o: Self) -> Self::Mask;
    /// The smaller of the two where neither is NaN (a NaN lane is
    /// unspecified: the formulas select such lanes away).
    fn min(self, o: Self) -> Self;
    /// `a` in the lanes of `mask`, `b` in the others.
    fn select(mask: Self::Mask, a: Self, b: Self) -> Self;
    /// No lane of `mask` is set.
    fn none(mask: Self::Mask) -> bool;
    /// Whether a step whose lanes are all off in `mask` is skipped: for one
    /// pixel, always (a branch); for eight, never (the step's lanes are
    /// selected away, and testing costs more than the rare packet it skips).
    fn skips(mask: Self::Mask) -> bool;
    /// `a` and `b()`: for one pixel `&&`, which skips `b` when `a` is false.
    fn both(a: Self::Mask, b: impl FnOnce() -> Self::Mask) -> Self::Mask;
    /// x^e where x > 0, else 0 (also for NaN): `f32::powf` lane by lane.
    fn pow_positive(self, e: f32) -> Self;
    /// x^e with an exponent per lane, where x > 0, else 0: `f32::powf` lane
    /// by lane.
    fn pow_lanes(self, e: Self) -> Self;
    /// `level`'s bilinear colour (R, G, B) at (u, v): `Level::bilinear`, or
    /// the packet read that gives its bits lane by lane.
    fn bilinear(level: &Level, u: Self, v: Self) -> [Self; 3];
    /// `Level::bilinear_with_gradient`: the bilinear colour (R, G, B) and
    /// the filtered height gradient, from one neighbourhood.
    fn bilinear_with_gradient(level: &Level, u: Self, v: Self) -> ([Self; 3], Self, Self);
    /// `Level::height_gradient_filtered`: the filtered height gradient.
    fn gradient(level: &Level, u: Self, v: Self) -> (Self, Self);
    /// `NormalMap::bilinear` at (u, v), in the lanes of `live` (0 in the
    /// others), or the packet read that gives its bits lane by lane.
    fn normal_bilinear(map: &NormalMap, u: Self, v: Self, live: u32) -> [Self; 3];
    /// The lanes as eight (one pixel: in every lane), for a step written
    /// once over eight lanes (a table or map read).
    fn to_x8(self) -> f32x8;
    /// The first `WIDTH` lanes of `v`.
    fn from_x8(v: f32x8) -> Self;
}

impl Lanes for f32 {
    type Mask = bool;
    const WIDTH: usize = 1;
    const ZERO: f32 = 0.0;
    const ONE: f32 = 1.0;
    #[inline(always)]
    fn splat(v: f32) -> f32 {
        v
    }
    #[inline(always)]
    fn lane(self, _i: usize) -> f32 {
        self
    }
    #[inline(always)]
    fn gather<const N: usize>(
        lanes: u32,
        or: f32,
        mut f: impl FnMut(usize) -> [f32; N],
    ) -> [f32; N] {
        if lanes & 1 != 0 { f(0) } else { [or; N] }
    }
    #[inline(always)]
    fn bits(mask: bool) -> u32 {
        mask as u32
    }
    #[inline(always)]
    fn sqrt(self) -> f32 {
        f32::sqrt(self)
    }
    #[inline(always)]
    fn abs(self) -> f32 {
        f32::abs(self)
    }
    #[inline(always)]
    fn gt(self, o: f32) -> bool {
        self > o
    }
    #[inline(always)]
    fn lt(self, o: f32) -> bool {
        self < o
    }
    #[inline(always)]
    fn le(self, o: f32) -> bool {
        self <= o
    }
    #[inline(always)]
    fn min(self, o: f32) -> f32 {
        f32::min(self, o)
    }
    #[inline(always)]
    fn select(mask: bool, a: f32, b: f32) -> f32 {
        if mask { a } else { b }
    }
    #[inline(always)]
    fn none(mask: bool) -> bool {
        !mask
    }
    #[inline(always)]
    fn skips(mask: bool) -> bool {
        !mask
    }
    #[inline(always)]
    fn both(a: bool, b: impl FnOnce() -> bool) -> bool {
        a && b()
    }
    #[inline(always)]
    fn pow_positive(self, e: f32) -> f32 {
        if self > 0.0 { self.powf(e) } else { 0.0 }
    }
    #[inline(always)]
    fn pow_lanes(self, e: f32) -> f32 {
        self.pow_positive(e)
    }
    #[inline(always)]
    fn bilinear(level: &Level, u: f32, v: f32) -> [f32; 3] {
        let t = level.bilinear(u, v);
        [t[0], t[1], t[2]]
    }
    #[inline(always)]
    fn bilinear_with_gradient(level: &Level, u: f32, v: f32) -> ([f32; 3], f32, f32) {
        let (t, (fu, fv)) = level.bilinear_with_gradient(u, v);
        ([t[0], t[1], t[2]], fu, fv)
    }
    #[inline(always)]
    fn gradient(level: &Level, u: f32, v: f32) -> (f32, f32) {
        level.height_gradient_filtered(u, v)
    }
    #[inline(always)]
    fn normal_bilinear(map: &NormalMap, u: f32, v: f32, _live: u32) -> [f32; 3] {
        map.bilinear(u, v)
    }
    #[inline(always)]
    fn to_x8(self) -> f32x8 {
        f32x8::splat(self)
    }
    #[inline(always)]
    fn from_x8(v: f32x8) -> f32 {
        v.as_array()[0]
    }
}

impl Lanes for f32x8 {
    type Mask = f32x8;
    const WIDTH: usize = LANES;
    const ZERO: f32x8 = f32x8::ZERO;
    const ONE: f32x8 = f32x8::ONE;
    #[inline(always)]
    fn splat(v: f32) -> f32x8 {
        f32x8::splat(v)
    }
    #[inline(always)]
    fn lane(self, i: usize) -> f32 {
        self.as_array()[i]
    }
    #[inline(always)]
    fn gather<const N: usize>(
        lanes: u32,
        or: f32,
        mut f: impl FnMut(usize) -> [f32; N],
    ) -> [f32x8; N] {
        let mut out = [[or; LANES]; N];
        for lane in (0..LANES).filter(|l| lanes & (1 << l) != 0) {
            for (o, v) in out.iter_mut().zip(f(lane)) {
                o[lane] = v;
            }
        }
        out.map(f32x8::from)
    }
    #[inline(always)]
    fn bits(mask: f32x8) -> u32 {
        mask.to_bitmask()
    }
    #[inline(always)]
    fn sqrt(self) -> f32x8 {
        f32x8::sqrt(self)
    }
    #[inline(always)]
    fn abs(self) -> f32x8 {
        f32x8::abs(self)
    }
    #[inline(always)]
    fn gt(self, o: f32x8) -> f32x8 {
        self.simd_gt(o)
    }
    #[inline(always)]
    fn lt(self, o: f32x8) -> f32x8 {
        self.simd_lt(o)
    }
    #[inline(always)]
    fn le(self, o: f32x8) -> f32x8 {
        self.simd_le(o)
    }
    #[inline(always)]
    fn min(self, o: f32x8) -> f32x8 {
        self.fast_min(o)
    }
    #[inline(always)]
    fn select(mask: f32x8, a: f32x8, b: f32x8) -> f32x8 {
        mask.select(a, b)
    }
    #[inline(always)]
    fn none(mask: f32x8) -> bool {
        mask.none()
    }
    #[inline(always)]
    fn skips(_: f32x8) -> bool {
        false
    }
    #[inline(always)]
    fn both(a: f32x8, b: impl FnOnce() -> f32x8) -> f32x8 {
        a & b()
    }
    #[inline(always)]
    fn pow_positive(self, e: f32) -> f32x8 {
        f32x8::from(self.to_array().map(|x| x.pow_positive(e)))
    }
    #[inline(always)]
    fn pow_lanes(self, e: f32x8) -> f32x8 {
        let (x, e) = (self.to_array(), e.to_array());
        f32x8::from(std::array::from_fn::<f32, 8, _>(|i| {
            x[i].pow_positive(e[i])
        }))
    }
    #[inline(always)]
    fn bilinear(level: &Level, u: f32x8, v: f32x8) -> [f32x8; 3] {
        let c = packet::bilinear::<true, false>(level, u, v).color;
        [c.x, c.y, c.z]
    }
    #[inline(always)]
    fn bilinear_with_gradient(level: &Level, u: f32x8, v: f32x8) -> ([f32x8; 3], f32x8, f32x8) {
        let t = packet::bilinear::<true, true>(level, u, v);
        ([t.color.x, t.color.y, t.color.z], t.fu, t.fv)
    }
    #[inline(always)]
    fn gradient(level: &Level, u: f32x8, v: f32x8) -> (f32x8, f32x8) {
        let t = packet::bilinear::<false, true>(level, u, v);
        (t.fu, t.fv)
    }
    #[inline(always)]
    fn normal_bilinear(map: &NormalMap, u: f32x8, v: f32x8, live: u32) -> [f32x8; 3] {
        packet::normal_bilinear(map, u, v, live)
    }
    #[inline(always)]
    fn to_x8(self) -> f32x8 {
        self
    }
    #[inline(always)]
    fn from_x8(v: f32x8) -> f32x8 {
        v
    }
}

/// A 3-vector per lane: glam's `Vec3` for one pixel, `packet::V3` for
/// eight. The operators are component-wise (`* L` and `/ L` scale every
/// component), as glam's are.
pub trait Vector:
    Copy
    + Debug
    + Neg<Output = Self>
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Mul<Self::L, Output = Self>
    + Div<Self::L, Output = Self>
{
    type L: Lanes;
    /// Pixels per value.
    const WIDTH: usize;
    /// `v` in every lane.
    fn uniform(v: Vec3) -> Self;
    /// The vector of components `x`, `y`, `z`.
    fn new(x: Self::L, y: Self::L, z: Self::L) -> Self;
    fn x(self) -> Self::L;
    fn y(self) -> Self::L;
    fn z(self) -> Self::L;
    /// The vector of lane `i`.
    #[inline(always)]
    fn lane(self, i: usize) -> Vec3 {
        Vec3::new(self.x().lane(i), self.y().lane(i), self.z().lane(i))
    }
    /// `f(i)` in each lane i whose bit is set in `lanes`, zero in the others.
    #[inline(always)]
    fn gather(lanes: u32, mut f: impl FnMut(usize) -> Vec3) -> Self {
        let [x, y, z] = Self::L::gather(lanes, 0.0, |i| f(i).to_array());
        Self::new(x, y, z)
    }
    /// glam's `dot`: (x·x') + (y·y') + (z·z').
    fn dot(self, o: Self) -> Self::L;
    /// glam's `cross`, term for term.
    fn cross(self, o: Self) -> Self;
    /// `a` in the lanes of `mask`, `b` in the others.
    fn select(mask: <Self::L as Lanes>::Mask, a: Self, b: Self) -> Self;
    /// `f` of each lane whose bit is set in `live` (0 in the others): a
    /// lookup made lane by lane.
    #[inline(always)]
    fn each_live(self, live: u32, mut f: impl FnMut(Vec3) -> Vec3) -> Self {
        Self::gather(live, |i| f(self.lane(i)))
    }
    /// Each component's `abs() < ∞` (glam's `is_finite`).
    #[inline(always)]
    fn finite(self) -> <Self::L as Lanes>::Mask {
        let inf = <Self::L as Lanes>::splat(f32::INFINITY);
        self.x().abs().lt(inf) & self.y().abs().lt(inf) & self.z().abs().lt(inf)
    }

    /// glam's `normalize_or`: `self` over its length, or `fallback` where
    /// that is not a finite positive scale (zero or non-finite vectors).
    #[inline(always)]
    fn normalize_or(self, fallback: Self) -> Self {
        let rcp = <Self::L as Lanes>::ONE / self.dot(self).sqrt();
        let inf = <Self::L as Lanes>::splat(f32::INFINITY);
        let ok = rcp.abs().lt(inf) & rcp.gt(<Self::L as Lanes>::ZERO);
        Self::select(ok, self * rcp, fallback)
    }
}

impl Vector for Vec3 {
    type L = f32;
    const WIDTH: usize = 1;
    #[inline(always)]
    fn uniform(v: Vec3) -> Vec3 {
        v
    }
    #[inline(always)]
    fn new(x: f32, y: f32, z: f32) -> Vec3 {
        Vec3::new(x, y, z)
    }
    #[inline(always)]
    fn x(self) -> f32 {
        self.x
    }
    #[inline(always)]
    fn y(self) -> f32 {
        self.y
    }
    #[inline(always)]
    fn z(self) -> f32 {
        self.z
    }
    #[inline(always)]
    fn dot(self, o: Vec3) -> f32 {
        Vec3::dot(self, o)
    }
    #[inline(always)]
    fn cross(self, o: Vec3) -> Vec3 {
        Vec3::cross(self, o)
    }
    #[inline(always)]
    fn select(mask: bool, a: Vec3, b: Vec3) -> Vec3 {
        if mask { a } else { b }
    }
}

/// Eight pixels: one register per component.
impl Vector for V3 {
    type L = f32x8;
    const WIDTH: usize = LANES;
    #[inline(always)]
    fn uniform(v: Vec3) -> V3 {
        V3::splat(v)
    }
    #[inline(always)]
    fn new(x: f32x8, y: f32x8, z: f32x8) -> V3 {
        V3 { x, y, z }
    }
    #[inline(always)]
    fn dot(self, o: V3) -> f32x8 {
        V3::dot(self, o)
    }
    #[inline(always)]
    fn cross(self, o: V3) -> V3 {
        V3::cross(self, o)
    }
    #[inline(always)]
    fn select(mask: f32x8, a: V3, b: V3) -> V3 {
        V3::select(mask, a, b)
    }
    #[inline(always)]
    fn x(self) -> f32x8 {
        self.x
    }
    #[inline(always)]
    fn y(self) -> f32x8 {
        self.y
    }
    #[inline(always)]
    fn z(self) -> f32x8 {
        self.z
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shade::packet::V3;

    /// The eight-lane operations give each lane the one-lane result, NaN,
    /// infinities and signed zeros included.
    #[test]
    fn eight_lanes_are_eight_single_lanes() {
        let a = [0.0, -0.0, 1.5, -2.25, f32::INFINITY, f32::NAN, 1e-30, 3e38];
        let b = [1.0, 2.0, -0.5, 0.0, 7.0, 1.0, 1e-30, 2.0];
        let (x, y) = (f32x8::from(a), f32x8::from(b));
        let lanes = |v: f32x8| v.to_array().map(f32::to_bits);
        let one = |f: &dyn Fn(f32, f32) -> f32| {
            std::array::from_fn::<u32, 8, _>(|i| f(a[i], b[i]).to_bits())
        };
        assert_eq!(lanes(x.pow_positive(2.5)), one(&|p, _| p.pow_positive(2.5)));
        assert_eq!(lanes(x.pow_lanes(y)), one(&|p, q| p.pow_lanes(q)));
        assert_eq!(
            lanes(<f32x8 as Lanes>::select(Lanes::lt(x, y), x, y)),
            one(&|p, q| if p < q { p } else { q })
        );
        // `both` skips its second condition for one lane only.
        let mut asked = false;
        assert!(!f32::both(false, || {
            asked = true;
            true
        }));
        assert!(!asked);
        let m = <f32x8 as Lanes>::both(Lanes::gt(x, y), || Lanes::lt(x, f32x8::splat(2.0)));
        let want = std::array::from_fn::<bool, 8, _>(|i| a[i] > b[i] && a[i] < 2.0);
        assert_eq!(
            m.to_bitmask(),
            (0..8).filter(|&i| want[i]).map(|i| 1 << i).sum::<u32>()
        );
    }

    /// The eight-lane normal-map read gives each live lane the one-point
    /// read's bits (repeating, clamped; f32 and 16-bit normals; points
    /// past the edges and on them; a map one texel wide), and 0 in the
    /// others.
    #[test]
    fn eight_normal_map_reads_are_eight_single_reads() {
        use relief_texture::sample::wrap::{Wrap, WrapMode};
        let u = [0.0, 0.999, -0.3, 1.7, 0.5, 0.1, -2.05, 0.9];
        let v = [0.0, 0.12, 0.999, -0.6, 0.5, 3.3, 0.75, 1.0];
        let live = 0b1101_1111;
        let cases = [(5, 4), (1, 3)].into_iter();
        for ((w, h), snorm) in cases.flat_map(|size| [(size, false), (size, true)]) {
            let mut level = Level::solid(w, h, [0.5; 4]);
            for (i, t) in level.texels.as_mut_slice().iter_mut().enumerate() {
                t[3] = ((i * 7) % 11) as f32 / 11.0;
            }
            for wrap in [
                Wrap::REPEAT,
                Wrap {
                    s: WrapMode::ClampToEdge,
                    t: WrapMode::MirroredRepeat,
                },
            ] {
                let mut map = NormalMap::build(&level, 3.0);
                if snorm {
                    let n = map.normals.len();
                    let normals = map.normals.clone();
                    map.normals =
                        relief_texture::sample::normal_map::Normals::snorm16(n, |i| normals.at(i));
                }
                map.wrap = wrap;
                let got = packet::normal_bilinear(&map, f32x8::from(u), f32x8::from(v), live);
                for i in 0..8 {
                    let want = if live & (1 << i) != 0 {
                        map.bilinear(u[i], v[i])
                    } else {
                        [0.0; 3]
                    };
                    let lane = [0, 1, 2].map(|k| got[k].as_array()[i].to_bits());
                    assert_eq!(
                        lane,
                        want.map(f32::to_bits),
                        "lane {i}, {wrap:?}, snorm {snorm}, {w}x{h}"
                    );
                }
            }
        }
    }

    #[test]
    fn normalize_or_is_glams_in_every_lane() {
        let vs = [
            Vec3::new(3.0, 4.0, 0.0),
            Vec3::ZERO,
            Vec3::new(f32::NAN, 0.0, 1.0),
            Vec3::new(1e-30, 0.0, 0.0),
            Vec3::new(f32::INFINITY, 1.0, 1.0),
            Vec3::new(-2.0, 0.5, 7.0),
            Vec3::new(1e20, 1e20, 1e20),
            Vec3::new(0.0, -0.0, -1.0),
        ];
        let v = V3 {
            x: f32x8::from(vs.map(|v| v.x)),
            y: f32x8::from(vs.map(|v| v.y)),
            z: f32x8::from(vs.map(|v| v.z)),
        };
        let fallback = Vec3::new(0.0, 1.0, 0.0);
        let got = Vector::normalize_or(v, V3::splat(fallback));
        let (x, y, z) = (got.x.to_array(), got.y.to_array(), got.z.to_array());
        for (i, v) in vs.iter().enumerate() {
            let want = v.normalize_or(fallback);
            assert_eq!(
                [x[i], y[i], z[i]].map(f32::to_bits),
                want.to_array().map(f32::to_bits),
                "{v}"
            );
        }
    }
}
