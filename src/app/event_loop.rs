//! The event loop: wait for input, apply it, render once, write once.
//!
//! The loop never writes the state itself: what it learns (input, a save's
//! outcome, a frame's cost, the screen's size) goes through `update` as an
//! [`Action`].
//!
//! Idle means blocked on the channel: no frame, no CPU. Frames are paced by
//! the terminal itself (see [`relief_term::pacing`]): each one ends with a
//! query, and the next waits for its reply. Whatever arrives meanwhile
//! (keys, drags, a storm of resizes) is applied all at once and only the
//! latest state is rendered, so a slow link drops stale frames instead of
//! queueing them. While input keeps coming over a link too slow for the
//! exact picture, a half-resolution preview is sent, and the exact picture
//! once input stops.

use std::cell::RefCell;
use std::collections::VecDeque;
use std::io::{self, Read, Write};
use std::os::fd::RawFd;
use std::sync::mpsc::{Receiver, RecvTimeoutError, Sender};
use std::time::{Duration, Instant};

use crossterm::event::Event;
use ratatui::Terminal;
use ratatui::backend::Backend;
use ratatui::buffer::Cell;
use ratatui::layout::Rect;

use super::action::{Action, FrameDone};
use super::command::Command;
use super::events::action_for_event;
use super::frame_cost::FrameCost;
use super::frame_watch::{FrameWatch, StatusRow};
use super::loading::Loader;
use super::schedule::{Frame as Due, Schedule};
use super::stage::Stage;
use super::state::{Look, State};
use super::textures;
use super::update::update;
use super::view;
use relief_core::framebuffer::{Framebuffer, Rgb};
use relief_core::stats::{Counters, FrameStats};
use relief_scene::SceneKind;
use relief_term::SgrBackend;
use relief_term::input::{Input, InputParser};
use relief_term::modes::{MouseReports, TermModes};
use relief_term::pacing::{Answers, Pacer, QUERY};
use relief_term::pixel_view::{PixelFrame, PixelView, TextLook};

/// The terminal modes the state wants: only the plasma asks for every
/// pointer motion (its light follows the pointer); everything else for
/// buttons and drags, as the guard's setup leaves them.
pub fn wanted_modes(state: &State) -> TermModes {
    TermModes::app(if state.scene == SceneKind::Plasma {
        MouseReports::Motion
    } else {
        MouseReports::Drags
    })
}

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
    /// The terminal answered a pacing query at this time: what was written
    /// before the query is on screen.
    Shown(Instant),
    /// The model load of this number ended on its worker (see [`Loader`]).
    Loaded(u64),
    /// A dense caster's shadow stand-in was made on its thread: the frame
    /// on screen drew the exact casters, the next draws the stand-in.
    StandInMade,
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
pub fn spawn_input_reader(input: impl Read + Send + 'static, tx: Sender<Msg>) {
    spawn_reader(input, None, tx);
}

/// How long a lone `ESC` waits for the rest of a sequence before it is the
/// Escape key: over SSH a terminal's reply can arrive split after its `ESC`
/// (read alone, it would quit).
pub const ESCAPE_WAIT: Duration = Duration::from_millis(50);

/// [`spawn_input_reader`] for the terminal itself: `fd` is polled for the
/// rest of a sequence split after its `ESC` (see [`ESCAPE_WAIT`]).
pub fn spawn_terminal_reader(input: impl Read + Send + 'static, fd: RawFd, tx: Sender<Msg>) {
    spawn_reader(input, Some(fd), tx);
}

fn spawn_reader(mut input: impl Read + Send + 'static, fd: Option<RawFd>, tx: Sender<Msg>) {
    std::thread::spawn(move || {
        let mut parser = match fd {
            Some(_) => InputParser::holding_escape(),
            None => InputParser::new(),
        };
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
                    if let Some(fd) = fd {
                        settle(&mut parser, fd, &mut events);
                    }
                    let at = Instant::now();
                    for e in events.drain(..) {
                        let msg = match e {
                            Input::Event(e) => Msg::Input(e),
                            Input::DeviceAttributes => Msg::Shown(at),
                        };
                        if tx.send(msg).is_err() {
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

/// Waits on `fd` for what the parser holds open: a lone `ESC` for
/// [`ESCAPE_WAIT`], a paste or an unfinished sequence until its deadline
/// (see [`InputParser::deadline`]); when nothing comes meanwhile, closes it.
/// Returns as soon as there is more to read.
fn settle(parser: &mut InputParser, fd: RawFd, events: &mut Vec<Input>) {
    loop {
        let wait = if parser.waiting() {
            ESCAPE_WAIT
        } else if let Some(deadline) = parser.deadline() {
            deadline.saturating_duration_since(Instant::now())
        } else {
            return;
        };
        if relief_term::wait::readable_within(fd, wait).unwrap_or(false) {
            return;
        }
        if parser.waiting() {
            parser.flush_pending(events);
        } else {
            parser.expire(Instant::now(), events);
        }
    }
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
    pub textures: Option<&'a RefCell<super::texture_list::TextureList>>,
    /// The scene that `o` and `p` rebuild (the render closure draws it).
    pub stage: Option<&'a RefCell<Stage>>,
    /// Frames in flight and the link's figures.
    pub pacer: Pacer,
    /// Loads model files on a worker while the stage keeps drawing (`None`:
    /// every scene is built on the loop's thread, as it is asked for).
    pub loader: Option<Loader>,
    /// Shows a long frame's progress on the status line (`None`: frames
    /// show nothing while they run).
    pub watch: Option<FrameWatch>,
}

/// Frames written during the last second, for the fps figure.
#[derive(Default)]
struct FrameClock {
    recent: VecDeque<Instant>,
}

impl FrameClock {
    /// Frames in the last second, `None` for a lone frame (no rate).
    fn tick(&mut self, now: Instant) -> Option<f32> {
        self.recent.push_back(now);
        while let Some(&t) = self.recent.front() {
            if now.duration_since(t) > Duration::from_secs(1) {
                self.recent.pop_front();
            } else {
                break;
            }
        }
        let n = self.recent.len();
        (n >= 2).then_some(n as f32)
    }
}

/// What the picture in the framebuffer shows: the look, its size, the
/// textures' generation.
type PictureKey = (Look, usize, usize, u64);

/// A frame's size and places, fixed as it starts.
struct Plan {
    areas: view::Areas,
    /// The framebuffer's size.
    w: usize,
    h: usize,
    key: PictureKey,
}

/// A frame's write: when it started and ended, and its bytes.
struct Written {
    start: Instant,
    bytes: u64,
    done: Instant,
}

/// What a frame cost, from the times it started, its encoding started, its
/// write started and it was done.
fn frame_done(
    stats: &FrameStats,
    [start, encode_start, write_start, done]: [Instant; 4],
    bytes: u64,
    clock: &mut FrameClock,
) -> Box<FrameDone> {
    Box::new(FrameDone {
        cost: FrameCost::new(stats, write_start - encode_start, done - write_start, bytes),
        time: done - start,
        bytes,
        fps: clock.tick(done),
    })
}

/// What the loop keeps from one frame to the next.
struct Frames {
    fb: Framebuffer,
    /// The half-resolution picture of a preview, before it is enlarged.
    coarse: Framebuffer,
    /// What `fb` holds (`None`: nothing worth keeping).
    rendered: Option<PictureKey>,
    /// The terminal's modes now.
    modes: TermModes,
    clock: FrameClock,
    /// The counters of the last render.
    last_counters: Counters,
    /// The status row's place and cells as the last frame drew them.
    status_cells: Option<(Rect, Vec<Cell>)>,
    /// When to draw and what (see `schedule`).
    schedule: Schedule,
    /// Pixel images on screen (kitty, sixel, iTerm2).
    pixels: PixelView,
}

impl Frames {
    fn new() -> Self {
        Frames {
            fb: Framebuffer::new(0, 0),
            coarse: Framebuffer::new(0, 0),
            rendered: None,
            // What the guard's setup left the terminal in.
            modes: TermModes::app(MouseReports::Drags),
            clock: FrameClock::default(),
            last_counters: Counters::default(),
            status_cells: None,
            schedule: Schedule::new(Instant::now()),
            pixels: PixelView::new(),
        }
    }
}

impl<'a, W: Write, R: FnMut(&State, &mut Framebuffer) -> FrameStats> Looper<'a, W, R> {
    /// A loop that draws with `render` and reads `rx`, with nothing else:
    /// a black background, no texture list, no stage or loader (scenes are
    /// the render closure's business), frames paced by the writes alone
    /// and no progress line. Set the other fields for more.
    pub fn new(
        terminal: &'a mut Terminal<SgrBackend<W>>,
        rx: &'a Receiver<Msg>,
        render: R,
    ) -> Self {
        Looper {
            terminal,
            render,
            background: [0, 0, 0],
            rx,
            textures: None,
            stage: None,
            pacer: Pacer::by_writes(),
            loader: None,
            watch: None,
        }
    }
}

impl<W: Write, R: FnMut(&State, &mut Framebuffer) -> FrameStats> Looper<'_, W, R> {
    /// Asks for a scene: a model file starts loading on the worker (unless
    /// it is loading already), anything else is built at once. Either way
    /// a load under way for something else stops.
    fn ask_scene(&mut self, state: &mut State, kind: SceneKind, model: relief_scene::ModelChoice) {
        let shown = (kind, &model) == (state.scene, &state.model);
        if let (Some(loader), Some(stage)) = (&mut self.loader, self.stage) {
            if loader.loading() == Some((kind, &model)) {
                return;
            }
            if Loader::wants(kind, &model) && !shown {
                let order = stage.borrow().order(kind, &model);
                let status = loader.start(order, Instant::now());
                update(state, Action::Loading(status));
                return;
            }
            loader.cancel();
        }
        self.build_and_note(state, kind, model);
    }

    /// A load's worker ended: its scene is shown, or its error said (the
    /// scene shown stays). A load cancelled or replaced since is ignored.
    fn load_finished(&mut self, state: &mut State, id: u64) {
        let Some(done) = self.loader.as_mut().and_then(|l| l.finished(id)) else {
            return;
        };
        let built = match (done.result, self.stage) {
            (Ok(ready), Some(stage)) => {
                stage.borrow_mut().install(ready);
                Ok((done.kind, done.model))
            }
            (Ok(_), None) => Err("no stage to show the model on".to_string()),
            (Err(e), _) => Err(e),
        };
        self.note_built(state, Action::SceneBuilt(built));
    }

    /// Runs a scene build on the stage: what is shown now, or the error
    /// (the old scene stays). Without a stage there is nothing to build.
    /// The state says what is shown: asking for it again builds nothing.
    fn build_scene(
        &self,
        state: &State,
        kind: SceneKind,
        model: relief_scene::ModelChoice,
    ) -> Action {
        let result = match self.stage {
            Some(stage) if (kind, &model) != (state.scene, &state.model) => {
                stage.borrow_mut().build(kind, &model)
            }
            _ => Ok(()),
        };
        Action::SceneBuilt(result.map(|()| (kind, model)))
    }

    /// Builds a scene and tells the state, with what loading the model said.
    fn build_and_note(&self, state: &mut State, kind: SceneKind, model: relief_scene::ModelChoice) {
        let built = self.build_scene(state, kind, model);
        self.note_built(state, built);
    }

    /// Tells the state what a build gave (`Action::SceneBuilt`), with what
    /// loading the model said.
    fn note_built(&self, state: &mut State, built: Action) {
        let ok = matches!(built, Action::SceneBuilt(Ok(_)));
        update(state, built);
        if let Some(stage) = self.stage
            && ok
        {
            let notes = stage.borrow_mut().take_notes();
            if notes != relief_scene::LoadedNotes::default() {
                update(state, Action::ModelNotes(notes));
            }
        }
        if ok {
            // The panel lists the new model's textures.
            self.report_textures(state);
        }
    }

    /// Runs a texture command on the list: the applied texture's label, or
    /// the first error (the list and the texture then stay as they were).
    fn texture_command(&self, command: Command) -> Option<Result<String, String>> {
        let mut list = self.textures?.borrow_mut();
        let errors = match command {
            Command::CycleTexture(forward) => list.cycle(forward).err().into_iter().collect(),
            Command::ReloadTexture => list.reload().err().into_iter().collect(),
            Command::AddPaths(text) => {
                let before = list.len();
                let errors = list.add_paste(&text);
                let added = list.len() - before;
                if !errors.is_empty() && added > 0 {
                    // Some applied, some not: say both.
                    let more = match errors.len() {
                        1 => String::new(),
                        n => format!(" (and {} more)", n - 1),
                    };
                    return Some(Ok(format!(
                        "{}; {added} added, {} not: {}{more}",
                        list.summary(),
                        errors.len(),
                        errors[0]
                    )));
                }
                errors
            }
            Command::SelectTexture(i) => list.select(i).err().into_iter().collect(),
            Command::SetHeights(h) => list.set_heights(h).err().into_iter().collect(),
            Command::ListTextures
            | Command::SavePng
            | Command::BuildScene(..)
            | Command::CompletePath(_)
            | Command::CancelLoad
            | Command::Suspend => return None,
        };
        Some(match errors.first() {
            None => Ok(list.summary()),
            Some(e) if errors.len() > 1 => Err(format!("{e} (and {} more)", errors.len() - 1)),
            Some(e) => Err(e.to_string()),
        })
    }

    /// Sends the texture panel what the list holds now (with the
    /// thumbnails while it is open: each made once, by the list).
    fn report_textures(&self, state: &mut State) {
        if let Some(list) = self.textures {
            let mut listing = textures::listing(&mut list.borrow_mut(), state.textures.open);
            if let Some(stage) = self.stage {
                listing.model = stage.borrow().model_textures(&state.model);
            }
            update(state, Action::TexturesListed(listing));
        }
    }

    /// Runs until the user quits, the terminal goes away or a signal comes.
    /// Quitting never waits for the terminal: whatever is still queued
    /// towards it is at most one frame and its query.
    pub fn run(&mut self, state: &mut State) -> io::Result<Exit> {
        let mut frames = Frames::new();
        self.report_textures(state);
        loop {
            let first = match self.wait(state, &mut frames.schedule) {
                Ok(first) => first,
                Err(exit) => return Ok(exit),
            };
            // Apply everything that is queued before drawing anything.
            let mut next = first;
            while let Some(msg) = next.take().or_else(|| self.rx.try_recv().ok()) {
                if let Some(exit) = self.on_message(state, &mut frames, msg)? {
                    return Ok(exit);
                }
                if state.quit {
                    return Ok(Exit::Quit);
                }
            }
            // A frame in flight or held: what came meanwhile waits for the next.
            let now = Instant::now();
            let Some(due) = frames
                .schedule
                .next(&mut self.pacer, state.continuous(), now)
            else {
                continue;
            };
            if due.strip {
                self.send_strip(state, &mut frames)?;
            } else {
                self.frame(state, &mut frames, &due)?;
            }
        }
    }

    /// Waits: for the frame in flight to be shown (input is applied
    /// meanwhile and folded into the next frame), not at all when a frame is
    /// due, until the exact picture or the next auto-rotation frame is due,
    /// or for as long as it takes. The first message, if one came; the
    /// loop's end when the input is gone.
    fn wait(&mut self, state: &State, schedule: &mut Schedule) -> Result<Option<Msg>, Exit> {
        let now = Instant::now();
        schedule.loading(state.loading.is_some(), now);
        let wait = schedule
            .wait(&mut self.pacer, state.continuous(), now)
            .until(now);
        let ended = || Exit::InputClosed("input ended".into());
        match wait {
            Some(at) if at <= now => Ok(self.rx.try_recv().ok()),
            Some(at) => match self.rx.recv_timeout(at - now) {
                Ok(m) => Ok(Some(m)),
                Err(RecvTimeoutError::Timeout) => Ok(None),
                Err(RecvTimeoutError::Disconnected) => Err(ended()),
            },
            None => self.rx.recv().map(Some).map_err(|_| ended()),
        }
    }

    /// Applies one message; the loop's end when it says so.
    fn on_message(
        &mut self,
        state: &mut State,
        frames: &mut Frames,
        msg: Msg,
    ) -> io::Result<Option<Exit>> {
        match msg {
            Msg::Input(event) => {
                if let Some(action) = action_for_event(state, &event) {
                    frames.schedule.input(Instant::now());
                    if let Some(command) = update(state, action) {
                        self.execute(state, frames, command)?;
                    }
                }
            }
            Msg::Shown(at) => self.pacer.reply(at),
            Msg::Loaded(id) => {
                self.load_finished(state, id);
                frames.schedule.redraw();
            }
            Msg::Resized | Msg::StandInMade => frames.schedule.redraw(),
            Msg::InputClosed(why) => return Ok(Some(Exit::InputClosed(why))),
            Msg::Signal(sig) => return Ok(Some(Exit::Signal(sig))),
        }
        Ok(None)
    }

    /// Does what `update` asked for, and tells the state how it went.
    fn execute(
        &mut self,
        state: &mut State,
        frames: &mut Frames,
        command: Command,
    ) -> io::Result<()> {
        match command {
            Command::SavePng => self.save_png(state, &frames.fb),
            Command::Suspend => self.suspend(frames)?,
            Command::CompletePath(typed) => {
                let found = super::line_edit::complete_path(&typed);
                update(state, Action::PromptCompleted(found));
            }
            Command::BuildScene(kind, model) => self.ask_scene(state, kind, model),
            Command::CancelLoad => {
                if let Some(loader) = &mut self.loader {
                    loader.cancel();
                }
            }
            Command::AddPaths(text) => self.add_paths(state, &text),
            Command::CycleTexture(_)
            | Command::ReloadTexture
            | Command::ListTextures
            | Command::SelectTexture(_)
            | Command::SetHeights(_) => {
                if let Some(result) = self.texture_command(command) {
                    update(state, Action::TextureResult(result));
                }
                self.report_textures(state);
            }
        }
        Ok(())
    }

    /// `Command::SavePng`: the picture at the size of the one shown.
    fn save_png(&mut self, state: &mut State, fb: &Framebuffer) {
        let (w, h) = (fb.width(), fb.height());
        let result = super::screenshot::save(state, w, h, &mut self.render);
        update(state, Action::Saved(result));
    }

    /// `Command::Suspend`: stops until resumed, then draws everything again
    /// on the new screen.
    fn suspend(&mut self, frames: &mut Frames) -> io::Result<()> {
        super::suspend::suspend()?;
        self.terminal.clear()?;
        frames.modes = TermModes::app(MouseReports::Drags); // what reenter sets up
        frames.rendered = None;
        frames.pixels.forget();
        Ok(())
    }

    /// `Command::AddPaths`: model files open as the model, images join the list.
    fn add_paths(&mut self, state: &mut State, text: &str) {
        let (models, images) = split_models(text);
        if let Some(model) = models {
            self.ask_scene(state, SceneKind::Cube, model);
        }
        if let Some(images) = images
            && let Some(result) = self.texture_command(Command::AddPaths(images))
        {
            update(state, Action::TextureResult(result));
        }
        self.report_textures(state);
    }

    /// The exact picture's next strip: one write, paced like a frame,
    /// nothing rendered or drawn again.
    fn send_strip(&mut self, state: &mut State, frames: &mut Frames) -> io::Result<()> {
        if let Some(strip) = frames.pixels.next_strip(self.pacer.throughput())? {
            let asks = self.pacer.asks();
            let backend = self.terminal.backend_mut();
            backend.begin_frame()?;
            backend.write_raw(&strip)?;
            let write_start = Instant::now();
            let trailer: &[u8] = if asks { QUERY } else { &[] };
            let bytes = backend.end_frame_then(trailer)?;
            self.pacer.sent(write_start, bytes, asks);
            let link = self.pacer.info();
            update(state, Action::FrameEnd { link, frame: None });
        }
        frames.schedule.set_strips(frames.pixels.pending());
        Ok(())
    }

    /// One frame: laid out, rendered when what the picture depends on
    /// changed, written, and its cost reported.
    fn frame(&mut self, state: &mut State, frames: &mut Frames, due: &Due) -> io::Result<()> {
        if let Some(seconds) = due.tick {
            update(state, Action::Tick { seconds });
        }
        // A load's progress as of this frame.
        if let Some(status) = self.loader.as_ref().and_then(|l| l.status(Instant::now())) {
            update(state, Action::Loading(status));
        }
        let start = Instant::now();
        let plan = self.lay_out(state)?;
        let same = frames.rendered.as_ref() == Some(&plan.key);
        // A preview is replaced by the exact picture even when nothing changed.
        let new_picture = frames.schedule.new_picture(due, same);
        // The status row as the last frame left it, should a long frame
        // write its progress over it.
        let status_row = plan
            .areas
            .status
            .filter(|r| (frames.status_cells.as_ref()).is_some_and(|(saved, _)| saved == r));
        // A frame that only redraws the text costs no render time; the
        // cost panel keeps the counters of the last render.
        let (stats, progress_shown) = if new_picture {
            self.render_picture(state, frames, &plan, due.preview, status_row)
        } else {
            let counters = frames.last_counters;
            (
                FrameStats {
                    counters,
                    ..FrameStats::default()
                },
                false,
            )
        };
        // A status-only redraw comes once nothing else is due: no frames
        // are flowing.
        let preview = frames.schedule.previewing();
        update(
            state,
            Action::FrameStart {
                preview,
                idle: due.status_only,
            },
        );
        let encode_start = Instant::now();
        let written = self.write_frame(
            state,
            frames,
            &plan,
            new_picture,
            status_row,
            progress_shown,
        )?;
        // A status-only redraw changes only the link's figures: the frame's
        // keep describing the picture.
        let frame = (!due.status_only).then(|| {
            let times = [start, encode_start, written.start, written.done];
            frame_done(&stats, times, written.bytes, &mut frames.clock)
        });
        let bytes = written.bytes;
        update(
            state,
            Action::FrameEnd {
                link: self.pacer.info(),
                frame,
            },
        );
        // An exact picture sent in strips costs all of them.
        let picture_bytes = frames.pixels.take_split_bytes().unwrap_or(bytes);
        (frames.schedule).written(due, new_picture, picture_bytes, state.continuous());
        frames.schedule.set_strips(frames.pixels.pending());
        Ok(())
    }

    /// Fixes the frame's size and places. One size for the whole frame:
    /// laid out, rendered and drawn at it, though the terminal be resized
    /// meanwhile (its signal brings the next frame).
    fn lay_out(&mut self, state: &mut State) -> io::Result<Plan> {
        let size = self.terminal.backend_mut().hold_size()?;
        // The help cannot scroll past what this screen needs: keep the
        // state there so the first key back moves it.
        let (width, height) = (size.width, size.height);
        update(
            state,
            Action::HelpFits(view::help_max_scroll(width, height)),
        );
        update(state, Action::HelpPageFits(view::help_page(width, height)));
        let areas = view::layout(state, Rect::new(0, 0, width, height));
        let panel = view::texture_panel_area(areas.viewport, state);
        update(state, Action::TexturesFit(panel));
        let (w, h) =
            PixelView::framebuffer_size(&state.output, areas.viewport, height, state.symbols);
        let generation = self.textures.map_or(0, |t| t.borrow().generation());
        let key = (state.look(), w, h, generation);
        Ok(Plan { areas, w, h, key })
    }

    /// Renders the picture (at half resolution for a preview, then
    /// enlarged), with a long frame's progress on the status row. Its
    /// figures, and whether the progress was shown.
    fn render_picture(
        &mut self,
        state: &State,
        frames: &mut Frames,
        plan: &Plan,
        cheaper: bool,
        status_row: Option<Rect>,
    ) -> (FrameStats, bool) {
        let status_row = status_row.map(|r| StatusRow {
            row: r.y,
            width: r.width,
        });
        let mut progress_shown = false;
        let render = &mut self.render;
        let mut watched = |fb: &mut Framebuffer| match self.watch.as_mut() {
            Some(watch) => {
                let (stats, shown) = watch.watch(status_row, || render(state, fb));
                progress_shown |= shown;
                stats
            }
            None => render(state, fb),
        };
        let (w, h) = (plan.w, plan.h);
        let stats = if cheaper {
            let (pw, ph) = frames.pixels.preview_size(
                state.output.format(),
                (w, h),
                frames.schedule.exact_bytes(),
                self.pacer.throughput(),
            );
            frames.coarse.resize(pw, ph);
            let stats = watched(&mut frames.coarse);
            frames.fb.resize(w, h);
            enlarge(&frames.coarse, &mut frames.fb);
            stats
        } else {
            frames.fb.resize(w, h);
            watched(&mut frames.fb)
        };
        frames.last_counters = stats.counters;
        // An abandoned frame (a key pressed during a long one) is drawn
        // again once that key is applied.
        frames.rendered = (!stats.abandoned).then_some(plan.key.clone());
        if stats.abandoned {
            frames.schedule.redraw();
        }
        (stats, progress_shown)
    }

    /// Writes the frame: the modes the state wants, the picture and the
    /// text, then the pacing query. When the write started, its bytes, and
    /// when it ended.
    fn write_frame(
        &mut self,
        state: &State,
        frames: &mut Frames,
        plan: &Plan,
        new_picture: bool,
        status_row: Option<Rect>,
        progress_shown: bool,
    ) -> io::Result<Written> {
        let backend = self.terminal.backend_mut();
        // Modes follow the state: a mode left puts back what it changed.
        let wanted = wanted_modes(state);
        if wanted != frames.modes {
            let mut change = Vec::new();
            frames.modes.change_to(&wanted, &mut change);
            backend.write_raw(&change)?;
            frames.modes = wanted;
        }
        let asks = self.pacer.asks();
        // The first write starts with a query of its own: its reply comes
        // one round trip later whatever the frame's size, so a terminal
        // that answers is known as such in time.
        let probe = frames.schedule.probe(asks);
        if probe {
            backend.write_raw(QUERY)?;
        }
        backend.begin_frame()?;
        if progress_shown {
            // The progress line goes: the row is drawn as ratatui believes it is.
            if let (Some(row), Some((_, cells))) = (status_row, frames.status_cells.as_ref()) {
                let cells = cells.iter().enumerate();
                backend.draw(cells.map(|(x, c)| (row.x + x as u16, row.y, c)))?;
            }
        }
        self.draw_view(state, frames, plan, new_picture)?;
        let write_start = Instant::now();
        let trailer: &[u8] = if asks { QUERY } else { &[] };
        let bytes = self.terminal.backend_mut().end_frame_then(trailer)?;
        self.terminal.backend_mut().release_size();
        let done = Instant::now();
        if probe {
            self.pacer.sent(write_start, 0, true);
        }
        self.pacer.sent(write_start, bytes, asks);
        Ok(Written {
            start: write_start,
            bytes,
            done,
        })
    }

    /// Draws the picture (as cells or pixels) and the view around it, and
    /// keeps the status row's cells as drawn.
    fn draw_view(
        &mut self,
        state: &State,
        frames: &mut Frames,
        plan: &Plan,
        new_picture: bool,
    ) -> io::Result<()> {
        let look = TextLook {
            symbols: state.symbols,
            depth: state.depth,
            dither: state.dither,
            pad: self.background,
        };
        let frame = PixelFrame {
            output: &state.output,
            fb: &frames.fb,
            preview: frames.schedule.previewing().then_some(&frames.coarse),
            new_picture,
            look,
            throughput: self.pacer.throughput(),
            unmeasured: self.pacer.throughput().is_none() && self.pacer.answers() != Answers::No,
        };
        let status_cells = &mut frames.status_cells;
        let background = self.background;
        let viewport = plan.areas.viewport;
        frames
            .pixels
            .draw(self.terminal, frame, viewport, |f, pic| {
                view::view(f, state, pic, background);
                // Only what the frame holds (the same size, as it is held).
                let buf = f.buffer_mut();
                *status_cells = plan
                    .areas
                    .status
                    .map(|r| r.intersection(buf.area))
                    .map(|r| (r, (r.x..r.right()).map(|x| buf[(x, r.y)].clone()).collect()));
            })
    }

    /// After the loop ended and the screen was restored: reads the replies
    /// to queries still on their way (at most `limit`), so they are not
    /// echoed onto the shell once raw mode is off. Only for a terminal
    /// known to answer.
    pub fn drain_replies(&mut self, limit: Duration) {
        if self.pacer.answers() != Answers::Yes {
            return;
        }
        let deadline = Instant::now() + limit;
        let mut left = self.pacer.outstanding();
        while left > 0 {
            let now = Instant::now();
            if now >= deadline {
                break;
            }
            match self.rx.recv_timeout(deadline - now) {
                Ok(Msg::Shown(_)) => left -= 1,
                Ok(_) => {}
                Err(_) => break,
            }
        }
    }
}

use relief_term::pixel_view::enlarge;

/// A paste or typed line split into the first model file it names (by
/// extension) and the rest, given back as text for the texture list (paths
/// quoted so spaces survive); none where there is nothing.
fn split_models(text: &str) -> (Option<relief_scene::ModelChoice>, Option<String>) {
    let paths = super::texture_list::parse_paste(text);
    let (models, images): (Vec<_>, Vec<_>) = paths
        .into_iter()
        .partition(|p| relief_scene::model_file::is_model_path(p));
    let model = models
        .into_iter()
        .next()
        .map(relief_scene::ModelChoice::File);
    if model.is_none() {
        // Nothing to take out: the list reads the text as it came.
        return (None, Some(text.to_string()));
    }
    let rest: Vec<String> = images
        .iter()
        .map(|p| format!("'{}'", p.to_string_lossy().replace('\'', "'\\''")))
        .collect();
    (model, (!rest.is_empty()).then(|| rest.join(" ")))
}
