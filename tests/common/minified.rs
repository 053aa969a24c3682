//! Scenes where a bump map is minified: a far cube and a grazing plane with
//! fine height detail, shared by the filtered-emboss and filtered-dot3 tests.

use clap::ValueEnum;
use std::sync::Arc;

use glam::{Mat4, Vec3};
use proptest::prelude::*;
use relief_bench::metrics::psnr;
use relief_bench::resolve::box_downsample;
use relief_core::framebuffer::Framebuffer;
use relief_core::settings::Settings;
use relief_core::settings::{Filter, HeightDerivative};
use relief_pipeline::render::render_frame;
use relief_scene::Scene;
use relief_scene::{Object, plane};
use relief_texture::{Level, Texture};

/// A repeatable value in 0..1 per texel.
pub fn noise(x: usize, y: usize) -> f32 {
    let mut h = (x as u32).wrapping_mul(0x9E37_79B9) ^ (y as u32).wrapping_mul(0x85EB_CA6B);
    h ^= h >> 15;
    h = h.wrapping_mul(0x2C1B_3C6D);
    h ^= h >> 12;
    (h & 0xFFFF) as f32 / 65535.0
}

/// `n × n` texels: a coarse two-tone colour checker, `height` per texel.
pub fn texture(n: usize, height: impl Fn(usize, usize) -> f32) -> Arc<Texture> {
    let mut level = Level::solid(n, n, [0.0; 4]);
    for y in 0..n {
        for x in 0..n {
            let c = if (x / 16 + y / 16) % 2 == 0 {
                0.85
            } else {
                0.55
            };
            level.texels.as_mut_slice()[y * n + x] = [c, 0.7, 1.0 - c, height(x, y)];
        }
    }
    Arc::new(Texture::new("test", level))
}

/// The reference cube, pulled back until its faces are a few texels per pixel.
pub fn far_cube() -> Scene {
    let mut scene = Scene::cube(texture(128, noise), true);
    scene.camera.eye = Vec3::new(0.0, 0.0, 14.0);
    scene
}

/// A large plane turned nearly edge-on, with a fine checker height.
pub fn grazing_plane() -> Scene {
    let checker = |x: usize, y: usize| {
        if (x / 2 + y / 2).is_multiple_of(2) {
            1.0
        } else {
            0.0
        }
    };
    let mut scene = Scene::model(plane::plane(), texture(128, checker));
    scene.objects = vec![Object {
        mesh: plane::plane(),
        transform: Mat4::from_scale(Vec3::splat(2.5)),
        rotates: true,
    }];
    scene
}

/// Any f32, the awkward ones often.
pub fn any_f32() -> impl Strategy<Value = f32> {
    prop_oneof![
        proptest::num::f32::ANY,
        -4.0f32..4.0,
        -0.05f32..0.05,
        Just(0.0),
        Just(f32::NAN),
        Just(f32::INFINITY),
        Just(f32::NEG_INFINITY),
        Just(f32::MAX),
    ]
}

/// Frame size of the comparisons.
pub const W: usize = 160;
pub const H: usize = 120;

/// `base` (a technique, view and light vector) supersampled 16 × 16 with
/// base-level heights and box-resolved: far more samples than texels,
/// averaged, as the eye would integrate them.
pub fn reference(scene: &Scene, base: &Settings) -> Framebuffer {
    let s = Settings {
        filter: Filter::Bilinear,
        height_derivative: HeightDerivative::Texel,
        ..*base
    };
    box_downsample(&render_frame(scene, &s, W * 16, H * 16).0, 16)
}

/// PSNR (dB) against [`reference`] of base-level (texel) and filtered
/// reads, per mip filter.
pub fn gains(scene: &Scene, base: &Settings) -> Vec<(Filter, f64, f64)> {
    let reference = reference(scene, base);
    Filter::value_variants()
        .iter()
        .copied()
        .filter(|f| f.uses_mips())
        .map(|filter| {
            let db = |height_derivative| {
                let s = Settings {
                    filter,
                    height_derivative,
                    ..*base
                };
                let (fb, stats) = render_frame(scene, &s, W, H);
                assert_eq!(stats.counters.nonfinite, 0);
                psnr(fb.pixels(), reference.pixels())
            };
            (
                filter,
                db(HeightDerivative::Texel),
                db(HeightDerivative::Filtered),
            )
        })
        .collect()
}
