//! Dot3 reads its normal map like the colour: on a minified surface,
//! trilinear and anisotropic (with the filtered derivative) read the
//! footprint's level of the map's mip chain, so the frame comes closer to
//! dot3's own supersampled render than base-level normals do; magnified,
//! nothing changes and no chain is built.
//!
//! The `texel` height derivative keeps dot3 on the base map whatever the
//! filter, so it is the "before" of every comparison here: the same frame,
//! colour filtering included, with normals read as they were.

use crate::common;

use std::sync::Arc;

use clap::ValueEnum;
use glam::{Vec2, Vec3};
use proptest::prelude::*;
use relief_core::framebuffer::Framebuffer;
use relief_core::settings::Settings;
use relief_core::settings::{Filter, HeightDerivative, LightVector, Technique};
use relief_pipeline::render::{Renderer, render_frame};
use relief_scene::Scene;
use relief_texture::sample::filter::read_normal;
use relief_texture::sample::mip::Footprint;
use relief_texture::sample::mip::{self, AnisoPlan};
use relief_texture::sample::sampler::Sampler;
use relief_texture::{NormalMap, Texture};

use common::minified::{H, W, any_f32, far_cube, gains, grazing_plane, noise, texture};

fn dot3(
    filter: Filter,
    height_derivative: HeightDerivative,
    light_vector: LightVector,
    rotation: Vec3,
) -> Settings {
    Settings {
        technique: Technique::Dot3,
        filter,
        height_derivative,
        light_vector,
        rotation,
        ..Settings::default()
    }
}

#[test]
fn a_minified_noise_cube_comes_much_closer_to_its_supersampled_render() {
    let scene = far_cube();
    for lv in [LightVector::Pixel, LightVector::Vertex] {
        for (filter, before, after) in gains(
            &scene,
            &dot3(
                Filter::Bilinear,
                HeightDerivative::Texel,
                lv,
                Vec3::new(25.0, 35.0, 0.0),
            ),
        ) {
            eprintln!("far cube, {lv:?} {filter:?}: {before:.2} -> {after:.2} dB");
            assert!(
                after > before + 6.0,
                "{lv:?} {filter:?}: {before:.2} -> {after:.2} dB"
            );
        }
    }
}

#[test]
fn a_grazing_checker_plane_comes_closer_to_its_supersampled_render() {
    let scene = grazing_plane();
    for (filter, before, after) in gains(
        &scene,
        &dot3(
            Filter::Bilinear,
            HeightDerivative::Texel,
            LightVector::Pixel,
            Vec3::new(-78.0, 0.0, 10.0),
        ),
    ) {
        eprintln!("grazing plane, {filter:?}: {before:.2} -> {after:.2} dB");
        assert!(
            after > before + 4.0,
            "{filter:?}: {before:.2} -> {after:.2} dB"
        );
    }
}

/// The map the plan uses for dot3 at the default strength (already built by
/// a frame: asking again returns the same map without building).
fn default_map(scene: &Scene) -> Arc<NormalMap> {
    let k = Settings::default().bump_strength;
    let (map, built) = scene
        .material
        .texture
        .normal_map(relief_texture::sample::normal_map::normal_map_scale(k));
    assert!(!built, "a frame has built it already");
    map
}

#[test]
fn magnified_dot3_is_bilinear_dot3_and_builds_no_chain() {
    // The front face seen straight on covers 104 × 104 pixels at 320 × 240:
    // a 96 × 96 texture is magnified on every pixel.
    for lv in [LightVector::Pixel, LightVector::Vertex] {
        for textured in [true, false] {
            let scene = Scene::cube(texture(96, noise), true);
            let frame = |filter| {
                let s = Settings {
                    texture: textured,
                    ..dot3(filter, HeightDerivative::Filtered, lv, Vec3::ZERO)
                };
                let (fb, stats) = render_frame(&scene, &s, 320, 240);
                assert_eq!(stats.counters.pixels_shaded, 104 * 104);
                assert_eq!(stats.counters.mip_builds, 0);
                fb
            };
            let bilinear = frame(Filter::Bilinear);
            for filter in [Filter::Trilinear, Filter::Anisotropic] {
                assert!(frame(filter) == bilinear, "{lv:?} {textured} {filter:?}");
            }
            assert!(!scene.material.texture.mips_built());
            assert!(
                !default_map(&scene).mips_built(),
                "{lv:?} {textured}: no normal-map chain while magnified"
            );
        }
    }
}

#[test]
fn base_level_reads_never_build_the_normal_map_chain() {
    let scene = far_cube();
    let r = Vec3::new(25.0, 35.0, 0.0);
    for filter in [Filter::Nearest, Filter::Bilinear] {
        for lv in [LightVector::Pixel, LightVector::Vertex] {
            // With nearest and bilinear the derivative setting cannot matter.
            let filtered = render_frame(
                &scene,
                &dot3(filter, HeightDerivative::Filtered, lv, r),
                W,
                H,
            );
            let texel = render_frame(&scene, &dot3(filter, HeightDerivative::Texel, lv, r), W, H);
            assert!(filtered.0 == texel.0, "{filter:?} {lv:?}");
        }
    }
    for filter in [Filter::Trilinear, Filter::Anisotropic] {
        let s = dot3(filter, HeightDerivative::Texel, LightVector::Pixel, r);
        render_frame(&scene, &s, W, H);
    }
    assert!(
        scene.material.texture.mips_built(),
        "the colour was minified"
    );
    assert!(
        !default_map(&scene).mips_built(),
        "minified, but the base map was read"
    );
}

#[test]
fn the_normal_map_chain_is_built_once_and_counted() {
    let scene = far_cube();
    let s = Settings {
        texture: false,
        ..dot3(
            Filter::Trilinear,
            HeightDerivative::Filtered,
            LightVector::Pixel,
            Vec3::new(25.0, 35.0, 0.0),
        )
    };
    let mut renderer = Renderer::new();
    let mut fb = Framebuffer::new(W, H);
    let first = renderer.render(&scene, &s, &mut fb).counters;
    assert_eq!(first.normal_map_builds, 1);
    assert_eq!(first.mip_builds, 1, "the map's chain; the colour is off");
    assert!(!scene.material.texture.mips_built());
    assert!(default_map(&scene).mips_built());
    let textured = Settings { texture: true, ..s };
    let second = renderer.render(&scene, &textured, &mut fb).counters;
    assert_eq!(second.normal_map_builds, 0);
    assert_eq!(second.mip_builds, 1, "the colour's chain only");
    let third = renderer.render(&scene, &textured, &mut fb).counters;
    assert_eq!(third.mip_builds, 0, "both kept");
}

#[test]
fn the_map_chain_averages_the_vectors_without_renormalising() {
    // Columns alternate between two tilts: level 1 averages each pair.
    let tex = texture(8, |x, _| if x % 4 < 2 { 0.0 } else { 1.0 });
    let (map, _) = tex.normal_map(0.5);
    let levels = map.mip_levels();
    assert_eq!(
        levels
            .iter()
            .map(|l| (l.width, l.height))
            .collect::<Vec<_>>(),
        [(4, 4), (2, 2), (1, 1)]
    );
    for (i, t) in levels[0].texels.iter().enumerate() {
        let (x, y) = (2 * (i % 4), 2 * (i / 4));
        let a = Vec3::from(map.normals.at(y * 8 + x));
        let b = Vec3::from(map.normals.at(y * 8 + x + 1));
        let mean = (a + b) * 0.5;
        assert!((Vec3::new(t[0], t[1], t[2]) - mean).length() < 1e-6);
    }
    // Tilted both ways in turn, the mean over the whole map is straight up
    // and shorter than 1: the relief is rough at that scale.
    let last = levels[2].texels.at(0);
    assert!(last[0].abs() < 1e-6 && last[1].abs() < 1e-6, "{last:?}");
    assert!(last[2] > 0.0 && last[2] < 0.99, "{last:?}");
    // At the smallest level's lod and beyond, every read is that vector.
    for lod in [3.0, 40.0, f32::INFINITY] {
        let n = Sampler::at_lod(lod, || map.mip_levels().len())
            .read(Vec2::new(0.3, 0.8), |i, at| map.level_bilinear(i, at));
        assert_eq!(n, [last[0], last[1], last[2]], "{lod}");
    }
}

fn small_map() -> &'static (Arc<Texture>, Arc<NormalMap>) {
    static MAP: std::sync::OnceLock<(Arc<Texture>, Arc<NormalMap>)> = std::sync::OnceLock::new();
    MAP.get_or_init(|| {
        let tex = texture(64, noise);
        let map = tex.normal_map(8.0).0;
        (tex, map)
    })
}

/// Every filter, so a new one is checked here too.
fn filters() -> impl Iterator<Item = Filter> {
    Filter::value_variants().iter().copied()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(1000))]

    /// Whatever the footprint: a finite vector no longer than 1 pointing out
    /// of the surface; the base map's bilinear read, bit for bit, for the
    /// texel derivative, nearest and bilinear, and for a magnified pixel.
    #[test]
    fn any_footprint_reads_a_finite_normal(
        u in any_f32(), v in any_f32(),
        a in any_f32(), b in any_f32(), c in any_f32(), d in any_f32(),
    ) {
        let (_, map) = small_map();
        let uv = Vec2::new(u, v);
        let fp = Footprint { dx: Vec2::new(a, b), dy: Vec2::new(c, d) };
        let base = map.bilinear(u, v);
        // Not minified, as each mip filter measures the footprint.
        let size = Vec2::new(map.width as f32, map.height as f32);
        let plan = AnisoPlan::at(size, fp);
        let magnified = |filter| match filter {
            Filter::NearestMip => mip::lod_at(size, fp) <= 0.5,
            Filter::Trilinear => mip::lod_at(size, fp) <= 0.0,
            Filter::Anisotropic => plan.taps == 1 && plan.lod == 0.0,
            _ => false,
        };
        for filter in filters() {
            for mode in [HeightDerivative::Texel, HeightDerivative::Filtered] {
                let n = read_normal(map, mode, filter, uv, fp);
                prop_assert!(n.iter().all(|c| c.is_finite()), "{filter:?} {mode:?}: {n:?}");
                prop_assert!(Vec3::from(n).length() <= 1.0 + 1e-5, "{n:?}");
                prop_assert!(n[2] > 0.0, "{n:?}");
                let on_base = mode == HeightDerivative::Texel
                    || matches!(filter, Filter::Nearest | Filter::Bilinear)
                    || magnified(filter);
                if on_base {
                    prop_assert_eq!(n.map(f32::to_bits), base.map(f32::to_bits), "{:?} {:?}", filter, mode);
                }
            }
        }
    }

    /// Base-level reads alone, with any footprint, never build the chain.
    #[test]
    fn base_level_reads_never_build_the_chain(
        u in any_f32(), v in any_f32(),
        a in any_f32(), b in any_f32(), c in any_f32(), d in any_f32(),
    ) {
        let tex = texture(16, noise);
        let (map, _) = tex.normal_map(1.0);
        let fp = Footprint { dx: Vec2::new(a, b), dy: Vec2::new(c, d) };
        for filter in filters() {
            read_normal(&map, HeightDerivative::Texel, filter, Vec2::new(u, v), fp);
        }
        for filter in [Filter::Nearest, Filter::Bilinear] {
            read_normal(&map, HeightDerivative::Filtered, filter, Vec2::new(u, v), fp);
        }
        prop_assert!(!map.mips_built());
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    /// Any view distance, turn, strength and light-vector mode: dot3 with
    /// the mip filters puts nothing non-finite in the frame.
    #[test]
    fn any_view_of_a_minified_dot3_cube_stays_finite(
        distance in prop_oneof![2.5f32..60.0, Just(1e4f32)],
        rx in -360.0f32..360.0, ry in -360.0f32..360.0, rz in -360.0f32..360.0,
        k in prop_oneof![0.0f32..0.2, Just(1e6f32), Just(f32::MAX)],
        aniso in any::<bool>(),
        per_vertex in any::<bool>(),
        textured in any::<bool>(),
    ) {
        let mut scene = far_cube();
        scene.camera.eye = Vec3::new(0.0, 0.0, distance);
        scene.camera.far = 2e4;
        let s = Settings {
            technique: Technique::Dot3,
            filter: if aniso { Filter::Anisotropic } else { Filter::Trilinear },
            light_vector: if per_vertex { LightVector::Vertex } else { LightVector::Pixel },
            texture: textured,
            bump_strength: k,
            rotation: Vec3::new(rx, ry, rz),
            ..Settings::default()
        };
        let (_, stats) = render_frame(&scene, &s, 64, 48);
        prop_assert_eq!(stats.counters.nonfinite, 0);
    }
}
