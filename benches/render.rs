//! Criterion micro-benchmarks of the renderer at 320×240 on the reference cube
//! (texture and bump on all six faces, 4 point lights): the full Phong path
//! and the cheapest flat untextured frame, on one thread and on all threads.
//! `cargo bench --bench render`; `relief bench` covers every setting.

use std::hint::black_box;
use std::time::Instant;

use criterion::{Criterion, criterion_group, criterion_main};
use relief::settings::{Settings, Shading};
use relief::{Framebuffer, Renderer, Scene};

const WIDTH: usize = 320;
const HEIGHT: usize = 240;

/// Renders `settings` repeatedly inside a pool of `threads` threads (0: rayon's default).
fn bench(c: &mut Criterion, name: &str, settings: Settings, threads: usize) {
    let (texture, _) = relief::bench::reference::texture();
    let scene = Scene::cube(texture, true);
    let mut builder = rayon::ThreadPoolBuilder::new();
    if threads > 0 {
        builder = builder.num_threads(threads);
    }
    let pool = builder.build().expect("thread pool");
    let mut renderer = Renderer::new();
    let mut fb = Framebuffer::new(WIDTH, HEIGHT);
    // The timing loop runs inside the pool, so no frame pays for entering it.
    c.bench_function(name, |b| {
        b.iter_custom(|iters| {
            pool.install(|| {
                let start = Instant::now();
                for _ in 0..iters {
                    black_box(renderer.render(&scene, black_box(&settings), &mut fb));
                }
                start.elapsed()
            })
        })
    });
}

fn renderer(c: &mut Criterion) {
    // Phong, vertex normals, bilinear texture, Blinn bump (filtered derivative), 4 lights.
    let phong = Settings::default();
    let flat = Settings {
        shading: Shading::Flat,
        texture: false,
        bump: false,
        ..Settings::default()
    };
    bench(c, "phong_bump_bilinear_320x240/all_threads", phong, 0);
    bench(c, "phong_bump_bilinear_320x240/1_thread", phong, 1);
    bench(c, "flat_untextured_320x240/all_threads", flat, 0);
    bench(c, "flat_untextured_320x240/1_thread", flat, 1);
}

criterion_group!(benches, renderer);
criterion_main!(benches);
