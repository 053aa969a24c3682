//! The main pass's triangle stage: each triangle of an object culled,
//! clipped, set up and given its shader. A big mesh is cut into chunks of
//! consecutive triangles done in parallel, each into buffers of its own
//! (kept from frame to frame), then joined in triangle order: the frame
//! draws the same triangles in the same order on any number of threads.

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

/// Triangles per chunk: enough that a chunk's bookkeeping is small next to
/// its work, few enough that two threads share a million triangles evenly.
const CHUNK: usize = 16_384;

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
                let face_normal = placed.facet_normal(mesh, tri_index);
                self.counters.light_evals += 3 * plan.lights.len() as u64;
                self.wire.push(wire_triangle(
                    plan,
                    idx.map(|i| placed.vertex(mesh, i)),
                    idx.map(|i| view.clip[i]),
                    face_normal * side,
                    side,
                ));
                continue;
            }
            let shader_index = self.shaders.len() as u32;
            let first_tri = self.tris.len();
            let clipped = clip_by_codes(idx.map(|i| view.codes[i]))
                .unwrap_or_else(|| clip_triangle(idx.map(|i| view.clip[i]), &mut self.polygon));
            match clipped {
                Clipped::Outside => {}
                Clipped::Inside => {
                    // Projected once per vertex; a sub-pixel triangle stops
                    // at its bounds.
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
            if self.tris.len() == first_tri {
                continue;
            }
            let verts = idx.map(|i| placed.vertex(mesh, i));
            let face_normal = placed.facet_normal(mesh, tri_index);
            let uv2 = match mesh.uv2() {
                [] => [glam::Vec2::ZERO; 3],
                set => idx.map(|i| set.get(i).copied().unwrap_or_default()),
            };
            let shader = build_shader(
                plan,
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
}

/// Runs the triangle stage over every triangle of `view`'s object in
/// chunks (in parallel when there are several), and returns the chunks
/// used, in triangle order. `chunks` keeps its buffers for the next frame.
pub(super) fn run_chunks<'c>(
    chunks: &'c mut Vec<TriChunk>,
    view: &ObjectView,
) -> &'c mut [TriChunk] {
    let n = view.object.mesh.triangles.len();
    let count = n.div_ceil(CHUNK).max(1);
    if chunks.len() < count {
        chunks.resize_with(count, TriChunk::default);
    }
    let used = &mut chunks[..count];
    let range = |c: usize| c * CHUNK..((c + 1) * CHUNK).min(n);
    if count == 1 || rayon::current_num_threads() == 1 {
        for (c, chunk) in used.iter_mut().enumerate() {
            chunk.clear();
            chunk.run(view, range(c));
        }
    } else {
        used.par_iter_mut().enumerate().for_each(|(c, chunk)| {
            chunk.clear();
            chunk.run(view, range(c));
        });
    }
    used
}
