//! The built-in studio environment (docs/shading.md, "Image-based light"):
//! the light a model is shown in when no `--environment-map` is given, made
//! here from a few shapes rather than copied from a photograph. Linear
//! radiance, the same conventions as every environment
//! (`texture::environment`: +Y up, the camera at +Z looking down −Z).
//!
//! A soft bright area overhead, a large softbox up, left and in front (on
//! the side of the model view's key light), a smaller one behind and to the
//! right (a rim), mid-grey walls toward the horizon and a darker floor, so
//! a smooth metal shows bright shapes and a horizon line to read its form
//! by, and a rough one a gentle gradient from top to bottom.

use glam::Vec3;

/// Width and height of the studio's picture (1.4° a texel).
pub const STUDIO_SIZE: (usize, usize) = (256, 128);

/// The radiance of the walls at the horizon and high up, and the floor's.
const WALL_LOW: f32 = 0.30;
const WALL_HIGH: f32 = 0.22;
const FLOOR: f32 = 0.06;
/// The overhead area's radiance at the zenith, falling to the walls'
/// 40° away.
const OVERHEAD: f32 = 1.2;

/// A rectangular softbox: its centre direction's azimuth and elevation
/// (degrees), half its width and height (degrees) and its radiance.
struct Softbox {
    azimuth: f32,
    elevation: f32,
    half_width: f32,
    half_height: f32,
    radiance: f32,
}

/// Azimuth 0 is the camera's side (+Z), 90° its right (+X).
const SOFTBOXES: [Softbox; 2] = [
    Softbox {
        azimuth: -35.0,
        elevation: 30.0,
        half_width: 22.0,
        half_height: 14.0,
        radiance: 2.2,
    },
    Softbox {
        azimuth: 150.0,
        elevation: 25.0,
        half_width: 12.0,
        half_height: 10.0,
        radiance: 1.4,
    },
];

/// The studio's radiance in direction `d` (any length; a zero direction
/// reads the horizon).
pub fn studio(d: Vec3) -> Vec3 {
    let d = d.normalize_or(Vec3::NEG_Z);
    let elevation = d.y.clamp(-1.0, 1.0).asin().to_degrees();
    let azimuth = d.x.atan2(d.z).to_degrees();
    // Walls darken upward; the floor meets them over 3° of soft edge.
    let wall = WALL_LOW + (WALL_HIGH - WALL_LOW) * (elevation / 90.0).max(0.0);
    let floor_share = smoothstep(1.5, -1.5, elevation);
    let mut radiance = wall + (FLOOR - wall) * floor_share;
    let zenith_angle = 90.0 - elevation;
    radiance += (OVERHEAD - WALL_HIGH) * smoothstep(40.0, 10.0, zenith_angle);
    for b in &SOFTBOXES {
        let da = wrap_degrees(azimuth - b.azimuth).abs();
        let de = (elevation - b.elevation).abs();
        // Edges soft over 2°, so the prefiltered levels do not ring.
        let inside = smoothstep(b.half_width + 1.0, b.half_width - 1.0, da)
            * smoothstep(b.half_height + 1.0, b.half_height - 1.0, de);
        radiance += (b.radiance - radiance) * inside;
    }
    Vec3::splat(radiance)
}

/// An angle in degrees brought into −180..180.
fn wrap_degrees(a: f32) -> f32 {
    (a + 180.0).rem_euclid(360.0) - 180.0
}

/// 0 at `edge0`, 1 at `edge1`, smooth between (either order).
fn smoothstep(edge0: f32, edge1: f32, x: f32) -> f32 {
    let t = ((x - edge0) / (edge1 - edge0)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_studio_is_bright_above_and_dark_below() {
        assert!((studio(Vec3::Y).x - OVERHEAD).abs() < 1e-6);
        assert!((studio(Vec3::NEG_Y).x - FLOOR).abs() < 1e-6);
        // The horizon is half-way through the soft edge between wall and floor.
        assert!((studio(Vec3::X).x - (WALL_LOW + FLOOR) / 2.0).abs() < 1e-6);
        // The key softbox's centre: azimuth −35°, elevation 30°.
        let (a, e) = ((-35.0f32).to_radians(), 30.0f32.to_radians());
        let d = Vec3::new(e.cos() * a.sin(), e.sin(), e.cos() * a.cos());
        assert!((studio(d).x - 2.2).abs() < 1e-5, "{}", studio(d));
        assert!(studio(Vec3::ZERO).is_finite());
    }
}
