//! Tangent frames: ∂P/∂u and ∂P/∂v per face from positions and UVs, then
//! accumulated per vertex and renormalised (docs/bump-dot3.md, from [004] §III-C).
//!
//! Both axes are kept, never rebuilt as N × T, so mirrored UVs keep their
//! handedness: a face whose texture is flipped gets Pu × Pv pointing inward,
//! and the bump built from Pu and Pv tilts the right way on it.

use glam::{Vec2, Vec3};
use rayon::prelude::*;

pub use super::face_frame::{FaceFrame, face_frame, frame_from_normal};
use super::mesh::Mesh;

/// `v` with its component along unit `n` removed, or `None` when nothing is left.
fn in_plane(v: Vec3, n: Vec3) -> Option<Vec3> {
    let t = v - n * n.dot(v);
    // Relative test: an accumulated sum that (nearly) cancelled carries no direction.
    (t.length_squared() > 1e-8 * v.length_squared().max(1e-30) && t.is_finite()).then_some(t)
}

/// One vertex's votes.
#[derive(Clone, Copy, Default)]
struct Sum {
    dir_u: Vec3,
    dir_v: Vec3,
    len_u: f32,
    len_v: f32,
    votes: u32,
    handedness: f32,
}

/// Per-vertex tangents from the triangles that use each vertex.
///
/// As in [004] (docs/sources.md): each face's Pu and Pv are normalised and summed at its
/// three vertices, then the sums are renormalised. Here they are also made
/// perpendicular to the vertex normal (the shading frame must lie in the
/// tangent plane) and given back a length, the mean of the faces' |Pu| and
/// |Pv|, because the renderer reads ∂P/∂u, not a unit vector. Faces with
/// degenerate UVs do not vote; a vertex left without a usable direction
/// (no votes, or votes that cancel) gets a frame from its normal, at the
/// mean length of its faces' axes, or 1.
pub fn accumulate(mesh: &mut Mesh) {
    accumulate_with(mesh, false, None, false);
}

/// [`accumulate`], each face's vote worked out once into an array of
/// [`vote_bytes`] (that the caller has reserved) instead of at each of
/// its corners: the same sums, bit for bit, in less time.
pub fn accumulate_votes_once(mesh: &mut Mesh) {
    accumulate_with(mesh, false, None, true);
}

/// [`accumulate`], but a vertex that already holds both texture axes (a
/// file's tangents) keeps their directions and takes only the lengths;
/// the faces' axes come from `uvs` (one per vertex) when given instead of
/// the vertices' own: those of a normal map that reads another set or
/// transform (glTF, `scene::map_uv`).
pub fn accumulate_keeping_directions(mesh: &mut Mesh, uvs: Option<&[Vec2]>) {
    accumulate_with(mesh, true, uvs, false);
}

/// One face's vote: its unit texture axes, their lengths and its
/// handedness; `len_u` is NaN for a face whose UVs are degenerate (no vote:
/// a length of finite axes is never NaN).
#[derive(Clone, Copy)]
struct Vote {
    dir_u: Vec3,
    dir_v: Vec3,
    len_u: f32,
    len_v: f32,
    handedness: f32,
}

const NO_VOTE: Vote = Vote {
    dir_u: Vec3::ZERO,
    dir_v: Vec3::ZERO,
    len_u: f32::NAN,
    len_v: 0.0,
    handedness: 0.0,
};

/// What [`accumulate`] allocates for `vertices` and `triangles`: each
/// vertex's sums and its place in the list of corners, and that list.
pub fn sum_bytes(vertices: u64, triangles: u64) -> u64 {
    let word = std::mem::size_of::<u32>() as u64;
    let bytes = |n: u64, size: u64| n.saturating_mul(size);
    bytes(vertices, std::mem::size_of::<Sum>() as u64)
        .saturating_add(vertices.saturating_add(1).saturating_mul(2 * word))
        .saturating_add(triangles.saturating_mul(3 * word))
}

/// What [`accumulate_votes_once`] allocates beyond [`sum_bytes`]: each
/// triangle's vote.
pub fn vote_bytes(triangles: u64) -> u64 {
    triangles.saturating_mul(std::mem::size_of::<Vote>() as u64)
}

fn accumulate_with(mesh: &mut Mesh, keep_directions: bool, uvs: Option<&[Vec2]>, votes_once: bool) {
    let vertex_count = mesh.vertices.len();
    // The corners at each vertex, in triangle order (a counting sort): each
    // vertex then sums its faces' votes on its own, in parallel, in the
    // order one pass over the triangles would add them, so the sums do not
    // depend on how the work is split.
    let mut start = vec![0u32; vertex_count + 1];
    let valid = |indices: &[u32; 3]| indices.iter().all(|&i| (i as usize) < vertex_count);
    for tri in mesh.triangles.iter().filter(|t| valid(&t.indices)) {
        for &i in &tri.indices {
            start[i as usize + 1] += 1;
        }
    }
    for i in 0..vertex_count {
        start[i + 1] += start[i];
    }
    let mut fill = start.clone();
    let mut around = vec![0u32; start[vertex_count] as usize];
    for (t, tri) in mesh.triangles.iter().enumerate() {
        if valid(&tri.indices) {
            for &i in &tri.indices {
                around[fill[i as usize] as usize] = t as u32;
                fill[i as usize] += 1;
            }
        }
    }
    drop(fill);
    let shared: &Mesh = mesh;
    // Each face's vote (a face is valid when the sums meet it).
    let vote_of = |t: usize| {
        let tri = &shared.triangles[t];
        let normal = shared.face_normal(t);
        let idx = tri.indices.map(|i| i as usize);
        let p = idx.map(|i| shared.vertices[i].position);
        let uv = idx.map(|i| uvs.map_or(shared.vertices[i].uv, |u| u[i]));
        let frame = face_frame(p, uv, normal);
        if !frame.from_uv {
            return NO_VOTE;
        }
        let (lu, lv) = (frame.tangent_u.length(), frame.tangent_v.length());
        Vote {
            dir_u: frame.tangent_u / lu,
            dir_v: frame.tangent_v / lv,
            len_u: lu,
            len_v: lv,
            handedness: frame.handedness(normal),
        }
    };
    let votes: Vec<Vote> = if votes_once {
        (0..shared.triangles.len())
            .into_par_iter()
            .map(|t| match valid(&shared.triangles[t].indices) {
                true => vote_of(t),
                false => NO_VOTE,
            })
            .collect()
    } else {
        Vec::new()
    };
    let sums: Vec<Sum> = (0..vertex_count)
        .into_par_iter()
        .map(|v| {
            let mut s = Sum::default();
            for &t in &around[start[v] as usize..start[v + 1] as usize] {
                let vote = match votes.get(t as usize) {
                    Some(vote) => *vote,
                    None => vote_of(t as usize),
                };
                if vote.len_u.is_nan() {
                    continue;
                }
                s.dir_u += vote.dir_u;
                s.dir_v += vote.dir_v;
                s.len_u += vote.len_u;
                s.len_v += vote.len_v;
                s.votes += 1;
                s.handedness += vote.handedness;
            }
            s
        })
        .collect();
    drop(votes);
    drop(around);
    drop(start);
    // Each vertex is finished from its own sums alone: in parallel.
    mesh.vertices
        .par_iter_mut()
        .zip(&sums)
        .for_each(|(vertex, s)| {
            let n = vertex.normal.normalize_or(Vec3::Z);
            let (len_u, len_v) = if s.votes > 0 {
                (s.len_u / s.votes as f32, s.len_v / s.votes as f32)
            } else {
                (1.0, 1.0)
            };
            let u = in_plane(s.dir_u, n).map(Vec3::normalize);
            let v = in_plane(s.dir_v, n).map(Vec3::normalize);
            // Mirrored faces were counted with −1: the sign of the sum says
            // which way Pv turns from Pu when one of the two has to be rebuilt.
            let hand = if s.handedness < 0.0 { -1.0 } else { 1.0 };
            let (tu, tv) = match (u, v) {
                (Some(u), Some(v)) if u.cross(v).length_squared() > 1e-6 => (u, v),
                (Some(u), _) => (u, hand * n.cross(u)),
                (None, Some(v)) => (hand * v.cross(n), v),
                (None, None) => {
                    let f = frame_from_normal(n);
                    (f.tangent_u, f.tangent_v)
                }
            };
            let (tu, tv) = (tu * len_u, tv * len_v);
            let kept = (
                vertex.tangent_u.try_normalize(),
                vertex.tangent_v.try_normalize(),
            );
            (vertex.tangent_u, vertex.tangent_v) = match kept {
                (Some(u), Some(w)) if keep_directions => (u * tu.length(), w * tv.length()),
                _ => (tu, tv),
            };
        });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn votes_worked_out_once_give_the_sums_of_votes_at_each_corner() {
        // A sphere (UV seams, poles of degenerate UVs) and a mesh with a
        // triangle naming a vertex it does not have.
        let mut meshes = vec![crate::scene::sphere::sphere()];
        let mut broken = crate::scene::sphere::sphere();
        broken.triangles[0].indices[1] = u32::MAX;
        meshes.push(broken);
        for mesh in meshes {
            let (mut once, mut each) = (mesh.clone(), mesh);
            for v in once.vertices.iter_mut().chain(each.vertices.iter_mut()) {
                (v.tangent_u, v.tangent_v) = (Vec3::ZERO, Vec3::ZERO);
            }
            accumulate_votes_once(&mut once);
            accumulate(&mut each);
            let bits = |m: &Mesh| -> Vec<[u32; 6]> {
                m.vertices
                    .iter()
                    .map(|v| {
                        let [a, b, c] = v.tangent_u.to_array().map(f32::to_bits);
                        let [d, e, f] = v.tangent_v.to_array().map(f32::to_bits);
                        [a, b, c, d, e, f]
                    })
                    .collect()
            };
            assert_eq!(bits(&once), bits(&each));
            assert!(once.vertices.iter().all(|v| v.tangent_u != Vec3::ZERO));
        }
    }

    #[test]
    fn frame_from_normal_is_right_handed_and_unit() {
        for n in [Vec3::X, Vec3::NEG_Y, Vec3::new(1.0, 2.0, -3.0), Vec3::ZERO] {
            let f = frame_from_normal(n);
            let n = n.normalize_or(Vec3::Z);
            assert!((f.tangent_u.length() - 1.0).abs() < 1e-5);
            assert!((f.tangent_v.length() - 1.0).abs() < 1e-5);
            assert!((f.tangent_u.cross(f.tangent_v) - n).length() < 1e-5);
            assert!(!f.from_uv);
        }
    }
}
