//! The steps of drawing a frame's screen triangles: the points and lines
//! displays, or the filled display cut into bands of rows, with
//! multisampling, a depth pre-pass, or neither.

use super::abandon::Abandon;
use super::bands::{
    CHUNKS_PER_THREAD, MaterialCtxs, PARALLEL_MIN_WORK, RowWork, draw_bands, split_rows,
};
use crate::plan::Plan;
use crate::raster::aa::{MSAA_SAMPLES, MsaaBand, RasterTarget, resolve_msaa};
use crate::raster::backdrop::Backdrop;
use crate::raster::pending::Pending;
use crate::raster::scan::OwnedBand;
use crate::raster::wire::{Canvas, WireTri, draw_lines, draw_points, point_size};
use crate::raster::{Band, ScreenTri};
use crate::shade::{ShadeCtx, TriShader};
use crate::shadow::Shadow;
use relief_core::framebuffer::{Framebuffer, Rgb};
use relief_core::settings::Display;
use relief_core::stats::Counters;
use relief_scene::Scene;
use relief_texture::Texture;

/// Clears `fb` and draws the points or lines display's triangles, `brush`
/// pixels wide (the supersampling factor, so they keep their size).
pub(super) fn draw_wire(
    wire: &[WireTri],
    plan: &Plan,
    background: Rgb,
    fb: &mut Framebuffer,
    brush: usize,
) -> Counters {
    let (width, height) = (fb.width(), fb.height());
    let mut counters = Counters::default();
    fb.fill(background);
    let mut canvas = Canvas::new(width, height, fb.pixels_mut());
    if plan.display == Display::Points {
        let size = point_size(width / brush, height / brush) * brush;
        draw_points(wire, size, &mut canvas, &mut counters);
    } else {
        draw_lines(wire, brush, &mut canvas, &mut counters);
    }
    counters
}

/// The shading context of the frame: one when every object shares the
/// scene's material, else one per material group with each shader's group.
pub(super) fn material_ctxs<'a>(
    scene: &'a Scene,
    (plans, textures): (&'a [Plan], &'a [&'a Texture]),
    shadow: Option<Shadow<'a>>,
    of_shader: &'a [u32],
) -> MaterialCtxs<'a> {
    if plans.len() == 1 {
        return MaterialCtxs::One(ShadeCtx {
            plan: &plans[0],
            texture: &scene.material.texture,
            shadow,
            packets: true,
        });
    }
    MaterialCtxs::Many {
        ctxs: plans
            .iter()
            .zip(textures)
            .map(|(plan, texture)| ShadeCtx {
                plan,
                texture,
                shadow,
                packets: true,
            })
            .collect(),
        of_shader,
    }
}

/// Whether the frame is drawn in parallel (enough estimated work and more
/// than one thread), and the rows its bands start at (then the height):
/// bands of even work when parallel, one band otherwise.
pub(super) fn band_bounds(
    tris: &[ScreenTri],
    shaders: &[TriShader],
    width: usize,
    height: usize,
) -> (bool, Vec<usize>) {
    let work = RowWork::new(tris, shaders, width, height);
    let threads = rayon::current_num_threads();
    let parallel = work.total() >= PARALLEL_MIN_WORK && threads > 1;
    let bounds = if parallel {
        work.split(threads * CHUNKS_PER_THREAD)
    } else {
        vec![0, height]
    };
    (parallel, bounds)
}

/// What every band of a filled frame is drawn from.
pub(super) struct Drawing<'a> {
    pub width: usize,
    pub bounds: &'a [usize],
    pub parallel: bool,
    pub tris: &'a [ScreenTri],
    pub shaders: &'a [TriShader],
    pub ctx: &'a MaterialCtxs<'a>,
    pub backdrop: &'a Backdrop,
    pub abandon: &'a Abandon<'a>,
    /// Small triangles' last pixels shaded together (`raster::pending`).
    pub shared_packets: bool,
}

impl Drawing<'_> {
    /// A band's queue of small triangles' last pixels.
    fn pending(&self) -> Pending {
        if self.shared_packets {
            Pending::on()
        } else {
            Pending::off()
        }
    }
}

impl Drawing<'_> {
    /// Draws the triangles into `bands`: the counters, and the bands drawn
    /// whole and in all.
    fn draw<T: RasterTarget + Send>(&self, bands: &mut [T]) -> (Counters, (usize, usize)) {
        let count = bands.len();
        let (total, drawn) = draw_bands(
            bands,
            self.bounds,
            self.parallel,
            self.tris,
            self.shaders,
            self.ctx,
            self.backdrop,
            self.abandon,
        );
        (total, (drawn, count))
    }
}

/// Multisampled bands (with their depths when `depth` is given), kept in
/// `color` between frames and resolved into `fb`.
pub(super) fn draw_msaa(
    drawing: &Drawing,
    color: &mut Vec<[Rgb; MSAA_SAMPLES]>,
    depth: Option<&mut Vec<[f32; MSAA_SAMPLES]>>,
    fb: &mut Framebuffer,
) -> (Counters, (usize, usize)) {
    let (width, height) = (drawing.width, fb.height());
    color.clear();
    color.resize(width * height, [drawing.backdrop.plain(); MSAA_SAMPLES]);
    let mut bands: Vec<MsaaBand> = match depth {
        Some(depth) => {
            depth.clear();
            depth.resize(width * height, [f32::INFINITY; MSAA_SAMPLES]);
            split_rows(color, width, drawing.bounds)
                .zip(split_rows(depth, width, drawing.bounds))
                .map(|((y0, samples), (_, depth))| MsaaBand {
                    y0,
                    width,
                    samples,
                    depth: Some(depth),
                })
                .collect()
        }
        None => split_rows(color, width, drawing.bounds)
            .map(|(y0, samples)| MsaaBand {
                y0,
                width,
                samples,
                depth: None,
            })
            .collect(),
    };
    let drawn = drawing.draw(&mut bands);
    drop(bands);
    resolve_msaa(color, fb.pixels_mut());
    drawn
}

/// Bands of `fb` drawn depth first: a pre-pass finds each pixel's nearest
/// triangle (its `owner`), so only that one is shaded.
pub(super) fn draw_depth_first(
    drawing: &Drawing,
    depth: &mut Vec<f32>,
    owner: &mut Vec<u32>,
    fb: &mut Framebuffer,
) -> (Counters, (usize, usize)) {
    let (width, height) = (drawing.width, fb.height());
    depth.clear();
    depth.resize(width * height, f32::INFINITY);
    owner.resize(width * height, u32::MAX);
    let mut bands: Vec<OwnedBand> = split_rows(fb.pixels_mut(), width, drawing.bounds)
        .zip(split_rows(depth, width, drawing.bounds))
        .zip(split_rows(owner, width, drawing.bounds))
        .map(|(((y0, color), (_, depth)), (_, owner))| OwnedBand {
            band: Band {
                y0,
                width,
                color,
                depth: Some(depth),
                pending: drawing.pending(),
            },
            owner,
        })
        .collect();
    drawing.draw(&mut bands)
}

/// Bands of `fb` drawn in one pass, depth tested when `depth` is given.
pub(super) fn draw_single_pass(
    drawing: &Drawing,
    depth: Option<&mut Vec<f32>>,
    fb: &mut Framebuffer,
) -> (Counters, (usize, usize)) {
    let (width, height) = (drawing.width, fb.height());
    let mut bands: Vec<Band> = match depth {
        Some(depth) => {
            depth.clear();
            depth.resize(width * height, f32::INFINITY);
            split_rows(fb.pixels_mut(), width, drawing.bounds)
                .zip(split_rows(depth, width, drawing.bounds))
                .map(|((y0, color), (_, depth))| Band {
                    y0,
                    width,
                    color,
                    depth: Some(depth),
                    pending: drawing.pending(),
                })
                .collect()
        }
        None => split_rows(fb.pixels_mut(), width, drawing.bounds)
            .map(|(y0, color)| Band {
                y0,
                width,
                color,
                depth: None,
                pending: drawing.pending(),
            })
            .collect(),
    };
    drawing.draw(&mut bands)
}
