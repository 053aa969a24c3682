//! The interactive view's state: everything `update` changes and `view` draws.

use std::path::PathBuf;
use std::time::Duration;

use glam::{Vec2, Vec3};

use super::action::DragButton;
use super::frame_cost::CostHistory;
use super::load_status::LoadStatus;
use super::textures::TexturePanel;
use relief_core::settings::{Settings, normalize_degrees};
use relief_plasma::PlasmaNormal;
use relief_scene::camera::{MAX_DISTANCE, MIN_DISTANCE, REFERENCE_DISTANCE};
use relief_scene::{ModelChoice, SceneKind};
use relief_term::pacing::LinkInfo;
use relief_term::{ColorDepth, Symbols};

/// Degrees per column of a drag (a column is one pixel wide).
pub const DEG_PER_COL: f32 = 2.0;
/// Degrees per row of a drag (a row is two pixels tall).
pub const DEG_PER_ROW: f32 = 4.0;
/// World units a pan drag moves the orbit centre per column and per row
/// at the reference distance: in a 48-row terminal showing the reference
/// view (5.8 units tall at the target) the model follows the pointer.
pub const PAN_PER_ROW: f32 = 0.12;
pub const PAN_PER_COL: f32 = 0.06;
/// Farthest a pan moves the orbit centre (world units): the model stays findable.
pub const PAN_MAX: Vec2 = Vec2::splat(20.0);
/// Auto-rotation speed about Y, degrees per second.
pub const AUTO_ROTATE_SPEED: f32 = 40.0;
/// A zoom step (wheel notch, `i` or `I`) divides or multiplies the camera
/// distance by this.
pub const ZOOM_STEP: f32 = 1.125;
/// Axis names of the orientation fields.
pub const AXES: [&str; 3] = ["X", "Y", "Z"];
/// The reference lights in scene order, as keys `1`–`4` name them.
pub const LIGHT_NAMES: [&str; 4] = ["white", "red", "green", "blue"];
/// The model view's neutral rig in scene order (`scene::model_view`).
pub const RIG_NAMES: [&str; 3] = ["key", "fill", "back"];

/// The three orientation fields (degrees about X, Y, Z).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Panel {
    /// The focused field, when the panel has the keyboard.
    pub focus: Option<usize>,
    /// Text typed into each field; `None` shows the live angle.
    pub edits: [Option<String>; 3],
    /// The next character replaces the focused field (it was just entered).
    pub fresh: bool,
    /// The axes Enter applied while another entry was refused (Esc then
    /// drops only the rest).
    pub applied: [bool; 3],
}

/// A drag in progress: the button and where the pointer was last.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Drag {
    pub button: DragButton,
    pub col: u16,
    pub row: u16,
}

/// What the last frame cost, shown in the status line.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FrameInfo {
    /// Render, encode and write time of the last frame.
    pub frame_time: Duration,
    /// Frames written in the last second; `None` when frames are not
    /// flowing (idle, or a lone frame).
    pub fps: Option<f32>,
    /// Bytes the last frame sent to the terminal.
    pub bytes: u64,
    /// The picture on screen is a preview (cheaper, while input keeps
    /// coming over a slow link); the exact one follows.
    pub preview: bool,
}

#[derive(Clone, Debug, PartialEq)]
pub struct State {
    pub settings: Settings,
    /// Orientation `r` goes back to.
    pub start_rotation: Vec3,
    pub depth: ColorDepth,
    /// What decided the depth (`--color`, `COLORTERM`, tmux…: see
    /// [`relief_term::depth`]); shown in the cost panel.
    pub depth_source: String,
    /// Ordered dithering in 256 and 16 colours.
    pub dither: bool,
    /// Glyphs the picture is drawn with (`u` cycles them).
    pub symbols: Symbols,
    /// Text symbols or pixel images (`U` cycles them), and why.
    pub output: relief_term::pixel_view::Output,
    pub help: bool,
    /// First help line shown when the help is taller than the screen.
    pub help_scroll: u16,
    pub auto_rotate: bool,
    /// An animated model's clips and where it is in them.
    pub playback: Playback,
    /// How many cameras of its own the model file has.
    pub cameras: usize,
    /// How many lights of its own the model file has (they replace the
    /// model view's rig).
    pub file_lights: usize,
    /// The model file's every part is shaded physically: the Phong-only
    /// keys are refused (`feedback`).
    pub physical: bool,
    /// What the model file's parts have that some keys act on (all there
    /// in the reference scenes, the normals but on the flat built-in
    /// models); the keys are refused without (`feedback`).
    pub features: relief_scene::model_view::ModelFeatures,
    /// Which parts of the model file can show a texture (`None`: a
    /// reference scene, or a model with nothing to say): the texture keys
    /// are refused where none shows (`feedback`).
    pub texture_reach: Option<relief_scene::model_view::TextureReach>,
    /// Who set the up axis: a model's format, or the user (`--up`, `Z`).
    pub up: UpChoice,
    /// The user chose the texture (a picture or map on the command line,
    /// or one applied in the view): a model's parts without a material take it.
    pub texture_chosen: bool,
    /// Key `V`: the file's camera the model is seen through (none: the
    /// framing camera).
    pub camera: Option<usize>,
    pub panel: Panel,
    pub drag: Option<Drag>,
    /// One line of feedback (errors, saved file, paste), already sanitized.
    pub message: Option<String>,
    pub frame: FrameInfo,
    /// Key `k`: the cost panel is shown.
    pub cost_panel: bool,
    /// Stage times of the last frames, for the cost panel.
    pub costs: CostHistory,
    /// Round trip and throughput to the terminal, for the cost panel.
    pub link: LinkInfo,
    pub quit: bool,
    /// The scene shown (changed only once it is built: see [`Action::SceneBuilt`]).
    pub scene: SceneKind,
    /// The model of the model scene.
    pub model: ModelChoice,
    /// The model file given with `--model` or opened since: `o` goes to it after the sphere.
    pub obj: Option<PathBuf>,
    /// Keys `1`–`4`: each reference light on or off (the scene applies them
    /// when rendering; `settings.lights` switches them all).
    pub light_on: [bool; 4],
    /// Key `z`: the plasma's Z² table or exact normal.
    pub plasma_normal: PlasmaNormal,
    /// The last pointer cell in the plasma scene (`None`: light at the centre).
    pub pointer: Option<(u16, u16)>,
    /// Key `/`: the texture path being typed (`None`: no prompt).
    pub prompt: Option<String>,
    /// Where the prompt's cursor is: a byte offset of `prompt`, on a
    /// character boundary (kept within the text when used).
    pub prompt_cursor: usize,
    /// Lines PgUp / PgDn scroll the help: the lines it shows on this screen
    /// (the loop reports them before each frame).
    pub help_page: u16,
    /// The last key was an Esc that closed an overlay: another Esc right
    /// after it does not quit.
    pub esc_closed: bool,
    /// Key `T`: the texture panel, and what it shows of the texture list.
    pub textures: TexturePanel,
    /// Camera distance in reference units (wheel, `i` / `I`): 5 is the
    /// reference view; kept within [`MIN_DISTANCE`]..=[`MAX_DISTANCE`].
    pub distance: f32,
    /// Distance `r` goes back to (`--distance`).
    pub start_distance: f32,
    /// Where the orbit centre appears, moved from the picture's centre in
    /// the view plane (world units, x right, y up): middle or Shift+drag.
    pub pan: Vec2,
    /// Degrees the lights are turned about the model (x about the
    /// vertical, y about the horizontal): Ctrl+drag, or drag with `D` on.
    pub light_turn: Vec2,
    /// Key `D`: a left drag turns the lights.
    pub light_drag: bool,
    /// The normal map file loaded with `--normal-map` (its name, sanitised):
    /// key `N` switches dot3 between it and the height-derived map.
    pub normal_map_file: Option<String>,
    /// A model file loading on its worker: the status line shows how far
    /// it is, and Esc cancels it (the model shown stays meanwhile).
    pub loading: Option<LoadStatus>,
}

/// Lines a help page scrolls before the loop reports the screen's.
const DEFAULT_HELP_PAGE: u16 = 8;

/// Everything the picture depends on besides its size and the texture:
/// the loop renders again only when this changes.
#[derive(Clone, Debug, PartialEq)]
pub struct Look {
    pub settings: Settings,
    pub scene: SceneKind,
    pub model: ModelChoice,
    pub light_on: [bool; 4],
    pub plasma_normal: PlasmaNormal,
    pub pointer: Option<(u16, u16)>,
    /// Camera distance (not in the plasma, which has no camera).
    pub distance: Option<f32>,
    pub pan: Vec2,
    pub light_turn: Vec2,
    /// The animation's clip and instant (none: the model has none).
    pub animation: Option<(usize, f32)>,
    /// The file's camera seen through.
    pub camera: Option<usize>,
}

/// An animated model's clips (keys `A`, `C`, `,`, `.`): which plays, and
/// how far in.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Playback {
    /// Each clip's name and length in seconds (empty: nothing to play).
    pub clips: Vec<(String, f32)>,
    pub clip: usize,
    /// Seconds into the clip, within its length.
    pub time: f32,
    pub playing: bool,
}

/// Seconds a step (`,` `.`) moves a paused animation: a frame at 30 per second.
pub const ANIMATION_STEP: f32 = 1.0 / 30.0;

impl Playback {
    /// The clip and instant shown, when there is a clip.
    pub fn shown(&self) -> Option<(usize, f32)> {
        (!self.clips.is_empty()).then_some((self.clip, self.time))
    }

    /// Moves `seconds` on (or back), looping within the clip.
    pub fn advance(&mut self, seconds: f32) {
        let length = self.clips.get(self.clip).map_or(0.0, |c| c.1);
        let t = self.time + seconds;
        self.time = if length > 0.0 && t.is_finite() {
            t.rem_euclid(length)
        } else {
            0.0
        };
    }
}

impl State {
    /// Whether the picture moves by itself: frames come at the frame
    /// interval (auto-rotation, or an animation playing).
    pub fn continuous(&self) -> bool {
        self.auto_rotate || self.playback.playing
    }

    /// Whether the picture is a model file's model view (its framing, rig
    /// and environment), not a reference scene.
    pub fn in_model_view(&self) -> bool {
        self.scene == SceneKind::Cube && matches!(self.model, ModelChoice::File(_))
    }

    /// What keys `1`–`4` switch, in order: the reference scene's four
    /// lights, a model file's neutral rig (key, fill, back) or its own
    /// lights (the first four).
    pub fn light_names(&self) -> Vec<String> {
        match self.file_lights {
            _ if !self.in_model_view() => LIGHT_NAMES.map(String::from).to_vec(),
            0 => RIG_NAMES.map(String::from).to_vec(),
            n => (1..=n.min(4)).map(|k| format!("light {k}")).collect(),
        }
    }

    pub fn new(settings: Settings, depth: ColorDepth) -> Self {
        let mut settings = settings;
        settings.rotation = settings.rotation.to_array().map(normalize_degrees).into();
        State {
            settings,
            start_rotation: settings.rotation,
            depth,
            depth_source: "--color".into(),
            dither: false,
            symbols: Symbols::Half,
            output: Default::default(),
            help: false,
            help_scroll: 0,
            auto_rotate: false,
            playback: Playback::default(),
            cameras: 0,
            file_lights: 0,
            physical: false,
            features: Default::default(),
            texture_reach: None,
            texture_chosen: false,
            up: UpChoice::Default,
            camera: None,
            panel: Panel::default(),
            drag: None,
            message: None,
            frame: FrameInfo::default(),
            cost_panel: false,
            costs: CostHistory::default(),
            link: LinkInfo::default(),
            quit: false,
            scene: SceneKind::Cube,
            model: ModelChoice::Cube,
            obj: None,
            light_on: [true; 4],
            plasma_normal: PlasmaNormal::Table,
            pointer: None,
            prompt: None,
            prompt_cursor: 0,
            help_page: DEFAULT_HELP_PAGE,
            esc_closed: false,
            textures: TexturePanel::default(),
            distance: REFERENCE_DISTANCE,
            start_distance: REFERENCE_DISTANCE,
            pan: Vec2::ZERO,
            light_turn: Vec2::ZERO,
            light_drag: false,
            normal_map_file: None,
            loading: None,
        }
    }

    /// What the picture depends on (the pointer only counts in the plasma).
    pub fn look(&self) -> Look {
        Look {
            settings: self.settings,
            scene: self.scene,
            model: self.model.clone(),
            light_on: self.light_on,
            plasma_normal: self.plasma_normal,
            pointer: self.pointer.filter(|_| self.scene == SceneKind::Plasma),
            distance: Some(self.distance).filter(|_| self.scene != SceneKind::Plasma),
            pan: self.pan,
            light_turn: self.light_turn,
            animation: self.playback.shown(),
            camera: self.camera,
        }
    }

    /// The model `o` shows next: triangle → plane → cube → sphere → the
    /// model file loaded last (if any) → triangle.
    pub fn next_model(&self) -> ModelChoice {
        match (&self.model, &self.obj) {
            (ModelChoice::Sphere, Some(path)) => ModelChoice::File(path.clone()),
            (m, _) => m.next(),
        }
    }

    /// What the option table's status fields and key messages read.
    pub fn ctx(&self) -> relief_options::Ctx<'_> {
        relief_options::Ctx {
            settings: &self.settings,
            lights_on: self.light_on.iter().any(|&on| on),
            normal_map_loaded: self.normal_map_file.is_some(),
            texture_waits: self.texture_reach
                == Some(relief_scene::model_view::TextureReach::WhenChosen)
                && !self.texture_chosen,
        }
    }

    /// Starts at `distance` (`--distance`), which `r` comes back to.
    pub fn with_distance(mut self, distance: f32) -> Self {
        let d = if distance.is_finite() {
            distance.clamp(MIN_DISTANCE, MAX_DISTANCE)
        } else {
            REFERENCE_DISTANCE
        };
        self.distance = d;
        self.start_distance = d;
        self
    }

    /// The message line: how far a load is, then the last message.
    pub fn message_line(&self) -> Option<String> {
        match (&self.loading, &self.message) {
            (Some(load), Some(message)) => Some(format!("{}  {message}", load.text())),
            (Some(load), None) => Some(load.text()),
            (None, message) => message.clone(),
        }
    }

    /// Text shown in orientation field `axis`: the edit, or the live angle.
    pub fn field_text(&self, axis: usize) -> String {
        match &self.panel.edits[axis] {
            Some(text) => text.clone(),
            None => format_angle(self.settings.rotation[axis]),
        }
    }

    /// Turns the model by `delta` degrees about X, Y and Z.
    pub(super) fn rotate(&mut self, delta: Vec3) {
        let r = self.settings.rotation + delta;
        self.settings.rotation = r.to_array().map(normalize_degrees).into();
    }
}

/// The plasma light for a pointer cell: cell (col, row) covers pixels
/// (col, 2·row) and (col, 2·row + 1), and the light goes on the lower one,
/// where the pointer's tip is drawn. No pointer yet: the centre.
pub fn plasma_light(pointer: Option<(u16, u16)>, width: usize, height: usize) -> (f32, f32) {
    match pointer {
        Some((col, row)) => (col as f32, 2.0 * row as f32 + 1.0),
        None => (width as f32 / 2.0, height as f32 / 2.0),
    }
}

/// An angle as the orientation fields show it.
pub fn format_angle(deg: f32) -> String {
    let s = format!("{deg:.1}");
    let s = s.strip_suffix(".0").map(str::to_owned).unwrap_or(s);
    // -0.04 rounds to a zero that keeps its sign.
    if s == "-0" { "0".into() } else { s }
}

/// Who set the view's up axis (`Settings::up`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum UpChoice {
    /// Nobody: Y up.
    Default,
    /// The shown model's format (an STL stands Z up): the axis goes back to
    /// Y with the next scene.
    File,
    /// The user (`--up`, or `Z`): kept for every model.
    User,
}
