//! Criterion micro-benchmarks of the renderer at 320×240 on the reference cube
//! (texture and bump on all six faces, 4 point lights): the full Phong path
//! and the cheapest flat untextured frame, on one thread and on all threads;
//! the other bump techniques (emboss, dot3, parallax, occlusion) on one;
//! and the model view's metallic-roughness kernel against Phong with Blinn's
//! bump on the same framed cube, with the image-based light's default and
//! other ways, and with glTF's layer maps (specular strength and colour,
//! clearcoat intensity, roughness and normal) against without
//! (docs/shading.md); and what the model view makes once before its first
//! frame (the studio's image-based light, the split-sum table).
//! `cargo bench --bench render`; `relief bench` covers every setting.

use std::hint::black_box;

use glam::Vec3;
use std::time::Instant;

use criterion::{Criterion, criterion_group, criterion_main};
use relief_core::framebuffer::Framebuffer;
use relief_core::settings::{Settings, Shading};
use relief_pipeline::render::Renderer;
use relief_scene::Scene;

const WIDTH: usize = 320;
const HEIGHT: usize = 240;

/// Renders `settings` repeatedly inside a pool of `threads` threads (0: rayon's default).
fn bench(c: &mut Criterion, name: &str, settings: Settings, threads: usize) {
    let (texture, _) = relief_bench::reference::texture();
    bench_scene(c, name, &Scene::cube(texture, true), settings, threads);
}

/// The reference cube in the model view (framed, the neutral rig): as it
/// is (Phong with Blinn's bump), or with a metallic-roughness material of
/// the same texture as base colour and its height map's normal map; with
/// `Layers::Factors` a clearcoat of factor 1 and roughness 0.3 and a
/// specular colour (0.04 f0) by their factors alone, with `Layers::Maps`
/// the same and the maps of `KHR_materials_specular` and
/// `KHR_materials_clearcoat` made from the same picture: its height as the
/// specular strength, its colour as the specular colour and as the
/// clearcoat's intensity (red) and roughness (green), one picture read
/// once, and its normal map as the clearcoat's; with `Layers::Sheen` a
/// sheen of colour (1, 0.6, 0.8) and roughness 0.5 by its factors.
fn model_view_cube(physical: bool, layers: Layers) -> Scene {
    use std::sync::Arc;

    use relief_scene::terms::{Clearcoat, MaterialTerms, PbrMaterial, Sheen, SpecularMaps};
    use relief_texture::Level;
    use relief_texture::sample::normal_map::normal_map_scale;
    let (texture, _) = relief_bench::reference::texture();
    let mut scene = Scene::cube(texture, true).into_model_view();
    if physical {
        let strength = relief_core::settings::DEFAULT_BUMP_STRENGTH;
        let normal = scene
            .material
            .texture
            .normal_map(normal_map_scale(strength))
            .0;
        let mut material = PbrMaterial {
            metallic: 0.5,
            roughness: 0.5,
            normal: Some(normal.clone()),
            ..PbrMaterial::gltf_default()
        };
        if layers == Layers::Sheen {
            material.sheen = Some(Sheen {
                colour: Vec3::new(1.0, 0.6, 0.8),
                roughness: 0.5,
                colour_map: None,
                roughness_map: None,
            });
        }
        if layers == Layers::Factors {
            material.clearcoat = Some(Clearcoat::of_factors(1.0, 0.3));
        }
        if layers == Layers::Maps {
            let base = scene.material.texture.base();
            let colour = Arc::new(base.clone());
            let strength = Arc::new(Level {
                texels: base.texels.channel_grey(3),
                ..base.clone()
            });
            material.specular_maps = Some(SpecularMaps {
                f0_colour: Vec3::splat(0.04),
                strength: Some(strength),
                colour: Some(colour.clone()),
            });
            material.clearcoat = Some(Clearcoat {
                factor_map: Some((colour.clone(), 0)),
                roughness_map: Some((colour, 1)),
                normal: Some(normal),
                ..Clearcoat::of_factors(1.0, 0.3)
            });
        }
        scene.object_terms = vec![Some(Arc::new(MaterialTerms {
            pbr: Some(material),
            ..MaterialTerms::default()
        }))];
    }
    scene
}

/// What the model view's cube has of glTF's material layers.
#[derive(Clone, Copy, PartialEq)]
enum Layers {
    None,
    Factors,
    Maps,
    Sheen,
}

fn bench_scene(c: &mut Criterion, name: &str, scene: &Scene, settings: Settings, threads: usize) {
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
                    black_box(renderer.render(scene, black_box(&settings), &mut fb));
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
    // The other bump techniques, on one thread: the kernels `e` switches to.
    use relief_core::settings::Technique;
    for (technique, name) in [
        (Technique::Emboss, "emboss"),
        (Technique::Dot3, "dot3"),
        (Technique::Parallax, "parallax"),
        (Technique::Pom, "pom"),
    ] {
        let settings = Settings {
            technique,
            ..Settings::default()
        };
        bench(c, &format!("{name}_320x240/1_thread"), settings, 1);
    }
    let start = Settings {
        rotation: relief_scene::model_view::START_ROTATION,
        ..Settings::default()
    };
    for (physical, layers, name) in [
        (false, Layers::None, "model_view_phong_bump"),
        (true, Layers::None, "model_view_pbr"),
        (true, Layers::Factors, "model_view_pbr_coat"),
        (true, Layers::Maps, "model_view_pbr_layer_maps"),
        (true, Layers::Sheen, "model_view_pbr_sheen"),
    ] {
        let scene = model_view_cube(physical, layers);
        bench_scene(c, &format!("{name}_320x240/all_threads"), &scene, start, 0);
        bench_scene(c, &format!("{name}_320x240/1_thread"), &scene, start, 1);
    }
    // The image-based light's other ways (`--ibl-diffuse`, `--ibl-specular`):
    // their maps are made before the timing (criterion's warm-up).
    use relief_core::settings::{IblDiffuse, IblSpecular};
    let scene = model_view_cube(true, Layers::None);
    for (ibl_diffuse, ibl_specular, name) in [
        (
            IblDiffuse::Integrated,
            IblSpecular::Prefiltered,
            "integrated",
        ),
        (IblDiffuse::Sh, IblSpecular::Sampled, "sampled"),
    ] {
        let settings = Settings {
            ibl_diffuse,
            ibl_specular,
            ..start
        };
        let name = format!("model_view_pbr_{name}_320x240");
        bench_scene(c, &format!("{name}/all_threads"), &scene, settings, 0);
        bench_scene(c, &format!("{name}/1_thread"), &scene, settings, 1);
    }
}

/// What the model view makes once per environment and once per process
/// before its first frame (docs/shading.md, "Image-based light"): the
/// studio's light (nine SH coefficients and the six prefiltered levels)
/// and the split-sum table, each on one thread and on all.
fn environment_setup(c: &mut Criterion) {
    use relief_texture::environment::Environment;
    use relief_texture::ibl::Ibl;
    let studio = Environment::studio();
    for (threads, name) in [(1, "1_thread"), (0, "all_threads")] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("a thread pool");
        let mut group = c.benchmark_group("environment_setup");
        group.sample_size(10);
        group.bench_function(format!("studio_light/{name}"), |b| {
            b.iter(|| pool.install(|| black_box(Ibl::new(studio.picture()))))
        });
        group.bench_function(format!("split_sum_table/{name}"), |b| {
            b.iter(|| pool.install(|| black_box(relief_pipeline::shade::split_sum::build())))
        });
        group.finish();
    }
}

criterion_group!(benches, renderer, environment_setup);
criterion_main!(benches);
