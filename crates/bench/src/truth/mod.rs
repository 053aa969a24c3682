//! The bench's ground truth: a ray caster in f64 written apart from the
//! renderer (no shading, raster or texture-sampling code of relief is
//! called), so that what the renderer gets wrong can show.
//!
//! Per pixel, `n × n` rays through jittered points of a stratified grid;
//! each ray is turned into object space and hit against every triangle of
//! the scene's meshes (brute force: the cube has twelve). At the hit, the
//! perspective-exact barycentrics interpolate the vertex normal, colour,
//! texture coordinates and tangents; the texture's base level is read
//! bilinearly (its continuous form); each technique's normal or cosine,
//! the lights, highlight, shadow rays and mirror reflection follow the
//! formulas of docs/ (`shade`). Each ray's colour is clamped to 0..1 as a
//! display would and the rays are averaged: the pixel integrates the texels
//! (and reflections) its area covers, read from the finest level, which is
//! what an ideal filter computes.
//!
//! What it draws is the ideal picture of a renderer setting (`Setting::of`).

pub mod geometry;
pub mod physical;
pub mod read;
pub mod setting;
pub mod shade;

use glam::DVec3;
use rayon::prelude::*;

use geometry::World;
use physical::Directions;
use relief_core::framebuffer::Framebuffer;
use relief_core::settings::Settings;
use relief_scene::Scene;
pub use setting::{Bump, Setting};

/// What the truth draws besides the scene: the model's rotation and the setting.
#[derive(Clone, Debug)]
pub struct View {
    /// Model rotation in degrees (X, then Y, then Z).
    pub rotation: glam::Vec3,
    pub setting: Setting,
}

impl View {
    /// The ideal picture of `settings` on `scene` (its rotation included).
    pub fn of(settings: &Settings, scene: &Scene) -> View {
        View {
            rotation: settings.rotation,
            setting: Setting::of(settings, scene),
        }
    }
}

/// The picture at `width × height` with `n × n` rays per pixel.
pub fn render(scene: &Scene, view: &View, width: usize, height: usize, n: usize) -> Framebuffer {
    let linear = render_linear(scene, view, width, height, n);
    let mut fb = Framebuffer::new(width, height);
    for (i, c) in linear.iter().enumerate() {
        fb.set(i % width, i / width, to_u8(*c));
    }
    fb
}

/// The mean clamped colour of each pixel, row by row, unrounded.
pub fn render_linear(
    scene: &Scene,
    view: &View,
    width: usize,
    height: usize,
    n: usize,
) -> Vec<DVec3> {
    let world = World::new(scene, view.rotation, width, height);
    let ctx = shade::Context::new(scene, &world, &view.setting);
    let background = DVec3::new(
        scene.background[0] as f64,
        scene.background[1] as f64,
        scene.background[2] as f64,
    ) / 255.0;
    let n = n.max(1);
    let physical = view.setting.physical.is_some();
    (0..width * height)
        .into_par_iter()
        .map(|i| {
            let (px, py) = (i % width, i / width);
            let order = physical.then(|| physical::PixelOrder::of(px, py, n));
            let mut sum = DVec3::ZERO;
            for sy in 0..n {
                for sx in 0..n {
                    let (jx, jy) = jitter(px, py, sx, sy);
                    let x = px as f64 + (sx as f64 + jx) / n as f64;
                    let y = py as f64 + (sy as f64 + jy) / n as f64;
                    sum += match world.camera_hit(x, y) {
                        (ray, Some(hit)) => {
                            let directions = match &order {
                                Some(o) => Directions::of(px, py, n, sy * n + sx, o),
                                None => Directions::alone(px, py, 1),
                            };
                            shade::shade(&ctx, &ray, &hit, &directions)
                                .clamp(DVec3::ZERO, DVec3::ONE)
                        }
                        (_, None) => background,
                    };
                }
            }
            sum / (n * n) as f64
        })
        .collect()
}

/// The clamped colour the ray through each pixel's centre sees, row by row
/// (`None` where it meets nothing): the truth sampled where a rasterizer
/// without anti-aliasing samples, for tests that compare point with point.
pub fn render_centres(
    scene: &Scene,
    view: &View,
    width: usize,
    height: usize,
) -> Vec<Option<DVec3>> {
    let world = World::new(scene, view.rotation, width, height);
    let ctx = shade::Context::new(scene, &world, &view.setting);
    (0..width * height)
        .into_par_iter()
        .map(|i| {
            let (px, py) = (i % width, i / width);
            let (ray, hit) = world.camera_hit(px as f64 + 0.5, py as f64 + 0.5);
            let directions = Directions::alone(px, py, CENTRE_SAMPLES_PER_AXIS);
            hit.map(|hit| {
                shade::shade(&ctx, &ray, &hit, &directions).clamp(DVec3::ZERO, DVec3::ONE)
            })
        })
        .collect()
}

/// Environment samples per lobe of a ray through a pixel's centre, per
/// axis: 32² = 1,024, as many as a pixel of 16 × 16 rays takes.
const CENTRE_SAMPLES_PER_AXIS: usize = 32;

/// A point in [0, 1)² for sub-pixel cell (sx, sy) of pixel (px, py): a
/// fixed hash, so the truth is the same on every run.
fn jitter(px: usize, py: usize, sx: usize, sy: usize) -> (f64, f64) {
    let mut h = (px as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)
        ^ (py as u64).wrapping_mul(0xC2B2_AE3D_27D4_EB4F)
        ^ ((sx as u64) << 32 | sy as u64).wrapping_mul(0x1656_67B1_9E37_79F9);
    let mut next = || {
        h ^= h >> 33;
        h = h.wrapping_mul(0xFF51_AFD7_ED55_8CCD);
        h ^= h >> 33;
        (h >> 11) as f64 / (1u64 << 53) as f64
    };
    (next(), next())
}

/// 0..1 to 8 bits, rounded.
fn to_u8(c: DVec3) -> [u8; 3] {
    let q = |x: f64| (x.clamp(0.0, 1.0) * 255.0).round() as u8;
    [q(c.x), q(c.y), q(c.z)]
}

/// RMS difference in 8-bit units between two unrounded pictures of equal size.
pub fn rms(a: &[DVec3], b: &[DVec3]) -> f64 {
    let sum: f64 = a
        .iter()
        .zip(b)
        .map(|(a, b)| ((*a - *b) * 255.0).length_squared())
        .sum();
    (sum / (3 * a.len().max(1)) as f64).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{config, reference};
    use relief_texture::Level;

    fn scene() -> Scene {
        Scene::cube(reference::texture().0, true)
    }

    fn view() -> View {
        View::of(&config::reference_setting(), &scene())
    }

    /// The truth's own error: against 24×24 rays, the error falls as the
    /// rays grow, and at the 16×16 the full bench casts it is far below the
    /// smallest error the table reports (≈ 4 in RMS, 33 dB and up).
    #[test]
    fn the_truth_converges_as_its_rays_grow() {
        let (w, h) = (80, 60);
        let s = scene();
        let best = render_linear(&s, &view(), w, h, 24);
        let errors: Vec<f64> = [2, 4, 8, 16]
            .iter()
            .map(|&n| rms(&render_linear(&s, &view(), w, h, n), &best))
            .collect();
        eprintln!("truth RMS error against 24x24 rays at 2, 4, 8, 16 rays per axis: {errors:?}");
        assert!(errors.windows(2).all(|e| e[1] < e[0]), "{errors:?}");
        // Stratified sampling of a pixel's edges converges at least as n^-1.5
        // per axis (n^-3 in variance): 2 → 16 divides the error by ≥ 8·√8/2.
        assert!(errors[3] < errors[0] / 10.0, "{errors:?}");
        assert!(errors[3] < 0.5, "{errors:?}");
    }

    /// The truths of the techniques' own settings, by name.
    fn technique_settings() -> Vec<(&'static str, relief_core::settings::Settings, Scene)> {
        use relief_core::settings::{Settings, Technique};
        let r = config::reference_setting();
        let s = scene();
        let mut non_convex = scene();
        for o in &mut non_convex.objects {
            o.mesh.convex = false;
        }
        let t = |technique| Settings { technique, ..r };
        vec![
            ("emboss", t(Technique::Emboss), s.clone()),
            ("dot3", t(Technique::Dot3), s.clone()),
            ("relief", t(Technique::Pom), s.clone()),
            (
                "specular",
                Settings {
                    specular: true,
                    ..r
                },
                s.clone(),
            ),
            (
                "environment",
                Settings {
                    environment: true,
                    ..r
                },
                s.clone(),
            ),
            ("shadows", r, non_convex),
        ]
    }

    /// Each technique's truth converges like the reference setting's: at
    /// 48×36 against 16×16 rays, 8×8 rays are closer than 4×4, and 4× the
    /// rays per axis (2 → 8) divide the error by at least 4 (stratified
    /// sampling: n^-1 per axis for a pixel's edges, faster inside smooth
    /// shading). The RMS at 8×8 stays under 1.5 levels although a 48×36
    /// pixel is 6.7 times wider than the bench's and holds that much more
    /// edge, texture and highlight detail (the bench's `truth dB` column
    /// measures its own size and rays).
    #[test]
    fn every_techniques_truth_converges_as_its_rays_grow() {
        let (w, h) = (48, 36);
        for (name, settings, scene) in technique_settings() {
            let view = View::of(&settings, &scene);
            let best = render_linear(&scene, &view, w, h, 16);
            let e: Vec<f64> = [2, 4, 8]
                .iter()
                .map(|&n| rms(&render_linear(&scene, &view, w, h, n), &best))
                .collect();
            eprintln!("{name}: RMS against 16x16 rays at 2, 4, 8 rays per axis: {e:?}");
            assert!(e[2] < e[1] && e[1] < e[0], "{name}: {e:?}");
            assert!(e[2] < e[0] / 4.0 && e[2] < 1.5, "{name}: {e:?}");
        }
    }

    /// Each technique's truth differs from Blinn's reference truth (the
    /// setting reaches the picture) but not wildly: the same cube, texture
    /// and lights, so most pixels stay within a few levels.
    #[test]
    fn each_technique_draws_its_own_truth() {
        let (w, h) = (48, 36);
        let reference = render_linear(&scene(), &view(), w, h, 2);
        for (name, settings, scene) in technique_settings() {
            let own = render_linear(&scene, &View::of(&settings, &scene), w, h, 2);
            let d = rms(&own, &reference);
            eprintln!("{name}: RMS against Blinn's truth {d:.2}");
            assert!(d > 0.1 && d < 40.0, "{name}: {d}");
        }
    }

    /// A shadow ray from the back face toward a light in front of the cube
    /// crosses the cube; from the front face it does not; the face a
    /// point lies on does not shadow it.
    #[test]
    fn shadow_rays_meet_the_cube_between_point_and_light() {
        let world = geometry::World::new(&scene(), glam::Vec3::ZERO, 32, 24);
        let light = DVec3::new(0.0, 0.0, 10.0);
        assert!(world.occluded(DVec3::new(0.2, 0.3, -1.0), light));
        assert!(!world.occluded(DVec3::new(0.2, 0.3, 1.0), light));
        assert!(!world.occluded(DVec3::new(1.0, 0.3, 0.2), DVec3::new(10.0, 0.0, 0.0)));
    }

    /// The carved relief with a constant height F = 1/2 sits at depth D/2
    /// = k·|P_u × P_v|/2 below the face: a ray through the front face
    /// (turned 0°) moves its texture coordinate by the tangent part of its
    /// direction over depth D/2, divided by |P_u| = |P_v| = 2.
    #[test]
    fn the_relief_of_a_constant_height_is_met_at_its_depth() {
        let level = Level {
            wrap: Default::default(),
            width: 4,
            height: 4,
            texels: vec![[0.5, 0.5, 0.5, 0.5]; 16].into(),
        };
        let s = Scene::cube(
            std::sync::Arc::new(relief_texture::Texture::new("c", level)),
            true,
        );
        let world = geometry::World::new(&s, glam::Vec3::ZERO, 64, 48);
        let ray = world.ray(40.0, 20.0);
        let hit = world.hit(&ray).unwrap();
        let k = 0.006;
        let got = shade::relief(s.material.texture.base(), &ray, &hit, k);
        let d = ray.dir.normalize();
        // Met at depth D/2 = k·4/2; per unit depth the ray moves d.xy/(−d.z)
        // in the face's plane, i.e. half that in texture coordinates.
        let met = k * 4.0 / 2.0;
        let want = hit.uv + glam::DVec2::new(d.x, d.y) / (-d.z) * met / 2.0;
        assert!((got - want).length() < 1e-9, "{got} {want}");
        assert!((got - hit.uv).length() > 1e-4);
    }

    /// The renderer's most accurate frame (anisotropic, 4×4 supersampled)
    /// against the truth: the same integral, so they agree to within what
    /// the mip filter's averaging of heights and f32 change.
    #[test]
    fn the_renderers_supersampled_frame_agrees_with_the_truth() {
        let (w, h) = (80, 60);
        let s = scene();
        let truth = render(&s, &view(), w, h, 8);
        let frame = reference::render(&s, view().rotation, w, h, 4);
        let mut squared = crate::metrics::SquaredError::default();
        squared.add(frame.pixels(), truth.pixels());
        let psnr = squared.psnr();
        let max = crate::metrics::max_channel_error(frame.pixels(), truth.pixels());
        eprintln!("supersampled renderer against truth at 80x60: {psnr:.2} dB, max {max}");
        assert!(psnr > 35.0, "{psnr} dB, max {max}");
    }

    /// A constant texture, no bump, the front face head on: each pixel of
    /// the face's middle is albedo × (ambient + Σ colour·max(0, N·L)) worked
    /// out here from the corner colours and normals of the cube.
    #[test]
    fn a_plain_face_head_on_is_the_lighting_formula() {
        let level = Level {
            wrap: Default::default(),
            width: 4,
            height: 4,
            texels: vec![[0.8, 0.6, 0.4, 0.5]; 16].into(),
        };
        let s = Scene::cube(
            std::sync::Arc::new(relief_texture::Texture::new("c", level)),
            true,
        );
        let v = View {
            rotation: glam::Vec3::ZERO,
            setting: Setting {
                bump: Bump::None,
                ..Setting::reference(0.0)
            },
        };
        let (w, h) = (64, 48);
        let world = geometry::World::new(&s, v.rotation, w, h);
        // The centre pixel: the ray hits (0, 0, 1), normal +Z (the four
        // averaged corner normals of the face sum along +Z), colour the
        // mean of the four corners 0.4 + 0.3·(p + 1) = 0.7 in R, G and 1.0 in B.
        let hit = world.hit(&world.ray(32.0, 24.0)).unwrap();
        assert!((hit.position - DVec3::new(0.0, 0.0, 1.0)).length() < 1e-9);
        let p = DVec3::new(0.0, 0.0, 1.0);
        let mut light = DVec3::splat(0.1);
        for (pos, col) in [
            (DVec3::new(3.0, 4.0, 6.0), DVec3::ONE),
            (DVec3::new(-8.0, 1.0, 3.0), DVec3::new(0.3, 0.0, 0.0)),
            (DVec3::new(8.0, -2.0, 3.0), DVec3::new(0.0, 0.3, 0.0)),
            (DVec3::new(0.0, -8.0, 2.0), DVec3::new(0.0, 0.0, 0.3)),
        ] {
            let d = pos - p;
            light += col * (d.z / d.length()).max(0.0);
        }
        let want = DVec3::new(0.7 * 0.8, 0.7 * 0.6, 1.0 * 0.4) * light;
        let ctx = shade::Context::new(&s, &world, &v.setting);
        let got = shade::shade(
            &ctx,
            &world.ray(32.0, 24.0),
            &hit,
            &Directions::alone(32, 24, 1),
        );
        // The scene holds its lights in f32 (0.3 is not exact there).
        assert!((got - want).length() < 1e-6, "{got} {want}");
    }

    /// A camera ray meets the same triangle through its tile's list as
    /// through a search of every triangle (the cube and the physical
    /// bench's sphere, framed by the model view, at several rotations).
    #[test]
    fn tiles_find_what_a_full_search_finds() {
        for scene in [scene(), crate::physical::scene()] {
            for rotation in crate::config::orientations(3, crate::config::SEED) {
                let world = geometry::World::new(&scene, rotation, 37, 23);
                for i in 0..37 * 23 {
                    let (x, y) = ((i % 37) as f64 + 0.31, (i / 37) as f64 + 0.77);
                    let (ray, tiled) = world.camera_hit(x, y);
                    let full = world.hit(&ray);
                    assert_eq!(tiled.map(|h| h.t), full.map(|h| h.t), "({x}, {y})");
                }
            }
        }
    }

    /// The physical truth's own error: against 12×12 rays (and 24² cosine
    /// and GGX directions per lobe), its error falls as rays and directions
    /// grow together.
    #[test]
    fn the_physical_truth_converges_as_its_rays_grow() {
        let s = crate::physical::scene();
        let v = View::of(&relief_core::settings::Settings::default(), &s);
        assert!(v.setting.physical.is_some());
        let (w, h) = (40, 30);
        let best = render_linear(&s, &v, w, h, 12);
        let e: Vec<f64> = [2, 4, 8]
            .iter()
            .map(|&n| rms(&render_linear(&s, &v, w, h, n), &best))
            .collect();
        eprintln!("physical truth: RMS against 12x12 rays at 2, 4, 8 rays per axis: {e:?}");
        assert!(e[2] < e[1] && e[1] < e[0], "{e:?}");
        assert!(e[2] < e[0] / 3.0 && e[2] < 1.5, "{e:?}");
    }

    /// The renderer's metallic-roughness frame, 4×4 supersampled, against
    /// the physical truth: written apart, they agree to within what the
    /// spherical harmonics, the prefiltered levels and the split sum
    /// approximate.
    #[test]
    fn the_renderers_physical_frame_agrees_with_the_physical_truth() {
        let (w, h) = (80, 60);
        let s = crate::physical::scene();
        let settings = relief_core::settings::Settings::default();
        for rotation in crate::config::orientations(2, crate::config::SEED) {
            let v = View::of(
                &relief_core::settings::Settings {
                    rotation,
                    ..settings
                },
                &s,
            );
            let truth = render(&s, &v, w, h, 6);
            let frame = reference::render(&s, rotation, w, h, 4);
            let mut squared = crate::metrics::SquaredError::default();
            squared.add(frame.pixels(), truth.pixels());
            let psnr = squared.psnr();
            let max = crate::metrics::max_channel_error(frame.pixels(), truth.pixels());
            eprintln!("physical frame against truth at {rotation}: {psnr:.2} dB, max {max}");
            assert!(psnr > 30.0, "{psnr} dB, max {max}");
        }
    }
}
