//! Diffuse lighting: ambient + Σ colour · max(0, N·L); with highlights,
//! also Σ colour · (N·H)^s (docs/specular.md).

use glam::Vec3;

use super::specular::blinn_phong;
use crate::plan::ActiveLight;

/// Distance attenuation 1 / (1 + c·d²); c keeps the reference scene readable
/// (about 0.6 at the white light's distance).
pub const ATTENUATION_QUADRATIC: f32 = 0.01;

/// The light reaching a point `p` with unit normal `n` (RGB, not clamped).
/// A light exactly at `p` (distance 0) has no direction and adds nothing.
#[inline]
pub fn diffuse(lights: &[ActiveLight], ambient: Vec3, p: Vec3, n: Vec3, attenuation: bool) -> Vec3 {
    diffuse_with(lights, ambient, p, n, attenuation, |_| 1.0)
}

/// `diffuse` with each lit light's contribution scaled by `visibility(i)`
/// (its shadow), asked only where light `i` faces the point.
#[inline]
pub fn diffuse_with(
    lights: &[ActiveLight],
    ambient: Vec3,
    p: Vec3,
    n: Vec3,
    attenuation: bool,
    visibility: impl FnMut(usize) -> f32,
) -> Vec3 {
    light_with::<false>(
        lights,
        ambient,
        p,
        n,
        attenuation,
        Vec3::ZERO,
        0.0,
        visibility,
    )
    .0
}

/// The one light loop: the diffuse sum and, when `SPEC`, the Blinn-Phong
/// highlights seen from the unit direction `view` with exponent `shininess`
/// (unused otherwise). A light adds to both only where it faces the point,
/// both scaled by the same attenuation and `visibility(i)` (asked once).
#[allow(clippy::too_many_arguments)]
#[inline]
pub fn light_with<const SPEC: bool>(
    lights: &[ActiveLight],
    ambient: Vec3,
    p: Vec3,
    n: Vec3,
    attenuation: bool,
    view: Vec3,
    shininess: f32,
    mut visibility: impl FnMut(usize) -> f32,
) -> (Vec3, Vec3) {
    let mut sum = ambient;
    let mut highlight = Vec3::ZERO;
    for (i, light) in lights.iter().enumerate() {
        let d = light.position - p;
        let ndl = n.dot(d);
        // Test the sign before normalising: most back-lit points stop here.
        if ndl > 0.0 {
            let len2 = d.length_squared();
            if len2 > 0.0 && len2.is_finite() {
                let mut k = ndl / len2.sqrt();
                let mut ks = if SPEC {
                    blinn_phong(n, d, len2, view, shininess)
                } else {
                    0.0
                };
                if attenuation {
                    k /= 1.0 + ATTENUATION_QUADRATIC * len2;
                    if SPEC {
                        ks /= 1.0 + ATTENUATION_QUADRATIC * len2;
                    }
                }
                let seen = visibility(i);
                sum += light.color * (k.min(1.0) * seen);
                if SPEC {
                    highlight += light.color * (ks.min(1.0) * seen);
                }
            }
        }
    }
    (sum, highlight)
}

/// Quantises a shaded colour, counting any non-finite one (tests assert
/// the count stays 0; the pixel still gets a defined value).
#[inline]
pub fn finish(c: Vec3, counters: &mut crate::stats::Counters) -> [u8; 3] {
    if !c.is_finite() {
        counters.nonfinite += 1;
    }
    to_rgb8(c)
}

/// Clamps to 0..1 and rounds to 8 bits. NaN becomes 0 (`max` drops NaN,
/// which `clamp` would keep).
#[inline]
pub fn to_rgb8(c: Vec3) -> [u8; 3] {
    #[allow(clippy::manual_clamp)]
    let q = |x: f32| (x.max(0.0).min(1.0) * 255.0 + 0.5) as u8;
    [q(c.x), q(c.y), q(c.z)]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn light(p: Vec3) -> ActiveLight {
        ActiveLight {
            position: p,
            color: Vec3::ONE,
        }
    }

    #[test]
    fn head_on_light_gives_full_colour() {
        let l = [light(Vec3::new(0.0, 0.0, 10.0))];
        let c = diffuse(&l, Vec3::splat(0.1), Vec3::ZERO, Vec3::Z, false);
        assert!((c - Vec3::splat(1.1)).length() < 1e-6);
    }

    #[test]
    fn light_at_the_point_and_behind_adds_nothing() {
        let l = [light(Vec3::ZERO), light(Vec3::new(0.0, 0.0, -3.0))];
        assert_eq!(
            diffuse(&l, Vec3::ZERO, Vec3::ZERO, Vec3::Z, false),
            Vec3::ZERO
        );
    }

    #[test]
    fn grazing_light_is_zero_and_finite() {
        let l = [light(Vec3::new(5.0, 0.0, 0.0))];
        let c = diffuse(&l, Vec3::ZERO, Vec3::ZERO, Vec3::Z, false);
        assert_eq!(c, Vec3::ZERO);
    }

    #[test]
    fn quantisation_rounds_clamps_and_drops_nan() {
        assert_eq!(to_rgb8(Vec3::new(0.5, 2.0, -1.0)), [128, 255, 0]);
        assert_eq!(
            to_rgb8(Vec3::new(f32::NAN, f32::INFINITY, f32::NEG_INFINITY)),
            [0, 255, 0]
        );
    }
}
