//! Zoom: the wheel and `i` / `I` move the camera along its line of sight,
//! within bounds, `r` comes back; and the picture grows as the projection
//! says it must.

use std::sync::Arc;

use crossterm::event::{Event, KeyCode, KeyEvent, KeyModifiers, MouseEvent, MouseEventKind};
use glam::Vec3;
use relief::app::state::ZOOM_STEP;
use relief::app::{Action, State, action_for_event, update};
use relief::scene::camera::{MAX_DISTANCE, MIN_DISTANCE, REFERENCE_DISTANCE};
use relief::scene::{BACKGROUND, Built, ModelChoice, SceneKind, build_scene};
use relief::settings::Settings;
use relief::term::ColorDepth;
use relief::{Framebuffer, Renderer};

fn wheel(s: &mut State, kind: MouseEventKind) {
    let e = Event::Mouse(MouseEvent {
        kind,
        column: 10,
        row: 5,
        modifiers: KeyModifiers::NONE,
    });
    if let Some(a) = action_for_event(s, &e) {
        update(s, a);
    }
}

fn key(s: &mut State, c: char) {
    let e = Event::Key(KeyEvent::new(KeyCode::Char(c), KeyModifiers::NONE));
    if let Some(a) = action_for_event(s, &e) {
        update(s, a);
    }
}

#[test]
fn the_wheel_and_keys_zoom_within_bounds_and_r_resets() {
    let mut s = State::new(Settings::default(), ColorDepth::Truecolor);
    assert_eq!(s.distance, REFERENCE_DISTANCE);
    wheel(&mut s, MouseEventKind::ScrollUp);
    assert!((s.distance - REFERENCE_DISTANCE / ZOOM_STEP).abs() < 1e-5);
    wheel(&mut s, MouseEventKind::ScrollDown);
    assert!((s.distance - REFERENCE_DISTANCE).abs() < 1e-5);
    key(&mut s, 'i');
    assert!(s.distance < REFERENCE_DISTANCE);
    key(&mut s, 'I');
    key(&mut s, 'I');
    assert!(s.distance > REFERENCE_DISTANCE);
    // Never through the model, never out of sight.
    for _ in 0..100 {
        wheel(&mut s, MouseEventKind::ScrollUp);
    }
    assert_eq!(s.distance, MIN_DISTANCE);
    for _ in 0..100 {
        key(&mut s, 'I');
    }
    assert_eq!(s.distance, MAX_DISTANCE);
    // The zoom is part of what the picture depends on, and shows in the status line.
    let far = s.look();
    assert!(relief::app::view::status_line(&s, 300).contains("distance 40.0"));
    key(&mut s, 'r');
    assert_eq!(s.distance, REFERENCE_DISTANCE);
    assert_ne!(s.look(), far);
    // `r` goes back to the distance the view started with.
    let mut s = State::new(Settings::default(), ColorDepth::Truecolor).with_distance(3.0);
    update(&mut s, Action::ZoomOut);
    update(&mut s, Action::ResetView);
    assert_eq!(s.distance, 3.0);
}

#[test]
fn the_plasma_has_no_camera_so_the_wheel_does_nothing() {
    let mut s = State::new(Settings::default(), ColorDepth::Truecolor);
    s.scene = SceneKind::Plasma;
    wheel(&mut s, MouseEventKind::ScrollUp);
    assert_eq!(s.distance, REFERENCE_DISTANCE);
}

/// Pixels of a `size`² frame covered by the cube seen face on from `distance`.
fn covered(distance: f32, size: usize) -> usize {
    let Built::Scene(mut scene) = build_scene(
        SceneKind::Cube,
        &ModelChoice::Cube,
        Arc::new(relief::texture::procedural::brick()),
        false,
    )
    .unwrap() else {
        panic!("the cube scene is 3D");
    };
    scene.camera = scene.camera.at_distance(distance);
    let settings = Settings {
        rotation: Vec3::ZERO,
        ..Settings::default()
    };
    let mut fb = Framebuffer::new(size, size);
    Renderer::new().render(&scene, &settings, &mut fb);
    (0..size)
        .flat_map(|y| fb.row(y).to_vec())
        .filter(|p| *p != BACKGROUND)
        .count()
}

#[test]
fn halving_the_distance_grows_the_cube_as_the_projection_says() {
    // Face on, only the front face (z = 1) shows: its half side, 1, is seen
    // from d − 1 away, so it spans f / (d − 1) pixels either side of the
    // centre, f = (size / 2) / tan(30°) for the 60° vertical field of view.
    let size = 200;
    let f = (size as f64 / 2.0) / 30f64.to_radians().tan();
    for d in [8.0f32, 4.0] {
        let half = f / (d as f64 - 1.0);
        let want = (2.0 * half).powi(2);
        let got = covered(d, size) as f64;
        // Edge pixels may go either way: at most one perimeter's worth.
        let slack = 8.0 * half;
        assert!(
            (got - want).abs() <= slack,
            "distance {d}: {got} pixels, {want:.0} expected"
        );
    }
    let ratio = covered(4.0, size) as f64 / covered(8.0, size) as f64;
    let expected = (7.0f64 / 3.0).powi(2);
    assert!(
        (ratio / expected - 1.0).abs() < 0.05,
        "{ratio} vs {expected}"
    );
}
