//! The texture axes of one triangle: ∂P/∂u and ∂P/∂v from its positions
//! and UVs, or a frame from its normal when the UVs say nothing. Both the
//! mesh (a facet's data, computed when drawn) and the per-vertex sums
//! (`tangents`) start from it.

use glam::{Vec2, Vec3};

/// The texture axes of one face.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FaceFrame {
    /// ∂P/∂u, in model units per unit of u.
    pub tangent_u: Vec3,
    /// ∂P/∂v.
    pub tangent_v: Vec3,
    /// False when the UVs were degenerate (zero determinant) and the frame
    /// was made up from the normal alone.
    pub from_uv: bool,
}

impl FaceFrame {
    /// +1 for a right-handed frame (Pu × Pv along the normal), −1 for mirrored UVs.
    pub fn handedness(&self, normal: Vec3) -> f32 {
        if self.tangent_u.cross(self.tangent_v).dot(normal) < 0.0 {
            -1.0
        } else {
            1.0
        }
    }
}

/// A unit frame in the plane perpendicular to `normal`, right-handed
/// (tangent_u × tangent_v = normal): what a face or vertex gets when its UVs
/// say nothing.
pub fn frame_from_normal(normal: Vec3) -> FaceFrame {
    let n = normal.normalize_or(Vec3::Z);
    let tangent_u = any_perpendicular(n);
    FaceFrame {
        tangent_u,
        tangent_v: n.cross(tangent_u),
        from_uv: false,
    }
}

/// The frame of one triangle: ∂P/∂u, ∂P/∂v from its UVs, or, when the UV
/// determinant is zero, a unit frame built from the face normal.
pub fn face_frame(p: [Vec3; 3], uv: [Vec2; 3], normal: Vec3) -> FaceFrame {
    match triangle_tangents(p, uv) {
        Some((tangent_u, tangent_v)) => FaceFrame {
            tangent_u,
            tangent_v,
            from_uv: true,
        },
        None => frame_from_normal(normal),
    }
}

/// ∂P/∂u and ∂P/∂v of a triangle from its positions and UVs, or `None`
/// when the UVs are degenerate (zero determinant).
pub fn triangle_tangents(p: [Vec3; 3], uv: [Vec2; 3]) -> Option<(Vec3, Vec3)> {
    let (e1, e2) = (p[1] - p[0], p[2] - p[0]);
    let (d1, d2) = (uv[1] - uv[0], uv[2] - uv[0]);
    let det = d1.x * d2.y - d2.x * d1.y;
    // Relative threshold: UV spans of any scale are judged alike.
    let scale = (d1.length_squared() * d2.length_squared()).sqrt();
    if !det.is_finite() || det.abs() <= 1e-7 * scale || scale == 0.0 {
        return None;
    }
    let inv = 1.0 / det;
    let tu = (e1 * d2.y - e2 * d1.y) * inv;
    let tv = (e2 * d1.x - e1 * d2.x) * inv;
    if !tu.is_finite() || !tv.is_finite() {
        return None;
    }
    Some((tu, tv))
}

/// Any unit vector perpendicular to `n` (for a tangent frame when UVs give none).
pub fn any_perpendicular(n: Vec3) -> Vec3 {
    let helper = if n.x.abs() < 0.9 { Vec3::X } else { Vec3::Y };
    n.cross(helper).normalize_or(Vec3::X)
}
