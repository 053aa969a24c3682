//! `relief bench --physical`: what the model view's physically based
//! shading costs, and how far each of its approximations stands from the
//! physical truth (`truth::physical`, the environment integrated by Monte
//! Carlo).
//!
//! The scene is a model as a file would bring it: a sphere of one
//! metallic-roughness material in the model view (framed, the neutral rig,
//! the built-in studio environment). Its metallic-roughness map makes the
//! sphere metal in the north and a dielectric in the south, and its
//! roughness run from 0.05 to 0.95 and back twice around, so the eight
//! orientations show mirror-like and rough metal, glossy and matte paint.

use std::sync::Arc;

use glam::Vec3;

use super::config::{Config, SceneVariant, Threads};
use super::runner::Plan;
use relief_core::settings::{AntiAlias, IblDiffuse, IblSpecular, Settings, ToneMap};
use relief_scene::Scene;
use relief_scene::terms::{MaterialTerms, PbrMaterial};
use relief_texture::{Level, Texture};

/// The sphere's base colour (linear): a warm gold, so metal and paint
/// differ in hue as well as in shine.
pub const BASE: Vec3 = Vec3::new(1.0, 0.71, 0.29);
/// Size of the metallic-roughness map.
const MAP_SIZE: (usize, usize) = (128, 64);

/// Roughness at longitude `u` (0..1 around): 0.05 to 0.95 and back twice.
pub fn roughness_at(u: f64) -> f64 {
    0.5 - 0.45 * (4.0 * std::f64::consts::PI * u).cos()
}

/// Metallic at `v` (0 at the top of the map, the north pole): 1 in the
/// northern half, 0 in the southern, over a soft band at the equator.
pub fn metallic_at(v: f64) -> f64 {
    let t = ((0.55 - v) / 0.1).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// The metallic-roughness map, glTF's layout: roughness in green,
/// metallic in blue.
fn metal_rough_map() -> Level {
    let (w, h) = MAP_SIZE;
    let mut rgba = Vec::with_capacity(w * h * 4);
    for y in 0..h {
        for x in 0..w {
            let u = (x as f64 + 0.5) / w as f64;
            let v = (y as f64 + 0.5) / h as f64;
            let byte = |f: f64| (f.clamp(0.0, 1.0) * 255.0).round() as u8;
            rgba.extend([0, byte(roughness_at(u)), byte(metallic_at(v)), 255]);
        }
    }
    Level::from_rgba8_top_down(w, h, &rgba)
}

/// The bench's physical scene.
pub fn scene() -> Scene {
    let mut mesh = relief_scene::sphere::sphere();
    for v in &mut mesh.vertices {
        v.color = BASE;
    }
    let white = Level::from_rgba8_top_down(1, 1, &[255, 255, 255, 255]);
    let mut scene = Scene::model(mesh, Arc::new(Texture::new("white", white)));
    let map = Arc::new(metal_rough_map());
    let terms = MaterialTerms {
        pbr: Some(PbrMaterial {
            metallic: 1.0,
            roughness: 1.0,
            roughness_map: Some((map.clone(), 1)),
            metallic_map: Some((map, 2)),
            ..PbrMaterial::gltf_default()
        }),
        ..MaterialTerms::default()
    };
    scene.object_terms = vec![Some(Arc::new(terms))];
    scene.into_model_view()
}

/// The rows of `relief bench --physical`.
pub fn rows() -> Vec<Config> {
    let r = Settings::default();
    // The environment's light without either approximation.
    let exact = Settings {
        ibl_diffuse: IblDiffuse::Integrated,
        ibl_specular: IblSpecular::Sampled,
        ..r
    };
    let row = |name: &str, settings: Settings| Config::new(name, settings, Threads::All);
    vec![
        row("metallic-roughness", r),
        Config::new("metallic-roughness, 1 thread", r, Threads::One),
        Config {
            variant: SceneVariant::BlinnPhong,
            ..row(
                "Blinn-Phong materials",
                Settings {
                    specular: true,
                    ..r
                },
            )
        },
        row(
            "ibl-diffuse=integrated",
            Settings {
                ibl_diffuse: IblDiffuse::Integrated,
                ..r
            },
        ),
        row(
            "ibl-specular=sampled",
            Settings {
                ibl_specular: IblSpecular::Sampled,
                ..r
            },
        ),
        row("ibl-diffuse=integrated, ibl-specular=sampled", exact),
        Config {
            variant: SceneVariant::NoEnvironment,
            ..row("lights only (no environment)", r)
        },
        row(
            "tone-map=aces",
            Settings {
                tone_map: ToneMap::Aces,
                ..r
            },
        ),
        row(
            "tone-map=none",
            Settings {
                tone_map: ToneMap::None,
                ..r
            },
        ),
        Config {
            variant: SceneVariant::Skinned,
            ..row("skinned, a new pose each frame", r)
        },
        row(
            "aa=4x4",
            Settings {
                aa: AntiAlias::Ssaa4,
                ..r
            },
        ),
        row(
            "aa=4x4, ibl-diffuse=integrated, ibl-specular=sampled",
            Settings {
                aa: AntiAlias::Ssaa4,
                ..exact
            },
        ),
    ]
}

/// The rows of a `--quick` run.
pub fn quick_rows() -> Vec<Config> {
    rows().into_iter().take(2).collect()
}

/// `plan` with the physical rows, fewer orientations and the truth's rays.
pub fn plan(mut plan: Plan, quick: bool) -> Plan {
    plan.configs = if quick { quick_rows() } else { rows() };
    plan.orientations = super::config::orientations(if quick { 1 } else { 4 }, super::config::SEED);
    plan.truth_rays = if quick { 4 } else { 16 };
    plan
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The map holds what its functions say: roughness 0.05 and 0.95 at
    /// u = 0 and ¼, metal in the north (v = 0 at the top), paint in the south.
    #[test]
    fn the_map_runs_from_smooth_to_rough_and_from_metal_to_paint() {
        assert!((roughness_at(0.0) - 0.05).abs() < 1e-12);
        assert!((roughness_at(0.25) - 0.95).abs() < 1e-12);
        assert_eq!(metallic_at(0.1), 1.0);
        assert_eq!(metallic_at(0.9), 0.0);
        let map = metal_rough_map();
        let texel = |x: usize, y: usize| map.texels.at(y * map.width + x);
        assert!((texel(0, 0)[1] - 0.05).abs() < 0.01 && texel(0, 0)[2] == 1.0);
        assert!((texel(32, 63)[1] - 0.95).abs() < 0.01 && texel(32, 63)[2] == 0.0);
    }

    /// The skinned sphere (`crate::skinned`) shows its rest pose at the clip's start; at its
    /// end the north pole has turned `BEND_DEGREES` about Z and the south
    /// pole has not moved.
    #[test]
    fn the_skinned_sphere_rests_then_bends_its_upper_half() {
        use crate::skinned::{BEND_DEGREES, BEND_SECONDS, skinned};
        let plain = scene();
        let mut skinned = skinned(&plain);
        let before = &plain.objects[0].mesh.vertices;
        for (a, b) in before.iter().zip(&skinned.objects[0].mesh.vertices) {
            assert!((a.position - b.position).length() < 1e-6);
        }
        let motion = skinned.motion.as_mut().unwrap();
        motion.show(&mut skinned.objects, Some(0), BEND_SECONDS);
        let after = &skinned.objects[0].mesh.vertices;
        let north = before.iter().position(|v| v.position.y > 0.999).unwrap();
        let south = before.iter().position(|v| v.position.y < -0.999).unwrap();
        let a = BEND_DEGREES.to_radians();
        let want = Vec3::new(-a.sin(), a.cos(), 0.0) * before[north].position.length();
        assert!(
            (after[north].position - want).length() < 1e-3,
            "{}",
            after[north].position
        );
        assert!((after[south].position - before[south].position).length() < 1e-6);
    }
}
