//! `relief bench --anchors --model FILE`: a model file in the view that
//! `docs/tools/llvmpipe_mesh.py` draws with Mesa llvmpipe, timed as that
//! harness times it, so the two run one after the other and compare as
//! ratios (docs/bench.md, "A model file side by side with llvmpipe").
//!
//! The view: the model as `relief FILE` loads it (centred on its bounding
//! box, farthest point 1.5 from the centre), but rotated 25°, 35°, 0° in the
//! reference view rather than the model view (`scene::model_view`), the
//! reference camera at (0, 0, 5) (60° vertical field of view, near 0.1,
//! far 100), the four reference point lights and ambient 0.1, no attenuation;
//! Phong with vertex normals, the vertex colours (0.4 + 0.3·(p/1.5 + 1)
//! from the fitted position, where the file gives none), no texture, no
//! bump, no highlight; back faces culled when the model is closed. A
//! renderer without shadows draws this, so the `mesh` rows draw no shadow
//! map; the `mesh+shadows` rows are the same frames with the self-shadow
//! pass relief adds to a model it does not know to be convex (as the view
//! and `relief render` draw it), printed only when relief draws one.

use std::io::Write;
use std::path::Path;
use std::time::{Duration, Instant};

use super::anchors::AnchorRow;
use relief_core::framebuffer::Framebuffer;
use relief_core::settings::{Normals, Settings, Shading};
use relief_pipeline::render::Renderer;
use relief_pipeline::shadow::CasterLod;
use relief_scene::{Built, ModelChoice, Scene, SceneKind, build_scene};

/// The frame sizes of the table: a 160×96-cell terminal's half blocks, and VGA.
pub const SIZES: [(usize, usize); 2] = [(320, 192), (640, 480)];
/// The size the pictures of the two renderers are compared at.
pub const COMPARE_SIZE: (usize, usize) = (320, 240);

/// Interleaved rounds per row.
const ROUNDS: usize = 3;
/// Frames of one row in one round: as many as fit in this time…
const ROUND_BUDGET: Duration = Duration::from_millis(600);
/// …but at least this many and at most `MAX_FRAMES`.
const MIN_FRAMES: usize = 2;
const MAX_FRAMES: usize = 40;

/// The settings of the view (see the module's comment).
pub fn settings() -> Settings {
    Settings {
        shading: Shading::Phong,
        normals: Normals::Vertex,
        texture: false,
        bump: false,
        specular: false,
        environment: false,
        ..Settings::default()
    }
}

/// The model file as `relief FILE` builds it (the cube scene with that
/// model), in the reference camera and lights rather than the model view,
/// as the llvmpipe harness draws it.
pub fn scene(path: &Path) -> anyhow::Result<Scene> {
    let (texture, _) = super::reference::texture();
    match build_scene(
        SceneKind::Cube,
        &ModelChoice::File(path.to_path_buf()),
        texture,
        true,
    )? {
        Built::Scene(scene) => Ok((*scene).into_reference_view()),
        Built::Plasma(_) => unreachable!("the cube scene is a 3D scene"),
    }
}

/// Pixels of `fb` that are not the background: what was drawn (the
/// harness counts the same way in what it reads back).
pub fn covered(fb: &Framebuffer, background: [u8; 3]) -> u64 {
    fb.pixels().iter().filter(|&&p| p != background).count() as u64
}

/// How many frames of `frame_time` each make one round's share.
fn frames_for(frame_time: Duration) -> usize {
    let fit = ROUND_BUDGET.as_secs_f64() / frame_time.as_secs_f64().max(1e-6);
    (fit as usize).clamp(MIN_FRAMES, MAX_FRAMES)
}

struct Cell {
    row: AnchorRow,
    renderer: Renderer,
    fb: Framebuffer,
    frames: usize,
    times: Vec<Duration>,
}

/// The rows' variant names: without shadows, then with relief's shadow pass.
pub type Variants = (&'static str, &'static str);
/// The Phong view's rows.
pub const MESH: Variants = ("mesh", "mesh+shadows");
/// The physically shaded view's rows (`pbr_anchor`).
pub const PBR: Variants = ("pbr", "pbr+shadows");

/// Times the view of `scene` at each size and thread count in `rounds`
/// interleaved rounds (each after one warm-up frame), and returns the rows:
/// `variants.0` without shadows, then `variants.1` where relief draws a
/// shadow map.
pub fn measure(
    scene: &Scene,
    variants: Variants,
    sizes: &[(usize, usize)],
    threads: &[usize],
    rounds: usize,
    mut progress: impl FnMut(&str),
) -> anyhow::Result<Vec<AnchorRow>> {
    let settings = settings();
    let pools: Vec<(usize, rayon::ThreadPool)> = threads
        .iter()
        .map(|&n| Ok((n, rayon::ThreadPoolBuilder::new().num_threads(n).build()?)))
        .collect::<anyhow::Result<_>>()?;
    let mut cells = Vec::new();
    for &(width, height) in sizes {
        for shadows in [false, true] {
            for (n, pool) in &pools {
                let mut fb = Framebuffer::new(width, height);
                let mut renderer = Renderer::new();
                renderer.set_shadows(shadows);
                // As the view draws once the stand-ins are made.
                renderer.set_caster_lod(CasterLod::Wait);
                // The second frame's time sets the count: the first also
                // finds the mesh's repeated triangles.
                let stats = pool.install(|| renderer.render(scene, &settings, &mut fb));
                let start = Instant::now();
                pool.install(|| renderer.render(scene, &settings, &mut fb));
                let first = start.elapsed();
                if shadows && stats.counters.shadow_texels == 0 {
                    break; // no shadow map: the `mesh` rows already are these frames
                }
                let stand_ins = renderer.stand_in_triangles();
                if shadows && stand_ins > 0 {
                    progress(&format!(
                        "anchors --model: {width}x{height}, {n} thread(s): the shadow map drawn from stand-ins of {stand_ins} triangles"
                    ));
                }
                cells.push(Cell {
                    row: AnchorRow {
                        variant: if shadows { variants.1 } else { variants.0 },
                        width,
                        height,
                        threads: *n,
                        median: Duration::ZERO,
                        min: Duration::ZERO,
                        frames: 0,
                        covered: covered(&fb, scene.background),
                    },
                    renderer,
                    fb,
                    frames: frames_for(first),
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
                cell.renderer.render(scene, &settings, &mut cell.fb);
                for _ in 0..cell.frames {
                    let start = Instant::now();
                    cell.renderer.render(scene, &settings, &mut cell.fb);
                    cell.times.push(start.elapsed());
                }
            });
        }
        progress(&format!(
            "anchors --model: round {}/{} done",
            round + 1,
            rounds.max(1)
        ));
    }
    Ok(cells.into_iter().map(|c| c.row.timed(c.times)).collect())
}

/// What `relief bench --anchors --model` asks for.
#[derive(Clone, Copy, Debug)]
pub struct Request<'a> {
    pub model: &'a Path,
    /// Receives the view at [`COMPARE_SIZE`] without shadows.
    pub picture: Option<&'a Path>,
    /// Replaces the two sizes of the table.
    pub size: Option<(usize, usize)>,
    /// A smoke run: 64×48, one round.
    pub quick: bool,
    pub markdown: bool,
    /// The thread count of the "all threads" rows.
    pub threads: usize,
    /// `--pbr`: shade the model physically (`pbr_anchor`).
    pub pbr: Option<super::pbr_anchor::Request<'a>>,
}

/// Runs `relief bench --anchors --model FILE`.
pub fn run(
    request: Request,
    out: &mut dyn Write,
    log: &mut dyn Write,
) -> anyhow::Result<Vec<AnchorRow>> {
    let Request {
        model: path,
        picture,
        size,
        quick,
        markdown,
        threads,
        pbr,
    } = request;
    let start = Instant::now();
    let mut scene = scene(path)?;
    if let Some(pbr) = &pbr {
        let factors = pbr.look.factors();
        scene = super::pbr_anchor::physical(scene, factors, pbr.environment()?);
    }
    let triangles: usize = scene.objects.iter().map(|o| o.mesh.triangles.len()).sum();
    let closed = scene.objects.iter().all(|o| o.mesh.closed);
    writeln!(
        log,
        "anchors --model: loaded in {:.2} s",
        start.elapsed().as_secs_f64()
    )?;
    if let Some(out) = picture {
        let (w, h) = COMPARE_SIZE;
        let mut fb = Framebuffer::new(w, h);
        let mut renderer = Renderer::new();
        renderer.set_shadows(false);
        renderer.render(&scene, &settings(), &mut fb);
        fb.save_png(out)?;
        writeln!(
            log,
            "anchors --model: wrote the view at {w}x{h} to {}",
            relief_core::sanitize::display_path(out)
        )?;
    }
    let sizes: Vec<(usize, usize)> = match (size, quick) {
        (Some(s), _) => vec![s],
        (None, true) => vec![(64, 48)],
        (None, false) => SIZES.to_vec(),
    };
    let mut counts = vec![1];
    if threads > 1 {
        counts.push(threads);
    }
    let rounds = if quick { 1 } else { ROUNDS };
    let shading = match &pbr {
        Some(pbr) => pbr.describe(),
        None => "4 point lights, Phong, vertex normals and colours, no texture".into(),
    };
    writeln!(
        out,
        "relief bench --anchors --model {}: {triangles} triangles, {}; fitted to radius 1.5, rotation 25,35,0, camera (0,0,5) 60°, {shading}; {rounds} interleaved rounds, each {MIN_FRAMES} to {MAX_FRAMES} frames (about {} ms) after one warm-up frame; median and min per frame (whole render, clear included)",
        relief_core::sanitize::display_path(path),
        if closed {
            "closed: back faces culled"
        } else {
            "not closed: both sides drawn"
        },
        ROUND_BUDGET.as_millis()
    )?;
    let variants = if pbr.is_some() { PBR } else { MESH };
    let rows = measure(&scene, variants, &sizes, &counts, rounds, |line| {
        let _ = writeln!(log, "{line}");
    })?;
    if markdown {
        write!(out, "{}", super::anchors::markdown(&rows))?;
    } else {
        write!(out, "{}", super::anchors::key_values(&rows))?;
    }
    Ok(rows)
}

/// A UV sphere of `rings` rings (from pole to pole) and `segments` segments
/// as a binary little-endian PLY with positions and unit normals, vertices
/// shared, triangles counter-clockwise seen from outside: a fan at each
/// pole and two triangles per cell between, 2·segments·(rings − 1) in all.
/// `docs/tools/llvmpipe_mesh.py sphere` writes the same file.
pub fn uv_sphere_ply(rings: u32, segments: u32, radius: f32, centre: glam::Vec3) -> Vec<u8> {
    assert!(
        rings >= 2 && segments >= 3,
        "a sphere needs 2 rings and 3 segments"
    );
    let vertices = 2 + (rings - 1) * segments;
    let triangles = 2 * segments * (rings - 1);
    let mut out = format!(
        "ply\nformat binary_little_endian 1.0\nelement vertex {vertices}\nproperty float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\nproperty float nz\nelement face {triangles}\nproperty list uchar uint vertex_indices\nend_header\n"
    )
    .into_bytes();
    let mut vertex = |n: [f64; 3]| {
        for k in 0..3 {
            let p = centre[k] as f64 + radius as f64 * n[k];
            out.extend_from_slice(&(p as f32).to_le_bytes());
        }
        for v in n {
            out.extend_from_slice(&(v as f32).to_le_bytes());
        }
    };
    vertex([0.0, 1.0, 0.0]);
    for i in 1..rings {
        let theta = std::f64::consts::PI * i as f64 / rings as f64;
        for j in 0..segments {
            let phi = std::f64::consts::TAU * j as f64 / segments as f64;
            vertex([
                theta.sin() * phi.cos(),
                theta.cos(),
                theta.sin() * phi.sin(),
            ]);
        }
    }
    vertex([0.0, -1.0, 0.0]);
    let (top, bottom) = (0, vertices - 1);
    let at = |i: u32, j: u32| 1 + (i - 1) * segments + j % segments;
    let mut face = |t: [u32; 3]| {
        out.push(3);
        for v in t {
            out.extend_from_slice(&v.to_le_bytes());
        }
    };
    for j in 0..segments {
        face([top, at(1, j + 1), at(1, j)]);
    }
    for i in 1..rings - 1 {
        for j in 0..segments {
            let (a, b, c, d) = (at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i + 1, j));
            face([a, b, c]);
            face([a, c, d]);
        }
    }
    for j in 0..segments {
        face([bottom, at(rings - 1, j), at(rings - 1, j + 1)]);
    }
    out
}
