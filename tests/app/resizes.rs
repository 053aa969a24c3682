//! The view at every size: drawn through ratatui's `TestBackend` at each
//! size from 0×0 up, with every overlay open, and while the terminal
//! shrinks and grows between frames (a dragged window corner), nothing is
//! drawn outside the area it is given.

use std::sync::mpsc;

use crossterm::event::{Event, KeyCode, KeyEvent, KeyModifiers};
use ratatui::Terminal;
use ratatui::backend::TestBackend;
use ratatui::layout::Rect;
use relief::app::event_loop::{Exit, Looper, Msg};
use relief::app::textures::{TextureListing, TextureRow};
use relief::app::view::{areas, framebuffer_size};
use relief::app::{Action, State, update, view};
use relief_core::framebuffer::Framebuffer;
use relief_core::settings::Settings;
use relief_scene::SceneKind;
use relief_term::format::{Clues, Format};
use relief_term::pixel_view::Output;
use relief_term::{ColorDepth, SgrBackend, Symbols};

const LONG: &str = "a message long enough to wrap over several rows of a narrow \
                    screen, with a_word_longer_than_any_narrow_line_can_hold in it";

fn listing(n: usize) -> TextureListing {
    TextureListing {
        rows: (0..n)
            .map(|i| TextureRow {
                label: format!("texture number {i} with a long name.png"),
                preview: None,
            })
            .collect(),
        current: 1,
        heights: Some(2),
        model: vec!["base colour: helmet_albedo.jpg 2048×2048".into(); 3],
    }
}

/// States covering every part the view draws: each overlay alone, all
/// of them at once, the prompt, the fields being edited, the plasma.
fn states() -> Vec<(&'static str, State)> {
    let base = || State::new(Settings::default(), ColorDepth::Truecolor);
    let with = |actions: Vec<Action>| {
        let mut s = base();
        for a in actions {
            update(&mut s, a);
        }
        s
    };
    let textures = || {
        vec![
            Action::TexturesListed(listing(7)),
            Action::ToggleTextures,
            Action::TexturesListed(listing(7)),
        ]
    };
    let mut all = textures();
    all.extend([
        Action::ToggleCost,
        Action::ToggleHelp,
        Action::TextureResult(Err(LONG.into())),
    ]);
    let mut plasma = base();
    plasma.scene = SceneKind::Plasma;
    let mut octants = base();
    octants.symbols = Symbols::Octant;
    vec![
        ("plain", base()),
        ("help", with(vec![Action::ToggleHelp])),
        ("cost panel", with(vec![Action::ToggleCost])),
        ("texture panel", with(textures())),
        (
            "long message",
            with(vec![Action::TextureResult(Err(LONG.into()))]),
        ),
        (
            "prompt",
            with(vec![Action::OpenPrompt, Action::PromptInput('x')]),
        ),
        ("fields", with(vec![Action::PanelNext])),
        ("everything", with(all)),
        ("plasma", plasma),
        ("octants", octants),
    ]
}

/// One frame at the terminal's size, as the app draws it.
fn draw(term: &mut Terminal<TestBackend>, s: &State) {
    let size = term.size().unwrap();
    let a = areas(Rect::new(0, 0, size.width, size.height));
    let (w, h) = framebuffer_size(a.viewport, s.symbols);
    let mut fb = Framebuffer::new(w, h);
    fb.fill([120, 60, 30]);
    term.draw(|f| view(f, s, &fb, [0, 0, 0])).unwrap();
}

/// The screen of `s` at 120×40.
fn screen(s: &State) -> ratatui::buffer::Buffer {
    let mut term = Terminal::new(TestBackend::new(120, 40)).unwrap();
    draw(&mut term, s);
    term.backend().buffer().clone()
}

#[test]
fn every_part_of_the_view_draws_at_every_small_size() {
    let plain = screen(&State::new(Settings::default(), ColorDepth::Truecolor));
    for (name, s) in states() {
        if name != "plain" {
            assert_ne!(screen(&s), plain, "{name} shows something of its own");
        }
        for w in 0..=90u16 {
            for h in 0..=30u16 {
                let mut term = Terminal::new(TestBackend::new(w, h)).unwrap();
                let r =
                    std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| draw(&mut term, &s)));
                assert!(r.is_ok(), "{name} at {w}×{h}");
            }
        }
    }
}

/// Sizes of a window corner dragged from 160×48 to nothing, one cell at
/// a time in turn, then back.
fn dragged_corner() -> Vec<(u16, u16)> {
    let mut sizes = Vec::new();
    let (mut w, mut h) = (160u16, 48u16);
    while w > 0 || h > 0 {
        sizes.push((w, h));
        w = w.saturating_sub(3);
        sizes.push((w, h));
        h = h.saturating_sub(1);
    }
    let shrink = sizes.clone();
    sizes.extend(shrink.into_iter().rev());
    sizes
}

#[test]
fn the_view_follows_a_dragged_corner_and_toggled_sizes() {
    let mut toggles = Vec::new();
    for _ in 0..20 {
        toggles.extend([(160, 48), (80, 24), (1, 1), (0, 0), (200, 3)]);
    }
    for (name, s) in states() {
        let mut term = Terminal::new(TestBackend::new(160, 48)).unwrap();
        for &(w, h) in dragged_corner().iter().chain(&toggles) {
            term.backend_mut().resize(w, h);
            draw(&mut term, &s);
            assert_eq!(
                term.backend().buffer().area,
                Rect::new(0, 0, w, h),
                "{name}"
            );
        }
    }
}

/// A terminal's output that, at each write of a frame, queues the next
/// of `next` for the loop (then the end of input).
struct Feeder {
    tx: mpsc::Sender<Msg>,
    next: std::collections::VecDeque<Msg>,
}

impl std::io::Write for Feeder {
    fn write(&mut self, b: &[u8]) -> std::io::Result<usize> {
        let msg = self
            .next
            .pop_front()
            .unwrap_or_else(|| Msg::InputClosed("end of input".into()));
        let _ = self.tx.send(msg);
        Ok(b.len())
    }

    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

fn key(c: char) -> Msg {
    Msg::Input(Event::Key(KeyEvent::new(
        KeyCode::Char(c),
        KeyModifiers::NONE,
    )))
}

/// Runs the loop while the terminal changes size between any two reads
/// of it (`sizes` in turn), overlays opening and closing; returns the
/// frames rendered.
fn run_resized_between_reads(format: Format, sizes: &[(u16, u16)], frames: usize) -> usize {
    let (tx, rx) = mpsc::channel();
    let mut next = std::collections::VecDeque::new();
    for i in 0..frames {
        next.push_back(Msg::Resized);
        match i % 6 {
            1 => next.push_back(key('?')),
            3 => next.push_back(key('k')),
            _ => {}
        }
    }
    let mut backend = SgrBackend::with_size(Feeder { tx, next }, 160, 48);
    backend.set_sizes_per_read(sizes);
    let mut term = Terminal::new(backend).unwrap();
    let mut state = State::new(Settings::default(), ColorDepth::Truecolor);
    state.output = Output::from_clues(
        &Clues {
            forced: Some((format, "--format")),
            ..Clues::default()
        },
        None,
    );
    let mut renders = 0;
    let exit = Looper::new(&mut term, &rx, |_: &State, fb: &mut Framebuffer| {
        renders += 1;
        fb.fill([renders as u8, 80, 160]);
        relief_core::stats::FrameStats::default()
    })
    .run(&mut state)
    .unwrap();
    assert!(matches!(exit, Exit::InputClosed(_)), "{exit:?}");
    let _ = relief_term::pixel_view::take_cleanup();
    renders
}

#[test]
fn a_terminal_resized_while_a_frame_is_laid_out_draws_at_one_size() {
    // Two sizes toggled (a read of the size in two gives the other one),
    // and an odd cycle with the smallest sizes, so that each frame's
    // reads disagree in another way.
    let toggled = [(160, 48), (80, 24)];
    let odd = [(160, 48), (80, 24), (1, 1), (0, 0), (81, 3)];
    for (format, frames) in [
        (Format::Symbols, 300),
        (Format::Kitty, 40),
        (Format::Sixels, 20),
    ] {
        for sizes in [&toggled[..], &odd[..]] {
            let renders = run_resized_between_reads(format, sizes, frames);
            assert!(
                renders > frames / 2,
                "{format:?}: {renders} frames rendered"
            );
        }
    }
}
