//! The depth-only rasterizer of the shadow pass: no colour, no attributes,
//! just the nearest distance along the light's axis per texel.
//!
//! The casters' triangles are set up once (corners in texels, the rows
//! they cover) and sorted into bands of rows as they are, then the bands
//! are filled, in parallel when the map has enough to fill. Every band goes through its triangles in the casters'
//! order and a texel is in one band only, so each texel sees the same
//! depths in the same order whatever the bands: the nearest wins, and of
//! equal ones the first, as with one band.

use std::borrow::Cow;

use glam::{Mat4, Vec2, Vec3};
use rayon::prelude::*;
use wide::{f32x4, f32x8};

use relief_scene::Mesh;
use relief_scene::repeats::RepeatSkipper;
use relief_scene::terms::Cutout;
use relief_scene::world::Placed;

use super::lod::Lod;

/// What the pass draws into: the map's texels (`size × size`, row 0 at the
/// top) and the light's view (the map keeps them; the pass needs no more).
pub(super) struct Target<'a> {
    pub size: usize,
    /// Distance along the light's axis of the nearest caster, per texel.
    pub depth: &'a mut [f32],
    /// Which object that nearest caster is, per texel.
    pub owner: &'a mut [u32],
    pub view_proj: Mat4,
    pub light: Vec3,
    pub near: f32,
}

/// Triangles set up, or visited by a band, between two questions to the
/// pass's [`Watch`].
pub const CHECK_EVERY: usize = 4096;

/// Bands per thread: a few, so a thread that finishes early takes another.
const BANDS_PER_THREAD: usize = 8;

/// Below this many texels to test (the triangles' areas) one thread fills
/// the map faster than several.
const PARALLEL_MIN_TEXELS: f64 = 32_768.0;

/// How the pass reports to whoever waits for it. Asked from the threads
/// that fill the bands, so it must be cheap and thread-safe.
pub trait Watch: Sync {
    /// The fills start: they will make `visits` triangle visits (a
    /// triangle is visited once by each band of rows it crosses).
    fn start(&self, visits: u64);
    /// `visits` more triangle visits made.
    fn advance(&self, visits: usize);
    /// Whether to stop now (the map is then incomplete). Asked every
    /// [`CHECK_EVERY`] triangles set up and every [`CHECK_EVERY`] visits
    /// of a band.
    fn stop(&self) -> bool;
}

/// A watch that never stops and counts nothing.
pub struct Unwatched;

impl Watch for Unwatched {
    fn start(&self, _: u64) {}
    fn advance(&self, _: usize) {}
    fn stop(&self) -> bool {
        false
    }
}

/// A caster triangle ready to fill (56 bytes).
#[derive(Clone, Copy, Debug)]
pub(super) struct Setup {
    /// Corners: texel coordinates and 1/w.
    corners: [(f32, f32, f32); 3],
    /// Twice the signed area in texels (either winding).
    area: f32,
    /// The rows and columns of its bounding box, clipped to the map (whose
    /// side fits in u16: `shadow::MAX_SIZE`).
    rows: (u16, u16),
    columns: (u16, u16),
    /// Its object (index in `Scene::objects`) and its index in that
    /// object's mesh (for the alpha mask's UVs).
    object: u32,
    triangle: u32,
}

impl Setup {
    /// Texels in its box: columns, and all of them.
    fn box_texels(&self) -> (usize, usize) {
        let columns = usize::from(self.columns.1 - self.columns.0);
        (columns, columns * usize::from(self.rows.1 - self.rows.0))
    }
}

// A triangle set up takes 56 bytes.
const _: () = assert!(std::mem::size_of::<Setup>() == 56);

/// The casters' alpha masks by object, with their meshes (for the UVs).
pub(super) type Masks<'a> = [Option<(&'a Cutout, &'a Mesh)>];

/// Triangles per task of the set-up: on several threads a big mesh is set
/// up in chunks of consecutive triangles, in parallel, each chunk kept
/// apart and filled in its order.
const SETUP_CHUNK: usize = 16_384;

/// Rows per band of the fill and how many bands, fixed before the setup so
/// that each chunk of triangles sorts its own into the bands as it sets
/// them up (on the threads: nothing is left to join or sort on one).
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Bands {
    rows: usize,
    count: usize,
}

impl Bands {
    /// The bands of a map of side `size` filled on `threads` threads:
    /// [`BANDS_PER_THREAD`] of equal rows per thread, one band on one thread.
    pub(super) fn for_map(size: usize, threads: usize) -> Bands {
        let wanted = if threads > 1 {
            threads * BANDS_PER_THREAD
        } else {
            1
        };
        let rows = size.div_ceil(wanted).max(1);
        Bands {
            rows,
            count: size.div_ceil(rows),
        }
    }
}

/// Consecutive caster triangles set up by one task (kept from frame to
/// frame, as its buffers).
#[derive(Clone, Debug, Default)]
struct SetupChunk {
    setups: Vec<Setup>,
    /// Per band (none with one band): the indices in `setups` of the
    /// triangles whose rows cross it, in order.
    bins: Vec<Vec<u32>>,
    /// Half the sum of the setups' areas: about the texels their fill tests.
    texels: f64,
}

impl SetupChunk {
    fn clear(&mut self, bands: Bands) {
        self.setups.clear();
        self.texels = 0.0;
        let bins = if bands.count > 1 { bands.count } else { 0 };
        self.bins.resize_with(bins, Vec::new);
        self.bins.iter_mut().for_each(Vec::clear);
    }

    fn push(&mut self, setup: Setup, bands: Bands) {
        let k = self.setups.len() as u32;
        self.texels += 0.5 * f64::from(setup.area.abs());
        if bands.count > 1 {
            // A setup's rows are not empty and end at the map's side.
            let first = usize::from(setup.rows.0) / bands.rows;
            let last = (usize::from(setup.rows.1) - 1) / bands.rows;
            for bin in &mut self.bins[first..=last] {
                bin.push(k);
            }
        }
        self.setups.push(setup);
    }
}

/// Every caster's triangles set up, chunk by chunk in the casters' order
/// and each chunk's in triangle order, sorted into the fill's bands.
#[derive(Clone, Debug, Default)]
pub(super) struct Setups {
    chunks: Vec<SetupChunk>,
    used: usize,
    bands: Bands,
}

impl Setups {
    /// Forgets the last frame's setups (keeping the buffers) for a map
    /// filled in `bands`.
    pub(super) fn start(&mut self, bands: Bands) {
        self.used = 0;
        self.bands = bands;
    }

    /// `count` more chunks, cleared, after those in use.
    fn take(&mut self, count: usize) -> &mut [SetupChunk] {
        let range = self.used..self.used + count;
        if self.chunks.len() < range.end {
            self.chunks.resize_with(range.end, SetupChunk::default);
        }
        self.used = range.end;
        let chunks = &mut self.chunks[range];
        chunks.iter_mut().for_each(|c| c.clear(self.bands));
        chunks
    }

    fn in_use(&self) -> &[SetupChunk] {
        &self.chunks[..self.used]
    }
}

/// Sets up `mesh` (object `object`) placed as `placed` into `setups`, but
/// for the triangles `repeats` (its repeated triangles) skips, the faces
/// second-depth drops, and those that cover no texel centre; stops
/// (returning false) as soon as `watch` says so. The vertices are projected
/// once into `projected` (kept from frame to frame: a big mesh's 16 MB a
/// frame cost page faults). On several threads a big mesh is set up in
/// chunks of consecutive triangles, in parallel, each into a chunk of its
/// own, which also sorts them into the fill's bands.
#[allow(clippy::too_many_arguments)]
pub(super) fn set_up_mesh(
    map: &Target,
    mesh: &Mesh,
    placed: &Placed,
    object: u32,
    repeats: &[(u32, u32)],
    watch: &dyn Watch,
    setups: &mut Setups,
    projected: &mut Vec<[f32; 3]>,
) -> bool {
    let positions = &placed.positions;
    project_vertices(map, positions.len(), |v| positions[v], projected);
    let projected = &projected[..];
    let triangles = &mesh.triangles;
    // Every facet, for the second-depth cull: the frame's own when its
    // world made them (a frame with a shadow pass does), else made here.
    let facets: Cow<[Vec3]> = if !mesh.closed || placed.facets.len() == triangles.len() {
        Cow::Borrowed(&placed.facets)
    } else if triangles.len() < SETUP_CHUNK {
        Cow::Owned(
            (0..triangles.len())
                .map(|t| placed.facet(mesh, t))
                .collect(),
        )
    } else {
        let all = (0..triangles.len()).into_par_iter();
        Cow::Owned(all.map(|t| placed.facet(mesh, t)).collect())
    };
    let bands = setups.bands;
    let run = |range: std::ops::Range<usize>, out: &mut SetupChunk| -> bool {
        let first = repeats.partition_point(|&(r, _)| (r as usize) < range.start);
        let mut repeats = RepeatSkipper::new(&repeats[first..]);
        for i in range {
            if repeats.skip(i, triangles) {
                continue;
            }
            if i % CHECK_EVERY == CHECK_EVERY - 1 && watch.stop() {
                return false;
            }
            let indices = triangles[i].indices;
            let [a, b, c] = indices.map(|i| projected.get(i as usize).copied());
            let (Some(a), Some(b), Some(c)) = (a, b, c) else {
                continue;
            };
            if a[2] == 0.0 || b[2] == 0.0 || c[2] == 0.0 {
                continue;
            }
            if mesh.closed {
                // Second depth: keep the faces turned away from the light.
                if facets[i].dot(map.light - positions[indices[0] as usize]) > 0.0 {
                    continue;
                }
            }
            let corners = [a, b, c].map(|[x, y, q]| (x, y, q));
            if let Some(s) = set_up(map.size, corners, object, i as u32) {
                out.push(s, bands);
            }
        }
        true
    };
    in_chunks(triangles.len(), setups, run)
}

/// Sets up the stand-in `lod` of a mesh (closed or not) placed as `placed`
/// (object `object`), as [`set_up_mesh`] sets up the mesh itself but for
/// the cull: a closed stand-in keeps the faces its corners, seen from the
/// light, wind as the faces turned away from it do (the stand-in's facets
/// are its corners'). Its vertices alone are projected.
#[allow(clippy::too_many_arguments)]
pub(super) fn set_up_lod(
    map: &Target,
    lod: &Lod,
    closed: bool,
    placed: &Placed,
    object: u32,
    watch: &dyn Watch,
    setups: &mut Setups,
    projected: &mut Vec<[f32; 3]>,
) -> bool {
    let positions = &placed.positions;
    let position = |k: usize| {
        let v = lod.vertices[k] as usize;
        positions.get(v).copied().unwrap_or(Vec3::NAN)
    };
    project_vertices(map, lod.vertices.len(), position, projected);
    let projected = &projected[..];
    let bands = setups.bands;
    let run = |range: std::ops::Range<usize>, out: &mut SetupChunk| -> bool {
        for i in range {
            if i % CHECK_EVERY == CHECK_EVERY - 1 && watch.stop() {
                return false;
            }
            let [a, b, c] = lod.triangles[i].map(|k| projected[k as usize]);
            if a[2] == 0.0 || b[2] == 0.0 || c[2] == 0.0 {
                continue;
            }
            if closed && !turned_away(a, b, c) {
                continue;
            }
            let corners = [a, b, c].map(|[x, y, q]| (x, y, q));
            if let Some(s) = set_up(map.size, corners, object, i as u32) {
                out.push(s, bands);
            }
        }
        true
    };
    in_chunks(lod.triangles.len(), setups, run)
}

/// Whether the triangle of map corners `a`, `b`, `c` (texels, row 0 at the
/// top, each in front of the light) is a face turned away from the light:
/// one whose corners wind counter-clockwise seen from behind, so clockwise
/// on the map, whose rows run down.
pub(super) fn turned_away(a: [f32; 3], b: [f32; 3], c: [f32; 3]) -> bool {
    (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]) > 0.0
}

/// Runs `run` over triangles `0..n` into chunks taken from `setups`: one
/// chunk on one thread or for a small mesh, else chunks of
/// [`SETUP_CHUNK`] consecutive triangles in parallel. Whether every chunk
/// ran to its end (none was stopped by the watch).
fn in_chunks(
    n: usize,
    setups: &mut Setups,
    run: impl Fn(std::ops::Range<usize>, &mut SetupChunk) -> bool + Sync,
) -> bool {
    if rayon::current_num_threads() == 1 || n <= SETUP_CHUNK {
        return run(0..n, &mut setups.take(1)[0]);
    }
    let chunks = setups.take(n.div_ceil(SETUP_CHUNK));
    chunks
        .par_iter_mut()
        .enumerate()
        .map(|(c, chunk)| run(c * SETUP_CHUNK..((c + 1) * SETUP_CHUNK).min(n), chunk))
        .all(|whole| whole)
}

/// Per vertex `0..count`, whose world position is `position(k)`, into
/// `projected`: its texel coordinates on `map` and 1/w, or 1/w = 0 (never
/// a real one, which is positive) when it is too near the light or not
/// finite. In parallel for a big mesh.
fn project_vertices(
    map: &Target,
    count: usize,
    position: impl Fn(usize) -> Vec3 + Sync,
    projected: &mut Vec<[f32; 3]>,
) {
    let size = map.size as f32;
    let project = |world: Vec3, out: &mut [f32; 3]| {
        let clip = map.view_proj * world.extend(1.0);
        *out = if clip.w > map.near * 0.5 && clip.is_finite() {
            let inv_w = 1.0 / clip.w;
            let x = (clip.x * inv_w * 0.5 + 0.5) * size;
            let y = (0.5 - clip.y * inv_w * 0.5) * size;
            [x, y, inv_w]
        } else {
            [0.0; 3]
        };
    };
    let run = |start: usize, out: &mut [[f32; 3]]| {
        let each = out.iter_mut().enumerate();
        each.for_each(|(k, p)| project(position(start + k), p));
    };
    projected.clear();
    projected.resize(count, [0.0; 3]);
    if count < SETUP_CHUNK {
        run(0, projected);
    } else {
        let chunks = projected.par_chunks_mut(SETUP_CHUNK).enumerate();
        chunks.for_each(|(c, out)| run(c * SETUP_CHUNK, out));
    }
}

/// One triangle's setup, or None if it would write no texel: no area, NaN
/// corners, a box off the map, or a box of at most [`SMALL_BOX`] texels
/// none of whose centres it covers.
fn set_up(size: usize, corners: [(f32, f32, f32); 3], object: u32, triangle: u32) -> Option<Setup> {
    let [(x0, y0, _), (x1, y1, _), (x2, y2, _)] = corners;
    let area = (x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0);
    // Also refuses NaN.
    if area.abs().partial_cmp(&1e-12) != Some(std::cmp::Ordering::Greater) {
        return None;
    }
    let lo_x = x0.min(x1).min(x2).floor().max(0.0) as usize;
    let hi_x = (x0.max(x1).max(x2).ceil().min(size as f32)) as usize;
    let lo_y = y0.min(y1).min(y2).floor().max(0.0) as usize;
    let hi_y = (y0.max(y1).max(y2).ceil().min(size as f32)) as usize;
    if lo_x >= hi_x || lo_y >= hi_y {
        return None;
    }
    let setup = Setup {
        corners,
        area,
        rows: (lo_y as u16, hi_y as u16),
        columns: (lo_x as u16, hi_x as u16),
        object,
        triangle,
    };
    // Most triangles of a dense mesh cover a texel centre or none: one
    // that covers none would write nothing, so it is not kept.
    let small = (hi_x - lo_x) * (hi_y - lo_y) <= SMALL_BOX;
    (!small || covers_a_centre(&setup)).then_some(setup)
}

/// Texels in a bounding box tested centre by centre at setup.
const SMALL_BOX: usize = 4;

/// Whether `t` (a box of at most [`SMALL_BOX`] texels) covers a texel
/// centre of its box, tested as [`fill`] tests it (see [`SmallBox`]), so a
/// triangle refused here is one `fill` would find outside every centre.
fn covers_a_centre(t: &Setup) -> bool {
    SmallBox::of(t).inside != 0
}

/// A box of at most [`SMALL_BOX`] texels, all at once, a texel per lane:
/// lane k is texel (k mod w, k div w) of a box w texels wide. Each lane's
/// weights are the operations [`fill`] makes on the same numbers (IEEE
/// arithmetic rounds alike in any lane), so the same bits. A loop that
/// stops at the first centre inside mispredicts on most triangles of a
/// dense mesh; this has no branch.
struct SmallBox {
    /// The lanes whose texel centre is inside (bit k for lane k).
    inside: u32,
    weights: [f32x4; 3],
    /// Each lane's texel: column and row offsets in the box.
    steps: ([f32; 4], [f32; 4]),
}

impl SmallBox {
    const STEPS: [([f32; 4], [f32; 4]); 5] = [
        ([0.0; 4], [0.0; 4]),
        ([0.0, 0.0, 0.0, 0.0], [0.0, 1.0, 2.0, 3.0]),
        ([0.0, 1.0, 0.0, 1.0], [0.0, 0.0, 1.0, 1.0]),
        ([0.0, 1.0, 2.0, 0.0], [0.0, 0.0, 0.0, 1.0]),
        ([0.0, 1.0, 2.0, 3.0], [0.0; 4]),
    ];

    #[inline]
    fn of(t: &Setup) -> SmallBox {
        let (w, texels) = t.box_texels();
        let steps = Self::STEPS[w.min(4)];
        let [(x0, y0, _), (x1, y1, _), (x2, y2, _)] = t.corners;
        let [x0, y0, x1, y1, x2, y2] = [x0, y0, x1, y1, x2, y2].map(f32x4::splat);
        let inv_area = f32x4::splat(1.0 / t.area);
        // Centres tx + 0.5 and ty + 0.5, exact in f32 (below 2^23).
        let px = f32x4::splat(f32::from(t.columns.0) + 0.5) + f32x4::from(steps.0);
        let py = f32x4::splat(f32::from(t.rows.0) + 0.5) + f32x4::from(steps.1);
        let (dy0, dy1, dy2) = (y0 - py, y1 - py, y2 - py);
        let b0 = ((x1 - px) * dy2 - (x2 - px) * dy1) * inv_area;
        let b1 = ((x2 - px) * dy0 - (x0 - px) * dy2) * inv_area;
        let b2 = f32x4::ONE - b0 - b1;
        let outside = b0.simd_lt(f32x4::ZERO) | b1.simd_lt(f32x4::ZERO) | b2.simd_lt(f32x4::ZERO);
        let inside = !outside.to_bitmask() & ((1 << texels) - 1);
        SmallBox {
            inside,
            weights: [b0, b1, b2],
            steps,
        }
    }
}

/// [`fill`] of a triangle whose box holds at most [`SMALL_BOX`] texels and
/// has no mask, its rows `y0..y1` of the map's (`depth` and `owner` hold
/// them): the same texels and depths, without a row loop.
fn fill_small(depth: &mut [f32], owner: &mut [u32], size: usize, y0: usize, t: &Setup) -> u64 {
    let lanes = SmallBox::of(t);
    let mut inside = lanes.inside;
    if inside == 0 {
        return 0;
    }
    let [(_, _, q0), (_, _, q1), (_, _, q2)] = t.corners;
    let [b0, b1, b2] = lanes.weights;
    let q = b0 * f32x4::splat(q0) + b1 * f32x4::splat(q1) + b2 * f32x4::splat(q2);
    let d = (f32x4::ONE / q).to_array();
    let y1 = y0 + depth.len() / size;
    let mut written = 0;
    while inside != 0 {
        let k = inside.trailing_zeros() as usize;
        inside &= inside - 1;
        let ty = usize::from(t.rows.0) + lanes.steps.1[k] as usize;
        let tx = usize::from(t.columns.0) + lanes.steps.0[k] as usize;
        if ty < y0 || ty >= y1 {
            continue;
        }
        let at = (ty - y0) * size + tx;
        if d[k] < depth[at] {
            depth[at] = d[k];
            owner[at] = t.object;
            written += 1;
        }
    }
    written
}

/// Fills the set-up triangles into the map, in parallel in the bands they
/// were sorted into when there is enough to fill (else as one band),
/// keeping per texel the nearest depth (the first of equal ones) and its
/// object. Tells `watch` the visits to come, counts them and stops when it
/// says so. Returns the texels written.
pub(super) fn fill_all(map: &mut Target, setups: &Setups, masks: &Masks, watch: &dyn Watch) -> u64 {
    let size = map.size;
    let chunks = setups.in_use();
    let bands = setups.bands;
    let texels: f64 = chunks.iter().map(|c| c.texels).sum();
    if bands.count == 1 || texels < PARALLEL_MIN_TEXELS {
        let visits = chunks.iter().map(|c| c.setups.len()).sum();
        watch.start(visits as u64);
        let all = chunks.iter().flat_map(|c| &c.setups);
        return fill_band(map.depth, map.owner, size, 0, all, visits, masks, watch);
    }
    let visits = chunks
        .iter()
        .flat_map(|c| &c.bins)
        .map(Vec::len)
        .sum::<usize>();
    watch.start(visits as u64);
    let texels_per_band = bands.rows * size;
    let depth = map.depth.par_chunks_mut(texels_per_band);
    depth
        .zip(map.owner.par_chunks_mut(texels_per_band))
        .enumerate()
        .with_max_len(1)
        .map(|(b, (depth, owner))| {
            // The band's triangles, in the casters' order.
            let tris = chunks
                .iter()
                .flat_map(|c| c.bins[b].iter().map(move |&k| &c.setups[k as usize]));
            let visits = chunks.iter().map(|c| c.bins[b].len()).sum();
            fill_band(
                depth,
                owner,
                size,
                b * bands.rows,
                tris,
                visits,
                masks,
                watch,
            )
        })
        .sum()
}

/// Fills the triangles `tris` (`visits` of them) into the band of rows
/// starting at `y0` (`depth` and `owner` hold its rows), asking `watch`
/// every [`CHECK_EVERY`] of them. Returns the texels written.
#[allow(clippy::too_many_arguments)]
fn fill_band<'a>(
    depth: &mut [f32],
    owner: &mut [u32],
    size: usize,
    y0: usize,
    tris: impl Iterator<Item = &'a Setup>,
    visits: usize,
    masks: &Masks,
    watch: &dyn Watch,
) -> u64 {
    let y1 = y0 + depth.len() / size;
    let mut written = 0;
    for (n, t) in tris.enumerate() {
        if n % CHECK_EVERY == CHECK_EVERY - 1 && {
            watch.advance(CHECK_EVERY);
            watch.stop()
        } {
            return written;
        }
        let small = t.box_texels().1 <= SMALL_BOX;
        if small && masks[t.object as usize].is_none() {
            written += fill_small(depth, owner, size, y0, t);
            continue;
        }
        let mask = masks[t.object as usize].map(|(cutout, mesh)| {
            let indices = mesh.triangles[t.triangle as usize].indices;
            let uv = indices.map(|i| mesh.vertices[i as usize].uv);
            // Only a transmission map on the second set reads it.
            let uv2 = Some(mesh.uv2())
                .filter(|set| cutout.reads_second_set() && !set.is_empty())
                .map(|set| indices.map(|i| set.get(i as usize).copied().unwrap_or_default()));
            (cutout, uv, uv2)
        });
        let rows = (t.rows.0 as usize).max(y0)..(t.rows.1 as usize).min(y1);
        written += fill(depth, owner, size, y0, rows, t, mask);
    }
    watch.advance(visits % CHECK_EVERY);
    written
}

/// A caster's cut-out on one triangle: the corners' UVs, and their second
/// set when the cut-out reads it.
type Mask<'a> = (&'a Cutout, [Vec2; 3], Option<[Vec2; 3]>);

/// Fills `rows` of one triangle (texel centres inside, either winding),
/// keeping the nearest depth; `depth` and `owner` hold the rows from `y0`.
/// `q` is 1/w, which is linear across the projected triangle. With a
/// `mask` (the alpha mask and the corners' two UV sets), a texel whose point it
/// cuts out is left as it is; its UV is perspective-correct (uv·q is
/// linear too), as the main pass reads it. Eight texels of a row at a
/// time: each lane's weights and depth are the same operations on the same
/// numbers as one texel's, so the same bits.
fn fill(
    depth: &mut [f32],
    owner: &mut [u32],
    size: usize,
    y0: usize,
    rows: std::ops::Range<usize>,
    t: &Setup,
    mask: Option<Mask>,
) -> u64 {
    let [(x0, y0f, q0), (x1, y1f, q1), (x2, y2f, q2)] = t.corners;
    let (lo_x, hi_x) = (t.columns.0 as usize, t.columns.1 as usize);
    let object = t.object;
    let inv_area = f32x8::splat(1.0 / t.area);
    let [x0, x1, x2, q0, q1, q2] = [x0, x1, x2, q0, q1, q2].map(f32x8::splat);
    let lane_offset = f32x8::from(std::array::from_fn::<f32, 8, _>(|k| k as f32));
    let mut written = 0;
    for ty in rows {
        let py = ty as f32 + 0.5;
        let [dy0, dy1, dy2] = [y0f - py, y1f - py, y2f - py].map(f32x8::splat);
        let at = (ty - y0) * size;
        let row = &mut depth[at..at + size];
        let owners = &mut owner[at..at + size];
        let mut tx = lo_x;
        while tx < hi_x {
            let lanes = (hi_x - tx).min(8);
            // Texel centres tx + k + 0.5, exact in f32 (below 2^23).
            let px = f32x8::splat(tx as f32 + 0.5) + lane_offset;
            // Barycentric weights, positive inside for either winding.
            let b0 = ((x1 - px) * dy2 - (x2 - px) * dy1) * inv_area;
            let b1 = ((x2 - px) * dy0 - (x0 - px) * dy2) * inv_area;
            let b2 = f32x8::ONE - b0 - b1;
            let outside =
                b0.simd_lt(f32x8::ZERO) | b1.simd_lt(f32x8::ZERO) | b2.simd_lt(f32x8::ZERO);
            let inside = !outside.to_bitmask() & ((1 << lanes) - 1);
            if inside != 0 {
                let q = b0 * q0 + b1 * q1 + b2 * q2;
                let d = f32x8::ONE / q;
                // The lanes inside and nearer than their texel.
                // Eight texels of the row at once wherever the row has
                // them (the lanes past the box are not inside).
                let mut nearer = if tx + 8 <= size {
                    let texels: [f32; 8] = row[tx..tx + 8].try_into().unwrap_or([0.0; 8]);
                    inside & d.simd_lt(f32x8::from(texels)).to_bitmask()
                } else {
                    let d = d.as_array();
                    (0..lanes)
                        .filter(|&k| inside & (1 << k) != 0 && d[k] < row[tx + k])
                        .fold(0, |m, k| m | 1 << k)
                };
                let d = d.as_array();
                while nearer != 0 {
                    let k = nearer.trailing_zeros() as usize;
                    nearer &= nearer - 1;
                    if let Some((cutout, uv, uv2)) = &mask {
                        let [b0, b1, b2, q0, q1, q2] =
                            [b0, b1, b2, q0, q1, q2].map(|v| v.as_array()[k]);
                        let w = [b0 * q0, b1 * q1, b2 * q2];
                        let at = |c: &[Vec2; 3]| (c[0] * w[0] + c[1] * w[1] + c[2] * w[2]) * d[k];
                        let first = at(uv);
                        if !cutout.opaque(first, uv2.as_ref().map_or(first, at)) {
                            continue;
                        }
                    }
                    row[tx + k] = d[k];
                    owners[tx + k] = object;
                    written += 1;
                }
            }
            tx += 8;
        }
    }
    written
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Random triangles of an 8×8 map with corners on a grid of quarter
    /// texels (so corners and edges often fall on centres: slivers, edges
    /// through centres), 1/w between 0.5 and 1, set up without refusing
    /// any, their boxes at most `most` texels (`usize::MAX`: any).
    fn quarter_grid_triangles(count: usize, most: usize) -> Vec<Setup> {
        let mut state = 7u32;
        let mut next = move || {
            state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            state >> 8
        };
        let mut tris = Vec::new();
        while tris.len() < count {
            let mut corner = || {
                let mut coord = || 2.0 + (next() % 12) as f32 * 0.25;
                (coord(), coord(), 0.5 + (next() % 64) as f32 / 128.0)
            };
            let corners = [corner(), corner(), corner()];
            let [(x0, y0, _), (x1, y1, _), (x2, y2, _)] = corners;
            let area = (x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0);
            if area.abs() <= 1e-12 {
                continue;
            }
            let (lo_x, hi_x) = (x0.min(x1).min(x2).floor(), x0.max(x1).max(x2).ceil());
            let (lo_y, hi_y) = (y0.min(y1).min(y2).floor(), y0.max(y1).max(y2).ceil());
            let t = Setup {
                corners,
                area,
                rows: (lo_y as u16, hi_y as u16),
                columns: (lo_x as u16, hi_x as u16),
                object: tris.len() as u32,
                triangle: 0,
            };
            if t.box_texels().1 <= most {
                tris.push(t);
            }
        }
        tris
    }

    /// A stand-in's cull by its corners' winding on the map keeps the faces
    /// the mesh's cull by facets keeps: those turned away from the light.
    /// Random triangles around the point the light looks at, 500 texels a
    /// side, the light at several places.
    #[test]
    fn the_winding_on_the_map_tells_the_faces_turned_away() {
        let mut state = 11u32;
        let mut next = move || {
            state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (state >> 8) as f32 / (1 << 24) as f32 * 2.0 - 1.0
        };
        let (mut away, mut toward) = (0, 0);
        for light in [
            Vec3::new(0.0, 0.0, 5.0),
            Vec3::new(3.0, 4.0, -2.0),
            Vec3::new(-1.0, 6.0, 0.5),
        ] {
            let near = light.length() - 1.5;
            let proj = Mat4::perspective_rh_gl(0.8, 1.0, near, light.length() + 1.5);
            let up = if light.cross(Vec3::Y).length_squared() > 1e-6 {
                Vec3::Y
            } else {
                Vec3::X
            };
            let (mut depth, mut owner) = (Vec::new(), Vec::new());
            let map = Target {
                size: 500,
                depth: &mut depth,
                owner: &mut owner,
                view_proj: proj * Mat4::look_at_rh(light, Vec3::ZERO, up),
                light,
                near,
            };
            for _ in 0..5_000 {
                let corners: Vec<Vec3> =
                    (0..3).map(|_| Vec3::new(next(), next(), next())).collect();
                let facet = (corners[1] - corners[0]).cross(corners[2] - corners[0]);
                let facing = facet.dot(light - corners[0]);
                // Edge-on from the light: either answer is right.
                if facing.abs() < 1e-3 * facet.length() * (light - corners[0]).length() {
                    continue;
                }
                let mut projected = Vec::new();
                project_vertices(&map, 3, |k| corners[k], &mut projected);
                let is_away = turned_away(projected[0], projected[1], projected[2]);
                assert_eq!(is_away, facing < 0.0, "{corners:?} from {light}");
                if is_away { away += 1 } else { toward += 1 }
            }
        }
        assert!(
            away > 5_000 && toward > 5_000,
            "{away} away, {toward} toward"
        );
    }

    /// A small triangle is refused at setup exactly when filling it would
    /// write no texel: each random triangle set up with the test and filled
    /// without it.
    #[test]
    fn a_refused_triangle_writes_nothing() {
        let (mut refused, mut kept) = (0, 0);
        for whole in quarter_grid_triangles(20_000, usize::MAX) {
            let (mut depth, mut owner) = (vec![f32::INFINITY; 64], vec![u32::MAX; 64]);
            let rows = usize::from(whole.rows.0)..usize::from(whole.rows.1);
            let written = fill(&mut depth, &mut owner, 8, 0, rows, &whole, None);
            match set_up(8, whole.corners, 0, 0) {
                Some(_) => kept += 1,
                None => {
                    refused += 1;
                    assert_eq!(written, 0, "{:?}", whole.corners);
                }
            }
            let small = whole.box_texels().1 <= SMALL_BOX;
            if written > 0 && small {
                assert!(covers_a_centre(&whole), "{:?}", whole.corners);
            }
        }
        assert!(
            refused > 1_000 && kept > 1_000,
            "{refused} refused, {kept} kept"
        );
    }

    /// A small box filled without a row loop writes the texels, depths and
    /// owners the row loop writes, bit for bit, into the whole map and into
    /// bands of rows that cut boxes in two: 5,000 random small triangles,
    /// twenty at a time over each other on a clear map (so nearer and
    /// farther ones meet).
    #[test]
    fn a_small_box_fills_as_the_row_loop_does() {
        let tris = quarter_grid_triangles(5_000, SMALL_BOX);
        let bits = |d: &[f32]| d.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        for (y0, y1) in [(0, 8), (0, 4), (4, 8), (3, 5)] {
            let mut written = 0;
            for group in tris.chunks(20) {
                let clear = (
                    vec![f32::INFINITY; (y1 - y0) * 8],
                    vec![u32::MAX; (y1 - y0) * 8],
                );
                let (mut by_rows, mut at_once) = (clear.clone(), clear);
                for t in group {
                    let band = usize::from(t.rows.0).max(y0)..usize::from(t.rows.1).min(y1);
                    let rows = fill(&mut by_rows.0, &mut by_rows.1, 8, y0, band, t, None);
                    let once = fill_small(&mut at_once.0, &mut at_once.1, 8, y0, t);
                    assert_eq!(rows, once, "rows {y0}..{y1}: {:?}", t.corners);
                    written += rows;
                }
                assert_eq!(bits(&by_rows.0), bits(&at_once.0), "rows {y0}..{y1}");
                assert_eq!(by_rows.1, at_once.1, "rows {y0}..{y1}");
            }
            assert!(written > 500, "rows {y0}..{y1}: {written} written");
        }
    }
}
