//! The tangent-frame view (docs/tangent-frames.md):
//! at each vertex of the visible textured triangles, three short segments
//! for the frame the bump shaders use, T red, B green, N blue, drawn over
//! the picture with the line code of the lines display.
//!
//! The frame is the shaders' own (`Frame::new(n, ∂P/∂u, ∂P/∂v)` in world
//! space): the vertex normal and tangents, or the facet's when the plan
//! lights with facet normals (flat shading, or face normals). Which frames
//! show: those of vertices of front-facing triangles (what fill draws
//! before depth), and, when the frame has a depth buffer, only those whose
//! origin is not behind the surface drawn there. A frame shows whole or not
//! at all: its segments are an overlay, not depth-tested themselves, so
//! they stay readable where they cross their own surface.

use std::collections::HashSet;

use glam::{Vec3, Vec4};

use crate::plan::Plan;
use crate::raster::aa::MSAA_SAMPLES;
use crate::raster::wire::{Canvas, draw_line};
use crate::shade::tangent::Frame;
use relief_core::framebuffer::Framebuffer;
use relief_core::settings::Shading;
use relief_core::stats::Counters;
use relief_scene::world::World;
use relief_scene::{Scene, Triangle};

/// A segment's length as a fraction of its object's bounding radius: long
/// enough to read on the cube and on OBJ models...
pub const LENGTH_FRACTION: f32 = 0.15;

/// ...but at most this fraction of the median edge of the object's textured
/// triangles, so that on a finely tessellated model (the sphere) a frame
/// stops well short of the next vertex's and the segments do not join into
/// a grid.
pub const SPACING_FRACTION: f32 = 0.4;

/// The colours of T, B and N.
pub const T_COLOR: Vec3 = Vec3::X;
pub const B_COLOR: Vec3 = Vec3::Y;
pub const N_COLOR: Vec3 = Vec3::Z;

/// How far along N (as a fraction of the segment length) a frame's origin
/// is lifted before its depth test, so that it is in front of its own
/// surface and behind any other.
const DEPTH_LIFT: f32 = 0.1;

/// The depth a frame's origins are tested against: none, one per pixel,
/// or the multisampled one (the farthest of a pixel's samples counts).
#[derive(Clone, Copy)]
pub enum DepthView<'a> {
    None,
    Pixels(&'a [f32]),
    Samples(&'a [[f32; MSAA_SAMPLES]]),
}

impl DepthView<'_> {
    /// The farthest depth stored within `reach` pixels of (x, y), or
    /// `None` without a usable buffer.
    fn farthest_near(
        &self,
        x: i64,
        y: i64,
        reach: i64,
        width: usize,
        height: usize,
    ) -> Option<f32> {
        let len = width * height;
        let at = |i: usize| match self {
            DepthView::None => None,
            DepthView::Pixels(d) => (d.len() == len).then(|| d[i]),
            DepthView::Samples(d) => {
                (d.len() == len).then(|| d[i].iter().copied().fold(f32::NEG_INFINITY, f32::max))
            }
        };
        let mut far: Option<f32> = None;
        for yy in (y - reach).max(0)..=(y + reach).min(height as i64 - 1) {
            for xx in (x - reach).max(0)..=(x + reach).min(width as i64 - 1) {
                let d = at(yy as usize * width + xx as usize)?;
                far = Some(far.map_or(d, |f| f.max(d)));
            }
        }
        far
    }
}

/// One vertex's frame in world space, and the length of its segments.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VertexFrame {
    pub origin: Vec3,
    pub t: Vec3,
    pub b: Vec3,
    pub n: Vec3,
    pub length: f32,
}

/// The frames at the vertices of every front-facing textured triangle of
/// `scene` placed as `world` (back faces of open meshes count, with N
/// towards the eye, as fill lights them), each shared vertex once.
pub fn vertex_frames(scene: &Scene, world: &World, plan: &Plan) -> Vec<VertexFrame> {
    let mut frames = Vec::new();
    // Vertices split only for their UVs (a cube's corner on three faces)
    // share a position and a normal but not their tangents: one frame each.
    let mut seen = HashSet::new();
    let facets = plan.face_normals || plan.shading == Shading::Flat;
    for (object_index, (object, placed)) in scene.objects.iter().zip(world.objects()).enumerate() {
        let positions = &placed.positions;
        let Some(length) = segment_length(positions, &object.mesh.triangles) else {
            continue;
        };
        for (t, tri) in object.mesh.triangles.iter().enumerate() {
            // The renderer's cull.
            if !tri.textured || placed.sides[t] == 0 {
                continue;
            }
            let side = f32::from(placed.sides[t]);
            for i in tri.indices.map(|i| i as usize) {
                let v = placed.vertex(&object.mesh, i);
                let (n, pu, pv) = if facets {
                    let facet = object.mesh.facet(t);
                    (
                        placed.facet_normal(&object.mesh, t),
                        placed.linear * facet.tangent_u,
                        placed.linear * facet.tangent_v,
                    )
                } else {
                    (v.normal, v.tangent_u, v.tangent_v)
                };
                let n = n * side;
                let origin = v.position;
                if n == Vec3::ZERO || !origin.is_finite() {
                    continue;
                }
                let f = Frame::new(n, pu, pv);
                let bits = |v: Vec3| v.to_array().map(f32::to_bits);
                if !seen.insert((object_index, bits(origin), bits(f.n), bits(f.t), bits(f.b))) {
                    continue;
                }
                frames.push(VertexFrame {
                    origin,
                    t: f.t,
                    b: f.b,
                    n: f.n,
                    length,
                });
            }
        }
    }
    frames
}

/// The length of an object's segments (see `LENGTH_FRACTION` and
/// `SPACING_FRACTION`), when its size is finite and above 0.
fn segment_length(world: &[Vec3], triangles: &[Triangle]) -> Option<f32> {
    let by_size = bounding_radius(world)? * LENGTH_FRACTION;
    let mut edges: Vec<f32> = triangles
        .iter()
        .filter(|t| t.textured)
        .flat_map(|t| {
            let p = t.indices.map(|i| world.get(i as usize).copied());
            [(p[0], p[1]), (p[1], p[2]), (p[2], p[0])]
        })
        .filter_map(|(a, b)| Some(a?.distance(b?)))
        .filter(|d| d.is_finite() && *d > 0.0)
        .collect();
    if edges.is_empty() {
        return Some(by_size);
    }
    let middle = edges.len() / 2;
    let (_, median, _) = edges.select_nth_unstable_by(middle, f32::total_cmp);
    Some(by_size.min(*median * SPACING_FRACTION))
}

/// The largest distance from the centre of the points' bounding box to a
/// point, when finite and above 0.
fn bounding_radius(points: &[Vec3]) -> Option<f32> {
    let (lo, hi) = points
        .iter()
        .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), &p| {
            (lo.min(p), hi.max(p))
        });
    let centre = (lo + hi) * 0.5;
    let r = points
        .iter()
        .map(|p| p.distance(centre))
        .fold(0.0f32, f32::max);
    (r.is_finite() && r > 0.0).then_some(r)
}

/// Draws the plan's tangent frames of `scene` placed as `world` over `fb`
/// (already drawn), segments `brush` pixels thick, the origins tested
/// against `depth` (the frame's own depth buffer, of `fb`'s size). The
/// view's `aspect` (width over height, with the pixels' own shape: sub-cell
/// symbols draw pixels that are not square) is the one the surfaces were
/// projected with, so each frame starts on its vertex. Counts the segments
/// drawn.
pub fn draw_tangent_frames(
    scene: &Scene,
    world: &World,
    plan: &Plan,
    depth: DepthView,
    fb: &mut Framebuffer,
    (brush, aspect): (usize, f32),
) -> Counters {
    let mut counters = Counters::default();
    if !plan.tangent_frames {
        return counters;
    }
    let (width, height) = (fb.width(), fb.height());
    if width == 0 || height == 0 {
        return counters;
    }
    let view_proj = plan.camera.projection(aspect) * plan.camera.view();
    let clip = |p: Vec3| -> Vec4 { view_proj * p.extend(1.0) };
    let mut canvas = Canvas::new(width, height, fb.pixels_mut());
    for f in vertex_frames(scene, world, plan) {
        if !visible(
            clip(f.origin + f.n * (f.length * DEPTH_LIFT)),
            depth,
            brush,
            width,
            height,
        ) {
            continue;
        }
        let o = clip(f.origin);
        for (axis, color) in [(f.t, T_COLOR), (f.b, B_COLOR), (f.n, N_COLOR)] {
            let end = clip(f.origin + axis * f.length);
            draw_line((o, color), (end, color), brush, &mut canvas, &mut counters);
            counters.frame_lines += 1;
        }
    }
    counters
}

/// Whether a frame whose (lifted) origin is at clip position `p` shows:
/// not behind the farthest surface stored around its pixel. Off screen,
/// behind the camera or without a depth buffer it shows (its segments are
/// clipped like any line).
fn visible(p: Vec4, depth: DepthView, reach: usize, width: usize, height: usize) -> bool {
    if !(p.is_finite() && p.w > 0.0) {
        return true;
    }
    let ndc = p.truncate() / p.w;
    let x = ((ndc.x + 1.0) * 0.5 * width as f32).floor() as i64;
    let y = ((1.0 - ndc.y) * 0.5 * height as f32).floor() as i64;
    if x < 0 || y < 0 || x >= width as i64 || y >= height as i64 {
        return true;
    }
    match depth.farthest_near(x, y, reach as i64, width, height) {
        Some(far) => ndc.z <= far,
        None => true,
    }
}
