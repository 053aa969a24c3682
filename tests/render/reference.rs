//! The reference cube scene checked against numbers derived by hand (in f64,
//! from the formulas of docs/shading.md and docs/bump-blinn.md,
//! independently of the renderer's code).

use crate::common;

use common::*;
use glam::{DMat3, DVec2, DVec3, Vec3};
use proptest::prelude::*;
use relief_core::settings::{Normals, Settings, Shading};
use relief_scene::Scene;

const W: usize = 320;
const H: usize = 240;

/// The reference lights: (position, colour).
fn lights() -> Vec<(DVec3, DVec3)> {
    vec![
        (DVec3::new(3.0, 4.0, 6.0), DVec3::ONE),
        (DVec3::new(-8.0, 1.0, 3.0), DVec3::new(0.3, 0.0, 0.0)),
        (DVec3::new(8.0, -2.0, 3.0), DVec3::new(0.0, 0.3, 0.0)),
        (DVec3::new(0.0, -8.0, 2.0), DVec3::new(0.0, 0.0, 0.3)),
    ]
}

/// ambient + Σ colour · max(0, N·L).
fn light_at(p: DVec3, n: DVec3) -> DVec3 {
    let mut sum = DVec3::splat(0.1);
    for (pos, color) in lights() {
        sum += color * n.dot((pos - p).normalize()).max(0.0);
    }
    sum
}

fn quantise(c: DVec3) -> [u8; 3] {
    c.to_array()
        .map(|x| (x.clamp(0.0, 1.0) * 255.0).round() as u8)
}

/// Rotation about X, then Y, then Z (degrees).
fn rotation(deg: DVec3) -> DMat3 {
    let r = deg * std::f64::consts::PI / 180.0;
    DMat3::from_rotation_z(r.z) * DMat3::from_rotation_y(r.y) * DMat3::from_rotation_x(r.x)
}

/// The camera ray through the centre of pixel (px, py): origin and direction.
fn ray(px: usize, py: usize) -> (DVec3, DVec3) {
    let tan = (30.0f64).to_radians().tan();
    let aspect = W as f64 / H as f64;
    let x = ((px as f64 + 0.5) / W as f64 * 2.0 - 1.0) * tan * aspect;
    let y = (1.0 - (py as f64 + 0.5) / H as f64 * 2.0) * tan;
    (DVec3::new(0.0, 0.0, 5.0), DVec3::new(x, y, -1.0))
}

/// Where the ray through a pixel meets the unrotated front face z = 1.
fn front_face_point(px: usize, py: usize) -> DVec3 {
    let (o, d) = ray(px, py);
    o + d * ((1.0 - o.z) / d.z)
}

fn vertex_color(p: DVec3) -> DVec3 {
    DVec3::splat(0.4) + 0.3 * (p + DVec3::ONE)
}

fn close(got: [u8; 3], want: [u8; 3]) -> bool {
    got.iter()
        .zip(want)
        .all(|(&g, w)| (g as i32 - w as i32).abs() <= 1)
}

fn front_view(settings: Settings) -> Settings {
    Settings {
        rotation: Vec3::ZERO,
        ..settings
    }
}

#[test]
fn reference_view_covers_the_documented_pixel_count() {
    // README "The reference scene": at 320×240 the cube covers 11,741 pixels.
    let scene = reference_scene(true);
    let (fb, stats) = render(&scene, &Settings::default(), W, H);
    assert_eq!(covered(&scene, &fb), 11_741);
    assert_eq!(stats.counters.pixels_shaded, 11_741);
}

#[test]
fn front_face_centre_pixel_with_face_normals_matches_the_formula() {
    let scene = reference_scene(false);
    let settings = front_view(Settings {
        normals: Normals::Face,
        colors: false,
        texture: false,
        bump: false,
        ..Settings::default()
    });
    let (fb, _) = render(&scene, &settings, W, H);
    for (px, py) in [(160, 120), (140, 100), (175, 133)] {
        let p = front_face_point(px, py);
        let want = quantise(light_at(p, DVec3::Z));
        assert!(
            close(fb.get(px, py), want),
            "({px},{py}): {:?} vs {want:?}",
            fb.get(px, py)
        );
    }
    // The documented numbers at the face centre: 0.1 + 1/√2 + small coloured terms.
    let centre = quantise(light_at(DVec3::Z, DVec3::Z));
    assert_eq!(centre, [224, 224, 215]);
}

#[test]
fn front_face_pixels_with_vertex_normals_and_colours_match_the_formula() {
    // On a face of the cube, the interpolated corner normals are the
    // position itself (normalised) and the colour is affine in the position.
    let scene = reference_scene(false);
    let settings = front_view(Settings {
        texture: false,
        bump: false,
        ..Settings::default()
    });
    let (fb, _) = render(&scene, &settings, W, H);
    for (px, py) in [(160, 120), (130, 95), (190, 150), (140, 140)] {
        let p = front_face_point(px, py);
        assert!(p.x.abs() < 1.0 && p.y.abs() < 1.0);
        let want = quantise(vertex_color(p) * light_at(p, p.normalize()));
        assert!(
            close(fb.get(px, py), want),
            "({px},{py}): {:?} vs {want:?}",
            fb.get(px, py)
        );
    }
}

#[test]
fn flat_shading_paints_each_untextured_face_in_one_derived_colour() {
    let scene = reference_scene(false);
    let settings = Settings {
        shading: Shading::Flat,
        texture: false,
        ..Settings::default()
    };
    let (fb, _) = render(&scene, &settings, W, H);
    let mut colours: Vec<[u8; 3]> = fb
        .pixels()
        .iter()
        .copied()
        .filter(|&p| p != scene.background)
        .collect();
    colours.sort();
    colours.dedup();
    // Three faces are visible in the reference view: three colours.
    assert_eq!(colours.len(), 3, "{colours:?}");
    // Each is the facet colour (mean of its corners) lit at the rotated face centre.
    let r = rotation(DVec3::new(25.0, 35.0, 0.0));
    for (n, u, v) in relief_scene::cube::FACES {
        let [n, u, v] = [n, u, v].map(|a| a.as_dvec3());
        let corners = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
        let mean = corners
            .iter()
            .map(|&(s, t)| vertex_color(n + u * s + v * t))
            .sum::<DVec3>()
            / 4.0;
        let world_n = r * n;
        let facing = world_n.dot(DVec3::new(0.0, 0.0, 5.0) - r * n) > 0.0;
        if facing {
            let want = quantise(mean * light_at(r * n, world_n));
            assert!(
                colours.iter().any(|&c| close(c, want)),
                "face {n}: {want:?} not in {colours:?}"
            );
        }
    }
}

/// Area of the convex hull of points (pixels²) and its perimeter.
fn hull_area_perimeter(mut pts: Vec<DVec2>) -> (f64, f64) {
    pts.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    let cross = |o: DVec2, a: DVec2, b: DVec2| (a - o).perp_dot(b - o);
    let mut hull: Vec<DVec2> = Vec::new();
    for pass in 0..2 {
        let start = hull.len();
        let iter: Box<dyn Iterator<Item = &DVec2>> = if pass == 0 {
            Box::new(pts.iter())
        } else {
            Box::new(pts.iter().rev())
        };
        for &p in iter {
            while hull.len() >= start + 2
                && cross(hull[hull.len() - 2], hull[hull.len() - 1], p) <= 0.0
            {
                hull.pop();
            }
            hull.push(p);
        }
        hull.pop();
    }
    let mut area = 0.0;
    let mut perimeter = 0.0;
    for i in 0..hull.len() {
        let (a, b) = (hull[i], hull[(i + 1) % hull.len()]);
        area += a.perp_dot(b);
        perimeter += (b - a).length();
    }
    (area.abs() / 2.0, perimeter)
}

/// The cube's analytic silhouette: the hull of its 8 projected corners.
fn silhouette(rot: DVec3) -> (f64, f64) {
    let r = rotation(rot);
    let tan = (30.0f64).to_radians().tan();
    let aspect = W as f64 / H as f64;
    let mut pts = Vec::new();
    for i in 0..8 {
        let c = DVec3::new(
            if i & 1 == 0 { -1.0 } else { 1.0 },
            if i & 2 == 0 { -1.0 } else { 1.0 },
            if i & 4 == 0 { -1.0 } else { 1.0 },
        );
        let p = r * c;
        let depth = 5.0 - p.z;
        let x = p.x / depth / (tan * aspect);
        let y = p.y / depth / tan;
        pts.push(DVec2::new(
            (x + 1.0) * 0.5 * W as f64,
            (1.0 - y) * 0.5 * H as f64,
        ));
    }
    hull_area_perimeter(pts)
}

fn count_at(scene: &Scene, rot: Vec3) -> usize {
    let settings = Settings {
        rotation: rot,
        shading: Shading::Flat,
        texture: false,
        ..Settings::default()
    };
    covered(scene, &render(scene, &settings, W, H).0)
}

#[test]
fn silhouette_area_matches_the_analytic_projection() {
    let scene = reference_scene(false);
    let (area, perimeter) = silhouette(DVec3::new(25.0, 35.0, 0.0));
    let count = count_at(&scene, Vec3::new(25.0, 35.0, 0.0)) as f64;
    // Pixel-centre sampling errs by at most about half a pixel along the outline.
    assert!(
        (count - area).abs() < perimeter * 0.5,
        "count {count}, area {area:.1}"
    );
    assert!((count - area).abs() / area < 0.02);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn silhouette_area_matches_for_any_orientation(x in -180.0f32..180.0, y in -180.0f32..180.0, z in -180.0f32..180.0) {
        let scene = reference_scene(false);
        let (area, perimeter) = silhouette(DVec3::new(x as f64, y as f64, z as f64));
        let count = count_at(&scene, Vec3::new(x, y, z)) as f64;
        prop_assert!((count - area).abs() < perimeter * 0.5 + 2.0, "count {}, area {}", count, area);
    }
}

/// A height map rising linearly along u (F = u, so ∂F/∂u = 1), any colour.
fn ramp_scene() -> Scene {
    let w = 64;
    let texels = (0..w * 4)
        .map(|i| [0.8, 0.8, 0.8, ((i % w) as f32 + 0.5) / w as f32])
        .collect();
    let level = relief_texture::Level {
        wrap: Default::default(),
        width: w,
        height: 4,
        texels,
    };
    Scene::cube(
        std::sync::Arc::new(relief_texture::Texture::new("ramp", level)),
        false,
    )
}

#[test]
fn blinn_bump_on_a_ramp_tilts_the_normal_as_the_formula_says() {
    // N' = N + k·(F_u·(N × Pv) − F_v·(N × Pu)) with N = Z, Pu = 2X, Pv = 2Y,
    // F_u = 1, F_v = 0: N' = (−2k, 0, 1), normalised.
    let scene = ramp_scene();
    let k = 0.25f32;
    for derivative in [
        relief_core::settings::HeightDerivative::Texel,
        relief_core::settings::HeightDerivative::Filtered,
    ] {
        let settings = front_view(Settings {
            normals: Normals::Face,
            colors: false,
            texture: false,
            bump_strength: k,
            height_derivative: derivative,
            ..Settings::default()
        });
        let (fb, _) = render(&scene, &settings, W, H);
        let n = DVec3::new(-2.0 * k as f64, 0.0, 1.0).normalize();
        for (px, py) in [(160, 120), (150, 110), (170, 128)] {
            let p = front_face_point(px, py);
            let want = quantise(light_at(p, n));
            assert!(
                close(fb.get(px, py), want),
                "{derivative:?} ({px},{py}): {:?} vs {want:?}",
                fb.get(px, py)
            );
        }
    }
}
