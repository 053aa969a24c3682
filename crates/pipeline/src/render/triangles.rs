//! The main pass's triangle stage: each triangle of an object culled,
//! clipped, set up and given its shader. On several threads a mesh with
//! enough triangles facing the camera is cut into chunks of consecutive
//! triangles, as many facing ones in each, done in parallel into buffers
//! of their own (kept from frame to frame), then joined in triangle order:
//! the frame draws the same triangles in the same order on any number of
//! threads.

use std::ops::Range;

use glam::{Vec3, Vec4};
use rayon::prelude::*;

use super::shaders::{build_shader, wire_triangle};
use crate::plan::Plan;
use crate::raster::clip::clip_by_codes;
use crate::raster::setup::{Projected, setup_projected};
use crate::raster::wire::WireTri;
use crate::raster::{ClipVertex, Clipped, ScreenTri, clip_triangle, setup_reaching};
use crate::shade::TriShader;
use crate::shadow::Shadow;
use relief_core::settings::Display;
use relief_core::stats::Counters;
use relief_scene::Object;
use relief_scene::repeats::RepeatSkipper;
use relief_scene::world::Placed;

/// Chunks of the triangle stage per thread: a few, so a thread that
/// finishes first takes another, but each one more is copied when the
/// chunks are joined.
const CHUNKS_PER_THREAD: usize = 2;

/// Triangles the camera faces in a chunk, at least: fewer are done faster
/// on one thread than handed to another.
const MIN_CHUNK: usize = 1_024;

/// Fewest elements a thread copies at once when the chunks are joined.
const JOIN_MIN_LEN: usize = 4_096;

/// One object as the triangle stage reads it: its placing, its vertices as
/// the view projected them, and the frame's settings for it.
pub(super) struct ObjectView<'a> {
    pub plan: &'a Plan,
    pub object: &'a Object,
    pub object_index: u32,
    pub placed: &'a Placed,
    /// Per vertex: clip position, outcode, and screen position when inside
    /// every plane.
    pub clip: &'a [Vec4],
    pub codes: &'a [u8],
    pub projected: &'a [Option<Projected>],
    /// Repeated triangles to skip (empty when repeats are drawn).
    pub repeats: &'a [(u32, u32)],
    pub shadow: Option<Shadow<'a>>,
    pub width: usize,
    pub height: usize,
    /// How far from pixel centres samples lie (multisampling), 1/256 pixel.
    pub reach: i64,
}

/// What one chunk of triangles gives: screen triangles whose `shader`
/// indexes the chunk's own `shaders`, or the wireframe's triangles.
#[derive(Default)]
pub(super) struct TriChunk {
    pub tris: Vec<ScreenTri>,
    pub shaders: Vec<TriShader>,
    pub wire: Vec<WireTri>,
    pub counters: Counters,
    /// Scratch polygon of the clipper.
    polygon: Vec<ClipVertex>,
}

impl TriChunk {
    fn clear(&mut self) {
        self.tris.clear();
        self.shaders.clear();
        self.wire.clear();
        self.counters = Counters::default();
    }

    /// The triangles `range` of `view`'s object, in order.
    fn run(&mut self, view: &ObjectView, range: Range<usize>) {
        let plan = view.plan;
        let placed = view.placed;
        let mesh = &view.object.mesh;
        let triangles = &mesh.triangles;
        let first_repeat = view
            .repeats
            .partition_point(|&(r, _)| (r as usize) < range.start);
        let mut repeats = RepeatSkipper::new(&view.repeats[first_repeat..]);
        for tri_index in range {
            if repeats.skip(tri_index, triangles) {
                continue;
            }
            // An open surface seen from behind is lit on the side we see.
            let side = match placed.sides[tri_index] {
                0 => continue,
                s => f32::from(s),
            };
            let idx = triangles[tri_index].indices.map(|i| i as usize);
            if plan.display != Display::Fill {
                self.push_wire(view, tri_index, idx, side);
                continue;
            }
            let shader_index = self.shaders.len() as u32;
            let first_tri = self.tris.len();
            self.set_up(view, idx, shader_index);
            if self.tris.len() > first_tri {
                self.push_shader(view, tri_index, idx, side);
            }
        }
    }

    /// Triangle `tri_index` (vertex indices `idx`) as lines and points.
    #[inline]
    fn push_wire(&mut self, view: &ObjectView, tri_index: usize, idx: [usize; 3], side: f32) {
        let (plan, placed, mesh) = (view.plan, view.placed, &view.object.mesh);
        let face_normal = placed.facet_normal(mesh, tri_index);
        self.counters.light_evals += 3 * plan.lights.len() as u64;
        self.wire.push(wire_triangle(
            plan,
            idx.map(|i| placed.vertex(mesh, i)),
            idx.map(|i| view.clip[i]),
            face_normal * side,
            side,
        ));
    }

    /// Clips the triangle of vertex indices `idx` and sets up the screen
    /// triangles of what is left, each drawn with shader `shader_index`.
    #[inline]
    fn set_up(&mut self, view: &ObjectView, idx: [usize; 3], shader_index: u32) {
        let clipped = clip_by_codes(idx.map(|i| view.codes[i]))
            .unwrap_or_else(|| clip_triangle(idx.map(|i| view.clip[i]), &mut self.polygon));
        match clipped {
            Clipped::Outside => {}
            Clipped::Inside => {
                // Projected once per vertex; a sub-pixel triangle stops at
                // its bounds.
                let [a, b, c] = idx.map(|i| view.projected[i]);
                if let (Some(a), Some(b), Some(c)) = (a, b, c)
                    && let Some(tri) = setup_projected(
                        [a, b, c],
                        Vec3::AXES,
                        view.width,
                        view.height,
                        shader_index,
                        view.reach,
                    )
                {
                    self.tris.push(tri);
                }
            }
            Clipped::Polygon => {
                self.counters.triangles_clipped += 1;
                for k in 1..self.polygon.len() - 1 {
                    let v = [self.polygon[0], self.polygon[k], self.polygon[k + 1]];
                    self.tris.extend(setup_reaching(
                        v,
                        view.width,
                        view.height,
                        shader_index,
                        view.reach,
                    ));
                }
            }
        }
    }

    /// The shader of triangle `tri_index`, seen from `side`.
    #[inline]
    fn push_shader(&mut self, view: &ObjectView, tri_index: usize, idx: [usize; 3], side: f32) {
        let (placed, mesh) = (view.placed, &view.object.mesh);
        let verts = idx.map(|i| placed.vertex(mesh, i));
        let face_normal = placed.facet_normal(mesh, tri_index);
        let uv2 = match mesh.uv2() {
            [] => [glam::Vec2::ZERO; 3],
            set => idx.map(|i| set.get(i).copied().unwrap_or_default()),
        };
        let shader = build_shader(
            view.plan,
            &verts,
            mesh,
            tri_index,
            face_normal * side,
            side,
            &placed.model,
            &placed.linear,
            view.shadow,
            view.object_index,
            uv2,
            &mut self.counters,
        );
        self.shaders.push(shader);
    }
}

/// Runs the triangle stage over every triangle of `view`'s object in
/// chunks (in parallel when there are several), and returns the chunks
/// used, in triangle order. `chunks` keeps its buffers for the next frame.
pub(super) fn run_chunks<'c>(
    chunks: &'c mut Vec<TriChunk>,
    view: &ObjectView,
) -> &'c mut [TriChunk] {
    let bounds = chunk_bounds(&view.placed.sides, rayon::current_num_threads());
    let count = bounds.len() - 1;
    if chunks.len() < count {
        chunks.resize_with(count, TriChunk::default);
    }
    let used = &mut chunks[..count];
    let range = |c: usize| bounds[c]..bounds[c + 1];
    if count == 1 {
        used[0].clear();
        used[0].run(view, range(0));
    } else {
        used.par_iter_mut().enumerate().for_each(|(c, chunk)| {
            chunk.clear();
            chunk.run(view, range(c));
        });
    }
    used
}

/// Where the triangles (whose sides are `sides`, 0 for culled) are cut
/// into chunks for `threads` threads: one chunk on one thread (nothing to
/// join) or for a small mesh; else up to [`CHUNKS_PER_THREAD`] per thread,
/// each with about as many triangles the camera faces (a culled one costs
/// next to nothing, a faced one its setup and shader).
fn chunk_bounds(sides: &[i8], threads: usize) -> Vec<usize> {
    let n = sides.len();
    if threads <= 1 {
        return vec![0, n];
    }
    let faced = sides.iter().filter(|&&s| s != 0).count();
    // A whole number of chunks per thread, so each thread gets as much.
    let parts = threads * CHUNKS_PER_THREAD.min(faced / MIN_CHUNK / threads);
    let mut bounds = vec![0];
    if parts > 1 {
        let mut seen = 0;
        for (t, &side) in sides.iter().enumerate() {
            seen += usize::from(side != 0);
            let part = bounds.len();
            if part < parts && seen * parts >= faced * part {
                bounds.push(t + 1);
            }
        }
    }
    bounds.push(n);
    bounds
}

/// Appends the chunks' triangles, shaders and lines to the frame's, in
/// triangle order, each triangle's shader index shifted past the shaders
/// before it; returns how many shaders were added. The first chunk is
/// taken whole, not copied, when the frame has nothing yet (a small mesh
/// is one chunk, and its shaders, 252 bytes each, and screen triangles,
/// 168, are most of what it moves); each side keeps its capacity.
pub(super) fn join_chunks(
    chunks: &mut [TriChunk],
    tris: &mut Vec<ScreenTri>,
    shaders: &mut Vec<TriShader>,
    wire: &mut Vec<WireTri>,
) -> usize {
    let base = shaders.len();
    let mut skip = 0;
    if tris.is_empty()
        && shaders.is_empty()
        && wire.is_empty()
        && let Some(first) = chunks.first_mut()
    {
        std::mem::swap(tris, &mut first.tris);
        std::mem::swap(shaders, &mut first.shaders);
        std::mem::swap(wire, &mut first.wire);
        skip = 1;
    }
    let rest = &chunks[skip..];
    let tri_starts = starts(rest.iter().map(|c| c.tris.len()));
    let shader_starts = starts(rest.iter().map(|c| c.shaders.len()));
    let first_shader = shaders.len();
    // Copied on the threads, each element written once where it lands
    // (`par_extend` of an indexed iterator): a dense mesh's copy, 420 bytes
    // a drawn triangle, was the frame's one serial stage on two threads.
    tris.par_extend(joined(rest, &tri_starts, |c| &c.tris).map(|(k, t)| {
        let offset = (first_shader + shader_starts[k]) as u32;
        ScreenTri {
            shader: t.shader + offset,
            ..t.clone()
        }
    }));
    shaders.par_extend(joined(rest, &shader_starts, |c| &c.shaders).map(|(_, s)| s.clone()));
    for chunk in rest {
        wire.extend_from_slice(&chunk.wire);
    }
    shaders.len() - base
}

/// Where each of the parts of these lengths starts when they are laid end
/// to end, and (last) their total.
fn starts(lens: impl Iterator<Item = usize>) -> Vec<usize> {
    let mut at = vec![0];
    for len in lens {
        at.push(at[at.len() - 1] + len);
    }
    at
}

/// Every element of `part(chunk)` for the chunks in order, each with its
/// chunk's place in `chunks`, as one indexed parallel iterator (`starts`:
/// where each chunk's elements start, then the total).
fn joined<'a, T: Sync + 'a>(
    chunks: &'a [TriChunk],
    starts: &'a [usize],
    part: impl Fn(&'a TriChunk) -> &'a Vec<T> + Sync + Send + 'a,
) -> impl IndexedParallelIterator<Item = (usize, &'a T)> + 'a {
    let total = starts[starts.len() - 1];
    (0..total)
        .into_par_iter()
        .with_min_len(JOIN_MIN_LEN)
        .map(move |g| {
            let k = starts.partition_point(|&s| s <= g) - 1;
            (k, &part(&chunks[k])[g - starts[k]])
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Culled triangles (side 0) weigh nothing: chunks hold as many faced
    /// triangles each, a whole number per thread, and cover every triangle
    /// once, in order.
    #[test]
    fn chunks_share_the_faced_triangles_evenly() {
        // 8,192 triangles, the first half culled, the second faced.
        let sides: Vec<i8> = (0..8_192).map(|t| if t < 4_096 { 0 } else { 1 }).collect();
        assert_eq!(chunk_bounds(&sides, 1), vec![0, 8_192]);
        assert_eq!(chunk_bounds(&sides, 2), vec![0, 5_120, 6_144, 7_168, 8_192]);
        // 4,096 faced triangles give three threads one chunk each.
        let three = chunk_bounds(&sides, 3);
        assert_eq!(three.len(), 4);
        let faced = |w: &[usize]| sides[w[0]..w[1]].iter().filter(|&&s| s != 0).count();
        for w in three.windows(2) {
            assert!(w[0] < w[1]);
            assert!(faced(w).abs_diff(4_096 / 3) <= 1, "{three:?}");
        }
        // Too few faced triangles to share.
        let few: Vec<i8> = (0..100_000).map(|t| i8::from(t % 100 == 0)).collect();
        assert_eq!(chunk_bounds(&few, 8), vec![0, 100_000]);
        assert_eq!(chunk_bounds(&[], 4), vec![0, 0]);
    }
}
