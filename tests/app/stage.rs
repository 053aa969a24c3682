//! The shown scene: rebuilt by `o` and `p`, kept when a model fails to
//! load, and the all-motion mouse mode switched with the plasma.

use std::cell::RefCell;
use std::sync::{Arc, Mutex, mpsc};

use crossterm::event::{Event, KeyCode, KeyEvent, KeyModifiers};
use ratatui::Terminal;
use relief::app::State;
use relief::app::event_loop::{Exit, Looper, Msg};
use relief::app::stage::Stage;
use relief_core::framebuffer::Framebuffer;
use relief_core::settings::Settings;
use relief_pipeline::render::Renderer;
use relief_scene::{Built, ModelChoice, SceneKind};
use relief_term::guard::{RESTORE, SETUP};
use relief_term::modes::{MouseReports, MouseSemantics, TermModes};
use relief_term::{ColorDepth, SgrBackend};
use relief_texture::decode::procedural::brick;

fn stage() -> Stage {
    Stage::new(
        SceneKind::Cube,
        &ModelChoice::Cube,
        Arc::new(brick()),
        false,
    )
    .unwrap()
}

/// A model file whose face points at a vertex that does not exist.
fn bad_obj(name: &str) -> std::path::PathBuf {
    let path = crate::common::scratch::scratch_file(&format!("stage-{name}"));
    std::fs::write(&path, "v 0 0 0\nv 1 0 0\nf 1 2 7\n").unwrap();
    path
}

fn picture(stage: &mut Stage, state: &State) -> Framebuffer {
    let mut fb = Framebuffer::new(64, 48);
    let stats = stage.render(&mut Renderer::new(), state, &mut fb);
    // The cost panel hears what was drawn, plasma included.
    assert!(stats.counters.pixels_shaded > 0);
    fb
}

#[test]
fn a_bad_obj_keeps_the_old_scene_and_says_why() {
    let mut st = stage();
    let state = State::new(Settings::default(), ColorDepth::Truecolor);
    let before = picture(&mut st, &state);
    let path = bad_obj("broken\x1b[31m.obj");
    let err = st
        .build(SceneKind::Cube, &ModelChoice::File(path.clone()))
        .unwrap_err();
    assert!(err.contains("broken") && err.contains(".obj"), "{err}");
    assert!(!err.chars().any(char::is_control), "sanitised: {err:?}");
    assert_eq!(picture(&mut st, &state), before, "the same cube");
    std::fs::remove_file(path).unwrap();
}

#[test]
fn scenes_switch_and_the_texture_stays_across_the_plasma() {
    let mut st = stage();
    let mut state = State::new(Settings::default(), ColorDepth::Truecolor);
    let cube = picture(&mut st, &state);
    st.build(SceneKind::Plasma, &ModelChoice::Cube).unwrap();
    assert!(matches!(st.built(), Built::Plasma(_)));
    state.scene = SceneKind::Plasma;
    let plasma = picture(&mut st, &state);
    assert_ne!(plasma, cube);
    // The light follows the pointer.
    state.pointer = Some((5, 3));
    let moved = picture(&mut st, &state);
    assert_ne!(moved, plasma);
    st.build(SceneKind::Cube, &ModelChoice::Cube).unwrap();
    state.scene = SceneKind::Cube;
    state.pointer = None;
    assert_eq!(picture(&mut st, &state), cube, "same texture, same cube");
    st.build(SceneKind::Shadow, &ModelChoice::Cube).unwrap();
    assert!(matches!(st.built(), Built::Scene(s) if s.objects.len() == 2));
}

#[test]
fn light_switches_reach_the_scene() {
    let mut st = stage();
    let mut state = State::new(Settings::default(), ColorDepth::Truecolor);
    let all = picture(&mut st, &state);
    state.light_on[0] = false;
    let no_white = picture(&mut st, &state);
    assert_ne!(all, no_white);
    let dim = |fb: &Framebuffer| {
        fb.pixels()
            .iter()
            .map(|p| p.iter().map(|&c| c as u64).sum::<u64>())
            .sum::<u64>()
    };
    assert!(
        dim(&no_white) < dim(&all),
        "the white light is the strong one"
    );
    state.light_on = [true; 4];
    assert_eq!(picture(&mut st, &state), all);
}

fn key(c: char) -> Msg {
    Msg::Input(Event::Key(KeyEvent::new(
        KeyCode::Char(c),
        KeyModifiers::NONE,
    )))
}

/// A terminal that tells the test each time a frame was written.
struct Tap {
    bytes: Arc<Mutex<Vec<u8>>>,
    written: mpsc::Sender<()>,
}

impl std::io::Write for Tap {
    fn write(&mut self, data: &[u8]) -> std::io::Result<usize> {
        self.bytes.lock().unwrap().extend_from_slice(data);
        let _ = self.written.send(());
        Ok(data.len())
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

/// Runs the loop with a stage; each batch of keys is sent after the
/// previous frame was written. Returns the state and the bytes written.
fn run(stage: &RefCell<Stage>, mut state: State, batches: Vec<Vec<char>>) -> (State, Vec<u8>) {
    let (tx, rx) = mpsc::channel();
    let (written_tx, written) = mpsc::channel();
    let bytes = Arc::new(Mutex::new(Vec::new()));
    let tap = Tap {
        bytes: bytes.clone(),
        written: written_tx,
    };
    let driver = std::thread::spawn(move || {
        for batch in batches {
            // A write, then any that followed it at once (the status line's
            // refresh after a new picture): the batch goes after all of
            // them, so the next wait sees a write that follows the batch.
            written.recv().unwrap();
            while written.try_recv().is_ok() {}
            for c in batch {
                tx.send(key(c)).unwrap();
            }
        }
        let _ = written.recv();
        drop(tx);
    });
    let mut term = Terminal::new(SgrBackend::with_size(tap, 40, 12)).unwrap();
    let mut renderer = Renderer::new();
    let exit = Looper {
        stage: Some(stage),
        ..Looper::new(&mut term, &rx, |s: &State, fb: &mut Framebuffer| {
            stage.borrow_mut().render(&mut renderer, s, fb)
        })
    }
    .run(&mut state)
    .unwrap();
    assert!(matches!(exit, Exit::InputClosed(_)));
    driver.join().unwrap();
    let out = bytes.lock().unwrap().clone();
    (state, out)
}

fn count(haystack: &[u8], needle: &[u8]) -> usize {
    haystack
        .windows(needle.len())
        .filter(|w| *w == needle)
        .count()
}

fn find(haystack: &[u8], needle: &[u8]) -> Option<usize> {
    haystack.windows(needle.len()).position(|w| w == needle)
}

#[test]
fn the_loop_rebuilds_keeps_the_scene_on_error_and_switches_mouse_motion() {
    let path = bad_obj("loop.obj");
    let st = RefCell::new(stage());
    let mut state = State::new(Settings::default(), ColorDepth::Truecolor);
    state.model = ModelChoice::Sphere;
    state.obj = Some(path.clone());
    st.borrow_mut()
        .build(SceneKind::Cube, &ModelChoice::Sphere)
        .unwrap();
    // `o` from the sphere tries the bad file: refused, the sphere stays;
    // then twice `p`: the plasma, which asks for every motion; then `p`
    // back to the model, motion off again.
    let (state, bytes) = run(&st, state, vec![vec!['o'], vec!['p', 'p'], vec!['p']]);
    assert_eq!(state.model, ModelChoice::Sphere);
    assert_eq!(state.scene, SceneKind::Cube);
    // The stage still draws the sphere.
    let still = State::new(Settings::default(), ColorDepth::Truecolor);
    let mut sphere = Stage::new(
        SceneKind::Cube,
        &ModelChoice::Sphere,
        Arc::new(brick()),
        false,
    )
    .unwrap();
    assert_eq!(
        picture(&mut st.borrow_mut(), &still),
        picture(&mut sphere, &still)
    );
    // The refusal's message was cleared by the keys after it.
    assert_eq!(state.message, None);
    let (on, off) = (b"\x1b[?1003h".as_slice(), b"\x1b[?1003l".as_slice());
    // The plasma was shown once and left (a loop that took every key in
    // one go would show no plasma and switch nothing: then nothing here
    // to check but the modes at the end).
    let switches = (count(&bytes, on), count(&bytes, off));
    assert!(switches == (1, 1) || switches == (0, 0), "{switches:?}");
    assert!(find(&bytes, on) <= find(&bytes, off));
    // Leaving the plasma put button and drag reports back.
    for s in SEMANTICS {
        assert_eq!(
            TermModes::app(MouseReports::Drags).after(&bytes, s),
            TermModes::app(MouseReports::Drags)
        );
    }
    std::fs::remove_file(path).unwrap();
}

const SEMANTICS: [MouseSemantics; 2] = [MouseSemantics::OneLevel, MouseSemantics::Flags];

#[test]
fn every_scene_switch_leaves_the_terminal_in_the_modes_of_the_scene() {
    use MouseReports::{Drags, Motion};
    use SceneKind::{Cube, Plasma, Shadow};
    // Each key, the scene it leads to and the mouse reports that scene
    // needs: every motion in the plasma only. `o` leaves any scene for
    // the model, `p` steps model → shadow → plasma → model.
    let steps = [
        ('p', Shadow, Drags),
        ('p', Plasma, Motion),
        ('p', Cube, Drags),
        ('p', Shadow, Drags),
        ('p', Plasma, Motion),
        ('o', Cube, Drags),
        ('o', Cube, Drags),
        ('p', Shadow, Drags),
        ('o', Cube, Drags),
        ('p', Shadow, Drags),
        ('p', Plasma, Motion),
    ];
    // One run per prefix: the terminal's modes after its last switch are
    // decoded from everything the loop wrote (after the guard's setup).
    for n in 1..=steps.len() {
        let st = RefCell::new(stage());
        let state = State::new(Settings::default(), ColorDepth::Truecolor);
        let batches = steps[..n].iter().map(|&(k, ..)| vec![k]).collect();
        let (state, bytes) = run(&st, state, batches);
        let (key, scene, mouse) = steps[n - 1];
        assert_eq!(state.scene, scene, "after {n} keys, the last `{key}`");
        for s in SEMANTICS {
            let setup = TermModes::SHELL.after(SETUP, s);
            assert_eq!(
                setup.after(&bytes, s),
                TermModes::app(mouse),
                "after {n} keys, the last `{key}` ({s:?})"
            );
            // Whatever the scene, the guard's restore gives the shell back.
            assert_eq!(setup.after(&bytes, s).after(RESTORE, s), TermModes::SHELL);
        }
    }
}

#[test]
fn a_texture_applied_to_the_stage_stays_through_rebuilds() {
    let mut list = relief::app::texture_list::TextureList::new();
    list.cycle(true).unwrap();
    let other = list.texture().clone();
    let state = State::new(Settings::default(), ColorDepth::Truecolor);
    let mut want = Stage::new(SceneKind::Cube, &ModelChoice::Cube, other.clone(), false).unwrap();
    let want = picture(&mut want, &state);
    let mut st = stage();
    assert_ne!(picture(&mut st, &state), want);
    st.set_texture(other);
    assert_eq!(picture(&mut st, &state), want, "applied to the shown scene");
    st.build(SceneKind::Plasma, &ModelChoice::Cube).unwrap();
    st.build(SceneKind::Cube, &ModelChoice::Cube).unwrap();
    assert_eq!(picture(&mut st, &state), want, "and to the rebuilt one");
}

/// Pixels of a 320×240 picture of the stage that are not the background.
fn covered(stage: &mut Stage, state: &State) -> usize {
    let mut fb = Framebuffer::new(320, 240);
    stage.render(&mut Renderer::new(), state, &mut fb);
    let bg = fb.pixels()[0];
    fb.pixels().iter().filter(|&&p| p != bg).count()
}

#[test]
fn the_field_of_view_scales_the_cube_as_the_projection_says() {
    let mut st = stage();
    let mut state = State::new(Settings::default(), ColorDepth::Truecolor);
    let at60 = covered(&mut st, &state);
    state.settings.fov = 90.0;
    let at90 = covered(&mut st, &state);
    // The picture shrinks by tan(30°)/tan(45°) across and down: its area
    // by that squared, 1/3 (within 5 % for the pixels on the edges).
    let ratio = at90 as f64 / at60 as f64;
    let want = (30f64.to_radians().tan() / 45f64.to_radians().tan()).powi(2);
    assert!(
        (ratio / want - 1.0).abs() < 0.05,
        "{at60} → {at90}: {ratio} vs {want}"
    );
}

// ---- Model files load on a worker while the stage keeps drawing ----

use relief::app::loading::Loader;

/// A grid of `n × n` quads (2n² triangles, shared vertices) written as an
/// OBJ file in the temporary directory.
fn grid_obj(name: &str, n: usize) -> std::path::PathBuf {
    use std::fmt::Write as _;
    let mut text = String::with_capacity(40 * n * n);
    for j in 0..=n {
        for i in 0..=n {
            let (x, y) = (i as f32 / n as f32, j as f32 / n as f32);
            let z = (x * 7.0).sin() * (y * 5.0).cos() * 0.1;
            writeln!(text, "v {x} {y} {z}").unwrap();
        }
    }
    let at = |i: usize, j: usize| j * (n + 1) + i + 1;
    for j in 0..n {
        for i in 0..n {
            let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
            writeln!(text, "f {a} {b} {c}\nf {a} {c} {d}").unwrap();
        }
    }
    let path = crate::common::scratch::scratch_file(&format!("load-{name}"));
    std::fs::write(&path, text).unwrap();
    path
}

/// What the state said when a picture was drawn.
#[derive(Clone, Debug)]
struct Seen {
    model: ModelChoice,
    /// The load's line on the status line, if one was under way.
    loading: Option<String>,
}

/// The test's side of a loop that loads on a worker: it sends input, hears
/// each picture drawn, and holds each load's wake-up until it passes it on,
/// so the order of events is the test's to choose (no timing involved).
struct Driver {
    tx: mpsc::Sender<Msg>,
    rendered: mpsc::Receiver<Seen>,
    woken: mpsc::Receiver<u64>,
}

impl Driver {
    fn send(&self, msgs: Vec<Msg>) {
        for m in msgs {
            self.tx.send(m).unwrap();
        }
    }
    /// The next picture the loop draws.
    fn picture(&self) -> Seen {
        self.rendered.recv().expect("the loop draws")
    }
    /// Waits for a load's worker to end; returns its number.
    fn worker_done(&self) -> u64 {
        self.woken.recv().expect("the worker ends")
    }
}

fn arrow() -> Msg {
    Msg::Input(Event::Key(KeyEvent::new(
        KeyCode::Right,
        KeyModifiers::NONE,
    )))
}

fn esc() -> Msg {
    Msg::Input(Event::Key(KeyEvent::new(KeyCode::Esc, KeyModifiers::NONE)))
}

/// Runs the loop on this thread with a loader and `drive` on another;
/// the loop ends when the driver returns (its sender dropped) or quits.
fn run_loading<T: Send + 'static>(
    stage: &RefCell<Stage>,
    mut state: State,
    drive: impl FnOnce(&Driver) -> T + Send + 'static,
) -> (Exit, State, T) {
    let (tx, rx) = mpsc::channel();
    let (rendered_tx, rendered) = mpsc::channel();
    let (woken_tx, woken) = mpsc::channel();
    let driver = std::thread::spawn(move || {
        let d = Driver {
            tx,
            rendered,
            woken,
        };
        // The first picture, before any input.
        d.picture();
        drive(&d)
    });
    let mut term = Terminal::new(SgrBackend::with_size(Vec::new(), 40, 12)).unwrap();
    let mut renderer = Renderer::new();
    let exit = Looper {
        stage: Some(stage),
        loader: Some(Loader::new(move |id| {
            let _ = woken_tx.send(id);
        })),
        ..Looper::new(&mut term, &rx, |s: &State, fb: &mut Framebuffer| {
            let stats = stage.borrow_mut().render(&mut renderer, s, fb);
            let _ = rendered_tx.send(Seen {
                model: s.model.clone(),
                loading: s.loading.as_ref().map(|l| l.text()),
            });
            stats
        })
    }
    .run(&mut state)
    .unwrap();
    // A driver still waiting for a picture hears that none will come.
    drop(rendered_tx);
    let out = driver.join().unwrap();
    (exit, state, out)
}

/// The sphere shown, with `path` next in the `o` cycle.
fn sphere_then(path: &std::path::Path) -> (RefCell<Stage>, State) {
    let st = RefCell::new(stage());
    st.borrow_mut()
        .build(SceneKind::Cube, &ModelChoice::Sphere)
        .unwrap();
    let mut state = State::new(Settings::default(), ColorDepth::Truecolor);
    state.model = ModelChoice::Sphere;
    state.obj = Some(path.to_path_buf());
    (st, state)
}

#[test]
fn a_big_model_loads_on_a_worker_while_the_old_one_is_drawn() {
    // 2 × 300² = 180,000 triangles.
    let path = grid_obj("big.obj", 300);
    let (st, state) = sphere_then(&path);
    let file = ModelChoice::File(path.clone());
    let (exit, state, seen) = run_loading(&st, state, |d| {
        // `o` starts the load; the arrow turns the sphere meanwhile.
        d.send(vec![key('o'), arrow()]);
        let during = d.picture();
        let id = d.worker_done();
        // The worker is done but the loop has not heard: a picture now
        // shows the load's last step complete.
        d.send(vec![arrow()]);
        let done = d.picture();
        d.send(vec![Msg::Loaded(id)]);
        let after = d.picture();
        (during, done, after)
    });
    assert!(matches!(exit, Exit::InputClosed(_)));
    let (during, done, after) = seen;
    assert_eq!(during.model, ModelChoice::Sphere, "the old model is drawn");
    let line = during.loading.expect("the status line shows the load");
    assert!(
        line.starts_with("loading ") && line.contains("big.obj"),
        "{line}"
    );
    assert!(line.ends_with("(Esc cancels)"), "{line}");
    let line = done
        .loading
        .expect("still loading as far as the loop knows");
    assert!(line.contains(": building 100% · "), "{line}");
    assert_eq!(after.model, file, "the new model once it is built");
    assert_eq!(after.loading, None);
    assert_eq!(state.model, file);
    assert_eq!(state.loading, None);
    // The stage draws what a synchronous build of the file draws.
    let still = State::new(Settings::default(), ColorDepth::Truecolor);
    let mut want = stage();
    want.build(SceneKind::Cube, &file).unwrap();
    assert_eq!(
        picture(&mut st.borrow_mut(), &still),
        picture(&mut want, &still)
    );
    std::fs::remove_file(path).unwrap();
}

#[test]
fn esc_stops_a_load_and_keeps_the_model_shown() {
    let path = grid_obj("esc.obj", 200);
    let (st, state) = sphere_then(&path);
    let (exit, state, during) = run_loading(&st, state, |d| {
        d.send(vec![key('o'), arrow()]);
        let during = d.picture();
        d.send(vec![esc()]);
        during
    });
    assert!(matches!(exit, Exit::InputClosed(_)), "Esc did not quit");
    assert!(during.loading.is_some());
    assert_eq!(state.loading, None);
    assert_eq!(state.model, ModelChoice::Sphere);
    let message = state.message.unwrap();
    assert!(
        message.starts_with("stopped loading") && message.contains("esc.obj"),
        "{message}"
    );
    std::fs::remove_file(path).unwrap();
}

#[test]
fn q_quits_during_a_load_without_waiting_for_it() {
    let path = grid_obj("quit.obj", 200);
    let (st, state) = sphere_then(&path);
    let (exit, state, during) = run_loading(&st, state, |d| {
        d.send(vec![key('o'), arrow()]);
        let during = d.picture();
        // The worker's wake-up is never passed on: the loop cannot be
        // waiting for it.
        d.send(vec![key('q')]);
        during
    });
    assert_eq!(exit, Exit::Quit);
    assert!(during.loading.is_some());
    assert!(state.loading.is_some(), "quit with the load under way");
    assert_eq!(state.model, ModelChoice::Sphere);
    std::fs::remove_file(path).unwrap();
}

#[test]
fn a_load_that_fails_says_why_in_one_line_and_keeps_the_model() {
    let path = bad_obj("worker.obj");
    let (st, state) = sphere_then(&path);
    let (exit, state, ()) = run_loading(&st, state, |d| {
        d.send(vec![key('o'), arrow()]);
        d.picture();
        let id = d.worker_done();
        d.send(vec![Msg::Loaded(id)]);
    });
    assert!(matches!(exit, Exit::InputClosed(_)));
    assert_eq!(state.model, ModelChoice::Sphere);
    assert_eq!(state.loading, None);
    let message = state.message.unwrap();
    assert!(
        message.contains("worker.obj") && message.contains("line 3"),
        "{message}"
    );
    assert!(!message.contains('\n'));
    std::fs::remove_file(path).unwrap();
}

#[test]
fn another_model_asked_for_during_a_load_replaces_it() {
    let path = grid_obj("replaced.obj", 200);
    let (st, state) = sphere_then(&path);
    let (exit, state, seen) = run_loading(&st, state, |d| {
        d.send(vec![key('o'), arrow()]);
        let during = d.picture();
        // `o` again from the sphere (still shown) asks for the same file:
        // the load goes on. `p` asks for the shadow scene: built at once,
        // the load stopped.
        d.send(vec![key('o'), arrow()]);
        let again = d.picture();
        d.send(vec![key('p')]);
        let shadow = d.picture();
        (during, again, shadow)
    });
    assert!(matches!(exit, Exit::InputClosed(_)));
    let (during, again, shadow) = seen;
    assert!(during.loading.is_some() && again.loading.is_some());
    assert_eq!(shadow.loading, None);
    assert_eq!(state.scene, SceneKind::Shadow);
    assert_eq!(state.model, ModelChoice::Sphere);
    std::fs::remove_file(path).unwrap();
}

/// In the view, a model file without a material of its own is plain until
/// the user applies a texture (`x`, `T`, a paste…: the state's
/// `texture_chosen`, which the stage reads), and a stage whose state says
/// the command line chose one dresses it at once.
#[test]
fn a_model_without_material_takes_a_texture_once_one_is_applied() {
    let path = crate::common::scratch::scratch_file("stage-bare.obj");
    std::fs::write(
        &path,
        "v -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\nf 1 2 3\nf 1 3 4\n",
    )
    .unwrap();
    let model = ModelChoice::File(path.clone());
    let mut state = State::new(Settings::default(), ColorDepth::Truecolor);
    state.start_rotation = glam::Vec3::ZERO;
    state.settings.rotation = glam::Vec3::ZERO;
    let texture = Arc::new(brick());
    let mut st = Stage::new(SceneKind::Cube, &model, texture.clone(), false).unwrap();
    let plain = picture(&mut st, &state);
    let mut untextured = state.clone();
    untextured.settings.texture = false;
    assert_eq!(picture(&mut st, &untextured), plain);
    st.set_texture(texture.clone());
    relief::app::update(
        &mut state,
        relief::app::Action::TextureResult(Ok("brick (built-in)".into())),
    );
    let dressed = picture(&mut st, &state);
    assert_ne!(dressed, plain);
    let mut chosen = Stage::new(SceneKind::Cube, &model, texture, false).unwrap();
    assert_eq!(picture(&mut chosen, &state), dressed);
    std::fs::remove_file(path).unwrap();
}
