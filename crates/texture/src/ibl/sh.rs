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
/// (`shade::pbr::irradiance` evaluates the same polynomials per lane.)
pub fn basis(x: f32, y: f32, z: f32) -> [f32; 9] {
    [
        0.282_094_8,
        0.488_602_5 * y,
        0.488_602_5 * z,
        0.488_602_5 * x,
        1.092_548_4 * x * y,
        1.092_548_4 * y * z,
        0.315_391_57 * (3.0 * z * z - 1.0),
        1.092_548_4 * x * z,
        0.546_274_2 * (x * x - y * y),
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
