//! The key table (`relief::app::keys::bindings`: the options' keys, then `KEYS`) drives both the key handling
//! and the help: every row is checked here by iterating the table, so a new
//! row is covered without touching these tests.

use std::collections::HashSet;

use crossterm::event::{KeyCode, KeyEvent, KeyModifiers};
use ratatui::Terminal;
use ratatui::backend::TestBackend;
use relief::app::keys::{Help, Key, Mode, bindings, help_lines};
use relief::app::{Action, State, action_for_key, update, view};
use relief_core::framebuffer::Framebuffer;
use relief_core::settings::Settings;
use relief_term::ColorDepth;

/// A state in `mode`.
fn state_in(mode: Mode) -> State {
    let mut s = State::new(Settings::default(), ColorDepth::Truecolor);
    match mode {
        Mode::Normal => {}
        Mode::Help => s.help = true,
        Mode::Textures => s.textures.open = true,
        Mode::Fields => s.panel.focus = Some(0),
        Mode::Prompt => s.prompt = Some(String::new()),
    }
    assert_eq!(Mode::of(&s), mode);
    s
}

/// A key press for a key of the table (a sample character for typed text).
fn event(key: Key) -> KeyEvent {
    match key {
        Key::Plain(code) => KeyEvent::new(code, KeyModifiers::NONE),
        Key::Ctrl(c) => KeyEvent::new(KeyCode::Char(c), KeyModifiers::CONTROL),
        Key::AnyChar => KeyEvent::new(KeyCode::Char('7'), KeyModifiers::NONE),
    }
}

#[test]
fn every_row_s_keys_give_its_action_in_its_mode() {
    for b in bindings() {
        let s = state_in(b.mode);
        for &key in b.keys {
            let typed = match event(key).code {
                KeyCode::Char(c) => Some(c),
                _ => None,
            };
            let want = b.action(key, typed);
            assert!(want.is_some(), "{key:?} in {:?} has no action", b.mode);
            assert_eq!(
                action_for_key(&s, &event(key)),
                want,
                "{key:?} in {:?}",
                b.mode
            );
        }
    }
}

#[test]
fn no_key_is_bound_twice_in_one_mode() {
    for mode in Mode::ALL {
        let mut seen = HashSet::new();
        for b in bindings().iter().filter(|b| b.mode == mode) {
            for key in b.keys {
                assert!(seen.insert(*key), "{key:?} twice in {mode:?}");
            }
        }
    }
}

#[test]
fn a_mode_without_a_row_for_a_key_leaves_it_to_its_fallback_or_ignores_it() {
    // `m` is only a Normal key: the overlays pass it on, typing modes take it as text.
    let m = KeyEvent::new(KeyCode::Char('m'), KeyModifiers::NONE);
    let normal = action_for_key(&state_in(Mode::Normal), &m);
    for mode in Mode::ALL {
        let got = action_for_key(&state_in(mode), &m);
        match mode.fallback() {
            _ if mode == Mode::Normal => {}
            Some(Mode::Normal) => assert_eq!(got, normal, "{mode:?}"),
            _ => assert_ne!(got, normal, "{mode:?}"),
        }
    }
    // Alt is never bound: the key only clears the message.
    let alt = KeyEvent::new(KeyCode::Char('m'), KeyModifiers::ALT);
    for mode in Mode::ALL {
        assert_eq!(action_for_key(&state_in(mode), &alt), Some(Action::Unbound));
    }
}

#[test]
fn every_row_is_described_in_the_help_and_the_overlay_shows_it() {
    let lines = help_lines();
    for mode in Mode::ALL {
        let rows: Vec<_> = bindings().iter().filter(|b| b.mode == mode).collect();
        // A row described by the line above needs a line above it in its mode.
        if let Some(first) = rows.first() {
            assert_ne!(first.help, Help::Above, "first row of {mode:?}");
        }
        for b in rows {
            if let Help::Line(k, t) = b.help {
                assert!(lines.contains(&(k, t)), "{k} {t}");
                assert!(!t.is_empty() && !k.is_empty(), "{k:?} {t:?}");
            }
        }
        if let Some(heading) = mode.heading() {
            assert!(lines.contains(&("", heading)), "{heading}");
        }
    }
    // Drawn: a screen big enough for the whole help shows every line.
    let mut s = state_in(Mode::Normal);
    update(&mut s, relief::app::Action::ToggleHelp);
    let (w, h) = (200, 120);
    let mut term = Terminal::new(TestBackend::new(w, h)).unwrap();
    let fb = Framebuffer::new(w as usize, 2 * h as usize);
    term.draw(|f| view(f, &s, &fb, [0, 0, 0])).unwrap();
    let buf = term.backend().buffer().clone();
    let text: Vec<String> = (0..h)
        .map(|y| (0..w).map(|x| buf[(x, y)].symbol().to_string()).collect())
        .collect();
    for (k, t) in lines {
        let wanted = if k.is_empty() {
            t.to_string()
        } else {
            format!("{k}  {t}")
        };
        assert!(
            text.iter().any(|row| row.contains(&wanted)),
            "{wanted:?} not drawn"
        );
    }
}
