//! Anti-aliasing on the raw framebuffer: a frame without edges is unchanged,
//! edge pixels take intermediate values, supersampling shades every sample
//! and multisampling once per pixel, and multisampled depth keeps the nearer
//! surface.

use crate::techniques_scenes;

use glam::{Vec2, Vec3};
use relief_core::settings::AntiAlias;
use relief_core::settings::Settings;
use relief_pipeline::render::Renderer;
use relief_pipeline::render::render_frame;
use techniques_scenes::*;

const LEVELS: [AntiAlias; 4] = [
    AntiAlias::Off,
    AntiAlias::Ssaa2,
    AntiAlias::Ssaa4,
    AntiAlias::Msaa4,
];

fn plain_texture() -> relief_texture::Texture {
    texture_of(4, |_, _| [1.0, 1.0, 1.0, 0.5])
}

/// A white quad lit by a full ambient term alone: one colour wherever it is.
fn white_quad_scene(half: f32, rotates: bool) -> relief_scene::Scene {
    let mesh = quad_mesh(half, 0.0, Vec2::ZERO, Vec2::ONE, Vec3::ONE);
    let object = if rotates { turning(mesh) } else { fixed(mesh) };
    scene_of(vec![object], plain_texture(), Vec::new(), Vec3::ONE)
}

fn aa(level: AntiAlias) -> Settings {
    Settings {
        aa: level,
        ..Settings::default()
    }
}

#[test]
fn a_frame_without_edges_is_unchanged() {
    // The quad covers the whole view: no edge, one colour.
    let scene = white_quad_scene(50.0, false);
    let (reference, _) = render_frame(&scene, &aa(AntiAlias::Off), 96, 64);
    assert!(reference.pixels().iter().all(|&p| p == [255, 255, 255]));
    for level in LEVELS {
        let (fb, stats) = render_frame(&scene, &aa(level), 96, 64);
        assert!(fb == reference, "{level:?}");
        assert_eq!(stats.counters.nonfinite, 0);
    }
}

#[test]
fn smooth_lighting_without_edges_barely_changes() {
    // Lit by the reference lights the colour varies across the frame;
    // averaging samples of a smooth gradient moves a pixel by a level at most.
    let mesh = quad_mesh(50.0, 0.0, Vec2::ZERO, Vec2::ONE, Vec3::ONE);
    let scene = scene_of(
        vec![fixed(mesh)],
        plain_texture(),
        relief_scene::light::reference_lights(),
        relief_scene::AMBIENT,
    );
    let (reference, _) = render_frame(&scene, &aa(AntiAlias::Off), 96, 64);
    for level in LEVELS {
        let (fb, _) = render_frame(&scene, &aa(level), 96, 64);
        assert!(max_diff(&fb, &reference) <= 1, "{level:?}");
    }
}

/// Pixels strictly between the background and white in every channel.
fn intermediate(fb: &relief_core::framebuffer::Framebuffer) -> usize {
    let bg = relief_scene::BACKGROUND;
    fb.pixels()
        .iter()
        .filter(|p| (0..3).all(|c| p[c] > bg[c] && p[c] < 255))
        .count()
}

#[test]
fn edge_pixels_take_intermediate_values() {
    let scene = white_quad_scene(1.0, true);
    let turned = |level| Settings {
        rotation: Vec3::new(0.0, 0.0, 30.0),
        ..aa(level)
    };
    let (off, _) = render_frame(&scene, &turned(AntiAlias::Off), 160, 120);
    assert_eq!(intermediate(&off), 0, "without AA a pixel is in or out");
    // The quad's coverage in pixels: white counts 1, background 0, blends between.
    let coverage = |fb: &relief_core::framebuffer::Framebuffer| -> f64 {
        fb.pixels()
            .iter()
            .map(|p| (p[0] as f64 - 16.0) / (255.0 - 16.0))
            .sum()
    };
    let hard = coverage(&off);
    for level in [AntiAlias::Ssaa2, AntiAlias::Ssaa4, AntiAlias::Msaa4] {
        let (fb, _) = render_frame(&scene, &turned(level), 160, 120);
        let edges = intermediate(&fb);
        // The perimeter is about 4 × 42 pixels long.
        assert!(edges > 60, "{level:?}: {edges}");
        // The same area, resolved: within a fraction of the perimeter.
        let soft = coverage(&fb);
        assert!((soft - hard).abs() < 30.0, "{level:?}: {soft} vs {hard}");
    }
}

#[test]
fn supersampling_shades_every_sample_and_multisampling_once_per_pixel() {
    let scene = relief_scene::Scene::cube(
        std::sync::Arc::new(relief_texture::decode::procedural::brick()),
        true,
    );
    let mut renderer = Renderer::new();
    let mut fb = relief_core::framebuffer::Framebuffer::new(320, 240);
    let mut shaded = |level| renderer.render(&scene, &aa(level), &mut fb).counters;
    let off = shaded(AntiAlias::Off).pixels_shaded;
    assert_eq!(off, 11_741);
    let ratio = |n: u64| n as f64 / off as f64;
    let ss2 = shaded(AntiAlias::Ssaa2);
    let ss4 = shaded(AntiAlias::Ssaa4);
    let ms4 = shaded(AntiAlias::Msaa4);
    assert!(
        (ratio(ss2.pixels_shaded) - 4.0).abs() < 0.1,
        "{}",
        ratio(ss2.pixels_shaded)
    );
    assert!(
        (ratio(ss4.pixels_shaded) - 16.0).abs() < 0.4,
        "{}",
        ratio(ss4.pixels_shaded)
    );
    // Once per pixel and triangle: pixels along edges may be shaded by
    // both triangles that share them, nothing more.
    assert!(ms4.pixels_shaded >= off, "{}", ms4.pixels_shaded);
    assert!(
        ratio(ms4.pixels_shaded) < 1.1,
        "{}",
        ratio(ms4.pixels_shaded)
    );
    assert_eq!(ms4.bump_evals, ms4.pixels_shaded);
    for c in [ss2, ss4, ms4] {
        assert_eq!(c.nonfinite, 0);
    }
}

#[test]
fn supersampling_reuses_its_scratch_frame_and_resolves_into_the_output() {
    let scene = white_quad_scene(1.0, true);
    let mut renderer = Renderer::new();
    let mut a = relief_core::framebuffer::Framebuffer::new(80, 60);
    let mut b = relief_core::framebuffer::Framebuffer::new(80, 60);
    let s = Settings {
        rotation: Vec3::new(0.0, 0.0, 20.0),
        ..aa(AntiAlias::Ssaa4)
    };
    renderer.render(&scene, &s, &mut a);
    renderer.render(&scene, &s, &mut b);
    assert!(a == b);
    assert_eq!((a.width(), a.height()), (80, 60));
    let (fresh, _) = render_frame(&scene, &s, 80, 60);
    assert!(fresh == a);
}

#[test]
fn multisampled_depth_keeps_the_nearer_surface_in_any_order() {
    // Two quads, red in front (z = 0.5) and green behind (z = 0), overlapping;
    // two objects, so depth is on.
    let front = quad_mesh(0.6, 0.5, Vec2::ZERO, Vec2::ONE, Vec3::new(1.0, 0.0, 0.0));
    let back = quad_mesh(1.0, 0.0, Vec2::ZERO, Vec2::ONE, Vec3::new(0.0, 1.0, 0.0));
    for order in [[front.clone(), back.clone()], [back.clone(), front.clone()]] {
        let scene = scene_of(
            order.into_iter().map(fixed).collect(),
            plain_texture(),
            Vec::new(),
            Vec3::ONE,
        );
        let (fb, stats) = render_frame(&scene, &aa(AntiAlias::Msaa4), 160, 120);
        assert!(stats.counters.depth_tests > 0);
        assert_eq!(fb.get(80, 60), [255, 0, 0], "the middle is the front quad");
        // Between the front quad's edge and the back quad's: green.
        assert_eq!(fb.get(80, 60 - 17), [0, 255, 0]);
    }
}

#[test]
fn multisampling_keeps_a_sliver_between_two_rows_of_pixel_centres() {
    // A white quad squashed to about half a pixel, centred on the screen's
    // middle line (y = 60.0 at 160×120): it covers no pixel centre (59.5 and
    // 60.5), but the samples 3/8 pixel off them (59.875, 60.125) lie inside.
    let mut object = fixed(quad_mesh(1.0, 0.0, Vec2::ZERO, Vec2::ONE, Vec3::ONE));
    // About 29 pixels per unit here: 0.02 units are about 0.6 pixel.
    object.transform = glam::Mat4::from_scale(Vec3::new(1.0, 0.01, 1.0));
    let scene = scene_of(vec![object], plain_texture(), Vec::new(), Vec3::ONE);
    let background = scene.background;
    let (plain, _) = render_frame(&scene, &aa(AntiAlias::Off), 160, 120);
    assert!(
        plain.pixels().iter().all(|&p| p == background),
        "no pixel centre is covered"
    );
    let (ms, stats) = render_frame(&scene, &aa(AntiAlias::Msaa4), 160, 120);
    assert!(stats.counters.pixels_shaded > 0);
    for x in [60, 80, 100] {
        for y in [59, 60] {
            let p = ms.get(x, y);
            // One or two of four samples: between the background and white.
            assert!(
                p != background && p[0] < 255 && p[0] > background[0],
                "({x},{y}) {p:?}"
            );
        }
    }
    assert!(
        (0..120)
            .filter(|y| !(59..=60).contains(y))
            .all(|y| (0..160).all(|x| ms.get(x, y) == background)),
        "only the two middle rows"
    );
}
