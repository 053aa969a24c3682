//! Shadow mapping: the shadow falls where geometry says, the pass runs only
//! where something can cast onto something else.

use std::sync::Arc;

use glam::Vec3;
use relief_core::framebuffer::Framebuffer;
use relief_core::settings::Settings;
use relief_core::settings::{Display, LightVector, Shading, Technique};
use relief_core::stats::Counters;
use relief_pipeline::plan::Plan;
use relief_pipeline::render::render_frame;
use relief_pipeline::shadow::ShadowMap;
use relief_scene::build::FLOOR_Y;
use relief_scene::{Built, ModelChoice, Scene, SceneKind, build_scene};
use relief_texture::decode::procedural;

fn texture() -> Arc<relief_texture::Texture> {
    Arc::new(procedural::brick())
}

fn scene(kind: SceneKind, model: ModelChoice) -> Scene {
    match build_scene(kind, &model, texture(), false).unwrap() {
        Built::Scene(s) => *s,
        Built::Plasma(_) => panic!("a 3D scene"),
    }
}

/// Object indices in the shadow scene.
const CUBE: u32 = 0;
const FLOOR: u32 = 1;

fn shadow_scene() -> Scene {
    scene(SceneKind::Shadow, ModelChoice::Cube)
}

/// Where the ray from `light` through `through` meets the floor.
fn on_floor(light: Vec3, through: Vec3) -> Vec3 {
    let t = (light.y - FLOOR_Y) / (light.y - through.y);
    light + t * (through - light)
}

/// The pixel where world point `p` lands.
fn pixel_of(scene: &Scene, p: Vec3, w: usize, h: usize) -> (usize, usize) {
    let clip = scene.camera.projection(w as f32 / h as f32) * scene.camera.view() * p.extend(1.0);
    let ndc = clip.truncate() / clip.w;
    assert!(
        clip.w > 0.0 && ndc.x.abs() < 1.0 && ndc.y.abs() < 1.0,
        "{p} is out of view"
    );
    (
        ((ndc.x * 0.5 + 0.5) * w as f32) as usize,
        ((0.5 - ndc.y * 0.5) * h as f32) as usize,
    )
}

#[test]
fn the_floor_under_the_cube_is_in_shadow_and_far_out_is_lit() {
    let scene = shadow_scene();
    for rotation in [
        Vec3::new(25.0, 35.0, 0.0),
        Vec3::ZERO,
        Vec3::new(-70.0, 10.0, 200.0),
    ] {
        let settings = Settings {
            rotation,
            ..Settings::default()
        };
        let plan = Plan::new(&scene, &settings);
        assert_eq!(plan.shadow_light, Some(0), "the strong white light");
        let light = plan.lights[0].position;
        let mut map = ShadowMap::new();
        let counters = map.render(&scene, plan.rotation, light, &plan.shadow_casters, 320, 240);
        assert!(counters.shadow_texels > 0);
        let under = on_floor(light, Vec3::ZERO);
        assert_eq!(
            map.visibility(under, Vec3::Y, FLOOR),
            0.0,
            "{rotation}: {under}"
        );
        // Around it too: the cube's shadow is about two units wide.
        for d in [Vec3::X, Vec3::Z, -Vec3::X, -Vec3::Z] {
            assert_eq!(map.visibility(under + 0.3 * d, Vec3::Y, FLOOR), 0.0);
        }
        // Far out on the floor, on the light's side, and beyond the shadow.
        for far in [
            Vec3::new(4.5, FLOOR_Y, 4.5),
            Vec3::new(-5.0, FLOOR_Y, 3.0),
            Vec3::new(4.0, FLOOR_Y, -4.0),
        ] {
            assert_eq!(
                map.visibility(far, Vec3::Y, FLOOR),
                1.0,
                "{rotation}: {far}"
            );
        }
        // Just behind the cube as seen from the light: a point of the floor
        // there is in shadow; the cube (convex) is never shaded by its own
        // texels, but a point of it whose normal turns away from the light
        // is in shadow by that alone.
        let back = -2.0 * light.normalize();
        assert_eq!(map.visibility(back, light.normalize(), CUBE), 1.0);
        assert_eq!(map.visibility(back, -light.normalize(), CUBE), 0.0);
        assert_eq!(map.visibility(back, light.normalize(), FLOOR), 0.0);
    }
}

#[test]
fn the_shadow_darkens_only_the_white_lights_share() {
    let (w, h) = (320, 240);
    let scene = shadow_scene();
    let settings = Settings::default();
    let light = scene.lights[0].position;
    let under = on_floor(light, Vec3::ZERO);
    let far = Vec3::new(3.0, FLOOR_Y, 4.0);
    // The same floor alone: no caster, so no shadow pass.
    let mut floor_only = scene.clone();
    floor_only.objects.remove(0);
    let mut floor_dark = floor_only.clone();
    floor_dark.lights[0].enabled = false;
    let (with_cube, stats) = render_frame(&scene, &settings, w, h);
    let (alone, alone_stats) = render_frame(&floor_only, &settings, w, h);
    let (dark, _) = render_frame(&floor_dark, &settings, w, h);
    assert!(stats.counters.shadow_lookups > 0);
    assert_eq!(alone_stats.counters.shadow_texels, 0);
    assert_eq!(alone_stats.counters.shadow_lookups, 0);
    let (x, y) = pixel_of(&scene, under, w, h);
    // In the shadow: exactly the floor without the white light.
    assert_eq!(with_cube.get(x, y), dark.get(x, y), "pixel ({x}, {y})");
    assert!(alone.get(x, y)[0] > dark.get(x, y)[0] + 40);
    let (x, y) = pixel_of(&scene, far, w, h);
    // Far from it: exactly the floor with all its light.
    assert_eq!(with_cube.get(x, y), alone.get(x, y), "pixel ({x}, {y})");
    assert_eq!(stats.counters.nonfinite, 0);
}

#[test]
fn flat_and_gouraud_shading_see_the_shadow_too() {
    let (w, h) = (320, 240);
    let scene = shadow_scene();
    let light = scene.lights[0].position;
    let under = on_floor(light, Vec3::ZERO);
    let (x, y) = pixel_of(&scene, under, w, h);
    for shading in [Shading::Flat, Shading::Gouraud] {
        let settings = Settings {
            shading,
            ..Settings::default()
        };
        let mut unshadowed = scene.clone();
        // The cube moved far away: still two objects (and a pass), no shadow on the floor.
        unshadowed.objects[0].transform = glam::Mat4::from_translation(Vec3::new(0.0, 0.0, 50.0));
        let (a, stats) = render_frame(&scene, &settings, w, h);
        let (b, _) = render_frame(&unshadowed, &settings, w, h);
        assert!(stats.counters.shadow_lookups > 0, "{shading:?}");
        // The floor is lit per cell (flat) or per vertex (Gouraud), so the
        // whole neighbourhood of the shadow centre is at least as dark.
        assert!(a.get(x, y)[0] < b.get(x, y)[0], "{shading:?}");
    }
}

/// Every bump technique in Phong, and dot3's two light vectors.
fn every_technique() -> Vec<Settings> {
    let mut all = Vec::new();
    for technique in [
        Technique::Blinn,
        Technique::Emboss,
        Technique::Dot3,
        Technique::Parallax,
        Technique::Pom,
    ] {
        for light_vector in [LightVector::Pixel, LightVector::Vertex] {
            if light_vector == LightVector::Vertex && technique != Technique::Dot3 {
                continue;
            }
            for bump in [true, false] {
                all.push(Settings {
                    technique,
                    light_vector,
                    bump,
                    ..Settings::default()
                });
            }
        }
    }
    all
}

#[test]
fn the_floor_shadow_shows_whatever_the_cubes_technique() {
    let (w, h) = (320, 240);
    let scene = shadow_scene();
    let light = scene.lights[0].position;
    let (x, y) = pixel_of(&scene, on_floor(light, Vec3::ZERO), w, h);
    let far = pixel_of(&scene, Vec3::new(3.0, FLOOR_Y, 4.0), w, h);
    let mut unshadowed = scene.clone();
    // The cube moved far away: the same two objects and pass, no shadow on the floor.
    unshadowed.objects[0].transform = glam::Mat4::from_translation(Vec3::new(0.0, 0.0, 50.0));
    for settings in every_technique() {
        let what = format!(
            "{:?} {:?} bump {}",
            settings.technique, settings.light_vector, settings.bump
        );
        let (a, stats) = render_frame(&scene, &settings, w, h);
        let (b, _) = render_frame(&unshadowed, &settings, w, h);
        assert!(stats.counters.shadow_lookups > 0, "{what}");
        assert_eq!(stats.counters.nonfinite, 0, "{what}");
        // The white light's share is gone under the cube...
        let (dark, lit) = (a.get(x, y), b.get(x, y));
        for c in 0..3 {
            assert!(dark[c] + 40 < lit[c], "{what}: {dark:?} vs {lit:?}");
        }
        // ...and nothing changes far from it.
        assert_eq!(a.get(far.0, far.1), b.get(far.0, far.1), "{what}");
    }
}

/// The reference cube (bumped on every face) with a small square between the
/// white light and the centre of the face turned most toward the camera:
/// the square shades that face's centre. Returns the scene, the pixel of the
/// shaded point, and the same scene with the square moved far away.
fn cube_under_a_caster(settings: &Settings, w: usize, h: usize) -> (Scene, (usize, usize), Scene) {
    let mut scene = Scene::cube(texture(), true);
    let turn = relief_scene::rotation_matrix(settings.rotation);
    let to_eye = scene.camera.eye.normalize();
    let normal = [Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z, -Vec3::Z]
        .map(|n| turn.transform_vector3(n))
        .into_iter()
        .max_by(|a, b| a.dot(to_eye).total_cmp(&b.dot(to_eye)))
        .unwrap();
    let p = normal; // the face centre of a cube of side 2
    let light = scene.lights[0].position;
    let toward = (light - p).normalize();
    assert!(toward.dot(normal) > 0.3, "the white light faces that face");
    let square = relief_scene::plane::grid(0.12, 1.0, 1, |_| Vec3::ONE);
    let place = |at: Vec3| {
        glam::Mat4::from_translation(at)
            * glam::Mat4::from_quat(glam::Quat::from_rotation_arc(Vec3::Z, toward))
    };
    scene.objects.push(relief_scene::Object {
        mesh: square,
        transform: place(p + 0.5 * toward),
        rotates: false,
    });
    let mut away = scene.clone();
    away.objects[1].transform = place(Vec3::new(0.0, 40.0, 0.0));
    let pixel = pixel_of(&scene, p, w, h);
    (scene, pixel, away)
}

#[test]
fn every_bump_technique_sees_a_shadow_on_the_bumped_cube() {
    let (w, h) = (320, 240);
    for settings in every_technique() {
        let what = format!(
            "{:?} {:?} bump {}",
            settings.technique, settings.light_vector, settings.bump
        );
        let (scene, (x, y), away) = cube_under_a_caster(&settings, w, h);
        let (a, stats) = render_frame(&scene, &settings, w, h);
        let (b, _) = render_frame(&away, &settings, w, h);
        assert!(stats.counters.shadow_lookups > 0, "{what}");
        assert!(stats.counters.bump_evals > 0 || !settings.bump, "{what}");
        assert_eq!(stats.counters.nonfinite, 0, "{what}");
        let (dark, lit) = (a.get(x, y), b.get(x, y));
        // The white light's share is gone in every channel (dot3 with the
        // per-vertex light vector has the least of it: the interpolated
        // vector is short at a face centre).
        for c in 0..3 {
            assert!(
                dark[c] + 8 < lit[c],
                "{what}: {dark:?} vs {lit:?} at ({x}, {y})"
            );
        }
    }
}

#[test]
fn in_the_embossed_lights_shadow_its_relief_goes_with_it() {
    // Emboss adds its relief to the strongest light's N·L; where the caster
    // hides that light the point is lit by the weak lights on the smooth
    // surface: what Phong without bump gives there.
    let (w, h) = (320, 240);
    let emboss = Settings {
        technique: Technique::Emboss,
        ..Settings::default()
    };
    let smooth = Settings {
        bump: false,
        ..Settings::default()
    };
    let (scene, (x, y), away) = cube_under_a_caster(&emboss, w, h);
    let (a, _) = render_frame(&scene, &emboss, w, h);
    let (b, _) = render_frame(&scene, &smooth, w, h);
    let (a, b) = (a.get(x, y), b.get(x, y));
    for c in 0..3 {
        assert!(a[c].abs_diff(b[c]) <= 1, "emboss {a:?} smooth {b:?}");
    }
    // In the light, emboss shows relief on that face.
    let (a, _) = render_frame(&away, &emboss, w, h);
    let (b, _) = render_frame(&away, &smooth, w, h);
    let differ = (y.saturating_sub(8)..y + 8)
        .flat_map(|yy| (x.saturating_sub(8)..x + 8).map(move |xx| (xx, yy)))
        .filter(|&(xx, yy)| a.get(xx, yy) != b.get(xx, yy))
        .count();
    assert!(differ > 50, "{differ}");
}

#[test]
fn no_shadow_pass_for_a_lone_convex_or_flat_model() {
    for model in [
        ModelChoice::Cube,
        ModelChoice::Sphere,
        ModelChoice::Plane,
        ModelChoice::Triangle,
    ] {
        let s = scene(SceneKind::Cube, model.clone());
        for shading in [Shading::Flat, Shading::Gouraud, Shading::Phong] {
            let settings = Settings {
                shading,
                ..Settings::default()
            };
            assert_eq!(Plan::new(&s, &settings).shadow_light, None);
            let (_, stats) = render_frame(&s, &settings, 160, 120);
            assert_eq!(stats.counters.shadow_texels, 0, "{model} {shading:?}");
            assert_eq!(stats.counters.shadow_lookups, 0, "{model} {shading:?}");
        }
        for settings in every_technique() {
            let (_, stats) = render_frame(&s, &settings, 160, 120);
            let what = format!("{model} {:?}", settings.technique);
            assert_eq!(stats.counters.shadow_texels, 0, "{what}");
            assert_eq!(stats.counters.shadow_lookups, 0, "{what}");
        }
    }
    // The reference scene exactly as the lead's constructor builds it.
    let reference = Scene::cube(texture(), true);
    let (_, stats) = render_frame(&reference, &Settings::default(), 320, 240);
    assert_eq!(
        stats.counters.shadow_texels + stats.counters.shadow_lookups,
        0
    );
}

#[test]
fn no_shadow_pass_without_lights_and_one_for_self_shadowing_models() {
    let s = shadow_scene();
    let off = Settings {
        lights: false,
        ..Settings::default()
    };
    let (_, stats) = render_frame(&s, &off, 160, 120);
    assert_eq!(
        stats.counters.shadow_texels + stats.counters.shadow_lookups,
        0
    );
    let mut all_disabled = s.clone();
    for l in &mut all_disabled.lights {
        l.enabled = false;
    }
    assert_eq!(
        Plan::new(&all_disabled, &Settings::default()).shadow_light,
        None
    );
    // A lone OBJ found convex when loaded (this pyramid) draws no pass.
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/pyramid_relative.obj");
    let plain = scene(SceneKind::Cube, ModelChoice::File(path));
    assert!(plain.objects[0].mesh.convex);
    let (fb_plain, stats_plain) = render_frame(&plain, &Settings::default(), 160, 120);
    assert_eq!(stats_plain.counters.shadow_texels, 0);
    // Not known to be convex, its parts may shade each other: the pass is drawn.
    let mut obj = plain.clone();
    obj.objects[0].mesh.convex = false;
    let (fb, stats) = render_frame(&obj, &Settings::default(), 160, 120);
    assert!(stats.counters.shadow_texels > 0);
    assert_eq!(stats.counters.nonfinite, 0);
    // Its lit faces are not darkened by themselves (no acne): the render
    // equals the one without the shadow pass wherever the pyramid is convex,
    // which is everywhere.
    assert_eq!(fb, fb_plain);
}

#[test]
fn a_floor_lit_from_below_casts_onto_the_cube() {
    // A flat object with the light behind it is a caster: here a smaller
    // floor (so the light stays outside the casters' bounds) shades the
    // cube's bottom from a light underneath.
    let mut s = shadow_scene();
    s.objects[1].mesh = relief_scene::plane::grid(2.5, 1.0, 4, |_| Vec3::ONE);
    s.lights[0].position = Vec3::new(0.3, -9.0, 0.2);
    let plan = Plan::new(&s, &Settings::default());
    let index = plan.shadow_light.expect("a shadow pass");
    let mut map = ShadowMap::new();
    map.render(
        &s,
        plan.rotation,
        plan.lights[index].position,
        &plan.shadow_casters,
        160,
        120,
    );
    assert_eq!(
        map.visibility(Vec3::new(0.0, -1.0, 0.0), -Vec3::Y, CUBE),
        0.0
    );
    // Seen from above the same floor casts nothing: no pass at all.
    s.lights[0].position = Vec3::new(0.3, 9.0, 0.2);
    let mut lone_floor = s.clone();
    lone_floor.objects.remove(0);
    assert_eq!(
        Plan::new(&lone_floor, &Settings::default()).shadow_light,
        None
    );
}

#[test]
fn any_size_renders_the_shadow_scene_without_trouble() {
    let s = shadow_scene();
    for (w, h) in [(1, 1), (1, 64), (64, 1), (7, 5), (2000, 30)] {
        let mut fb = Framebuffer::new(w, h);
        let stats =
            relief_pipeline::render::Renderer::new().render(&s, &Settings::default(), &mut fb);
        assert_eq!(stats.counters.nonfinite, 0, "{w}x{h}");
    }
    let size = ShadowMap::size_for(100_000, 3);
    assert_eq!(size, relief_pipeline::shadow::MAX_SIZE);
    assert_eq!(ShadowMap::size_for(1, 1), relief_pipeline::shadow::MIN_SIZE);
}

#[test]
fn every_technique_darkens_a_textured_floor_in_the_shadow() {
    let (w, h) = (320, 240);
    let mut scene = shadow_scene();
    for tri in &mut scene.objects[FLOOR as usize].mesh.triangles {
        tri.textured = true;
    }
    let mut away = scene.clone();
    away.objects[CUBE as usize].transform = glam::Mat4::from_translation(Vec3::new(0.0, 0.0, 50.0));
    let light = scene.lights[0].position;
    let (x, y) = pixel_of(&scene, on_floor(light, Vec3::ZERO), w, h);
    let (fx, fy) = pixel_of(&scene, Vec3::new(3.0, FLOOR_Y, 4.0), w, h);
    let lone = Scene::cube(texture(), true);
    for settings in every_technique() {
        let technique = settings.technique;
        let (a, stats) = render_frame(&scene, &settings, w, h);
        let (b, _) = render_frame(&away, &settings, w, h);
        assert!(stats.counters.shadow_lookups > 0, "{technique:?}");
        // Summed over a 5×5 patch: emboss may zero a lit texel's light.
        let patch = |fb: &Framebuffer| -> u32 {
            (0..25)
                .map(|i| fb.get(x + i % 5 - 2, y + i / 5 - 2))
                .map(|c| c.iter().map(|&v| v as u32).sum::<u32>())
                .sum()
        };
        assert!(patch(&a) < patch(&b), "{technique:?}");
        assert_eq!(a.get(fx, fy), b.get(fx, fy), "{technique:?} lit pixel");
        let (_, lone_stats) = render_frame(&lone, &settings, w, h);
        assert_eq!(
            lone_stats.counters.shadow_lookups + lone_stats.counters.shadow_texels,
            0
        );
    }
}

#[test]
fn points_and_lines_draw_no_shadow_map() {
    // Their colours never read it: the pass would be work for nothing.
    let s = shadow_scene();
    for display in [Display::Points, Display::Lines, Display::Fill] {
        let settings = Settings {
            display,
            ..Settings::default()
        };
        let (_, stats) = render_frame(&s, &settings, 160, 120);
        let drawn = stats.counters.shadow_texels > 0;
        assert_eq!(drawn, display == Display::Fill, "{display:?}");
        assert_eq!(Plan::new(&s, &settings).shadow_light.is_some(), drawn);
    }
}

#[test]
fn the_shadowed_light_is_the_one_emboss_follows_even_on_a_tie() {
    let mut s = shadow_scene();
    // Two equally bright white lights: the first is both emboss's light
    // and the shadow map's.
    s.lights[1].color = s.lights[0].color;
    s.lights[1].position = Vec3::new(-3.0, 5.0, 4.0);
    let plan = Plan::new(&s, &Settings::default());
    assert_eq!(
        plan.shadow_light,
        relief_pipeline::plan::strongest_light(&plan.lights)
    );
    assert_eq!(plan.shadow_light, Some(0));
}

/// The shadow scene with its cube replaced by a horizontal square of side
/// 2 at y = 0 (u = (x + 1)/2), cut out over x > 0 when `masked`: an alpha
/// map of four texels 1, 1, 0, 0 read bilinearly with wrapping is ≥ 0.5
/// exactly for u in [0, 0.5].
fn masked_square_over_the_floor(masked: bool) -> Scene {
    use relief_scene::terms::{Cutout, MaterialTerms};
    use relief_texture::Level;
    let mut scene = shadow_scene();
    scene.objects[0] = relief_scene::Object {
        mesh: relief_scene::plane::plane(),
        transform: glam::Mat4::from_rotation_x(-std::f32::consts::FRAC_PI_2),
        rotates: false,
    };
    if masked {
        let alpha = |a: f32| [a, a, a, 1.0];
        let map = Level::from_texels(4, 1, vec![alpha(1.0), alpha(1.0), alpha(0.0), alpha(0.0)]);
        let terms = MaterialTerms {
            cutout: Some(Cutout {
                factor: 1.0,
                map: Some(Arc::new(map)),
                cutoff: 0.5,
                blend: false,
                transmission: None,
                tint: glam::Vec3::ONE,
            }),
            ..Default::default()
        };
        scene.object_terms = vec![Some(Arc::new(terms)), None];
    }
    scene
}

#[test]
fn a_masked_caster_lets_the_light_through_where_the_mask_cuts() {
    let (w, h) = (320, 240);
    let settings = Settings::default();
    let light = shadow_scene().lights[0].position;
    // Under the kept half (x = −0.5) and under the cut half (x = 0.5).
    let kept = on_floor(light, Vec3::new(-0.5, 0.0, 0.0));
    let cut = on_floor(light, Vec3::new(0.5, 0.0, 0.0));
    let mut floor_only = shadow_scene();
    floor_only.objects.remove(0);
    let (alone, _) = render_frame(&floor_only, &settings, w, h);
    for masked in [false, true] {
        let scene = masked_square_over_the_floor(masked);
        let plan = Plan::new(&scene, &settings);
        assert_eq!(plan.shadow_light, Some(0));
        let mut map = ShadowMap::new();
        map.render(&scene, plan.rotation, light, &plan.shadow_casters, w, h);
        assert_eq!(map.visibility(kept, Vec3::Y, FLOOR), 0.0, "masked {masked}");
        let expected = if masked { 1.0 } else { 0.0 };
        assert_eq!(
            map.visibility(cut, Vec3::Y, FLOOR),
            expected,
            "masked {masked}"
        );
        // In the picture: where the light comes through, the floor is as
        // it is with no caster at all.
        let (fb, _) = render_frame(&scene, &settings, w, h);
        let (kx, ky) = pixel_of(&scene, kept, w, h);
        let (cx, cy) = pixel_of(&scene, cut, w, h);
        assert!(
            fb.get(kx, ky)[0] + 40 < alone.get(kx, ky)[0],
            "masked {masked}"
        );
        assert_eq!(
            fb.get(cx, cy) == alone.get(cx, cy),
            masked,
            "masked {masked}: {:?} {:?}",
            fb.get(cx, cy),
            alone.get(cx, cy)
        );
    }
}

/// The map is filled in bands of rows, in parallel on a pool of several
/// threads: every texel keeps the same depth and owner as on one thread,
/// ties included (a second cube at the same place as the first loses
/// every texel to it, the earlier caster, as in one pass).
#[test]
fn the_map_is_the_same_on_one_thread_and_on_several() {
    let mut scene = shadow_scene();
    scene.objects.push(scene.objects[CUBE as usize].clone());
    let twin = scene.objects.len() - 1;
    let plan = Plan::new(&scene, &Settings::default());
    let light = plan.lights[plan.shadow_light.expect("a shadow pass")].position;
    let mut casters = plan.shadow_casters.clone();
    let cube = *casters
        .iter()
        .find(|c| c.object == CUBE as usize)
        .expect("the cube casts");
    casters.retain(|c| c.object != twin);
    casters.push(relief_scene::casters::Caster {
        object: twin,
        ..cube
    });
    let draw = |map: &mut ShadowMap| map.render(&scene, plan.rotation, light, &casters, 640, 480);
    let one = map_on_threads(1, &draw);
    let cube_texels = one.1.iter().filter(|&&o| o == CUBE).count();
    // Enough to fill for the pass to share the rows out (see depth.rs).
    assert!(cube_texels > 100_000, "{cube_texels}");
    assert!(!one.1.contains(&(twin as u32)), "ties go to the first");
    assert_same_on_more_threads(&one, &draw);
}

/// A map's texels: each one's depth bits and owner, and the count written.
type MapTexels = (Vec<u32>, Vec<u32>, u64);

/// The map `draw` makes on a pool of `threads` threads.
fn map_on_threads(threads: usize, draw: &(dyn Fn(&mut ShadowMap) -> Counters + Sync)) -> MapTexels {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("a pool");
    pool.install(|| {
        let mut map = ShadowMap::new();
        let counters = draw(&mut map);
        let (depth, owner) = map.texels();
        let bits: Vec<u32> = depth.iter().map(|d| d.to_bits()).collect();
        (bits, owner.to_vec(), counters.shadow_texels)
    })
}

/// The map `draw` makes on 2, 3 and 4 threads is `one`, made on one.
fn assert_same_on_more_threads(
    one: &MapTexels,
    draw: &(dyn Fn(&mut ShadowMap) -> Counters + Sync),
) {
    for threads in [2, 3, 4] {
        let many = map_on_threads(threads, draw);
        assert!(many.0 == one.0, "depths on {threads} threads");
        assert!(many.1 == one.1, "owners on {threads} threads");
        assert_eq!(many.2, one.2, "texels written on {threads} threads");
    }
}

/// A big caster is set up in chunks of triangles on the threads, then
/// joined in order: a 58 k-triangle closed sphere, with repeated triangles
/// whose first copies lie in another chunk, gives every texel the same
/// depth and owner, and the same count of texels written, on one thread
/// and on several.
#[test]
fn a_big_caster_is_set_up_the_same_on_one_thread_and_on_several() {
    use relief_scene::world::World;
    use relief_scene::{Mesh, Triangle};
    let mut scene = shadow_scene();
    let (vertices, mut triangles) = sphere(121, 240, 0.0);
    let first: Vec<Triangle> = triangles[..500].to_vec();
    triangles.extend(first);
    assert!(triangles.len() > 3 * 16_384, "{}", triangles.len());
    let repeats = relief_scene::repeats::find_repeats(&triangles);
    assert_eq!(repeats.len(), 500);
    scene.objects[CUBE as usize].mesh = Mesh::of_triangles(vertices, triangles, false, true);
    let plan = Plan::new(&scene, &Settings::default());
    let light = plan.lights[plan.shadow_light.expect("a shadow pass")].position;
    let world = World::of(&scene, plan.rotation);
    let mut all_repeats: Vec<&[(u32, u32)]> = vec![&[]; scene.objects.len()];
    all_repeats[CUBE as usize] = &repeats;
    let draw = |map: &mut ShadowMap| {
        map.render_placed(
            &scene,
            &world,
            light,
            &plan.shadow_casters,
            640,
            480,
            &all_repeats,
            &relief_pipeline::shadow::Unwatched,
        )
    };
    let one = map_on_threads(1, &draw);
    let sphere_texels = one.1.iter().filter(|&&o| o == CUBE).count();
    assert!(sphere_texels > 10_000, "{sphere_texels}");
    assert_same_on_more_threads(&one, &draw);
}

/// A UV sphere of radius 0.8 with `rings` rings of `segments` vertices
/// (poles included as rings of one place), its radius dented by
/// `1 + dent·sin 7θ·sin 9φ`: its vertices and outward-wound triangles.
fn sphere(
    rings: u32,
    segments: u32,
    dent: f32,
) -> (Vec<relief_scene::Vertex>, Vec<relief_scene::Triangle>) {
    use relief_scene::{Triangle, Vertex};
    let mut vertices = Vec::new();
    for i in 0..=rings {
        let theta = std::f32::consts::PI * i as f32 / rings as f32;
        for j in 0..segments {
            let phi = std::f32::consts::TAU * j as f32 / segments as f32;
            let p = Vec3::new(
                theta.sin() * phi.cos(),
                theta.cos(),
                theta.sin() * phi.sin(),
            );
            let radius = 0.8 * (1.0 + dent * (7.0 * theta).sin() * (9.0 * phi).sin());
            vertices.push(Vertex {
                position: p * radius,
                normal: p,
                uv: glam::Vec2::ZERO,
                color: Vec3::ONE,
                tangent_u: Vec3::X,
                tangent_v: Vec3::Y,
            });
        }
    }
    let at = |i: u32, j: u32| i * segments + j % segments;
    let mut triangles = Vec::new();
    for i in 0..rings {
        for j in 0..segments {
            let (a, b, c, d) = (at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i + 1, j));
            triangles.push(Triangle::new([a, c, b], true));
            triangles.push(Triangle::new([a, d, c], true));
        }
    }
    (vertices, triangles)
}

/// The shadow scene with its cube replaced by a dented sphere of 130 k
/// triangles (closed, not convex): a dense caster, shadowing itself and
/// the floor.
fn dense_caster_scene() -> Scene {
    let mut scene = shadow_scene();
    let (vertices, triangles) = sphere(181, 360, 0.06);
    assert!(triangles.len() >= relief_pipeline::shadow::LOD_MIN_TRIANGLES);
    let mesh = relief_scene::Mesh::of_triangles(vertices, triangles, false, true);
    scene.objects[CUBE as usize].mesh = mesh;
    scene
}

/// A frame of `scene` at 320×240 drawn by a renderer whose shadow pass
/// draws stand-ins as `mode` says, and the stand-in triangles it drew.
fn frame_with(
    renderer: &mut relief_pipeline::render::Renderer,
    scene: &Scene,
) -> (Framebuffer, usize) {
    let mut fb = Framebuffer::new(320, 240);
    renderer.render(scene, &Settings::default(), &mut fb);
    (fb, renderer.stand_in_triangles())
}

/// A dense caster's stand-in draws the shadow map its mesh draws, but
/// within the stand-in's error: of the texels both cover, nearly all are
/// within 2 % of the sphere's radius of the same depth; a texel only one
/// covers lies next to the other's edge; the frame differs in a few
/// pixels at the shadows' edges. And it is far fewer triangles.
#[test]
fn a_dense_casters_stand_in_draws_the_map_its_mesh_draws() {
    assert_stand_in_draws_the_map_its_mesh_draws(&dense_caster_scene());
}

/// The same for an open caster, whose stand-in draws both sides: the
/// dented sphere's upper 100 of 181 rings, a bowl upside down (72 k
/// triangles).
#[test]
fn an_open_dense_casters_stand_in_draws_the_map_its_mesh_draws() {
    let mut scene = shadow_scene();
    let (vertices, mut triangles) = sphere(181, 360, 0.06);
    triangles.truncate(100 * 360 * 2);
    assert!(triangles.len() >= relief_pipeline::shadow::LOD_MIN_TRIANGLES);
    let mesh = relief_scene::Mesh::of_triangles(vertices, triangles, false, false);
    scene.objects[CUBE as usize].mesh = mesh;
    assert_stand_in_draws_the_map_its_mesh_draws(&scene);
}

/// The map and frame of `scene`'s shadow scene caster (object `CUBE`),
/// drawn by its stand-in, are those of the caster itself but within the
/// stand-in's error (see the tests above).
fn assert_stand_in_draws_the_map_its_mesh_draws(scene: &Scene) {
    use relief_pipeline::render::Renderer;
    use relief_pipeline::shadow::CasterLod;
    let plan = Plan::new(scene, &Settings::default());
    let light = plan.lights[plan.shadow_light.expect("a shadow pass")].position;
    let casters = &plan.shadow_casters;
    let (w, h) = (320, 240);
    let mut exact = ShadowMap::new();
    exact.render(scene, plan.rotation, light, casters, w, h);
    assert_eq!(exact.stand_in_triangles(), 0, "off by default");
    let mut stood = ShadowMap::new();
    stood.set_caster_lod(CasterLod::Wait);
    stood.render(scene, plan.rotation, light, casters, w, h);
    let triangles = scene.objects[CUBE as usize].mesh.triangles.len();
    let stand_in = stood.stand_in_triangles();
    assert!(
        stand_in > 0 && stand_in * 4 < triangles,
        "{stand_in} of {triangles}"
    );

    let size = exact.size();
    let ((e_depth, e_owner), (s_depth, _)) = (exact.texels(), stood.texels());
    let covered = |d: &[f32], x: usize, y: usize| d[y * size + x].is_finite();
    let next_to_edge = |x: usize, y: usize| {
        let here = covered(e_depth, x, y);
        let (x0, y0) = (x.saturating_sub(1), y.saturating_sub(1));
        (y0..=(y + 1).min(size - 1))
            .any(|ny| (x0..=(x + 1).min(size - 1)).any(|nx| covered(e_depth, nx, ny) != here))
    };
    let (mut both, mut near, mut one_only) = (0, 0, 0);
    for y in 0..size {
        for x in 0..size {
            let at = y * size + x;
            let (e, s) = (e_depth[at], s_depth[at]);
            match (e.is_finite(), s.is_finite()) {
                (true, true) => {
                    both += 1;
                    // 2 % of the sphere's radius.
                    near += usize::from((e - s).abs() <= 0.016);
                }
                (false, false) => {}
                _ => {
                    one_only += 1;
                    assert!(next_to_edge(x, y), "texel {x},{y} away from any edge");
                }
            }
        }
    }
    let sphere_texels = e_owner.iter().filter(|&&o| o == CUBE).count();
    assert!(sphere_texels > 20_000, "{sphere_texels}");
    assert!(near * 100 >= both * 99, "{near} of {both} near");
    assert!(
        one_only * 100 < both,
        "{one_only} covered by one only, {both} by both"
    );

    // The frame: a few pixels at the shadows' edges.
    let (exact_frame, none) = frame_with(&mut Renderer::new(), scene);
    assert_eq!(none, 0);
    let mut waiting = Renderer::new();
    waiting.set_caster_lod(CasterLod::Wait);
    let (stood_frame, drawn) = frame_with(&mut waiting, scene);
    assert!(drawn > 0);
    let differ = exact_frame
        .pixels()
        .iter()
        .zip(stood_frame.pixels())
        .filter(|(a, b)| a != b)
        .count();
    assert!(differ * 100 < w * h, "{differ} pixels differ");
}

/// In the background the first frame draws the exact casters; the thread
/// says once when the stand-in is made (the view then draws again), and
/// the next frame draws the frame the waiting renderer draws.
#[test]
fn a_stand_in_made_in_the_background_comes_in_a_later_frame() {
    use relief_pipeline::render::Renderer;
    use relief_pipeline::shadow::{CasterLod, StandInReady};
    let scene = dense_caster_scene();
    let mut waiting = Renderer::new();
    waiting.set_caster_lod(CasterLod::Wait);
    let (expected, _) = frame_with(&mut waiting, &scene);
    let mut view = Renderer::new();
    view.set_caster_lod(CasterLod::Background);
    let (tx, made) = std::sync::mpsc::channel();
    view.set_stand_in_ready(Some(StandInReady(std::sync::Arc::new(move || {
        let _ = tx.send(());
    }))));
    let (first, drawn) = frame_with(&mut view, &scene);
    assert_eq!(drawn, 0, "the first frame does not wait");
    assert_eq!(
        first.pixels(),
        frame_with(&mut Renderer::new(), &scene).0.pixels()
    );
    // Not a timing: the thread only has to finish at all. Once it says so,
    // the very next frame draws the stand-in.
    made.recv_timeout(std::time::Duration::from_secs(120))
        .expect("the thread says the stand-in is made");
    let (frame, drawn) = frame_with(&mut view, &scene);
    assert!(drawn > 0);
    assert_eq!(frame.pixels(), expected.pixels());
    // Once: the frames after it find it made.
    frame_with(&mut view, &scene);
    assert!(made.try_recv().is_err());
}
