//! Loading and overdraw benchmarks on generated files (nothing committed):
//!
//! - `load`: a 110 MB OBJ of a 708 × 708 grid (positions, UVs and normals
//!   on every corner, 8 decimals, 999,698 triangles) read by relief's loader
//!   and by tobj (single index, triangulated: the same mesh a renderer needs)
//!   on the same file, relief on all threads and on one; the load average
//!   is printed (the ratios, not the times, compare across machines);
//! - `frames`: frame time of a UV sphere (positions only, shared
//!   vertices) of 10 k, 100 k and 1 M triangles at 320 × 192 and 640 × 480,
//!   on one thread and two (default settings: Phong, texture, bump);
//! - `overdraw`: the OBJ of 8 cube corners and 15 faces of 65,536 corners
//!   (983 k triangles over the same pixels) loaded and drawn once at
//!   320 × 192.
//!
//! `cargo bench --bench load` (both) or `cargo bench --bench load -- overdraw`.
//! Prints the median of several runs; no statistics, no assertions.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use relief_core::framebuffer::Framebuffer;
use relief_core::settings::Settings;
use relief_pipeline::render::Renderer;
use relief_scene::Scene;
use relief_scene::obj;

const RUNS: usize = 5;

/// An `n × n` grid of vertices in the plane z = a ripple, every corner with
/// its UV and normal (`v/vt/vn`), two triangles per cell.
fn write_grid(path: &Path, n: usize) -> std::io::Result<()> {
    let mut out = std::io::BufWriter::new(std::fs::File::create(path)?);
    for y in 0..n {
        for x in 0..n {
            let (u, v) = (x as f32 / (n - 1) as f32, y as f32 / (n - 1) as f32);
            let z = 0.05 * (u * 40.0).sin() * (v * 30.0).cos();
            writeln!(out, "v {:.8} {:.8} {:.8}", u * 2.0 - 1.0, v * 2.0 - 1.0, z)?;
        }
    }
    for y in 0..n {
        for x in 0..n {
            writeln!(
                out,
                "vt {:.6} {:.6}",
                x as f32 / (n - 1) as f32,
                y as f32 / (n - 1) as f32
            )?;
        }
    }
    for _ in 0..n * n {
        writeln!(out, "vn 0.00000000 0.00000000 1.00000000")?;
    }
    let at = |x: usize, y: usize| y * n + x + 1;
    for y in 0..n - 1 {
        for x in 0..n - 1 {
            let (a, b, c, d) = (at(x, y), at(x + 1, y), at(x + 1, y + 1), at(x, y + 1));
            writeln!(out, "f {a}/{a}/{a} {b}/{b}/{b} {c}/{c}/{c}")?;
            writeln!(out, "f {a}/{a}/{a} {c}/{c}/{c} {d}/{d}/{d}")?;
        }
    }
    out.flush()
}

/// The 8 corners of a cube and `faces` faces of `corners` corners each,
/// going round all eight again and again: every fan repeats its few
/// distinct triangles thousands of times over the same pixels.
fn write_stacked(path: &Path, faces: usize, corners: usize) -> std::io::Result<()> {
    let mut out = std::io::BufWriter::new(std::fs::File::create(path)?);
    for x in [-1, 1] {
        for y in [-1, 1] {
            for z in [-1, 1] {
                writeln!(out, "v {x} {y} {z}")?;
            }
        }
    }
    for _ in 0..faces {
        write!(out, "f")?;
        for k in 0..corners {
            write!(out, " {}", k % 8 + 1)?;
        }
        writeln!(out)?;
    }
    out.flush()
}

fn median(mut times: Vec<Duration>) -> Duration {
    times.sort();
    times[times.len() / 2]
}

fn timed<T>(runs: usize, mut f: impl FnMut() -> T) -> Duration {
    median(
        (0..runs)
            .map(|_| {
                let start = Instant::now();
                std::hint::black_box(f());
                start.elapsed()
            })
            .collect(),
    )
}

fn pool(threads: usize) -> rayon::ThreadPool {
    let mut builder = rayon::ThreadPoolBuilder::new();
    if threads > 0 {
        builder = builder.num_threads(threads);
    }
    builder.build().expect("thread pool")
}

fn load(dir: &Path) {
    let path = dir.join("grid.obj");
    write_grid(&path, 708).expect("write the grid");
    if let Ok(load) = std::fs::read_to_string("/proc/loadavg") {
        println!("load average: {}", load.trim());
    }
    let mb = std::fs::metadata(&path).expect("written").len() as f64 / 1e6;
    let mesh = obj::load(&path).expect("relief loads it");
    println!(
        "load: {mb:.1} MB, {} triangles, {} vertices",
        mesh.triangles.len(),
        mesh.vertices.len()
    );
    drop(mesh);
    let tobj_time = timed(RUNS, || {
        tobj::load_obj(&path, &tobj::GPU_LOAD_OPTIONS).expect("tobj loads it")
    });
    println!(
        "  tobj 4 (one thread)     {:>8.3} s  {:>6.0} MB/s",
        tobj_time.as_secs_f64(),
        mb / tobj_time.as_secs_f64()
    );
    for threads in [0, 1] {
        let t = pool(threads).install(|| timed(RUNS, || obj::load_model(&path).expect("loads")));
        println!(
            "  relief ({} threads)      {:>8.3} s  {:>6.0} MB/s  {:.2}x tobj's speed",
            if threads == 0 {
                rayon::current_num_threads()
            } else {
                1
            },
            t.as_secs_f64(),
            mb / t.as_secs_f64(),
            tobj_time.as_secs_f64() / t.as_secs_f64()
        );
    }
}

fn overdraw(dir: &Path) {
    let path = dir.join("stacked.obj");
    write_stacked(&path, 15, 65_536).expect("write the stacked faces");
    let loading = timed(3, || obj::load(&path).expect("loads"));
    let mesh = obj::load(&path).expect("loads");
    println!("overdraw: {} triangles", mesh.triangles.len());
    let (texture, _) = relief_bench::reference::texture();
    let mut scene = Scene::cube(texture, true);
    scene.objects[0].mesh = mesh;
    let settings = Settings::default();
    let mut fb = Framebuffer::new(320, 192);
    // The first frame finds the repeated triangles; later ones reuse them.
    let first = timed(1, || Renderer::new().render(&scene, &settings, &mut fb));
    let mut renderer = Renderer::new();
    renderer.render(&scene, &settings, &mut fb);
    let next = timed(RUNS, || renderer.render(&scene, &settings, &mut fb));
    println!(
        "  load {:.3} s, first frame {:.3} s, next frames {:.4} s",
        loading.as_secs_f64(),
        first.as_secs_f64(),
        next.as_secs_f64()
    );
}

/// A UV sphere of `rings × segments` cells (two triangles each, one at
/// the poles), positions only, vertices shared.
fn write_sphere(path: &Path, rings: usize, segments: usize) -> std::io::Result<()> {
    let mut out = std::io::BufWriter::new(std::fs::File::create(path)?);
    for i in 1..rings {
        let theta = std::f64::consts::PI * i as f64 / rings as f64;
        for j in 0..segments {
            let phi = std::f64::consts::TAU * j as f64 / segments as f64;
            let (x, y, z) = (
                theta.sin() * phi.cos(),
                theta.cos(),
                theta.sin() * phi.sin(),
            );
            writeln!(out, "v {x:.6} {y:.6} {z:.6}")?;
        }
    }
    writeln!(out, "v 0 1 0\nv 0 -1 0")?;
    let (top, bottom) = ((rings - 1) * segments + 1, (rings - 1) * segments + 2);
    let at = |i: usize, j: usize| (i - 1) * segments + j % segments + 1;
    for j in 0..segments {
        writeln!(out, "f {top} {} {}", at(1, j + 1), at(1, j))?;
        writeln!(
            out,
            "f {bottom} {} {}",
            at(rings - 1, j),
            at(rings - 1, j + 1)
        )?;
    }
    for i in 1..rings - 1 {
        for j in 0..segments {
            let (a, b, c, d) = (at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i + 1, j));
            writeln!(out, "f {a} {b} {c}\nf {a} {c} {d}")?;
        }
    }
    out.flush()
}

fn frames(dir: &Path) {
    println!("frames: median frame time (ms), default settings");
    println!("  triangles   size      1 thread  2 threads");
    for (rings, segments) in [(50, 100), (158, 316), (500, 1000)] {
        let path = dir.join("sphere.obj");
        write_sphere(&path, rings, segments).expect("write the sphere");
        let mesh = obj::load(&path).expect("loads");
        let count = mesh.triangles.len();
        let (texture, _) = relief_bench::reference::texture();
        let mut scene = Scene::cube(texture, true);
        scene.objects[0].mesh = mesh;
        let settings = Settings::default();
        for (w, h) in [(320, 192), (640, 480)] {
            let mut row = format!("  {count:>9}  {w}x{h}");
            for threads in [1, 2] {
                let t = pool(threads).install(|| {
                    let mut renderer = Renderer::new();
                    let mut fb = Framebuffer::new(w, h);
                    renderer.render(&scene, &settings, &mut fb);
                    timed(RUNS, || renderer.render(&scene, &settings, &mut fb))
                });
                row += &format!("  {:>8.1}", t.as_secs_f64() * 1e3);
            }
            println!("{row}");
        }
    }
}

fn main() {
    let filter: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with('-'))
        .collect();
    let wanted = |name: &str| filter.is_empty() || filter.iter().any(|f| name.contains(f.as_str()));
    let dir: PathBuf =
        std::env::temp_dir().join(format!("relief-load-bench-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a temporary directory");
    if wanted("overdraw") {
        overdraw(&dir);
    }
    if wanted("frames") {
        frames(&dir);
    }
    if wanted("load") {
        load(&dir);
    }
    let _ = std::fs::remove_dir_all(&dir);
}
