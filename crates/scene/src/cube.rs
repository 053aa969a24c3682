//! The reference cube of the documented software renderer.

use glam::{Vec2, Vec3};

use super::mesh::{Face, Mesh, Vertex};

/// The six faces: normal N and texture axes U, V with U × V = N.
pub const FACES: [(Vec3, Vec3, Vec3); 6] = [
    (Vec3::X, Vec3::NEG_Z, Vec3::Y),
    (Vec3::NEG_X, Vec3::Z, Vec3::Y),
    (Vec3::Y, Vec3::X, Vec3::NEG_Z),
    (Vec3::NEG_Y, Vec3::X, Vec3::Z),
    (Vec3::Z, Vec3::X, Vec3::Y),
    (Vec3::NEG_Z, Vec3::NEG_X, Vec3::Y),
];

/// Per-vertex colour of the reference scene: 0.4 + 0.3·(p + 1) per component.
pub fn corner_color(p: Vec3) -> Vec3 {
    Vec3::splat(0.4) + 0.3 * (p + Vec3::ONE)
}

/// Cube of side 2 at the origin, 24 vertices, 12 triangles, counter-clockwise
/// from outside. The texture applies to the front (+Z) and back (−Z) faces,
/// or to all six with `all_faces`.
pub fn cube(all_faces: bool) -> Mesh {
    let mut vertices = Vec::with_capacity(24);
    let mut triangles = Vec::with_capacity(12);
    for (n, u, v) in FACES {
        let base = vertices.len() as u32;
        let corners = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)];
        let mut color_sum = Vec3::ZERO;
        for (s, t) in corners {
            let position = n + u * (2.0 * s - 1.0) + v * (2.0 * t - 1.0);
            let color = corner_color(position);
            color_sum += color;
            vertices.push(Vertex {
                position,
                // The averaged normal of the three faces meeting at a corner.
                normal: position.normalize(),
                uv: Vec2::new(s, t),
                color,
                tangent_u: 2.0 * u,
                tangent_v: 2.0 * v,
            });
        }
        let textured = all_faces || n.z != 0.0;
        let facet = Face {
            indices: [0; 3],
            face_normal: n,
            face_tangent_u: 2.0 * u,
            face_tangent_v: 2.0 * v,
            facet_center: n,
            facet_color: color_sum / 4.0,
            textured,
        };
        // Split along the (0,0)–(1,1) diagonal.
        triangles.push(Face {
            indices: [base, base + 1, base + 2],
            ..facet
        });
        triangles.push(Face {
            indices: [base, base + 2, base + 3],
            ..facet
        });
    }
    Mesh::new(vertices, &triangles, true, true)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn faces_are_right_handed_and_counter_clockwise() {
        let mesh = cube(false);
        assert_eq!(mesh.vertices.len(), 24);
        assert_eq!(mesh.triangles.len(), 12);
        for (n, u, v) in FACES {
            assert_eq!(u.cross(v), n);
        }
        for (t, tri) in mesh.triangles.iter().enumerate() {
            let [a, b, c] = tri.indices.map(|i| mesh.vertices[i as usize].position);
            let geometric = (b - a).cross(c - a).normalize();
            assert!((geometric - mesh.face_normal(t)).length() < 1e-6);
        }
    }

    #[test]
    fn only_front_and_back_are_textured_by_default() {
        let mesh = cube(false);
        let textured: Vec<Vec3> = (0..mesh.triangles.len())
            .filter(|&t| mesh.triangles[t].textured)
            .map(|t| mesh.face_normal(t))
            .collect();
        assert_eq!(textured.len(), 4);
        assert!(textured.iter().all(|n| n.z.abs() == 1.0));
        assert!(cube(true).triangles.iter().all(|t| t.textured));
    }
}
