//! A mesh placed in the world, and the matrices that place it.

use glam::{Mat3, Mat4, Vec3};

use super::mesh::Mesh;
use relief_core::settings::normalize_degrees;

/// A mesh placed in the world. `rotates` objects follow the user's rotation.
#[derive(Clone, Debug)]
pub struct Object {
    pub mesh: Mesh,
    /// Placement applied after the user's rotation (e.g. a floor's offset).
    pub transform: Mat4,
    /// Whether the user's rotation applies.
    pub rotates: bool,
}

impl Object {
    /// Object space to world space: its placement, after the user's
    /// rotation when it follows it.
    pub fn model_matrix(&self, user_rotation: Mat4) -> Mat4 {
        if self.rotates {
            self.transform * user_rotation
        } else {
            self.transform
        }
    }
}

/// The matrix that carries normals through `model` (the inverse transpose
/// of its linear part). A singular model (an object flattened to a plane
/// or a line) has none: its linear part is used instead, so normals stay
/// finite and the caller's normalisation decides what survives.
pub fn normal_matrix(model: Mat4) -> Mat3 {
    let linear = Mat3::from_mat4(model);
    let inverse_transpose = linear.inverse().transpose();
    if inverse_transpose.is_finite() {
        inverse_transpose
    } else {
        linear
    }
}

/// Model rotation in degrees: about X first, then Y, then Z. Angles are
/// reduced modulo 360 in f64 first; NaN and infinities count as 0.
pub fn rotation_matrix(degrees: Vec3) -> Mat4 {
    let [x, y, z] = degrees
        .to_array()
        .map(|d| normalize_degrees(d).to_radians());
    Mat4::from_rotation_z(z) * Mat4::from_rotation_y(y) * Mat4::from_rotation_x(x)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normals_stay_perpendicular_under_a_stretch() {
        // A plane tilted 45° in XY, stretched 4× along X: its normal must
        // stay perpendicular to the stretched plane, not follow the stretch.
        let model = Mat4::from_scale(Vec3::new(4.0, 1.0, 1.0));
        let (along, normal) = (Vec3::new(1.0, 1.0, 0.0), Vec3::new(1.0, -1.0, 0.0));
        let n = normal_matrix(model) * normal;
        let a = Mat3::from_mat4(model) * along;
        assert!(n.dot(a).abs() < 1e-5, "{n} · {a}");
    }

    #[test]
    fn a_flattened_object_keeps_finite_normals() {
        let model = Mat4::from_scale(Vec3::new(1.0, 1.0, 0.0));
        let m = normal_matrix(model);
        assert!(m.is_finite());
        assert_eq!(m * Vec3::X, Vec3::X);
    }
}
