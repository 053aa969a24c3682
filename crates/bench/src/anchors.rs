//! `relief bench --anchors`: the scene other CPU renderers are measured on,
//! timed the way their harnesses time it, so the three can be run one after
//! the other and compared as ratios.
//!
//! The scene: the reference cube (side 2, rotation 25, 35, 0), face normals,
//! the reference brick on all six faces with bilinear filtering, the four
//! point lights, and three variants — flat (untextured), Gouraud + texture,
//! Phong + texture + Blinn bump (filtered height derivative) — at 320×240 and
//! 640×480, on one thread and on all threads. A timed frame is a whole
//! `Renderer::render` (clear included) into a kept framebuffer.

use std::io::Write;
use std::sync::Arc;
use std::time::{Duration, Instant};

use relief_core::framebuffer::{Framebuffer, Rgb};
use relief_core::settings::{Normals, Settings, Shading};
use relief_pipeline::render::Renderer;
use relief_scene::Scene;
use relief_texture::Texture;

/// The three variants, named as the other harnesses name them.
pub const VARIANTS: [&str; 3] = ["flat", "gouraud", "phong"];

/// The settings of variant `name` on the anchors' scene.
pub fn settings(name: &str) -> Settings {
    let base = Settings {
        normals: Normals::Face,
        ..Settings::default()
    };
    match name {
        "flat" => Settings {
            shading: Shading::Flat,
            texture: false,
            bump: false,
            ..base
        },
        "gouraud" => Settings {
            shading: Shading::Gouraud,
            bump: false,
            ..base
        },
        _ => base,
    }
}

/// The anchors' scene: the reference cube, textured on all six faces.
pub fn scene(texture: Arc<Texture>) -> Scene {
    Scene::cube(texture, true)
}

/// One measured row.
#[derive(Clone, Debug)]
pub struct AnchorRow {
    pub variant: &'static str,
    pub width: usize,
    pub height: usize,
    pub threads: usize,
    pub median: Duration,
    pub min: Duration,
    pub frames: usize,
    pub covered: u64,
}

impl AnchorRow {
    /// Nanoseconds per covered pixel.
    pub fn ns_per_pixel(&self) -> f64 {
        self.median.as_secs_f64() * 1e9 / self.covered.max(1) as f64
    }
}

impl AnchorRow {
    /// This row with the median, the fastest and the count of `times`
    /// (at least one frame).
    pub(crate) fn timed(self, mut times: Vec<Duration>) -> AnchorRow {
        times.sort_unstable();
        AnchorRow {
            median: times[times.len() / 2],
            min: times[0],
            frames: times.len(),
            ..self
        }
    }
}

struct Cell {
    row: AnchorRow,
    settings: Settings,
    renderer: Renderer,
    fb: Framebuffer,
    times: Vec<Duration>,
}

/// Times every variant × size × thread count in `rounds` interleaved rounds
/// of `frames` frames each (after a warm-up), and returns the rows.
pub fn measure(
    texture: Arc<Texture>,
    sizes: &[(usize, usize)],
    threads: &[usize],
    rounds: usize,
    frames: usize,
    mut progress: impl FnMut(&str),
) -> anyhow::Result<Vec<AnchorRow>> {
    let scene = scene(texture);
    let pools: Vec<(usize, rayon::ThreadPool)> = threads
        .iter()
        .map(|&n| Ok((n, rayon::ThreadPoolBuilder::new().num_threads(n).build()?)))
        .collect::<anyhow::Result<_>>()?;
    let mut cells = Vec::new();
    for &(width, height) in sizes {
        for variant in VARIANTS {
            for &(n, _) in &pools {
                let settings = settings(variant);
                let mut fb = Framebuffer::new(width, height);
                let mut renderer = Renderer::new();
                let stats = renderer.render(&scene, &settings, &mut fb);
                cells.push(Cell {
                    row: AnchorRow {
                        variant,
                        width,
                        height,
                        threads: n,
                        median: Duration::ZERO,
                        min: Duration::ZERO,
                        frames: 0,
                        covered: stats.counters.pixels_shaded,
                    },
                    settings,
                    renderer,
                    fb,
                    times: Vec::new(),
                });
            }
        }
    }
    for round in 0..rounds.max(1) {
        for cell in cells.iter_mut() {
            let pool = &pools
                .iter()
                .find(|(n, _)| *n == cell.row.threads)
                .expect("a pool per thread count")
                .1;
            pool.install(|| {
                // Warm-up: caches, the pool's threads, the kept buffers.
                for _ in 0..3 {
                    cell.renderer.render(&scene, &cell.settings, &mut cell.fb);
                }
                for _ in 0..frames.max(1) {
                    let start = Instant::now();
                    cell.renderer.render(&scene, &cell.settings, &mut cell.fb);
                    cell.times.push(start.elapsed());
                }
            });
        }
        progress(&format!(
            "anchors: round {}/{} done",
            round + 1,
            rounds.max(1)
        ));
    }
    Ok(cells.into_iter().map(|c| c.row.timed(c.times)).collect())
}

/// The rows as `key=value` lines, the format of the other harnesses.
pub fn key_values(rows: &[AnchorRow]) -> String {
    let mut s = String::new();
    for r in rows {
        s += &format!(
            "variant={:<7} size={}x{} threads={} frames={} median_ms={:.4} min_ms={:.4} covered_px={} ns_per_px={:.1}\n",
            r.variant,
            r.width,
            r.height,
            r.threads,
            r.frames,
            r.median.as_secs_f64() * 1e3,
            r.min.as_secs_f64() * 1e3,
            r.covered,
            r.ns_per_pixel()
        );
    }
    s
}

/// The rows as a Markdown table.
pub fn markdown(rows: &[AnchorRow]) -> String {
    let mut s = String::from(
        "| variant | size | threads | median ms | min ms | covered px | ns / px |\n|:--|:--|--:|--:|--:|--:|--:|\n",
    );
    for r in rows {
        s += &format!(
            "| {} | {}×{} | {} | {:.3} | {:.3} | {} | {:.1} |\n",
            r.variant,
            r.width,
            r.height,
            r.threads,
            r.median.as_secs_f64() * 1e3,
            r.min.as_secs_f64() * 1e3,
            r.covered,
            r.ns_per_pixel()
        );
    }
    s
}

/// How far one picture is from another over the pixels the cube covers.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Agreement {
    pub psnr: f64,
    pub rms: f64,
    /// Largest channel difference.
    pub max: u8,
}

/// `a` against `b` over the pixels where `covered` is true.
pub fn agreement(a: &[Rgb], b: &[Rgb], covered: &[bool]) -> Agreement {
    let (mut sum, mut count, mut max) = (0.0, 0u64, 0u8);
    for ((x, y), &c) in a.iter().zip(b).zip(covered) {
        if c {
            for k in 0..3 {
                let d = x[k].abs_diff(y[k]);
                max = max.max(d);
                sum += (d as f64).powi(2);
                count += 1;
            }
        }
    }
    let mse = if count == 0 { 0.0 } else { sum / count as f64 };
    Agreement {
        psnr: if mse == 0.0 {
            f64::INFINITY
        } else {
            10.0 * (255.0f64 * 255.0 / mse).log10()
        },
        rms: mse.sqrt(),
        max,
    }
}

/// relief, Mesa llvmpipe and the ray-cast truth on one variant at 320×240.
#[derive(Clone, Debug)]
pub struct ThreeWay {
    pub variant: &'static str,
    /// Pixels covered by both renderers.
    pub covered: usize,
    /// Against the truth's area mean (its rays over the whole pixel).
    pub relief_truth: Agreement,
    pub llvmpipe_truth: Agreement,
    pub relief_llvmpipe: Agreement,
    /// Against the truth's ray through the pixel centre, where both
    /// renderers sample (no anti-aliasing on either side).
    pub relief_centre: Agreement,
    pub llvmpipe_centre: Agreement,
}

/// Size of the llvmpipe pictures in tests/data/anchors.
pub const ANCHOR_SIZE: (usize, usize) = (320, 240);

/// Where the repository keeps llvmpipe's pictures (known at build time; an
/// installed binary may not find them).
const ANCHOR_PICTURES: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../tests/data/anchors");

/// llvmpipe's picture of `variant`, rows top first, if it is there.
pub fn llvmpipe_picture(variant: &str) -> Option<Vec<Rgb>> {
    let (w, h) = ANCHOR_SIZE;
    let path = format!("{ANCHOR_PICTURES}/anchor_llvmpipe_{variant}_{w}x{h}.png");
    let img = relief_texture::picture::open(path).ok()?.to_rgb8();
    ((img.width() as usize, img.height() as usize) == (w, h))
        .then(|| img.pixels().map(|p| p.0).collect())
}

/// The three-way comparison of every variant whose llvmpipe picture is
/// found, the truth cast with `rays × rays` rays per pixel. The truth's
/// setting is the variant's (`truth::Setting::of`): Phong with face normals,
/// no texture for `flat`, texture for `gouraud`, texture and Blinn's bump
/// for `phong`; flat and Gouraud approximate that per-pixel picture.
pub fn three_way(texture: Arc<Texture>, rays: usize) -> Vec<ThreeWay> {
    let scene = scene(texture);
    let (w, h) = ANCHOR_SIZE;
    let background = scene.background;
    VARIANTS
        .iter()
        .filter_map(|&variant| {
            let theirs = llvmpipe_picture(variant)?;
            let settings = settings(variant);
            let mut fb = Framebuffer::new(w, h);
            Renderer::new().render(&scene, &settings, &mut fb);
            let ours = fb.pixels();
            let view = super::truth::View::of(&settings, &scene);
            let area = super::truth::render(&scene, &view, w, h, rays);
            let centre: Vec<Rgb> = super::truth::render_centres(&scene, &view, w, h)
                .into_iter()
                .map(|c| {
                    c.map_or(background, |c| {
                        let q = |x: f64| (x.clamp(0.0, 1.0) * 255.0).round() as u8;
                        [q(c.x), q(c.y), q(c.z)]
                    })
                })
                .collect();
            let covered: Vec<bool> = ours
                .iter()
                .zip(&theirs)
                .map(|(a, b)| *a != background && *b != background)
                .collect();
            Some(ThreeWay {
                variant,
                covered: covered.iter().filter(|&&c| c).count(),
                relief_truth: agreement(ours, area.pixels(), &covered),
                llvmpipe_truth: agreement(&theirs, area.pixels(), &covered),
                relief_llvmpipe: agreement(ours, &theirs, &covered),
                relief_centre: agreement(ours, &centre, &covered),
                llvmpipe_centre: agreement(&theirs, &centre, &covered),
            })
        })
        .collect()
}

/// The three-way comparison as a Markdown table: PSNR in dB (RMS, largest
/// difference) over the covered pixels.
pub fn three_way_markdown(rows: &[ThreeWay]) -> String {
    let cell = |a: &Agreement| format!("{:.2} ({:.2}, {})", a.psnr, a.rms, a.max);
    let mut s = String::from(
        "| variant | covered px | relief vs truth | llvmpipe vs truth | relief vs llvmpipe | relief vs truth at centres | llvmpipe vs truth at centres |\n|:--|--:|--:|--:|--:|--:|--:|\n",
    );
    for r in rows {
        s += &format!(
            "| {} | {} | {} | {} | {} | {} | {} |\n",
            r.variant,
            r.covered,
            cell(&r.relief_truth),
            cell(&r.llvmpipe_truth),
            cell(&r.relief_llvmpipe),
            cell(&r.relief_centre),
            cell(&r.llvmpipe_centre)
        );
    }
    s
}

/// Runs the anchors' bench: `quick` is a smoke run (one small size, few frames).
pub fn run(
    quick: bool,
    markdown_out: bool,
    threads: usize,
    out: &mut dyn Write,
    log: &mut dyn Write,
) -> anyhow::Result<Vec<AnchorRow>> {
    let (texture, texture_line) = super::reference::texture();
    let sizes: &[(usize, usize)] = if quick {
        &[(64, 48)]
    } else {
        &[(320, 240), (640, 480)]
    };
    let mut counts = vec![1];
    if threads > 1 {
        counts.push(threads);
    }
    let (rounds, frames) = if quick { (1, 2) } else { (5, 60) };
    writeln!(
        out,
        "relief bench --anchors: cube 25,35,0, face normals, {} on all faces (top row at v = 0), bilinear, 4 point lights; {rounds} interleaved rounds of {frames} frames, median and min per frame (whole render, clear included)",
        relief_core::sanitize::clean(&texture_line)
    )?;
    let rows = measure(texture, sizes, &counts, rounds, frames, |line| {
        let _ = writeln!(log, "{line}");
    })?;
    if markdown_out {
        write!(out, "{}", markdown(&rows))?;
    } else {
        write!(out, "{}", key_values(&rows))?;
    }
    if !quick {
        let (texture, _) = super::reference::texture();
        let rays = 16;
        writeln!(
            log,
            "anchors: ray-casting the truth of each variant ({rays}x{rays} rays)…"
        )?;
        let three = three_way(texture, rays);
        if three.is_empty() {
            writeln!(
                log,
                "anchors: llvmpipe's pictures not found (tests/data/anchors); no three-way comparison"
            )?;
        } else {
            writeln!(
                out,
                "\nrelief, Mesa llvmpipe and the ray-cast truth ({rays}x{rays} rays; and its ray through each pixel centre), 320x240, over the pixels both renderers cover: PSNR dB (RMS, largest channel difference)"
            )?;
            write!(out, "{}", three_way_markdown(&three))?;
        }
    }
    Ok(rows)
}

#[cfg(test)]
mod tests {
    use super::*;
    use relief_texture::decode::procedural;

    #[test]
    fn every_variant_covers_the_same_pixels_and_reports_them() {
        let tex = Arc::new(procedural::brick());
        let rows = measure(tex, &[(64, 48)], &[1, 2], 1, 1, |_| {}).unwrap();
        assert_eq!(rows.len(), 6);
        let covered = rows[0].covered;
        assert!(covered > 0);
        assert!(rows.iter().all(|r| r.covered == covered && r.frames == 1));
        let text = key_values(&rows);
        assert_eq!(text.lines().count(), 6);
        assert!(markdown(&rows).contains("| gouraud | 64×48 | 2 |"));
    }

    /// Two pixels covered of three: differences 0, 3, 4 in one channel of
    /// the second and 0 elsewhere; MSE = 25/6 per channel value.
    #[test]
    fn agreement_counts_covered_pixels_only() {
        let a = [[10, 10, 10], [13, 14, 10], [200, 0, 0]];
        let b = [[10, 10, 10], [10, 10, 10], [0, 0, 0]];
        let got = agreement(&a, &b, &[true, true, false]);
        assert_eq!(got.max, 4);
        assert!((got.rms - (25.0f64 / 6.0).sqrt()).abs() < 1e-12);
        assert!((got.psnr - 10.0 * (255.0f64 * 255.0 * 6.0 / 25.0).log10()).abs() < 1e-9);
        assert!(agreement(&a, &a, &[true; 3]).psnr.is_infinite());
    }
}
