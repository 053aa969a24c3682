//! Criterion benchmark of an animated model: a skinned tube of 6,144
//! vertices and 12,032 triangles (a limb's size: CesiumMan has 3,273
//! vertices) bending at a joint, each frame a new instant, posed and drawn
//! at 320×192 in the model view on two threads; and the posing alone
//! (docs/models.md, "Animation"). `cargo bench --bench anim`.

use std::hint::black_box;
use std::time::Instant;

use criterion::{Criterion, criterion_group, criterion_main};
use glam::{Vec2, Vec3};
use relief_core::framebuffer::Framebuffer;
use relief_core::settings::Settings;
use relief_pipeline::render::Renderer;
use relief_scene::Scene;
use relief_scene::anim::Motion;
use relief_scene::{Mesh, Triangle, Vertex};

const WIDTH: usize = 320;
const HEIGHT: usize = 192;
const SEGMENTS: u32 = 64;
const RINGS: u32 = 96;

/// A closed-sided tube of radius 0.3 from y = −1.5 to 1.5.
fn tube() -> Mesh {
    let mut vertices = Vec::new();
    for j in 0..RINGS {
        let v = j as f32 / (RINGS - 1) as f32;
        for i in 0..SEGMENTS {
            let a = i as f32 / SEGMENTS as f32 * std::f32::consts::TAU;
            let normal = Vec3::new(a.cos(), 0.0, a.sin());
            vertices.push(Vertex {
                position: normal * 0.3 + Vec3::Y * (3.0 * v - 1.5),
                normal,
                uv: Vec2::new(i as f32 / SEGMENTS as f32, v),
                color: Vec3::ONE,
                tangent_u: Vec3::ZERO,
                tangent_v: Vec3::ZERO,
            });
        }
    }
    let at = |i: u32, j: u32| j * SEGMENTS + i % SEGMENTS;
    let mut triangles = Vec::new();
    for j in 0..RINGS - 1 {
        for i in 0..SEGMENTS {
            let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
            triangles.push(Triangle::new([a, c, b], false));
            triangles.push(Triangle::new([a, d, c], false));
        }
    }
    Mesh::of_triangles(vertices, triangles, false, false)
}

/// The tube skinned to a root joint and a child at y = 0 that turns 90°
/// about Z over 2 s; weights blend over the middle third.
fn skinned() -> Scene {
    let (texture, _) = relief_bench::reference::texture();
    let mesh = tube();
    let rest = mesh.vertices.clone();
    let mut scene = Scene::model(mesh, texture).into_model_view();
    let rig =
        relief_bench::skinned::bend_rig(rest, |y| ((y + 0.5) / 1.0).clamp(0.0, 1.0), 90.0, 2.0);
    scene.motion = Some(Motion::new(rig));
    scene
}

/// Each iteration a new instant, a 60th of a second on: posed, and drawn
/// unless `pose_only`.
fn bench_frames(c: &mut Criterion, name: &str, pose_only: bool) {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .expect("thread pool");
    let mut scene = skinned();
    let settings = Settings {
        rotation: relief_scene::model_view::START_ROTATION,
        ..Settings::default()
    };
    let mut renderer = Renderer::new();
    let mut fb = Framebuffer::new(WIDTH, HEIGHT);
    let mut time = 0.0f32;
    c.bench_function(name, |b| {
        b.iter_custom(|iters| {
            pool.install(|| {
                let start = Instant::now();
                for _ in 0..iters {
                    time += 1.0 / 60.0;
                    let motion = scene.motion.as_mut().expect("animated");
                    motion.show(&mut scene.objects, Some(0), time);
                    if !pose_only {
                        black_box(renderer.render(&scene, &settings, &mut fb));
                    }
                }
                start.elapsed()
            })
        })
    });
}

fn animated(c: &mut Criterion) {
    bench_frames(c, "skinned_tube_pose_and_draw_320x192/2_threads", false);
    bench_frames(c, "skinned_tube_pose_320x192/2_threads", true);
}

criterion_group!(benches, animated);
criterion_main!(benches);
