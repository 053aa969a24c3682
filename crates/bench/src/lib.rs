//! `relief bench`: what accuracy costs in time.
//!
//! For each configuration (see `config`): the median and spread of the frame
//! time over fixed orientations, shaded pixels per second, and the error
//! against a supersampled reference image of the same views (PSNR, largest
//! channel error, SSIM). Output as an aligned table or Markdown, optionally
//! CSV and a PNG plot of error against time with the Pareto front.

pub mod anchors;
pub mod config;
pub mod figures;
pub mod font;
pub mod mesh_anchor;
pub mod metrics;
pub mod pareto;
pub mod pbr_anchor;
pub mod physical;
pub mod plot;
pub mod reference;
pub mod report;
pub mod resolve;
pub mod runner;
pub mod skinned;
pub mod terminal;
pub mod truth;

use std::io::Write;
use std::path::PathBuf;

use clap::Args;

pub use report::Report;
pub use runner::{Plan, Row};

use relief_core::sanitize::display_path;
use relief_scene::Scene;

/// Flags of `relief bench`.
#[derive(Args, Debug, Clone, Default)]
pub struct BenchArgs {
    /// Frame size [default: 320x240, or 128x96 with --quick].
    #[arg(long, value_name = "WxH", value_parser = parse_size)]
    pub size: Option<(usize, usize)>,
    /// Smoke run: five rows, two orientations, a few frames each.
    #[arg(long)]
    pub quick: bool,
    /// Also write every row, unrounded and with its full settings, as CSV.
    #[arg(long, value_name = "FILE")]
    pub csv: Option<PathBuf>,
    /// Print the table as Markdown (for the README) instead of aligned text.
    #[arg(long)]
    pub markdown: bool,
    /// Also draw PSNR against frame time, Pareto front marked, as a PNG.
    #[arg(long, value_name = "FILE.png")]
    pub plot: Option<PathBuf>,
    /// Threads of the "all threads" rows [default: one per core].
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u16).range(1..=1024))]
    pub threads: Option<u16>,
    /// Time the scene other CPU renderers are measured on (face normals,
    /// flat / Gouraud / Phong, 320x240 and 640x480, 1 thread and all).
    #[arg(long)]
    pub anchors: bool,
    /// With --anchors: time this model file instead, in the view
    /// docs/tools/llvmpipe_mesh.py draws with llvmpipe (Phong, vertex normals
    /// and colours, no texture; 320x192 and 640x480, or --size).
    #[arg(long, value_name = "FILE", requires = "anchors")]
    pub model: Option<PathBuf>,
    /// With --model: also write the view at 320x240 (no shadows) as a PNG, to
    /// compare with llvmpipe's (docs/tools/llvmpipe_mesh.py compare).
    #[arg(long, value_name = "FILE.png", requires = "model")]
    pub picture: Option<PathBuf>,
    /// With --model: shade it with a glTF metallic-roughness material (metal:
    /// gold, the default; dielectric: blue paint), one white point light and
    /// the image-based light of --environment-map, as
    /// docs/tools/llvmpipe_mesh.py bench --pbr draws it.
    #[arg(
        long,
        value_enum,
        value_name = "MATERIAL",
        num_args = 0..=1,
        default_missing_value = "metal",
        requires = "model"
    )]
    pub pbr: Option<pbr_anchor::Look>,
    /// With --pbr: the equirectangular picture of the environment's light
    /// (.hdr, .exr, PNG…) [default: the built-in studio].
    #[arg(long, value_name = "PATH", requires = "pbr")]
    pub environment_map: Option<PathBuf>,
    /// Compare the output modes instead (half, quad, sextant, octant, kitty,
    /// sixels, iterm): bytes of a first frame and of a 2° turn, encode time,
    /// and PSNR / SSIM of what the terminal shows against the full-resolution
    /// frame, on 100x30 cells of 8x16 pixels.
    #[arg(long, conflicts_with = "anchors")]
    pub modes: bool,
    /// The physically based rows instead: a metallic-roughness sphere in
    /// the model view (the studio environment, the neutral lights), each
    /// approximation against a truth that integrates the environment by
    /// Monte Carlo [default size 160x120].
    #[arg(long, conflicts_with_all = ["anchors", "modes"])]
    pub physical: bool,
}

/// Largest side `--size` accepts.
pub const MAX_SIDE: usize = 4096;
/// The reference's supersampled frame stays under this many pixels.
const MAX_REFERENCE_PIXELS: usize = 40_000_000;

/// `WxH` (also `W×H`), each side 1..=4096.
pub fn parse_size(text: &str) -> Result<(usize, usize), String> {
    let (w, h) = text.split_once(['x', 'X', '×']).ok_or_else(|| {
        format!(
            "expected WxH, such as 320x240, got '{}'",
            relief_core::sanitize::clean(text)
        )
    })?;
    let side = |s: &str| -> Result<usize, String> {
        let v: usize = s.trim().parse().map_err(|_| {
            format!(
                "'{}' is not a whole number",
                relief_core::sanitize::clean(s)
            )
        })?;
        if (1..=MAX_SIDE).contains(&v) {
            Ok(v)
        } else {
            Err(format!("each side must be 1 to {MAX_SIDE}, got {v}"))
        }
    };
    Ok((side(w)?, side(h)?))
}

/// The largest of 8, 4, 2, 1 whose supersampled frame fits the pixel budget.
fn reference_factor(width: usize, height: usize, wanted: usize) -> usize {
    let mut f = wanted.max(1);
    while f > 1 && width * height * f * f > MAX_REFERENCE_PIXELS {
        f /= 2;
    }
    f
}

/// The plan `args` ask for.
pub fn plan(args: &BenchArgs) -> Plan {
    let threads = args.threads.map(usize::from).unwrap_or_else(|| {
        std::thread::available_parallelism()
            .map(|n| n.get())
            .unwrap_or(1)
    });
    let default = match (args.physical, args.quick) {
        (true, true) => (48, 36),
        (true, false) => (160, 120),
        (false, true) => (128, 96),
        (false, false) => (320, 240),
    };
    let (w, h) = args.size.unwrap_or(default);
    let mut plan = if args.quick {
        Plan::quick(w, h, threads)
    } else {
        Plan::full(w, h, threads)
    };
    if args.physical {
        plan = physical::plan(plan, args.quick);
    }
    plan.reference_factor = reference_factor(w, h, plan.reference_factor);
    plan
}

/// What the table's figures mean, for the lines above it: the cube's
/// table, or with `physical` the physical rows'.
fn header(plan: &Plan, texture: &str, physical: bool) -> Vec<String> {
    let cores = std::thread::available_parallelism()
        .map(|n| n.get())
        .unwrap_or(1);
    let what = if physical {
        "a metallic-roughness sphere in the model view (the studio environment, the neutral lights; metal in the north, paint in the south, roughness 0.05–0.95 around)"
    } else {
        "reference cube (texture on all faces)"
    };
    let rays = plan.truth_rays.max(2);
    let truth = if physical {
        let q = truth::physical::SAMPLES_PER_AXIS;
        format!(
            "truth: the glTF BRDF (GGX, Smith height-correlated, Schlick) ray-cast in f64 apart from the renderer (crates/bench/src/truth/physical.rs): the lights exact, the environment integrated by Monte Carlo; {rays}x{rays} stratified rays per pixel, each with {q}x{q} cosine-distributed and {q}x{q} GGX-distributed directions, stratified over the pixel ({d} per lobe); truth dB = that truth with {h}x{h} rays against itself",
            d = (rays * q) * (rays * q),
            h = rays / 2
        )
    } else {
        format!(
            "truth: each row's ideal picture (its technique's own definition) ray-cast in f64 apart from the renderer (crates/bench/src/truth), {rays}x{rays} stratified rays per pixel, texture read from its finest level; truth dB = that truth with {h}x{h} rays against itself (its own error is smaller still)",
            h = rays / 2
        )
    };
    let mut lines = vec![
        format!(
            "relief bench: {}x{}, {what}, {} orientations (seed {:#X}), all threads = {} ({} cores)",
            plan.width,
            plan.height,
            plan.orientations.len(),
            config::SEED,
            plan.threads,
            cores
        ),
        format!("texture: {}", relief_core::sanitize::clean(texture)),
        format!(
            "reference image: {}, {f}x{f} supersampled and box-resolved",
            if physical {
                "metallic-roughness with the default settings and the anisotropic filter"
            } else {
                "Phong, anisotropic filter, filtered height derivative, Blinn bump"
            },
            f = plan.reference_factor
        ),
        format!(
            "time: median and p10–p90 of {} ms or at least {} timed frames per row ({} interleaved rounds) after a warm-up frame per orientation; Mpx/s = shaded pixels (or samples) per second",
            plan.budget.as_millis(),
            plan.min_frames,
            plan.rounds
        ),
        truth,
        "error against the row's truth, whole frames: PSNR (inf = identical), largest channel error (0–255), mean SSIM of luma; self PSNR/max = against the supersampled reference image; front = on the Pareto front of time and PSNR".into(),
        format!(
            "terminal bytes: mean bytes the view's encoder writes for the picture after a {}° turn about Y (half blocks, colour tolerance {}), 24-bit and 256 colours",
            terminal::STEP_DEGREES,
            terminal::TOLERANCE
        ),
    ];
    if cfg!(debug_assertions) {
        lines.push(
            "warning: debug build, times are not representative (build with --release)".into(),
        );
    }
    lines
}

/// `relief bench --modes`: the output-mode table for the default view
/// settings over the plan's orientations.
fn output_modes(
    args: &BenchArgs,
    plan: &Plan,
    scene: &Scene,
    out: &mut dyn Write,
    log: &mut dyn Write,
) -> anyhow::Result<Report> {
    writeln!(
        log,
        "relief bench --modes: {} orientations…",
        plan.orientations.len()
    )?;
    let mut renderer = relief_pipeline::render::Renderer::new();
    let settings = relief_core::settings::Settings::default();
    let rows = terminal::measure_modes(
        &plan.orientations,
        scene.background,
        |rotation, aspect, fb| {
            renderer.set_pixel_aspect(aspect);
            renderer.render(
                scene,
                &relief_core::settings::Settings {
                    rotation,
                    ..settings
                },
                fb,
            );
        },
    )?;
    let (c, r) = terminal::MODE_CELLS;
    let (cw, ch) = terminal::MODE_CELL_PIXELS;
    writeln!(
        out,
        "relief bench --modes: reference cube, default view settings, {} orientations; a {c}x{r}-cell picture, cells of {cw}x{ch} pixels",
        plan.orientations.len()
    )?;
    writeln!(
        out,
        "bytes: first frame on a blank screen, then the frame after a {}° turn about Y (text: ratatui's diff, 24-bit, colour tolerance {}; pixels: the whole image again); encode ms: that frame, median",
        terminal::STEP_DEGREES,
        terminal::TOLERANCE
    )?;
    writeln!(
        out,
        "error: what the terminal shows (each cell's glyph in its two colours; sixel's palette) against the frame rendered at {}x{} pixels: PSNR and mean SSIM of luma",
        usize::from(c) * cw,
        usize::from(r) * ch
    )?;
    write!(out, "{}", terminal::modes_table(&rows, args.markdown))?;
    Ok(Report {
        header: Vec::new(),
        rows: Vec::new(),
    })
}

/// Runs the bench `args` describe: the table goes to `out`, progress to `log`,
/// the CSV and plot to their files. Returns the report.
pub fn run(args: &BenchArgs, out: &mut dyn Write, log: &mut dyn Write) -> anyhow::Result<Report> {
    let plan = plan(args);
    if let Some(model) = &args.model {
        let request = mesh_anchor::Request {
            model,
            picture: args.picture.as_deref(),
            size: args.size,
            quick: args.quick,
            markdown: args.markdown,
            threads: plan.threads,
            pbr: args.pbr.map(|look| pbr_anchor::Request {
                look,
                environment: args.environment_map.as_deref(),
            }),
        };
        mesh_anchor::run(request, out, log)?;
        return Ok(Report {
            header: Vec::new(),
            rows: Vec::new(),
        });
    }
    if args.anchors {
        anchors::run(args.quick, args.markdown, plan.threads, out, log)?;
        return Ok(Report {
            header: Vec::new(),
            rows: Vec::new(),
        });
    }
    let (scene, texture_line) = if args.physical {
        (
            physical::scene(),
            "metallic-roughness map made by crates/bench/src/physical.rs".to_string(),
        )
    } else {
        let (texture, line) = reference::texture();
        (Scene::cube(texture, true), line)
    };
    if args.modes {
        return output_modes(args, &plan, &scene, out, log);
    }
    let header = header(&plan, &texture_line, args.physical);
    writeln!(
        log,
        "relief bench: {} rows at {}x{}; rendering the reference ({} orientations)…",
        plan.configs.len(),
        plan.width,
        plan.height,
        plan.orientations.len()
    )?;
    let rows = runner::measure(&plan, &scene, |line| {
        let _ = writeln!(log, "{}", relief_core::sanitize::clean(line));
    })?;
    let report = Report { header, rows };
    if args.markdown {
        write!(out, "{}", report::markdown(&report))?;
    } else {
        write!(out, "{}", report::text(&report))?;
    }
    if let Some(path) = &args.csv {
        std::fs::write(path, report::csv(&report))
            .map_err(|e| anyhow::anyhow!("cannot write {}: {e}", display_path(path)))?;
        writeln!(log, "wrote {}", display_path(path))?;
    }
    if let Some(path) = &args.plot {
        let title = format!(
            "RELIEF BENCH {}X{}: PSNR AGAINST TIME PER FRAME",
            plan.width, plan.height
        );
        plot::save(&report, &title, path)?;
        writeln!(log, "wrote {}", display_path(path))?;
    }
    Ok(report)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_parse_and_refuse_garbage() {
        assert_eq!(parse_size("320x240"), Ok((320, 240)));
        assert_eq!(parse_size("64X48"), Ok((64, 48)));
        assert_eq!(parse_size("8×6"), Ok((8, 6)));
        for bad in ["0x10", "10x0", "320", "ax2", "5000x10", "-1x3", "1x\u{1b}"] {
            assert!(parse_size(bad).is_err(), "{bad}");
        }
        assert!(!parse_size("1x\u{1b}[2J").unwrap_err().contains('\u{1b}'));
    }

    #[test]
    fn reference_factor_shrinks_for_big_frames() {
        assert_eq!(reference_factor(320, 240, 8), 8);
        assert_eq!(reference_factor(1920, 1080, 8), 4);
        assert_eq!(reference_factor(4096, 4096, 8), 1);
    }

    #[test]
    fn quick_plan_is_small() {
        let args = BenchArgs {
            quick: true,
            threads: Some(2),
            ..Default::default()
        };
        let p = plan(&args);
        assert_eq!((p.width, p.height, p.threads), (128, 96, 2));
        assert!(p.configs.len() <= 6 && p.orientations.len() <= 2);
    }
}
