//! What the user asked for: every key, mouse report and paste becomes an `Action`.
//!
//! An option's keys are [`Action::Option`], made from its entry in the
//! option table ([`relief_options::OPTIONS`]). Another control is one
//! `Action` variant, one row in the key table ([`super::keys::KEYS`]) and
//! one arm in `update`.

use std::time::Duration;

use ratatui::layout::Rect;

use super::frame_cost::FrameCost;
use super::line_edit::{Completion, Edit};
use super::textures::TextureListing;
use relief_options::{OptId, Press};
use relief_scene::{ModelChoice, SceneKind};
use relief_term::pacing::LinkInfo;

/// Which button drags (with its modifier), and so what the drag does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DragButton {
    /// Rotates about X (vertical motion) and Y (horizontal motion).
    Left,
    /// Rotates about Z (horizontal motion) and X (vertical motion).
    Right,
    /// Middle button or Shift+left: moves the orbit centre in the view plane.
    Pan,
    /// Ctrl+left, or left while `D` is on: turns the lights about the model.
    Light,
}

/// Everything that changes the state.
#[derive(Clone, Debug, PartialEq)]
pub enum Action {
    Quit,
    /// Esc outside the overlays that take it: closes the cost panel, else
    /// quits (not right after an Esc that closed an overlay).
    Escape,
    /// Ctrl-Z: suspend (the shell's `fg` resumes).
    Suspend,
    /// A key of an option of the table ([`relief_options::OPTIONS`]):
    /// `id` is the option, `press` what the key does to it.
    Option {
        id: OptId,
        press: Press,
    },
    /// Arrow keys (X, Y) and PageUp/PageDown (Z): add `degrees` about `axis` (0 = X).
    RotateStep {
        axis: usize,
        degrees: f32,
    },
    /// `r`: back to the start orientation and distance, auto-rotation off.
    ResetView,
    /// `D`: a left drag turns the lights instead of the model.
    ToggleLightDrag,
    /// Wheel up or `i`: the camera one step closer.
    ZoomIn,
    /// Wheel down or `I`: the camera one step farther.
    ZoomOut,
    /// Space.
    ToggleAutoRotate,
    /// `A`: the animation plays or pauses.
    TogglePlay,
    /// `C`: the model's next animation, from its start.
    NextClip,
    /// `,` `.`: the animation paused and stepped this many frames.
    StepClip(i32),
    /// `V`: the model file's next camera, then the framing camera.
    NextCamera,
    /// `seconds` of time passed while something moves by itself (the
    /// auto-rotation, a playing animation).
    Tick {
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
    /// `x` / `X`: next / previous texture of the list.
    NextTexture,
    PrevTexture,
    /// `T`: open / close the texture panel.
    ToggleTextures,
    /// Esc in the texture panel.
    CloseTextures,
    /// ↑ ↓ j k Home End in the texture panel: move the cursor this many entries.
    TexturesMove(i32),
    /// Enter in the texture panel: apply the entry under the cursor.
    TexturesChoose,
    /// `H` in the texture panel: the heights from the entry under the
    /// cursor (again: each texture's own).
    TexturesHeights,
    /// A click on the texture panel: the left button applies the entry
    /// there, the right one takes its heights.
    TexturesClick {
        button: DragButton,
        col: u16,
        row: u16,
    },
    /// The wheel over the texture panel: scroll it by this many entries.
    TexturesScroll(i32),
    /// What the texture panel shows, from the loop after each texture command.
    TexturesListed(TextureListing),
    /// Where the texture panel is drawn on this screen (the loop reports it
    /// before each frame, as it does the help's height).
    TexturesFit(Option<Rect>),
    /// `R`: re-read the current texture file.
    ReloadTexture,
    /// `/`: open the prompt to type a texture path.
    OpenPrompt,
    /// A character typed into the prompt.
    PromptInput(char),
    PromptBackspace,
    /// An edit of the prompt's line (cursor moves, deletions).
    PromptEdit(Edit),
    /// Tab in the prompt: complete the path before the cursor.
    PromptComplete,
    /// What the loop found for [`Action::PromptComplete`].
    PromptCompleted(Completion),
    /// Enter in the prompt: load the typed path(s).
    PromptSubmit,
    /// Esc in the prompt.
    PromptCancel,
    /// What a texture command did: the new texture's label, or the error.
    TextureResult(Result<String, String>),
    /// `N`: dot3's normal map from the `--normal-map` file / derived from
    /// the height map.
    ToggleNormalMapFile,
    /// `u`: the picture's glyphs: half blocks → quadrants → sextants → octants.
    CycleSymbols,
    /// `U`: the output format: symbols → kitty → sixels → iTerm2 images.
    CycleFormat,
    /// `1`–`4`: one light on / off (0 = white, red, green, blue in the
    /// reference scenes; key, fill, back of a model file's rig).
    ToggleLight(usize),
    /// `z`: plasma Z² table / exact normal.
    TogglePlasmaNormal,
    /// `o`: next model (the loop builds it, then reports with `SceneBuilt`).
    NextModel,
    /// `p`: model → shadow → plasma.
    NextScene,
    /// Outcome of a scene build: what is now shown, or the error (the old scene stays).
    SceneBuilt(Result<(SceneKind, ModelChoice), String>),
    /// How far the model file loading on its worker is (the loop reads it
    /// when the load starts and a few times a second until it ends).
    Loading(super::load_status::LoadStatus),
    /// What loading the shown model had to say: its warnings go to the
    /// message line, and a point cloud switches the display to points.
    ModelNotes(relief_scene::LoadedNotes),
    /// The pointer is at a cell (the plasma's light follows it).
    Pointer {
        col: u16,
        row: u16,
    },
    /// The terminal changed size: nothing in the state changes, the frame must.
    Resize,
    /// A key bound to nothing where the user is: it changes nothing but
    /// clears the message, as every key does.
    Unbound,
    /// Scroll the help by this many lines (arrows, pages, Home/End while it is open).
    HelpScroll(i32),
    /// PgUp / PgDn in the help: this many pages (a page is what it shows).
    HelpPage(i32),
    /// The lines the help shows on this screen (the loop reports them).
    HelpPageFits(u16),
    /// The help on this screen scrolls at most this far (the loop reports
    /// it before each frame, so scrolling back responds at once).
    HelpFits(u16),
    /// A frame is about to be drawn: whether its picture is a preview, and
    /// whether it only redraws the text while no frames flow (no rate then).
    FrameStart {
        preview: bool,
        idle: bool,
    },
    /// A frame was written: the link's figures, and the frame's cost
    /// (`None` for a redraw of the text only).
    FrameEnd {
        link: LinkInfo,
        frame: Option<Box<FrameDone>>,
    },
}

impl Action {
    /// The key of option `id` that gives its next value (a toggle flips).
    pub const fn next(id: OptId) -> Action {
        Action::Option {
            id,
            press: Press::Next,
        }
    }
    /// The key of number option `id` that moves it a step up.
    pub const fn up(id: OptId) -> Action {
        Action::Option {
            id,
            press: Press::Up,
        }
    }
    /// The key of number option `id` that moves it a step down.
    pub const fn down(id: OptId) -> Action {
        Action::Option {
            id,
            press: Press::Down,
        }
    }
}

/// What writing a frame cost, as the loop reports it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameDone {
    /// Time per stage, for the cost panel.
    pub cost: FrameCost,
    /// Render, encode and write time.
    pub time: Duration,
    /// Bytes sent to the terminal.
    pub bytes: u64,
    /// Frames in the last second (`None` for a lone frame).
    pub fps: Option<f32>,
}
