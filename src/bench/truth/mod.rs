//! The bench's ground truth: a ray caster in f64 written apart from the
//! renderer (no shading, raster or texture-sampling code of relief is
//! called), so that what the renderer gets wrong can show.
//!
//! Per pixel, `n × n` rays through jittered points of a stratified grid;
//! each ray is turned into object space and hit against every triangle of
//! the scene's meshes (brute force: the cube has twelve). At the hit, from
//! the formulas of docs/shading.md and docs/bump-blinn.md: the
//! perspective-exact barycentrics, the interpolated vertex normal, colour,
//! texture coordinates and tangents; the base level of the texture read
//! bilinearly (the texture's continuous form), Blinn's perturbed normal from
//! central differences one texel apart on that form; ambient plus each
//! light's colour times max(0, N·L) clamped to 1. Each ray's colour is
//! clamped to 0..1 as a display would and the rays are averaged: the pixel
//! integrates the texels its area covers, read from the finest level, which
//! is what an ideal minification filter computes.
//!
//! What it draws is the bench's reference setting: Phong, vertex normals,
//! texture, Blinn bump, no highlights, no environment, no shadows.

pub mod geometry;

use glam::DVec3;
use rayon::prelude::*;

use crate::framebuffer::Framebuffer;
use crate::scene::Scene;
use crate::texture::Level;
use geometry::{Hit, World};

/// What the truth draws besides the scene: the model's rotation and the bump strength.
#[derive(Clone, Copy, Debug)]
pub struct View {
    /// Model rotation in degrees (X, then Y, then Z).
    pub rotation: glam::Vec3,
    /// Blinn's k (0: no bump).
    pub bump_strength: f64,
}

/// The picture at `width × height` with `n × n` rays per pixel.
pub fn render(scene: &Scene, view: View, width: usize, height: usize, n: usize) -> Framebuffer {
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
    view: View,
    width: usize,
    height: usize,
    n: usize,
) -> Vec<DVec3> {
    let world = World::new(scene, view.rotation, width, height);
    let base = scene.material.texture.base();
    let background = DVec3::new(
        scene.background[0] as f64,
        scene.background[1] as f64,
        scene.background[2] as f64,
    ) / 255.0;
    let n = n.max(1);
    (0..width * height)
        .into_par_iter()
        .map(|i| {
            let (px, py) = (i % width, i / width);
            let mut sum = DVec3::ZERO;
            for sy in 0..n {
                for sx in 0..n {
                    let (jx, jy) = jitter(px, py, sx, sy);
                    let x = px as f64 + (sx as f64 + jx) / n as f64;
                    let y = py as f64 + (sy as f64 + jy) / n as f64;
                    let ray = world.ray(x, y);
                    sum += match world.hit(&ray) {
                        Some(hit) => {
                            shade(scene, &world, base, view, &hit).clamp(DVec3::ZERO, DVec3::ONE)
                        }
                        None => background,
                    };
                }
            }
            sum / (n * n) as f64
        })
        .collect()
}

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

/// The texture's continuous form at (u, v): bilinear between texel
/// centres, repeating; texel (0, 0) is the first stored, v grows by rows.
pub fn bilinear(level: &Level, u: f64, v: f64) -> [f64; 4] {
    let (w, h) = (level.width as i64, level.height as i64);
    let x = (u - u.floor()) * w as f64 - 0.5;
    let y = (v - v.floor()) * h as f64 - 0.5;
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = (x - x0, y - y0);
    let at = |i: i64, j: i64| {
        level
            .texels
            .at((j.rem_euclid(h) * w + i.rem_euclid(w)) as usize)
    };
    let (i, j) = (x0 as i64, y0 as i64);
    let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i, j + 1), at(i + 1, j + 1));
    std::array::from_fn(|k| {
        let (a, b, c, d) = (a[k] as f64, b[k] as f64, c[k] as f64, d[k] as f64);
        (a * (1.0 - fx) + b * fx) * (1.0 - fy) + (c * (1.0 - fx) + d * fx) * fy
    })
}

/// The colour a ray sees at `hit`, before clamping.
fn shade(scene: &Scene, world: &World, base: &Level, view: View, hit: &Hit) -> DVec3 {
    let mut n = hit.normal.normalize();
    let mut albedo = hit.color;
    if hit.textured {
        let t = bilinear(base, hit.uv.x, hit.uv.y);
        albedo *= DVec3::new(t[0], t[1], t[2]);
        if view.bump_strength != 0.0 {
            // Blinn: N' = normalise(N + k (F_u (N × P_v) − F_v (N × P_u))),
            // F_u, F_v central differences one texel apart; k changes sign
            // where (P_u × P_v)·N < 0 (a mirrored frame).
            let (du, dv) = (1.0 / base.width as f64, 1.0 / base.height as f64);
            let height = |u: f64, v: f64| bilinear(base, u, v)[3];
            let (u, v) = (hit.uv.x, hit.uv.y);
            let fu = (height(u + du, v) - height(u - du, v)) / (2.0 * du);
            let fv = (height(u, v + dv) - height(u, v - dv)) / (2.0 * dv);
            let (pu, pv) = (hit.tangent_u, hit.tangent_v);
            let k = if pu.cross(pv).dot(n) < 0.0 {
                -view.bump_strength
            } else {
                view.bump_strength
            };
            let p = n + k * (fu * n.cross(pv) - fv * n.cross(pu));
            if p.length_squared() > 1e-40 {
                n = p.normalize();
            }
        }
    }
    let mut light = scene.ambient.as_dvec3();
    for l in scene.lights.iter().filter(|l| l.enabled) {
        let d = l.position.as_dvec3() - hit.position;
        let len = d.length();
        if len > 0.0 {
            light += l.color.as_dvec3() * (n.dot(d) / len).clamp(0.0, 1.0);
        }
    }
    let _ = world;
    albedo * light
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bench::{config, reference};

    fn scene() -> Scene {
        Scene::cube(reference::texture().0, true)
    }

    fn view() -> View {
        View {
            rotation: config::reference_setting().rotation,
            bump_strength: config::reference_setting().bump_strength as f64,
        }
    }

    /// RMS difference in 8-bit units between two unrounded pictures.
    fn rms(a: &[DVec3], b: &[DVec3]) -> f64 {
        let sum: f64 = a
            .iter()
            .zip(b)
            .map(|(a, b)| ((*a - *b) * 255.0).length_squared())
            .sum();
        (sum / (3 * a.len()) as f64).sqrt()
    }

    /// The truth's own error: against 24×24 rays, the error falls as the
    /// rays grow, and at the 16×16 the full bench casts it is far below the
    /// smallest error the table reports (≈ 4 in RMS, 33 dB and up).
    #[test]
    fn the_truth_converges_as_its_rays_grow() {
        let (w, h) = (80, 60);
        let s = scene();
        let best = render_linear(&s, view(), w, h, 24);
        let errors: Vec<f64> = [2, 4, 8, 16]
            .iter()
            .map(|&n| rms(&render_linear(&s, view(), w, h, n), &best))
            .collect();
        eprintln!("truth RMS error against 24x24 rays at 2, 4, 8, 16 rays per axis: {errors:?}");
        assert!(errors.windows(2).all(|e| e[1] < e[0]), "{errors:?}");
        // Stratified sampling of a pixel's edges converges at least as n^-1.5
        // per axis (n^-3 in variance): 2 → 16 divides the error by ≥ 8·√8/2.
        assert!(errors[3] < errors[0] / 10.0, "{errors:?}");
        assert!(errors[3] < 0.5, "{errors:?}");
    }

    /// The renderer's most accurate frame (anisotropic, 4×4 supersampled)
    /// against the truth: the same integral, so they agree to within what
    /// the mip filter's averaging of heights and f32 change.
    #[test]
    fn the_renderers_supersampled_frame_agrees_with_the_truth() {
        let (w, h) = (80, 60);
        let s = scene();
        let truth = render(&s, view(), w, h, 8);
        let frame = reference::render(&s, view().rotation, w, h, 4);
        let mut squared = crate::bench::metrics::SquaredError::default();
        squared.add(frame.pixels(), truth.pixels());
        let psnr = squared.psnr();
        let max = crate::bench::metrics::max_channel_error(frame.pixels(), truth.pixels());
        eprintln!("supersampled renderer against truth at 80x60: {psnr:.2} dB, max {max}");
        assert!(psnr > 35.0, "{psnr} dB, max {max}");
    }

    /// A constant texture, no bump, the front face head on: each pixel of
    /// the face's middle is albedo × (ambient + Σ colour·max(0, N·L)) worked
    /// out here from the corner colours and normals of the cube.
    #[test]
    fn a_plain_face_head_on_is_the_lighting_formula() {
        let level = Level {
            width: 4,
            height: 4,
            texels: vec![[0.8, 0.6, 0.4, 0.5]; 16].into(),
        };
        let s = Scene::cube(
            std::sync::Arc::new(crate::texture::Texture::new("c", level)),
            true,
        );
        let v = View {
            rotation: glam::Vec3::ZERO,
            bump_strength: 0.0,
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
        let got = shade(&s, &world, s.material.texture.base(), v, &hit);
        // The scene holds its lights in f32 (0.3 is not exact there).
        assert!((got - want).length() < 1e-6, "{got} {want}");
    }
}
