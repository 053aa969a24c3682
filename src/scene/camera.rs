//! A right-handed perspective camera.

use glam::{Mat4, Vec3};

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    pub eye: Vec3,
    pub target: Vec3,
    pub up: Vec3,
    /// Vertical field of view in degrees.
    pub fov_y_degrees: f32,
    pub near: f32,
    pub far: f32,
}

impl Default for Camera {
    /// The reference camera: at (0, 0, 5) looking at the origin, 60°.
    fn default() -> Self {
        Camera {
            eye: Vec3::new(0.0, 0.0, 5.0),
            target: Vec3::ZERO,
            up: Vec3::Y,
            fov_y_degrees: 60.0,
            near: 0.1,
            far: 100.0,
        }
    }
}

impl Camera {
    pub fn view(&self) -> Mat4 {
        Mat4::look_at_rh(self.eye, self.target, self.up)
    }

    /// OpenGL-style projection (clip z in −w..w) for a viewport of this aspect.
    pub fn projection(&self, aspect: f32) -> Mat4 {
        let aspect = if aspect.is_finite() && aspect > 0.0 {
            aspect
        } else {
            1.0
        };
        Mat4::perspective_rh_gl(self.fov_y_degrees.to_radians(), aspect, self.near, self.far)
    }
}

/// Distance from the reference camera to what it looks at.
pub const REFERENCE_DISTANCE: f32 = 5.0;
/// Closest the camera comes (zoom): the cube's corners are √3 ≈ 1.73 from
/// its centre and the near plane 0.1 in front of the eye, so at 2.5 no
/// orientation of the cube (nor the 1.5-radius models) reaches the near
/// plane.
pub const MIN_DISTANCE: f32 = 2.5;
/// Farthest the camera goes (the cube is then a few cells wide).
pub const MAX_DISTANCE: f32 = 40.0;

impl Camera {
    /// This camera moved along its line of sight so that it is `distance`
    /// reference units away, scaled from the reference distance: the
    /// reference camera ends `distance` from its target, and a camera that
    /// starts farther (the shadow scene's) keeps its proportion. A distance
    /// that is not finite leaves the camera as it is.
    pub fn at_distance(&self, distance: f32) -> Camera {
        if !distance.is_finite() || distance <= 0.0 {
            return *self;
        }
        let scale = distance.clamp(MIN_DISTANCE, MAX_DISTANCE) / REFERENCE_DISTANCE;
        Camera {
            eye: self.target + (self.eye - self.target) * scale,
            ..*self
        }
    }
}
