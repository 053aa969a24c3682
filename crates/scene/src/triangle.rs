//! The single triangle of the documented viewer's model list.

use glam::{Vec2, Vec3};

use super::cube::corner_color;
use super::mesh::{Face, Mesh, Vertex};

/// One triangle in the z = 0 plane facing +Z, fitting the cube's front face:
/// corners (−1, −1), (1, −1), (0, 1) with UVs (0, 0), (1, 0), (½, 1), so
/// ∂P/∂u = 2X and ∂P/∂v = 2Y as on the cube. Seen from both sides (not closed).
pub fn triangle() -> Mesh {
    let corners = [
        (Vec3::new(-1.0, -1.0, 0.0), Vec2::new(0.0, 0.0)),
        (Vec3::new(1.0, -1.0, 0.0), Vec2::new(1.0, 0.0)),
        (Vec3::new(0.0, 1.0, 0.0), Vec2::new(0.5, 1.0)),
    ];
    let (tangent_u, tangent_v) = (2.0 * Vec3::X, 2.0 * Vec3::Y);
    let vertices: Vec<Vertex> = corners
        .iter()
        .map(|&(position, uv)| Vertex {
            position,
            normal: Vec3::Z,
            uv,
            color: corner_color(position),
            tangent_u,
            tangent_v,
        })
        .collect();
    let facet_color = vertices.iter().map(|v| v.color).sum::<Vec3>() / 3.0;
    let facet_center = vertices.iter().map(|v| v.position).sum::<Vec3>() / 3.0;
    let faces = [Face {
        indices: [0, 1, 2],
        face_normal: Vec3::Z,
        face_tangent_u: tangent_u,
        face_tangent_v: tangent_v,
        facet_center,
        facet_color,
        textured: true,
    }];
    // One flat triangle never overlaps itself: no depth buffer needed.
    Mesh::new(vertices, &faces, true, false)
}
