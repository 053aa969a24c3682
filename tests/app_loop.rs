//! The event loop without a terminal: coalescing, rendering only on change,
//! and ending when input ends.

use std::sync::mpsc;

use crossterm::event::{Event, KeyCode, KeyEvent, KeyModifiers};
use ratatui::Terminal;
use relief::app::State;
use relief::app::event_loop::{Exit, Looper, Msg, spawn_input_reader};
use relief::settings::Settings;
use relief::term::backend::BEGIN_SYNC;
use relief::term::{ColorDepth, SgrBackend};

fn key(c: char) -> Msg {
    Msg::Input(Event::Key(KeyEvent::new(
        KeyCode::Char(c),
        KeyModifiers::NONE,
    )))
}

/// Runs the loop over queued messages; returns (exit, renders, frames written, state).
fn run(msgs: Vec<Msg>, close: bool) -> (Exit, usize, usize, State) {
    let (tx, rx) = mpsc::channel();
    for m in msgs {
        tx.send(m).unwrap();
    }
    if close {
        drop(tx);
    } else {
        // Keep the sender alive until after the queued messages: end with EOF.
        tx.send(Msg::InputClosed("end of input".into())).unwrap();
    }
    let mut term = Terminal::new(SgrBackend::with_size(Vec::new(), 40, 12)).unwrap();
    let mut renders = 0;
    let mut state = State::new(Settings::default(), ColorDepth::Truecolor);
    let exit = Looper {
        terminal: &mut term,
        render: |_: &State, fb: &mut relief::Framebuffer| {
            renders += 1;
            fb.fill([renders as u8 * 40, 0, 0]);
            relief::FrameStats::default()
        },
        background: [0, 0, 0],
        rx: &rx,
        textures: None,
        stage: None,
    }
    .run(&mut state)
    .unwrap();
    let out = term.backend().writer();
    let frames = out
        .windows(BEGIN_SYNC.len())
        .filter(|w| *w == BEGIN_SYNC)
        .count();
    (exit, renders, frames, state)
}

#[test]
fn queued_input_is_applied_at_once_and_rendered_once() {
    let mut msgs: Vec<Msg> = (0..30).map(|_| Msg::Resized).collect();
    msgs.extend((0..5).map(|_| key('m')));
    msgs.extend((0..7).map(|_| {
        Msg::Input(Event::Key(KeyEvent::new(
            KeyCode::Right,
            KeyModifiers::NONE,
        )))
    }));
    let (exit, renders, frames, state) = run(msgs, true);
    assert!(matches!(exit, Exit::InputClosed(_)));
    assert_eq!(renders, 1, "one render for the whole batch");
    assert_eq!(
        frames, 2,
        "one frame written, then its figures in the status line"
    );
    assert_eq!(state.settings.rotation.y, 70.0);
    assert_eq!(state.settings.shading, relief::settings::Shading::Gouraud);
    assert!(state.frame.bytes > 0, "the frame's bytes are recorded");
}

#[test]
fn nothing_to_do_means_one_first_frame_and_no_more() {
    // The picture, then one text-only write of its figures, then nothing.
    let (exit, renders, frames, state) = run(vec![], true);
    assert!(matches!(exit, Exit::InputClosed(_)));
    assert_eq!((renders, frames), (1, 2));
    assert!(state.frame.bytes > 0 && !state.frame.frame_time.is_zero());
}

#[test]
fn quit_and_signals_end_the_loop_before_anything_else() {
    let (exit, ..) = run(vec![key('q'), key('m')], false);
    assert_eq!(exit, Exit::Quit);
    let (exit, renders, frames, _) = run(vec![Msg::Signal(15), key('m')], false);
    assert_eq!(exit, Exit::Signal(15));
    assert_eq!((renders, frames), (0, 0));
    let (exit, ..) = run(vec![key('m')], false);
    assert_eq!(exit, Exit::InputClosed("end of input".into()));
}

/// A reader that fails like a terminal whose connection dropped.
struct Broken;

impl std::io::Read for Broken {
    fn read(&mut self, _: &mut [u8]) -> std::io::Result<usize> {
        Err(std::io::Error::from_raw_os_error(5)) // EIO
    }
}

#[test]
fn end_of_file_or_a_read_error_closes_the_input() {
    let (tx, rx) = mpsc::channel();
    spawn_input_reader(std::io::Cursor::new(b"m\x1b[A".to_vec()), tx);
    let got: Vec<Msg> = rx.iter().collect();
    assert_eq!(got.len(), 3, "{got:?}");
    assert!(matches!(got[2], Msg::InputClosed(_)));

    let (tx, rx) = mpsc::channel();
    spawn_input_reader(Broken, tx);
    let got: Vec<Msg> = rx.iter().collect();
    assert_eq!(got.len(), 1);
    assert!(
        matches!(&got[0], Msg::InputClosed(why) if why.contains("error")),
        "{got:?}"
    );
}
