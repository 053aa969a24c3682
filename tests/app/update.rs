//! Every key and mouse action through `action_for_event` and the pure `update`.

use crossterm::event::{
    Event, KeyCode, KeyEvent, KeyModifiers, MouseButton, MouseEvent, MouseEventKind,
};
use glam::Vec3;
use relief::app::state::{DEG_PER_COL, DEG_PER_ROW};
use relief::app::{Action, Command, State, action_for_event, update};
use relief_core::settings::{DEFAULT_BUMP_STRENGTH, Normals, Settings, Shading};
use relief_scene::{ModelChoice, SceneKind};
use relief_term::ColorDepth;

fn state() -> State {
    State::new(Settings::default(), ColorDepth::Truecolor)
}

fn key_event(code: KeyCode, modifiers: KeyModifiers) -> Event {
    Event::Key(KeyEvent::new(code, modifiers))
}

/// Feeds a key through the mapping and `update`; returns any command.
fn press(s: &mut State, code: KeyCode) -> Option<Command> {
    press_mod(s, code, KeyModifiers::NONE)
}

fn press_mod(s: &mut State, code: KeyCode, m: KeyModifiers) -> Option<Command> {
    let action = action_for_event(s, &key_event(code, m))?;
    update(s, action)
}

fn ch(s: &mut State, c: char) -> Option<Command> {
    press(s, KeyCode::Char(c))
}

fn type_text(s: &mut State, text: &str) {
    for c in text.chars() {
        ch(s, c);
    }
}

fn mouse(s: &mut State, kind: MouseEventKind, column: u16, row: u16) {
    let e = Event::Mouse(MouseEvent {
        kind,
        column,
        row,
        modifiers: KeyModifiers::NONE,
    });
    if let Some(a) = action_for_event(s, &e) {
        update(s, a);
    }
}

#[test]
fn m_cycles_flat_gouraud_phong() {
    let mut s = state();
    assert_eq!(s.settings.shading, Shading::Phong);
    ch(&mut s, 'm');
    assert_eq!(s.settings.shading, Shading::Flat);
    ch(&mut s, 'm');
    assert_eq!(s.settings.shading, Shading::Gouraud);
    ch(&mut s, 'm');
    assert_eq!(s.settings.shading, Shading::Phong);
}

#[test]
fn n_t_c_b_toggle_and_toggle_back() {
    let mut s = state();
    ch(&mut s, 'n');
    assert_eq!(s.settings.normals, Normals::Face);
    ch(&mut s, 'n');
    assert_eq!(s.settings.normals, Normals::Vertex);
    for (c, get) in [
        ('t', (|s: &State| s.settings.texture) as fn(&State) -> bool),
        ('c', |s: &State| s.settings.colors),
        ('b', |s: &State| s.settings.bump),
    ] {
        assert!(get(&s));
        ch(&mut s, c);
        assert!(!get(&s), "{c}");
        ch(&mut s, c);
        assert!(get(&s), "{c}");
    }
    // Nothing else moved.
    assert_eq!(s.settings, Settings::default());
}

#[test]
fn quit_keys() {
    for (code, m) in [
        (KeyCode::Char('q'), KeyModifiers::NONE),
        (KeyCode::Esc, KeyModifiers::NONE),
        (KeyCode::Char('c'), KeyModifiers::CONTROL),
    ] {
        let mut s = state();
        press_mod(&mut s, code, m);
        assert!(s.quit, "{code:?}");
    }
    // Plain c is colours, not quit.
    let mut s = state();
    ch(&mut s, 'c');
    assert!(!s.quit);
}

#[test]
fn unbound_keys_do_nothing() {
    let mut s = state();
    for c in ['j', 'K', 'Q'] {
        let m = if c.is_uppercase() {
            KeyModifiers::SHIFT
        } else {
            KeyModifiers::NONE
        };
        // Nothing but what every key does: the message goes.
        assert_eq!(
            action_for_event(&s, &key_event(KeyCode::Char(c), m)),
            Some(Action::Unbound),
            "{c}"
        );
        press_mod(&mut s, KeyCode::Char(c), m);
    }
    assert_eq!(s, state());
}

#[test]
fn arrows_and_page_keys_rotate_by_steps() {
    let mut s = state();
    let start = s.settings.rotation;
    press(&mut s, KeyCode::Right);
    assert_eq!(s.settings.rotation, start + Vec3::new(0.0, 5.0, 0.0));
    press(&mut s, KeyCode::Left);
    press(&mut s, KeyCode::Left);
    assert_eq!(s.settings.rotation, start + Vec3::new(0.0, -5.0, 0.0));
    press(&mut s, KeyCode::Down);
    assert_eq!(s.settings.rotation.x, start.x + 5.0);
    press(&mut s, KeyCode::Up);
    press(&mut s, KeyCode::Up);
    assert_eq!(s.settings.rotation.x, start.x - 5.0);
    press(&mut s, KeyCode::PageUp);
    assert_eq!(s.settings.rotation.z, 5.0);
    press(&mut s, KeyCode::PageDown);
    press(&mut s, KeyCode::PageDown);
    // Angles stay in [0, 360).
    assert_eq!(s.settings.rotation.z, 355.0);
}

#[test]
fn r_resets_orientation_and_stops_auto_rotation() {
    let mut s = state();
    press(&mut s, KeyCode::Right);
    ch(&mut s, ' ');
    assert!(s.auto_rotate);
    ch(&mut s, 'r');
    assert_eq!(s.settings.rotation, Vec3::new(25.0, 35.0, 0.0));
    assert!(!s.auto_rotate);
}

#[test]
fn space_toggles_auto_rotation_which_turns_with_time() {
    let mut s = state();
    update(&mut s, Action::Tick { seconds: 0.1 });
    assert_eq!(s.settings.rotation.y, 35.0, "no turning while off");
    ch(&mut s, ' ');
    assert!(s.auto_rotate);
    update(&mut s, Action::Tick { seconds: 0.1 });
    assert!((s.settings.rotation.y - 39.0).abs() < 1e-4);
    // A long stall is capped, NaN ignored.
    update(&mut s, Action::Tick { seconds: 100.0 });
    assert!((s.settings.rotation.y - 49.0).abs() < 1e-3);
    update(&mut s, Action::Tick { seconds: f32::NAN });
    assert!((s.settings.rotation.y - 49.0).abs() < 1e-3);
    ch(&mut s, ' ');
    assert!(!s.auto_rotate);
}

#[test]
fn an_animated_model_plays_its_first_clip_and_the_keys_drive_it() {
    let mut s = state();
    // Without clips the keys say so and nothing moves.
    ch(&mut s, 'A');
    assert_eq!(s.message.as_deref(), Some("this model has no animation"));
    assert!(!s.continuous());
    let notes = relief_scene::LoadedNotes {
        clips: vec![("Walk".into(), 2.0), ("Run".into(), 1.0)],
        ..Default::default()
    };
    update(&mut s, Action::ModelNotes(notes));
    assert!(s.playback.playing && s.continuous());
    assert_eq!(s.look().animation, Some((0, 0.0)));
    update(&mut s, Action::Tick { seconds: 0.2 });
    assert_eq!(s.look().animation, Some((0, 0.2)));
    // A stall is capped at a quarter second; time loops within the clip.
    update(&mut s, Action::Tick { seconds: 9.0 });
    assert!((s.playback.time - 0.45).abs() < 1e-5, "{}", s.playback.time);
    for _ in 0..7 {
        update(&mut s, Action::Tick { seconds: 0.25 });
    }
    assert!((s.playback.time - 0.2).abs() < 1e-5, "{}", s.playback.time);
    // A pauses: ticks then do nothing; `.` and `,` step a 30th of a second.
    ch(&mut s, 'A');
    assert!(!s.playback.playing && !s.continuous());
    update(&mut s, Action::Tick { seconds: 0.1 });
    assert!((s.playback.time - 0.2).abs() < 1e-5);
    ch(&mut s, '.');
    ch(&mut s, '.');
    ch(&mut s, ',');
    assert!((s.playback.time - (0.2 + 1.0 / 30.0)).abs() < 1e-5);
    // Stepping back past the start goes to the end.
    s.playback.time = 0.0;
    ch(&mut s, ',');
    assert!((s.playback.time - (2.0 - 1.0 / 30.0)).abs() < 1e-5);
    // C: the next clip from its start, then back to the first.
    ch(&mut s, 'C');
    assert_eq!(s.look().animation, Some((1, 0.0)));
    let line = s.message.clone().unwrap();
    assert!(line.contains("animation 2 of 2: Run"), "{line}");
    ch(&mut s, 'C');
    assert_eq!(s.playback.clip, 0);
    // Another scene has no clips until its notes say so.
    update(
        &mut s,
        Action::SceneBuilt(Ok((
            relief_scene::SceneKind::Cube,
            relief_scene::ModelChoice::Cube,
        ))),
    );
    assert_eq!(s.look().animation, None);
    assert!(!s.continuous());
}

#[test]
fn v_cycles_the_files_cameras_then_the_framing_camera() {
    let mut s = state();
    ch(&mut s, 'V');
    assert_eq!(
        s.message.as_deref(),
        Some("this model has no camera of its own")
    );
    let notes = relief_scene::LoadedNotes {
        cameras: 2,
        ..Default::default()
    };
    update(&mut s, Action::ModelNotes(notes));
    let start = s.settings.rotation;
    ch(&mut s, 'V');
    assert_eq!((s.camera, s.look().camera), (Some(0), Some(0)));
    // Through the file's camera the model stands as the file places it,
    // and `r` comes back to that.
    assert_eq!(s.settings.rotation, Vec3::ZERO);
    ch(&mut s, 'r');
    assert_eq!(s.settings.rotation, Vec3::ZERO);
    ch(&mut s, 'V');
    assert_eq!(s.camera, Some(1));
    ch(&mut s, 'V');
    assert_eq!(s.camera, None);
    assert_eq!(s.settings.rotation, start);
}

#[test]
fn plus_minus_change_bump_strength_within_bounds() {
    let mut s = state();
    ch(&mut s, '+');
    assert!((s.settings.bump_strength - DEFAULT_BUMP_STRENGTH * 1.25).abs() < 1e-7);
    ch(&mut s, '-');
    assert!((s.settings.bump_strength - DEFAULT_BUMP_STRENGTH).abs() < 1e-7);
    for _ in 0..100 {
        ch(&mut s, '-');
    }
    assert_eq!(s.settings.bump_strength, 0.0);
    ch(&mut s, '+');
    assert!(s.settings.bump_strength > 0.0);
    for _ in 0..200 {
        ch(&mut s, '+');
    }
    assert_eq!(s.settings.bump_strength, 1.0);
}

#[test]
fn s_asks_the_loop_to_save_and_the_result_is_shown() {
    let mut s = state();
    assert_eq!(ch(&mut s, 's'), Some(Command::SavePng));
    update(&mut s, Action::Saved(Ok("relief-1.png".into())));
    assert_eq!(s.message.as_deref(), Some("saved relief-1.png"));
    update(&mut s, Action::Saved(Err("cannot write \x1b[31mx".into())));
    assert_eq!(s.message.as_deref(), Some("not saved: cannot write ?[31mx"));
}

#[test]
fn question_mark_opens_help_and_escape_closes_it_without_quitting() {
    let mut s = state();
    ch(&mut s, '?');
    assert!(s.help);
    press(&mut s, KeyCode::Esc);
    assert!(!s.help);
    assert!(!s.quit);
    ch(&mut s, '?');
    ch(&mut s, '?');
    assert!(!s.help);
    // Keys still work under the help.
    ch(&mut s, '?');
    ch(&mut s, 'm');
    assert_eq!(s.settings.shading, Shading::Flat);
    // But the scrolling keys scroll the help, not the model.
    let before = s.settings.rotation;
    press(&mut s, KeyCode::Down);
    press(&mut s, KeyCode::PageDown);
    assert_eq!(s.help_scroll, 9);
    press(&mut s, KeyCode::Up);
    assert_eq!(s.help_scroll, 8);
    press(&mut s, KeyCode::Home);
    assert_eq!(s.help_scroll, 0);
    press(&mut s, KeyCode::Up);
    assert_eq!(s.help_scroll, 0);
    assert_eq!(s.settings.rotation, before);
    // With the help closed the arrows rotate again.
    press(&mut s, KeyCode::Esc);
    press(&mut s, KeyCode::Down);
    assert_ne!(s.settings.rotation, before);
}

#[test]
fn left_drag_turns_about_x_and_y() {
    let mut s = state();
    mouse(&mut s, MouseEventKind::Down(MouseButton::Left), 10, 5);
    mouse(&mut s, MouseEventKind::Drag(MouseButton::Left), 13, 7);
    assert_eq!(
        s.settings.rotation,
        Vec3::new(25.0 + 2.0 * DEG_PER_ROW, 35.0 + 3.0 * DEG_PER_COL, 0.0)
    );
    mouse(&mut s, MouseEventKind::Up(MouseButton::Left), 13, 7);
    assert_eq!(s.drag, None);
    // Motion after release does nothing (no button held: no drag report).
    let before = s.settings.rotation;
    mouse(&mut s, MouseEventKind::Moved, 20, 20);
    assert_eq!(s.settings.rotation, before);
}

#[test]
fn right_drag_turns_about_z_and_x() {
    let mut s = state();
    mouse(&mut s, MouseEventKind::Down(MouseButton::Right), 10, 5);
    mouse(&mut s, MouseEventKind::Drag(MouseButton::Right), 12, 6);
    assert_eq!(
        s.settings.rotation,
        Vec3::new(25.0 + DEG_PER_ROW, 35.0, 360.0 - 2.0 * DEG_PER_COL)
    );
}

#[test]
fn a_drag_whose_press_was_missed_starts_where_it_is() {
    let mut s = state();
    mouse(&mut s, MouseEventKind::Drag(MouseButton::Left), 40, 10);
    assert_eq!(s.settings.rotation, Vec3::new(25.0, 35.0, 0.0));
    mouse(&mut s, MouseEventKind::Drag(MouseButton::Left), 41, 10);
    assert_eq!(s.settings.rotation.y, 35.0 + DEG_PER_COL);
    // Middle button and wheel do nothing.
    mouse(&mut s, MouseEventKind::Down(MouseButton::Middle), 1, 1);
    mouse(&mut s, MouseEventKind::ScrollUp, 1, 1);
    assert_eq!(s.settings.rotation.y, 35.0 + DEG_PER_COL);
}

#[test]
fn orientation_fields_edit_apply_and_cancel() {
    let mut s = state();
    press(&mut s, KeyCode::Tab);
    assert_eq!(s.panel.focus, Some(0));
    // Typing replaces the field; letters go to the field, not to the commands.
    type_text(&mut s, "90");
    assert_eq!(s.field_text(0), "90");
    press(&mut s, KeyCode::Tab);
    assert_eq!(s.panel.focus, Some(1));
    type_text(&mut s, "-45.5");
    press(&mut s, KeyCode::Tab);
    type_text(&mut s, "370");
    press(&mut s, KeyCode::Backspace);
    assert_eq!(s.field_text(2), "37");
    assert_eq!(
        s.settings.rotation,
        Vec3::new(25.0, 35.0, 0.0),
        "not applied yet"
    );
    press(&mut s, KeyCode::Enter);
    assert_eq!(s.settings.rotation, Vec3::new(90.0, 314.5, 37.0));
    assert_eq!(s.panel.focus, None);
    assert_eq!(s.message, None);

    // Esc cancels every edit.
    press(&mut s, KeyCode::Tab);
    type_text(&mut s, "1");
    press(&mut s, KeyCode::Esc);
    assert_eq!(s.settings.rotation.x, 90.0);
    assert_eq!(s.panel.focus, None);
    assert!(!s.quit, "Esc in the fields does not quit");
    assert_eq!(s.field_text(0), "90");

    // Shift-Tab goes backwards, from outside to Z.
    press_mod(&mut s, KeyCode::BackTab, KeyModifiers::SHIFT);
    assert_eq!(s.panel.focus, Some(2));
    press_mod(&mut s, KeyCode::BackTab, KeyModifiers::SHIFT);
    assert_eq!(s.panel.focus, Some(1));
}

#[test]
fn invalid_entries_are_refused_and_the_old_value_kept() {
    for bad in ["abc", "NaN", "inf", "-infinity", "", "1e99", "1,5"] {
        let mut s = state();
        press(&mut s, KeyCode::Tab);
        press(&mut s, KeyCode::Tab);
        if bad.is_empty() {
            press(&mut s, KeyCode::Backspace);
            press(&mut s, KeyCode::Backspace);
        } else {
            type_text(&mut s, bad);
        }
        press(&mut s, KeyCode::Enter);
        assert_eq!(s.settings.rotation, Vec3::new(25.0, 35.0, 0.0), "{bad:?}");
        let msg = s.message.clone().unwrap_or_default();
        assert!(
            msg.starts_with("Y: ") && msg.contains("kept 35°"),
            "{bad:?}: {msg}"
        );
        assert_eq!(s.panel.focus, Some(1), "focus stays on the bad field");
        assert_eq!(s.field_text(1), "35");
    }
    // A good field is applied even when another is refused.
    let mut s = state();
    press(&mut s, KeyCode::Tab);
    type_text(&mut s, "10");
    press(&mut s, KeyCode::Tab);
    type_text(&mut s, "x");
    press(&mut s, KeyCode::Enter);
    assert_eq!(s.settings.rotation, Vec3::new(10.0, 35.0, 0.0));
    // Huge finite angles are reduced, not refused.
    let mut s = state();
    press(&mut s, KeyCode::Tab);
    type_text(&mut s, "1e9");
    press(&mut s, KeyCode::Enter);
    assert_eq!(s.settings.rotation.x, 1e9f64.rem_euclid(360.0) as f32);
}

#[test]
fn drags_update_the_fields_live() {
    let mut s = state();
    press(&mut s, KeyCode::Tab);
    assert_eq!(s.field_text(1), "35");
    mouse(&mut s, MouseEventKind::Down(MouseButton::Left), 0, 0);
    mouse(&mut s, MouseEventKind::Drag(MouseButton::Left), 5, 0);
    assert_eq!(s.field_text(1), "45");
}

#[test]
fn paste_shows_sanitized_text_or_fills_the_focused_field() {
    let mut s = state();
    let e = Event::Paste("/tmp/brick\x1b[2J.png\n".into());
    let a = action_for_event(&s, &e).unwrap();
    assert_eq!(a, Action::Paste("/tmp/brick\x1b[2J.png\n".into()));
    update(&mut s, a);
    assert_eq!(s.message.as_deref(), Some("pasted: /tmp/brick?[2J.png?"));
    press(&mut s, KeyCode::Tab);
    update(&mut s, Action::Paste("12.5".into()));
    press(&mut s, KeyCode::Enter);
    assert_eq!(s.settings.rotation.x, 12.5);
}

#[test]
fn resize_changes_nothing_in_the_state() {
    let mut s = state();
    let a = action_for_event(&s, &Event::Resize(10, 3)).unwrap();
    assert_eq!(a, Action::Resize);
    update(&mut s, a);
    assert_eq!(s, state());
}

#[test]
fn slash_opens_a_path_prompt_that_takes_every_key() {
    let mut s = state();
    assert_eq!(ch(&mut s, '/'), None);
    assert_eq!(s.prompt.as_deref(), Some(""));
    // Mode keys are text while the prompt is open.
    type_text(&mut s, "my bricks.mxq");
    assert_eq!(s.settings, Settings::default());
    press(&mut s, KeyCode::Backspace);
    press(&mut s, KeyCode::Backspace);
    type_text(&mut s, "pm");
    assert_eq!(s.prompt.as_deref(), Some("my bricks.mpm"));
    // A paste goes into the prompt, not into the texture list.
    assert_eq!(update(&mut s, Action::Paste("\x1b[31m\n".into())), None);
    assert_eq!(s.prompt.as_deref(), Some("my bricks.mpm\x1b[31m"));
    press(&mut s, KeyCode::Backspace);
    press(&mut s, KeyCode::Backspace);
    press(&mut s, KeyCode::Backspace);
    press(&mut s, KeyCode::Backspace);
    press(&mut s, KeyCode::Backspace);
    assert_eq!(
        press(&mut s, KeyCode::Enter),
        Some(Command::AddPaths("my bricks.mpm".into()))
    );
    assert_eq!(s.prompt, None);
    assert!(s.message.as_deref().unwrap().contains("my bricks.mpm"));
}

#[test]
fn the_prompt_cancels_with_esc_and_refuses_an_empty_path() {
    let mut s = state();
    ch(&mut s, '/');
    type_text(&mut s, "x.png");
    assert_eq!(press(&mut s, KeyCode::Esc), None);
    assert_eq!(s.prompt, None);
    assert!(!s.quit, "Esc closes the prompt, it does not quit");
    ch(&mut s, '/');
    type_text(&mut s, "   ");
    assert_eq!(press(&mut s, KeyCode::Enter), None);
    assert_eq!(s.message.as_deref(), Some("no path typed"));
}

fn in_plasma() -> State {
    let mut s = state();
    update(
        &mut s,
        Action::SceneBuilt(Ok((
            relief_scene::SceneKind::Plasma,
            relief_scene::ModelChoice::Cube,
        ))),
    );
    s
}

#[test]
fn keys_of_the_3d_scene_are_refused_in_the_plasma_and_change_nothing() {
    let keys: Vec<KeyCode> = "mtbefadFgincyYE+-hlL1vr"
        .chars()
        .map(KeyCode::Char)
        .chain([
            KeyCode::Left,
            KeyCode::Right,
            KeyCode::Up,
            KeyCode::Down,
            KeyCode::PageUp,
            KeyCode::Tab,
            KeyCode::Char(' '),
        ])
        .collect();
    for code in keys {
        let mut s = in_plasma();
        let before = s.clone();
        assert_eq!(press(&mut s, code), None, "{code:?}");
        let msg = s.message.clone().unwrap_or_default();
        assert!(msg.contains("not in the plasma"), "{code:?}: {msg:?}");
        s.message = None;
        assert_eq!(s, before, "{code:?} changed the state");
    }
    // z acts in the plasma, and is refused elsewhere.
    let mut s = in_plasma();
    ch(&mut s, 'z');
    assert_eq!(s.plasma_normal, relief_plasma::PlasmaNormal::Exact);
    assert_eq!(s.message, None);
    let mut s = state();
    ch(&mut s, 'z');
    assert_eq!(s.plasma_normal, relief_plasma::PlasmaNormal::Table);
    assert!(s.message.unwrap().contains("only in the plasma"));
}

#[test]
fn entering_the_plasma_stops_auto_rotation() {
    let mut s = state();
    ch(&mut s, ' ');
    assert!(s.auto_rotate);
    let s = {
        let mut t = s.clone();
        update(
            &mut t,
            Action::SceneBuilt(Ok((
                relief_scene::SceneKind::Plasma,
                relief_scene::ModelChoice::Cube,
            ))),
        );
        t
    };
    assert!(!s.auto_rotate);
}

#[test]
fn keys_whose_effect_cannot_show_say_so_and_change_nothing() {
    use relief_core::settings::Technique;
    // E outside Phong.
    let mut s = state();
    ch(&mut s, 'm'); // flat
    let before = s.settings;
    ch(&mut s, 'E');
    assert_eq!(s.settings, before);
    assert!(s.message.as_deref().unwrap().contains("Phong"));
    // In Phong it acts (the default is fill display).
    let mut s = state();
    ch(&mut s, 'E');
    assert!(s.settings.environment);
    assert_eq!(s.message, None);
    // v outside dot3, then with dot3.
    let mut s = state();
    ch(&mut s, 'v');
    assert_eq!(s.settings.light_vector, Settings::default().light_vector);
    assert!(s.message.as_deref().unwrap().contains("dot3"));
    s.settings.technique = Technique::Dot3;
    ch(&mut s, 'v');
    assert_ne!(s.settings.light_vector, Settings::default().light_vector);
    // y and Y with specular off, then on.
    let mut s = state();
    let shininess = s.settings.shininess;
    ch(&mut s, 'y');
    ch(&mut s, 'Y');
    assert_eq!(s.settings.shininess, shininess);
    assert!(s.message.as_deref().unwrap().contains("specular on (g)"));
    ch(&mut s, 'g');
    ch(&mut s, 'y');
    assert_eq!(s.settings.shininess, shininess * 2.0);
    assert_eq!(
        s.message.as_deref(),
        Some(format!("shininess {}", shininess * 2.0).as_str())
    );
    // + and - say the strength they set; outside Phong they are refused.
    let mut s = state();
    ch(&mut s, '+');
    let k = DEFAULT_BUMP_STRENGTH * relief_core::settings::BUMP_FACTOR;
    assert!((s.settings.bump_strength - k).abs() < 1e-9);
    assert!(
        s.message
            .as_deref()
            .unwrap()
            .starts_with("bump strength 0.007")
    );
    ch(&mut s, 'm');
    let k = s.settings.bump_strength;
    ch(&mut s, '-');
    assert_eq!(s.settings.bump_strength, k);
    assert!(s.message.as_deref().unwrap().contains("Phong"));
}

#[test]
fn the_next_action_clears_the_message_and_reports_do_not() {
    let mut s = state();
    update(&mut s, Action::Saved(Ok("x.png".into())));
    assert!(s.message.is_some());
    // What the loop reports keeps it.
    update(&mut s, Action::Resize);
    update(&mut s, Action::HelpFits(3));
    assert!(s.message.is_some());
    ch(&mut s, 'n');
    assert_eq!(s.message, None);
}

#[test]
fn esc_closes_the_top_overlay_only() {
    // The cost panel: Esc closes it; a second Esc right after does not quit.
    let mut s = state();
    ch(&mut s, 'k');
    press(&mut s, KeyCode::Esc);
    assert!(!s.cost_panel && !s.quit);
    press(&mut s, KeyCode::Esc);
    assert!(!s.quit, "the Esc after a closing one does not quit");
    assert!(s.message.as_deref().unwrap().contains("Esc again"));
    press(&mut s, KeyCode::Esc);
    assert!(s.quit);
    // Help over the texture panel: one Esc each, then one that only warns.
    let mut s = state();
    ch(&mut s, 'T');
    ch(&mut s, '?');
    press(&mut s, KeyCode::Esc);
    assert!(!s.help && s.textures.open);
    press(&mut s, KeyCode::Esc);
    assert!(!s.textures.open && !s.quit);
    press(&mut s, KeyCode::Esc);
    assert!(!s.quit);
    // Another key in between: Esc quits again.
    let mut s = state();
    ch(&mut s, '?');
    press(&mut s, KeyCode::Esc);
    ch(&mut s, 'n');
    press(&mut s, KeyCode::Esc);
    assert!(s.quit);
}

#[test]
fn help_pages_are_the_lines_shown() {
    let mut s = state();
    ch(&mut s, '?');
    update(&mut s, Action::HelpPageFits(22));
    press(&mut s, KeyCode::PageDown);
    assert_eq!(s.help_scroll, 22);
    press(&mut s, KeyCode::PageDown);
    assert_eq!(s.help_scroll, 44);
    press(&mut s, KeyCode::PageUp);
    assert_eq!(s.help_scroll, 22);
}

#[test]
fn the_path_prompt_edits_like_a_line_editor() {
    let mut s = state();
    ch(&mut s, '/');
    type_text(&mut s, "tex/bricks.png");
    press(&mut s, KeyCode::Home);
    type_text(&mut s, "my");
    assert_eq!(s.prompt.as_deref(), Some("mytex/bricks.png"));
    press(&mut s, KeyCode::Right);
    press(&mut s, KeyCode::Delete);
    assert_eq!(s.prompt.as_deref(), Some("mytx/bricks.png"));
    press(&mut s, KeyCode::Left);
    press(&mut s, KeyCode::Backspace);
    assert_eq!(s.prompt.as_deref(), Some("mtx/bricks.png"));
    press(&mut s, KeyCode::End);
    type_text(&mut s, "é");
    press_mod(&mut s, KeyCode::Char('w'), KeyModifiers::CONTROL);
    assert_eq!(s.prompt.as_deref(), Some("mtx/"));
    type_text(&mut s, "a b");
    press(&mut s, KeyCode::Left);
    press_mod(&mut s, KeyCode::Char('u'), KeyModifiers::CONTROL);
    assert_eq!(s.prompt.as_deref(), Some("b"));
    assert_eq!(s.prompt_cursor, 0);
    // Tab asks the loop to complete what is before the cursor.
    press(&mut s, KeyCode::End);
    assert_eq!(
        press(&mut s, KeyCode::Tab),
        Some(Command::CompletePath("b".into()))
    );
    update(
        &mut s,
        Action::PromptCompleted(relief::app::line_edit::Completion {
            completed: "bricks/".into(),
            choices: Vec::new(),
            matches: 1,
        }),
    );
    assert_eq!(s.prompt.as_deref(), Some("bricks/"));
    assert_eq!(s.prompt_cursor, 7);
}

#[test]
fn tab_completes_paths_from_the_folder() {
    use relief::app::line_edit::complete_path;
    let dir = std::env::temp_dir().join(format!("relief-complete-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("stones")).unwrap();
    for f in [
        "stone-a.png",
        "stone-b.png",
        ".stone-hidden.png",
        "wood.png",
    ] {
        std::fs::write(dir.join(f), b"").unwrap();
    }
    let base = format!("{}/", dir.display());
    let c = complete_path(&format!("{base}st"));
    assert_eq!(c.completed, format!("{base}stone"));
    assert_eq!(c.matches, 3);
    assert_eq!(c.choices, ["stone-a.png", "stone-b.png", "stones/"]);
    let c = complete_path(&format!("{base}w"));
    assert_eq!(c.completed, format!("{base}wood.png"));
    // A lone folder gets its slash.
    let c = complete_path(&format!("{base}stones"));
    assert_eq!(c.completed, format!("{base}stones/"));
    let c = complete_path(&format!("{base}stone-a"));
    assert_eq!((c.completed, c.matches), (format!("{base}stone-a.png"), 1));
    let c = complete_path(&format!("{base}ston"));
    assert_eq!(c.completed, format!("{base}stone"));
    let c = complete_path(&format!("{base}x"));
    assert_eq!((c.completed, c.matches), (format!("{base}x"), 0));
    let c = complete_path(&format!("{base}.st"));
    assert_eq!(c.completed, format!("{base}.stone-hidden.png"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn esc_after_a_partly_applied_orientation_says_what_was_applied() {
    let mut s = state();
    press(&mut s, KeyCode::Tab);
    type_text(&mut s, "10");
    press(&mut s, KeyCode::Tab);
    type_text(&mut s, "abc");
    press(&mut s, KeyCode::Enter);
    assert_eq!(s.settings.rotation.x, 10.0);
    assert_eq!(s.panel.focus, Some(1));
    press(&mut s, KeyCode::Esc);
    assert_eq!(
        s.message.as_deref(),
        Some("X 10° applied; the other edits dropped")
    );
    // Nothing applied: unchanged.
    let mut s = state();
    press(&mut s, KeyCode::Tab);
    type_text(&mut s, "7");
    press(&mut s, KeyCode::Esc);
    assert_eq!(s.message.as_deref(), Some("orientation unchanged"));
}

#[test]
fn a_negative_zero_angle_shows_as_zero() {
    use relief::app::state::format_angle;
    assert_eq!(format_angle(-0.0), "0");
    assert_eq!(format_angle(-0.04), "0");
    assert_eq!(format_angle(-0.06), "-0.1");
    assert_eq!(format_angle(-5.0), "-5");
}

#[test]
fn ctrl_z_asks_the_loop_to_suspend() {
    let mut s = state();
    assert_eq!(
        press_mod(&mut s, KeyCode::Char('z'), KeyModifiers::CONTROL),
        Some(Command::Suspend)
    );
    assert!(!s.quit);
}

#[test]
fn w_and_w_widen_and_narrow_the_field_of_view_within_its_range() {
    let mut s = state();
    assert_eq!(s.settings.fov, 60.0);
    // Each press multiplies or divides by 9/8, exact in binary.
    ch(&mut s, 'w');
    assert_eq!(s.settings.fov, 67.5);
    assert_eq!(s.message.as_deref(), Some("field of view 67.5°"));
    assert!(relief::app::view::status_line(&s, 300).contains("fov 67.5°"));
    ch(&mut s, 'W');
    assert_eq!(s.settings.fov, 60.0);
    assert!(!relief::app::view::status_line(&s, 300).contains("fov"));
    // 60 · (9/8)^6 ≈ 121.6: the sixth press stops at 120, and 10 is the floor.
    for _ in 0..6 {
        ch(&mut s, 'w');
    }
    assert_eq!(s.settings.fov, 120.0);
    for _ in 0..30 {
        ch(&mut s, 'W');
    }
    assert_eq!(s.settings.fov, 10.0);
    // The plasma has no camera.
    let mut p = state();
    p.scene = relief_scene::SceneKind::Plasma;
    ch(&mut p, 'w');
    assert_eq!(p.settings.fov, 60.0);
    assert!(
        p.message
            .as_deref()
            .unwrap()
            .starts_with("w W (field of view): not in the plasma")
    );
}

#[test]
fn esc_stops_a_load_first_and_the_status_line_shows_it_until_then() {
    use relief::app::load_status::LoadStatus;
    use relief_scene::load_progress::{LoadStep, ProgressNow};
    use relief_scene::{ModelChoice, SceneKind};
    let mut s = state();
    let status = |done| LoadStatus {
        name: "scan.ply".into(),
        progress: ProgressNow {
            step: LoadStep::Reading,
            done,
            total: 4_000_000,
        },
        elapsed: std::time::Duration::from_millis(700),
    };
    assert_eq!(update(&mut s, Action::Loading(status(1_000_000))), None);
    assert_eq!(
        s.message_line().as_deref(),
        Some("loading scan.ply: reading 25% of 4.0 MB · 0.7 s (Esc cancels)")
    );
    // A user's key clears the last message, not the load's line.
    ch(&mut s, 'm');
    update(&mut s, Action::Loading(status(3_000_000)));
    assert!(s.message_line().unwrap().contains("reading 75%"));
    // Esc stops the load, and does not quit; the next Esc would.
    assert_eq!(press(&mut s, KeyCode::Esc), Some(Command::CancelLoad));
    assert!(!s.quit);
    assert_eq!(s.loading, None);
    assert_eq!(
        s.message_line().as_deref(),
        Some("stopped loading scan.ply: the model shown stays")
    );
    assert_eq!(press(&mut s, KeyCode::Esc), None);
    assert!(!s.quit, "the Esc after a stop says how to quit");
    assert_eq!(press(&mut s, KeyCode::Esc), None);
    assert!(s.quit);
    // A build's outcome ends a load's line, whichever it is.
    let mut s = state();
    update(&mut s, Action::Loading(status(0)));
    update(
        &mut s,
        Action::SceneBuilt(Err("model scan.ply, byte 12: bad".into())),
    );
    assert_eq!(s.loading, None);
    update(&mut s, Action::Loading(status(0)));
    update(
        &mut s,
        Action::SceneBuilt(Ok((SceneKind::Cube, ModelChoice::Sphere))),
    );
    assert_eq!(s.loading, None);
}

/// A state showing a model file in the model view.
fn model_view_state() -> State {
    let mut s = state();
    let file = ModelChoice::File("model.glb".into());
    update(&mut s, Action::SceneBuilt(Ok((SceneKind::Cube, file))));
    assert!(s.in_model_view());
    s
}

/// `B` puts the environment behind the model and takes it away; the
/// status line says so while it shows; in the points display, and on a
/// reference scene, it changes nothing and says why.
#[test]
fn capital_b_shows_the_environment_behind_the_model() {
    let mut cube = state();
    ch(&mut cube, 'B');
    assert!(!cube.settings.backdrop);
    let said = cube.message.clone().unwrap_or_default();
    assert!(said.contains("model view"), "{said}");
    let mut s = model_view_state();
    assert!(!s.settings.backdrop);
    ch(&mut s, 'B');
    assert!(s.settings.backdrop);
    assert!(relief::app::view::status_line(&s, 300).contains("backdrop"));
    ch(&mut s, 'B');
    assert!(!s.settings.backdrop);
    assert!(!relief::app::view::status_line(&s, 300).contains("backdrop"));
    ch(&mut s, 'd');
    assert_ne!(s.settings.display, relief_core::settings::Display::Fill);
    ch(&mut s, 'B');
    assert!(!s.settings.backdrop);
}

#[test]
fn capital_j_turns_the_environment_by_thirty_degrees_around_the_circle() {
    let mut cube = state();
    ch(&mut cube, 'J');
    assert_eq!(cube.settings.environment_turn, 0.0);
    let said = cube.message.clone().unwrap_or_default();
    assert!(said.contains("model view"), "{said}");
    let mut s = model_view_state();
    assert_eq!(s.settings.environment_turn, 0.0);
    ch(&mut s, 'J');
    assert_eq!(s.settings.environment_turn, 30.0);
    assert_eq!(s.message.as_deref(), Some("environment turn 30°"));
    assert!(relief::app::view::status_line(&s, 300).contains("env 30°"));
    // Twelve presses make the full turn, back to 0 and off the status line.
    for _ in 0..11 {
        ch(&mut s, 'J');
    }
    assert_eq!(s.settings.environment_turn, 0.0);
    assert!(!relief::app::view::status_line(&s, 300).contains("env "));
    // Outside Phong the key changes nothing and says why.
    ch(&mut s, 'm');
    ch(&mut s, 'J');
    assert_eq!(s.settings.environment_turn, 0.0);
}
