//! Hand-derived values of the image-based light's parts.

use glam::{Vec2, Vec3};
use proptest::prelude::*;

use super::prefilter::{oct_direction, oct_uv};
use super::{Ibl, sh};
use crate::Level;
use crate::lat_long::direction;

/// The irradiance over π the coefficients give at unit normal `n`.
fn irradiance(c: &[Vec3; 9], n: Vec3) -> Vec3 {
    c.iter()
        .zip(sh::basis(n.x, n.y, n.z))
        .map(|(c, b)| *c * b)
        .sum()
}

fn level_of(w: usize, h: usize, f: impl Fn(Vec3) -> Vec3) -> Level {
    let mut texels = Vec::with_capacity(w * h);
    for y in 0..h {
        for x in 0..w {
            let uv = Vec2::new((x as f32 + 0.5) / w as f32, (y as f32 + 0.5) / h as f32);
            texels.push(f(direction(uv)).extend(0.0).to_array());
        }
    }
    Level::from_texels(w, h, texels)
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
        let e: Vec3 = irradiance(&ibl.sh, n);
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
    let at = |n: Vec3| irradiance(&ibl.sh, n).x;
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
