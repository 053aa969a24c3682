//! Distance attenuation of point lights (`--attenuation on`).
//!
//! 1 / (1 + a·d + b·d²), the classic constant-linear-quadratic falloff
//! (seed 004 lists attenuation as the second factor of a light's
//! contribution). The constants keep the reference scene readable: its
//! lights are 6 to 10 units from the cube, where the factor is 0.68 to 0.5,
//! so the near and far faces of the cube differ visibly without the scene
//! going dark.

/// a: the linear term, per unit of distance.
pub const LINEAR: f32 = 0.05;
/// b: the quadratic term, per unit of distance squared.
pub const QUADRATIC: f32 = 0.005;

/// The factor applied to a light `distance` units away: 1 at the light,
/// falling smoothly toward 0; 0 for an infinite or NaN distance.
pub fn attenuation(distance: f32) -> f32 {
    if distance.is_nan() {
        return 0.0;
    }
    let d = distance.max(0.0);
    let f = 1.0 / (1.0 + LINEAR * d + QUADRATIC * d * d);
    if f.is_finite() { f } else { 0.0 }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn falls_from_one_and_stays_in_range() {
        assert_eq!(attenuation(0.0), 1.0);
        assert_eq!(attenuation(-3.0), 1.0);
        assert_eq!(attenuation(f32::INFINITY), 0.0);
        assert_eq!(attenuation(f32::NAN), 0.0);
        assert_eq!(attenuation(f32::MAX), 0.0);
        let mut last = 1.0;
        for d in 1..200 {
            let f = attenuation(d as f32 * 0.5);
            assert!(f < last && f > 0.0);
            last = f;
        }
        // The reference scene's range stays readable.
        let white = attenuation(glam::Vec3::new(3.0, 4.0, 6.0).length());
        assert!((0.55..0.7).contains(&white), "{white}");
    }
}
