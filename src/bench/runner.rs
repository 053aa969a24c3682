//! Renders every configuration: first once per orientation against the
//! reference (the error, and the warm-up), then timed until the row's budget.

use std::time::{Duration, Instant};

use glam::Vec3;

use super::config::{self, Config, Threads};
use super::metrics::{self, SquaredError};
use super::reference;
use crate::Renderer;
use crate::framebuffer::Framebuffer;
use crate::scene::Scene;
use crate::settings::Settings;

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
    /// Size of the "all threads" pool.
    pub threads: usize,
    /// Timed wall time per row, after the error pass that also warms up.
    pub budget: Duration,
    /// At least this many timed frames per row, whatever the budget.
    pub min_frames: usize,
    /// At most this many timed frames per row.
    pub max_frames: usize,
}

impl Plan {
    /// Every configuration, 8 orientations, reference at 8×8, ~1 s per row.
    pub fn full(width: usize, height: usize, threads: usize) -> Self {
        Plan {
            width,
            height,
            configs: config::full(),
            orientations: config::orientations(8, config::SEED),
            reference_factor: 8,
            threads,
            budget: Duration::from_millis(1000),
            min_frames: 16,
            max_frames: 4000,
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
            threads,
            budget: Duration::from_millis(50),
            min_frames: 4,
            max_frames: 200,
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
    /// PSNR in dB over all orientations seen as one image (infinite if equal).
    pub psnr: f64,
    /// Largest channel error over all orientations.
    pub max_error: u8,
    /// Mean SSIM over the orientations.
    pub ssim: f64,
    /// Mean plan and raster+shade time reported by the renderer (error pass).
    pub plan_time: Duration,
    pub raster_time: Duration,
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

/// Renders the reference frames, then measures every row, calling
/// `progress(done, total, row)` after each.
pub fn measure(
    plan: &Plan,
    scene: &Scene,
    mut progress: impl FnMut(usize, usize, &Row),
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
    let mut rows = Vec::with_capacity(plan.configs.len());
    for config in &plan.configs {
        let threads = plan.pool_size(config.threads);
        let row = pool(&pools, threads)
            .install(|| measure_row(plan, scene, config, threads, &references));
        progress(rows.len() + 1, plan.configs.len(), &row);
        rows.push(row);
    }
    Ok(rows)
}

fn measure_row(
    plan: &Plan,
    scene: &Scene,
    config: &Config,
    threads: usize,
    references: &[Framebuffer],
) -> Row {
    let mut renderer = Renderer::new();
    let mut fb = Framebuffer::new(plan.width, plan.height);
    let at = |rotation: Vec3| Settings {
        rotation,
        ..config.settings
    };

    // Error pass: one frame per orientation, which also warms caches up.
    let mut squared = SquaredError::default();
    let (mut max_error, mut ssim_sum, mut pixels) = (0u8, 0.0, 0u64);
    let (mut plan_time, mut raster_time) = (Duration::ZERO, Duration::ZERO);
    for (&rotation, reference) in plan.orientations.iter().zip(references) {
        let stats = renderer.render(scene, &at(rotation), &mut fb);
        squared.add(fb.pixels(), reference.pixels());
        max_error = max_error.max(metrics::max_channel_error(fb.pixels(), reference.pixels()));
        ssim_sum += metrics::ssim(fb.pixels(), reference.pixels(), plan.width, plan.height);
        pixels += stats.counters.pixels_shaded;
        plan_time += stats.plan_time;
        raster_time += stats.raster_time;
    }
    let n = plan.orientations.len();

    // Timed pass: whole rounds over the orientations until the budget is spent.
    let mut times = Vec::new();
    let start = Instant::now();
    while times.len() < plan.min_frames
        || (start.elapsed() < plan.budget && times.len() < plan.max_frames)
    {
        for &rotation in &plan.orientations {
            let settings = at(rotation);
            let t = Instant::now();
            let stats = renderer.render(scene, &settings, &mut fb);
            times.push(t.elapsed());
            std::hint::black_box(stats);
        }
    }
    times.sort_unstable();
    Row {
        config: config.clone(),
        threads,
        frames: times.len(),
        median: quantile(&times, 0.5),
        p10: quantile(&times, 0.1),
        p90: quantile(&times, 0.9),
        pixels_per_frame: pixels as f64 / n as f64,
        psnr: squared.psnr(),
        max_error,
        ssim: ssim_sum / n as f64,
        plan_time: plan_time / n as u32,
        raster_time: raster_time / n as u32,
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
