//! Tangent frames: ∂P/∂u and ∂P/∂v per face from positions and UVs, then
//! accumulated per vertex and renormalised (docs/bump-dot3.md, from [004] §III-C).
//!
//! Both axes are kept, never rebuilt as N × T, so mirrored UVs keep their
//! handedness: a face whose texture is flipped gets Pu × Pv pointing inward,
//! and the bump built from Pu and Pv tilts the right way on it.

use glam::{Vec2, Vec3};
use rayon::prelude::*;

use super::face_frame::{face_frame, frame_from_normal};
use super::mesh::{Mesh, Vertex};

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
    accumulate_with(mesh, false, None, BLOCK);
}

/// [`accumulate`], but a vertex that already holds both texture axes (a
/// file's tangents) keeps their directions and takes only the lengths;
/// the faces' axes come from `uvs` (one per vertex) when given instead of
/// the vertices' own: those of a normal map that reads another set or
/// transform (glTF, `scene::map_uv`).
pub fn accumulate_keeping_directions(mesh: &mut Mesh, uvs: Option<&[Vec2]>) {
    accumulate_with(mesh, true, uvs, BLOCK);
}

/// One face's vote: its unit texture axes, their lengths and its
/// handedness.
struct Vote {
    dir_u: Vec3,
    dir_v: Vec3,
    len_u: f32,
    len_v: f32,
    handedness: f32,
}

/// Triangles in a block whose lowest and highest vertex are noted, so a
/// range of vertices skips the blocks that do not reach it.
const BLOCK: usize = 1024;

/// What [`accumulate`] allocates for `vertices` and `triangles`: each
/// vertex's sums and each block's vertex bounds.
pub fn sum_bytes(vertices: u64, triangles: u64) -> u64 {
    let blocks = triangles / BLOCK as u64 + 1;
    vertices
        .saturating_mul(std::mem::size_of::<Sum>() as u64)
        .saturating_add(blocks.saturating_mul(std::mem::size_of::<(u32, u32)>() as u64))
}

/// The sums with `block` triangles a block (any size gives the same bits).
fn accumulate_with(mesh: &mut Mesh, keep_directions: bool, uvs: Option<&[Vec2]>, block: usize) {
    let vertex_count = mesh.vertices.len();
    let shared: &Mesh = mesh;
    let bounds = block_bounds(shared, block);
    // The vertices are cut into ranges, each summed by one thread that
    // walks the triangles in order (skipping the blocks that cannot reach
    // it): every vertex adds its faces' votes in triangle order, as one
    // pass over the triangles would, so the floating-point sums do not
    // depend on the cut. A face whose corners lie in two ranges has its
    // vote worked out in each (the same bits); on a mesh whose vertices
    // are numbered in order of use, as the builder numbers them, that is
    // only the faces along the cuts.
    let mut sums = vec![Sum::default(); vertex_count];
    let ranges = (2 * rayon::current_num_threads()).clamp(1, vertex_count.max(1));
    split_into_ranges(&mut sums, ranges)
        .into_par_iter()
        .for_each(|(lo, out)| sum_range(shared, uvs, &bounds, block, lo, out));
    drop(bounds);
    // Each vertex is finished from its own sums alone: in parallel.
    mesh.vertices
        .par_iter_mut()
        .zip(&sums)
        .for_each(|(vertex, s)| finish_vertex(vertex, s, keep_directions));
}

/// Whether all three corners name one of the mesh's `vertex_count`
/// vertices (a face is valid when the sums meet it).
#[inline]
fn indices_valid(indices: &[u32; 3], vertex_count: usize) -> bool {
    indices.iter().all(|&i| (i as usize) < vertex_count)
}

/// Triangle `t`'s vote, none when its UVs are degenerate.
#[inline]
fn face_vote(mesh: &Mesh, uvs: Option<&[Vec2]>, t: usize) -> Option<Vote> {
    let tri = &mesh.triangles[t];
    let normal = mesh.face_normal(t);
    let idx = tri.indices.map(|i| i as usize);
    let p = idx.map(|i| mesh.vertices[i].position);
    let uv = idx.map(|i| uvs.map_or(mesh.vertices[i].uv, |u| u[i]));
    let frame = face_frame(p, uv, normal);
    if !frame.from_uv {
        return None;
    }
    let (lu, lv) = (frame.tangent_u.length(), frame.tangent_v.length());
    Some(Vote {
        dir_u: frame.tangent_u / lu,
        dir_v: frame.tangent_v / lv,
        len_u: lu,
        len_v: lv,
        handedness: frame.handedness(normal),
    })
}

/// Each block's lowest and highest vertex over its valid triangles (none:
/// lowest above highest).
fn block_bounds(mesh: &Mesh, block: usize) -> Vec<(u32, u32)> {
    let vertex_count = mesh.vertices.len();
    mesh.triangles
        .par_chunks(block)
        .map(|block| {
            block
                .iter()
                .filter(|t| indices_valid(&t.indices, vertex_count))
                .fold((u32::MAX, 0), |(lo, hi), t| {
                    let [a, b, c] = t.indices;
                    (lo.min(a.min(b).min(c)), hi.max(a.max(b).max(c)))
                })
        })
        .collect()
}

/// `sums` cut into `ranges` consecutive pieces of near-equal length, each
/// with the index of its first vertex.
fn split_into_ranges(sums: &mut [Sum], ranges: usize) -> Vec<(usize, &mut [Sum])> {
    let vertex_count = sums.len();
    let mut pieces = Vec::with_capacity(ranges);
    let mut rest = sums;
    for r in 0..ranges {
        let (lo, hi) = (r * vertex_count / ranges, (r + 1) * vertex_count / ranges);
        let (piece, tail) = std::mem::take(&mut rest).split_at_mut(hi - lo);
        pieces.push((lo, piece));
        rest = tail;
    }
    pieces
}

/// Adds to `out`, the sums of the vertices from `lo` on, the votes of the
/// faces that use them, in triangle order, skipping the blocks whose
/// `bounds` do not reach them.
fn sum_range(
    mesh: &Mesh,
    uvs: Option<&[Vec2]>,
    bounds: &[(u32, u32)],
    block: usize,
    lo: usize,
    out: &mut [Sum],
) {
    let vertex_count = mesh.vertices.len();
    let hi = (lo + out.len()) as u32;
    let lo = lo as u32;
    for (b, &(least, most)) in bounds.iter().enumerate() {
        if least > most || least >= hi || most < lo {
            continue;
        }
        let first = b * block;
        let end = (first + block).min(mesh.triangles.len());
        for (k, tri) in mesh.triangles[first..end].iter().enumerate() {
            let inside = tri.indices.map(|i| (lo..hi).contains(&i));
            if inside == [false; 3] || !indices_valid(&tri.indices, vertex_count) {
                continue;
            }
            let Some(vote) = face_vote(mesh, uvs, first + k) else {
                continue;
            };
            for (&i, _) in tri.indices.iter().zip(inside).filter(|(_, inside)| *inside) {
                out[(i - lo) as usize].add(&vote);
            }
        }
    }
}

impl Sum {
    /// Counts one face's vote.
    #[inline]
    fn add(&mut self, vote: &Vote) {
        self.dir_u += vote.dir_u;
        self.dir_v += vote.dir_v;
        self.len_u += vote.len_u;
        self.len_v += vote.len_v;
        self.votes += 1;
        self.handedness += vote.handedness;
    }

    /// The mean lengths of the voting faces' axes, or 1 without votes.
    #[inline]
    fn mean_lengths(&self) -> (f32, f32) {
        if self.votes > 0 {
            (
                self.len_u / self.votes as f32,
                self.len_v / self.votes as f32,
            )
        } else {
            (1.0, 1.0)
        }
    }

    /// The unit texture axes in the plane of unit normal `n`: the summed
    /// directions where they are usable, one rebuilt from the other, or a
    /// frame from the normal.
    #[inline]
    fn unit_axes(&self, n: Vec3) -> (Vec3, Vec3) {
        let u = in_plane(self.dir_u, n).map(Vec3::normalize);
        let v = in_plane(self.dir_v, n).map(Vec3::normalize);
        // Mirrored faces were counted with −1: the sign of the sum says
        // which way Pv turns from Pu when one of the two has to be rebuilt.
        let hand = if self.handedness < 0.0 { -1.0 } else { 1.0 };
        match (u, v) {
            (Some(u), Some(v)) if u.cross(v).length_squared() > 1e-6 => (u, v),
            (Some(u), _) => (u, hand * n.cross(u)),
            (None, Some(v)) => (hand * v.cross(n), v),
            (None, None) => {
                let f = frame_from_normal(n);
                (f.tangent_u, f.tangent_v)
            }
        }
    }
}

/// Sets `vertex`'s tangents from its sums `s` (only their lengths when
/// `keep_directions` and it already holds both axes).
#[inline]
fn finish_vertex(vertex: &mut Vertex, s: &Sum, keep_directions: bool) {
    let n = vertex.normal.normalize_or(Vec3::Z);
    let (len_u, len_v) = s.mean_lengths();
    let (tu, tv) = s.unit_axes(n);
    let (tu, tv) = (tu * len_u, tv * len_v);
    let kept = (
        vertex.tangent_u.try_normalize(),
        vertex.tangent_v.try_normalize(),
    );
    (vertex.tangent_u, vertex.tangent_v) = match kept {
        (Some(u), Some(w)) if keep_directions => (u * tu.length(), w * tv.length()),
        _ => (tu, tv),
    };
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sums_do_not_depend_on_how_the_vertices_are_cut() {
        // A sphere (UV seams, poles of degenerate UVs), the same with its
        // triangles shuffled (every block then reaches every range) and
        // one with a triangle naming a vertex it does not have; summed on
        // 1 to 7 threads (2 to 14 ranges), in blocks of 1, 5, 16 and 1024
        // triangles.
        let sphere = crate::sphere::sphere();
        let mut shuffled = sphere.clone();
        let mut seed = 12345u64;
        for i in (1..shuffled.triangles.len()).rev() {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            shuffled.triangles.swap(i, (seed >> 33) as usize % (i + 1));
        }
        let mut broken = sphere.clone();
        broken.triangles[0].indices[1] = u32::MAX;
        assert!(sphere.triangles.len() > 8 * 16);
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
        for mesh in [sphere, shuffled, broken] {
            let summed = |threads: usize, block: usize| {
                let mut m = mesh.clone();
                for v in &mut m.vertices {
                    (v.tangent_u, v.tangent_v) = (Vec3::ZERO, Vec3::ZERO);
                }
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .unwrap();
                pool.install(|| accumulate_with(&mut m, false, None, block));
                assert!(m.vertices.iter().all(|v| v.tangent_u != Vec3::ZERO));
                bits(&m)
            };
            let one = summed(1, BLOCK);
            for threads in 1..=7 {
                for block in [1, 5, 16, BLOCK] {
                    let same = summed(threads, block) == one;
                    assert!(same, "{threads} threads, blocks of {block}");
                }
            }
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
