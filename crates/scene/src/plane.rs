//! A flat square: the documented viewer's "plane" model, and (as a grid)
//! the floor of the shadow scene.

use glam::{Vec2, Vec3};

use super::cube::corner_color;
use super::mesh::{Face, Mesh, Vertex};

/// A square of side 2 in the z = 0 plane facing +Z, texture axes U = X,
/// V = Y as on the cube's front face, split along its (0,0)–(1,1) diagonal
/// like the cube faces. Seen from both sides (not closed).
pub fn plane() -> Mesh {
    grid(1.0, 1.0, 1, corner_color)
}

/// A square of side `2·half` facing +Z made of `cells × cells` squares, each
/// a facet split like the cube faces; the texture repeats `repeats` times
/// across (coordinates wrap), so |∂P/∂u| = |∂P/∂v| = 2·half/repeats.
/// `color` gives the vertex colour from the position scaled to −1..1.
pub fn grid(half: f32, repeats: f32, cells: u32, color: fn(Vec3) -> Vec3) -> Mesh {
    let cells = cells.max(1);
    let (u_axis, v_axis) = (Vec3::X, Vec3::Y);
    let tangent_u = u_axis * (2.0 * half / repeats);
    let tangent_v = v_axis * (2.0 * half / repeats);
    let mut vertices = Vec::with_capacity(((cells + 1) * (cells + 1)) as usize);
    for j in 0..=cells {
        for i in 0..=cells {
            let (s, t) = (i as f32 / cells as f32, j as f32 / cells as f32);
            let unit = u_axis * (2.0 * s - 1.0) + v_axis * (2.0 * t - 1.0);
            vertices.push(Vertex {
                position: half * unit,
                normal: Vec3::Z,
                uv: Vec2::new(s, t) * repeats,
                color: color(unit),
                tangent_u,
                tangent_v,
            });
        }
    }
    let index = |i: u32, j: u32| j * (cells + 1) + i;
    let mut triangles = Vec::with_capacity((2 * cells * cells) as usize);
    for j in 0..cells {
        for i in 0..cells {
            let corners = [
                index(i, j),
                index(i + 1, j),
                index(i + 1, j + 1),
                index(i, j + 1),
            ];
            let at = |k: usize| vertices[corners[k] as usize];
            let facet = Face {
                indices: [corners[0], corners[1], corners[2]],
                face_normal: Vec3::Z,
                face_tangent_u: tangent_u,
                face_tangent_v: tangent_v,
                facet_center: (0..4).map(|k| at(k).position).sum::<Vec3>() / 4.0,
                facet_color: (0..4).map(|k| at(k).color).sum::<Vec3>() / 4.0,
                textured: true,
            };
            triangles.push(facet);
            triangles.push(Face {
                indices: [corners[0], corners[2], corners[3]],
                ..facet
            });
        }
    }
    // Coplanar triangles never overlap: no depth buffer needed.
    Mesh::new(vertices, &triangles, true, false)
}
