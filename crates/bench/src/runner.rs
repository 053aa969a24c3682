//! Renders every configuration: first once per orientation against the
//! reference (the error, and the warm-up), then timed until the row's budget.

use std::time::{Duration, Instant};

use glam::Vec3;

use super::config::{self, Config, Threads};
use super::metrics::{self, SquaredError};
use super::reference;
use super::terminal;
use super::truth;
use relief_core::framebuffer::{Framebuffer, Rgb};
use relief_core::settings::Settings;
use relief_core::stats::FrameStats;
use relief_pipeline::render::Renderer;
use relief_scene::Scene;
use relief_term::ColorDepth;

/// What a run measures and how long it may take.
#[derive(Clone, Debug)]
pub struct Plan {
    pub width: usize,
    pub height: usize,
    pub configs: Vec<Config>,
    /// Model rotations every row is rendered at (and the reference too).
    pub orientations: Vec<Vec3>,
    /// Supersampling of the reference, per axis.
    pub reference_factor: usize,
    /// Rays per pixel of the ray-cast truth, per axis.
    pub truth_rays: usize,
    /// Size of the "all threads" pool.
    pub threads: usize,
    /// Timed wall time per row, after the error pass that also warms up.
    pub budget: Duration,
    /// At least this many timed frames per row, whatever the budget.
    pub min_frames: usize,
    /// At most this many timed frames per row.
    pub max_frames: usize,
    /// The timing is split into this many rounds over all rows.
    pub rounds: usize,
}

impl Plan {
    /// Every configuration, 8 orientations, reference at 8×8, ~1 s per row in 4 rounds.
    pub fn full(width: usize, height: usize, threads: usize) -> Self {
        Plan {
            width,
            height,
            configs: config::full(),
            orientations: config::orientations(8, config::SEED),
            reference_factor: 8,
            truth_rays: 16,
            threads,
            budget: Duration::from_millis(1000),
            min_frames: 32,
            max_frames: 4000,
            rounds: 4,
        }
    }

    /// A smoke run: five rows, two orientations, a few frames each.
    pub fn quick(width: usize, height: usize, threads: usize) -> Self {
        Plan {
            width,
            height,
            configs: config::quick(),
            orientations: config::orientations(2, config::SEED),
            reference_factor: 4,
            truth_rays: 6,
            threads,
            budget: Duration::from_millis(50),
            min_frames: 4,
            max_frames: 200,
            rounds: 1,
        }
    }

    fn pool_size(&self, threads: Threads) -> usize {
        match threads {
            Threads::One => 1,
            Threads::All => self.threads.max(1),
        }
    }
}

/// The measured figures of one configuration.
#[derive(Clone, Debug)]
pub struct Row {
    pub config: Config,
    /// Threads of the pool it ran in.
    pub threads: usize,
    /// Timed frames.
    pub frames: usize,
    pub median: Duration,
    /// 10th and 90th percentiles of the frame time.
    pub p10: Duration,
    pub p90: Duration,
    /// Mean of `pixels_shaded` over the orientations.
    pub pixels_per_frame: f64,
    /// PSNR in dB against the ray-cast truth, over all orientations seen
    /// as one image (infinite if equal).
    pub psnr: f64,
    /// Largest channel error against the truth over all orientations.
    pub max_error: u8,
    /// PSNR and largest error against relief's own supersampled frame
    /// (the reference the bench used before the truth).
    pub self_psnr: f64,
    pub self_max_error: u8,
    /// What the row's truth draws (`truth::Setting::label`).
    pub truth: String,
    /// The truth's own convergence: PSNR of that truth cast with half the
    /// rays per axis (a quarter of the rays) against itself; the full
    /// truth's error is smaller still.
    pub truth_psnr: f64,
    /// Mean SSIM over the orientations.
    pub ssim: f64,
    /// Mean bytes the terminal encoder writes for the frame after a small
    /// rotation, at 24-bit colour and at 256 colours.
    pub bytes_truecolor: f64,
    pub bytes_256: f64,
    /// Mean plan and raster+shade time reported by the renderer (error pass).
    pub plan_time: Duration,
    pub raster_time: Duration,
    /// Why this setting shades one pixel at a time (`None`: eight at a time).
    pub one_pixel: Option<&'static str>,
}

impl Row {
    /// Shaded pixels per second at the median frame time.
    pub fn pixels_per_second(&self) -> f64 {
        let s = self.median.as_secs_f64();
        if s > 0.0 {
            self.pixels_per_frame / s
        } else {
            0.0
        }
    }
}

/// The `q` quantile (0..=1) of sorted durations, interpolated linearly.
pub fn quantile(sorted: &[Duration], q: f64) -> Duration {
    match sorted.len() {
        0 => Duration::ZERO,
        1 => sorted[0],
        n => {
            let pos = q.clamp(0.0, 1.0) * (n - 1) as f64;
            let i = pos.floor() as usize;
            let j = (i + 1).min(n - 1);
            let t = pos - i as f64;
            let a = sorted[i].as_secs_f64();
            let b = sorted[j].as_secs_f64();
            Duration::from_secs_f64(a + (b - a) * t)
        }
    }
}

/// Builds one rayon pool per thread count the plan needs.
fn pools(plan: &Plan) -> anyhow::Result<Vec<(usize, rayon::ThreadPool)>> {
    let mut sizes: Vec<usize> = plan
        .configs
        .iter()
        .map(|c| plan.pool_size(c.threads))
        .chain([plan.pool_size(Threads::All)])
        .collect();
    sizes.sort_unstable();
    sizes.dedup();
    sizes
        .into_iter()
        .map(|n| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(n).build()?;
            Ok((n, pool))
        })
        .collect()
}

fn pool(pools: &[(usize, rayon::ThreadPool)], n: usize) -> &rayon::ThreadPool {
    &pools
        .iter()
        .find(|(k, _)| *k == n)
        .expect("a pool per size")
        .1
}

/// A row being measured: its renderer and frame stay between rounds.
struct Measuring {
    renderer: Renderer,
    fb: Framebuffer,
    scene: Scene,
    threads: usize,
    times: Vec<Duration>,
    row: Row,
    /// An animated scene's instant, in seconds: each timed frame poses it
    /// a 60th of a second on.
    clock: f32,
}

/// Renders the reference frames, measures every row's error (which also warms
/// it up), then times the rows in `plan.rounds` interleaved rounds, so a burst
/// of load from elsewhere on the machine spreads over all rows instead of
/// landing on one. `progress` gets a line per step.
pub fn measure(
    plan: &Plan,
    scene: &Scene,
    mut progress: impl FnMut(&str),
) -> anyhow::Result<Vec<Row>> {
    anyhow::ensure!(
        plan.width > 0 && plan.height > 0,
        "the frame size must not be zero"
    );
    anyhow::ensure!(!plan.orientations.is_empty(), "no orientation to render");
    let pools = pools(plan)?;
    let all = pool(&pools, plan.pool_size(Threads::All));
    let references: Vec<Framebuffer> = all.install(|| {
        plan.orientations
            .iter()
            .map(|&r| reference::render(scene, r, plan.width, plan.height, plan.reference_factor))
            .collect()
    });
    let truths = truths(plan, scene, all, &mut progress);
    let total = plan.configs.len();
    let mut rows: Vec<Measuring> = Vec::with_capacity(total);
    for (i, config) in plan.configs.iter().enumerate() {
        let threads = plan.pool_size(config.threads);
        let variant = config.variant.apply(scene);
        let setting = truth::Setting::of(&config.settings, &variant);
        let own = truths
            .iter()
            .find(|t| t.setting == setting)
            .expect("a truth per setting");
        let measuring = pool(&pools, threads)
            .install(|| error_pass(plan, &variant, config, threads, &references, own))?;
        progress(&format!(
            "[{}/{total}] {}: {} dB",
            i + 1,
            config.name,
            super::figures::db(measuring.row.psnr)
        ));
        rows.push(measuring);
    }
    let rounds = plan.rounds.max(1);
    let budget = plan.budget / rounds as u32;
    let min_frames = plan.min_frames.div_ceil(rounds);
    let max_frames = plan.max_frames.div_ceil(rounds);
    for round in 0..rounds {
        for m in rows.iter_mut() {
            pool(&pools, m.threads)
                .install(|| timed_burst(plan, m, budget, min_frames, max_frames));
        }
        progress(&format!("timing: round {}/{rounds} done", round + 1));
    }
    Ok(rows
        .into_iter()
        .map(|mut m| {
            m.times.sort_unstable();
            Row {
                frames: m.times.len(),
                median: quantile(&m.times, 0.5),
                p10: quantile(&m.times, 0.1),
                p90: quantile(&m.times, 0.9),
                ..m.row
            }
        })
        .collect())
}

/// The truth of one setting at every orientation, and its convergence.
struct Truth {
    setting: truth::Setting,
    frames: Vec<Framebuffer>,
    /// PSNR of the same truth with half the rays per axis against it.
    psnr: f64,
}

/// One truth per distinct setting of the rows (`truth::Setting::of`), each
/// also cast with half the rays per axis to measure its own convergence.
fn truths(
    plan: &Plan,
    scene: &Scene,
    pool: &rayon::ThreadPool,
    progress: &mut impl FnMut(&str),
) -> Vec<Truth> {
    let mut settings: Vec<truth::Setting> = Vec::new();
    for config in &plan.configs {
        let s = truth::Setting::of(&config.settings, &config.variant.apply(scene));
        if !settings.contains(&s) {
            settings.push(s);
        }
    }
    let rays = plan.truth_rays.max(2);
    let count = settings.len();
    settings
        .into_iter()
        .enumerate()
        .map(|(i, setting)| {
            progress(&format!(
                "ray-cast truth {}/{}: {} ({rays}x{rays} rays per pixel, and {h}x{h})…",
                i + 1,
                count,
                setting.label(),
                h = rays / 2
            ));
            let mut squared = SquaredError::default();
            let frames = pool.install(|| {
                plan.orientations
                    .iter()
                    .map(|&rotation| {
                        let view = truth::View {
                            rotation,
                            setting: setting.clone(),
                        };
                        let full = truth::render(scene, &view, plan.width, plan.height, rays);
                        let half = truth::render(scene, &view, plan.width, plan.height, rays / 2);
                        squared.add(half.pixels(), full.pixels());
                        full
                    })
                    .collect()
            });
            Truth {
                setting,
                frames,
                psnr: squared.psnr(),
            }
        })
        .collect()
}

/// One frame per orientation, compared with the reference, and the bytes
/// the terminal gets for the frame after it.
fn error_pass(
    plan: &Plan,
    scene: &Scene,
    config: &Config,
    threads: usize,
    references: &[Framebuffer],
    truth: &Truth,
) -> anyhow::Result<Measuring> {
    let mut renderer = Renderer::new();
    let mut fb = Framebuffer::new(plan.width, plan.height);
    let mut turned = Framebuffer::new(plan.width, plan.height);
    let mut sums = ErrorSums::default();
    for ((&rotation, reference), truth) in
        plan.orientations.iter().zip(references).zip(&truth.frames)
    {
        let settings = Settings {
            rotation,
            ..config.settings
        };
        let stats = renderer.render(scene, &settings, &mut fb);
        sums.add_frame(plan, &fb, reference, truth, &stats);
        render_turned(&mut renderer, scene, config, rotation, &mut turned);
        sums.add_terminal_bytes(&fb, &turned, scene.background)?;
    }
    let row = sums.row(plan.orientations.len(), scene, config, threads, truth);
    Ok(Measuring {
        renderer,
        fb,
        scene: scene.clone(),
        threads,
        times: Vec::new(),
        row,
        clock: 0.0,
    })
}

/// What the error pass adds up over the orientations.
#[derive(Default)]
struct ErrorSums {
    /// Against the truth.
    squared: SquaredError,
    max_error: u8,
    /// Against relief's own supersampled reference.
    self_squared: SquaredError,
    self_max_error: u8,
    ssim_sum: f64,
    pixels: u64,
    plan_time: Duration,
    raster_time: Duration,
    bytes_truecolor: u64,
    bytes_256: u64,
}

impl ErrorSums {
    /// The frame `fb` of one orientation against its reference and truth.
    fn add_frame(
        &mut self,
        plan: &Plan,
        fb: &Framebuffer,
        reference: &Framebuffer,
        truth: &Framebuffer,
        stats: &FrameStats,
    ) {
        self.self_squared.add(fb.pixels(), reference.pixels());
        self.self_max_error = self
            .self_max_error
            .max(metrics::max_channel_error(fb.pixels(), reference.pixels()));
        self.squared.add(fb.pixels(), truth.pixels());
        self.max_error = self
            .max_error
            .max(metrics::max_channel_error(fb.pixels(), truth.pixels()));
        self.ssim_sum += metrics::ssim(fb.pixels(), truth.pixels(), plan.width, plan.height);
        self.pixels += stats.counters.pixels_shaded;
        self.plan_time += stats.plan_time;
        self.raster_time += stats.raster_time;
    }

    /// The bytes the terminal gets to go from `fb` to `turned`, at both
    /// colour depths.
    fn add_terminal_bytes(
        &mut self,
        fb: &Framebuffer,
        turned: &Framebuffer,
        bg: Rgb,
    ) -> anyhow::Result<()> {
        self.bytes_truecolor += terminal::bytes_after(fb, turned, ColorDepth::Truecolor, bg)?;
        self.bytes_256 += terminal::bytes_after(fb, turned, ColorDepth::Palette256, bg)?;
        Ok(())
    }

    /// The row of `config`, its figures the means over `n` orientations;
    /// the timing is left to the rounds.
    fn row(self, n: usize, scene: &Scene, config: &Config, threads: usize, truth: &Truth) -> Row {
        Row {
            config: config.clone(),
            threads,
            frames: 0,
            median: Duration::ZERO,
            p10: Duration::ZERO,
            p90: Duration::ZERO,
            pixels_per_frame: self.pixels as f64 / n as f64,
            psnr: self.squared.psnr(),
            max_error: self.max_error,
            self_psnr: self.self_squared.psnr(),
            self_max_error: self.self_max_error,
            truth: truth.setting.label(),
            truth_psnr: truth.psnr,
            ssim: self.ssim_sum / n as f64,
            bytes_truecolor: self.bytes_truecolor as f64 / n as f64,
            bytes_256: self.bytes_256 as f64 / n as f64,
            plan_time: self.plan_time / n as u32,
            raster_time: self.raster_time / n as u32,
            one_pixel: relief_pipeline::shade::kernels::one_pixel_reason(
                &relief_pipeline::plan::Plan::new(scene, &config.settings),
            ),
        }
    }
}

/// The next frame of a slow turn after `rotation`, as the terminal would
/// receive it, drawn into `turned`.
fn render_turned(
    renderer: &mut Renderer,
    scene: &Scene,
    config: &Config,
    rotation: Vec3,
    turned: &mut Framebuffer,
) {
    let step = Vec3::new(0.0, terminal::STEP_DEGREES, 0.0);
    renderer.render(
        scene,
        &Settings {
            rotation: rotation + step,
            ..config.settings
        },
        turned,
    );
}

/// Whole rounds over the orientations until `budget` is spent (at least
/// `min_frames`, at most about `max_frames` frames), each frame timed; an
/// animated scene is posed at a new instant in each frame's time.
fn timed_burst(
    plan: &Plan,
    m: &mut Measuring,
    budget: Duration,
    min_frames: usize,
    max_frames: usize,
) {
    let start = Instant::now();
    let mut frames = 0;
    while frames < min_frames || (start.elapsed() < budget && frames < max_frames) {
        for &rotation in &plan.orientations {
            let settings = Settings {
                rotation,
                ..m.row.config.settings
            };
            let t = Instant::now();
            if let Some(motion) = m.scene.motion.as_mut() {
                m.clock += 1.0 / 60.0;
                motion.show(&mut m.scene.objects, Some(0), m.clock);
            }
            let stats = m.renderer.render(&m.scene, &settings, &mut m.fb);
            m.times.push(t.elapsed());
            std::hint::black_box(stats);
            frames += 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantiles_interpolate_between_sorted_samples() {
        let ms = |v: u64| Duration::from_millis(v);
        let sorted: Vec<Duration> = (1..=5).map(ms).collect();
        assert_eq!(quantile(&sorted, 0.5), ms(3));
        assert_eq!(quantile(&sorted, 0.0), ms(1));
        assert_eq!(quantile(&sorted, 1.0), ms(5));
        assert_eq!(quantile(&sorted, 0.1), Duration::from_secs_f64(0.0014));
        assert_eq!(quantile(&sorted[..2], 0.5), Duration::from_secs_f64(0.0015));
        assert_eq!(quantile(&[], 0.5), Duration::ZERO);
    }
}
