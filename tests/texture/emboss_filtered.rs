//! Emboss reads its heights like the colour: on a minified surface,
//! trilinear and anisotropic difference the footprint's mip level, so the
//! frame comes closer to emboss's own supersampled render than base-level
//! heights do; magnified, nothing changes and no mip chain is built.
//!
//! The `texel` height derivative keeps emboss on the base level whatever the
//! filter, so it is the "before" of every comparison here: the same frame,
//! colour filtering included, with heights read as they were.

use crate::common;

use std::sync::Arc;

use clap::ValueEnum;
use glam::{Vec2, Vec3};
use proptest::prelude::*;
use relief_core::settings::Settings;
use relief_core::settings::{Filter, HeightDerivative, Technique};
use relief_pipeline::render::render_frame;
use relief_scene::Scene;
use relief_texture::Texture;
use relief_texture::sample::filter::read_heights;
use relief_texture::sample::mip::Footprint;
use relief_texture::sample::sampler::Sampler;

use common::minified::{H, W, any_f32, far_cube, gains, grazing_plane, noise, texture};

/// The filters that read mip levels (every one the enum has).
fn mip_filters() -> impl Iterator<Item = Filter> {
    Filter::value_variants()
        .iter()
        .copied()
        .filter(|f| f.uses_mips())
}

fn emboss(filter: Filter, height_derivative: HeightDerivative, rotation: Vec3) -> Settings {
    Settings {
        technique: Technique::Emboss,
        filter,
        height_derivative,
        rotation,
        ..Settings::default()
    }
}

#[test]
fn a_minified_noise_cube_comes_much_closer_to_its_supersampled_render() {
    let scene = far_cube();
    for (filter, before, after) in gains(
        &scene,
        &emboss(
            Filter::Bilinear,
            HeightDerivative::Texel,
            Vec3::new(25.0, 35.0, 0.0),
        ),
    ) {
        eprintln!("far cube, {filter:?}: {before:.2} -> {after:.2} dB");
        assert!(
            after > before + 5.0,
            "{filter:?}: {before:.2} -> {after:.2} dB"
        );
    }
    assert!(scene.material.texture.mips_built());
}

#[test]
fn a_grazing_checker_plane_comes_closer_to_its_supersampled_render() {
    let scene = grazing_plane();
    for (filter, before, after) in gains(
        &scene,
        &emboss(
            Filter::Bilinear,
            HeightDerivative::Texel,
            Vec3::new(-78.0, 0.0, 10.0),
        ),
    ) {
        eprintln!("grazing plane, {filter:?}: {before:.2} -> {after:.2} dB");
        assert!(
            after > before + 1.0,
            "{filter:?}: {before:.2} -> {after:.2} dB"
        );
    }
}

#[test]
fn magnified_bump_techniques_read_the_base_level_only() {
    // The front face seen straight on covers 104 × 104 pixels at 320 × 240:
    // a 96 × 96 texture is magnified on every pixel.
    for &technique in Technique::value_variants() {
        let scene = Scene::cube(texture(96, noise), true);
        let frame = |filter, height_derivative| {
            let s = Settings {
                technique,
                filter,
                height_derivative,
                rotation: Vec3::ZERO,
                ..Settings::default()
            };
            let (fb, stats) = render_frame(&scene, &s, 320, 240);
            assert_eq!(stats.counters.pixels_shaded, 104 * 104);
            assert!(stats.counters.bump_evals > 0);
            fb
        };
        let bilinear = frame(Filter::Bilinear, HeightDerivative::Filtered);
        for filter in mip_filters() {
            let fb = frame(filter, HeightDerivative::Filtered);
            // The same bits as bilinear filtering: colour, heights and
            // gradient all come from the base level.
            assert!(fb == bilinear, "{technique:?} {filter:?}");
        }
        assert!(
            !scene.material.texture.mips_built(),
            "{technique:?}: no mip chain while magnified"
        );
    }
}

#[test]
fn nearest_and_bilinear_emboss_is_the_documented_base_level_emboss() {
    let scene = far_cube();
    for filter in Filter::value_variants()
        .iter()
        .copied()
        .filter(|f| !f.uses_mips())
    {
        let r = Vec3::new(25.0, 35.0, 0.0);
        let filtered = render_frame(&scene, &emboss(filter, HeightDerivative::Filtered, r), W, H);
        let texel = render_frame(&scene, &emboss(filter, HeightDerivative::Texel, r), W, H);
        assert!(filtered.0 == texel.0, "{filter:?}");
    }
    assert!(
        !scene.material.texture.mips_built(),
        "minified, but never read"
    );
}

#[test]
fn the_sampler_blends_the_levels_trilinear_reads() {
    let tex = texture(64, noise);
    let width = |lod: f32| {
        Sampler::at_lod(lod, || tex.mip_levels().len())
            .read(Vec2::ZERO, |i, _| tex.level(i).width as f32)
    };
    for lod in [0.0, -2.0, f32::NAN, f32::NEG_INFINITY] {
        assert_eq!(width(lod), 64.0, "{lod}");
    }
    assert_eq!(
        Sampler::BASE.read(Vec2::ZERO, |i, _| tex.level(i).width as f32),
        64.0
    );
    assert!(!tex.mips_built(), "the base level needs no chain");
    // Between levels 1 (32 texels) and 2 (16), a quarter of the way.
    assert_eq!(width(1.25), 28.0);
    assert_eq!(width(3.0), 8.0);
    for lod in [6.0, 40.0, f32::INFINITY] {
        assert_eq!(width(lod), 1.0, "{lod}");
    }
}

fn small_texture() -> &'static Arc<Texture> {
    static TEX: std::sync::OnceLock<Arc<Texture>> = std::sync::OnceLock::new();
    TEX.get_or_init(|| texture(64, noise))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(1000))]

    /// Whatever the footprint: filtered heights stay heights, and a
    /// one-texel difference on any level is a slope no steeper than one
    /// height unit per base texel.
    #[test]
    fn any_footprint_reads_heights_in_range(
        u in any_f32(), v in any_f32(),
        a in any_f32(), b in any_f32(), c in any_f32(), d in any_f32(),
        angle in 0.0f32..std::f32::consts::TAU,
    ) {
        let tex = small_texture();
        let uv = Vec2::new(u, v);
        let fp = Footprint { dx: Vec2::new(a, b), dy: Vec2::new(c, d) };
        let toward = Vec2::from_angle(angle);
        for &filter in Filter::value_variants() {
            for mode in [HeightDerivative::Texel, HeightDerivative::Filtered] {
                let h = read_heights(tex, mode, filter, uv, fp, |l, p| l.bilinear_height(p.x, p.y));
                prop_assert!((-1e-5..=1.0 + 1e-5).contains(&h), "{filter:?} {mode:?}: {h}");
                let slope = read_heights(tex, mode, filter, uv, fp, |l, p| {
                    let texel = 1.0 / l.width.max(l.height) as f32;
                    let q = p + toward * texel;
                    (l.bilinear_height(p.x, p.y) - l.bilinear_height(q.x, q.y)) / texel
                });
                prop_assert!(slope.is_finite(), "{filter:?} {mode:?}");
                prop_assert!(slope.abs() <= tex.width() as f32 + 1e-2, "{slope}");
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    /// Any view distance, turn and strength: emboss, parallax and POM with
    /// the mip filters put nothing non-finite in the frame.
    #[test]
    fn any_view_of_a_minified_bumped_cube_stays_finite(
        distance in prop_oneof![2.5f32..60.0, Just(1e4f32)],
        rx in -360.0f32..360.0, ry in -360.0f32..360.0,
        k in prop_oneof![0.0f32..0.2, Just(1e6f32), Just(f32::MAX)],
        which in 0usize..3,
        aniso in any::<bool>(),
    ) {
        let mut scene = far_cube();
        scene.camera.eye = Vec3::new(0.0, 0.0, distance);
        scene.camera.far = 2e4;
        let s = Settings {
            technique: [Technique::Emboss, Technique::Parallax, Technique::Pom][which],
            filter: if aniso { Filter::Anisotropic } else { Filter::Trilinear },
            bump_strength: k,
            rotation: Vec3::new(rx, ry, 0.0),
            ..Settings::default()
        };
        let (_, stats) = render_frame(&scene, &s, 64, 48);
        prop_assert_eq!(stats.counters.nonfinite, 0);
    }
}
