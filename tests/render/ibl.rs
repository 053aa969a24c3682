//! Image-based light in the model view (docs/shading.md, "Image-based
//! light"): quads written as GLB files (`pbr`'s helpers) lit by
//! environments made here, and pixels checked against values worked out by
//! hand.

use std::sync::Arc;

use glam::Vec3;
use relief_core::settings::{IblDiffuse, IblSpecular, Settings};
use relief_scene::model_view::view_axes;
use relief_texture::environment::Environment;

use super::pbr::{centre, draw, facing, material, model, near, srgb8};

/// Only the environment lights the quads.
fn environment_only(scene: &mut relief_scene::Scene, env: Environment) {
    scene.lights.clear();
    scene.material.environment = Some(Arc::new(env));
}

/// A white metal of roughness 0 facing the camera reflects the direction
/// back to the eye, R = V: the texel the eye stands in front of. Its
/// specular share F0·A + B is 1 for F0 = 1 (the split sum of a white
/// mirror head on), so the centre pixel is that texel's colour. Turned
/// 180°, the environment puts the other colour there. Sampling the lobe
/// (`--ibl-specular sampled`) gives the same: its samples all fall on R,
/// each weighing F·G2/G1 = 1.
#[test]
fn a_smooth_metal_mirrors_the_environment_behind_the_eye() {
    let [_, _, back] = view_axes();
    let (red, blue) = (Vec3::new(0.8, 0.1, 0.05), Vec3::new(0.05, 0.2, 0.6));
    let env = || {
        Environment::from_fn("two colours", 256, 128, |d| {
            if d.dot(back) > 25f32.to_radians().cos() {
                red
            } else {
                blue
            }
        })
    };
    let mut scene = model(
        "ibl-mirror",
        1,
        &format!("[{}]", material([1.0; 3], 1.0, 0.0)),
        &[],
    );
    environment_only(&mut scene, env());
    for ibl_specular in [IblSpecular::Prefiltered, IblSpecular::Sampled] {
        let settings = Settings {
            ibl_specular,
            ..facing()
        };
        let fb = draw(&scene, &settings, 120, 90);
        let want = red.to_array().map(srgb8);
        assert!(
            near(centre(&fb), want, 2),
            "{ibl_specular:?}: {:?}, want {want:?}",
            centre(&fb)
        );

        let turned = Settings {
            environment_turn: 180.0,
            ..settings
        };
        let fb = draw(&scene, &turned, 120, 90);
        let want = blue.to_array().map(srgb8);
        assert!(
            near(centre(&fb), want, 2),
            "{ibl_specular:?}: {:?}, want {want:?}",
            centre(&fb)
        );
    }
}

/// Every way of computing the environment's light (`--ibl-diffuse`,
/// `--ibl-specular`), the default first.
const IBL_MODES: [(IblDiffuse, IblSpecular); 4] = [
    (IblDiffuse::Sh, IblSpecular::Prefiltered),
    (IblDiffuse::Integrated, IblSpecular::Prefiltered),
    (IblDiffuse::Sh, IblSpecular::Sampled),
    (IblDiffuse::Integrated, IblSpecular::Sampled),
];

/// The white furnace: a white dielectric under a uniform environment of
/// radiance 1 sends back at most 1 whatever its roughness and the angle it
/// is seen at, and a rough one nearly all of it (exposure ½ keeps the
/// result below the clamp at 1, so an excess would show), with every way
/// of computing the environment's light. A smooth white metal (F0 = 1)
/// sends back nearly all of it too.
#[test]
fn a_white_dielectric_in_a_white_furnace_reflects_at_most_its_input() {
    for (ibl_diffuse, ibl_specular) in IBL_MODES {
        for roughness in [0.0, 0.3, 0.6, 1.0] {
            let mut scene = model(
                "ibl-furnace",
                1,
                &format!("[{}]", material([1.0; 3], 0.0, roughness)),
                &[],
            );
            environment_only(
                &mut scene,
                Environment::from_fn("white", 64, 32, |_| Vec3::ONE),
            );
            for turn in [0.0, 30.0, 50.0] {
                let mut settings = Settings {
                    ibl_diffuse,
                    ibl_specular,
                    ..facing()
                };
                settings.rotation.y = turn;
                settings.exposure = 0.5;
                let got = centre(&draw(&scene, &settings, 120, 90));
                let most = srgb8(0.5) as i32 + 1;
                let at = format!("{ibl_diffuse:?} {ibl_specular:?} {roughness} {turn}");
                assert!(got.iter().all(|&c| c as i32 <= most), "{at}: {got:?}");
                if roughness == 1.0 {
                    let least = srgb8(0.5 * 0.95) as i32;
                    assert!(got.iter().all(|&c| c as i32 >= least), "{at}: {got:?}");
                }
            }
        }
        let mut scene = model(
            "ibl-furnace-metal",
            1,
            &format!("[{}]", material([1.0; 3], 1.0, 0.0)),
            &[],
        );
        environment_only(
            &mut scene,
            Environment::from_fn("white", 64, 32, |_| Vec3::ONE),
        );
        let settings = Settings {
            ibl_diffuse,
            ibl_specular,
            exposure: 0.5,
            ..facing()
        };
        let got = centre(&draw(&scene, &settings, 120, 90));
        let (least, most) = (srgb8(0.5 * 0.97) as i32, srgb8(0.5) as i32 + 1);
        assert!(
            got.iter().all(|&c| (least..=most).contains(&(c as i32))),
            "{ibl_diffuse:?} {ibl_specular:?}: {got:?}"
        );
    }
}

/// The clear-coat sample (several materials, normal maps, clearcoat
/// layers) in the studio with the rig's lights: each other way of
/// computing the environment's light changes the picture, by a little
/// (both are nearer the true integrals than the defaults), and makes no
/// pixel black or white that was not (no NaN, no blow-up).
#[test]
fn each_ibl_setting_changes_the_picture_a_little_and_stays_finite() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/models/gltf/ClearCoatTest/ClearCoatTest.gltf");
    let scene = match relief_scene::build_scene(
        relief_scene::SceneKind::Cube,
        &relief_scene::ModelChoice::File(path),
        Arc::new(relief_texture::decode::procedural::brick()),
        false,
    ) {
        Ok(relief_scene::Built::Scene(scene)) => *scene,
        Ok(relief_scene::Built::Plasma(_)) => unreachable!(),
        Err(e) => panic!("{e}"),
    };
    let (w, h) = (160, 120);
    let start = Settings {
        rotation: relief_scene::model_view::START_ROTATION,
        ..Settings::default()
    };
    let default = draw(&scene, &start, w, h);
    let background = relief_scene::BACKGROUND;
    let covered = default
        .pixels()
        .iter()
        .filter(|&&p| p != background)
        .count();
    assert!(covered > 2000, "{covered}");
    for (ibl_diffuse, ibl_specular) in &IBL_MODES[1..] {
        let settings = Settings {
            ibl_diffuse: *ibl_diffuse,
            ibl_specular: *ibl_specular,
            ..start
        };
        let got = draw(&scene, &settings, w, h);
        let at = format!("{ibl_diffuse:?} {ibl_specular:?}");
        let (mut changed, mut most, mut sum) = (0, 0i32, 0i64);
        for (a, b) in default.pixels().iter().zip(got.pixels()) {
            assert_eq!(*a == background, *b == background, "{at}: {a:?} {b:?}");
            let d = (0..3)
                .map(|k| (a[k] as i32 - b[k] as i32).abs())
                .max()
                .unwrap();
            changed += (d > 0) as usize;
            most = most.max(d);
            sum += d as i64;
            for k in 0..3 {
                if a[k] > 8 && a[k] < 247 {
                    assert!(b[k] > 0 && b[k] < 255, "{at}: {a:?} became {b:?}");
                }
            }
        }
        let mean = sum as f64 / covered as f64;
        assert!(
            changed > covered / 10,
            "{at}: {changed} of {covered} changed"
        );
        assert!(mean < 12.0 && most < 120, "{at}: mean {mean}, most {most}");
    }
}

/// The built-in studio with the model view's white key light: a white
/// dielectric facing the camera stays below white with the default
/// exposure and tone map, and brighter than mid-grey.
#[test]
fn a_white_dielectric_in_the_studio_does_not_blow_out() {
    let scene = model(
        "ibl-studio",
        1,
        &format!("[{}]", material([1.0; 3], 0.0, 0.5)),
        &[],
    );
    let settings = relief_core::settings::Settings {
        rotation: facing().rotation,
        ..relief_core::settings::Settings::default()
    };
    let got = centre(&draw(&scene, &settings, 120, 90));
    assert!(got.iter().all(|&c| (150..250).contains(&c)), "{got:?}");
}

/// The environment behind the model (`B`, `--backdrop`): an environment
/// whose colour is its direction, (d + 1)/2, seen through the model
/// view's camera (looking down −back from above, right +X, 60° high, no
/// tone map). The ray through the centre of pixel (x, y) of a W×H frame
/// is −back + right·nx·t·W/H + up·ny·t, t = tan 30°, nx = 2(x + ½)/W − 1,
/// ny = 1 − 2(y + ½)/H; the pixel is that direction's colour, turned as
/// `J` turns the light: (c·x − s·z, y, s·x + c·z) for the turn's cosine
/// and sine. Off, the corners are the plain background; the model's own
/// pixels are the same either way.
#[test]
fn the_backdrop_shows_the_environment_through_each_pixel() {
    let [right, up, back] = view_axes();
    let mut scene = model(
        "ibl-backdrop",
        1,
        &format!("[{}]", material([1.0; 3], 0.0, 0.5)),
        &[],
    );
    environment_only(
        &mut scene,
        Environment::from_fn("directions", 512, 256, |d| (d + Vec3::ONE) * 0.5),
    );
    let (w, h) = (120usize, 90usize);
    for degrees in [0.0f32, 90.0] {
        let settings = relief_core::settings::Settings {
            backdrop: true,
            environment_turn: degrees,
            ..facing()
        };
        let shown = draw(&scene, &settings, w, h);
        let plain = relief_core::settings::Settings {
            backdrop: false,
            ..settings
        };
        let plain = draw(&scene, &plain, w, h);
        let t = (settings.fov.to_radians() / 2.0).tan();
        let (c, s) = (degrees.to_radians().cos(), degrees.to_radians().sin());
        for (x, y) in [(0, 0), (w - 1, 0), (0, h - 1), (w - 1, h - 1), (w / 2, 0)] {
            let nx = 2.0 * (x as f32 + 0.5) / w as f32 - 1.0;
            let ny = 1.0 - 2.0 * (y as f32 + 0.5) / h as f32;
            let d = (-back + right * nx * t * (w as f32 / h as f32) + up * ny * t).normalize();
            let d = Vec3::new(c * d.x - s * d.z, d.y, s * d.x + c * d.z);
            let want = ((d + Vec3::ONE) * 0.5).to_array().map(srgb8);
            let got = shown.pixels()[y * w + x];
            assert!(
                near(got, want, 3),
                "{degrees}° ({x}, {y}): {got:?}, want {want:?}"
            );
            assert_eq!(
                plain.pixels()[y * w + x],
                relief_scene::BACKGROUND,
                "({x}, {y})"
            );
        }
        // The model covers the centre alike with and without the backdrop.
        assert_eq!(centre(&shown), centre(&plain));
    }
}
