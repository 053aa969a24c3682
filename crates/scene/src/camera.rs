//! A right-handed camera: perspective, or orthographic for a glTF file's
//! orthographic camera.

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
    /// Half the view's height in world units for an orthographic camera
    /// (glTF's `ymag`), none for a perspective one. Its width follows the
    /// picture's aspect, as a perspective camera's does.
    pub orthographic: Option<f32>,
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
            orthographic: None,
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
        match self.orthographic {
            Some(half) => {
                let (x, y) = (half * aspect, half);
                Mat4::orthographic_rh_gl(-x, x, -y, y, self.near, self.far)
            }
            None => Mat4::perspective_rh_gl(
                self.fov_y_degrees.to_radians(),
                aspect,
                self.near,
                self.far,
            ),
        }
    }

    /// The point the shading takes the eye to be at. For an orthographic
    /// camera, whose view direction is the same at every pixel, a point
    /// `ORTHOGRAPHIC_EYE_DISTANCE` back along its axis: the direction from
    /// a point within a few units of the model to it is then the axis
    /// within 10⁻⁴ radians, below what an 8-bit picture shows.
    pub fn shading_eye(&self) -> Vec3 {
        match self.orthographic {
            Some(_) => {
                let back = (self.eye - self.target).normalize_or_zero();
                self.eye + back * ORTHOGRAPHIC_EYE_DISTANCE
            }
            None => self.eye,
        }
    }
}

/// How far behind an orthographic camera the shading puts its eye
/// (`Camera::shading_eye`).
pub const ORTHOGRAPHIC_EYE_DISTANCE: f32 = 1.0e4;

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

impl Camera {
    /// This camera moved in its view plane so that what it looked at
    /// appears `pan` (world units, x right, y up) away from the centre of
    /// the picture: the pan of the orbit centre (docs/models.md, "Camera").
    pub fn panned(&self, pan: glam::Vec2) -> Camera {
        if !pan.is_finite() || pan == glam::Vec2::ZERO {
            return *self;
        }
        let forward = (self.target - self.eye).normalize_or_zero();
        let right = forward.cross(self.up).normalize_or_zero();
        let up = right.cross(forward);
        let shift = -(right * pan.x + up * pan.y);
        Camera {
            eye: self.eye + shift,
            target: self.target + shift,
            ..*self
        }
    }
}

/// The turn a light drag gives the scene's lights about the origin:
/// `turn.x` degrees about the vertical (a drag to the right moves the
/// light to the right), then `turn.y` about the horizontal (a drag down
/// moves it down), as the reference camera sees them.
pub fn light_turn(turn: glam::Vec2) -> glam::Mat3 {
    if !turn.is_finite() {
        return glam::Mat3::IDENTITY;
    }
    glam::Mat3::from_rotation_y(turn.x.to_radians())
        * glam::Mat3::from_rotation_x(turn.y.to_radians())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_pan_shifts_the_target_in_the_view_plane() {
        let c = Camera::default().panned(glam::Vec2::new(0.5, -0.25));
        // The reference camera looks down −Z with +Y up: right is +X.
        assert_eq!(c.eye, Vec3::new(-0.5, 0.25, 5.0));
        assert_eq!(c.target, Vec3::new(-0.5, 0.25, 0.0));
        let p = c.projection(1.0) * c.view() * glam::Vec4::new(0.0, 0.0, 0.0, 1.0);
        assert!(
            p.x > 0.0 && p.y < 0.0,
            "the origin moves right and down: {p}"
        );
    }

    #[test]
    fn a_light_turn_moves_a_light_in_front_right_and_down() {
        let m = light_turn(glam::Vec2::new(90.0, 0.0));
        assert!((m * Vec3::Z - Vec3::X).length() < 1e-6);
        let m = light_turn(glam::Vec2::new(0.0, 90.0));
        assert!((m * Vec3::Z + Vec3::Y).length() < 1e-6);
    }
}
