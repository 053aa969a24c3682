//! Tangents a normal-mapped primitive lacks, made by MikkTSpace as the
//! glTF 2.0 specification asks (§3.7.2.1), and turned into relief's
//! texture axes.

use glam::{Vec2, Vec3};

use crate::scene::mesh::Vertex;

/// Triangles given one vertex per corner (corners 3f, 3f + 1, 3f + 2).
struct Corners<'a> {
    vertices: &'a mut [Vertex],
    /// The normal map's coordinates per corner, when not the vertices' own.
    uvs: Option<&'a [Vec2]>,
}

impl mikktspace::Geometry for Corners<'_> {
    fn num_faces(&self) -> usize {
        self.vertices.len() / 3
    }
    fn num_vertices_of_face(&self, _face: usize) -> usize {
        3
    }
    fn position(&self, face: usize, vert: usize) -> [f32; 3] {
        self.vertices[3 * face + vert].position.to_array()
    }
    fn normal(&self, face: usize, vert: usize) -> [f32; 3] {
        self.vertices[3 * face + vert].normal.to_array()
    }
    fn tex_coord(&self, face: usize, vert: usize) -> [f32; 2] {
        // glTF's v grows down the picture; MikkTSpace's bitangent is to
        // follow the picture's up, the way glTF's normal maps are drawn.
        let k = 3 * face + vert;
        let uv = self.uvs.map_or(self.vertices[k].uv, |u| u[k]);
        [uv.x, 1.0 - uv.y]
    }
    fn set_tangent_encoded(&mut self, t: [f32; 4], face: usize, vert: usize) {
        let v = &mut self.vertices[3 * face + vert];
        (v.tangent_u, v.tangent_v) = axes(Vec3::new(t[0], t[1], t[2]), t[3], v.normal);
    }
}

/// ∂P/∂u and ∂P/∂v directions per corner (unit length) from MikkTSpace,
/// into each vertex's tangent fields (one vertex per corner), of the
/// texture coordinates `uvs` (one per corner) when given, else of the
/// vertices' own; false when it cannot make them (the fields are then left
/// as they are or partly written).
pub(super) fn mikktspace(vertices: &mut [Vertex], uvs: Option<&[Vec2]>) -> bool {
    mikktspace::generate_tangents(&mut Corners { vertices, uvs })
}

/// relief's ∂P/∂u and ∂P/∂v directions from a glTF tangent (xyz, w) and
/// normal: the bitangent w·(N × T) points where v falls, so ∂P/∂v is its
/// opposite.
pub(super) fn axes(t: Vec3, w: f32, n: Vec3) -> (Vec3, Vec3) {
    let sign = if w < 0.0 { -1.0 } else { 1.0 };
    (t, -(n.cross(t) * sign))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// MikkTSpace's axes for one vertex per corner at `p` with `uv`, facing +Z.
    fn axes_of(p: &[Vec3], uv: &[Vec2]) -> Vec<(Vec3, Vec3)> {
        let mut vertices: Vec<Vertex> = p
            .iter()
            .zip(uv)
            .map(|(&position, &uv)| Vertex {
                position,
                normal: Vec3::Z,
                uv,
                color: Vec3::ONE,
                tangent_u: Vec3::ZERO,
                tangent_v: Vec3::ZERO,
            })
            .collect();
        assert!(mikktspace(&mut vertices, None));
        vertices
            .iter()
            .map(|v| (v.tangent_u, v.tangent_v))
            .collect()
    }

    /// Two triangles of a unit quad in z = 0, facing +Z.
    const QUAD: [Vec3; 6] = [
        Vec3::new(0.0, 1.0, 0.0),
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(0.0, 1.0, 0.0),
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(1.0, 1.0, 0.0),
    ];
    /// Their texture coordinates: u along +x, v down the picture (−y).
    const QUAD_UV: [Vec2; 6] = [
        Vec2::new(0.0, 0.0),
        Vec2::new(0.0, 1.0),
        Vec2::new(1.0, 1.0),
        Vec2::new(0.0, 0.0),
        Vec2::new(1.0, 1.0),
        Vec2::new(1.0, 0.0),
    ];

    /// A unit quad in z = 0 facing +Z, u along +x and v down the picture
    /// (along −y): T must be +x, and ∂P/∂v −y (w = +1).
    #[test]
    fn a_quad_gets_its_texture_axes() {
        let axes = axes_of(&QUAD, &QUAD_UV);
        for (pu, pv) in axes {
            assert!(pu.abs_diff_eq(Vec3::X, 1e-5), "{pu}");
            assert!(pv.abs_diff_eq(-Vec3::Y, 1e-5), "{pv}");
        }
    }

    /// The same quad with u mirrored (u along −x): T is −x, ∂P/∂v still −y.
    #[test]
    fn a_mirrored_quad_keeps_its_v_axis() {
        let uv = QUAD_UV.map(|uv| Vec2::new(1.0 - uv.x, uv.y));
        let axes = axes_of(&QUAD, &uv);
        for (pu, pv) in axes {
            assert!(pu.abs_diff_eq(-Vec3::X, 1e-5), "{pu}");
            assert!(pv.abs_diff_eq(-Vec3::Y, 1e-5), "{pv}");
        }
    }
}
