//! Diffuse light from an environment as nine spherical-harmonic
//! coefficients (Ramamoorthi and Hanrahan, "An Efficient Representation for
//! Irradiance Environment Maps", 2001): the radiance projected on the real
//! SH basis of bands 0–2, each band scaled by the clamped cosine's
//! convolution (π, 2π/3, π/4) and divided by π, so `irradiance(N)` is what
//! a white Lambert surface facing N sends back (a uniform radiance L gives
//! L). Band 2 keeps the irradiance within about 3 % of the exact integral
//! for any environment (their paper's bound).

use glam::Vec3;

use super::source::Source;
use crate::shade::lanes::{Lanes, Vector};

/// The bands' cosine-convolution factors over π, per coefficient.
const BAND: [f32; 9] = [
    1.0,
    2.0 / 3.0,
    2.0 / 3.0,
    2.0 / 3.0,
    0.25,
    0.25,
    0.25,
    0.25,
    0.25,
];

/// The real SH basis of bands 0–2 at unit direction (x, y, z), in the
/// order Y00, Y1−1, Y10, Y11, Y2−2, Y2−1, Y20, Y21, Y22.
#[inline(always)]
fn basis<L: Lanes>(x: L, y: L, z: L) -> [L; 9] {
    let c = L::splat;
    [
        c(0.282_094_8),
        c(0.488_602_5) * y,
        c(0.488_602_5) * z,
        c(0.488_602_5) * x,
        c(1.092_548_4) * x * y,
        c(1.092_548_4) * y * z,
        c(0.315_391_57) * (c(3.0) * z * z - L::ONE),
        c(1.092_548_4) * x * z,
        c(0.546_274_2) * (x * x - y * y),
    ]
}

/// The nine coefficients of `source`'s irradiance (over π), with the
/// texels' solid angles as weights.
pub fn project(source: &Source) -> [Vec3; 9] {
    let mut c = [Vec3::ZERO; 9];
    for (d, d_omega, radiance) in source.texels_with_solid_angles() {
        let y = basis(d.x, d.y, d.z);
        for (ci, yi) in c.iter_mut().zip(y) {
            *ci += radiance * (yi * d_omega);
        }
    }
    for (ci, band) in c.iter_mut().zip(BAND) {
        *ci *= band;
    }
    c
}

/// The irradiance over π at unit normals `n`: nine multiply-adds per
/// channel; never below 0 (the truncated series can ring below 0 opposite
/// a bright light).
#[inline(always)]
pub fn irradiance<V: Vector>(c: &[Vec3; 9], n: V) -> V {
    let y = basis(n.x(), n.y(), n.z());
    let mut sum = V::uniform(c[0]) * y[0];
    for i in 1..9 {
        sum = sum + V::uniform(c[i]) * y[i];
    }
    let zero = V::L::ZERO;
    let pos = |x: V::L| V::L::select(x.gt(zero), x, zero);
    V::new(pos(sum.x()), pos(sum.y()), pos(sum.z()))
}
