//! The physical truth (docs/bench.md, "The physical rows"): a model view's
//! metallic-roughness materials as the glTF 2.0 specification defines
//! them (appendix B), in f64, written from the specification and not from
//! the renderer.
//!
//! At a hit: the base colour (vertex colour times the colour texture
//! decoded from sRGB), metallic and roughness (factors times the map's
//! channels, read in their continuous form), F0 = mix(dielectric F0, base,
//! metallic), F90 = mix(specular weight, 1, metallic). The BRDF is
//! (1 − F)·(1 − metallic)·base/π + F·D·V with GGX's D, Smith's
//! height-correlated V and Schlick's F of V·H. Each light adds
//! π·BRDF·colour·N·L (a light of colour 1 on a white Lambert surface facing
//! it gives 1, as the renderer's lights are scaled). The environment adds
//! ∫ radiance·BRDF·N·L over the hemisphere, by Monte Carlo: the diffuse
//! term with cosine-distributed directions, the specular term with
//! GGX-distributed half vectors, each its own unbiased estimator; the
//! directions are stratified over the pixel (`Directions`). Then the
//! occlusion map on the environment's light, the emission, the exposure,
//! the tone map and the exact sRGB encoding, per ray.
//!
//! Not covered (the bench's scene has none of them): the clearcoat layer,
//! the sheen, the specular and clearcoat maps, normal maps, a second
//! texture coordinate set and texture transforms.

use std::f64::consts::{PI, TAU};
use std::sync::Arc;

use glam::{DVec2, DVec3, Vec3};

use super::geometry::Hit;
use super::read::{bilinear, environment};
use relief_core::settings::{Settings, ToneMap};
use relief_scene::Scene;
use relief_scene::terms::{MaterialTerms, PbrMaterial};
use relief_texture::Level;
use relief_texture::environment::Environment;

/// The smallest roughness drawn: a smaller one would turn a point light's
/// highlight into a point of unbounded brightness. The renderer draws no
/// smoother either.
pub const MIN_ROUGHNESS: f64 = 0.045;

/// Environment samples per ray and lobe, per axis of the unit square.
pub const SAMPLES_PER_AXIS: usize = 2;

/// What the physical truth draws besides the materials.
#[derive(Clone, Debug)]
pub struct Physical {
    /// The environment that lights the materials (none: the lights alone).
    pub environment: Option<Arc<Environment>>,
    /// The environment's turn about +Y in degrees, from +Z toward +X.
    pub turn: f64,
    /// Multiplies the light before the tone map.
    pub exposure: f64,
    pub tone_map: ToneMap,
}

impl PartialEq for Physical {
    fn eq(&self, other: &Self) -> bool {
        let env = |p: &Physical| p.environment.as_ref().map(Arc::as_ptr);
        env(self) == env(other)
            && self.turn == other.turn
            && self.exposure == other.exposure
            && self.tone_map == other.tone_map
    }
}

impl Physical {
    /// What `settings` ask of a model view scene: the scene's environment
    /// (the built-in studio when it has none; none without ambient
    /// light), its turn, the exposure (1 unless positive and finite) and
    /// the tone map.
    pub fn of(settings: &Settings, scene: &Scene) -> Physical {
        let exposure = settings.exposure as f64;
        let turn = settings.environment_turn as f64;
        Physical {
            environment: (scene.ambient != Vec3::ZERO).then(|| {
                scene
                    .material
                    .environment
                    .clone()
                    .unwrap_or_else(Environment::studio)
            }),
            turn: if turn.is_finite() { turn } else { 0.0 },
            exposure: if exposure.is_finite() && exposure > 0.0 {
                exposure
            } else {
                1.0
            },
            tone_map: settings.tone_map,
        }
    }

    /// A short name for the table.
    pub fn label(&self) -> String {
        let light = match &self.environment {
            Some(e) => format!("{} environment", e.name()),
            None => "lights only".into(),
        };
        let tone = match self.tone_map {
            ToneMap::PbrNeutral => "PBR Neutral",
            ToneMap::Aces => "ACES",
            ToneMap::None => "no tone map",
        };
        format!("physical, {light}, {tone}")
    }
}

/// Which integral a set of directions serves.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Lobe {
    Diffuse = 0,
    Specular = 1,
}

/// The points of the unit square one ray's environment samples use, per
/// lobe: over a pixel's n × n rays the square is cut into (n·q)² cells
/// and every cell gets one jittered point. Each ray takes the q × q cells
/// of one block of the square, blocks dealt to the rays in a shuffled
/// order (a shuffle per pixel and lobe), so where a ray crosses the pixel
/// says nothing of which directions it samples.
#[derive(Clone, Copy, Debug)]
pub struct Directions {
    /// Cells per side of the square.
    grid: usize,
    /// Cells per side of a block (points per ray and lobe: q²).
    q: usize,
    /// The ray's block per lobe (column, row), in blocks of q × q cells.
    block: [(usize, usize); 2],
    seed: u64,
}

impl Directions {
    /// The points of ray `ray` (0..n²) of pixel (px, py) with n × n rays.
    pub fn of(px: usize, py: usize, n: usize, ray: usize, order: &PixelOrder) -> Directions {
        let at = |lobe: usize| {
            let b = order.blocks[lobe][ray];
            (b % n, b / n)
        };
        Directions {
            grid: n * SAMPLES_PER_AXIS,
            q: SAMPLES_PER_AXIS,
            block: [at(0), at(1)],
            seed: hash3(px as u64, py as u64, ray as u64),
        }
    }

    /// A ray that samples the whole square alone, with `q` × `q` cells per
    /// lobe (a pixel of one ray).
    pub fn alone(px: usize, py: usize, q: usize) -> Directions {
        Directions {
            grid: q,
            q,
            block: [(0, 0); 2],
            seed: hash3(px as u64, py as u64, u64::MAX),
        }
    }

    /// The points for `lobe`.
    pub fn points(&self, lobe: Lobe) -> impl Iterator<Item = DVec2> + '_ {
        let q = self.q;
        let (bx, by) = self.block[lobe as usize];
        let g = self.grid as f64;
        (0..q * q).map(move |k| {
            let (i, j) = (k % q, k / q);
            let mut h = Hash(hash3(self.seed, lobe as u64, k as u64));
            let x = (bx * q + i) as f64 + h.next();
            let y = (by * q + j) as f64 + h.next();
            DVec2::new(x / g, y / g)
        })
    }
}

/// The order in which a pixel's rays take the blocks of each lobe's square.
pub struct PixelOrder {
    blocks: [Vec<usize>; 2],
}

impl PixelOrder {
    /// A shuffle of the n² blocks per lobe, fixed by the pixel.
    pub fn of(px: usize, py: usize, n: usize) -> PixelOrder {
        let shuffled = |lobe: u64| {
            let mut v: Vec<usize> = (0..n * n).collect();
            let mut h = Hash(hash3(px as u64, py as u64, 0xB10C ^ lobe));
            for i in (1..v.len()).rev() {
                let j = (h.next() * (i + 1) as f64) as usize;
                v.swap(i, j.min(i));
            }
            v
        };
        PixelOrder {
            blocks: [shuffled(0), shuffled(1)],
        }
    }
}

/// A fixed mix of three numbers.
fn hash3(a: u64, b: u64, c: u64) -> u64 {
    a.wrapping_mul(0x9E37_79B9_7F4A_7C15)
        ^ b.wrapping_mul(0xC2B2_AE3D_27D4_EB4F)
        ^ c.wrapping_mul(0x1656_67B1_9E37_79F9)
}

/// Uniform numbers in [0, 1) from a seed (splitmix-style finaliser).
struct Hash(u64);

impl Hash {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// What a physical hit needs of the scene.
pub struct Surface<'a> {
    pub pbr: &'a PbrMaterial,
    pub terms: &'a MaterialTerms,
    /// The object's colour texture (None: untextured).
    pub texture: Option<&'a Level>,
    /// Each light that lights: position and colour.
    pub lights: &'a [(DVec3, DVec3)],
    /// 1 / (1 + 0.01 d²) per light.
    pub attenuation: bool,
    pub eye: DVec3,
}

/// The colour the ray sees at `hit`, encoded for display (before clamping).
pub fn shade(physical: &Physical, s: &Surface, hit: &Hit, directions: &Directions) -> DVec3 {
    let n = hit.normal.normalize_or(hit.face_normal);
    let v = (s.eye - hit.position).normalize_or(n);
    let mut base = hit.color;
    if let Some(t) = s.texture {
        let c = bilinear(t, hit.uv.x, hit.uv.y);
        base *= DVec3::new(decode(c[0]), decode(c[1]), decode(c[2]));
    }
    if s.terms.unlit {
        return display(physical, base);
    }
    let m = material(s.pbr, base, hit.uv);
    // A normal turned away from the eye is lit as if grazing.
    let nv = n.dot(v).clamp(1e-4, 1.0);
    let at = At { n, v, nv, m };
    let mut lit = lights(s, &at, hit.position);
    if let Some(env) = &physical.environment {
        let mut light = diffuse_integral(env, physical.turn, &at, directions)
            + specular_integral(env, physical.turn, &at, directions);
        if let Some((map, strength)) = &s.terms.occlusion {
            let occ = bilinear(map, hit.uv.x, hit.uv.y)[0];
            light *= 1.0 + *strength as f64 * (occ - 1.0);
        }
        lit += light;
    }
    lit += emission(s.terms, hit.uv);
    display(physical, lit)
}

/// The material at a point.
struct Material {
    /// (1 − metallic)·base.
    diffuse: DVec3,
    f0: DVec3,
    f90: f64,
    /// GGX's α² (α = roughness²).
    alpha2: f64,
}

/// The shading point: normal, unit direction to the eye, N·V, material.
struct At {
    n: DVec3,
    v: DVec3,
    nv: f64,
    m: Material,
}

/// The material of `pbr` with base colour `base` at `uv`.
fn material(pbr: &PbrMaterial, base: DVec3, uv: DVec2) -> Material {
    let channel = |map: &Option<(Arc<Level>, usize)>| {
        map.as_ref()
            .map_or(1.0, |(level, c)| bilinear(level, uv.x, uv.y)[*c])
    };
    let metallic = (pbr.metallic as f64 * channel(&pbr.metallic_map)).clamp(0.0, 1.0);
    let roughness = (pbr.roughness as f64 * channel(&pbr.roughness_map)).clamp(MIN_ROUGHNESS, 1.0);
    let dielectric = pbr.dielectric_f0.as_dvec3();
    let weight = pbr.specular_weight as f64;
    let alpha = roughness * roughness;
    Material {
        diffuse: base * (1.0 - metallic),
        f0: dielectric + (base - dielectric) * metallic,
        f90: weight + (1.0 - weight) * metallic,
        alpha2: alpha * alpha,
    }
}

/// Schlick: F0 + (F90 − F0)(1 − V·H)⁵.
fn fresnel(m: &Material, vh: f64) -> DVec3 {
    let k = (1.0 - vh.clamp(0.0, 1.0)).powi(5);
    m.f0 + (DVec3::splat(m.f90) - m.f0) * k
}

/// GGX: α² / (π ((N·H)²(α² − 1) + 1)²).
fn ggx(alpha2: f64, nh: f64) -> f64 {
    let d = nh * nh * (alpha2 - 1.0) + 1.0;
    alpha2 / (PI * d * d)
}

/// Smith's height-correlated visibility G / (4 N·L N·V):
/// 0.5 / (N·L √(N·V²(1 − α²) + α²) + N·V √(N·L²(1 − α²) + α²)).
fn smith(alpha2: f64, nl: f64, nv: f64) -> f64 {
    let a = nl * (nv * nv * (1.0 - alpha2) + alpha2).sqrt();
    let b = nv * (nl * nl * (1.0 - alpha2) + alpha2).sqrt();
    if a + b > 0.0 { 0.5 / (a + b) } else { 0.0 }
}

/// Σ over the lights of colour × N·L × π·BRDF (times the attenuation).
fn lights(s: &Surface, at: &At, p: DVec3) -> DVec3 {
    let mut sum = DVec3::ZERO;
    for &(position, colour) in s.lights {
        let d = position - p;
        let len = d.length();
        if len == 0.0 || !len.is_finite() {
            continue;
        }
        let l = d / len;
        let nl = at.n.dot(l);
        if nl <= 0.0 {
            continue;
        }
        let h = (l + at.v).normalize_or(at.n);
        let f = fresnel(&at.m, at.v.dot(h));
        let specular = ggx(at.m.alpha2, at.n.dot(h).max(0.0)) * smith(at.m.alpha2, nl, at.nv);
        let brdf = (DVec3::ONE - f) * at.m.diffuse + f * (PI * specular);
        let att = if s.attenuation {
            1.0 / (1.0 + 0.01 * len * len)
        } else {
            1.0
        };
        sum += brdf * colour * (nl * att);
    }
    sum
}

/// An orthonormal frame (t, b) around unit `n`.
fn frame(n: DVec3) -> (DVec3, DVec3) {
    let t = n.any_orthonormal_vector();
    (t, n.cross(t))
}

/// The environment's radiance arriving from direction `d`, the picture
/// turned by `turn` degrees about +Y.
fn radiance(env: &Environment, turn: f64, d: DVec3) -> DVec3 {
    let (s, c) = turn.to_radians().sin_cos();
    let turned = DVec3::new(c * d.x - s * d.z, d.y, s * d.x + c * d.z);
    environment(env.picture(), turned)
}

/// ∫ radiance·(1 − F)·diffuse/π·N·L dω with directions of density N·L/π:
/// each sample is radiance·(1 − F(V·H))·diffuse.
fn diffuse_integral(env: &Environment, turn: f64, at: &At, dirs: &Directions) -> DVec3 {
    if at.m.diffuse == DVec3::ZERO {
        return DVec3::ZERO;
    }
    let (t, b) = frame(at.n);
    let (mut sum, mut count) = (DVec3::ZERO, 0usize);
    for u in dirs.points(Lobe::Diffuse) {
        count += 1;
        let phi = TAU * u.x;
        let (sin_t, cos_t) = (u.y.sqrt(), (1.0 - u.y).max(0.0).sqrt());
        let l = t * (sin_t * phi.cos()) + b * (sin_t * phi.sin()) + at.n * cos_t;
        let h = (l + at.v).normalize_or(at.n);
        let f = fresnel(&at.m, at.v.dot(h));
        sum += radiance(env, turn, l) * (DVec3::ONE - f) * at.m.diffuse;
    }
    sum / count.max(1) as f64
}

/// ∫ radiance·F·D·V·N·L dω with half vectors of density D·N·H (so
/// directions of density D·N·H / (4 V·H)): each sample is
/// radiance·F·V·N·L·4·V·H / N·H; half vectors that reflect the eye below
/// the surface add nothing.
fn specular_integral(env: &Environment, turn: f64, at: &At, dirs: &Directions) -> DVec3 {
    let (t, b) = frame(at.n);
    let a2 = at.m.alpha2;
    let (mut sum, mut count) = (DVec3::ZERO, 0usize);
    for u in dirs.points(Lobe::Specular) {
        count += 1;
        let phi = TAU * u.x;
        let cos2 = ((1.0 - u.y) / (1.0 + (a2 - 1.0) * u.y)).clamp(0.0, 1.0);
        let (cos_h, sin_h) = (cos2.sqrt(), (1.0 - cos2).sqrt());
        let h = t * (sin_h * phi.cos()) + b * (sin_h * phi.sin()) + at.n * cos_h;
        let vh = at.v.dot(h);
        if vh <= 0.0 || cos_h <= 0.0 {
            continue;
        }
        let l = h * (2.0 * vh) - at.v;
        let nl = at.n.dot(l);
        if nl <= 0.0 {
            continue;
        }
        let weight = smith(a2, nl, at.nv) * nl * 4.0 * vh / cos_h;
        sum += radiance(env, turn, l) * fresnel(&at.m, vh) * weight;
    }
    sum / count.max(1) as f64
}

/// The emissive factor times the emissive map decoded from sRGB.
fn emission(terms: &MaterialTerms, uv: DVec2) -> DVec3 {
    let e = terms.emissive.as_dvec3();
    match &terms.emissive_map {
        Some(map) if e != DVec3::ZERO => {
            let c = bilinear(map, uv.x, uv.y);
            e * DVec3::new(decode(c[0]), decode(c[1]), decode(c[2]))
        }
        _ => e,
    }
}

/// Linear light times the exposure, tone mapped, encoded as sRGB.
pub fn display(physical: &Physical, c: DVec3) -> DVec3 {
    let c = c * physical.exposure;
    let c = match physical.tone_map {
        ToneMap::PbrNeutral => pbr_neutral(c),
        ToneMap::Aces => DVec3::new(aces(c.x), aces(c.y), aces(c.z)),
        ToneMap::None => c,
    };
    DVec3::new(encode(c.x), encode(c.y), encode(c.z))
}

/// Khronos PBR Neutral (its specification's reference formula): colours
/// whose largest channel stays under 0.76 pass, less a small offset near
/// black; brighter ones are compressed toward 1 and desaturated.
pub fn pbr_neutral(c: DVec3) -> DVec3 {
    const START: f64 = 0.8 - 0.04;
    const DESATURATION: f64 = 0.15;
    let x = c.min_element();
    let offset = if x < 0.08 { x - 6.25 * x * x } else { 0.04 };
    let c = c - DVec3::splat(offset);
    let peak = c.max_element();
    if peak < START {
        return c;
    }
    let d = 1.0 - START;
    let new_peak = 1.0 - d * d / (peak + d - START);
    let c = c * (new_peak / peak);
    let g = 1.0 - 1.0 / (DESATURATION * (peak - new_peak) + 1.0);
    c * (1.0 - g) + DVec3::splat(new_peak) * g
}

/// ACES filmic as Narkowicz fitted it: x(2.51x + 0.03) / (x(2.43x + 0.59) + 0.14).
pub fn aces(x: f64) -> f64 {
    let x = x.max(0.0);
    x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14)
}

/// The sRGB encoding of linear `x` (IEC 61966-2-1).
pub fn encode(x: f64) -> f64 {
    if x <= 0.003_130_8 {
        12.92 * x
    } else {
        1.055 * x.powf(1.0 / 2.4) - 0.055
    }
}

/// The linear value of sRGB-encoded `x`.
pub fn decode(x: f64) -> f64 {
    if x <= 0.040_45 {
        x / 12.92
    } else {
        ((x + 0.055) / 1.055).powf(2.4)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn uniform(radiance: f32) -> Environment {
        Environment::from_fn("uniform", 16, 8, |_| Vec3::splat(radiance))
    }

    fn white(metallic: f32, roughness: f32) -> PbrMaterial {
        PbrMaterial {
            metallic,
            roughness,
            ..PbrMaterial::gltf_default()
        }
    }

    /// The environment's light (linear) on a point of normal +Z seen from
    /// `view`, with 128² directions per lobe.
    fn ambient(env: &Environment, pbr: &PbrMaterial, view: DVec3) -> DVec3 {
        let n = DVec3::Z;
        let v = view.normalize();
        let at = At {
            n,
            v,
            nv: n.dot(v).clamp(1e-4, 1.0),
            m: material(pbr, DVec3::ONE, DVec2::ZERO),
        };
        let dirs = Directions::alone(3, 5, 128);
        diffuse_integral(env, 0.0, &at, &dirs) + specular_integral(env, 0.0, &at, &dirs)
    }

    /// White furnace: a white dielectric under a uniform environment of
    /// radiance 1 reflects at most 1 seen within 30° of its normal, at
    /// any roughness, and a rough one nearly all of it. Toward grazing the
    /// specification's BRDF gives back more than it gets when smooth: its
    /// diffuse part is weighted by 1 − F of each direction's own half
    /// vector (at most 1 − F0, nearly that around the eye), while the
    /// mirror direction reflects F(N·V) on top. So 1 − F0 + F(N·V) bounds
    /// it: 1.37 at 80°.
    #[test]
    fn a_white_dielectric_in_a_white_furnace_reflects_at_most_its_light() {
        let env = uniform(1.0);
        for roughness in [0.05, 0.3, 0.6, 1.0] {
            for angle in [0.0f64, 30.0, 60.0, 80.0] {
                let a = angle.to_radians();
                let view = DVec3::new(a.sin(), 0.0, a.cos());
                let c = ambient(&env, &white(0.0, roughness), view);
                let m = material(&white(0.0, roughness), DVec3::ONE, DVec2::ZERO);
                let bound = 1.0 - 0.04 + fresnel(&m, a.cos()).x;
                let most = if angle <= 30.0 { 1.001 } else { bound + 0.005 };
                assert!(c.max_element() <= most, "r {roughness} at {angle}°: {c}");
                if roughness == 1.0 && angle <= 60.0 {
                    assert!(c.min_element() > 0.9, "r {roughness} at {angle}°: {c}");
                }
            }
        }
    }

    /// A white metal (F0 = 1) reflects everything when mirror-smooth. At
    /// roughness 1 (α = 1, D = 1/π) seen head on, half vectors are
    /// cosine-distributed and each sample weighs 2·N·L / (N·L + 1) with
    /// N·L = 2(N·H)² − 1: the single-scattering albedo is
    /// ∫ from ½ to 1 of (2w − 1)/w dw = 1 − ln 2.
    #[test]
    fn a_white_metal_in_a_white_furnace_loses_only_to_roughness() {
        let env = uniform(1.0);
        let smooth = ambient(&env, &white(1.0, 0.0), DVec3::new(0.3, 0.0, 1.0));
        assert!((smooth - DVec3::ONE).abs().max_element() < 0.01, "{smooth}");
        let rough = ambient(&env, &white(1.0, 1.0), DVec3::Z);
        let want = 1.0 - std::f64::consts::LN_2;
        assert!(
            (rough - DVec3::splat(want)).abs().max_element() < 0.003,
            "{rough} {want}"
        );
    }

    /// Schlick's Fresnel is F0 head on and F90 at grazing incidence.
    #[test]
    fn fresnel_is_f0_head_on_and_f90_at_grazing() {
        let m = material(&white(0.0, 0.5), DVec3::ONE, DVec2::ZERO);
        assert!((fresnel(&m, 1.0) - DVec3::splat(0.04)).abs().max_element() < 1e-7);
        assert!((fresnel(&m, 0.0) - DVec3::ONE).abs().max_element() < 1e-12);
        let gold = material(&white(1.0, 0.5), DVec3::new(1.0, 0.7, 0.3), DVec2::ZERO);
        assert!(
            (fresnel(&gold, 1.0) - DVec3::new(1.0, 0.7, 0.3))
                .abs()
                .max_element()
                < 1e-7
        );
    }

    /// A smooth white metal mirrors the environment: seen head on along
    /// +Z, it shows what the environment has straight back toward the eye.
    #[test]
    fn a_smooth_metal_mirrors_the_environment() {
        let env = Environment::from_fn("gradient", 256, 128, |d| {
            Vec3::new(0.5 + 0.4 * d.x, 0.5 + 0.4 * d.y, 0.5 + 0.4 * d.z)
        });
        let view = DVec3::new(0.6, 0.0, 0.8);
        let got = ambient(&env, &white(1.0, 0.0), view);
        let r = DVec3::new(-0.6, 0.0, 0.8);
        let want = environment(env.picture(), r);
        assert!((got - want).abs().max_element() < 0.01, "{got} {want}");
    }

    /// The tone curves and the sRGB encoding at inputs worked out by hand.
    #[test]
    fn tone_curves_and_encoding_at_known_inputs() {
        // PBR Neutral: under 0.76, only the offset 0.04 (lowest channel ≥ 0.08).
        let c = pbr_neutral(DVec3::new(0.5, 0.3, 0.2));
        assert!((c - DVec3::new(0.46, 0.26, 0.16)).abs().max_element() < 1e-12);
        // Grey 1: offset 0.04, peak 0.96, compressed to 1 − 0.04²/(0.96 + 0.24 − 0.76).
        let g = 1.0 - 0.0576 / 0.44;
        assert!(
            (pbr_neutral(DVec3::ONE) - DVec3::splat(g))
                .abs()
                .max_element()
                < 1e-12
        );
        assert!((aces(1.0) - 2.54 / 3.16).abs() < 1e-12);
        assert_eq!(aces(0.0), 0.0);
        assert!((encode(0.5) - 0.735_356_983).abs() < 1e-6);
        assert!((encode(0.002) - 0.025_84).abs() < 1e-9);
        for x in [0.0, 0.001, 0.2, 0.9, 1.0] {
            assert!((decode(encode(x)) - x).abs() < 1e-12, "{x}");
        }
    }

    /// Over a pixel's n × n rays, every cell of each lobe's (n·q)² grid
    /// gets exactly one direction.
    #[test]
    fn a_pixels_rays_sample_every_cell_once() {
        let n = 4;
        let g = n * SAMPLES_PER_AXIS;
        let order = PixelOrder::of(7, 9, n);
        for lobe in [Lobe::Diffuse, Lobe::Specular] {
            let mut seen = vec![0; g * g];
            for ray in 0..n * n {
                for p in Directions::of(7, 9, n, ray, &order).points(lobe) {
                    assert!((0.0..1.0).contains(&p.x) && (0.0..1.0).contains(&p.y));
                    let (i, j) = ((p.x * g as f64) as usize, (p.y * g as f64) as usize);
                    seen[j * g + i] += 1;
                }
            }
            assert!(seen.iter().all(|&k| k == 1), "{lobe:?}: {seen:?}");
        }
    }

    /// The Monte Carlo specular integral of a white metal in the studio
    /// agrees with the direct sum over every texel of the studio's picture
    /// (radiance × F·D·V·N·L × the texel's solid angle), head on, at 45°
    /// and at 70°, at roughness 0.25, 0.5 and 0.75.
    #[test]
    fn the_specular_integral_is_the_sum_over_the_environments_texels() {
        let env = Environment::studio();
        let level = env.picture();
        let (w, h) = (level.width, level.height);
        for roughness in [0.25f32, 0.5, 0.75] {
            for (azimuth, angle) in [(0.0f64, 0.0f64), (30.0, 45.0), (200.0, 70.0), (120.0, 45.0)] {
                let (a, z) = (angle.to_radians(), azimuth.to_radians());
                // Normal tilted up by 20°, view `angle` away from it.
                let n = DVec3::new(0.0, 20f64.to_radians().sin(), 20f64.to_radians().cos());
                let (t, b) = frame(n);
                let v = (n * a.cos() + (t * z.cos() + b * z.sin()) * a.sin()).normalize();
                let m = material(&white(1.0, roughness), DVec3::ONE, DVec2::ZERO);
                let nv = n.dot(v);
                let mut sum = DVec3::ZERO;
                for y in 0..h {
                    for x in 0..w {
                        let (u, vv) = ((x as f64 + 0.5) / w as f64, (y as f64 + 0.5) / h as f64);
                        let theta = vv * PI;
                        let phi = (u - 0.5) * TAU;
                        // The picture's convention: u = ½ + atan2(x, −z)/2π, v = acos(y)/π.
                        let l = DVec3::new(
                            theta.sin() * phi.sin(),
                            theta.cos(),
                            -theta.sin() * phi.cos(),
                        );
                        let nl = n.dot(l);
                        if nl <= 0.0 {
                            continue;
                        }
                        let hv = (l + v).normalize();
                        let f = fresnel(&m, v.dot(hv));
                        let brdf = ggx(m.alpha2, n.dot(hv).max(0.0)) * smith(m.alpha2, nl, nv);
                        let texel = level.texels.at(y * w + x);
                        let radiance =
                            DVec3::new(texel[0] as f64, texel[1] as f64, texel[2] as f64);
                        let solid = (TAU / w as f64) * (PI / h as f64) * theta.sin();
                        sum += radiance * f * (brdf * nl * solid);
                    }
                }
                let at = At { n, v, nv, m };
                let mc = specular_integral(&env, 0.0, &at, &Directions::alone(1, 2, 128));
                let e = ((mc - sum) / sum).abs().max_element();
                eprintln!(
                    "r {roughness} at {angle}°: MC {mc:.4} sum {sum:.4} ({:.2} %)",
                    e * 100.0
                );
                assert!(e < 0.02, "r {roughness} at {angle}°: {mc} {sum}");
            }
        }
    }
}
