//! Environment mapping (docs/environment.md) against directions worked out
//! by hand: a plane z = 0 of side 4 facing the reference camera at
//! (0, 0, 5), mirroring environments built here, one colour per axis or
//! the direction itself as a colour.

use crate::common;

use std::sync::Arc;

use clap::ValueEnum;
use glam::{Vec2, Vec3};
use relief_core::framebuffer::Rgb;
use relief_core::settings::Settings;
use relief_core::settings::{Display, Shading, Technique};
use relief_pipeline::render::render_frame;
use relief_pipeline::shade::environment::reflect;
use relief_scene::Scene;
use relief_scene::light::Light;
use relief_scene::plane::grid;
use relief_scene::rotation_matrix;
use relief_texture::environment::Environment;
use relief_texture::lat_long::{direction, lat_long};
use relief_texture::{Level, Texture};

const W: usize = 160;
const H: usize = 120;
const EYE: [f64; 3] = [0.0, 0.0, 5.0];

/// The colour of each axis direction: every pair of opposite axes apart.
fn axis_colour(d: Vec3) -> Vec3 {
    let a = d.abs();
    if a.x >= a.y && a.x >= a.z {
        if d.x > 0.0 {
            Vec3::X
        } else {
            Vec3::new(0.0, 1.0, 1.0)
        }
    } else if a.y >= a.z {
        if d.y > 0.0 {
            Vec3::Y
        } else {
            Vec3::new(1.0, 0.0, 1.0)
        }
    } else if d.z > 0.0 {
        Vec3::Z
    } else {
        Vec3::new(1.0, 1.0, 0.0)
    }
}

/// Six coloured directions: the cube of axes, as a lat-long picture.
fn axes() -> Arc<Environment> {
    Arc::new(Environment::from_fn("axes", 64, 32, axis_colour))
}

/// The direction as a colour, 0.5 + 0.5·d: any turn of R shows.
fn compass() -> Arc<Environment> {
    Arc::new(Environment::from_fn("compass", 512, 256, |d| {
        Vec3::splat(0.5) + 0.5 * d
    }))
}

fn rgb(c: Vec3) -> Rgb {
    let q = |x: f32| (x.clamp(0.0, 1.0) * 255.0 + 0.5) as u8;
    [q(c.x), q(c.y), q(c.z)]
}

/// The plane, textured with `texture`, under one grey light at (1, 1, 3)
/// and no ambient, mirroring `env`.
fn plane_scene(env: Arc<Environment>, texture: Texture) -> Scene {
    let mut scene = Scene::model(grid(2.0, 1.0, 4, |_| Vec3::ONE), Arc::new(texture));
    scene.lights = vec![Light::new(Vec3::new(1.0, 1.0, 3.0), Vec3::splat(0.5))];
    scene.ambient = Vec3::ZERO;
    scene.material.environment = Some(env);
    scene
}

fn white() -> Texture {
    Texture::new("white", Level::solid(4, 4, [1.0; 4]))
}

fn settings(rotation: Vec3, reflectivity: f32, bump: bool) -> Settings {
    Settings {
        shading: Shading::Phong,
        texture: false,
        colors: false,
        bump,
        rotation,
        environment: true,
        reflectivity,
        ..Settings::default()
    }
}

/// The centre pixel's colour (its centre is half a pixel from the axis).
fn centre(scene: &Scene, s: &Settings) -> Rgb {
    render_frame(scene, s, W, H).0.get(W / 2, H / 2)
}

/// The unit direction from a point toward the eye, in f64.
fn to_eye(p: [f64; 3]) -> [f64; 3] {
    let d = [EYE[0] - p[0], EYE[1] - p[1], EYE[2] - p[2]];
    let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    [d[0] / l, d[1] / l, d[2] / l]
}

/// Where the ray through pixel (x, y)'s centre meets z = 0 (60° vertical
/// field, rows from the top).
fn on_plane(x: usize, y: usize) -> [f64; 3] {
    let half_h = (30f64).to_radians().tan();
    let aspect = W as f64 / H as f64;
    let nx = 2.0 * (x as f64 + 0.5) / W as f64 - 1.0;
    let ny = 1.0 - 2.0 * (y as f64 + 0.5) / H as f64;
    [EYE[2] * nx * half_h * aspect, EYE[2] * ny * half_h, 0.0]
}

#[test]
fn reflect_mirrors_about_the_normal() {
    // Head-on: straight back.
    assert_eq!(reflect(Vec3::Z, Vec3::Z), Vec3::Z);
    // 45° incidence: the tangential part changes sign, the normal part stays.
    let v = Vec3::new(1.0, 0.0, 1.0).normalize();
    let r = reflect(v, Vec3::Z);
    assert!((r - Vec3::new(-v.x, 0.0, v.z)).length() < 1e-6, "{r}");
    // Normal tilted 45° toward +X, eye along +Z: R turns 90° to +X.
    let n = Vec3::new(1.0, 0.0, 1.0).normalize();
    assert!((reflect(Vec3::Z, n) - Vec3::X).length() < 1e-6);
    // Grazing: R = V on the surface's plane.
    assert!((reflect(Vec3::X, Vec3::Z) + Vec3::X).length() < 1e-6);
}

#[test]
fn lat_long_puts_the_axes_where_documented() {
    let close = |d: Vec3, u: f32, v: f32| {
        let uv = lat_long(d);
        assert!((uv - Vec2::new(u, v)).length() < 1e-6, "{d}: {uv}");
    };
    close(Vec3::NEG_Z, 0.5, 0.5);
    close(Vec3::X, 0.75, 0.5);
    close(Vec3::NEG_X, 0.25, 0.5);
    // Any length reads the same direction.
    close(Vec3::new(3.0, 0.0, 0.0), 0.75, 0.5);
    // Behind the camera is the seam: u = 0 or 1.
    let seam = lat_long(Vec3::Z);
    assert!(seam.x == 0.0 || seam.x == 1.0, "{seam}");
    assert_eq!(seam.y, 0.5);
    // The poles: v = 0 up and 1 down, with a finite u.
    for (d, v) in [(Vec3::Y, 0.0), (Vec3::NEG_Y, 1.0)] {
        let uv = lat_long(d);
        assert!(uv.x.is_finite() && (0.0..=1.0).contains(&uv.x), "{uv}");
        assert_eq!(uv.y, v);
    }
    // Nothing to point at: the front, not NaN.
    for d in [Vec3::ZERO, Vec3::NAN, Vec3::INFINITY] {
        assert_eq!(lat_long(d), Vec2::splat(0.5));
    }
    // direction() is the inverse at the axes.
    for d in [Vec3::X, Vec3::NEG_X, Vec3::Y, Vec3::NEG_Y, Vec3::NEG_Z] {
        assert!((direction(lat_long(d)) - d).length() < 1e-6, "{d}");
    }
}

/// An 8 × 4 picture whose texel (c, r) holds (c/8, r/4, 1): which texels a
/// read blended shows in its colour.
fn grid_env() -> Environment {
    let (w, h) = (8, 4);
    let texels = (0..h)
        .flat_map(|r| (0..w).map(move |c| [c as f32 / 8.0, r as f32 / 4.0, 1.0, 0.0]))
        .collect();
    Environment::from_texture(Texture::new(
        "grid",
        Level {
            wrap: Default::default(),
            width: w,
            height: h,
            texels,
        },
    ))
}

#[test]
fn lookup_is_bilinear_across_the_seam_and_clamped_at_the_poles() {
    let env = grid_env();
    // The front (u = 1/2, v = 1/2) is the corner of texels 3, 4 and rows 1, 2.
    let front = env.lookup(Vec3::NEG_Z);
    assert!(
        (front - Vec3::new(3.5 / 8.0, 1.5 / 4.0, 1.0)).length() < 1e-6,
        "{front}"
    );
    // +X (u = 3/4): columns 5 and 6.
    let east = env.lookup(Vec3::X);
    assert!(
        (east - Vec3::new(5.5 / 8.0, 1.5 / 4.0, 1.0)).length() < 1e-6,
        "{east}"
    );
    // The seam (+Z) blends the last column with the first: (7 + 0) / 2.
    let seam = env.lookup(Vec3::Z);
    assert!(
        (seam - Vec3::new(3.5 / 8.0, 1.5 / 4.0, 1.0)).length() < 1e-6,
        "{seam}"
    );
    // Just either side of the seam: nearly the same blend, no jump to a
    // single column.
    for side in [-1e-3f32, 1e-3] {
        let c = env.lookup(Vec3::new(side, 0.0, 1.0));
        assert!((c.x - 3.5 / 8.0).abs() < 0.01, "{side}: {c}");
    }
    // The poles read their own row only (clamped, never the other pole's),
    // whatever the azimuth, and never NaN.
    for k in 0..8 {
        let a = k as f32 * std::f32::consts::TAU / 8.0;
        let off = 1e-4 * Vec3::new(a.cos(), 0.0, a.sin());
        let up = env.lookup(Vec3::Y + off);
        let down = env.lookup(Vec3::NEG_Y + off);
        assert!(up.is_finite() && down.is_finite());
        assert_eq!(up.y, 0.0, "{up}");
        assert_eq!(down.y, 3.0 / 4.0, "{down}");
    }
    assert!(env.lookup(Vec3::Y).is_finite() && env.lookup(Vec3::NEG_Y).is_finite());
}

#[test]
fn a_plane_seen_head_on_mirrors_what_is_behind_the_camera() {
    let scene = plane_scene(axes(), white());
    // k = 1: the pixel is the environment in R = +Z, nothing else.
    assert_eq!(
        centre(&scene, &settings(Vec3::ZERO, 1.0, false)),
        rgb(Vec3::Z)
    );
    // k = 1/2: half the lit colour, half the reflection, by hand. The
    // light at (1, 1, 3) is 3/√11 above the plane at the centre.
    let lit = 0.5 * 3.0 / 11f32.sqrt();
    let want = Vec3::splat(lit) * 0.5 + Vec3::Z * 0.5;
    let got = centre(&scene, &settings(Vec3::ZERO, 0.5, false));
    let want = rgb(want);
    for c in 0..3 {
        assert!(
            (got[c] as i32 - want[c] as i32).abs() <= 1,
            "{got:?} vs {want:?}"
        );
    }
}

#[test]
fn tilting_the_plane_45_degrees_turns_the_reflection_90() {
    let scene = plane_scene(axes(), white());
    for (rotation, turned) in [
        // About Y, +45°: the normal leans to +X, R = +X.
        (Vec3::new(0.0, 45.0, 0.0), Vec3::X),
        (Vec3::new(0.0, -45.0, 0.0), Vec3::NEG_X),
        // About X, +45°: the normal leans to −Y, R = −Y.
        (Vec3::new(45.0, 0.0, 0.0), Vec3::NEG_Y),
        (Vec3::new(-45.0, 0.0, 0.0), Vec3::Y),
    ] {
        // R by hand from the rotated normal, at the plane's centre (the
        // centre pixel sees it, the eye straight in front).
        let n = rotation_matrix(rotation).transform_vector3(Vec3::Z);
        let r = reflect(Vec3::Z, n);
        assert!((r - turned).length() < 1e-5, "{rotation}: {r}");
        assert_eq!(
            centre(&scene, &settings(rotation, 1.0, false)),
            rgb(axis_colour(turned)),
            "{rotation}"
        );
    }
}

#[test]
fn bump_bends_the_reflection_and_without_it_the_plane_is_a_mirror() {
    let texture = relief_texture::decode::procedural::brick();
    let scene = plane_scene(compass(), texture);
    let (flat, stats) = render_frame(&scene, &settings(Vec3::ZERO, 1.0, false), W, H);
    let (bumped, _) = render_frame(&scene, &settings(Vec3::ZERO, 1.0, true), W, H);
    // Without bump every covered pixel shows 0.5 + 0.5·R, R = (−Vx, −Vy, Vz).
    let mut covered = 0;
    for y in 0..H {
        for x in 0..W {
            if flat.get(x, y) == scene.background {
                continue;
            }
            covered += 1;
            let v = to_eye(on_plane(x, y));
            let r = Vec3::new(-v[0] as f32, -v[1] as f32, v[2] as f32);
            let want = rgb(Vec3::splat(0.5) + 0.5 * r);
            let got = flat.get(x, y);
            for c in 0..3 {
                assert!(
                    (got[c] as i32 - want[c] as i32).abs() <= 1,
                    "({x}, {y}): {got:?} vs {want:?}"
                );
            }
        }
    }
    assert!(covered > 5000);
    assert_eq!(stats.counters.env_lookups, covered as u64);
    // With bump the bricks' slopes bend R: the mortar lines show.
    let bent = flat
        .pixels()
        .iter()
        .zip(bumped.pixels())
        .filter(|(a, b)| a != b)
        .count();
    assert!(bent > covered / 10, "{bent} of {covered} pixels bent");
}

#[test]
fn off_is_the_picture_without_it_and_reads_nothing() {
    let mut scene = common::reference_scene(true);
    scene.material.environment = Some(axes());
    let base = Settings::default();
    let (before, _) = render_frame(&scene, &base, 96, 72);
    let cases = [
        // Off, whatever the reflectivity.
        Settings {
            reflectivity: 1.0,
            ..base
        },
        // On but cannot show: no share, Gouraud, flat, lines.
        Settings {
            environment: true,
            reflectivity: 0.0,
            ..base
        },
        Settings {
            environment: true,
            shading: Shading::Gouraud,
            ..base
        },
        Settings {
            environment: true,
            shading: Shading::Flat,
            ..base
        },
        Settings {
            environment: true,
            display: Display::Lines,
            ..base
        },
    ];
    for s in cases {
        let (frame, stats) = render_frame(&scene, &s, 96, 72);
        assert_eq!(stats.counters.env_lookups, 0, "{s:?}");
        let (without, _) = render_frame(
            &scene,
            &Settings {
                environment: false,
                ..s
            },
            96,
            72,
        );
        assert!(frame.pixels() == without.pixels(), "{s:?}");
        if s.shading == base.shading && s.display == base.display && s.technique == base.technique {
            assert!(frame.pixels() == before.pixels(), "{s:?}");
        }
    }
    // On: one read per shaded pixel, and the picture changes.
    let on = Settings {
        environment: true,
        ..base
    };
    let (frame, stats) = render_frame(&scene, &on, 96, 72);
    assert_eq!(stats.counters.env_lookups, stats.counters.pixels_shaded);
    assert!(frame.pixels() != before.pixels());
    // Every bump technique mirrors it: they share the one shading core.
    for &technique in Technique::value_variants() {
        let s = Settings {
            technique,
            bump: true,
            ..on
        };
        let (_, stats) = render_frame(&scene, &s, 96, 72);
        assert!(stats.counters.pixels_shaded > 0);
        assert_eq!(
            stats.counters.env_lookups, stats.counters.pixels_shaded,
            "{technique:?}"
        );
        assert_eq!(stats.counters.nonfinite, 0, "{technique:?}");
    }
}

#[test]
fn a_picture_file_loads_as_an_environment_and_a_missing_one_says_so() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/pngsuite");
    let env = Environment::load(&dir.join("basn2c08.png")).unwrap();
    assert_eq!(env.size(), (32, 32));
    for d in [Vec3::X, Vec3::Y, Vec3::NEG_Y, Vec3::Z, Vec3::NEG_Z] {
        let c = env.lookup(d);
        assert!(
            c.is_finite() && c.min_element() >= 0.0 && c.max_element() <= 1.0,
            "{d}: {c}"
        );
    }
    let missing = Environment::load(&dir.join("no-such-environment.png"));
    assert!(matches!(
        missing,
        Err(relief_texture::TextureError::NotFound { .. })
    ));
}

/// A Radiance or OpenEXR environment keeps its radiance above 1 (a sun of
/// 40, a window of 5): the image-based light and the backdrop see what the
/// file holds. The same file as a texture is clamped to 0..=1, and a
/// negative or not-a-number value reads 0 either way.
#[test]
fn a_float_environment_keeps_its_radiance_and_a_texture_of_it_is_clamped() {
    use image::{DynamicImage, ImageFormat, Rgb32FImage, Rgba32FImage};
    let (w, h) = (16u32, 8u32);
    // Column 0: 40 (the sun); column 5: 5; column 9: negative; the rest 0.5.
    let value = |x: u32| match x {
        0 => 40.0,
        5 => 5.0,
        9 => -3.0,
        _ => 0.5,
    };
    let dir = crate::common::scratch::scratch_dir("env");
    let hdr = Rgb32FImage::from_fn(w, h, |x, _| image::Rgb([value(x); 3]));
    let exr = Rgba32FImage::from_fn(w, h, |x, _| {
        image::Rgba([value(x), value(x), value(x), 1.0])
    });
    for (name, picture, format) in [
        ("sun.hdr", DynamicImage::ImageRgb32F(hdr), ImageFormat::Hdr),
        (
            "sun.exr",
            DynamicImage::ImageRgba32F(exr),
            ImageFormat::OpenExr,
        ),
    ] {
        let path = dir.join(name);
        let bytes = relief_texture::picture::encode(&picture, format).unwrap();
        std::fs::write(&path, bytes).unwrap();
        let env = Environment::load(&path).unwrap();
        let texels = &env.picture().texels;
        let row = |x: usize| texels.at(3 * w as usize + x);
        // Radiance keeps an 8-bit mantissa: within 1 %.
        for (x, want) in [(0, 40.0f32), (5, 5.0), (9, 0.0), (2, 0.5)] {
            let got = row(x)[0];
            assert!(
                (got - want).abs() <= 0.01 * want,
                "{name} column {x}: {got}"
            );
        }
        let texture = relief_texture::load_texture(&path).unwrap();
        let texel = |x: usize| texture.base().texels.at(3 * w as usize + x);
        assert_eq!(texel(0)[0], 1.0, "{name}");
        assert_eq!(texel(5)[0], 1.0, "{name}");
        assert_eq!(texel(9)[0], 0.0, "{name}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
