//! What the user asked for: every key, mouse report and paste becomes an `Action`.
//!
//! Adding a control is one `Action` variant, one arm in [`action_for_key`]
//! and one arm in `update`.

use crossterm::event::{
    Event, KeyCode, KeyEvent, KeyEventKind, KeyModifiers, MouseButton, MouseEventKind,
};

use super::state::State;
use crate::scene::{ModelChoice, SceneKind};

/// Which button drags.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DragButton {
    /// Rotates about X (vertical motion) and Y (horizontal motion).
    Left,
    /// Rotates about Z (horizontal motion) and X (vertical motion).
    Right,
}

/// Everything that changes the state.
#[derive(Clone, Debug, PartialEq)]
pub enum Action {
    Quit,
    /// `m`: flat → Gouraud → Phong.
    CycleShading,
    /// `n`: vertex / face normals.
    ToggleNormals,
    /// `t`
    ToggleTexture,
    /// `c`
    ToggleColors,
    /// `b`
    ToggleBump,
    /// `+`
    BumpStronger,
    /// `-`
    BumpWeaker,
    /// Arrow keys (X, Y) and PageUp/PageDown (Z): add `degrees` about `axis` (0 = X).
    RotateStep {
        axis: usize,
        degrees: f32,
    },
    /// `r`: back to the start orientation, auto-rotation off.
    ResetView,
    /// Space.
    ToggleAutoRotate,
    /// Auto-rotation advances by `seconds` of time.
    AutoRotateTick {
        seconds: f32,
    },
    /// `s`: the event loop writes the PNG and reports with `Saved`.
    SavePng,
    /// Outcome of a save: the path written, or the error.
    Saved(Result<String, String>),
    /// `?`
    ToggleHelp,
    /// `k`: the cost panel.
    ToggleCost,
    CloseHelp,
    /// Tab: into the orientation fields, then to the next field.
    PanelNext,
    /// Shift-Tab: previous field.
    PanelPrev,
    /// A character typed into the focused field.
    PanelInput(char),
    PanelBackspace,
    /// Enter: apply the edited fields.
    PanelApply,
    /// Esc in the fields: drop the edits.
    PanelCancel,
    /// A button went down at a cell.
    MouseDown {
        button: DragButton,
        col: u16,
        row: u16,
    },
    /// The pointer moved with a button down.
    MouseDrag {
        button: DragButton,
        col: u16,
        row: u16,
    },
    MouseUp,
    /// Bracketed paste (a file dragged onto the terminal arrives this way).
    Paste(String),
    /// `f`: next texture filter.
    CycleFilter,
    /// `x` / `X`: next / previous texture of the list.
    NextTexture,
    PrevTexture,
    /// `R`: re-read the current texture file.
    ReloadTexture,
    /// `/`: open the prompt to type a texture path.
    OpenPrompt,
    /// A character typed into the prompt.
    PromptInput(char),
    PromptBackspace,
    /// Enter in the prompt: load the typed path(s).
    PromptSubmit,
    /// Esc in the prompt.
    PromptCancel,
    /// What a texture command did: the new texture's label, or the error.
    TextureResult(Result<String, String>),
    /// `e`: Blinn → emboss → dot3 → parallax → POM.
    CycleTechnique,
    /// `v`: dot3's light vector per vertex / per pixel.
    ToggleLightVector,
    /// `h`: height derivative per texel / filtered.
    ToggleHeightDerivative,
    /// `a`: off → SSAA 2×2 → SSAA 4×4 → MSAA 4.
    CycleAntiAlias,
    /// `d`: points → lines → fill.
    CycleDisplay,
    /// `l`: all lights on / off.
    ToggleLights,
    /// `L`: distance attenuation on / off.
    ToggleAttenuation,
    /// `1`–`4`: one reference light (0 = white, red, green, blue) on / off.
    ToggleLight(usize),
    /// `z`: plasma Z² table / exact normal.
    TogglePlasmaNormal,
    /// `o`: next model (the loop builds it, then reports with `SceneBuilt`).
    NextModel,
    /// `p`: model → shadow → plasma.
    NextScene,
    /// Outcome of a scene build: what is now shown, or the error (the old scene stays).
    SceneBuilt(Result<(SceneKind, ModelChoice), String>),
    /// The pointer is at a cell (the plasma's light follows it).
    Pointer {
        col: u16,
        row: u16,
    },
    /// The terminal changed size: nothing in the state changes, the frame must.
    Resize,
    /// Scroll the help by this many lines (arrows, pages, Home/End while it is open).
    HelpScroll(i32),
}

/// Lines PgUp / PgDn scroll the help.
const HELP_PAGE: i32 = 8;

/// Degrees an arrow key turns the model.
pub const ARROW_STEP: f32 = 5.0;

/// The action a terminal event asks for in this state, if any.
pub fn action_for_event(state: &State, event: &Event) -> Option<Action> {
    match event {
        Event::Key(key) => action_for_key(state, key),
        Event::Mouse(mouse) => {
            let button = |b: MouseButton| match b {
                MouseButton::Left => Some(DragButton::Left),
                MouseButton::Right => Some(DragButton::Right),
                MouseButton::Middle => None,
            };
            let (col, row) = (mouse.column, mouse.row);
            if state.scene == SceneKind::Plasma {
                // The light follows the pointer, pressed or not; nothing turns.
                return match mouse.kind {
                    MouseEventKind::Moved | MouseEventKind::Down(_) | MouseEventKind::Drag(_) => {
                        Some(Action::Pointer { col, row })
                    }
                    _ => None,
                };
            }
            match mouse.kind {
                MouseEventKind::Down(b) => {
                    button(b).map(|button| Action::MouseDown { button, col, row })
                }
                MouseEventKind::Drag(b) => {
                    button(b).map(|button| Action::MouseDrag { button, col, row })
                }
                MouseEventKind::Up(_) => Some(Action::MouseUp),
                _ => None,
            }
        }
        Event::Paste(text) => Some(Action::Paste(text.clone())),
        Event::Resize(..) => Some(Action::Resize),
        _ => None,
    }
}

/// The action a key asks for. Keys `/ k` are kept for the texture path
/// and cost panel.
pub fn action_for_key(state: &State, key: &KeyEvent) -> Option<Action> {
    if key.kind == KeyEventKind::Release {
        return None;
    }
    let ctrl = key.modifiers.contains(KeyModifiers::CONTROL);
    if ctrl && matches!(key.code, KeyCode::Char('c') | KeyCode::Char('C')) {
        return Some(Action::Quit);
    }
    if key.modifiers.contains(KeyModifiers::ALT) {
        return None;
    }
    if state.prompt.is_some() {
        return match key.code {
            KeyCode::Enter => Some(Action::PromptSubmit),
            KeyCode::Esc => Some(Action::PromptCancel),
            KeyCode::Backspace => Some(Action::PromptBackspace),
            KeyCode::Char(c) if !ctrl => Some(Action::PromptInput(c)),
            _ => None,
        };
    }
    if state.panel.focus.is_some() {
        return match key.code {
            KeyCode::Tab => Some(Action::PanelNext),
            KeyCode::BackTab => Some(Action::PanelPrev),
            KeyCode::Enter => Some(Action::PanelApply),
            KeyCode::Esc => Some(Action::PanelCancel),
            KeyCode::Backspace => Some(Action::PanelBackspace),
            KeyCode::Char(c) if !ctrl => Some(Action::PanelInput(c)),
            _ => None,
        };
    }
    if ctrl {
        return None;
    }
    let step = |axis: usize, degrees: f32| Some(Action::RotateStep { axis, degrees });
    if state.help {
        // The open help takes the scrolling keys (it may not fit the screen).
        let lines = match key.code {
            KeyCode::Up => Some(-1),
            KeyCode::Down => Some(1),
            KeyCode::PageUp => Some(-HELP_PAGE),
            KeyCode::PageDown => Some(HELP_PAGE),
            KeyCode::Home => Some(i32::MIN),
            KeyCode::End => Some(i32::MAX),
            _ => None,
        };
        if let Some(lines) = lines {
            return Some(Action::HelpScroll(lines));
        }
    }
    match key.code {
        KeyCode::Char('q') => Some(Action::Quit),
        KeyCode::Esc if state.help => Some(Action::CloseHelp),
        KeyCode::Esc => Some(Action::Quit),
        KeyCode::Char('m') => Some(Action::CycleShading),
        KeyCode::Char('n') => Some(Action::ToggleNormals),
        KeyCode::Char('t') => Some(Action::ToggleTexture),
        KeyCode::Char('c') => Some(Action::ToggleColors),
        KeyCode::Char('b') => Some(Action::ToggleBump),
        KeyCode::Char('+') | KeyCode::Char('=') => Some(Action::BumpStronger),
        KeyCode::Char('-') | KeyCode::Char('_') => Some(Action::BumpWeaker),
        KeyCode::Left => step(1, -ARROW_STEP),
        KeyCode::Right => step(1, ARROW_STEP),
        KeyCode::Up => step(0, -ARROW_STEP),
        KeyCode::Down => step(0, ARROW_STEP),
        KeyCode::PageUp => step(2, ARROW_STEP),
        KeyCode::PageDown => step(2, -ARROW_STEP),
        KeyCode::Char('r') => Some(Action::ResetView),
        KeyCode::Char(' ') => Some(Action::ToggleAutoRotate),
        KeyCode::Char('s') => Some(Action::SavePng),
        KeyCode::Char('f') => Some(Action::CycleFilter),
        KeyCode::Char('x') => Some(Action::NextTexture),
        KeyCode::Char('X') => Some(Action::PrevTexture),
        KeyCode::Char('R') => Some(Action::ReloadTexture),
        KeyCode::Char('/') => Some(Action::OpenPrompt),
        KeyCode::Char('e') => Some(Action::CycleTechnique),
        KeyCode::Char('v') => Some(Action::ToggleLightVector),
        KeyCode::Char('h') => Some(Action::ToggleHeightDerivative),
        KeyCode::Char('a') => Some(Action::CycleAntiAlias),
        KeyCode::Char('d') => Some(Action::CycleDisplay),
        KeyCode::Char('l') => Some(Action::ToggleLights),
        KeyCode::Char('L') => Some(Action::ToggleAttenuation),
        KeyCode::Char(c @ '1'..='4') => Some(Action::ToggleLight(c as usize - '1' as usize)),
        KeyCode::Char('z') => Some(Action::TogglePlasmaNormal),
        KeyCode::Char('o') => Some(Action::NextModel),
        KeyCode::Char('p') => Some(Action::NextScene),
        KeyCode::Char('?') => Some(Action::ToggleHelp),
        KeyCode::Char('k') => Some(Action::ToggleCost),
        KeyCode::Tab => Some(Action::PanelNext),
        KeyCode::BackTab => Some(Action::PanelPrev),
        _ => None,
    }
}
