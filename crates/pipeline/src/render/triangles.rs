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
    /// Moves the chunk's triangles, shaders and lines to the end of the
    /// frame's, its shader indices shifted past the shaders before it.
    pub(super) fn move_into(
        &mut self,
        tris: &mut Vec<ScreenTri>,
        shaders: &mut Vec<TriShader>,
        wire: &mut Vec<WireTri>,
    ) {
        if tris.is_empty() && shaders.is_empty() && wire.is_empty() {
            // The frame's first triangles are taken whole, not copied: a
            // small mesh is one chunk, and its shaders (252 bytes) and
            // screen triangles (168) are most of what it moves. Each side
            // keeps its capacity.
            std::mem::swap(tris, &mut self.tris);
            std::mem::swap(shaders, &mut self.shaders);
            std::mem::swap(wire, &mut self.wire);
            return;
        }
        let offset = shaders.len() as u32;
        tris.extend(self.tris.drain(..).map(|mut t| {
            t.shader += offset;
            t
        }));
        shaders.append(&mut self.shaders);
        wire.append(&mut self.wire);
    }

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
