//! The UV sphere of the documented viewer's model list.
//!
//! P(u, v) = (cos λ sin φ, sin λ, cos λ cos φ) with φ = 2π(u − ½) and
//! λ = π(v − ½): u runs once around (u = ½ faces the camera, the seam is at
//! the back), v from the south pole (0) to the north pole (1), and
//! ∂P/∂u × ∂P/∂v points outward, as on the cube.
//!
//! Seam: the column u = 1 duplicates u = 0 with its own UVs, so no triangle
//! interpolates u from 0.97 back to 0. Poles: each pole triangle has its own
//! pole vertex, at the u of the triangle's middle, so the texture converges
//! without a twisted fan; its ∂P/∂v is the exact one there, and its ∂P/∂u
//! (zero at the pole itself) takes the limit direction along that middle
//! meridian with the length it has on the neighbouring ring, so the frame
//! never degenerates.

use std::f32::consts::PI;

use glam::{Vec2, Vec3};

use super::cube::corner_color;
use super::mesh::{Face, Mesh, Vertex};
use crate::face_frame::face_frame;

/// Columns around (longitude).
pub const SEGMENTS: u32 = 32;
/// Bands from pole to pole (latitude).
pub const RINGS: u32 = 16;

fn angles(u: f32, v: f32) -> (f32, f32) {
    (2.0 * PI * (u - 0.5), PI * (v - 0.5))
}

/// A point of the unit sphere with its exact ∂P/∂u and ∂P/∂v.
fn surface(u: f32, v: f32) -> (Vec3, Vec3, Vec3) {
    let (phi, lambda) = angles(u, v);
    let (sp, cp) = phi.sin_cos();
    let (sl, cl) = lambda.sin_cos();
    let p = Vec3::new(cl * sp, sl, cl * cp);
    let pu = 2.0 * PI * cl * Vec3::new(cp, 0.0, -sp);
    let pv = PI * Vec3::new(-sl * sp, cl, -sl * cp);
    (p, pu, pv)
}

fn vertex(position: Vec3, uv: Vec2, tangent_u: Vec3, tangent_v: Vec3) -> Vertex {
    Vertex {
        position,
        normal: position.normalize(),
        uv,
        color: corner_color(position),
        tangent_u,
        tangent_v,
    }
}

/// Unit sphere at the origin: `SEGMENTS × RINGS` cells, quads on the rings
/// split along their (0,0)–(1,1) diagonal, one triangle per cell at the poles.
pub fn sphere() -> Mesh {
    let mut vertices = ring_vertices();
    let mut triangles = Vec::new();
    push_pole_cells(&mut vertices, &mut triangles, -1.0);
    push_ring_quads(&vertices, &mut triangles);
    push_pole_cells(&mut vertices, &mut triangles, 1.0);
    Mesh::new(vertices, &triangles, true, true)
}

/// The index of column `i` of interior ring `j` (1..RINGS−1) among the
/// ring vertices.
fn ring_index(i: u32, j: u32) -> u32 {
    (j - 1) * (SEGMENTS + 1) + i
}

/// The vertices of the interior rings j = 1..RINGS−1, each with
/// SEGMENTS + 1 columns (seam duplicated).
fn ring_vertices() -> Vec<Vertex> {
    let (seg, rings) = (SEGMENTS, RINGS);
    let mut vertices = Vec::new();
    for j in 1..rings {
        for i in 0..=seg {
            let uv = Vec2::new(i as f32 / seg as f32, j as f32 / rings as f32);
            if i == seg {
                // The seam column: column 0 again, bit for bit (so the seam
                // cannot crack), with u = 1.
                let first: Vertex = vertices[ring_index(0, j) as usize];
                vertices.push(Vertex { uv, ..first });
            } else {
                let (p, pu, pv) = surface(uv.x, uv.y);
                vertices.push(vertex(p, uv, pu, pv));
            }
        }
    }
    vertices
}

/// The cells around the pole on `side` (−1 south, +1 north): one triangle
/// each, with its own pole vertex pushed just before it.
fn push_pole_cells(vertices: &mut Vec<Vertex>, triangles: &mut Vec<Face>, side: f32) {
    let (seg, rings) = (SEGMENTS, RINGS);
    let v = if side < 0.0 { 0.0 } else { 1.0 };
    for i in 0..seg {
        let u = (i as f32 + 0.5) / seg as f32;
        let (p, pu, pv) = pole(u, side);
        let apex = vertices.len() as u32;
        vertices.push(vertex(p, Vec2::new(u, v), pu, pv));
        // Counter-clockwise seen from outside: the ring is walked the other
        // way round under the south pole than under the north one.
        let tri = if side < 0.0 {
            [apex, ring_index(i + 1, 1), ring_index(i, 1)]
        } else {
            [ring_index(i, rings - 1), ring_index(i + 1, rings - 1), apex]
        };
        push_facet(triangles, vertices, &[tri]);
    }
}

/// The quads between consecutive interior rings, two triangles each.
fn push_ring_quads(vertices: &[Vertex], triangles: &mut Vec<Face>) {
    let (seg, rings) = (SEGMENTS, RINGS);
    for j in 1..rings - 1 {
        for i in 0..seg {
            let (a, b) = (ring_index(i, j), ring_index(i + 1, j));
            let (c, d) = (ring_index(i + 1, j + 1), ring_index(i, j + 1));
            push_facet(triangles, vertices, &[[a, b, c], [a, c, d]]);
        }
    }
}

/// Pushes the triangles `tris` of one cell, sharing the cell's facet data:
/// the mean of its distinct corners' positions and colours, and its
/// triangles' summed normal and mean texture axes.
fn push_facet(triangles: &mut Vec<Face>, vertices: &[Vertex], tris: &[[u32; 3]]) {
    let corners = distinct_corners(tris);
    let center = corners
        .iter()
        .map(|&i| vertices[i as usize].position)
        .sum::<Vec3>()
        / corners.len() as f32;
    let color = corners
        .iter()
        .map(|&i| vertices[i as usize].color)
        .sum::<Vec3>()
        / corners.len() as f32;
    let (normal, tu, tv) = summed_frames(vertices, tris);
    let normal = normal.normalize_or(center.normalize_or(Vec3::Y));
    let k = tris.len() as f32;
    for &indices in tris {
        triangles.push(Face {
            indices,
            face_normal: normal,
            face_tangent_u: tu / k,
            face_tangent_v: tv / k,
            facet_center: center,
            facet_color: color,
            textured: true,
        });
    }
}

/// The vertex ids of `tris`, each once, in increasing order.
fn distinct_corners(tris: &[[u32; 3]]) -> Vec<u32> {
    let mut c: Vec<u32> = tris.iter().flatten().copied().collect();
    c.sort_unstable();
    c.dedup();
    c
}

/// The sums over `tris`, in order, of their (unnormalised) normals and of
/// their texture axes.
fn summed_frames(vertices: &[Vertex], tris: &[[u32; 3]]) -> (Vec3, Vec3, Vec3) {
    let mut normal = Vec3::ZERO;
    let (mut tu, mut tv) = (Vec3::ZERO, Vec3::ZERO);
    for t in tris {
        let p = t.map(|i| vertices[i as usize].position);
        let n = (p[1] - p[0]).cross(p[2] - p[0]);
        normal += n;
        let f = face_frame(p, t.map(|i| vertices[i as usize].uv), n);
        tu += f.tangent_u;
        tv += f.tangent_v;
    }
    (normal, tu, tv)
}

/// The pole vertex of the cell whose middle is at `u`: `side` −1 south, +1 north.
fn pole(u: f32, side: f32) -> (Vec3, Vec3, Vec3) {
    let v = if side < 0.0 { 0.0 } else { 1.0 };
    let (phi, _) = angles(u, v);
    let (sp, cp) = phi.sin_cos();
    // Exact ∂P/∂v at the pole: π(−sin λ sin φ, cos λ, −sin λ cos φ), sin λ = ±1.
    let pv = PI * Vec3::new(-side * sp, 0.0, -side * cp);
    // ∂P/∂u vanishes at the pole: keep its limit direction along this
    // meridian, at the length it has on the first ring.
    let ring_v = if side < 0.0 { 1.0 } else { (RINGS - 1) as f32 } / RINGS as f32;
    let (_, ring_pu, _) = surface(u, ring_v);
    let pu = ring_pu.length() * Vec3::new(cp, 0.0, -sp);
    (Vec3::new(0.0, side, 0.0), pu, pv)
}
