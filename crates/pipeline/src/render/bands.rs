//! Splitting a frame into bands of rows of equal estimated work, drawn in
//! parallel when the frame is big enough to gain.

use rayon::prelude::*;

use super::abandon::{Abandon, CHECK_EVERY};
use super::dispatch::{draw_into, shade_pending};
use crate::raster::ScreenTri;
use crate::raster::aa::RasterTarget;
use crate::raster::backdrop::Backdrop;
use crate::raster::setup::ONE;
use crate::shade::packet::LANES;
use crate::shade::{ShadeCtx, TriShader};
use relief_core::stats::Counters;

/// Bands of equal estimated work per thread: one would leave a thread idle
/// whenever the estimate is off; a few let the first to finish take another.
pub(super) const CHUNKS_PER_THREAD: usize = 8;

/// Below this much estimated work (covered pixels weighted by kernel cost,
/// plus the clear) one thread is faster than splitting the frame.
pub(super) const PARALLEL_MIN_WORK: f64 = 16_384.0;

/// Work units of a row that one triangle spans, besides its pixels: finding
/// the covered span.
pub(super) const ROW_SETUP_WORK: f64 = 4.0;

/// The estimated work of each row: a triangle's covered area spread evenly
/// over its rows (a flat colour counts a quarter: its rows are fills), a
/// setup cost per row it spans, and the clear.
pub(super) struct RowWork {
    /// `before[y]`: the work of rows 0..y (`height + 1` entries).
    before: Vec<f64>,
}

impl RowWork {
    pub(super) fn new(
        tris: &[ScreenTri],
        shaders: &[TriShader],
        width: usize,
        height: usize,
    ) -> Self {
        // Per-row increments, summed once at the end.
        let mut delta = vec![0.0f64; height + 1];
        let px_per_unit = 1.0 / (2 * ONE * ONE) as f64;
        for t in tris {
            let weight = match shaders[t.shader as usize] {
                TriShader::Solid(_) => 0.25,
                _ => 1.0,
            };
            let rows = (t.y1 - t.y0 + 1) as f64;
            let per_row = t.area as f64 * px_per_unit * weight / rows + ROW_SETUP_WORK;
            delta[t.y0 as usize] += per_row;
            delta[t.y1 as usize + 1] -= per_row;
        }
        let clear = width as f64 / 16.0;
        let mut before = Vec::with_capacity(height + 1);
        let (mut sum, mut rate) = (0.0, 0.0);
        before.push(0.0);
        for d in &delta[..height] {
            rate += d;
            sum += rate.max(0.0) + clear;
            before.push(sum);
        }
        RowWork { before }
    }

    pub(super) fn total(&self) -> f64 {
        *self.before.last().unwrap_or(&0.0)
    }

    /// Row bounds of at most `parts` bands of about equal work, from 0 to
    /// the height.
    pub(super) fn split(&self, parts: usize) -> Vec<usize> {
        let height = self.before.len() - 1;
        let total = self.total();
        let mut bounds = vec![0];
        let mut y = 0;
        for k in 1..parts {
            let goal = total * k as f64 / parts as f64;
            while y < height && self.before[y] < goal {
                y += 1;
            }
            if y > *bounds.last().unwrap_or(&0) && y < height {
                bounds.push(y);
            }
        }
        bounds.push(height);
        bounds
    }
}

/// Overdraw at which drawing every triangle's depth before shading any
/// pays (see [`depth_first_pays`]).
pub(super) const DEPTH_FIRST_OVERDRAW: f64 = 2.0;

/// Whether a depth pre-pass pays for these triangles: when their areas sum
/// to at least [`DEPTH_FIRST_OVERDRAW`] times the box that holds them all,
/// at least half the pixels a single pass shades would be shaded again
/// (a lone surface sums to at most its box; a mesh stacked over itself to
/// a multiple of it). The pre-pass costs a depth test per covered pixel
/// and layer, far less than a shading.
pub(super) fn depth_first_pays(tris: &[ScreenTri]) -> bool {
    let Some(first) = tris.first() else {
        return false;
    };
    let (mut x0, mut x1, mut y0, mut y1) = (first.x0, first.x1, first.y0, first.y1);
    let mut area = 0.0f64;
    for t in tris {
        (x0, x1) = (x0.min(t.x0), x1.max(t.x1));
        (y0, y1) = (y0.min(t.y0), y1.max(t.y1));
        area += t.area as f64;
    }
    let pixels = area / (2 * ONE * ONE) as f64;
    let box_pixels = (x1 - x0 + 1) as f64 * (y1 - y0 + 1) as f64;
    pixels >= DEPTH_FIRST_OVERDRAW * box_pixels
}

/// Cuts a frame-sized buffer into the bands between consecutive row
/// `bounds`, each with its first row.
pub(super) fn split_rows<'a, T>(
    mut buf: &'a mut [T],
    width: usize,
    bounds: &'a [usize],
) -> impl Iterator<Item = (usize, &'a mut [T])> + 'a {
    bounds.windows(2).map(move |b| {
        let (band, rest) = std::mem::take(&mut buf).split_at_mut((b[1] - b[0]) * width);
        buf = rest;
        (b[0], band)
    })
}

/// The shading context of each triangle: one for the whole frame, or one
/// per material with the material of each shader.
pub(super) enum MaterialCtxs<'a> {
    One(ShadeCtx<'a>),
    Many {
        ctxs: Vec<ShadeCtx<'a>>,
        of_shader: &'a [u32],
    },
}

impl<'a> MaterialCtxs<'a> {
    /// The context of shader `s`'s material.
    #[inline]
    pub(super) fn of(&self, s: usize) -> &ShadeCtx<'a> {
        match self {
            MaterialCtxs::One(ctx) => ctx,
            MaterialCtxs::Many { ctxs, of_shader } => &ctxs[of_shader[s] as usize],
        }
    }
}

/// Shades the band's deferred pixels a packet at a time while at least
/// `least` of them wait (`raster::pending`).
fn shade_pending_packets<T: RasterTarget>(
    band: &mut T,
    shaders: &[TriShader],
    ctxs: &MaterialCtxs,
    least: usize,
    counters: &mut Counters,
) {
    let Some(mut q) = band.pending() else {
        return;
    };
    while q.pending.len() >= least.max(1) {
        let ctx = ctxs.of(q.pending.packet()[0].shader as usize);
        shade_pending(&mut q, shaders, ctx, counters);
    }
}

/// Clears each band and draws every triangle into it, in parallel or not
/// (the same result either way: bands never share a pixel). Band `i` holds
/// rows `bounds[i]..bounds[i + 1]`; a triangle whose rows miss a band is
/// passed over before its shader is looked at. Stops when `abandon` says
/// so (a band then stays as it was); returns the counters and how many
/// bands were drawn whole.
#[allow(clippy::too_many_arguments)]
pub(super) fn draw_bands<T: RasterTarget + Send>(
    bands: &mut [T],
    bounds: &[usize],
    parallel: bool,
    tris: &[ScreenTri],
    shaders: &[TriShader],
    ctxs: &MaterialCtxs,
    backdrop: &Backdrop,
    abandon: &Abandon,
) -> (Counters, usize) {
    // Each band goes through every triangle, twice when it draws depth first.
    let passes = 1 + bands.first().map_or(0, |b| u64::from(b.depth_first()));
    abandon.drawing(bands.len() as u64 * tris.len() as u64 * passes);
    let draw = |(i, band): (usize, &mut T)| -> (Counters, bool) {
        let mut counters = Counters::default();
        if abandon.now() {
            return (counters, false);
        }
        band.clear(backdrop);
        let (y0, y1) = (bounds[i] as i32, bounds[i + 1] as i32);
        let misses = |tri: &ScreenTri| tri.y1 < y0 || tri.y0 >= y1;
        // Asked every `CHECK_EVERY` triangles: stop, and count them done.
        let check = |n: usize| {
            n % CHECK_EVERY == CHECK_EVERY - 1 && {
                abandon.advance(CHECK_EVERY);
                abandon.now()
            }
        };
        let rest = tris.len() % CHECK_EVERY;
        if band.depth_first() {
            for (n, tri) in tris.iter().enumerate() {
                if check(n) {
                    return (counters, false);
                }
                if !misses(tri) {
                    band.prepass(tri, &mut counters);
                }
            }
            abandon.advance(rest);
        }
        for (n, tri) in tris.iter().enumerate() {
            if check(n) {
                return (counters, false);
            }
            if misses(tri) {
                continue;
            }
            let s = tri.shader as usize;
            draw_into(tri, &shaders[s], ctxs.of(s), band, &mut counters);
            shade_pending_packets(band, shaders, ctxs, LANES, &mut counters);
        }
        shade_pending_packets(band, shaders, ctxs, 1, &mut counters);
        abandon.advance(rest);
        (counters, true)
    };
    let per_band: Vec<(Counters, bool)> = if parallel {
        // One band per task, so an idle thread can take any band left.
        bands
            .par_iter_mut()
            .enumerate()
            .with_max_len(1)
            .map(draw)
            .collect()
    } else {
        bands.iter_mut().enumerate().map(draw).collect()
    };
    let mut total = Counters::default();
    let mut drawn = 0;
    for (c, whole) in per_band {
        total += c;
        drawn += usize::from(whole);
    }
    (total, drawn)
}
