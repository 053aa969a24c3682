//! The tangent-frame view (docs/tangent-frames.md):
//! where the T, B and N segments land on screen, derived by hand from the
//! reference camera; what hides them; and that off costs nothing.

use std::sync::Arc;

use clap::ValueEnum;
use glam::{Mat4, Vec3};
use relief::app::view::status_line;
use relief::app::{Action, State, update};
use relief_core::framebuffer::Framebuffer;
use relief_core::settings::Settings;
use relief_core::settings::{AntiAlias, Display};
use relief_options::OptId;
use relief_pipeline::raster::frames::LENGTH_FRACTION;
use relief_pipeline::render::{Renderer, render_frame};
use relief_scene::Scene;
use relief_scene::plane::grid;
use relief_scene::{Mesh, Object};
use relief_term::ColorDepth;
use relief_texture::{Level, Texture};

const RED: [u8; 3] = [255, 0, 0];
const GREEN: [u8; 3] = [0, 255, 0];
const BLUE: [u8; 3] = [0, 0, 255];
const W: usize = 320;
const H: usize = 240;

/// A grey texture: no surface pixel can be a pure primary.
fn grey() -> Arc<Texture> {
    Arc::new(Texture::new(
        "grey",
        Level::solid(4, 4, [0.5, 0.5, 0.5, 0.5]),
    ))
}

/// The 2×2 square facing the camera, cut in 2×2 cells so that one vertex
/// is at the origin, on the camera's axis.
fn square() -> Mesh {
    grid(1.0, 1.0, 2, |_| Vec3::splat(0.7))
}

/// The square seen head-on from the reference camera (no rotation).
fn head_on() -> (Scene, Settings) {
    let settings = Settings {
        rotation: Vec3::ZERO,
        tangent_frames: true,
        ..Settings::default()
    };
    (Scene::model(square(), grey()), settings)
}

fn at(fb: &Framebuffer, x: usize, y: usize) -> [u8; 3] {
    fb.get(x, y)
}

/// The length in pixels of a segment of world length `l` lying in the
/// z = 0 plane, seen from the reference camera (distance 5, vertical field
/// of view 60°): l · cot 30° / 5 half-heights.
fn projected(l: f32) -> f32 {
    l / (30f32.to_radians().tan() * 5.0) * H as f32 / 2.0
}

#[test]
fn head_on_t_runs_along_plus_x_b_up_and_n_is_seen_end_on() {
    let (scene, settings) = head_on();
    let (fb, stats) = render_frame(&scene, &settings, W, H);
    // The square's bounding radius is √2; its median edge (1) does not cap it.
    let len = projected(LENGTH_FRACTION * 2f32.sqrt());
    assert!(len > 6.0, "{len}");
    // The centre vertex projects to the middle of the frame.
    let (cx, cy) = (W / 2, H / 2);
    // N points at the eye: one pixel, drawn last.
    assert_eq!(at(&fb, cx, cy), BLUE);
    // T: red along the row, from just right of the vertex to its end.
    let end = cx as f32 + len;
    for x in cx + 1..end.floor() as usize {
        assert_eq!(at(&fb, x, cy), RED, "T at x = {x}");
        assert_ne!(at(&fb, x, cy - 1), RED);
        assert_ne!(at(&fb, x, cy + 1), RED);
    }
    for x in (end + 1.5) as usize..(end + 6.0) as usize {
        assert_ne!(at(&fb, x, cy), RED, "past T's end at x = {x}");
    }
    // B: green up the column (v grows along +Y, screen y grows down).
    let top = cy as f32 - len;
    for y in top.ceil() as usize + 1..cy {
        assert_eq!(at(&fb, cx, y), GREEN, "B at y = {y}");
    }
    for y in (top - 6.0) as usize..(top - 1.5) as usize {
        assert_ne!(at(&fb, cx, y), GREEN, "past B's end at y = {y}");
    }
    // Nothing left of the vertex or below it: T and B are one-sided.
    for k in 2..8 {
        assert_ne!(at(&fb, cx - k, cy), RED);
        assert_ne!(at(&fb, cx, cy + k), GREEN);
    }
    // Nine vertices, three segments each.
    assert_eq!(stats.counters.frame_lines, 27);
}

/// Under sub-cell symbols a pixel is `a` times as wide as tall (sextant
/// ¾, quad ½) and the view is widened by that: a length along x covers 1/a
/// times the pixels it does on square pixels, one along y the same. The
/// frames are projected as the surfaces are: the centre's T runs
/// projected(len)/a pixels while B keeps projected(len), and the T of the
/// right-hand vertex (1, 0, 0) starts projected(1)/a pixels right of the
/// centre. (Projected with square pixels, T would stop at projected(len)
/// and that vertex's frame would sit projected(1) from the centre.)
#[test]
fn frames_follow_the_pixel_aspect_of_sub_cell_symbols() {
    let (scene, settings) = head_on();
    for a in [0.75f32, 0.5] {
        let mut fb = Framebuffer::new(W, H);
        let mut renderer = Renderer::new();
        renderer.set_pixel_aspect(a);
        renderer.render(&scene, &settings, &mut fb);
        let (cx, cy) = (W / 2, H / 2);
        let len = projected(LENGTH_FRACTION * 2f32.sqrt());
        let end = cx as f32 + len / a;
        for x in cx + 1..end.floor() as usize {
            assert_eq!(at(&fb, x, cy), RED, "aspect {a}: T at x = {x}");
        }
        for x in (end + 1.5) as usize..(end + 4.0) as usize {
            assert_ne!(at(&fb, x, cy), RED, "aspect {a}: past T's end at x = {x}");
        }
        let top = cy as f32 - len;
        for y in top.ceil() as usize + 1..cy {
            assert_eq!(at(&fb, cx, y), GREEN, "aspect {a}: B at y = {y}");
        }
        for y in (top - 4.0) as usize..(top - 1.5) as usize {
            assert_ne!(at(&fb, cx, y), GREEN, "aspect {a}: past B's end at y = {y}");
        }
        // The right-hand vertex: its T starts on it and runs right, past
        // its N, which comes towards the eye (distance 5 − l instead of 5)
        // and so lands l/(5 − l) further out than the vertex, drawn last.
        let x = (cx as f32 + projected(1.0) / a).round() as usize;
        let l = LENGTH_FRACTION * 2f32.sqrt();
        let n_reach = projected(1.0) / a * l / (5.0 - l);
        for k in n_reach.ceil() as usize + 2..(len / a) as usize - 1 {
            assert_eq!(
                at(&fb, x + k, cy),
                RED,
                "aspect {a}: its T at x = {}",
                x + k
            );
        }
    }
}

#[test]
fn the_overlay_adds_only_its_three_colours() {
    let (scene, on) = head_on();
    let off = Settings {
        tangent_frames: false,
        ..on
    };
    let (with, _) = render_frame(&scene, &on, W, H);
    let (without, stats) = render_frame(&scene, &off, W, H);
    let mut changed = 0;
    for (a, b) in with.pixels().iter().zip(without.pixels()) {
        if a != b {
            assert!([RED, GREEN, BLUE].contains(a), "{a:?}");
            changed += 1;
        }
    }
    assert!(changed > 100, "{changed}");
    assert_eq!(stats.counters.frame_lines, 0);
}

#[test]
fn off_counts_nothing_and_an_untextured_scene_draws_none() {
    let scene = Scene::model(square(), grey());
    for &display in Display::value_variants() {
        for &aa in AntiAlias::value_variants() {
            let s = Settings {
                display,
                aa,
                ..Settings::default()
            };
            let (_, stats) = render_frame(&scene, &s, 64, 48);
            assert_eq!(stats.counters.frame_lines, 0, "{display:?} {aa:?}");
            // On, every display and anti-aliasing draws them.
            let on = Settings {
                tangent_frames: true,
                ..s
            };
            let (_, stats) = render_frame(&scene, &on, 64, 48);
            assert!(stats.counters.frame_lines > 0, "{display:?} {aa:?}");
        }
    }
    // Without texture coordinates there is no frame to show: the same
    // picture as off, bit for bit.
    let mut mesh = square();
    for t in &mut mesh.triangles {
        t.textured = false;
    }
    let bare = Scene::model(mesh, grey());
    let on = Settings {
        tangent_frames: true,
        ..Settings::default()
    };
    let (a, stats) = render_frame(&bare, &on, 64, 48);
    let (b, _) = render_frame(&bare, &Settings::default(), 64, 48);
    assert_eq!(a.pixels(), b.pixels());
    assert_eq!(stats.counters.frame_lines, 0);
}

#[test]
fn a_surface_in_front_hides_the_frames_behind_it() {
    let (mut scene, settings) = head_on();
    let (_, alone) = render_frame(&scene, &settings, W, H);
    assert_eq!(alone.counters.frame_lines, 27);
    // A larger untextured square one unit nearer covers the first one.
    let mut wall = grid(2.0, 1.0, 1, |_| Vec3::splat(0.7));
    for t in &mut wall.triangles {
        t.textured = false;
    }
    scene.objects.push(Object {
        mesh: wall,
        transform: Mat4::from_translation(Vec3::Z),
        rotates: true,
    });
    let (fb, hidden) = render_frame(&scene, &settings, W, H);
    assert_eq!(hidden.counters.frame_lines, 0);
    assert!(fb.pixels().iter().all(|p| ![RED, GREEN, BLUE].contains(p)));
    // Moved behind, it hides nothing.
    scene.objects[1].transform = Mat4::from_translation(-Vec3::Z);
    let (_, behind) = render_frame(&scene, &settings, W, H);
    assert_eq!(behind.counters.frame_lines, 27);
}

#[test]
fn key_f_toggles_the_frames_and_the_status_line_says_so() {
    let mut s = State::new(Settings::default(), ColorDepth::Truecolor);
    assert!(!status_line(&s, 300).contains("tangent frames"));
    update(&mut s, Action::next(OptId::TangentFrames));
    assert!(s.settings.tangent_frames);
    assert!(status_line(&s, 300).contains("tangent frames"));
    update(&mut s, Action::next(OptId::TangentFrames));
    assert!(!s.settings.tangent_frames);
}
