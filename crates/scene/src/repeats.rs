//! Triangles that repeat an earlier triangle of the same mesh: the same
//! three vertex indices in the same order (a polygon fanned over a few
//! corners again and again, faces exported twice).
//!
//! Every depth test in relief is strict (`z < stored`), and a triangle's
//! depths depend only on its vertices: a repeat lands on exactly the depths
//! its first copy left or something nearer, so behind a depth buffer it can
//! change no pixel and no shadow texel. The renderer and the shadow pass
//! skip repeats when they test depth; without a depth buffer (painter's
//! order on convex meshes) a repeat still paints and is drawn.

use rayon::prelude::*;

use super::mesh::Triangle;

/// Each repeated triangle with the first triangle it repeats, in
/// increasing order of the repeat (empty when every triangle is unique).
pub type RepeatPairs = Vec<(u32, u32)>;

/// The repeats of `triangles`: every triangle's corners with its index,
/// sorted on the threads, so equal corners lie together with their first
/// triangle leading. A sort of 16 bytes a triangle beats a hash table of a
/// million entries and more, which is filled on one thread and takes twice
/// the memory.
pub fn find_repeats(triangles: &[Triangle]) -> RepeatPairs {
    let mut keys: Vec<([u32; 3], u32)> = triangles
        .par_iter()
        .enumerate()
        .map(|(i, t)| (t.indices, i as u32))
        .collect();
    keys.par_sort_unstable();
    let mut pairs: RepeatPairs = keys
        .par_chunk_by(|a, b| a.0 == b.0)
        .flat_map_iter(|run| run[1..].iter().map(move |&(_, i)| (i, run[0].1)))
        .collect();
    pairs.par_sort_unstable();
    pairs
}

/// Walks the triangles of a mesh in order and says which to skip. A skip is
/// checked against the triangles as they are now (the pairs may have been
/// found on an older version of the mesh): a stale pair only costs a
/// triangle drawn in vain, never a triangle missed.
pub struct RepeatSkipper<'a> {
    pairs: &'a [(u32, u32)],
    next: usize,
}

impl<'a> RepeatSkipper<'a> {
    pub fn new(pairs: &'a [(u32, u32)]) -> Self {
        RepeatSkipper { pairs, next: 0 }
    }

    /// Whether triangle `i` of `triangles` repeats an earlier one; call
    /// with increasing `i`.
    #[inline]
    pub fn skip(&mut self, i: usize, triangles: &[Triangle]) -> bool {
        while let Some(&(repeat, first)) = self.pairs.get(self.next) {
            let repeat = repeat as usize;
            if repeat > i {
                return false;
            }
            self.next += 1;
            if repeat == i {
                let first = first as usize;
                return first < i
                    && triangles.get(first).map(|t| t.indices)
                        == triangles.get(i).map(|t| t.indices);
            }
        }
        false
    }
}
