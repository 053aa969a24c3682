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
use relief_core::settings::{AntiAlias, Settings, ToneMap};
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
        row(
            "aa=4x4",
            Settings {
                aa: AntiAlias::Ssaa4,
                ..r
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
