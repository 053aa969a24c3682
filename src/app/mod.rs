//! The interactive view: Elm style. Terminal events become [`Action`]s, a
//! pure [`update`] changes the [`State`], [`view`] draws it.

pub mod action;
pub mod command;
pub mod event_loop;
pub mod events;
pub mod feedback;
pub mod file_cameras;
pub mod frame_cost;
pub mod frame_watch;
pub mod keys;
pub mod line_edit;
pub mod load_status;
pub mod loading;
pub mod playback;
pub mod schedule;
pub mod screenshot;
pub mod stage;
pub mod state;
pub mod suspend;
pub mod texture_list;
pub mod textures;
pub mod thumbnail;
pub mod update;
pub mod view;

pub use action::{Action, DragButton};
pub use command::Command;
pub use events::action_for_event;
pub use keys::action_for_key;
pub use state::State;
pub use update::update;
pub use view::view;

use std::io::{IsTerminal, Read};
use std::os::fd::{AsFd, AsRawFd};
use std::sync::{Arc, mpsc};

use anyhow::{Context, bail};
use ratatui::Terminal;

use crate::cli::{Cli, ColorDepthArg};
use event_loop::{Exit, Looper, Msg, spawn_terminal_reader};
use frame_watch::LONG_FRAME;
use loading::Loader;
use relief_term::guard::{GuardedStdout, TerminalGuard};
use relief_term::{ColorDepth, SgrBackend, depth, probe};
use stage::Stage;

/// The colour depth to use: `--color` when given, else what the environment
/// announces (the view then also asks the terminal, see [`relief_term::probe`]).
pub fn color_depth(arg: Option<ColorDepthArg>) -> ColorDepth {
    match arg {
        Some(ColorDepthArg::Truecolor) => ColorDepth::Truecolor,
        Some(ColorDepthArg::Palette256) => ColorDepth::Palette256,
        Some(ColorDepthArg::Palette16) => ColorDepth::Palette16,
        None => ColorDepth::from_env(),
    }
}

/// Runs the interactive view until the user quits.
pub fn run(cli: Cli) -> anyhow::Result<()> {
    let tty = open_tty()?;
    let mut cli = cli;
    let Start {
        mut state,
        textures,
        first_load,
        model_notes,
    } = initial_state(&mut cli)?;
    let stage = read_stage(&cli, &mut state, &textures, model_notes)?;
    let stage = std::cell::RefCell::new(stage);
    let mut stage_generation = textures.generation();
    let textures = std::cell::RefCell::new(textures);

    let (tx, rx) = mpsc::channel();
    let loader = start_loader(tx.clone(), &stage.borrow(), &cli, first_load, &mut state);
    let signals = spawn_signal_thread(tx.clone())?;
    let stand_in_tx = tx.clone();
    // tmux and infocmp are asked before the terminal is set up.
    let settled = cli.color.is_none().then(depth::settled_here).flatten();
    let clues = relief_term::format::clues_here(cli.format);
    let guard = TerminalGuard::enter().context("cannot set up the terminal")?;
    let typed = probe_terminal(&cli, tty.as_ref(), &mut state, settled, clues);
    // Keys pressed are counted on their way to the loop, so a long frame
    // can see that the user wants something else (`q` quits at once).
    let keys = Arc::new(std::sync::atomic::AtomicU64::new(0));
    spawn_input(tty, typed, count_keys(tx, keys.clone()));
    let mut backend = SgrBackend::new(GuardedStdout::new()?);
    backend.set_tolerance(cli.color_tolerance);
    let mut terminal = Terminal::new(backend)?;
    let (mut renderer, watch) = watched_renderer(stand_in_tx)?;
    let mut looper = Looper {
        terminal: &mut terminal,
        render: |s: &State, fb: &mut relief_core::framebuffer::Framebuffer| {
            let mut stage = stage.borrow_mut();
            let list = textures.borrow();
            if list.generation() != stage_generation {
                stage.set_texture(list.texture().clone());
                stage_generation = list.generation();
            }
            // Pixel images have square pixels.
            renderer.set_pixel_aspect(if s.output.format().is_pixels() {
                1.0
            } else {
                s.symbols.pixel_aspect()
            });
            renderer.set_cancel(Some(abandon_when_keys(keys.clone())));
            stage.render(&mut renderer, s, fb)
        },
        background: relief_scene::BACKGROUND,
        rx: &rx,
        textures: Some(&textures),
        stage: Some(&stage),
        pacer: relief_term::pacing::pacer_here(cli.link),
        loader: Some(loader),
        watch: Some(watch),
    };
    let exit = looper.run(&mut state);
    // The screen first (quitting never waits for the terminal), then the
    // replies still on their way are read so the shell does not get them.
    relief_term::guard::restore_screen();
    if !matches!(exit, Ok(Exit::InputClosed(_))) {
        looper.drain_replies(std::time::Duration::from_millis(500));
    }
    drop(looper);
    drop(terminal);
    drop(guard);
    signals.close();
    match exit? {
        Exit::Quit => Ok(()),
        Exit::InputClosed(_) => Ok(()),
        Exit::Signal(sig) => std::process::exit(128 + sig),
    }
}

/// The worker that loads model files, already loading `first_load` (the
/// model file the command line names).
fn start_loader(
    tx: mpsc::Sender<Msg>,
    stage: &Stage,
    cli: &Cli,
    first_load: Option<relief_scene::ModelChoice>,
    state: &mut State,
) -> Loader {
    let mut loader = Loader::new(move |id| {
        let _ = tx.send(Msg::Loaded(id));
    });
    if let Some(model) = first_load {
        let order = stage.order(cli.view.scene, &model);
        let status = loader.start(order, std::time::Instant::now());
        update(state, Action::Loading(status));
    }
    loader
}

/// The renderer, with a long frame's progress counted by it and shown by
/// the loop's watch.
fn watched_renderer(
    tx: mpsc::Sender<Msg>,
) -> anyhow::Result<(relief_pipeline::render::Renderer, frame_watch::FrameWatch)> {
    use relief_pipeline::shadow::{CasterLod, StandInReady};
    let mut renderer = relief_pipeline::render::Renderer::new();
    // A dense model's shadow from its stand-in once that is made, drawn as
    // soon as it is.
    renderer.set_caster_lod(CasterLod::Background);
    renderer.set_stand_in_ready(Some(StandInReady(Arc::new(move || {
        let _ = tx.send(Msg::StandInMade);
    }))));
    let progress = Arc::new(relief_pipeline::render::FrameProgress::new());
    renderer.set_progress(Some(progress.clone()));
    let watch = frame_watch::FrameWatch {
        progress,
        out: Box::new(GuardedStdout::new()?),
    };
    Ok((renderer, watch))
}

/// Where keys come from: standard input when it is a terminal, else the
/// process's terminal (`Some`). No terminal on standard output is an error.
fn open_tty() -> anyhow::Result<Option<std::fs::File>> {
    if !std::io::stdout().is_terminal() {
        bail!("the interactive view needs a terminal on standard output (try `relief render`)");
    }
    Ok(if std::io::stdin().is_terminal() {
        None
    } else {
        Some(std::fs::File::open("/dev/tty").context("no terminal to read keys from")?)
    })
}

/// What the view starts from, read from the flags.
struct Start {
    state: State,
    textures: texture_list::TextureList,
    /// The model file to load once the view runs (`cli`'s model is then
    /// the cube shown meanwhile).
    first_load: Option<relief_scene::ModelChoice>,
    /// What reading the positional arguments as models noted.
    model_notes: Vec<String>,
}

/// The state the flags ask for, the texture list, and the model to load.
fn initial_state(cli: &mut Cli) -> anyhow::Result<Start> {
    let model_notes = crate::cli::models_from_positional(&mut cli.images, &mut cli.view.model);
    let settings = cli.view.settings();
    let mut state = State::new(settings, color_depth(cli.color)).with_distance(cli.view.distance);
    state.dither = cli.dither;
    state.symbols = cli.symbols;
    if cli.view.options.given(relief_options::OptId::Up) {
        state.up = state::UpChoice::User;
    }
    // The first image that loads is applied; the others wait for the texture list.
    let (textures, errors) =
        texture_list::TextureList::from_args(&cli.images, cli.view.height_map.as_deref());
    if !errors.is_empty() {
        let text: Vec<String> = errors.iter().map(|e| e.to_string()).collect();
        state.message = Some(relief_core::sanitize::clean(&text.join("; ")));
    }
    state.scene = cli.view.scene;
    // A model file loads on the worker once the view runs (with its
    // progress on the status line); the cube is shown meanwhile, and
    // stays if the file cannot be loaded. One that cannot even be opened
    // stops here, before the terminal is touched.
    let mut first_load = None;
    if let relief_scene::ModelChoice::File(path) = &cli.view.model {
        state.obj = Some(path.clone());
        if Loader::wants(cli.view.scene, &cli.view.model) {
            relief_scene::model_io::check_openable(path)?;
            first_load = Some(cli.view.model.clone());
            cli.view.model = relief_scene::ModelChoice::Cube;
        }
    }
    state.model = cli.view.model.clone();
    state.plasma_normal = cli.view.plasma_normal;
    Ok(Start {
        state,
        textures,
        first_load,
        model_notes,
    })
}

/// The stage the view draws, with the maps the flags name. A normal map
/// file that cannot be read is a message (the view goes on with the
/// height-derived map); a --model file that cannot be read stops here,
/// before the terminal is touched, then a specular or environment map that
/// cannot.
fn read_stage(
    cli: &Cli,
    state: &mut State,
    textures: &texture_list::TextureList,
    model_notes: Vec<String>,
) -> anyhow::Result<Stage> {
    // The flags' maps, read as `relief render` reads them.
    let read = relief_scene::flag_maps::FlagMaps::read(
        cli.view.specular_map.as_deref(),
        cli.view.normal_map.as_deref(),
        cli.view.environment_map.as_deref(),
    );
    let normal = match read.normal {
        Ok(map) => {
            if let Some(map) = &map {
                state.normal_map_file = Some(map.name.clone());
                if !relief_pipeline::plan::normal_map_file_shows(&state.settings, true) {
                    state.message = Some(format!(
                        "normal map {} loaded: it shows with dot3 (N)",
                        map.name
                    ));
                }
            }
            map
        }
        Err(e) => {
            state.settings.normal_map_file = false;
            let text = relief_core::sanitize::clean(&e.to_string());
            state.message = Some(match state.message.take() {
                Some(before) => format!("{before}; {text}"),
                None => text,
            });
            None
        }
    };
    let maps = relief_scene::flag_maps::FlagMaps {
        specular: read.specular?,
        normal,
        environment: read.environment?,
    };
    // An image, a height map or a surface map the user named is a texture
    // chosen: a model file's parts without a material take it.
    state.texture_chosen =
        textures.generation() > 0 || cli.view.height_map.is_some() || maps.name_surface_maps();
    let mut stage = Stage::new(
        cli.view.scene,
        &cli.view.model,
        textures.texture().clone(),
        cli.view.all_faces,
    )?
    .with_maps(maps);
    let mut notes = stage.take_notes();
    notes.warnings.splice(0..0, model_notes);
    if notes != relief_scene::LoadedNotes::default() {
        update(state, Action::ModelNotes(notes));
    }
    Ok(stage)
}

/// Asks the terminal for 24-bit colour when neither --color nor the
/// environment, tmux or terminfo settled it, and for its pixel formats
/// unless one is forced: one burst of questions. Sets the state's output
/// and colour depth from the answers; gives back the keys typed meanwhile
/// (they go to the decoder first).
fn probe_terminal(
    cli: &Cli,
    tty: Option<&std::fs::File>,
    state: &mut State,
    settled: Option<depth::DepthChoice>,
    mut clues: relief_term::format::Clues,
) -> Vec<u8> {
    let mut typed = Vec::new();
    let ask_colour = cli.color.is_none() && settled.is_none();
    let found = (ask_colour || clues.wants_probe()).then(|| {
        let stdin = std::io::stdin();
        let fd = match tty {
            Some(file) => file.as_fd(),
            None => stdin.as_fd(),
        };
        let through_tmux = clues.asks_through_tmux();
        let in_tmux = clues.tmux.is_some();
        probe::ask(
            fd,
            &mut std::io::stdout(),
            probe::TIMEOUT,
            in_tmux,
            through_tmux,
        )
        .ok()
    });
    let mut truecolor_reply = None;
    let mut cell_reply = None;
    let mut sixel_max = None;
    if let Some(found) = found.flatten() {
        clues.kitty_reply = found.kitty;
        clues.sixel_da1 = found.sixel;
        clues.client_sixel = found.client_sixel == Some(true);
        clues.version = found.version;
        truecolor_reply = Some(found.truecolor);
        cell_reply = found.cell_pixels;
        sixel_max = found.sixel_max;
        typed = found.other;
    }
    state.output = relief_term::pixel_view::Output::from_clues(&clues, cell_reply);
    state.output.sixel_max = sixel_max;
    if state.message.is_none() {
        state.message = state.output.choice.note.clone();
    }
    if cli.color.is_none() {
        let choice = match settled {
            Some(choice) => choice,
            None => match truecolor_reply {
                Some(true) => depth::DepthChoice {
                    depth: ColorDepth::Truecolor,
                    source: "terminal's reply".into(),
                },
                _ => depth::fallback_here(),
            },
        };
        state.depth = choice.depth;
        state.depth_source = choice.source;
    }
    typed
}

/// Reads the terminal (`tty`, else standard input) on its own thread, the
/// keys typed during the probe first.
fn spawn_input(tty: Option<std::fs::File>, typed: Vec<u8>, tx: mpsc::Sender<Msg>) {
    let fd = tty.as_ref().map_or(0, |file| file.as_raw_fd());
    let input: Box<dyn std::io::Read + Send> = match tty {
        Some(file) => Box::new(std::io::Cursor::new(typed).chain(file)),
        None => Box::new(std::io::Cursor::new(typed).chain(std::io::stdin())),
    };
    spawn_terminal_reader(input, fd, tx);
}

/// A sender whose messages reach `tx`, counting the keys among them in `keys`.
fn count_keys(tx: mpsc::Sender<Msg>, keys: Arc<std::sync::atomic::AtomicU64>) -> mpsc::Sender<Msg> {
    let (forward, rx) = mpsc::channel();
    std::thread::spawn(move || {
        for msg in rx {
            if matches!(msg, Msg::Input(crossterm::event::Event::Key(_))) {
                keys.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
            }
            if tx.send(msg).is_err() {
                return;
            }
        }
    });
    forward
}

/// The renderer's cancel hook for the frame starting now: stop once the
/// frame has run [`LONG_FRAME`] and a key was pressed since it began.
fn abandon_when_keys(
    keys: Arc<std::sync::atomic::AtomicU64>,
) -> relief_pipeline::render::CancelHook {
    let start = std::time::Instant::now();
    let before = keys.load(std::sync::atomic::Ordering::Relaxed);
    Arc::new(move || {
        start.elapsed() >= LONG_FRAME && keys.load(std::sync::atomic::Ordering::Relaxed) != before
    })
}

/// Forwards SIGWINCH, SIGINT, SIGTERM and SIGHUP to the loop. After a
/// terminating signal the loop has one second to finish; then the terminal
/// is restored from here and the process exits (a write stuck on a dead link).
fn spawn_signal_thread(tx: mpsc::Sender<Msg>) -> anyhow::Result<signal_hook::iterator::Handle> {
    use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM, SIGWINCH};
    let mut signals = signal_hook::iterator::Signals::new([SIGWINCH, SIGINT, SIGTERM, SIGHUP])
        .context("cannot install signal handlers")?;
    let handle = signals.handle();
    std::thread::spawn(move || {
        for sig in signals.forever() {
            if sig == SIGWINCH {
                let _ = tx.send(Msg::Resized);
                continue;
            }
            let _ = tx.send(Msg::Signal(sig));
            std::thread::sleep(std::time::Duration::from_secs(1));
            relief_term::guard::restore();
            std::process::exit(128 + sig);
        }
    });
    Ok(handle)
}
