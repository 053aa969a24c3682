//! Tangents a normal-mapped primitive lacks, made by MikkTSpace as the
//! glTF 2.0 specification asks (§3.7.2.1), and turned into relief's
//! texture axes.

use glam::{Vec2, Vec3};

use crate::mesh::Vertex;

/// Triangles given one vertex per corner (corners 3f, 3f + 1, 3f + 2), of
/// which MikkTSpace sees only `faces`.
struct Corners<'a> {
    vertices: &'a mut [Vertex],
    /// The normal map's coordinates per corner, when not the vertices' own.
    uvs: Option<&'a [Vec2]>,
    /// The triangles handed to MikkTSpace, by their index among all.
    faces: &'a [usize],
}

impl Corners<'_> {
    /// The corner `vert` of MikkTSpace's face `face`, among all corners.
    fn corner(&self, face: usize, vert: usize) -> usize {
        3 * self.faces[face] + vert
    }
}

impl mikktspace::Geometry for Corners<'_> {
    fn num_faces(&self) -> usize {
        self.faces.len()
    }
    fn num_vertices_of_face(&self, _face: usize) -> usize {
        3
    }
    fn position(&self, face: usize, vert: usize) -> [f32; 3] {
        self.vertices[self.corner(face, vert)].position.to_array()
    }
    fn normal(&self, face: usize, vert: usize) -> [f32; 3] {
        self.vertices[self.corner(face, vert)].normal.to_array()
    }
    fn tex_coord(&self, face: usize, vert: usize) -> [f32; 2] {
        flipped(uv_at(self.vertices, self.uvs, self.corner(face, vert)))
    }
    fn set_tangent_encoded(&mut self, t: [f32; 4], face: usize, vert: usize) {
        let v = &mut self.vertices[self.corner(face, vert)];
        (v.tangent_u, v.tangent_v) = axes(Vec3::new(t[0], t[1], t[2]), t[3], v.normal);
    }
}

/// The normal map's coordinates of corner `k`.
fn uv_at(vertices: &[Vertex], uvs: Option<&[Vec2]>, k: usize) -> Vec2 {
    uvs.map_or(vertices[k].uv, |u| u[k])
}

/// glTF's v grows down the picture; MikkTSpace's bitangent is to follow
/// the picture's up, the way glTF's normal maps are drawn.
fn flipped(uv: Vec2) -> [f32; 2] {
    [uv.x, 1.0 - uv.y]
}

/// Whether MikkTSpace may be given triangle `f`: every value it reads is
/// finite and its three points span an area. The `mikktspace` crate reads
/// memory it does not own (and may fault) on triangles whose corners
/// coincide, so none reaches it; such a triangle has no area to draw
/// either (the mesh drops it), and one with an area keeps its tangents.
fn takes(vertices: &[Vertex], uvs: Option<&[Vec2]>, f: usize) -> bool {
    let k = [3 * f, 3 * f + 1, 3 * f + 2];
    let finite = k.iter().all(|&k| {
        let v = &vertices[k];
        v.position.is_finite() && v.normal.is_finite() && uv_at(vertices, uvs, k).is_finite()
    });
    let p = k.map(|k| vertices[k].position);
    let area = (p[1] - p[0]).cross(p[2] - p[0]);
    finite && area.is_finite() && area != Vec3::ZERO && p[0] != p[1] && p[1] != p[2] && p[0] != p[2]
}

/// ∂P/∂u and ∂P/∂v directions per corner (unit length) from MikkTSpace,
/// into each vertex's tangent fields (one vertex per corner), of the
/// texture coordinates `uvs` (one per corner) when given, else of the
/// vertices' own; false when it cannot make them (the fields are then left
/// as they are or partly written). Only the triangles MikkTSpace can take
/// ([`takes`]) are given to it; the others' corners keep their fields.
pub(super) fn mikktspace(vertices: &mut [Vertex], uvs: Option<&[Vec2]>) -> bool {
    let count = vertices.len() / 3;
    let faces: Vec<usize> = (0..count).filter(|&f| takes(vertices, uvs, f)).collect();
    if faces.is_empty() {
        return false;
    }
    let faces = &faces;
    mikktspace::generate_tangents(&mut Corners {
        vertices,
        uvs,
        faces,
    })
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
    use proptest::prelude::*;

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

    /// A vertex at `p` facing `normal` with `uv`, no axes yet.
    fn vertex(p: Vec3, normal: Vec3, uv: Vec2) -> Vertex {
        Vertex {
            position: p,
            normal,
            uv,
            color: Vec3::ONE,
            tangent_u: Vec3::ZERO,
            tangent_v: Vec3::ZERO,
        }
    }

    /// Triangles that repeat a corner (the file that made the `mikktspace`
    /// crate fault) are not handed to it: all of them, or one among good ones.
    #[test]
    fn repeated_corners_are_left_out() {
        let p = Vec3::new(0.0, 0.0, 1.0);
        let same = vertex(p, Vec3::Z, Vec2::ZERO);
        let mut all_bad = vec![same; 3 * 1000];
        assert!(!mikktspace(&mut all_bad, None));
        let mut one_bad = vec![same; 3];
        assert!(!mikktspace(&mut one_bad, None));
        let mut mixed: Vec<Vertex> = QUAD
            .iter()
            .zip(QUAD_UV)
            .map(|(&p, uv)| vertex(p, Vec3::Z, uv))
            .collect();
        mixed.extend([same; 6]);
        assert!(mikktspace(&mut mixed, None));
        for v in &mixed[..6] {
            assert!(v.tangent_u.abs_diff_eq(Vec3::X, 1e-5), "{}", v.tangent_u);
        }
        for v in &mixed[6..] {
            assert_eq!((v.tangent_u, v.tangent_v), (Vec3::ZERO, Vec3::ZERO));
        }
    }

    /// Values drawn from a few, so that corners coincide often; now and
    /// then not finite.
    fn value() -> impl Strategy<Value = f32> {
        prop_oneof![
            8 => (0..4u8).prop_map(f32::from),
            4 => -1e3f32..1e3,
            1 => Just(f32::NAN),
            1 => Just(f32::INFINITY),
            1 => Just(3e38f32),
            1 => Just(1e-30f32),
        ]
    }

    fn any_vertex() -> impl Strategy<Value = Vertex> {
        let v3 = || (value(), value(), value()).prop_map(|(x, y, z)| Vec3::new(x, y, z));
        let v2 = (value(), value()).prop_map(|(x, y)| Vec2::new(x, y));
        (v3(), v3(), v2).prop_map(|(p, n, uv)| vertex(p, n, uv))
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(3000))]

        /// Random meshes, degenerate, coincident, huge and non-finite ones
        /// among them, never fault nor panic, and the corners of triangles
        /// MikkTSpace is not given keep their fields.
        #[test]
        fn random_meshes_are_safe(
            mut corners in prop::collection::vec(any_vertex(), 0..60),
            second in prop::bool::ANY,
        ) {
            corners.truncate(corners.len() / 3 * 3);
            let uvs: Option<Vec<Vec2>> = second.then(|| corners.iter().map(|v| v.uv * 0.5).collect());
            let before = corners.clone();
            mikktspace(&mut corners, uvs.as_deref());
            for f in 0..before.len() / 3 {
                if !takes(&before, uvs.as_deref(), f) {
                    for v in &corners[3 * f..3 * f + 3] {
                        prop_assert_eq!(v.tangent_u, Vec3::ZERO);
                        prop_assert_eq!(v.tangent_v, Vec3::ZERO);
                    }
                }
            }
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
