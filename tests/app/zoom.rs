//! Zoom: the wheel and `i` / `I` move the camera along its line of sight,
//! within bounds, `r` comes back; and the picture grows as the projection
//! says it must.

use std::sync::Arc;

use crossterm::event::{
    Event, KeyCode, KeyEvent, KeyModifiers, MouseButton, MouseEvent, MouseEventKind,
};
use glam::Vec3;
use relief::app::state::ZOOM_STEP;
use relief::app::{Action, State, action_for_event, update};
use relief_core::framebuffer::Framebuffer;
use relief_core::settings::Settings;
use relief_pipeline::render::Renderer;
use relief_scene::camera::{MAX_DISTANCE, MIN_DISTANCE, REFERENCE_DISTANCE};
use relief_scene::{BACKGROUND, Built, ModelChoice, SceneKind, build_scene};
use relief_term::ColorDepth;

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
        Arc::new(relief_texture::decode::procedural::brick()),
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

fn mouse(s: &mut State, kind: MouseEventKind, column: u16, row: u16, modifiers: KeyModifiers) {
    let e = Event::Mouse(MouseEvent {
        kind,
        column,
        row,
        modifiers,
    });
    if let Some(a) = action_for_event(s, &e) {
        update(s, a);
    }
}

/// The cube seen face on through the view's stage with this state, and
/// the centre (mean column and row) of the pixels it covers.
fn centre_through_stage(s: &State, size: usize) -> (f64, f64) {
    use relief::app::stage::Stage;
    let mut stage = Stage::new(
        SceneKind::Cube,
        &ModelChoice::Cube,
        Arc::new(relief_texture::decode::procedural::brick()),
        false,
    )
    .unwrap();
    let mut fb = Framebuffer::new(size, size);
    stage.render(&mut Renderer::new(), s, &mut fb);
    let (mut n, mut sx, mut sy) = (0.0, 0.0, 0.0);
    for y in 0..size {
        for (x, p) in fb.row(y).iter().enumerate() {
            if *p != BACKGROUND {
                n += 1.0;
                sx += x as f64 + 0.5;
                sy += y as f64 + 0.5;
            }
        }
    }
    (sx / n, sy / n)
}

/// A middle drag (or Shift+drag) of 10 columns and 5 rows moves the orbit
/// centre 10·0.06 right and 5·0.12 up (world units at the reference
/// distance). Face on, the cube's front face (z = 1, 4 units from the eye)
/// then moves by f·(0.6, 0.6)/4 pixels, f = (size/2)/tan 30°; `r` brings
/// it back.
#[test]
fn a_pan_drag_moves_the_picture_by_the_projected_amount() {
    use relief::app::state::{PAN_PER_COL, PAN_PER_ROW};
    let settings = Settings {
        rotation: Vec3::ZERO,
        ..Settings::default()
    };
    let mut s = State::new(settings, ColorDepth::Truecolor);
    let size = 200;
    let (x0, y0) = centre_through_stage(&s, size);
    assert!(
        (x0 - 100.0).abs() < 0.5 && (y0 - 100.0).abs() < 0.5,
        "{x0} {y0}"
    );
    let look = s.look();
    mouse(
        &mut s,
        MouseEventKind::Down(MouseButton::Middle),
        20,
        20,
        KeyModifiers::NONE,
    );
    mouse(
        &mut s,
        MouseEventKind::Drag(MouseButton::Middle),
        30,
        15,
        KeyModifiers::NONE,
    );
    mouse(
        &mut s,
        MouseEventKind::Up(MouseButton::Middle),
        30,
        15,
        KeyModifiers::NONE,
    );
    assert_eq!(
        s.pan,
        glam::Vec2::new(10.0 * PAN_PER_COL, 5.0 * PAN_PER_ROW)
    );
    assert_eq!(
        s.settings.rotation,
        Vec3::ZERO,
        "a pan does not turn the model"
    );
    assert_ne!(s.look(), look, "the picture depends on the pan");
    let f = (size as f64 / 2.0) / 30f64.to_radians().tan();
    let (x1, y1) = centre_through_stage(&s, size);
    let want_x = f * s.pan.x as f64 / 4.0;
    let want_y = -f * s.pan.y as f64 / 4.0;
    assert!(
        (x1 - x0 - want_x).abs() < 0.5,
        "moved {} for {want_x}",
        x1 - x0
    );
    assert!(
        (y1 - y0 - want_y).abs() < 0.5,
        "moved {} for {want_y}",
        y1 - y0
    );
    // Shift+left drag pans the same way.
    let mut t = State::new(settings, ColorDepth::Truecolor);
    mouse(
        &mut t,
        MouseEventKind::Down(MouseButton::Left),
        20,
        20,
        KeyModifiers::SHIFT,
    );
    mouse(
        &mut t,
        MouseEventKind::Drag(MouseButton::Left),
        30,
        15,
        KeyModifiers::SHIFT,
    );
    assert_eq!(t.pan, s.pan);
    key(&mut s, 'r');
    assert_eq!(s.pan, glam::Vec2::ZERO);
    assert_eq!(s.look(), look);
}

/// Ctrl+drag (or a drag with `D` on) turns the lights, not the model, and
/// changes the picture; `r` turns them back.
#[test]
fn a_light_drag_turns_the_lights_and_r_brings_them_back() {
    use relief::app::state::{DEG_PER_COL, DEG_PER_ROW};
    let settings = Settings {
        rotation: Vec3::ZERO,
        ..Settings::default()
    };
    let mut s = State::new(settings, ColorDepth::Truecolor);
    let before = s.look();
    mouse(
        &mut s,
        MouseEventKind::Down(MouseButton::Left),
        20,
        20,
        KeyModifiers::CONTROL,
    );
    mouse(
        &mut s,
        MouseEventKind::Drag(MouseButton::Left),
        25,
        22,
        KeyModifiers::CONTROL,
    );
    assert_eq!(
        s.light_turn,
        glam::Vec2::new(5.0 * DEG_PER_COL, 2.0 * DEG_PER_ROW)
    );
    assert_eq!(s.settings.rotation, Vec3::ZERO);
    let mut w = State::new(settings, ColorDepth::Truecolor);
    key(&mut w, 'D');
    assert_eq!(
        w.message.as_deref(),
        Some("a left drag turns the lights (D again: the model)")
    );
    mouse(
        &mut w,
        MouseEventKind::Down(MouseButton::Left),
        20,
        20,
        KeyModifiers::NONE,
    );
    mouse(
        &mut w,
        MouseEventKind::Drag(MouseButton::Left),
        25,
        22,
        KeyModifiers::NONE,
    );
    assert_eq!(w.light_turn, s.light_turn);
    key(&mut w, 'D');
    assert_eq!(w.message.as_deref(), Some("a left drag turns the model"));
    mouse(
        &mut w,
        MouseEventKind::Down(MouseButton::Left),
        25,
        22,
        KeyModifiers::NONE,
    );
    mouse(
        &mut w,
        MouseEventKind::Drag(MouseButton::Left),
        30,
        22,
        KeyModifiers::NONE,
    );
    assert_eq!(
        w.light_turn, s.light_turn,
        "`D` again: the drag turns the model"
    );
    assert_ne!(w.settings.rotation, Vec3::ZERO);
    // The picture changes with the lights' turn, and comes back with `r`.
    let size = 64;
    let picture = |s: &State| {
        use relief::app::stage::Stage;
        let mut stage = Stage::new(
            SceneKind::Cube,
            &ModelChoice::Cube,
            Arc::new(relief_texture::decode::procedural::brick()),
            false,
        )
        .unwrap();
        let mut fb = Framebuffer::new(size, size);
        stage.render(&mut Renderer::new(), s, &mut fb);
        fb.pixels().to_vec()
    };
    let turned = picture(&s);
    key(&mut s, 'r');
    assert_eq!(s.light_turn, glam::Vec2::ZERO);
    assert_eq!(s.look(), before);
    assert_ne!(picture(&s), turned);
}

/// `Z` turns a Z-up model so +Z points up: the plan's model rotation then
/// carries +Z to +Y (and −Y towards the viewer); `Z` again undoes it.
#[test]
fn the_up_axis_key_stands_z_up_models_upright() {
    use relief_core::settings::UpAxis;
    use relief_pipeline::plan::Plan;
    let settings = Settings {
        rotation: Vec3::ZERO,
        ..Settings::default()
    };
    let mut s = State::new(settings, ColorDepth::Truecolor);
    let Built::Scene(scene) = build_scene(
        SceneKind::Cube,
        &ModelChoice::Cube,
        Arc::new(relief_texture::decode::procedural::brick()),
        false,
    )
    .unwrap() else {
        panic!("3D");
    };
    key(&mut s, 'Z');
    assert_eq!(s.settings.up, UpAxis::Z);
    let r = Plan::new(&scene, &s.settings).rotation;
    assert!((r.transform_vector3(Vec3::Z) - Vec3::Y).length() < 1e-6);
    assert!((r.transform_vector3(-Vec3::Y) - Vec3::Z).length() < 1e-6);
    key(&mut s, 'Z');
    assert_eq!(s.settings.up, UpAxis::Y);
    let r = Plan::new(&scene, &s.settings).rotation;
    assert!((r.transform_vector3(Vec3::Z) - Vec3::Z).length() < 1e-6);
}
