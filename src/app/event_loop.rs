//! The event loop: wait for input, apply it, render once, write once.
//!
//! Idle means blocked on the channel: no frame, no CPU. Whatever queued up
//! while a frame was being written (keys, drags, a storm of resizes) is
//! applied all at once and only the latest state is rendered, so a slow
//! link drops stale frames instead of queueing them.

use std::cell::RefCell;
use std::collections::VecDeque;
use std::io::{self, Read, Write};
use std::sync::mpsc::{Receiver, RecvTimeoutError, Sender};
use std::time::{Duration, Instant};

use crossterm::event::Event;
use ratatui::Terminal;

use super::action::{Action, action_for_event};
use super::cost::FrameCost;
use super::stage::Stage;
use super::state::{Command, Look, State, update};
use super::view;
use crate::framebuffer::{Framebuffer, Rgb};
use crate::scene::SceneKind;
use crate::stats::{Counters, FrameStats};
use crate::term::SgrBackend;
use crate::term::input::InputParser;

/// Mouse mode 1003: every pointer motion is reported (the plasma's light follows it).
pub const MOTION_ON: &[u8] = b"\x1b[?1003h";
/// Back to button and drag reports only.
pub const MOTION_OFF: &[u8] = b"\x1b[?1003l";

/// Auto-rotation frame pacing.
pub const FRAME_INTERVAL: Duration = Duration::from_millis(33);

/// What reaches the loop from the input and signal threads.
#[derive(Debug)]
pub enum Msg {
    Input(Event),
    /// The terminal is gone (end of file or a read error).
    InputClosed(String),
    /// SIGWINCH.
    Resized,
    /// SIGINT, SIGTERM or SIGHUP.
    Signal(i32),
}

/// How the loop ended.
#[derive(Debug, PartialEq, Eq)]
pub enum Exit {
    Quit,
    InputClosed(String),
    Signal(i32),
}

/// Reads the terminal on its own thread and sends decoded events; ends
/// (with `InputClosed`) at end of file or on a read error, so a dropped
/// connection is never spun on.
pub fn spawn_input_reader(mut input: impl Read + Send + 'static, tx: Sender<Msg>) {
    std::thread::spawn(move || {
        let mut parser = InputParser::new();
        let mut buf = [0u8; 4096];
        let mut events = Vec::new();
        loop {
            match input.read(&mut buf) {
                Ok(0) => {
                    let _ = tx.send(Msg::InputClosed("end of input".into()));
                    return;
                }
                Ok(n) => {
                    parser.feed(&buf[..n], &mut events);
                    for e in events.drain(..) {
                        if tx.send(Msg::Input(e)).is_err() {
                            return;
                        }
                    }
                }
                Err(e) if e.kind() == io::ErrorKind::Interrupted => continue,
                Err(e) => {
                    let _ = tx.send(Msg::InputClosed(e.to_string()));
                    return;
                }
            }
        }
    });
}

/// Everything the loop needs besides the state.
pub struct Looper<'a, W: Write, R: FnMut(&State, &mut Framebuffer) -> FrameStats> {
    pub terminal: &'a mut Terminal<SgrBackend<W>>,
    /// Draws the state's picture (from the stage, in the app).
    pub render: R,
    pub background: Rgb,
    pub rx: &'a Receiver<Msg>,
    /// The texture list the texture keys and pastes act on (the render
    /// closure reads the applied texture from it).
    pub textures: Option<&'a RefCell<crate::texture::TextureList>>,
    /// The scene that `o` and `p` rebuild (the render closure draws it).
    pub stage: Option<&'a RefCell<Stage>>,
}

/// Frames written during the last second, for the fps figure.
#[derive(Default)]
struct FrameClock {
    recent: VecDeque<Instant>,
}

impl FrameClock {
    fn tick(&mut self, now: Instant) -> f32 {
        self.recent.push_back(now);
        while let Some(&t) = self.recent.front() {
            if now.duration_since(t) > Duration::from_secs(1) {
                self.recent.pop_front();
            } else {
                break;
            }
        }
        self.recent.len() as f32
    }
}

impl<W: Write, R: FnMut(&State, &mut Framebuffer) -> FrameStats> Looper<'_, W, R> {
    /// Runs a scene build on the stage: what is shown now, or the error
    /// (the old scene stays). Without a stage there is nothing to build.
    fn build_scene(&self, kind: SceneKind, model: crate::scene::ModelChoice) -> Action {
        let result = match self.stage {
            Some(stage) => stage.borrow_mut().build(kind, &model),
            None => Ok(()),
        };
        Action::SceneBuilt(result.map(|()| (kind, model)))
    }

    /// Runs a texture command on the list: the applied texture's label, or
    /// the first error (the list and the texture then stay as they were).
    fn texture_command(&self, command: Command) -> Option<Result<String, String>> {
        let mut list = self.textures?.borrow_mut();
        let errors = match command {
            Command::CycleTexture(forward) => list.cycle(forward).err().into_iter().collect(),
            Command::ReloadTexture => list.reload().err().into_iter().collect(),
            Command::AddPaths(text) => list.add_paste(&text),
            Command::SavePng | Command::BuildScene(..) => return None,
        };
        Some(match errors.first() {
            None => Ok(list.summary()),
            Some(e) if errors.len() > 1 => Err(format!("{e} (and {} more)", errors.len() - 1)),
            Some(e) => Err(e.to_string()),
        })
    }

    /// Runs until the user quits, the terminal goes away or a signal comes.
    pub fn run(&mut self, state: &mut State) -> io::Result<Exit> {
        let mut fb = Framebuffer::new(0, 0);
        let mut rendered: Option<(Look, usize, usize, u64)> = None;
        // The guard's setup leaves all-motion reports off.
        let mut motion = false;
        let mut clock = FrameClock::default();
        let mut dirty = true;
        // After a new picture, one more (text-only) write lets the status
        // line show that picture's own time and bytes instead of the
        // previous one's; skipped while auto-rotation draws anyway.
        let mut refresh_status = false;
        let mut last_tick = Instant::now();
        let mut last_counters = Counters::default();
        loop {
            // Wait: not at all when a frame is due, until the next auto-rotation
            // frame, or for as long as it takes.
            let first = if dirty {
                None
            } else if refresh_status {
                self.rx.try_recv().ok()
            } else if state.auto_rotate {
                let wait = (last_tick + FRAME_INTERVAL).saturating_duration_since(Instant::now());
                match self.rx.recv_timeout(wait) {
                    Ok(m) => Some(m),
                    Err(RecvTimeoutError::Timeout) => None,
                    Err(RecvTimeoutError::Disconnected) => {
                        return Ok(Exit::InputClosed("input ended".into()));
                    }
                }
            } else {
                match self.rx.recv() {
                    Ok(m) => Some(m),
                    Err(_) => return Ok(Exit::InputClosed("input ended".into())),
                }
            };
            // Apply everything that is queued before drawing anything.
            let mut next = first;
            while let Some(msg) = next.take().or_else(|| self.rx.try_recv().ok()) {
                match msg {
                    Msg::Input(event) => {
                        if let Some(action) = action_for_event(state, &event) {
                            dirty = true;
                            match update(state, action) {
                                Some(Command::SavePng) => {
                                    let result = save_png(&fb);
                                    update(state, Action::Saved(result));
                                }
                                Some(Command::BuildScene(kind, model)) => {
                                    let built = self.build_scene(kind, model);
                                    update(state, built);
                                }
                                Some(command) => {
                                    if let Some(result) = self.texture_command(command) {
                                        update(state, Action::TextureResult(result));
                                    }
                                }
                                None => {}
                            }
                        }
                    }
                    Msg::Resized => dirty = true,
                    Msg::InputClosed(why) => return Ok(Exit::InputClosed(why)),
                    Msg::Signal(sig) => return Ok(Exit::Signal(sig)),
                }
                if state.quit {
                    return Ok(Exit::Quit);
                }
            }
            let now = Instant::now();
            if state.auto_rotate {
                if now >= last_tick + FRAME_INTERVAL {
                    let seconds = now.duration_since(last_tick).as_secs_f32();
                    update(state, Action::AutoRotateTick { seconds });
                    last_tick = now;
                    dirty = true;
                }
            } else {
                last_tick = now;
            }
            let status_only = refresh_status && !dirty;
            refresh_status = false;
            if !dirty && !status_only {
                continue;
            }
            dirty = false;

            // Render only when what the picture depends on changed.
            let start = Instant::now();
            let size = self.terminal.size()?;
            // The help cannot scroll past what this screen needs: keep the
            // state there so the first key back moves it.
            state.help_scroll = state
                .help_scroll
                .min(view::help_max_scroll(size.width, size.height));
            let areas = view::areas(ratatui::layout::Rect::new(0, 0, size.width, size.height));
            let (w, h) = view::framebuffer_size(areas.viewport);
            let generation = self.textures.map_or(0, |t| t.borrow().generation());
            let key = (state.look(), w, h, generation);
            // A frame that only redraws the text costs no render time; the
            // cost panel keeps the counters of the last render.
            let mut stats = FrameStats {
                counters: last_counters,
                ..FrameStats::default()
            };
            let new_picture = rendered.as_ref() != Some(&key);
            if new_picture {
                fb.resize(w, h);
                stats = (self.render)(state, &mut fb);
                last_counters = stats.counters;
                rendered = Some(key);
            }
            let encode_start = Instant::now();
            let backend = self.terminal.backend_mut();
            // Only the plasma asks for every pointer motion.
            let want_motion = state.scene == SceneKind::Plasma;
            if want_motion != motion {
                backend.write_raw(if want_motion { MOTION_ON } else { MOTION_OFF })?;
                motion = want_motion;
            }
            backend.begin_frame()?;
            self.terminal
                .draw(|frame| view::view(frame, state, &fb, self.background))?;
            let write_start = Instant::now();
            let bytes = self.terminal.backend_mut().end_frame()?;
            let done = Instant::now();
            if status_only {
                // Only the figures changed: they keep describing the picture.
                continue;
            }
            state.costs.push(FrameCost::new(
                &stats,
                write_start - encode_start,
                done - write_start,
                bytes,
            ));
            state.frame.frame_time = done - start;
            state.frame.bytes = bytes;
            state.frame.fps = clock.tick(done);
            refresh_status = new_picture && !state.auto_rotate;
        }
    }
}

/// Writes the framebuffer as `relief-<seconds>.png` in the current directory
/// (never over an existing file).
pub fn save_png(fb: &Framebuffer) -> Result<String, String> {
    let stamp = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.as_secs())
        .unwrap_or(0);
    for n in 0..100 {
        let name = if n == 0 {
            format!("relief-{stamp}.png")
        } else {
            format!("relief-{stamp}-{n}.png")
        };
        let path = std::path::Path::new(&name);
        if path.exists() {
            continue;
        }
        return fb
            .save_png(path)
            .map(|_| name)
            .map_err(|e| format!("{e:#}"));
    }
    Err("too many screenshots this second".into())
}
