//! Blinn-Phong highlights against numbers worked out by hand in f64
//! (docs/specular.md): a white plane z = 0 facing the reference camera at
//! (0, 0, 5), one grey light, no ambient. The highlight is the difference
//! between the frame with specular on and the frame with it off.

use crate::common;

use std::sync::Arc;

use glam::Vec3;
use relief_core::framebuffer::Framebuffer;
use relief_core::settings::Settings;
use relief_core::settings::Shading;
use relief_core::stats::FrameStats;
use relief_pipeline::render::render_frame;
use relief_scene::Scene;
use relief_scene::light::Light;
use relief_scene::plane::grid;
use relief_texture::{Level, Texture};

const W: usize = 160;
const H: usize = 120;
/// The light's grey level: diffuse + highlight stays below 1 (no clamping).
const GREY: f64 = 0.4;
const EYE: [f64; 3] = [0.0, 0.0, 5.0];

/// A 4×4 plane of side 4 (white vertices, textured with a flat white
/// texture) lit by one grey light at `light`.
fn plane_scene(light: [f64; 3]) -> Scene {
    let texture = Texture::new("white", Level::solid(4, 4, [1.0; 4]));
    let mut scene = Scene::model(grid(2.0, 1.0, 4, |_| Vec3::ONE), Arc::new(texture));
    let l = Vec3::new(light[0] as f32, light[1] as f32, light[2] as f32);
    scene.lights = vec![Light::new(l, Vec3::splat(GREY as f32))];
    scene.ambient = Vec3::ZERO;
    scene
}

fn settings(shading: Shading, specular: bool, shininess: f32) -> Settings {
    Settings {
        shading,
        texture: false,
        colors: false,
        bump: false,
        rotation: Vec3::ZERO,
        specular,
        shininess,
        ..Settings::default()
    }
}

/// The red channel of on − off at every pixel, and the frames' stats.
fn highlight(scene: &Scene, shading: Shading, s: f32) -> (Vec<i32>, FrameStats) {
    let (off, _) = render_frame(scene, &settings(shading, false, s), W, H);
    let (on, stats) = render_frame(scene, &settings(shading, true, s), W, H);
    let diff = on
        .pixels()
        .iter()
        .zip(off.pixels())
        .map(|(a, b)| a[0] as i32 - b[0] as i32)
        .collect();
    (diff, stats)
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn unit(a: [f64; 3]) -> [f64; 3] {
    let l = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
    [a[0] / l, a[1] / l, a[2] / l]
}

/// Where the ray through pixel (x, y)'s centre meets z = 0: the camera
/// looks down −Z with a 60° vertical field, rows counted from the top.
fn on_plane(x: usize, y: usize) -> [f64; 3] {
    let half_h = (30f64).to_radians().tan();
    let aspect = W as f64 / H as f64;
    let nx = 2.0 * (x as f64 + 0.5) / W as f64 - 1.0;
    let ny = 1.0 - 2.0 * (y as f64 + 0.5) / H as f64;
    // The ray from the eye reaches z = 0 after 5 units along −Z.
    [EYE[2] * nx * half_h * aspect, EYE[2] * ny * half_h, 0.0]
}

/// Where a point of z = 0 projects to, in pixels from the top left corner.
fn pixel_of_f(p: [f64; 3]) -> (f64, f64) {
    let half_h = (30f64).to_radians().tan();
    let aspect = W as f64 / H as f64;
    let nx = p[0] / (EYE[2] * half_h * aspect);
    let ny = p[1] / (EYE[2] * half_h);
    ((nx + 1.0) / 2.0 * W as f64, (1.0 - ny) / 2.0 * H as f64)
}

/// The pixel a point of z = 0 projects into.
fn pixel_of(p: [f64; 3]) -> (usize, usize) {
    let (x, y) = pixel_of_f(p);
    (x as usize, y as usize)
}

/// The mirror point on z = 0: where the light's reflection reaches the eye
/// (equal angles: the heights split the segment between their feet).
fn mirror_point(light: [f64; 3]) -> [f64; 3] {
    let t = EYE[2] / (EYE[2] + light[2]);
    [
        EYE[0] + (light[0] - EYE[0]) * t,
        EYE[1] + (light[1] - EYE[1]) * t,
        0.0,
    ]
}

/// Diffuse and highlight at a point of the plane (N = +Z), by hand.
fn lit(p: [f64; 3], light: [f64; 3], s: f64) -> (f64, f64) {
    let l = unit(sub(light, p));
    let v = unit(sub(EYE, p));
    let h = unit([l[0] + v[0], l[1] + v[1], l[2] + v[2]]);
    (GREY * l[2], GREY * h[2].max(0.0).powf(s))
}

fn q(c: f64) -> i32 {
    (c.clamp(0.0, 1.0) * 255.0 + 0.5) as i32
}

fn argmax(diff: &[i32]) -> (usize, usize, i32) {
    let (i, &v) = diff
        .iter()
        .enumerate()
        .max_by_key(|&(i, &v)| (v, std::cmp::Reverse(i)))
        .unwrap();
    (i % W, i / W, v)
}

#[test]
fn phong_highlight_matches_the_mirror_point_and_the_power_law() {
    let light = [1.5, 0.75, 2.5];
    let scene = plane_scene(light);
    for s in [8.0, 32.0, 128.0] {
        let (diff, stats) = highlight(&scene, Shading::Phong, s as f32);
        // Every pixel of the plane: quantised (diffuse + highlight) minus
        // quantised diffuse, as worked out in f64.
        let (off, _) = render_frame(&scene, &settings(Shading::Phong, false, 32.0), W, H);
        let mut covered = 0;
        for y in 0..H {
            for x in 0..W {
                if off.get(x, y) == scene.background {
                    continue;
                }
                covered += 1;
                let (d, h) = lit(on_plane(x, y), light, s);
                let want = q(d + h) - q(d);
                let got = diff[y * W + x];
                assert!(
                    (got - want).abs() <= 1,
                    "s {s} at ({x}, {y}): {got} vs {want}"
                );
            }
        }
        assert!(covered > 5000);
        // The peak: worth the light's grey (N·H = 1), at the mirror point's
        // pixel, and centred on it (the top of a wide highlight is a plateau
        // of equal 8-bit values).
        let (mx, my) = pixel_of(mirror_point(light));
        let (.., peak) = argmax(&diff);
        assert!((peak - q(GREY)).abs() <= 1, "s {s}: peak {peak}");
        assert_eq!(diff[my * W + mx], peak, "s {s}");
        let top: Vec<(usize, usize)> = (0..W * H)
            .filter(|&i| diff[i] == peak)
            .map(|i| (i % W, i / W))
            .collect();
        let n = top.len() as f64;
        let cx = top.iter().map(|p| p.0 as f64 + 0.5).sum::<f64>() / n;
        let cy = top.iter().map(|p| p.1 as f64 + 0.5).sum::<f64>() / n;
        let (ex, ey) = pixel_of_f(mirror_point(light));
        assert!(
            (cx - ex).abs() <= 1.0 && (cy - ey).abs() <= 1.0,
            "s {s}: peak centred at ({cx}, {cy}), mirror point at ({ex}, {ey})"
        );
        // One highlight per light and pixel shaded.
        assert_eq!(stats.counters.specular_evals, stats.counters.pixels_shaded);
    }
}

#[test]
fn higher_shininess_gives_a_smaller_highlight() {
    let light = [-1.0, 0.5, 3.0];
    let scene = plane_scene(light);
    let area = |s: f32| {
        let (diff, _) = highlight(&scene, Shading::Phong, s);
        diff.iter().filter(|&&d| d >= q(GREY) / 2).count()
    };
    let areas = [4.0, 16.0, 64.0, 256.0].map(area);
    assert!(areas.windows(2).all(|w| w[0] > w[1]), "{areas:?}");
    // By hand: the pixels where (N·H)^s ≥ ½ shrink as 1/s near the peak
    // (N·H ≈ 1 − r²/c, so r² ∝ ln 2 / s): the area ratio of s = 16 and
    // s = 64 is about 4.
    let ratio = areas[1] as f64 / areas[2] as f64;
    assert!((3.0..5.0).contains(&ratio), "{areas:?}");
}

#[test]
fn specular_map_scales_the_highlight() {
    let light = [1.5, 0.75, 2.5];
    let mut scene = plane_scene(light);
    let (plain, _) = highlight(&scene, Shading::Phong, 32.0);
    scene.material.specular_map = Some(Arc::new(Level::solid(3, 5, [0.5; 4])));
    let (half, _) = highlight(&scene, Shading::Phong, 32.0);
    let (_, _, peak) = argmax(&half);
    assert!((peak - q(GREY * 0.5)).abs() <= 1, "{peak}");
    assert!(plain.iter().zip(&half).all(|(p, h)| h <= p));
    scene.material.specular_map = Some(Arc::new(Level::solid(2, 2, [0.0; 4])));
    let (none, stats) = highlight(&scene, Shading::Phong, 32.0);
    assert!(none.iter().all(|&d| d == 0));
    assert!(stats.counters.specular_evals > 0);
}

#[test]
fn gouraud_lights_the_vertices_and_flat_the_facets() {
    // The mirror point on a vertex of the grid: (1, 1).
    let light = [1.5, 1.5, 2.5];
    let m = mirror_point(light);
    assert!((m[0] - 1.0).abs() < 1e-12 && (m[1] - 1.0).abs() < 1e-12);
    let scene = plane_scene(light);
    let (diff, stats) = highlight(&scene, Shading::Gouraud, 32.0);
    let (mx, my) = pixel_of(m);
    let (px, py, peak) = argmax(&diff);
    assert!(px.abs_diff(mx) <= 1 && py.abs_diff(my) <= 1, "({px}, {py})");
    assert!((q(GREY) - peak) <= 4 && peak <= q(GREY), "{peak}");
    let c = stats.counters;
    assert_eq!(c.specular_evals, 3 * c.triangles_drawn);
    // Flat: once per facet, so every pixel of a facet gets the same highlight.
    let (diff, stats) = highlight(&scene, Shading::Flat, 32.0);
    let c = stats.counters;
    assert_eq!(c.specular_evals, c.triangles_drawn);
    assert!(diff.iter().any(|&d| d > 0));
}

/// Off (the default) is today's picture in every shading mode, whatever the
/// exponent or map, and does no specular work; on, every mode does some.
#[test]
fn specular_off_is_the_picture_of_today_and_costs_nothing() {
    let mut scene = common::reference_scene(false);
    let frame = |scene: &Scene, s: &Settings| -> (Framebuffer, FrameStats) {
        render_frame(scene, s, 96, 72)
    };
    for shading in [Shading::Flat, Shading::Gouraud, Shading::Phong] {
        let base = Settings {
            shading,
            ..Settings::default()
        };
        let (today, _) = frame(&scene, &base);
        for shininess in [1.0, 32.0, 700.0] {
            scene.material.specular_map = Some(Arc::new(Level::solid(2, 2, [0.3; 4])));
            let s = Settings { shininess, ..base };
            let (fb, stats) = frame(&scene, &s);
            assert!(fb.pixels() == today.pixels(), "{s:?}");
            assert_eq!(stats.counters.specular_evals, 0, "{s:?}");
            let on = Settings {
                specular: true,
                ..s
            };
            let (lit, stats) = frame(&scene, &on);
            assert!(stats.counters.specular_evals > 0, "{on:?}");
            // (A facet-centre highlight of s = 700 rounds to nothing.)
            if shininess < 100.0 {
                assert!(lit.pixels() != today.pixels(), "{on:?}");
            }
            scene.material.specular_map = None;
        }
    }
    // No light, nothing to reflect: no work even when on.
    let dark = Settings {
        specular: true,
        lights: false,
        ..Settings::default()
    };
    assert_eq!(frame(&scene, &dark).1.counters.specular_evals, 0);
}

/// Where a point in world space projects to, in pixels from the top left
/// corner (the reference camera: eye on +Z looking at the origin, 60°).
fn project(p: [f64; 3]) -> (f64, f64) {
    let half_h = (30f64).to_radians().tan();
    let aspect = W as f64 / H as f64;
    let depth = EYE[2] - p[2];
    let nx = p[0] / depth / (half_h * aspect);
    let ny = p[1] / depth / half_h;
    ((nx + 1.0) / 2.0 * W as f64, (1.0 - ny) / 2.0 * H as f64)
}

/// The point of the unit sphere whose normal bisects the directions to the
/// light and to the eye (N·H = 1 there: the highlight's peak), found by
/// refining a search over the sphere in f64.
fn sphere_mirror_point(light: [f64; 3]) -> [f64; 3] {
    let score = |theta: f64, phi: f64| {
        let p = [
            theta.sin() * phi.cos(),
            theta.sin() * phi.sin(),
            theta.cos(),
        ];
        let l = unit(sub(light, p));
        let v = unit(sub(EYE, p));
        let h = unit([l[0] + v[0], l[1] + v[1], l[2] + v[2]]);
        (p[0] * h[0] + p[1] * h[1] + p[2] * h[2], p)
    };
    let (mut theta, mut phi, mut step) = (0.5f64, 0.5f64, 0.25f64);
    while step > 1e-9 {
        let mut best = (score(theta, phi).0, theta, phi);
        for (dt, dp) in [(step, 0.0), (-step, 0.0), (0.0, step), (0.0, -step)] {
            let s = score(theta + dt, phi + dp).0;
            if s > best.0 {
                best = (s, theta + dt, phi + dp);
            }
        }
        if (best.1, best.2) == (theta, phi) {
            step *= 0.5;
        }
        (theta, phi) = (best.1, best.2);
    }
    let (ndh, p) = score(theta, phi);
    assert!((ndh - 1.0).abs() < 1e-9, "the mirror point bisects: {ndh}");
    p
}

/// Where the ray through pixel (x, y)'s centre first meets the unit sphere.
fn on_sphere(x: usize, y: usize) -> Option<[f64; 3]> {
    let half_h = (30f64).to_radians().tan();
    let aspect = W as f64 / H as f64;
    let nx = 2.0 * (x as f64 + 0.5) / W as f64 - 1.0;
    let ny = 1.0 - 2.0 * (y as f64 + 0.5) / H as f64;
    let d = unit([nx * half_h * aspect, ny * half_h, -1.0]);
    // |E + t·d|² = 1: t² + 2(E·d)t + |E|² − 1 = 0, the nearer root.
    let b = EYE[0] * d[0] + EYE[1] * d[1] + EYE[2] * d[2];
    let c = EYE[0] * EYE[0] + EYE[1] * EYE[1] + EYE[2] * EYE[2] - 1.0;
    let disc = b * b - c;
    (disc >= 0.0).then(|| {
        let t = -b - disc.sqrt();
        [EYE[0] + t * d[0], EYE[1] + t * d[1], EYE[2] + t * d[2]]
    })
}

/// On the unit sphere, the highlight peaks on the pixel of the point whose
/// normal bisects light and eye (N·H = 1 there), and its value is the
/// light's grey × (N·H)^s at the point that pixel's centre sees.
#[test]
fn sphere_highlight_peaks_on_the_mirror_point_at_the_light_grey() {
    let light = [3.0, 2.0, 4.0];
    let texture = Texture::new("white", Level::solid(4, 4, [1.0; 4]));
    let mut scene = Scene::model(relief_scene::sphere::sphere(), Arc::new(texture));
    scene.lights = vec![Light::new(
        Vec3::new(light[0] as f32, light[1] as f32, light[2] as f32),
        Vec3::splat(GREY as f32),
    )];
    scene.ambient = Vec3::ZERO;
    let p = sphere_mirror_point(light);
    let (px, py) = project(p);
    for s in [32.0f32, 128.0] {
        let (diff, stats) = highlight(&scene, Shading::Phong, s);
        assert_eq!(stats.counters.nonfinite, 0);
        let (x, y, peak) = argmax(&diff);
        // The pixel whose centre is nearest the projected point, give or take
        // one for the facets (32 × 16) the interpolated normals smooth over.
        assert!(
            (x as f64 + 0.5 - px).abs() <= 1.5 && (y as f64 + 0.5 - py).abs() <= 1.5,
            "s = {s}: peak at ({x}, {y}), the mirror point projects to ({px:.2}, {py:.2})"
        );
        let at = on_sphere(x, y).expect("the peak pixel sees the sphere");
        let l = unit(sub(light, at));
        let v = unit(sub(EYE, at));
        let h = unit([l[0] + v[0], l[1] + v[1], l[2] + v[2]]);
        let ndh = at[0] * h[0] + at[1] * h[1] + at[2] * h[2];
        let expected = q(GREY * ndh.powf(s as f64));
        assert!(
            (peak - expected).abs() <= 2,
            "s = {s}: peak {peak}, by hand {expected} (N·H = {ndh:.6})"
        );
        assert!(peak <= q(GREY), "never above the light's grey");
    }
}
