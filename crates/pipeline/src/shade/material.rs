//! A pixel's colour from its light (docs/shading.md): albedo × light +
//! highlight, with a model material's terms when the plan carries them
//! (`scene::terms`: the ambient occluded, the highlight tinted by `Ks`, the
//! emission added), and the environment mixed in.
//!
//! Written once for one point or eight (`shade::lanes`), so a material with
//! terms takes the packet path bit for bit; the maps are read lane by lane
//! with the one-pixel bilinear read.

use glam::Vec3;

use super::environment::mirror;
use super::lanes::{Lanes, Vector};
use super::map_uv::Coords;
use crate::plan::Plan;
use relief_core::stats::Counters;
use relief_scene::terms::MaterialTerms;

/// The diffuse `light` at (u, v) with its ambient part occluded: `light`
/// holds the plan's `ambient` once (the light loop starts from it), and the
/// occlusion map's red r at strength s keeps 1 + s·(r − 1) of it.
#[inline(always)]
pub fn occlude<V: Vector>(terms: &MaterialTerms, ambient: Vec3, u: V::L, v: V::L, light: V) -> V {
    match &terms.occlusion {
        Some((map, strength)) => {
            let occ = V::L::bilinear(map, u, v)[0];
            light - V::uniform(ambient) * (V::L::splat(*strength) * (V::L::ONE - occ))
        }
        None => light,
    }
}

/// The light given off at (u, v): the emissive colour, times the emissive
/// map's RGB when there is one.
#[inline(always)]
pub fn emission<V: Vector>(terms: &MaterialTerms, u: V::L, v: V::L) -> V {
    match &terms.emissive_map {
        Some(map) => {
            let [r, g, b] = V::L::bilinear(map, u, v);
            V::uniform(terms.emissive) * V::new(r, g, b)
        }
        None => V::uniform(terms.emissive),
    }
}

/// The colour of the point(s) `p` of shading normal `n`, where the maps
/// read `at` (each its own coordinate, `shade::map_uv`), before quantising: `albedo × light` plus, when
/// `SPEC`, the `highlight`; with the plan's material terms and environment.
/// `live` has a bit per covered lane (1 for one pixel).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub fn compose<V: Vector, const SPEC: bool>(
    plan: &Plan,
    p: V,
    n: V,
    at: Coords<V::L>,
    albedo: V,
    light: V,
    highlight: V,
    live: u32,
    counters: &mut Counters,
) -> V {
    let Some(terms) = plan.terms.as_deref() else {
        let lit = if SPEC {
            albedo * light + highlight
        } else {
            albedo * light
        };
        return mirror(plan, p, n, lit, live, counters);
    };
    let (u, v) = at.of(&terms.uvs.occlusion);
    let light = occlude(terms, plan.ambient, u, v, light);
    let lit = if SPEC {
        albedo * light + highlight * V::uniform(terms.specular_color)
    } else {
        albedo * light
    };
    let (u, v) = at.of(&terms.uvs.emissive);
    mirror(plan, p, n, lit, live, counters) + emission(terms, u, v)
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use super::*;
    use relief_texture::Level;

    #[test]
    fn occlusion_strength_scales_the_ambient_part_only() {
        // A map of red 0.25: strength 1 keeps a quarter of the ambient,
        // strength 0.5 keeps 1 + 0.5·(0.25 − 1) = 0.625 of it.
        let map = Arc::new(Level::solid(1, 1, [0.25, 0.0, 0.0, 0.0]));
        let ambient = Vec3::splat(0.2);
        let light = Vec3::splat(0.2 + 0.5);
        for (strength, kept) in [(1.0, 0.05), (0.5, 0.125)] {
            let terms = MaterialTerms {
                occlusion: Some((map.clone(), strength)),
                ..Default::default()
            };
            let lit = occlude(&terms, ambient, 0.3f32, 0.7f32, light);
            assert!((lit - Vec3::splat(kept + 0.5)).abs().max_element() < 1e-6);
        }
    }

    #[test]
    fn emission_is_the_factor_times_the_map() {
        let terms = MaterialTerms {
            emissive: Vec3::new(0.5, 1.0, 2.0),
            emissive_map: Some(Arc::new(Level::solid(1, 1, [0.5, 0.25, 0.125, 1.0]))),
            ..Default::default()
        };
        let e: Vec3 = emission(&terms, 0.3f32, 0.7f32);
        assert!((e - Vec3::new(0.25, 0.25, 0.25)).abs().max_element() < 1e-6);
    }
}
