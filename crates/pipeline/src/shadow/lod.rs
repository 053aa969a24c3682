//! A dense caster's stand-in for the shadow pass (docs/shadows.md, "Dense
//! casters"): its surface simplified by edge collapses (meshoptimizer's
//! simplifier) to within half a texel of the map where the map's texels
//! are finest, so a mesh of a million triangles smaller than a texel is
//! drawn into the map as a few tens of thousands. The stand-in keeps a
//! subset of the mesh's own vertices, so it is placed with the frame's
//! world positions and needs no transform of its own.
//!
//! Made once per mesh and error (a power of two of the mesh's size), on
//! first need: on a thread of its own while the view goes on with the
//! exact casters ([`CasterLod::Background`]), or before the frame that
//! needs it ([`CasterLod::Wait`], for timings).

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, OnceLock, PoisonError};

use glam::Vec3;

use relief_core::budget::Reservation;
use relief_scene::Mesh;
use relief_scene::corners::position_ids;

/// Below this many triangles a caster is drawn as it is: its setup costs
/// less than making a stand-in would save.
pub const MIN_TRIANGLES: usize = 65_536;

/// How far the stand-in may stray from the surface by the simplifier's
/// estimate, in texels of the map where its texels are finest (the
/// casters' near side). The surface strays by up to about twice the
/// estimate (`tests`): about a texel, under the lookup's bias (one texel
/// and more) and the percentage-closer filter's own blur.
pub const ERROR_TEXELS: f32 = 0.5;

/// The errors made, relative to the mesh's size: 2^-6 to 2^-15 in steps
/// of a half power of two (a step of two would draw up to twice the
/// triangles needed). Finer than that a stand-in would keep most of a
/// mesh's triangles.
const COARSEST: f32 = 6.0;
const FINEST: f32 = 15.0;
const STEPS_PER_OCTAVE: f32 = 2.0;
const LEVELS: usize = ((FINEST - COARSEST) * STEPS_PER_OCTAVE) as usize + 1;

/// Whether the shadow pass draws a dense caster's stand-in.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum CasterLod {
    /// Never: every caster as it is (one frame alone, the tests).
    #[default]
    Off,
    /// When it is made; the first frame that needs one starts making it
    /// on a thread of its own, and the frames draw the exact casters until
    /// it is there (the view).
    Background,
    /// Always: a frame that needs one makes it first (timings).
    Wait,
}

/// A mesh simplified: `triangles` index `vertices`, which are indices of
/// the mesh's own vertices, each once, in increasing order.
#[derive(Debug, PartialEq)]
pub struct Lod {
    pub vertices: Vec<u32>,
    pub triangles: Vec<[u32; 3]>,
}

/// Called on the thread that made a stand-in in the background, once it
/// is there: the view draws again to show it.
#[derive(Clone)]
pub struct StandInReady(pub Arc<dyn Fn() + Send + Sync>);

impl std::fmt::Debug for StandInReady {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("StandInReady")
    }
}

/// Held by the thread making a stand-in in the background.
static MAKING: Mutex<()> = Mutex::new(());

/// One mesh's stand-ins by level, made or being made.
#[derive(Debug, Default)]
struct Levels {
    /// The largest side of the mesh's box, in its own space (NaN: a
    /// position is not finite).
    extent: f32,
    /// `None` inside: simplifying did not halve the triangles.
    made: [OnceLock<Option<Arc<Lod>>>; LEVELS],
    started: [AtomicBool; LEVELS],
}

/// Which mesh a cache entry is for: its triangles' and vertices' buffers,
/// and a sample of its triangles (a mesh made again in freed buffers, a
/// file read again, has other triangles as a rule). Not its positions: an
/// animation that carries a part whole moves them every frame.
type Key = (usize, usize, usize, usize, u64);

/// Triangles sampled for a cache key.
const SAMPLED: usize = 64;

/// The stand-ins of the scene's objects, kept from frame to frame for as
/// long as their meshes' buffers stay.
#[derive(Clone, Debug, Default)]
pub(super) struct LodCache {
    objects: Vec<Option<(Key, Arc<Levels>)>>,
    pub(super) ready: Option<StandInReady>,
}

impl LodCache {
    /// Object `i`'s stand-in for an error of at most `error` in its own
    /// space, when `mode` draws one and it is made (or, with
    /// [`CasterLod::Wait`], made now); `None` draws `mesh` as it is.
    pub(super) fn get(
        &mut self,
        i: usize,
        mesh: &Mesh,
        error: f32,
        mode: CasterLod,
    ) -> Option<Arc<Lod>> {
        if mode == CasterLod::Off || mesh.triangles.len() < MIN_TRIANGLES {
            return None;
        }
        let levels = self.levels(i, mesh);
        let level = level_for(error, levels.extent)?;
        if let Some(made) = levels.made[level].get() {
            return made.clone();
        }
        let relative = relative_error(level);
        let make = move |held: Reservation, (positions, triangles): Mesh32| {
            let made = simplify(&positions, &triangles, relative).map(Arc::new);
            drop((held, positions, triangles));
            made
        };
        match mode {
            CasterLod::Off => None,
            CasterLod::Wait => {
                let made = levels.made[level].get_or_init(|| {
                    let held = reserve_for(mesh).ok()?;
                    make(held, copy_of(mesh))
                });
                made.clone()
            }
            CasterLod::Background => {
                if levels.started[level].swap(true, Ordering::Relaxed) {
                    return None;
                }
                // Beyond the budget the casters stay exact.
                let Ok(held) = reserve_for(mesh) else {
                    let _ = levels.made[level].set(None);
                    return None;
                };
                let copy = copy_of(mesh);
                let levels = Arc::clone(&levels);
                let ready = self.ready.clone();
                let made = move || {
                    // One stand-in made at a time: a model of many dense
                    // parts should not take every core from the view.
                    let _turn = MAKING.lock().unwrap_or_else(PoisonError::into_inner);
                    let made = levels.made[level].get_or_init(|| make(held, copy));
                    if let (Some(_), Some(ready)) = (made, ready) {
                        (ready.0)();
                    }
                };
                let spawned = std::thread::Builder::new()
                    .name("relief-caster-lod".into())
                    .spawn(made);
                // Without a thread the casters stay exact.
                drop(spawned);
                None
            }
        }
    }

    /// Object `i`'s entry, made again when its mesh's buffers changed.
    fn levels(&mut self, i: usize, mesh: &Mesh) -> Arc<Levels> {
        if self.objects.len() <= i {
            self.objects.resize(i + 1, None);
        }
        let (t, v) = (&mesh.triangles, &mesh.vertices);
        let key = (
            t.as_ptr() as usize,
            t.len(),
            v.as_ptr() as usize,
            v.len(),
            sample(mesh),
        );
        match &self.objects[i] {
            Some((k, levels)) if *k == key => Arc::clone(levels),
            _ => {
                let levels = Arc::new(Levels {
                    extent: extent(mesh),
                    ..Levels::default()
                });
                self.objects[i] = Some((key, Arc::clone(&levels)));
                levels
            }
        }
    }
}

/// A hash of [`SAMPLED`] of `mesh`'s triangles, evenly spaced.
fn sample(mesh: &Mesh) -> u64 {
    use std::hash::{BuildHasher, Hash, Hasher};
    let mut hasher = foldhash::fast::FixedState::with_seed(0).build_hasher();
    let step = (mesh.triangles.len() / SAMPLED).max(1);
    for t in mesh.triangles.iter().step_by(step) {
        t.indices.hash(&mut hasher);
    }
    hasher.finish()
}

/// The largest side of `mesh`'s box: NaN when a position is not finite,
/// 0 when the box is a point (neither has a level: such a mesh is drawn
/// as it is).
fn extent(mesh: &Mesh) -> f32 {
    let mut lo = Vec3::splat(f32::INFINITY);
    let mut hi = Vec3::splat(f32::NEG_INFINITY);
    for v in &mesh.vertices {
        lo = lo.min(v.position);
        hi = hi.max(v.position);
    }
    if lo.is_finite() && hi.is_finite() {
        (hi - lo).max_element()
    } else {
        f32::NAN
    }
}

/// The level whose error (a fraction of `extent`) is the largest at most
/// `error`; `None` past the finest.
fn level_for(error: f32, extent: f32) -> Option<usize> {
    let ratio = error / extent;
    if !(ratio.is_finite() && ratio > 0.0) {
        return None;
    }
    // 2^-(COARSEST + k/STEPS) <= ratio  <=>  k >= STEPS·(-log2(ratio) - COARSEST).
    let k = (STEPS_PER_OCTAVE * (-ratio.log2() - COARSEST))
        .ceil()
        .max(0.0);
    let level = k as usize;
    // Rounding at a step's edge: the level asked for must not err more.
    let level = level + usize::from(relative_error(level) > ratio);
    (level < LEVELS).then_some(level)
}

/// The error of `level` relative to the mesh's size.
fn relative_error(level: usize) -> f32 {
    (-(COARSEST + level as f32 / STEPS_PER_OCTAVE)).exp2()
}

/// A mesh's positions and triangles, as the simplifier reads them.
type Mesh32 = (Vec<Vec3>, Vec<[u32; 3]>);

/// Bytes that making a stand-in of a mesh holds at its peak, per triangle
/// and per vertex: the copy, the weld and the simplifier's own tables. The
/// dented sphere's million triangles and 520 K vertices took 87 MB more
/// peak resident memory; these reserve 114 MB for it.
const MAKING_BYTES_PER_TRIANGLE: u64 = 64;
const MAKING_BYTES_PER_VERTEX: u64 = 96;

/// The memory budget's reservation for making a stand-in of `mesh`.
fn reserve_for(mesh: &Mesh) -> Result<Reservation, relief_core::budget::BudgetError> {
    let bytes = mesh.triangles.len() as u64 * MAKING_BYTES_PER_TRIANGLE
        + mesh.vertices.len() as u64 * MAKING_BYTES_PER_VERTEX;
    relief_core::budget::reserve("a dense caster's shadow stand-in", bytes)
}

/// The mesh's positions and triangles, for a simplification that may
/// outlive the frame.
fn copy_of(mesh: &Mesh) -> Mesh32 {
    let positions = mesh.vertices.iter().map(|v| v.position);
    let triangles = mesh.triangles.iter().map(|t| t.indices);
    (positions.collect(), triangles.collect())
}

/// `triangles` over `positions` simplified to within `relative` of the
/// mesh's size (its box's largest side), or `None` when that does not
/// halve them. Vertices at the same position are welded first (the
/// scene's `position_ids`): a file that repeats its corners per face, or
/// splits them at a seam, is one surface, and the simplifier, which sees
/// every vertex at a position, would keep such a place as a seam (a third
/// of the collapses or more).
pub fn simplify(positions: &[Vec3], triangles: &[[u32; 3]], relative: f32) -> Option<Lod> {
    let (welded, count) = position_ids(positions);
    // Each distinct position once, and the first vertex there.
    let mut first_vertex = vec![u32::MAX; count];
    for (v, &id) in welded.iter().enumerate().rev() {
        first_vertex[id as usize] = v as u32;
    }
    let points: Vec<Vec3> = first_vertex
        .iter()
        .map(|&v| positions[v as usize])
        .collect();
    let indices: Option<Vec<u32>> = triangles
        .iter()
        .flatten()
        .map(|&v| welded.get(v as usize).copied())
        .collect();
    let stream = meshopt::VertexDataAdapter::new(meshopt::typed_to_bytes(&points), 12, 0).ok()?;
    let kept = meshopt::simplify(
        &indices?,
        &stream,
        0,
        relative,
        meshopt::SimplifyOptions::empty(),
        None,
    );
    if kept.len() / 3 > triangles.len() / 2 {
        return None;
    }
    // The vertices kept, in the mesh's order (each frame reads their world
    // positions: in order, the reads go one way through memory).
    let mut local = vec![u32::MAX; points.len()];
    kept.iter().for_each(|&p| local[p as usize] = 0);
    let mut vertices = Vec::new();
    for (p, slot) in local.iter_mut().enumerate() {
        if *slot == 0 {
            *slot = vertices.len() as u32;
            vertices.push(first_vertex[p]);
        }
    }
    let triangles = kept
        .chunks_exact(3)
        .map(|t| [t[0], t[1], t[2]].map(|p| local[p as usize]))
        .collect();
    Some(Lod {
        vertices,
        triangles,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_level_errs_at_most_what_was_asked() {
        for (error, extent) in [(0.01, 1.0), (1e-3, 2.9), (0.5, 1.0), (3e-4, 0.1)] {
            let level = level_for(error, extent).unwrap();
            assert!(relative_error(level) * extent <= error, "{error} {extent}");
            if level > 0 {
                assert!(
                    relative_error(level - 1) * extent > error,
                    "{error} {extent}"
                );
            }
        }
        assert_eq!(level_for(1e-9, 1.0), None);
        assert_eq!(level_for(f32::NAN, 1.0), None);
        assert_eq!(level_for(10.0, 1.0), Some(0));
    }

    /// A UV sphere of unit radius: positions and triangles.
    fn sphere(rings: u32, segments: u32) -> (Vec<Vec3>, Vec<[u32; 3]>) {
        let mut positions = Vec::new();
        for i in 0..=rings {
            let theta = std::f32::consts::PI * i as f32 / rings as f32;
            for j in 0..segments {
                let phi = std::f32::consts::TAU * j as f32 / segments as f32;
                let p = Vec3::new(
                    theta.sin() * phi.cos(),
                    theta.cos(),
                    theta.sin() * phi.sin(),
                );
                positions.push(p);
            }
        }
        let at = |i: u32, j: u32| i * segments + j % segments;
        let mut triangles = Vec::new();
        for i in 0..rings {
            for j in 0..segments {
                let (a, b, c, d) = (at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i + 1, j));
                triangles.push([a, c, b]);
                triangles.push([a, d, c]);
            }
        }
        (positions, triangles)
    }

    /// A mesh whose corners are repeated per face (as STL files are)
    /// simplifies as far as the same mesh indexed; the stand-in's vertices
    /// are the mesh's own, each once; its faces stray from the sphere by at
    /// most twice the error asked (the simplifier's error is an estimate).
    #[test]
    fn a_triangle_soup_simplifies_as_its_indexed_mesh() {
        let (positions, triangles) = sphere(60, 120);
        let soup_positions: Vec<Vec3> = triangles
            .iter()
            .flatten()
            .map(|&v| positions[v as usize])
            .collect();
        let soup: Vec<[u32; 3]> = (0..triangles.len() as u32)
            .map(|t| [3 * t, 3 * t + 1, 3 * t + 2])
            .collect();
        let relative = 1.0 / 256.0;
        let indexed = simplify(&positions, &triangles, relative).expect("halved");
        let welded = simplify(&soup_positions, &soup, relative).expect("halved");
        assert!(
            indexed.triangles.len() * 10 < triangles.len(),
            "{}",
            indexed.triangles.len()
        );
        assert_eq!(welded.triangles.len(), indexed.triangles.len());
        for lod in [&indexed, &welded] {
            let increasing = lod.vertices.windows(2).all(|w| w[0] < w[1]);
            assert!(increasing, "each vertex once, in order");
            for t in &lod.triangles {
                assert!(t.iter().all(|&k| (k as usize) < lod.vertices.len()));
            }
        }
        for relative in [1.0 / 64.0, 1.0 / 128.0, 1.0 / 256.0, 1.0 / 512.0] {
            let lod = simplify(&positions, &triangles, relative).expect("halved");
            let mut worst = 0.0f32;
            for t in &lod.triangles {
                let [a, b, c] = t.map(|k| positions[lod.vertices[k as usize] as usize]);
                for p in [
                    (a + b + c) / 3.0,
                    (a + b) / 2.0,
                    (b + c) / 2.0,
                    (c + a) / 2.0,
                ] {
                    worst = worst.max(1.0 - p.length());
                }
            }
            // The simplifier's error is an estimate from its quadrics: the
            // surface strays by up to 1.8 times it here (the box's side is 2).
            assert!(worst <= 2.0 * (2.0 * relative), "{relative}: {worst}");
            assert!(
                worst >= 0.5 * (2.0 * relative),
                "{relative}: {worst}, not simplified"
            );
        }
    }
}
