//! Points and lines display modes, and the no-NaN property over every
//! technique, anti-aliasing level, display mode and orientation.

use std::sync::Arc;

use glam::Vec3;
use proptest::prelude::*;
use relief_core::framebuffer::Framebuffer;
use relief_core::settings::Settings;
use relief_core::settings::{AntiAlias, Display, LightVector, Normals, Shading, Technique};
use relief_pipeline::render::render_frame;
use relief_scene::Scene;
use relief_texture::decode::procedural;

fn cube() -> Scene {
    Scene::cube(Arc::new(procedural::brick()), true)
}

fn shown(display: Display) -> Settings {
    Settings {
        display,
        ..Settings::default()
    }
}

fn is_bg(scene: &Scene, p: [u8; 3]) -> bool {
    p == scene.background
}

/// Pixels of `fb` that are not background.
fn marks(scene: &Scene, fb: &Framebuffer) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    for y in 0..fb.height() {
        for x in 0..fb.width() {
            if !is_bg(scene, fb.get(x, y)) {
                out.push((x, y));
            }
        }
    }
    out
}

/// Whether `fb` has a mark within `r` pixels of (x, y).
fn mark_near(scene: &Scene, fb: &Framebuffer, x: usize, y: usize, r: usize) -> bool {
    (y.saturating_sub(r)..=(y + r).min(fb.height() - 1)).any(|yy| {
        (x.saturating_sub(r)..=(x + r).min(fb.width() - 1)).any(|xx| !is_bg(scene, fb.get(xx, yy)))
    })
}

#[test]
fn the_wireframe_touches_the_silhouette_and_stays_inside_it() {
    let scene = cube();
    let (fill, _) = render_frame(&scene, &shown(Display::Fill), 320, 240);
    let (lines, stats) = render_frame(&scene, &shown(Display::Lines), 320, 240);
    assert!(stats.counters.pixels_shaded > 300);
    assert_eq!(stats.counters.triangles_drawn, 0, "no triangle is filled");
    // Each row of the filled cube: its first and last pixels have a line next to them.
    let mut rows = 0;
    for y in 0..240 {
        let xs: Vec<usize> = (0..320)
            .filter(|&x| !is_bg(&scene, fill.get(x, y)))
            .collect();
        if let (Some(&a), Some(&b)) = (xs.first(), xs.last()) {
            rows += 1;
            assert!(mark_near(&scene, &lines, a, y, 1), "left of row {y}");
            assert!(mark_near(&scene, &lines, b, y, 1), "right of row {y}");
        }
    }
    assert!(rows > 100);
    // And no line strays outside the filled cube.
    for (x, y) in marks(&scene, &lines) {
        assert!(
            mark_near(&scene, &fill, x, y, 1),
            "line pixel ({x}, {y}) off the cube"
        );
    }
}

#[test]
fn back_edges_are_culled_like_fill() {
    // Seen face-on, the cube's front face is the whole silhouette: with back
    // faces culled, no line crosses its inside (only its diagonal does).
    let scene = cube();
    let s = Settings {
        rotation: Vec3::ZERO,
        ..shown(Display::Lines)
    };
    let (lines, _) = render_frame(&scene, &s, 320, 240);
    let (fill, _) = render_frame(
        &scene,
        &Settings {
            display: Display::Fill,
            ..s
        },
        320,
        240,
    );
    let inside: Vec<(usize, usize)> = marks(&scene, &fill);
    let (x0, x1) = (
        inside.iter().map(|p| p.0).min().unwrap(),
        inside.iter().map(|p| p.0).max().unwrap(),
    );
    let (y0, y1) = (
        inside.iter().map(|p| p.1).min().unwrap(),
        inside.iter().map(|p| p.1).max().unwrap(),
    );
    // The front face's diagonal runs from bottom-left to top-right; the back
    // face's would run the same way but its other edges would form a second,
    // smaller square. Check the smaller square's corner region is empty.
    let (w, h) = (x1 - x0, y1 - y0);
    for (x, y) in marks(&scene, &lines) {
        let (fx, fy) = ((x - x0) as f32 / w as f32, (y - y0) as f32 / h as f32);
        let on_border = !(0.03..=0.97).contains(&fx) || !(0.03..=0.97).contains(&fy);
        let on_diagonal = ((1.0 - fy) - fx).abs() < 0.03;
        assert!(on_border || on_diagonal, "({x}, {y}) = ({fx}, {fy})");
    }
}

#[test]
fn points_are_the_visible_vertices() {
    let scene = cube();
    let (fb, _) = render_frame(&scene, &shown(Display::Points), 320, 240);
    // Three faces seen: seven distinct corners, one pixel each at this size.
    let n = marks(&scene, &fb).len();
    assert!((6..=7).contains(&n), "{n}");
    let (big, _) = render_frame(&scene, &shown(Display::Points), 640, 480);
    let m = marks(&scene, &big).len();
    assert!((20..=28).contains(&m), "2×2 dots on a large frame: {m}");
}

#[test]
fn lines_and_points_widen_with_supersampling() {
    let scene = cube();
    for display in [Display::Lines, Display::Points] {
        let (plain, _) = render_frame(&scene, &shown(display), 320, 240);
        let (ss, _) = render_frame(
            &scene,
            &Settings {
                aa: AntiAlias::Ssaa4,
                ..shown(display)
            },
            320,
            240,
        );
        let (a, b) = (marks(&scene, &plain).len(), marks(&scene, &ss).len());
        // Same size, softer edges: a few more (blended) pixels, not 4× fewer.
        assert!(b >= a && b <= 3 * a + 10, "{display:?}: {a} vs {b}");
    }
}

fn technique() -> impl Strategy<Value = Technique> {
    prop_oneof![
        Just(Technique::Blinn),
        Just(Technique::Emboss),
        Just(Technique::Dot3),
        Just(Technique::Parallax),
        Just(Technique::Pom),
    ]
}

fn aa() -> impl Strategy<Value = AntiAlias> {
    prop_oneof![
        Just(AntiAlias::Off),
        Just(AntiAlias::Ssaa2),
        Just(AntiAlias::Ssaa4),
        Just(AntiAlias::Msaa4),
    ]
}

fn display() -> impl Strategy<Value = Display> {
    prop_oneof![
        Just(Display::Points),
        Just(Display::Lines),
        Just(Display::Fill)
    ]
}

fn angle() -> impl Strategy<Value = f32> {
    prop_oneof![
        -720.0f32..720.0,
        Just(0.0),
        Just(90.0),
        Just(1e9),
        Just(f32::NAN),
        Just(f32::INFINITY),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]

    /// No combination gives a non-finite colour, panics, or writes outside
    /// the framebuffer (it would panic), including with the camera inside
    /// or right against the cube.
    #[test]
    fn no_nan_for_any_combination(
        technique in technique(),
        aa in aa(),
        display in display(),
        rx in angle(), ry in angle(), rz in angle(),
        vertex_light in any::<bool>(),
        face_normals in any::<bool>(),
        all_faces in any::<bool>(),
        strength in prop_oneof![Just(0.006f32), Just(0.0), 0.0f32..2.0, Just(1e6)],
        eye_z in prop_oneof![Just(5.0f32), 0.0f32..3.0, Just(1.05)],
        w in 1usize..72,
        h in 1usize..56,
    ) {
        let mut scene = Scene::cube(Arc::new(procedural::brick()), all_faces);
        scene.camera.eye = Vec3::new(0.3, 0.2, eye_z);
        let settings = Settings {
            shading: Shading::Phong,
            technique,
            aa,
            display,
            rotation: Vec3::new(rx, ry, rz),
            light_vector: if vertex_light { LightVector::Vertex } else { LightVector::Pixel },
            normals: if face_normals { Normals::Face } else { Normals::Vertex },
            bump_strength: strength,
            ..Settings::default()
        };
        let (fb, stats) = render_frame(&scene, &settings, w, h);
        prop_assert_eq!(stats.counters.nonfinite, 0);
        prop_assert_eq!((fb.width(), fb.height()), (w, h));
    }
}

fn clip_coord() -> impl Strategy<Value = f32> {
    prop_oneof![
        -50.0f32..50.0,
        Just(0.0),
        Just(1e-30),
        Just(-1e-30),
        Just(1e30),
        Just(-1e30),
        Just(f32::NAN),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    /// Any segment in clip space, on any canvas: every write is in bounds
    /// (an out-of-bounds index would panic), and a line never paints more
    /// pixels than a `size`-wide stroke across the whole canvas could.
    #[test]
    fn lines_and_points_never_leave_the_canvas(
        a in (clip_coord(), clip_coord(), clip_coord(), clip_coord()),
        b in (clip_coord(), clip_coord(), clip_coord(), clip_coord()),
        w in 1usize..40,
        h in 1usize..30,
        size in 1usize..5,
    ) {
        use glam::Vec4;
        use relief_pipeline::raster::wire::{Canvas, WireTri, draw_line, draw_points};
        let (a, b) = (Vec4::new(a.0, a.1, a.2, a.3), Vec4::new(b.0, b.1, b.2, b.3));
        let mut px = vec![[0u8; 3]; w * h];
        let mut canvas = Canvas::new(w, h, &mut px);
        let mut counters = relief_core::stats::Counters::default();
        draw_line((a, Vec3::ONE), (b, Vec3::new(0.5, 0.2, 1.0)), size, &mut canvas, &mut counters);
        let tri = WireTri { clip: [a, b, a], color: [Vec3::ONE; 3] };
        draw_points(&[tri], size, &mut canvas, &mut counters);
        let longest = (w.max(h) + 2) * size * size * 2 + 3 * size * size;
        prop_assert!(counters.pixels_shaded as usize <= longest);
        prop_assert_eq!(counters.nonfinite, 0);
    }
}
