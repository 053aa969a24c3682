//! Every key as one table: which input mode it works in, the key, the
//! action it asks for and its line in the help. [`action_for_key`] and the
//! help overlay both read [`bindings`] (the options' keys from the option
//! table, then [`KEYS`]), so a key cannot work without being documented,
//! nor be documented without working.
//!
//! An option's keys are declared in its entry of the option table
//! ([`relief_options::OPTIONS`]). Another control is one `Action` variant,
//! one row here and one arm in `update`.

use std::sync::LazyLock;

use crossterm::event::{KeyCode, KeyEvent, KeyEventKind, KeyModifiers};

use super::action::Action;
use super::line_edit::Edit;
use super::state::State;
use relief_options::{KeyHelp, OPTIONS};

/// Who has the keyboard.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Mode {
    /// The picture: every control.
    Normal,
    /// The help overlay is open: it takes the scrolling keys and Esc; the
    /// other keys still act on the picture.
    Help,
    /// The texture panel is open: it takes the keys that move in the list,
    /// pick a row and close it; the other keys still act on the picture.
    Textures,
    /// Typing into the orientation fields.
    Fields,
    /// Typing a texture path.
    Prompt,
}

impl Mode {
    /// Every mode, in the order the help lists them.
    pub const ALL: [Mode; 5] = [
        Mode::Normal,
        Mode::Help,
        Mode::Textures,
        Mode::Fields,
        Mode::Prompt,
    ];

    /// The mode the state is in: a field being edited or a prompt takes
    /// every key; an open overlay takes only its own (the help, drawn on
    /// top, before the texture panel).
    pub fn of(state: &State) -> Mode {
        if state.prompt.is_some() {
            Mode::Prompt
        } else if state.panel.focus.is_some() {
            Mode::Fields
        } else if state.help {
            Mode::Help
        } else if state.textures.open {
            Mode::Textures
        } else {
            Mode::Normal
        }
    }

    /// Where a key this mode does not bind is looked up next (`None`: it
    /// does nothing).
    pub fn fallback(self) -> Option<Mode> {
        match self {
            Mode::Help | Mode::Textures => Some(Mode::Normal),
            Mode::Normal | Mode::Fields | Mode::Prompt => None,
        }
    }

    /// The heading of this mode's part of the help (`None`: no heading).
    pub fn heading(self) -> Option<&'static str> {
        match self {
            Mode::Normal => None,
            Mode::Help => Some("while this help is open"),
            Mode::Textures => Some("in the texture panel (T)"),
            Mode::Fields => Some("in the orientation fields (Tab)"),
            Mode::Prompt => Some("in the texture path prompt (/)"),
        }
    }
}

/// A key as the table names it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Key {
    /// The key alone (Shift allowed: it is part of the character).
    Plain(KeyCode),
    /// Ctrl and this letter (either case).
    Ctrl(char),
    /// Any printable character not bound otherwise in the mode (typing).
    AnyChar,
}

/// What a row does.
#[derive(Clone, Debug)]
pub enum Does {
    /// Always this action.
    Act(Action),
    /// An action made from the character typed.
    Char(fn(char) -> Action),
    /// A mouse gesture or a paste: listed in the help, turned into actions
    /// by [`super::events::action_for_event`].
    Gesture,
}

/// How a row shows in the help.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Help {
    /// Its own line: the keys as shown, then the text.
    Line(&'static str, &'static str),
    /// Described by the nearest line above it in the same mode (e.g. `-`
    /// under "+ -"), or by an option's line that names it (`N` under "v N").
    Above,
}

/// One row of the table.
#[derive(Clone, Debug)]
pub struct Binding {
    pub mode: Mode,
    /// The keys (empty: a mouse gesture, listed in the help only).
    pub keys: &'static [Key],
    pub does: Does,
    pub help: Help,
}

impl Binding {
    /// The action this row gives for `key` (one of its keys).
    pub fn action(&self, key: Key, c: Option<char>) -> Option<Action> {
        match &self.does {
            Does::Act(a) => Some(a.clone()),
            Does::Gesture => None,
            Does::Char(f) => match (key, c) {
                (Key::Plain(KeyCode::Char(k)), _) => Some(f(k)),
                (Key::AnyChar, Some(c)) => Some(f(c)),
                _ => None,
            },
        }
    }
}

/// Degrees an arrow key turns the model.
pub const ARROW_STEP: f32 = 5.0;

use Help::{Above, Line};
use Key::{Ctrl, Plain};
use KeyCode::{
    BackTab, Backspace, Down, End, Enter, Esc, Home, Left, PageDown, PageUp, Right, Tab, Up,
};

const fn c(ch: char) -> Key {
    Plain(KeyCode::Char(ch))
}

const fn row(mode: Mode, keys: &'static [Key], action: Action, help: Help) -> Binding {
    Binding {
        mode,
        keys,
        does: Does::Act(action),
        help,
    }
}

const fn gesture(mode: Mode, keys: &'static str, text: &'static str) -> Binding {
    Binding {
        mode,
        keys: &[],
        does: Does::Gesture,
        help: Line(keys, text),
    }
}

const fn rotate(axis: usize, degrees: f32) -> Action {
    Action::RotateStep { axis, degrees }
}

fn light(c: char) -> Action {
    Action::ToggleLight(c as usize - '1' as usize)
}

use Mode::{Fields, Normal, Prompt, Textures};

/// The keys that are not an option's, and the mouse gestures, in the
/// help's order ([`bindings`] adds the options' keys before them).
pub const KEYS: &[Binding] = &[
    // The picture.
    gesture(
        Normal,
        "left drag",
        "rotate about X (↕) and Y (↔); Shift: pan; Ctrl, D: lights",
    ),
    row(Normal, &[c('D')], Action::ToggleLightDrag, Above),
    gesture(
        Normal,
        "right drag",
        "rotate about Z (↔) and X (↕); middle drag: pan",
    ),
    row(
        Normal,
        &[Plain(Left)],
        rotate(1, -ARROW_STEP),
        Line("arrows", "rotate 5° about X (↑↓) or Y (←→)"),
    ),
    row(Normal, &[Plain(Right)], rotate(1, ARROW_STEP), Above),
    row(Normal, &[Plain(Up)], rotate(0, -ARROW_STEP), Above),
    row(Normal, &[Plain(Down)], rotate(0, ARROW_STEP), Above),
    row(
        Normal,
        &[Plain(PageUp)],
        rotate(2, ARROW_STEP),
        Line("PgUp PgDn", "rotate 5° about Z"),
    ),
    row(Normal, &[Plain(PageDown)], rotate(2, -ARROW_STEP), Above),
    row(
        Normal,
        &[Plain(Tab)],
        Action::PanelNext,
        Line("Tab", "orientation fields X Y Z: type degrees"),
    ),
    row(Normal, &[Plain(BackTab)], Action::PanelPrev, Above),
    row(
        Normal,
        &[c(' ')],
        Action::ToggleAutoRotate,
        Line("space", "auto-rotation on / off"),
    ),
    row(
        Normal,
        &[c('A')],
        Action::TogglePlay,
        Line(
            "A C , .",
            "animation: play / pause; next clip; a frame back / on",
        ),
    ),
    row(Normal, &[c('C')], Action::NextClip, Above),
    row(Normal, &[c(',')], Action::StepClip(-1), Above),
    row(Normal, &[c('.')], Action::StepClip(1), Above),
    row(
        Normal,
        &[c('V')],
        Action::NextCamera,
        Line("V", "a glTF model's own cameras, then the framing camera"),
    ),
    row(
        Normal,
        &[c('i')],
        Action::ZoomIn,
        Line("i I wheel", "zoom: camera closer / farther"),
    ),
    row(Normal, &[c('I')], Action::ZoomOut, Above),
    row(
        Normal,
        &[c('r')],
        Action::ResetView,
        Line("r", "reset orientation, zoom, pan and lights"),
    ),
    row(
        Normal,
        &[c('s')],
        Action::SavePng,
        Line("s", "save the frame as a PNG"),
    ),
    row(
        Normal,
        &[c('x')],
        Action::NextTexture,
        Line("x X T", "next / previous texture; T: the texture panel"),
    ),
    row(Normal, &[c('X')], Action::PrevTexture, Above),
    row(Normal, &[c('T')], Action::ToggleTextures, Above),
    row(
        Normal,
        &[c('R')],
        Action::ReloadTexture,
        Line("R", "re-read the current texture file"),
    ),
    row(
        Normal,
        &[c('/')],
        Action::OpenPrompt,
        Line("/", "type a texture path (Enter loads, Esc cancels)"),
    ),
    gesture(
        Normal,
        "paste",
        "a pasted (dragged) file joins the texture list",
    ),
    row(
        Normal,
        &[c('k')],
        Action::ToggleCost,
        Line(
            "k",
            "cost panel: time per stage, frame times, active stages",
        ),
    ),
    row(
        Normal,
        &[c('N')],
        Action::ToggleNormalMapFile,
        // Described by the `v N` line of the option `light_vector`.
        Above,
    ),
    row(
        Normal,
        &[c('u')],
        Action::CycleSymbols,
        // Described by the `d F u U` line of the option `display`.
        Above,
    ),
    row(
        Normal,
        &[c('U')],
        Action::CycleFormat,
        // Described by the `d F u U` line of the option `display`.
        Above,
    ),
    Binding {
        mode: Normal,
        keys: &[c('1'), c('2'), c('3'), c('4')],
        does: Does::Char(light),
        // Described by the `l 1 2 3 4` line of the option `lights`.
        help: Above,
    },
    row(
        Normal,
        &[c('o')],
        Action::NextModel,
        Line("o", "model: triangle → plane → cube → sphere → OBJ"),
    ),
    row(
        Normal,
        &[c('p')],
        Action::NextScene,
        Line("p", "scene: model → shadow → plasma"),
    ),
    row(
        Normal,
        &[c('z')],
        Action::TogglePlasmaNormal,
        Line("z", "plasma: Z² table / exact normal"),
    ),
    gesture(Normal, "pointer", "plasma: the light follows the mouse"),
    row(
        Normal,
        &[c('?')],
        Action::ToggleHelp,
        Line("?", "this help (Esc closes it; ↑↓ PgUp PgDn scroll it)"),
    ),
    row(
        Normal,
        &[c('q'), Ctrl('c')],
        Action::Quit,
        Line(
            "q Esc Ctrl-C",
            "quit (Esc closes the cost panel first); Ctrl-Z suspends",
        ),
    ),
    row(Normal, &[Plain(Esc)], Action::Escape, Above),
    row(Normal, &[Ctrl('z')], Action::Suspend, Above),
    // The help overlay.
    row(
        Mode::Help,
        &[Plain(Up)],
        Action::HelpScroll(-1),
        Line("↑ ↓", "scroll a line"),
    ),
    row(Mode::Help, &[Plain(Down)], Action::HelpScroll(1), Above),
    row(
        Mode::Help,
        &[Plain(PageUp)],
        Action::HelpPage(-1),
        Line("PgUp PgDn", "scroll a page"),
    ),
    row(Mode::Help, &[Plain(PageDown)], Action::HelpPage(1), Above),
    row(
        Mode::Help,
        &[Plain(Home)],
        Action::HelpScroll(i32::MIN),
        Line("Home End", "first / last line"),
    ),
    row(
        Mode::Help,
        &[Plain(End)],
        Action::HelpScroll(i32::MAX),
        Above,
    ),
    row(
        Mode::Help,
        &[Plain(Esc)],
        Action::CloseHelp,
        Line("Esc ?", "close the help"),
    ),
    // The texture panel.
    row(
        Textures,
        &[Plain(Up), c('k')],
        Action::TexturesMove(-1),
        Line("↑ ↓ j k", "move in the list (Home End: first / last)"),
    ),
    row(
        Textures,
        &[Plain(Down), c('j')],
        Action::TexturesMove(1),
        Above,
    ),
    row(
        Textures,
        &[Plain(Home)],
        Action::TexturesMove(i32::MIN),
        Above,
    ),
    row(
        Textures,
        &[Plain(End)],
        Action::TexturesMove(i32::MAX),
        Above,
    ),
    row(
        Textures,
        &[Plain(Enter)],
        Action::TexturesChoose,
        Line("Enter H", "use it / take its heights (H again: their own)"),
    ),
    row(Textures, &[c('H')], Action::TexturesHeights, Above),
    gesture(
        Textures,
        "click wheel",
        "left: use it; right: its heights; wheel: scroll",
    ),
    row(
        Textures,
        &[Plain(Esc), c('T')],
        Action::CloseTextures,
        Line("Esc T", "close the panel"),
    ),
    // The orientation fields.
    row(
        Fields,
        &[Plain(Tab)],
        Action::PanelNext,
        Line("Tab", "next field (Shift-Tab: previous)"),
    ),
    row(Fields, &[Plain(BackTab)], Action::PanelPrev, Above),
    Binding {
        mode: Fields,
        keys: &[Key::AnyChar],
        does: Does::Char(Action::PanelInput),
        help: Line("0-9 . -", "type degrees (Backspace erases)"),
    },
    row(Fields, &[Plain(Backspace)], Action::PanelBackspace, Above),
    row(
        Fields,
        &[Plain(Enter)],
        Action::PanelApply,
        Line("Enter", "apply the fields"),
    ),
    row(
        Fields,
        &[Plain(Esc)],
        Action::PanelCancel,
        Line("Esc", "drop the edits"),
    ),
    row(Fields, &[Ctrl('c')], Action::Quit, Line("Ctrl-C", "quit")),
    // The texture path prompt.
    Binding {
        mode: Prompt,
        keys: &[Key::AnyChar],
        does: Does::Char(Action::PromptInput),
        help: Line("text Tab", "type the path; Tab completes a file name"),
    },
    row(Prompt, &[Plain(Tab)], Action::PromptComplete, Above),
    row(
        Prompt,
        &[Plain(Left)],
        Action::PromptEdit(Edit::Left),
        Line("← → Home End", "move; Backspace Delete Ctrl-U Ctrl-W erase"),
    ),
    row(
        Prompt,
        &[Plain(Right)],
        Action::PromptEdit(Edit::Right),
        Above,
    ),
    row(
        Prompt,
        &[Plain(Home)],
        Action::PromptEdit(Edit::Home),
        Above,
    ),
    row(Prompt, &[Plain(End)], Action::PromptEdit(Edit::End), Above),
    row(Prompt, &[Ctrl('a')], Action::PromptEdit(Edit::Home), Above),
    row(Prompt, &[Ctrl('e')], Action::PromptEdit(Edit::End), Above),
    row(Prompt, &[Plain(Backspace)], Action::PromptBackspace, Above),
    row(
        Prompt,
        &[Plain(KeyCode::Delete)],
        Action::PromptEdit(Edit::Delete),
        Above,
    ),
    row(
        Prompt,
        &[Ctrl('u')],
        Action::PromptEdit(Edit::KillToStart),
        Above,
    ),
    row(
        Prompt,
        &[Ctrl('w')],
        Action::PromptEdit(Edit::KillWord),
        Above,
    ),
    row(
        Prompt,
        &[Plain(Enter)],
        Action::PromptSubmit,
        Line("Enter Esc", "load the path / close the prompt"),
    ),
    row(Prompt, &[Plain(Esc)], Action::PromptCancel, Above),
    row(Prompt, &[Ctrl('c')], Action::Quit, Line("Ctrl-C", "quit")),
];

/// The key an event is, as the table names keys (`None`: modifiers no row uses).
fn key_of(key: &KeyEvent) -> Option<Key> {
    let m = key.modifiers;
    if m.contains(KeyModifiers::CONTROL) {
        return match key.code {
            KeyCode::Char(ch) if !m.contains(KeyModifiers::ALT) => {
                Some(Ctrl(ch.to_ascii_lowercase()))
            }
            _ => None,
        };
    }
    if m.contains(KeyModifiers::ALT) {
        return None;
    }
    Some(Plain(key.code))
}

/// The rows of the options' keys, from the option table: each press of
/// an entry is one row of the picture's mode.
fn option_rows() -> Vec<Binding> {
    let mut rows = Vec::new();
    for (i, opt) in OPTIONS.iter().enumerate() {
        for (j, k) in opt.keys.iter().enumerate() {
            // Made once (see `bindings`): the keys live as long as the program.
            let keys: &'static [Key] = Vec::leak(k.keys.iter().map(|&ch| c(ch)).collect());
            rows.push(Binding {
                mode: Normal,
                keys,
                does: Does::Act(Action::Option {
                    id: opt.id,
                    press: k.press,
                }),
                // Made once too: the keys shown and the text filled in
                // from the entries.
                help: match k.help {
                    KeyHelp::Line { text, .. } => Line(
                        String::leak(relief_options::help_keys(i, j)),
                        String::leak(opt.fill(text)),
                    ),
                    KeyHelp::Above => Above,
                },
            });
        }
    }
    rows
}

/// Every key of every mode, and the mouse gestures, in the help's order:
/// the options' keys first, then [`KEYS`].
pub fn bindings() -> &'static [Binding] {
    static ALL: LazyLock<Vec<Binding>> = LazyLock::new(|| {
        let mut all = option_rows();
        all.extend(KEYS.iter().cloned());
        all
    });
    &ALL
}

/// The row of `mode` (not its fallback) that binds `key`, and the
/// character when it is typed text.
pub fn binding_in(mode: Mode, key: Key) -> Option<(&'static Binding, Key)> {
    let rows = || bindings().iter().filter(move |b| b.mode == mode);
    if let Some(b) = rows().find(|b| b.keys.contains(&key)) {
        return Some((b, key));
    }
    match key {
        Plain(KeyCode::Char(ch)) if !ch.is_control() => rows()
            .find(|b| b.keys.contains(&Key::AnyChar))
            .map(|b| (b, Key::AnyChar)),
        _ => None,
    }
}

/// The action a key asks for in this state: [`Action::Unbound`] for a key
/// bound to nothing here (it still clears the message); `None` for a
/// key's release.
pub fn action_for_key(state: &State, event: &KeyEvent) -> Option<Action> {
    if event.kind == KeyEventKind::Release {
        return None;
    }
    let Some(key) = key_of(event) else {
        return Some(Action::Unbound);
    };
    let typed = match event.code {
        KeyCode::Char(ch) => Some(ch),
        _ => None,
    };
    let mut mode = Some(Mode::of(state));
    while let Some(m) = mode {
        if let Some((b, k)) = binding_in(m, key) {
            return b.action(k, typed);
        }
        mode = m.fallback();
    }
    Some(Action::Unbound)
}

/// One line of the help: the keys column and the text (a heading has no
/// keys and its text ends with a colon).
pub type HelpLine = (&'static str, &'static str);

/// The help's lines: the picture's keys, then each other mode's under its
/// heading.
pub fn help_lines() -> Vec<HelpLine> {
    let mut lines = Vec::new();
    for mode in Mode::ALL {
        if let Some(heading) = mode.heading() {
            lines.push(("", heading));
        }
        for b in bindings().iter().filter(|b| b.mode == mode) {
            if let Line(keys, text) = b.help {
                lines.push((keys, text));
            }
        }
    }
    lines
}
