//! Bump techniques on the raw framebuffer: nothing to perturb gives the
//! unbumped image exactly, a known slope tilts the normal as Blinn's formula
//! says, emboss and dot3 agree with Blinn in sign and roughly in magnitude,
//! dot3's per-vertex light vector darkens the middle of a large triangle,
//! and the counters say what each technique read.

use crate::techniques_scenes;

use glam::{Vec2, Vec3};
use relief_core::settings::Settings;
use relief_core::settings::{LightVector, Normals, Technique};
use relief_pipeline::render::Renderer;
use relief_pipeline::render::render_frame;
use relief_scene::light::reference_lights;
use techniques_scenes::*;

const TECHNIQUES: [Technique; 5] = [
    Technique::Blinn,
    Technique::Emboss,
    Technique::Dot3,
    Technique::Parallax,
    Technique::Pom,
];

/// Height 1 (the surface) under texture coordinates 0.07..0.72 with a
/// coloured checker; recessed texels from u = 0.75 on, so the height map is
/// not flat (the plan would drop the bump stage) but nothing a pixel of the
/// test quad reads is sloped.
fn flat_where_seen() -> relief_texture::Texture {
    texture_of(32, |x, y| {
        let c = if (x / 4 + y / 4) % 2 == 0 { 0.9 } else { 0.4 };
        let h = if x >= 24 { 0.3 } else { 1.0 };
        [c, 0.6, 1.0 - c, h]
    })
}

fn flat_scene(rotates: bool) -> relief_scene::Scene {
    let mesh = quad_mesh(1.0, 0.0, Vec2::splat(0.1), Vec2::splat(0.6), Vec3::ONE);
    let object = if rotates { turning(mesh) } else { fixed(mesh) };
    scene_of(
        vec![object],
        flat_where_seen(),
        reference_lights(),
        relief_scene::AMBIENT,
    )
}

fn with(technique: Technique, normals: Normals) -> Settings {
    Settings {
        technique,
        normals,
        ..Settings::default()
    }
}

#[test]
fn flat_height_gives_exactly_the_unbumped_image() {
    let scene = flat_scene(false);
    for normals in [Normals::Vertex, Normals::Face] {
        let off = Settings {
            bump: false,
            ..with(Technique::Blinn, normals)
        };
        let (reference, _) = render_frame(&scene, &off, 320, 240);
        for technique in TECHNIQUES {
            let (fb, stats) = render_frame(&scene, &with(technique, normals), 320, 240);
            let c = stats.counters;
            assert!(c.bump_evals > 1000, "{technique:?}: the bump kernel ran");
            assert_eq!(c.nonfinite, 0);
            assert_eq!(max_diff(&fb, &reference), 0, "{technique:?} {normals:?}");
            assert!(fb == reference, "{technique:?} {normals:?}");
        }
    }
}

#[test]
fn flat_height_on_a_turned_quad_stays_within_one_level() {
    // Turned, normals are unit only to rounding, so Blinn's renormalisation
    // may move a channel by one level; the other techniques follow Blinn or
    // Phong term for term.
    let scene = flat_scene(true);
    let turn = Vec3::new(20.0, 30.0, 10.0);
    let off = Settings {
        bump: false,
        rotation: turn,
        ..Settings::default()
    };
    let (reference, _) = render_frame(&scene, &off, 320, 240);
    for technique in TECHNIQUES {
        let s = Settings {
            rotation: turn,
            ..with(technique, Normals::Vertex)
        };
        let (fb, stats) = render_frame(&scene, &s, 320, 240);
        assert!(stats.counters.bump_evals > 1000);
        assert!(max_diff(&fb, &reference) <= 1, "{technique:?}");
    }
}

/// White texture whose height rises along u by 0.5 per unit of u.
fn ramp_scene(light: Vec3) -> relief_scene::Scene {
    let n = 64;
    let texture = texture_of(n, |x, _| [1.0, 1.0, 1.0, 0.25 + 0.5 * x as f32 / n as f32]);
    // Texture coordinates 0..1 over 2 units: ∂P/∂u = 2X, ∂P/∂v = 2Y as on the cube.
    let mesh = quad_mesh(1.0, 0.0, Vec2::ZERO, Vec2::ONE, Vec3::ONE);
    scene_of(vec![fixed(mesh)], texture, white_light(light), Vec3::ZERO)
}

fn ramp_settings(technique: Technique) -> Settings {
    Settings {
        technique,
        bump_strength: 0.5,
        ..Settings::default()
    }
}

#[test]
fn a_ramp_tilts_the_normal_as_blinns_formula_says() {
    // F_u = 0.5, k = 0.5, Pu = 2X, Pv = 2Y: N' = Z + k·F_u·(Z × 2Y) = (−0.5, 0, 1),
    // normalised. Light straight above: N'·L = 1/√1.25 = 0.894 → 228.
    let scene = ramp_scene(Vec3::new(0.0, 0.0, 10.0));
    let (flat, _) = render_frame(
        &scene,
        &Settings {
            bump: false,
            ..ramp_settings(Technique::Blinn)
        },
        320,
        240,
    );
    assert_eq!(red(&flat, 160, 120), 255);
    for technique in [
        Technique::Blinn,
        Technique::Dot3,
        Technique::Parallax,
        Technique::Pom,
    ] {
        let (fb, _) = render_frame(&scene, &ramp_settings(technique), 320, 240);
        let r = red(&fb, 160, 120);
        assert!((r - 228).abs() <= 1, "{technique:?}: {r}");
    }
    // Emboss's documented limit: a light straight above has no tangent
    // part, so the shift and the relief vanish.
    let (fb, _) = render_frame(&scene, &ramp_settings(Technique::Emboss), 320, 240);
    assert_eq!(red(&fb, 160, 120), 255);
}

#[test]
fn the_tilt_faces_minus_u() {
    // The height rises toward +u, so the slope faces −u (−X): a light on
    // that side lights it more than one on the other side, for every technique.
    for technique in TECHNIQUES {
        let lit = |x: f32| {
            let scene = ramp_scene(Vec3::new(x, 0.0, 8.0));
            red(
                &render_frame(&scene, &ramp_settings(technique), 320, 240).0,
                160,
                120,
            )
        };
        assert!(lit(-6.0) > lit(6.0) + 20, "{technique:?}");
    }
}

#[test]
fn emboss_and_dot3_agree_with_blinn_on_a_ramp() {
    for light in [
        Vec3::new(6.0, 0.0, 8.0),
        Vec3::new(-6.0, 0.0, 8.0),
        Vec3::new(4.0, 3.0, 8.0),
        Vec3::new(-3.0, -4.0, 8.0),
    ] {
        // A gentle slope (k = 0.25: the normal tilts by 14°), where emboss's
        // first-order estimate holds; steeper, it overshoots (no renormalisation).
        let scene = ramp_scene(light);
        let value = |s: &Settings| {
            let s = Settings {
                bump_strength: 0.25,
                ..*s
            };
            red(&render_frame(&scene, &s, 320, 240).0, 160, 120)
        };
        let flat = value(&Settings {
            bump: false,
            ..ramp_settings(Technique::Blinn)
        });
        let blinn = value(&ramp_settings(Technique::Blinn)) - flat;
        assert!(blinn.abs() > 10, "the light at {light} must show the slope");
        for technique in [Technique::Emboss, Technique::Dot3] {
            let delta = value(&ramp_settings(technique)) - flat;
            assert_eq!(delta.signum(), blinn.signum(), "{technique:?} at {light}");
            let ratio = delta as f32 / blinn as f32;
            assert!(
                (0.5..=2.0).contains(&ratio),
                "{technique:?} at {light}: {ratio}"
            );
        }
        // Dot3's map is built for the same slope scale as Blinn's k: equal here.
        let dot3 = value(&ramp_settings(Technique::Dot3)) - flat;
        assert!((dot3 - blinn).abs() <= 1, "{dot3} vs {blinn}");
    }
}

#[test]
fn dot3_per_vertex_light_vector_darkens_the_middle() {
    // A light close above the middle: the unit vectors at the corners lean
    // outward, and their interpolation at the middle is short (the tutorial's
    // artefact); per pixel the middle is lit head-on.
    let mesh = quad_mesh(1.0, 0.0, Vec2::splat(0.1), Vec2::splat(0.6), Vec3::ONE);
    let scene = scene_of(
        vec![fixed(mesh)],
        flat_where_seen(),
        white_light(Vec3::new(0.0, 0.0, 1.2)),
        Vec3::ZERO,
    );
    let frame = |lv: LightVector| {
        let s = Settings {
            light_vector: lv,
            ..with(Technique::Dot3, Normals::Vertex)
        };
        render_frame(&scene, &s, 320, 240)
    };
    let (pixel, ps) = frame(LightVector::Pixel);
    let (vertex, vs) = frame(LightVector::Vertex);
    assert_eq!(ps.counters.pixels_shaded, vs.counters.pixels_shaded);
    // Green channel: 0.6 everywhere in the texture.
    let g = |fb: &relief_core::framebuffer::Framebuffer| fb.get(160, 120)[1] as i32;
    assert!(
        g(&pixel) > g(&vertex) + 30,
        "{} vs {}",
        g(&pixel),
        g(&vertex)
    );
    let sum = |fb: &relief_core::framebuffer::Framebuffer| {
        fb.pixels().iter().map(|p| p[1] as u64).sum::<u64>()
    };
    assert!(sum(&pixel) > sum(&vertex));
}

#[test]
fn counters_say_what_each_technique_read() {
    let scene = ramp_scene(Vec3::new(3.0, 2.0, 10.0));
    let mut renderer = Renderer::new();
    let mut fb = relief_core::framebuffer::Framebuffer::new(160, 120);
    let mut run = |t: Technique, k: f32| {
        let s = Settings {
            bump_strength: k,
            ..ramp_settings(t)
        };
        renderer.render(&scene, &s, &mut fb).counters
    };
    let blinn = run(Technique::Blinn, 0.5);
    let px = blinn.pixels_shaded;
    assert!(px > 500);
    assert_eq!(blinn.bump_evals, px);
    assert_eq!(
        blinn.texture_samples, px,
        "colour only: the gradient is bump_evals"
    );
    assert_eq!(blinn.normal_map_builds, 0);

    let emboss = run(Technique::Emboss, 0.5);
    assert_eq!(emboss.bump_evals, px);
    assert_eq!(emboss.texture_samples, 3 * px, "colour + two heights");

    let dot3 = run(Technique::Dot3, 0.5);
    assert_eq!(dot3.bump_evals, px);
    assert_eq!(dot3.texture_samples, 2 * px, "colour + normal map");
    assert_eq!(dot3.normal_map_builds, 1, "built on first use");
    assert_eq!(run(Technique::Dot3, 0.5).normal_map_builds, 0, "then kept");
    assert_eq!(
        run(Technique::Dot3, 0.25).normal_map_builds,
        1,
        "rebuilt for a new k"
    );

    let parallax = run(Technique::Parallax, 0.5);
    assert_eq!(parallax.bump_evals, px);
    assert_eq!(parallax.texture_samples, 2 * px, "colour + one height");

    let pom = run(Technique::Pom, 0.5);
    assert_eq!(pom.bump_evals, px);
    // Every pixel is below height 1, so each march reads at least twice.
    assert!(
        pom.texture_samples >= 3 * px,
        "{} vs {px}",
        pom.texture_samples
    );
    assert!(pom.texture_samples <= (2 + 32) * px);
    for c in [blinn, emboss, dot3, parallax, pom] {
        assert_eq!(c.nonfinite, 0);
    }
}

#[test]
fn techniques_need_phong_and_bump() {
    // Gouraud, or bump off: every technique draws the same unbumped image.
    let scene = ramp_scene(Vec3::new(6.0, 0.0, 8.0));
    for base in [
        Settings {
            shading: relief_core::settings::Shading::Gouraud,
            ..ramp_settings(Technique::Blinn)
        },
        Settings {
            bump: false,
            ..ramp_settings(Technique::Blinn)
        },
    ] {
        let (reference, _) = render_frame(&scene, &base, 160, 120);
        for technique in TECHNIQUES {
            let (fb, stats) = render_frame(&scene, &Settings { technique, ..base }, 160, 120);
            assert!(fb == reference, "{technique:?}");
            assert_eq!(stats.counters.bump_evals, 0);
        }
    }
}

#[test]
fn parallax_follows_the_flat_face_not_its_rounded_vertex_normals() {
    // A quad with normals leaning outward at its corners (as a cube's vertex
    // normals do), stripes in u, heights below the surface, ambient light
    // only: the picture is the texture read at the displaced coordinate, and
    // the displacement must not depend on how the normals lean.
    let texture = || {
        texture_of(32, |x, _| {
            let c = if (x / 2) % 2 == 0 { 1.0 } else { 0.2 };
            [c, c, c, 0.2 + 0.6 * (x % 5) as f32 / 4.0]
        })
    };
    let scene_with = |lean: f32| {
        let mut mesh = quad_mesh(1.0, 0.0, Vec2::ZERO, Vec2::ONE, Vec3::ONE);
        for v in &mut mesh.vertices {
            v.normal = Vec3::new(lean * v.position.x, lean * v.position.y, 1.0).normalize();
        }
        scene_of(vec![fixed(mesh)], texture(), Vec::new(), Vec3::ONE)
    };
    for technique in [Technique::Parallax, Technique::Pom] {
        let settings = Settings {
            bump_strength: 4.0 * Settings::default().bump_strength,
            ..with(technique, Normals::Vertex)
        };
        let (upright, _) = render_frame(&scene_with(0.0), &settings, 160, 120);
        let (leaning, _) = render_frame(&scene_with(1.0), &settings, 160, 120);
        assert!(upright == leaning, "{technique:?}: the texture bent");
        // And the relief does show: the picture differs from plain Phong.
        let plain = Settings {
            bump: false,
            ..settings
        };
        let (flat, _) = render_frame(&scene_with(0.0), &plain, 160, 120);
        let d = max_diff(&flat, &upright);
        assert!(d > 20, "{technique:?}: {d}");
    }
}
