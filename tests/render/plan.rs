//! Toggles change what they should and nothing else, and the stage counters
//! prove the plan: an effect that is off, or cannot show, does no work.

use crate::common;

use std::sync::Arc;

use common::*;
use glam::Vec3;
use relief_core::framebuffer::Framebuffer;
use relief_core::settings::{Filter, Normals, Settings, Shading};
use relief_scene::Light;
use relief_scene::Scene;
use relief_texture::{Level, Texture};

const W: usize = 160;
const H: usize = 120;

/// Pixels of the textured faces: where a black texture makes the cube black.
fn textured_mask(all_faces: bool, settings: &Settings) -> Vec<bool> {
    let black = plain_scene([0.0, 0.0, 0.0, 0.5], all_faces);
    let s = Settings {
        texture: true,
        ..*settings
    };
    let (fb, _) = render(&black, &s, W, H);
    fb.pixels().iter().map(|&p| p == [0, 0, 0]).collect()
}

fn differing(a: &Framebuffer, b: &Framebuffer) -> Vec<bool> {
    a.pixels()
        .iter()
        .zip(b.pixels())
        .map(|(x, y)| x != y)
        .collect()
}

#[test]
fn texture_and_bump_toggles_only_change_the_textured_faces() {
    let scene = reference_scene(false);
    let base = Settings::default();
    let mask = textured_mask(false, &base);
    assert!(
        mask.iter().filter(|&&m| m).count() > 1000,
        "the front face is visible"
    );
    let on = render(&scene, &base, W, H).0;
    for other in [
        Settings {
            texture: false,
            ..base
        },
        Settings {
            bump: false,
            ..base
        },
    ] {
        let off = render(&scene, &other, W, H).0;
        let diff = differing(&on, &off);
        assert!(diff.iter().any(|&d| d), "the toggle changed nothing");
        assert!(
            diff.iter().zip(&mask).all(|(&d, &m)| !d || m),
            "an untextured pixel changed"
        );
    }
}

#[test]
fn bump_shows_in_phong_only() {
    let scene = reference_scene(true);
    for shading in [Shading::Flat, Shading::Gouraud] {
        let on = render(
            &scene,
            &Settings {
                shading,
                ..Settings::default()
            },
            W,
            H,
        );
        let off = render(
            &scene,
            &Settings {
                shading,
                bump: false,
                ..Settings::default()
            },
            W,
            H,
        );
        assert_eq!(on.0, off.0);
        assert_eq!(on.1.counters.bump_evals, 0);
    }
    let on = render(&scene, &Settings::default(), W, H).0;
    let off = render(
        &scene,
        &Settings {
            bump: false,
            ..Settings::default()
        },
        W,
        H,
    )
    .0;
    assert_ne!(on, off);
}

#[test]
fn normals_switch_changes_gouraud_and_phong_but_not_flat() {
    let scene = reference_scene(true);
    for shading in [Shading::Flat, Shading::Gouraud, Shading::Phong] {
        let vertex = render(
            &scene,
            &Settings {
                shading,
                ..Settings::default()
            },
            W,
            H,
        )
        .0;
        let face = render(
            &scene,
            &Settings {
                shading,
                normals: Normals::Face,
                ..Settings::default()
            },
            W,
            H,
        )
        .0;
        assert_eq!(vertex == face, shading == Shading::Flat, "{shading:?}");
    }
}

#[test]
fn colours_off_and_texture_off_under_white_light_is_a_grey_cube() {
    let mut scene = reference_scene(true);
    scene.lights.truncate(1); // the white light alone
    let settings = Settings {
        colors: false,
        texture: false,
        bump: false,
        ..Settings::default()
    };
    for shading in [Shading::Flat, Shading::Gouraud, Shading::Phong] {
        let (fb, _) = render(
            &scene,
            &Settings {
                shading,
                ..settings
            },
            W,
            H,
        );
        let cube: Vec<_> = fb
            .pixels()
            .iter()
            .filter(|&&p| p != scene.background)
            .collect();
        assert!(cube.len() > 1000);
        assert!(
            cube.iter().all(|p| p[0] == p[1] && p[1] == p[2]),
            "{shading:?}"
        );
    }
    // Colours on: the same view is no longer grey.
    let (fb, _) = render(
        &scene,
        &Settings {
            colors: true,
            ..settings
        },
        W,
        H,
    );
    assert!(fb.pixels().iter().any(|p| p[0] != p[2]));
}

#[test]
fn texture_off_reads_no_texel() {
    let scene = reference_scene(true);
    for shading in [Shading::Flat, Shading::Gouraud, Shading::Phong] {
        let s = Settings {
            shading,
            texture: false,
            bump: false,
            ..Settings::default()
        };
        let stats = render(&scene, &s, W, H).1;
        assert_eq!(stats.counters.texture_samples, 0, "{shading:?}");
        assert!(stats.counters.pixels_shaded > 0);
    }
}

#[test]
fn texture_is_read_only_on_textured_faces() {
    let front_back = render(&reference_scene(false), &Settings::default(), W, H)
        .1
        .counters;
    let all = render(&reference_scene(true), &Settings::default(), W, H)
        .1
        .counters;
    assert_eq!(all.texture_samples, all.pixels_shaded);
    assert!(
        front_back.texture_samples > 0 && front_back.texture_samples < front_back.pixels_shaded
    );
    assert_eq!(front_back.bump_evals, front_back.texture_samples);
}

#[test]
fn bump_work_is_zero_outside_phong_when_off_at_strength_zero_or_on_a_flat_height_map() {
    let scene = reference_scene(true);
    let flat_heights = plain_scene([0.6, 0.5, 0.4, 0.3], true);
    let cases = [
        (
            &scene,
            Settings {
                shading: Shading::Flat,
                ..Settings::default()
            },
        ),
        (
            &scene,
            Settings {
                shading: Shading::Gouraud,
                ..Settings::default()
            },
        ),
        (
            &scene,
            Settings {
                bump: false,
                ..Settings::default()
            },
        ),
        (
            &scene,
            Settings {
                bump_strength: 0.0,
                ..Settings::default()
            },
        ),
        (&flat_heights, Settings::default()),
    ];
    for (scene, s) in cases {
        assert_eq!(render(scene, &s, W, H).1.counters.bump_evals, 0, "{s:?}");
    }
    let on = render(&scene, &Settings::default(), W, H).1.counters;
    assert_eq!(on.bump_evals, on.pixels_shaded);
}

#[test]
fn lighting_work_follows_the_mode_and_skips_dark_lights() {
    let scene = reference_scene(true);
    let phong = render(&scene, &Settings::default(), W, H).1.counters;
    assert_eq!(phong.light_evals, 4 * phong.pixels_shaded);
    // Gouraud lights three vertices per drawn triangle, flat one facet.
    let gouraud = render(
        &scene,
        &Settings {
            shading: Shading::Gouraud,
            ..Settings::default()
        },
        W,
        H,
    )
    .1
    .counters;
    assert_eq!(gouraud.light_evals, 4 * 3 * gouraud.triangles_drawn);
    let flat = render(
        &scene,
        &Settings {
            shading: Shading::Flat,
            ..Settings::default()
        },
        W,
        H,
    )
    .1
    .counters;
    assert_eq!(flat.light_evals, 4 * flat.triangles_drawn);
    // Lights off: none evaluated. A black or disabled light: skipped.
    let off = render(
        &scene,
        &Settings {
            lights: false,
            ..Settings::default()
        },
        W,
        H,
    )
    .1
    .counters;
    assert_eq!(off.light_evals, 0);
    let mut dim = reference_scene(true);
    dim.lights[1].color = Vec3::ZERO;
    dim.lights[2].enabled = false;
    let two = render(&dim, &Settings::default(), W, H).1.counters;
    assert_eq!(two.light_evals, 2 * two.pixels_shaded);
}

#[test]
fn one_convex_object_needs_no_depth_buffer() {
    let scene = reference_scene(true);
    for shading in [Shading::Flat, Shading::Gouraud, Shading::Phong] {
        let s = Settings {
            shading,
            ..Settings::default()
        };
        assert_eq!(render(&scene, &s, W, H).1.counters.depth_tests, 0);
    }
    // Two objects may overlap: depth is tested, and the nearer one wins.
    let mut two = reference_scene(true);
    let mut behind = two.objects[0].clone();
    behind.transform = glam::Mat4::from_translation(Vec3::new(0.5, 0.3, -2.0));
    two.objects.insert(0, behind);
    // Face normals and no bump: two objects make a shadow pass, which puts
    // the faces turned away from the light in shadow, and only smoothed or
    // bumped normals light those.
    let faces = Settings {
        normals: Normals::Face,
        bump: false,
        ..Settings::default()
    };
    let (fb, stats) = render(&two, &faces, W, H);
    assert!(stats.counters.depth_tests > 0);
    let (alone, _) = render(&scene, &faces, W, H);
    // Wherever the front cube is drawn alone, it is drawn the same in front.
    for (a, b) in alone.pixels().iter().zip(fb.pixels()) {
        if *a != scene.background {
            assert_eq!(a, b);
        }
    }
}

#[test]
fn magnifying_filters_never_build_a_mip_chain() {
    let tex = Arc::new(Texture::new(
        "fresh",
        Level::solid(64, 64, [0.5, 0.5, 0.5, 0.5]),
    ));
    let scene = Scene::cube(tex.clone(), true);
    for filter in [Filter::Nearest, Filter::Bilinear] {
        let stats = render(
            &scene,
            &Settings {
                filter,
                ..Settings::default()
            },
            W,
            H,
        )
        .1;
        assert_eq!(stats.counters.mip_builds, 0);
    }
    assert!(!tex.mips_built());
}

#[test]
fn a_light_inside_the_scene_gives_the_same_frame_as_a_disabled_one_when_it_is_black() {
    let scene = reference_scene(true);
    let mut with_black = reference_scene(true);
    with_black
        .lights
        .push(Light::new(Vec3::new(1.0, 2.0, 3.0), Vec3::ZERO));
    assert_eq!(
        render(&scene, &Settings::default(), W, H).0,
        render(&with_black, &Settings::default(), W, H).0
    );
}
