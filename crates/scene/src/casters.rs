//! Which objects can cast a shadow onto something, and the sphere that
//! holds them: scene geometry the plan decides with and the shadow pass
//! fits its map to, computed once per frame.

use glam::{Mat3, Mat4, Vec3};
use rayon::prelude::*;

use super::{Mesh, Scene, normal_matrix};

/// An object that can shade something, with its world bounding sphere.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Caster {
    /// Index in the scene's objects.
    pub object: usize,
    pub centre: Vec3,
    pub radius: f32,
}

/// Below this many vertices a sphere is found on one thread.
const PARALLEL_MIN: usize = 16_384;

/// A sphere around `mesh` placed by `model`: about the centre of its box,
/// out to its farthest vertex. Found each frame (an animation moves the
/// vertices), so a big mesh is swept on the threads; minima and maxima
/// come out the same in any order.
fn bounding_sphere(mesh: &Mesh, model: Mat4) -> Option<(Vec3, f32)> {
    let vertices = &mesh.vertices;
    let first = vertices.first()?.position;
    let parallel = vertices.len() >= PARALLEL_MIN;
    let widen = |(lo, hi): (Vec3, Vec3), p: Vec3| (lo.min(p), hi.max(p));
    let (lo, hi) = if parallel {
        vertices
            .par_iter()
            .fold(|| (first, first), |b, v| widen(b, v.position))
            .reduce(|| (first, first), |a, (lo, hi)| widen(widen(a, lo), hi))
    } else {
        vertices
            .iter()
            .map(|v| v.position)
            .fold((first, first), widen)
    };
    let centre = (lo + hi) * 0.5;
    // The farthest vertex by its squared distance, then one square root:
    // the root is monotonic and correctly rounded, so the root of the
    // largest square is the largest of the roots `length` would give.
    let reach = |v: &super::Vertex| (v.position - centre).length_squared();
    let reach = if parallel {
        vertices.par_iter().map(reach).reduce(|| 0.0, f32::max)
    } else {
        vertices.iter().map(reach).fold(0.0f32, f32::max)
    };
    let radius = reach.sqrt();
    let linear = Mat3::from_mat4(model);
    let scale = [linear.x_axis, linear.y_axis, linear.z_axis]
        .iter()
        .map(|a| a.length())
        .fold(0.0f32, f32::max);
    let sphere = (model.transform_point3(centre), radius * scale);
    (sphere.0.is_finite() && sphere.1.is_finite()).then_some(sphere)
}

/// The plane of a flat mesh (all facets share one normal and one plane),
/// in model space.
fn plane_of(mesh: &Mesh) -> Option<(Vec3, Vec3)> {
    mesh.triangles.first()?;
    let n = mesh.face_normal(0);
    let p0 = mesh.vertices.first()?.position;
    let flat = (0..mesh.triangles.len())
        .all(|t| (mesh.face_normal(t) - n).length_squared() < 1e-10)
        && mesh
            .vertices
            .iter()
            .all(|v| n.dot(v.position - p0).abs() < 1e-5);
    flat.then_some((n, p0))
}

/// The objects that can throw a shadow on something when lit from `light`,
/// with their world spheres, the user's rotation being `rotation`.
pub fn casters(scene: &Scene, rotation: Mat4, light: Vec3) -> Vec<Caster> {
    let spheres: Vec<Option<(Vec3, f32)>> = scene
        .objects
        .iter()
        .map(|o| bounding_sphere(&o.mesh, o.model_matrix(rotation)))
        .collect();
    let mut out = Vec::new();
    for (i, object) in scene.objects.iter().enumerate() {
        let Some((centre, radius)) = spheres[i] else {
            continue;
        };
        // Alone, a convex or flat object cannot shade itself.
        let others = scene.objects.len() > 1;
        let plane = plane_of(&object.mesh);
        if !others && (object.mesh.convex || plane.is_some()) {
            continue;
        }
        if let Some((n, p0)) = plane {
            let model = object.model_matrix(rotation);
            let normal_matrix = normal_matrix(model);
            let n = (normal_matrix * n).normalize_or_zero();
            let p0 = model.transform_point3(p0);
            let in_front = |c: Vec3, r: f32| n.dot(c - p0) >= r;
            let everything_in_front = in_front(light, 0.0)
                && spheres
                    .iter()
                    .enumerate()
                    .all(|(j, s)| j == i || s.is_none_or(|(c, r)| in_front(c, r)));
            if everything_in_front {
                continue;
            }
        }
        out.push(Caster {
            object: i,
            centre,
            radius,
        });
    }
    out
}

/// A sphere around the casters' spheres.
pub fn enclose(casters: &[Caster]) -> Option<(Vec3, f32)> {
    if casters.is_empty() {
        return None;
    }
    let centre = casters.iter().map(|c| c.centre).sum::<Vec3>() / casters.len() as f32;
    let radius = casters
        .iter()
        .map(|c| c.centre.distance(centre) + c.radius)
        .fold(0.0f32, f32::max);
    Some((centre, radius.max(1e-3)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Face, Vertex};

    /// The sphere as first written: the box's centre, then the largest of
    /// every vertex's distance.
    fn plain_sphere(mesh: &Mesh) -> (Vec3, f32) {
        let first = mesh.vertices[0].position;
        let (mut lo, mut hi) = (first, first);
        for v in &mesh.vertices {
            lo = lo.min(v.position);
            hi = hi.max(v.position);
        }
        let centre = (lo + hi) * 0.5;
        let radius = mesh
            .vertices
            .iter()
            .map(|v| (v.position - centre).length())
            .fold(0.0f32, f32::max);
        (centre, radius)
    }

    fn scattered(count: usize) -> Mesh {
        // A fixed scatter (a linear congruential sequence) in a box.
        let mut state = 12_345u32;
        let mut next = || {
            state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (state >> 8) as f32 / (1u32 << 24) as f32 * 6.0 - 2.5
        };
        let vertices: Vec<Vertex> = (0..count)
            .map(|_| Vertex {
                position: Vec3::new(next(), next(), next()),
                normal: Vec3::Y,
                uv: glam::Vec2::ZERO,
                color: Vec3::ONE,
                tangent_u: Vec3::X,
                tangent_v: Vec3::Z,
            })
            .collect();
        let faces: Vec<Face> = Vec::new();
        Mesh::new(vertices, &faces, false, false)
    }

    /// One square root of the largest square, swept on any number of
    /// threads, gives the very sphere of the distance-by-distance sweep.
    #[test]
    fn the_sphere_is_the_same_bits_on_any_threads() {
        for count in [1, 7, 20_000, 70_001] {
            let mesh = scattered(count);
            let (centre, radius) = plain_sphere(&mesh);
            for threads in [1, 2, 5] {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .unwrap();
                let got = pool.install(|| bounding_sphere(&mesh, Mat4::IDENTITY));
                let (c, r) = got.expect("a sphere");
                assert_eq!(
                    c.to_array().map(f32::to_bits),
                    centre.to_array().map(f32::to_bits)
                );
                assert_eq!(
                    r.to_bits(),
                    radius.to_bits(),
                    "{count} vertices, {threads} threads"
                );
            }
        }
        assert_eq!(bounding_sphere(&Mesh::default(), Mat4::IDENTITY), None);
    }
}
