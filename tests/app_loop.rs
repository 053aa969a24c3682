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
        pacer: relief::term::pacing::Pacer::by_writes(),
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

// ---- Pacing by the terminal's replies, with a fake terminal ----

use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use relief::term::pacing::{Pacer, PacingConfig, QUERY};

/// What the fake terminal saw: per write, the frames and queries in it,
/// and the queries still unanswered when it came.
#[derive(Default)]
struct Seen {
    writes: Vec<(usize, usize, usize)>,
    queries: usize,
    answered: usize,
}

/// A terminal that answers the pacing queries only when the test says
/// so: every write is logged and announced on `wrote`.
struct FakeTerm {
    seen: Arc<Mutex<Seen>>,
    wrote: mpsc::Sender<usize>,
}

fn count(data: &[u8], what: &[u8]) -> usize {
    data.windows(what.len()).filter(|w| *w == what).count()
}

impl std::io::Write for FakeTerm {
    fn write(&mut self, data: &[u8]) -> std::io::Result<usize> {
        let queries = count(data, QUERY);
        let mut seen = self.seen.lock().unwrap();
        let unanswered = seen.queries - seen.answered;
        seen.writes
            .push((count(data, BEGIN_SYNC), queries, unanswered));
        seen.queries += queries;
        let _ = self.wrote.send(queries);
        Ok(data.len())
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

/// The test's side: sends input and answers queries.
struct Driver {
    tx: mpsc::Sender<Msg>,
    wrote: mpsc::Receiver<usize>,
    seen: Arc<Mutex<Seen>>,
}

impl Driver {
    /// Waits for the loop's next write; returns the queries in it.
    fn next_write(&self) -> usize {
        self.wrote
            .recv_timeout(Duration::from_secs(30))
            .expect("the loop writes")
    }
    /// The terminal answers `n` queries.
    fn answer(&self, n: usize) {
        for _ in 0..n {
            self.seen.lock().unwrap().answered += 1;
            self.tx.send(Msg::Shown(Instant::now())).unwrap();
        }
    }
    fn send(&self, m: Msg) {
        self.tx.send(m).unwrap();
    }
}

fn right() -> Msg {
    Msg::Input(Event::Key(KeyEvent::new(
        KeyCode::Right,
        KeyModifiers::NONE,
    )))
}

/// Runs the loop on a 100×30 fake terminal with `config` while `drive`
/// plays the terminal and the user. Returns the exit, the rotation and
/// width of each render (a preview renders at half width), what the
/// terminal saw, and the pacer's unanswered queries at the end.
fn paced(
    config: PacingConfig,
    drive: impl FnOnce(&Driver) + Send,
) -> (Exit, Vec<(f32, usize)>, Seen, usize) {
    let (tx, rx) = mpsc::channel();
    let (wrote_tx, wrote) = mpsc::channel();
    let seen = Arc::new(Mutex::new(Seen::default()));
    let driver = Driver {
        tx,
        wrote,
        seen: seen.clone(),
    };
    let term = FakeTerm {
        seen: seen.clone(),
        wrote: wrote_tx,
    };
    let mut renders = Vec::new();
    let (exit, outstanding) = std::thread::scope(|scope| {
        scope.spawn(move || drive(&driver));
        let mut terminal = Terminal::new(SgrBackend::with_size(term, 100, 30)).unwrap();
        let mut state = State::new(Settings::default(), ColorDepth::Truecolor);
        let mut looper = Looper {
            terminal: &mut terminal,
            // A picture that changes everywhere with the rotation: every
            // frame costs many bytes.
            render: |s: &State, fb: &mut relief::Framebuffer| {
                let turn = s.settings.rotation.y as usize;
                renders.push((s.settings.rotation.y, fb.width()));
                for y in 0..fb.height() {
                    for x in 0..fb.width() {
                        let v = (x * 7 + y * 13 + turn * 31) % 251;
                        fb.set(x, y, [v as u8, (v * 3 % 256) as u8, (255 - v) as u8]);
                    }
                }
                relief::FrameStats::default()
            },
            background: [0, 0, 0],
            rx: &rx,
            textures: None,
            stage: None,
            pacer: Pacer::new(config),
        };
        let exit = looper.run(&mut state).unwrap();
        (exit, looper.pacer.outstanding())
    });
    let seen = Arc::into_inner(seen).unwrap().into_inner().unwrap();
    (exit, renders, seen, outstanding)
}

/// Time-outs far beyond any test's run: nothing here waits for them.
fn patient() -> PacingConfig {
    PacingConfig {
        first_reply: Duration::from_secs(600),
        lost_reply: Duration::from_secs(600),
        previews: false,
        ..PacingConfig::default()
    }
}

#[test]
fn one_frame_in_flight_and_input_meanwhile_folds_into_one_frame() {
    let (exit, renders, seen, _) = paced(patient(), |d| {
        // The first write: a probe query, the first frame and its query.
        assert_eq!(d.next_write(), 2);
        // Keys while the frame is in flight: nothing is drawn for them yet.
        for _ in 0..5 {
            d.send(right());
        }
        d.answer(2);
        // One frame for all five keys.
        assert_eq!(d.next_write(), 1);
        d.answer(1);
        // Then its figures in the status line, then nothing.
        assert_eq!(d.next_write(), 1);
        d.answer(1);
        d.send(Msg::InputClosed("end of input".into()));
    });
    assert!(matches!(exit, Exit::InputClosed(_)));
    assert_eq!(
        renders.iter().map(|r| r.0).collect::<Vec<_>>(),
        vec![35.0, 60.0],
        "the first picture, then one with the latest state"
    );
    // (The terminal's own restore when it is dropped is not a frame.)
    let writes: Vec<_> = seen.writes.iter().filter(|w| w.0 > 0).collect();
    assert_eq!(writes.len(), 3, "{writes:?}");
    for (i, &&(frames, _, unanswered)) in writes.iter().enumerate() {
        assert_eq!(frames, 1, "write {i} is one frame");
        assert_eq!(unanswered, 0, "write {i} went with a frame in flight");
    }
}

#[test]
fn quitting_does_not_wait_for_the_frame_in_flight() {
    let (exit, _, seen, outstanding) = paced(patient(), |d| {
        assert_eq!(d.next_write(), 2);
        // Never answered; the user quits.
        d.send(right());
        d.send(key('q'));
    });
    assert_eq!(exit, Exit::Quit);
    let frames = seen.writes.iter().filter(|w| w.0 > 0).count();
    assert_eq!(frames, 1, "nothing more was drawn: {:?}", seen.writes);
    assert_eq!(outstanding, 2, "the loop ended with both replies still due");
}

#[test]
fn a_terminal_that_never_answers_is_paced_by_writes_after_the_time_out() {
    let config = PacingConfig {
        first_reply: Duration::from_millis(50),
        ..patient()
    };
    let (exit, renders, seen, _) = paced(config, |d| {
        assert_eq!(d.next_write(), 2);
        // No answer: after the time-out the key is drawn, with no query.
        d.send(right());
        assert_eq!(d.next_write(), 0);
        // The late replies to the first queries are credited to them: they
        // release nothing, and show the terminal does answer, so the
        // next frame asks again and waits for its own reply.
        d.answer(2);
        d.send(right());
        assert_eq!(d.next_write(), 1);
        d.answer(1);
        assert_eq!(d.next_write(), 1, "the status refresh");
        d.answer(1);
        d.send(Msg::InputClosed("end of input".into()));
    });
    assert!(matches!(exit, Exit::InputClosed(_)));
    assert_eq!(renders[0].0, 35.0);
    assert_eq!(
        renders.iter().map(|r| r.0).collect::<Vec<_>>(),
        vec![35.0, 40.0, 45.0]
    );
    let frames: Vec<_> = seen.writes.iter().filter(|w| w.0 > 0).collect();
    assert_eq!(frames.len(), 4, "{frames:?}");
    // The frame after the late replies went with nothing in flight.
    assert_eq!(frames[2].2, 0, "{frames:?}");
}

#[test]
fn a_burst_over_a_slow_link_gets_previews_then_the_exact_picture() {
    let config = PacingConfig {
        previews: true,
        // Input counts as still coming for half a second: the test's own
        // pace never ends a burst by accident.
        quiet_min: Duration::from_millis(500),
        quiet_max: Duration::from_millis(500),
        ..patient()
    };
    let (_, renders, _, _) = paced(config, |d| {
        assert_eq!(d.next_write(), 2);
        // The probe at once, the frame slowly: a slow link.
        d.answer(1);
        std::thread::sleep(Duration::from_millis(200));
        d.answer(1);
        assert_eq!(d.next_write(), 1); // the status refresh
        d.answer(1);
        // A burst of keys, each while a frame is in flight.
        d.send(right());
        for _ in 0..3 {
            let q = d.next_write();
            d.send(right());
            d.send(right());
            std::thread::sleep(Duration::from_millis(50));
            d.answer(q);
        }
        // Input stops: the exact picture follows on its own, then its figures.
        loop {
            let q = d.next_write();
            d.answer(q);
            // The exact picture's status refresh is the last write.
            let writes = d.seen.lock().unwrap().writes.len();
            if q == 1 && writes >= 7 {
                break;
            }
        }
        d.send(Msg::InputClosed("end of input".into()));
    });
    let full = 100;
    assert_eq!(renders[0], (35.0, full), "the first picture is exact");
    assert_eq!(renders[1], (40.0, full), "a lone key is exact at once");
    assert!(
        renders[2..renders.len() - 1]
            .iter()
            .all(|r| r.1 == full / 2),
        "previews at half resolution during the burst: {renders:?}"
    );
    assert_eq!(
        *renders.last().unwrap(),
        (35.0 + 5.0 * 7.0, full),
        "the exact picture of the latest state last: {renders:?}"
    );
}
