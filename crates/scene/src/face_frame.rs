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
    let inv = 1.0 / uv_determinant(uv)?;
    let tu = (e1 * d2.y - e2 * d1.y) * inv;
    let tv = (e2 * d1.x - e1 * d2.x) * inv;
    if !tu.is_finite() || !tv.is_finite() {
        return None;
    }
    Some((tu, tv))
}

/// The determinant of a triangle's UV edges, `None` when it is degenerate:
/// zero, not finite, or tiny beside the edges (a relative threshold, so UV
/// spans of any scale are judged alike).
fn uv_determinant(uv: [Vec2; 3]) -> Option<f32> {
    let (d1, d2) = (uv[1] - uv[0], uv[2] - uv[0]);
    let det = d1.x * d2.y - d2.x * d1.y;
    let scale = (d1.length_squared() * d2.length_squared()).sqrt();
    (det.is_finite() && det.abs() > 1e-7 * scale && scale != 0.0).then_some(det)
}

/// Whether a triangle's texture axes are mirrored: ∂P/∂u × ∂P/∂v is the
/// triangle's normal divided by the UV determinant, so it points against
/// the normal exactly when the determinant is negative. A frame made from
/// the normal (degenerate UVs) is right-handed. Needs no positions.
pub fn uv_mirrored(uv: [Vec2; 3]) -> bool {
    uv_determinant(uv).is_some_and(|det| det < 0.0)
}

/// Any unit vector perpendicular to `n` (for a tangent frame when UVs give none).
pub fn any_perpendicular(n: Vec3) -> Vec3 {
    let helper = if n.x.abs() < 0.9 { Vec3::X } else { Vec3::Y };
    n.cross(helper).normalize_or(Vec3::X)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn point() -> impl Strategy<Value = Vec3> {
        (-2.0f32..2.0, -2.0f32..2.0, -2.0f32..2.0).prop_map(|(x, y, z)| Vec3::new(x, y, z))
    }

    fn uv() -> impl Strategy<Value = Vec2> {
        (-3.0f32..3.0, -3.0f32..3.0).prop_map(|(u, v)| Vec2::new(u, v))
    }

    #[test]
    fn a_quad_mapped_backwards_is_mirrored() {
        let uv = [Vec2::ZERO, Vec2::X, Vec2::Y];
        assert!(!uv_mirrored(uv));
        assert!(uv_mirrored(uv.map(|t| Vec2::new(1.0 - t.x, t.y))));
        // Degenerate UVs give a frame from the normal: right-handed.
        assert!(!uv_mirrored([Vec2::ZERO, Vec2::X, Vec2::X * 2.0]));
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(2000))]

        /// The flag read from the UVs alone is the handedness of the frame
        /// made from positions and UVs.
        #[test]
        fn the_uv_flag_is_the_frames_handedness(
            p in [point(), point(), point()],
            uv in [uv(), uv(), uv()],
        ) {
            let normal = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
            prop_assume!(normal != Vec3::ZERO);
            let frame = face_frame(p, uv, normal);
            prop_assert_eq!(uv_mirrored(uv), frame.handedness(normal) < 0.0);
        }
    }
}
