//! The event loop without a terminal: coalescing, rendering only on change,
//! and ending when input ends.

use std::sync::mpsc;

use crossterm::event::{Event, KeyCode, KeyEvent, KeyModifiers};
use ratatui::Terminal;
use relief::app::State;
use relief::app::event_loop::{Exit, Looper, Msg, spawn_input_reader};
use relief_core::settings::Settings;
use relief_term::backend::BEGIN_SYNC;
use relief_term::{ColorDepth, SgrBackend};

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
    let exit = Looper::new(
        &mut term,
        &rx,
        |_: &State, fb: &mut relief_core::framebuffer::Framebuffer| {
            renders += 1;
            fb.fill([renders as u8 * 40, 0, 0]);
            relief_core::stats::FrameStats::default()
        },
    )
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
    assert_eq!(
        state.settings.shading,
        relief_core::settings::Shading::Gouraud
    );
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

use std::collections::VecDeque;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use relief_term::pacing::{Pacer, PacingConfig, QUERY};

/// A write of more bytes than this carries a picture (the test's pictures
/// are noise: tens of kilobytes); smaller ones are status refreshes.
const PICTURE: usize = 10_000;

/// What the fake terminal saw, per write: whether it carried a picture,
/// its queries, and the pictures whose query was still unanswered then.
#[derive(Default)]
struct Seen {
    writes: Vec<(bool, usize, usize)>,
    /// Unanswered queries, oldest first: true when one follows a picture.
    pending: VecDeque<bool>,
}

/// Replies sent by the fake terminal.
type Answerer = Option<mpsc::Sender<(Duration, usize)>>;

/// A terminal that logs every write and announces it on `wrote`; its
/// queries are answered by the test (`answer`) or, with an answerer, on
/// their own after a delay (in order, a picture's after `slow`).
struct FakeTerm {
    seen: Arc<Mutex<Seen>>,
    wrote: mpsc::Sender<(usize, bool)>,
    answerer: Answerer,
    slow: Duration,
}

fn count(data: &[u8], what: &[u8]) -> usize {
    data.windows(what.len()).filter(|w| *w == what).count()
}

impl std::io::Write for FakeTerm {
    fn write(&mut self, data: &[u8]) -> std::io::Result<usize> {
        let queries = count(data, QUERY);
        let picture = data.len() > PICTURE;
        let mut seen = self.seen.lock().unwrap();
        let in_flight = seen.pending.iter().filter(|p| **p).count();
        seen.writes.push((picture, queries, in_flight));
        for i in 0..queries {
            // A probe may come before the frame: the last query follows it.
            seen.pending.push_back(picture && i + 1 == queries);
        }
        drop(seen);
        if let Some(a) = &self.answerer {
            let delay = if picture { self.slow } else { Duration::ZERO };
            let _ = a.send((delay, queries));
        }
        let _ = self.wrote.send((queries, picture));
        Ok(data.len())
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

/// The test's side: sends input and answers queries.
struct Driver {
    tx: mpsc::Sender<Msg>,
    wrote: mpsc::Receiver<(usize, bool)>,
    seen: Arc<Mutex<Seen>>,
    renders: Arc<Mutex<Vec<(f32, usize)>>>,
    /// The terminal answers by itself: the test must not answer too.
    auto: bool,
}

impl Driver {
    /// Waits for the loop's next write: its queries and whether it carried a picture.
    fn next_write(&self) -> (usize, bool) {
        self.wrote
            .recv_timeout(Duration::from_secs(30))
            .expect("the loop writes")
    }
    /// Waits for the next write that carries a picture, answering the
    /// queries of the writes before it; returns its queries.
    fn next_picture(&self) -> usize {
        loop {
            match self.next_write() {
                (q, true) => return q,
                (q, false) => self.answer(q),
            }
        }
    }
    /// The terminal answers `n` queries.
    fn answer(&self, n: usize) {
        if self.auto {
            return;
        }
        for _ in 0..n {
            self.seen.lock().unwrap().pending.pop_front();
            self.tx.send(Msg::Shown(Instant::now())).unwrap();
        }
    }
    /// Every query written so far.
    fn answer_all(&self) {
        let n = self.seen.lock().unwrap().pending.len();
        self.answer(n);
    }
    fn send(&self, m: Msg) {
        self.tx.send(m).unwrap();
    }
    fn renders(&self) -> Vec<(f32, usize)> {
        self.renders.lock().unwrap().clone()
    }
}

fn right() -> Msg {
    Msg::Input(Event::Key(KeyEvent::new(
        KeyCode::Right,
        KeyModifiers::NONE,
    )))
}

/// Runs the loop on a 100×30 fake terminal with `config` while `drive`
/// plays the user (and the terminal, unless `slow` is given: then the
/// terminal answers by itself, a picture's query after `slow`). Returns
/// the exit, the rotation and width of each render (a preview renders at
/// half width), what the terminal saw, and the pacer's unanswered queries.
fn paced(
    config: PacingConfig,
    slow: Option<Duration>,
    drive: impl FnOnce(&Driver) + Send,
) -> (Exit, Vec<(f32, usize)>, Seen, usize) {
    let (tx, rx) = mpsc::channel();
    let (wrote_tx, wrote) = mpsc::channel();
    let seen = Arc::new(Mutex::new(Seen::default()));
    let renders = Arc::new(Mutex::new(Vec::new()));
    let answerer = slow.map(|_| {
        let (a_tx, a_rx) = mpsc::channel::<(Duration, usize)>();
        let tx = tx.clone();
        let seen = seen.clone();
        std::thread::spawn(move || {
            // In order: each write's replies after the ones before.
            for (delay, n) in a_rx {
                for i in 0..n {
                    // A probe before the picture comes back at once.
                    if i + 1 == n {
                        std::thread::sleep(delay);
                    }
                    seen.lock().unwrap().pending.pop_front();
                    if tx.send(Msg::Shown(Instant::now())).is_err() {
                        return;
                    }
                }
            }
        });
        a_tx
    });
    let driver = Driver {
        tx,
        wrote,
        seen: seen.clone(),
        renders: renders.clone(),
        auto: slow.is_some(),
    };
    let term = FakeTerm {
        seen: seen.clone(),
        wrote: wrote_tx,
        answerer,
        slow: slow.unwrap_or_default(),
    };
    let (exit, outstanding) = std::thread::scope(|scope| {
        scope.spawn(move || drive(&driver));
        let mut terminal = Terminal::new(SgrBackend::with_size(term, 100, 30)).unwrap();
        let mut state = State::new(Settings::default(), ColorDepth::Truecolor);
        let mut looper = Looper {
            pacer: Pacer::new(config),
            ..Looper::new(
                &mut terminal,
                &rx,
                // A picture that changes everywhere with the rotation: every
                // frame costs many bytes.
                |s: &State, fb: &mut relief_core::framebuffer::Framebuffer| {
                    let turn = s.settings.rotation.y as usize;
                    renders
                        .lock()
                        .unwrap()
                        .push((s.settings.rotation.y, fb.width()));
                    for y in 0..fb.height() {
                        for x in 0..fb.width() {
                            let v = (x * 7 + y * 13 + turn * 31) % 251;
                            fb.set(x, y, [v as u8, (v * 3 % 256) as u8, (255 - v) as u8]);
                        }
                    }
                    relief_core::stats::FrameStats::default()
                },
            )
        };
        let exit = looper.run(&mut state).unwrap();
        (exit, looper.pacer.outstanding())
    });
    let seen = std::mem::take(&mut *seen.lock().unwrap());
    let renders = renders.lock().unwrap().clone();
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

/// No picture was written while another was still unanswered.
fn one_picture_in_flight(seen: &Seen) {
    for (i, &(picture, _, in_flight)) in seen.writes.iter().enumerate() {
        assert!(
            !picture || in_flight == 0,
            "write {i} went with a picture in flight: {:?}",
            seen.writes
        );
    }
}

#[test]
fn one_frame_in_flight_and_input_meanwhile_folds_into_one_frame() {
    let (exit, renders, seen, _) = paced(patient(), None, |d| {
        // The first write: a probe query, the first frame and its query.
        assert_eq!(d.next_picture(), 2);
        // Keys while the frame is in flight: nothing is drawn for them yet.
        for _ in 0..5 {
            d.send(right());
        }
        d.answer_all();
        // One frame for all five keys (a status refresh may come first).
        assert_eq!(d.next_picture(), 1);
        d.answer_all();
        // Then its figures in the status line, then nothing.
        let (q, picture) = d.next_write();
        assert!(!picture);
        d.answer(q);
        d.send(Msg::InputClosed("end of input".into()));
    });
    assert!(matches!(exit, Exit::InputClosed(_)));
    assert_eq!(
        renders.iter().map(|r| r.0).collect::<Vec<_>>(),
        vec![35.0, 60.0],
        "the first picture, then one with the latest state"
    );
    one_picture_in_flight(&seen);
    assert_eq!(seen.writes.iter().filter(|w| w.0).count(), 2);
}

#[test]
fn quitting_does_not_wait_for_the_frame_in_flight() {
    let (exit, renders, seen, outstanding) = paced(patient(), None, |d| {
        assert_eq!(d.next_picture(), 2);
        // Never answered; the user turns, then quits.
        d.send(right());
        d.send(key('q'));
    });
    assert_eq!(exit, Exit::Quit);
    assert_eq!(renders.len(), 1, "nothing more was drawn");
    assert_eq!(seen.writes.iter().filter(|w| w.0).count(), 1);
    assert!(
        seen.pending.iter().any(|p| *p),
        "the loop ended with the picture's reply still due"
    );
    assert!(outstanding >= 2, "the pacer knows the replies still due");
}

#[test]
fn a_terminal_that_never_answers_is_paced_by_writes_after_the_time_out() {
    let config = PacingConfig {
        first_reply: Duration::from_millis(50),
        ..patient()
    };
    let (exit, renders, seen, _) = paced(config, None, |d| {
        assert_eq!(d.next_picture(), 2);
        // No answer: after the time-out the key is drawn, with no query.
        d.send(right());
        loop {
            match d.next_write() {
                (0, true) => break,
                (_, true) => panic!("a picture with a query before the time-out"),
                _ => {}
            }
        }
        // The late replies to the first queries are credited to them: they
        // release nothing, and show the terminal does answer, so a later
        // frame asks again and waits for its own reply.
        d.answer_all();
        d.send(right());
        loop {
            let (q, picture) = d.next_write();
            d.answer(q);
            if picture {
                assert_eq!(q, 1, "asking again");
                break;
            }
        }
        d.answer_all();
        d.send(Msg::InputClosed("end of input".into()));
    });
    assert!(matches!(exit, Exit::InputClosed(_)));
    assert_eq!(
        renders.iter().map(|r| r.0).collect::<Vec<_>>(),
        vec![35.0, 40.0, 45.0]
    );
    // The picture after the late replies went with nothing in flight.
    let pictures: Vec<_> = seen.writes.iter().filter(|w| w.0).collect();
    assert_eq!(pictures.len(), 3);
    assert_eq!(*pictures[2], (true, 1, 0), "{pictures:?}");
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
    // The terminal answers by itself, a picture after 150 ms: a slow link.
    let (_, renders, seen, _) = paced(config, Some(Duration::from_millis(150)), |d| {
        d.next_picture();
        // Idle long enough for the first picture's reply to be measured.
        while d.seen.lock().unwrap().pending.iter().any(|p| *p) {
            std::thread::sleep(Duration::from_millis(20));
        }
        std::thread::sleep(Duration::from_millis(600));
        // A lone key after a pause.
        d.send(right());
        d.next_picture();
        // A burst of keys.
        for _ in 0..6 {
            std::thread::sleep(Duration::from_millis(30));
            d.send(right());
        }
        // Input stops: the exact picture of the latest state follows.
        while d.renders().last() != Some(&(70.0, 100)) {
            d.next_write();
        }
        d.send(Msg::InputClosed("end of input".into()));
    });
    let full = 100;
    assert_eq!(renders[0], (35.0, full), "the first picture is exact");
    assert_eq!(renders[1], (40.0, full), "a lone key is exact at once");
    let burst = &renders[2..renders.len() - 1];
    assert!(
        !burst.is_empty() && burst.iter().all(|r| r.1 == full / 2),
        "previews at half resolution during the burst: {renders:?}"
    );
    assert_eq!(*renders.last().unwrap(), (70.0, full));
    one_picture_in_flight(&seen);
}

/// Bytes written by the loop's terminal and by the frame watcher, in the
/// order a terminal would get them, and the terminal's own alone.
#[derive(Clone, Default)]
struct Wire {
    all: std::sync::Arc<std::sync::Mutex<Vec<u8>>>,
    own: Option<std::sync::Arc<std::sync::Mutex<Vec<u8>>>>,
}

impl std::io::Write for Wire {
    fn write(&mut self, b: &[u8]) -> std::io::Result<usize> {
        self.all.lock().unwrap().extend_from_slice(b);
        if let Some(own) = &self.own {
            own.lock().unwrap().extend_from_slice(b);
        }
        Ok(b.len())
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

/// The characters on screen after `bytes`.
fn screen_text(bytes: &[u8], w: usize, h: usize) -> Vec<String> {
    let mut screen = crate::screen::Screen::lenient(w, h);
    screen.feed(bytes);
    screen.rows()
}

/// A frame that runs long shows its progress over the status line, and the
/// next frame leaves the screen exactly as it would be had the line never
/// been written. The slow render waits until it sees the line (no clock).
#[test]
fn a_long_frame_shows_its_progress_and_leaves_no_trace() {
    use relief::app::frame_watch::FrameWatch;
    let (tx, rx) = mpsc::channel();
    let own = std::sync::Arc::new(std::sync::Mutex::new(Vec::new()));
    let wire = Wire::default();
    let loop_wire = Wire {
        own: Some(own.clone()),
        ..wire.clone()
    };
    let (w, h) = (60u16, 12u16);
    let mut term = Terminal::new(SgrBackend::with_size(loop_wire, w, h)).unwrap();
    let mut state = State::new(Settings::default(), ColorDepth::Truecolor);
    let mut renders = 0;
    let seen = wire.all.clone();
    let exit = Looper {
        watch: Some(FrameWatch {
            progress: std::sync::Arc::new(relief_pipeline::render::FrameProgress::new()),
            out: Box::new(wire.clone()),
        }),
        ..Looper::new(
            &mut term,
            &rx,
            // A key for a second frame, once the first is on screen.
            // The second frame runs until its progress shows (a minute
            // at most: then the test fails below).
            |_: &State, fb: &mut relief_core::framebuffer::Framebuffer| {
                renders += 1;
                if renders == 1 {
                    tx.send(key('m')).unwrap();
                }
                if renders == 2 {
                    let shown = || {
                        String::from_utf8_lossy(&seen.lock().unwrap())
                            .contains("preparing the frame")
                    };
                    let give_up = std::time::Instant::now() + std::time::Duration::from_secs(60);
                    while !shown() && std::time::Instant::now() < give_up {
                        std::thread::sleep(std::time::Duration::from_millis(10));
                    }
                    tx.send(Msg::InputClosed("end of input".into())).unwrap();
                }
                fb.fill([renders as u8 * 40, 0, 0]);
                relief_core::stats::FrameStats::default()
            },
        )
    }
    .run(&mut state)
    .unwrap();
    assert!(matches!(exit, Exit::InputClosed(_)));
    assert_eq!(renders, 2);
    let all = wire.all.lock().unwrap().clone();
    let text = String::from_utf8_lossy(&all);
    assert!(
        text.contains("\x1b7\x1b[12;1H\x1b[0;7mpreparing the frame · "),
        "the line went over the status row"
    );
    let own = own.lock().unwrap().clone();
    assert!(all.len() > own.len(), "the watcher wrote");
    let (with, without) = (
        screen_text(&all, w.into(), h.into()),
        screen_text(&own, w.into(), h.into()),
    );
    assert!(!with[11].contains("the frame"), "{:?}", with[11]);
    assert_eq!(with, without);
}
