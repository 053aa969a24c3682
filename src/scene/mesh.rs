//! Triangle meshes with everything the shaders interpolate.

use glam::{Vec2, Vec3};

/// One vertex. Vertices are split wherever a face needs its own UVs or
/// tangents (a cube has 24), so hard edges stay hard.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Vertex {
    pub position: Vec3,
    /// Smooth normal (averaged over the faces that meet here), unit length.
    pub normal: Vec3,
    pub uv: Vec2,
    /// Per-vertex colour in 0..1.
    pub color: Vec3,
    /// ∂P/∂u and ∂P/∂v: the surface's texture axes scaled to model units
    /// (for a cube face of side 2: 2U and 2V).
    pub tangent_u: Vec3,
    pub tangent_v: Vec3,
}

/// One triangle, counter-clockwise seen from outside, with its facet data.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Triangle {
    pub indices: [u32; 3],
    /// Normal of the facet (the polygon this triangle belongs to), unit length.
    pub face_normal: Vec3,
    /// ∂P/∂u, ∂P/∂v of the facet.
    pub face_tangent_u: Vec3,
    pub face_tangent_v: Vec3,
    /// Centre of the facet: flat shading lights the whole facet from here.
    pub facet_center: Vec3,
    /// Mean colour of the facet's vertices: flat shading paints it.
    pub facet_color: Vec3,
    /// Whether the material's texture and height map apply to this triangle.
    pub textured: bool,
}

/// A mesh in model space.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    pub vertices: Vec<Vertex>,
    pub triangles: Vec<Triangle>,
    /// A closed convex surface: with back-face culling no two visible
    /// triangles overlap, so no depth buffer is needed.
    pub convex: bool,
    /// A closed surface: back faces can never be seen from outside, so they are culled.
    pub closed: bool,
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
