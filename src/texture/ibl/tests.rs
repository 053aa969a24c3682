//! Hand-derived values of the image-based light's parts.

use glam::{Vec2, Vec3};
use proptest::prelude::*;

use super::lut::{Lut, SIZE, split_sum};
use super::prefilter::{oct_direction, oct_uv};
use super::{Ibl, sh};
use crate::texture::Level;
use crate::texture::environment::Environment;

fn level_of(w: usize, h: usize, f: impl Fn(Vec3) -> Vec3) -> Level {
    Environment::from_fn("test", w, h, f).picture().clone()
}

/// A white Lambert surface under uniform radiance L sends back L
/// (irradiance πL, over π), whatever way it faces.
#[test]
fn a_constant_environment_gives_its_own_irradiance() {
    let ibl = Ibl::new(&level_of(64, 32, |_| Vec3::new(0.7, 1.0, 2.5)));
    for n in [
        Vec3::X,
        Vec3::Y,
        Vec3::NEG_Z,
        Vec3::new(1.0, -2.0, 0.5).normalize(),
    ] {
        let e: Vec3 = sh::irradiance(&ibl.sh, n);
        assert!(
            (e / Vec3::new(0.7, 1.0, 2.5) - 1.0).abs().max_element() < 1e-3,
            "{n}: {e}"
        );
    }
}

/// Radiance 1 over the upper half, 0 below: E/π = (1 + cos θ)/2 from the
/// zenith, which bands 0 and 1 hold exactly (band 2 of a half-space is 0).
#[test]
fn a_half_lit_sky_gives_the_cosine_ramp() {
    let ibl = Ibl::new(&level_of(128, 64, |d| {
        Vec3::splat((d.y > 0.0) as u8 as f32)
    }));
    let at = |n: Vec3| sh::irradiance::<Vec3>(&ibl.sh, n).x;
    assert!((at(Vec3::Y) - 1.0).abs() < 0.01, "{}", at(Vec3::Y));
    assert!(at(Vec3::NEG_Y).abs() < 0.01, "{}", at(Vec3::NEG_Y));
    assert!((at(Vec3::X) - 0.5).abs() < 0.01, "{}", at(Vec3::X));
    let n = Vec3::new(0.0, 0.5, 0.75f32.sqrt());
    assert!((at(n) - 0.75).abs() < 0.01, "{}", at(n));
}

#[test]
fn a_uniform_environment_is_the_same_at_every_level() {
    let ibl = Ibl::new(&level_of(64, 32, |_| Vec3::splat(0.3)));
    for t in ibl.level_texels() {
        assert!((*t - Vec3::splat(0.3)).abs().max_element() < 1e-4, "{t}");
    }
}

/// A mirror (roughness 0) sees the texel in its direction; a rough level
/// mixes in the surroundings.
#[test]
fn the_mirror_level_reads_the_environment() {
    let red = Vec3::new(1.0, 0.0, 0.0);
    let ibl = Ibl::new(&level_of(128, 64, |d| {
        if d.dot(Vec3::X) > 0.95 {
            red
        } else {
            Vec3::splat(0.1)
        }
    }));
    assert!((ibl.specular(Vec3::X, 0.0) - red).abs().max_element() < 1e-3);
    let rough = ibl.specular(Vec3::X, 1.0);
    assert!(rough.x < 0.9 && rough.y > 0.05, "{rough}");
}

#[test]
fn octahedral_coordinates_are_inverse() {
    for d in [
        Vec3::X,
        Vec3::NEG_Y,
        Vec3::Z,
        Vec3::NEG_Z,
        Vec3::new(0.3, -0.5, -0.8).normalize(),
        Vec3::new(-0.6, 0.2, 0.1).normalize(),
    ] {
        let back = oct_direction(oct_uv(d));
        assert!((back - d).length() < 1e-5, "{d}: {back}");
    }
    assert_eq!(oct_uv(Vec3::Z), Vec2::splat(0.5));
}

/// A mirror head on reflects everything it receives: A + B = 1 at N·V = 1
/// and roughness 0 (the sampled H is N, V = 1/4, weight 1, F weight 0).
#[test]
fn the_table_is_one_for_a_mirror_head_on_and_never_above_one() {
    let (a, b) = split_sum(1.0, 0.0);
    assert!((a - 1.0).abs() < 1e-6 && b.abs() < 1e-6, "{a} {b}");
    let lut = Lut::new();
    let (a, b) = lut.read(1.0, 0.0);
    assert!((a + b - 1.0).abs() < 1e-6, "{a} {b}");
    let mut worst = 0.0f32;
    for r in 0..SIZE {
        for c in 0..SIZE {
            let step = 1.0 / (SIZE - 1) as f32;
            let (a, b) = lut.read(c as f32 * step, r as f32 * step);
            assert!(a >= 0.0 && b >= 0.0, "{c} {r}: {a} {b}");
            worst = worst.max(a + b);
        }
    }
    assert!(worst <= 1.0 + 1e-6, "{worst}");
    // Roughness 1 (α = 1): D = 1/π and V = ½/(N·L + N·V), so head on
    // A + B = ∫ N·L/(2π(N·L + 1)) dω = ∫₀¹ μ/(μ + 1) dμ = 1 − ln 2.
    let (a, b) = lut.read(1.0, 1.0);
    assert!((a + b - (1.0 - 2f32.ln())).abs() < 0.005, "{a} {b}");
    // Grazing, Fresnel's share grows: B above A for a mirror.
    let (a, b) = lut.read(0.0, 0.0);
    assert!(b > a, "{a} {b}");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]
    #[test]
    fn prefiltered_levels_are_finite_and_not_negative(
        w in 1usize..40,
        h in 1usize..20,
        seed in any::<u64>(),
        wild in any::<bool>(),
    ) {
        let mut state = seed | 1;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        let texels: Vec<[f32; 4]> = (0..w * h)
            .map(|_| {
                let x = (next() % 10_000) as f32 / 100.0;
                let odd = [f32::NAN, f32::INFINITY, -5.0, 1e30][(next() % 4) as usize];
                let v = if wild && next() % 5 == 0 { odd } else { x };
                [v, x, x * 0.5, 0.0]
            })
            .collect();
        let ibl = Ibl::new(&Level::from_texels(w, h, texels));
        for t in ibl.level_texels() {
            prop_assert!(t.is_finite() && t.min_element() >= 0.0, "{t}");
        }
        for c in ibl.sh {
            prop_assert!(c.is_finite(), "{c}");
        }
    }
}
