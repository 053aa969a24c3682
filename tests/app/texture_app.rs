//! The texture list in the interactive view, without a terminal: keys and
//! pastes go through `update` to the event loop, which applies them to the
//! list; errors land in the status message and keep the texture.

use std::cell::RefCell;
use std::path::{Path, PathBuf};
use std::sync::{Arc, mpsc};

use clap::ValueEnum;
use crossterm::event::{Event, KeyCode, KeyEvent, KeyModifiers};
use ratatui::Terminal;
use relief::app::event_loop::{Looper, Msg};
use relief::app::texture_list::TextureList;
use relief::app::{Action, Command, State, action_for_key, update};
use relief_core::settings::{Filter, Settings};
use relief_term::{ColorDepth, SgrBackend};

fn data(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(rel)
}

fn key(c: char) -> KeyEvent {
    KeyEvent::new(KeyCode::Char(c), KeyModifiers::NONE)
}

#[test]
fn texture_keys_and_paste_become_commands() {
    let mut s = State::new(Settings::default(), ColorDepth::Truecolor);
    let act = |s: &State, c| action_for_key(s, &key(c)).unwrap();
    assert_eq!(act(&s, 'x'), Action::NextTexture);
    assert_eq!(act(&s, 'X'), Action::PrevTexture);
    assert_eq!(act(&s, 'R'), Action::ReloadTexture);
    let f = act(&s, 'f');
    assert_eq!(update(&mut s, f.clone()), None);
    assert_eq!(s.settings.filter, Filter::NearestMip);
    // `f` visits every filter and comes back.
    let mut seen = vec![s.settings.filter];
    for _ in 1..Filter::value_variants().len() {
        update(&mut s, f.clone());
        seen.push(s.settings.filter);
    }
    for v in Filter::value_variants() {
        assert!(seen.contains(v), "{v:?}");
    }
    update(&mut s, f.clone());
    assert_eq!(s.settings.filter, Filter::NearestMip);
    assert_eq!(
        update(&mut s, Action::NextTexture),
        Some(Command::CycleTexture(true))
    );
    assert_eq!(
        update(&mut s, Action::ReloadTexture),
        Some(Command::ReloadTexture)
    );
    assert_eq!(
        update(&mut s, Action::Paste("'/a b.png'".into())),
        Some(Command::AddPaths("'/a b.png'".into()))
    );
    update(
        &mut s,
        Action::TextureResult(Err("x.png: bad\x1b[2J".into())),
    );
    assert_eq!(s.message.as_deref(), Some("x.png: bad?[2J"));
}

/// Runs the loop over `msgs` with `list`; returns the final state.
fn run(list: &RefCell<TextureList>, msgs: Vec<Msg>) -> State {
    let (tx, rx) = mpsc::channel();
    for m in msgs {
        tx.send(m).unwrap();
    }
    tx.send(Msg::InputClosed("end".into())).unwrap();
    let mut term = Terminal::new(SgrBackend::with_size(Vec::new(), 40, 12)).unwrap();
    let mut state = State::new(Settings::default(), ColorDepth::Truecolor);
    Looper {
        textures: Some(list),
        ..Looper::new(
            &mut term,
            &rx,
            |_: &State, fb: &mut relief_core::framebuffer::Framebuffer| {
                fb.fill([1, 2, 3]);
                relief_core::stats::FrameStats::default()
            },
        )
    }
    .run(&mut state)
    .unwrap();
    state
}

#[test]
fn the_loop_applies_texture_commands_and_reports_errors() {
    let list = RefCell::new(TextureList::new());
    let n0 = list.borrow().len();
    // `x` applies the next built-in.
    let s = run(&list, vec![Msg::Input(Event::Key(key('x')))]);
    assert_eq!(list.borrow().current(), 1);
    assert!(s.message.unwrap().contains("tiles"));
    // A pasted file joins the list and is applied.
    let pasted = format!("'{}'", data("formats/basn2c08.xpm").display());
    let s = run(&list, vec![Msg::Input(Event::Paste(pasted))]);
    assert_eq!((list.borrow().len(), list.borrow().current()), (n0 + 1, n0));
    assert!(s.message.unwrap().contains("basn2c08.xpm"));
    // A bad paste: the error is shown, list and texture stay.
    let before = Arc::clone(list.borrow().texture());
    let bad = format!("{}\n", data("pngsuite/xcrn0g04.png").display());
    let s = run(&list, vec![Msg::Input(Event::Paste(bad))]);
    let msg = s.message.unwrap();
    assert!(
        msg.contains("xcrn0g04.png") && msg.contains("corrupt"),
        "{msg}"
    );
    assert!(Arc::ptr_eq(&before, list.borrow().texture()));
    assert_eq!(list.borrow().len(), n0 + 1);
    // `R` re-reads the current file.
    let s = run(&list, vec![Msg::Input(Event::Key(key('R')))]);
    assert!(s.message.unwrap().contains("basn2c08.xpm"));
}
