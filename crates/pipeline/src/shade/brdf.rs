//! The glTF 2.0 metallic-roughness BRDF (specification, appendix B) and
//! the colour pipeline around it (docs/shading.md, "Metallic-roughness"):
//! sRGB decoding of colour textures, the tone maps and the sRGB encoding
//! of the result. Written once over the lane type (`shade::lanes`): every
//! step is adds, multiplies, divides, square roots and selects, the same
//! in one lane and eight.
//!
//! f = (1 − F)·(1 − metallic)·base/π + F·D·V, with
//! D = α²/(π((N·H)²(α² − 1) + 1)²) (GGX), α = roughness²,
//! V = 1/2 / (N·L·√((N·V)²(1 − α²) + α²) + N·V·√((N·L)²(1 − α²) + α²))
//! (Smith, height-correlated), F = F0 + (F90 − F0)(1 − V·H)⁵ (Schlick),
//! F0 = mix(dielectric F0, base, metallic), F90 = mix(specular weight, 1,
//! metallic): the dielectric's 0.04 and 1 unless `KHR_materials_ior` or
//! `KHR_materials_specular` say otherwise.

use std::f32::consts::PI;

use glam::Vec3;

use super::lanes::{Lanes, Vector};
use relief_core::settings::ToneMap;

/// The smallest roughness shaded: a point light has no size, so a perfect
/// mirror would show it as one infinitely bright point (D → ∞ at N = H).
pub const MIN_ROUGHNESS: f32 = 0.045;

/// `x` clamped to 0..=1 (NaN to 0).
#[inline(always)]
pub fn saturate<L: Lanes>(x: L) -> L {
    L::select(x.gt(L::ZERO), x.min(L::ONE), L::ZERO)
}

/// The larger of `a` and `b`.
#[inline(always)]
pub fn max<L: Lanes>(a: L, b: L) -> L {
    L::select(a.gt(b), a, b)
}

/// GGX (Trowbridge-Reitz) D for α² = `alpha2` at N·H = `nh`.
#[inline(always)]
pub fn distribution<L: Lanes>(alpha2: L, nh: L) -> L {
    let d = nh * nh * (alpha2 - L::ONE) + L::ONE;
    alpha2 / (L::splat(PI) * d * d)
}

/// Smith's height-correlated GGX visibility V = G/(4·N·L·N·V) for α² =
/// `alpha2`; 0 where both cosines are 0.
#[inline(always)]
pub fn visibility<L: Lanes>(alpha2: L, nl: L, nv: L) -> L {
    let rest = L::ONE - alpha2;
    let ggx_v = nl * (nv * nv * rest + alpha2).sqrt();
    let ggx_l = nv * (nl * nl * rest + alpha2).sqrt();
    let sum = ggx_v + ggx_l;
    L::select(sum.gt(L::ZERO), L::splat(0.5) / sum, L::ZERO)
}

/// (1 − c)⁵, Schlick's weight, for c in 0..=1.
#[inline(always)]
pub fn schlick_weight<L: Lanes>(c: L) -> L {
    let m = L::ONE - saturate(c);
    let m2 = m * m;
    m2 * m2 * m
}

/// Schlick's Fresnel F = F0 + (F90 − F0)(1 − V·H)⁵ (F90 is 1 but for a
/// `KHR_materials_specular` weight below 1).
#[inline(always)]
pub fn fresnel<V: Vector>(f0: V, f90: V::L, vh: V::L) -> V {
    let w = schlick_weight(vh);
    f0 + (V::uniform(Vec3::ONE) * f90 - f0) * w
}

/// An sRGB-encoded value in 0..=1 as linear light, by the cubic fit
/// x·(x·(0.305306·x + 0.682171) + 0.012523) (within 0.3 % of the exact
/// curve's range; exact at 0 and 1 to 1e-6).
#[inline(always)]
pub fn srgb_to_linear<V: Vector>(c: V) -> V {
    let f = |x: V::L| {
        x * (x * (x * V::L::splat(0.305_306_01) + V::L::splat(0.682_171_1))
            + V::L::splat(0.012_522_878))
    };
    V::new(f(c.x()), f(c.y()), f(c.z()))
}

/// Linear light in 0..=1 as an sRGB-encoded value: 12.92·x near 0, else
/// the fit 0.585122·√x + 0.783140·x^¼ − 0.368263·x^⅛ of 1.055·x^(1/2.4) −
/// 0.055 (within one 8-bit step), three square roots instead of a power.
#[inline(always)]
pub fn linear_to_srgb<L: Lanes>(x: L) -> L {
    let x = saturate(x);
    let s1 = x.sqrt();
    let s2 = s1.sqrt();
    let s3 = s2.sqrt();
    let curve =
        L::splat(0.585_122_4) * s1 + L::splat(0.783_140_4) * s2 - L::splat(0.368_262_74) * s3;
    L::select(
        x.gt(L::splat(0.003_130_8)),
        curve.min(L::ONE),
        x * L::splat(12.92),
    )
}

/// Khronos PBR Neutral: linear colour in, linear colour in 0..=1 out;
/// colours below 0.76 keep their values (less a small offset near black),
/// brighter ones are compressed toward white and desaturated.
#[inline(always)]
pub fn pbr_neutral<V: Vector>(c: V) -> V {
    const START: f32 = 0.8 - 0.04;
    const DESATURATION: f32 = 0.15;
    let (r, g, b) = (c.x(), c.y(), c.z());
    let low = r.min(g).min(b);
    let offset = V::L::select(
        low.lt(V::L::splat(0.08)),
        low - V::L::splat(6.25) * low * low,
        V::L::splat(0.04),
    );
    let c = c - V::new(offset, offset, offset);
    let peak = max(max(c.x(), c.y()), c.z());
    let d = V::L::splat(1.0 - START);
    let new_peak = V::L::ONE - d * d / (peak + d - V::L::splat(START));
    let scaled = c * (new_peak / peak);
    let g = V::L::ONE - V::L::ONE / (V::L::splat(DESATURATION) * (peak - new_peak) + V::L::ONE);
    let white = V::new(new_peak, new_peak, new_peak);
    let compressed = scaled * (V::L::ONE - g) + white * g;
    V::select(peak.lt(V::L::splat(START)), c, compressed)
}

/// ACES filmic, Narkowicz's fit of the reference tone curve:
/// x(2.51x + 0.03) / (x(2.43x + 0.59) + 0.14), per channel.
#[inline(always)]
pub fn aces<L: Lanes>(x: L) -> L {
    let x = max(x, L::ZERO);
    x * (L::splat(2.51) * x + L::splat(0.03))
        / (x * (L::splat(2.43) * x + L::splat(0.59)) + L::splat(0.14))
}

/// Linear light, times the exposure, tone mapped and encoded as sRGB (each
/// channel in 0..=1).
#[inline(always)]
pub fn display<V: Vector>(c: V, exposure: f32, tone: ToneMap) -> V {
    let c = c * V::L::splat(exposure);
    let c = match tone {
        ToneMap::PbrNeutral => pbr_neutral(c),
        ToneMap::Aces => V::new(aces(c.x()), aces(c.y()), aces(c.z())),
        ToneMap::None => c,
    };
    V::new(
        linear_to_srgb(c.x()),
        linear_to_srgb(c.y()),
        linear_to_srgb(c.z()),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use relief_scene::terms::{DIELECTRIC_F0, f0_of_ior};

    /// KHR_materials_ior: water (1.33) reflects ((0.33)/(2.33))² = 2.006 %
    /// head on; 1.5 gives exactly glTF's 0.04; 0 stands for an infinite
    /// index (1). A specular weight w sets F at grazing: F(0°) = F0,
    /// F(90°) = w.
    #[test]
    fn the_index_of_refraction_and_the_specular_weight_set_fresnel() {
        assert!((f0_of_ior(1.33) - 0.020_059).abs() < 1e-6);
        assert_eq!(f0_of_ior(1.5), DIELECTRIC_F0);
        assert_eq!(f0_of_ior(0.0), 1.0);
        assert_eq!(f0_of_ior(f32::NAN), DIELECTRIC_F0);
        let f0 = Vec3::splat(0.02);
        assert!((fresnel(f0, 0.5, 1.0f32) - f0).abs().max_element() < 1e-7);
        assert!(
            (fresnel(f0, 0.5, 0.0f32) - Vec3::splat(0.5))
                .abs()
                .max_element()
                < 1e-7
        );
    }

    fn exact_encode(x: f32) -> f32 {
        if x <= 0.003_130_8 {
            12.92 * x
        } else {
            1.055 * x.powf(1.0 / 2.4) - 0.055
        }
    }

    fn exact_decode(x: f32) -> f32 {
        if x <= 0.040_45 {
            x / 12.92
        } else {
            ((x + 0.055) / 1.055).powf(2.4)
        }
    }

    #[test]
    fn srgb_fits_stay_within_an_eighth_bit_step() {
        for i in 0..=1000 {
            let x = i as f32 / 1000.0;
            let e = linear_to_srgb(x);
            assert!((e - exact_encode(x)).abs() < 0.5 / 255.0, "encode {x}: {e}");
            let d: Vec3 = srgb_to_linear(Vec3::splat(x));
            assert!((d.x - exact_decode(x)).abs() < 0.003, "decode {x}: {}", d.x);
        }
        assert_eq!(linear_to_srgb(0.0f32), 0.0);
        assert!((linear_to_srgb(1.0f32) - 1.0).abs() < 1e-6);
    }

    #[test]
    fn fresnel_is_f0_head_on_and_one_at_grazing() {
        let f0 = Vec3::splat(DIELECTRIC_F0);
        assert!((fresnel(f0, 1.0, 1.0f32) - f0).abs().max_element() < 1e-7);
        assert!((fresnel(f0, 1.0, 0.0f32) - Vec3::ONE).abs().max_element() < 1e-7);
        // At V·H = 0.5: 0.04 + 0.96/32 = 0.07.
        assert!((fresnel(f0, 1.0, 0.5f32).x - 0.07).abs() < 1e-6);
        let gold = Vec3::new(1.0, 0.77, 0.34);
        assert!((fresnel(gold, 1.0, 1.0f32) - gold).abs().max_element() < 1e-7);
    }

    #[test]
    fn distribution_and_visibility_at_known_inputs() {
        // Roughness 0.5: α = 0.25, α² = 1/16. Head on D = 1/(π α²) = 16/π;
        // at N·H = 0, D = α²/π.
        let a2 = 1.0f32 / 16.0;
        assert!((distribution(a2, 1.0f32) - 16.0 / PI).abs() < 1e-4);
        assert!((distribution(a2, 0.0f32) - a2 / PI).abs() < 1e-7);
        // Head on, V = 1/(4·N·L·N·V) = 1/4 for any roughness.
        assert!((visibility(a2, 1.0f32, 1.0f32) - 0.25).abs() < 1e-7);
        assert!((visibility(1.0f32, 1.0f32, 1.0f32) - 0.25).abs() < 1e-7);
        // α = 1: V = 1/2 / (N·L + N·V); at 0.5 and 0.5 it is 1/2.
        assert!((visibility(1.0f32, 0.5f32, 0.5f32) - 0.5).abs() < 1e-7);
        // Both cosines 0: no light, not NaN.
        assert_eq!(visibility(a2, 0.0f32, 0.0f32), 0.0);
    }

    #[test]
    fn tone_curves_at_known_inputs() {
        let grey = |x: f32| pbr_neutral(Vec3::splat(x)).x;
        // Mid grey: less the 0.04 offset. Near black: x − 6.25x².
        assert!((grey(0.5) - 0.46).abs() < 1e-6);
        assert!((grey(0.05) - 6.25 * 0.0025).abs() < 1e-6);
        // White: 0.96 compressed to 1 − 0.24²/(0.96 + 0.24 − 0.76).
        assert!((grey(1.0) - (1.0 - 0.0576 / 0.44)).abs() < 1e-6);
        // Anything bright stays below 1.
        assert!(grey(1000.0) <= 1.0 && grey(1000.0) > 0.99);
        assert!((aces(1.0f32) - 2.54 / 3.16).abs() < 1e-6);
        assert_eq!(aces(0.0f32), 0.0);
        assert!(aces(1e6f32) < 1.04);
    }

    /// The light a white dielectric sends back from a unit light, over
    /// every view direction: ∫ f·cos θ_v dω, with f = ((1 − F)·1 + π·F·D·V)/π
    /// (the kernel's convention: a unit light makes a white Lambert
    /// surface 1). Never more than it receives; a rough one nearly all.
    fn directional_albedo(roughness: f32, light_angle: f32) -> f64 {
        let a = roughness * roughness;
        let a2 = a * a;
        let n = Vec3::Z;
        let l = Vec3::new(light_angle.sin(), 0.0, light_angle.cos());
        let (steps_t, steps_p) = (1500, 600);
        let mut sum = 0.0f64;
        for i in 0..steps_t {
            let t = (i as f32 + 0.5) / steps_t as f32 * std::f32::consts::FRAC_PI_2;
            for j in 0..steps_p {
                let p = (j as f32 + 0.5) / steps_p as f32 * 2.0 * PI;
                let v = Vec3::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos());
                let h = (l + v).normalize();
                let (nl, nv, nh, vh) = (n.dot(l), n.dot(v), n.dot(h), v.dot(h));
                let f = fresnel(Vec3::splat(DIELECTRIC_F0), 1.0, vh).x;
                let brdf =
                    ((1.0 - f) + PI * f * distribution(a2, nh) * visibility(a2, nl, nv)) / PI;
                let d_omega = t.sin()
                    * (std::f32::consts::FRAC_PI_2 / steps_t as f32)
                    * (2.0 * PI / steps_p as f32);
                sum += (brdf * nv * d_omega) as f64;
            }
        }
        sum
    }

    /// Head on it gives back less than it receives. The specification's mix
    /// weights Lambert by 1 − F(V·H) rather than by what the specular lobe
    /// took, so with an oblique light it may return a little more: 1.020
    /// at 60° and roughness 0.4 (measured here; a property of appendix B's
    /// approximation, bounded at 3 %).
    #[test]
    fn a_white_dielectric_never_reflects_more_than_it_receives() {
        for roughness in [0.4, 0.7, 1.0] {
            let albedo = directional_albedo(roughness, 0.0);
            assert!(albedo <= 1.0, "roughness {roughness} head on: {albedo}");
            for angle in [0.0f32, 60.0] {
                let albedo = directional_albedo(roughness, angle.to_radians());
                assert!(
                    albedo <= 1.03,
                    "roughness {roughness} at {angle}°: {albedo}"
                );
                assert!(albedo > 0.8, "roughness {roughness} at {angle}°: {albedo}");
            }
        }
    }
}
