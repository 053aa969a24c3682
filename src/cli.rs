//! The command line: `relief` (interactive), `relief render`, `relief bench`.

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand, ValueEnum};
use glam::{Vec2, Vec3};

use relief_core::settings::Settings;
use relief_options::OptionArgs;
use relief_options::text::parse_finite;
use relief_plasma::PlasmaNormal;
use relief_scene::{ModelChoice, SceneKind};
use relief_term::{Format, Symbols};

#[derive(Parser, Debug)]
#[command(
    name = "relief",
    version,
    about = "Bump-mapped 3D scenes rendered on the CPU, shown in the terminal",
    args_conflicts_with_subcommands = true
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Option<Command>,
    /// Options of the interactive view (when no subcommand is given).
    #[command(flatten)]
    pub view: ViewArgs,
    /// Colour depth of the terminal output. Default: detected, in this order:
    /// COLORTERM=truecolor|24bit, a TERM ending in -direct, inside tmux the
    /// client's RGB feature (tmux display '#{client_termfeatures}'; before tmux
    /// 3.2 the client terminal's terminfo), TERM's
    /// terminfo (Tc, RGB or setrgbf, through infocmp), the terminal's reply
    /// to XTGETTCAP and DECRQSS; else 16 colours on the Linux console, 256
    /// elsewhere. The cost panel (k) says which one decided.
    #[arg(long, value_enum)]
    pub color: Option<ColorDepthArg>,
    /// Ordered dithering when the colour depth is 256 or 16 colours.
    #[arg(long)]
    pub dither: bool,
    /// 24-bit colours within N levels (of 255) of the colour the terminal already
    /// has are drawn with it, which saves bytes on slow links; 0 means exact.
    #[arg(long, value_name = "N", default_value_t = 2, value_parser = clap::value_parser!(u8).range(0..=32))]
    pub color_tolerance: u8,
    /// What the picture is sent as: text symbols (--symbols), or pixels through the kitty
    /// graphics protocol, sixel or iTerm2 inline images; `U` cycles them. Default (auto): what
    /// the terminal is found to speak (kitty > iterm > sixels > symbols), or the environment
    /// variable RELIEF_FORMAT. Inside tmux, pixels need `allow-passthrough` on.
    #[arg(long, value_enum)]
    pub format: Option<Format>,
    /// Glyphs of the picture: half blocks (1×2 pixels a cell, every font), quadrants (2×2),
    /// sextants (2×3, Unicode 13) or octants (2×4, Unicode 16); `u` cycles them.
    #[arg(long, value_enum, default_value_t = Symbols::Half)]
    pub symbols: Symbols,
    /// The link to the terminal in bits/s (1M, 50M, 500k), or auto. A stated rate spaces the
    /// frames so the link carries them and sends previews while input keeps coming when the
    /// exact picture takes it longer than a frame. auto measures: by the terminal's replies,
    /// and inside tmux or GNU screen over SSH by the SSH connection's send queue
    /// (docs/ssh-tmux.md).
    #[arg(long, value_name = "RATE", default_value = "auto", value_parser = relief_term::hold::parse_link)]
    pub link: relief_term::hold::LinkRate,
    /// Print a line of every glyph of each symbol set and exit: a set whose line shows
    /// boxes, gaps or a ragged right bar is missing from the font.
    #[arg(long)]
    pub symbols_test: bool,
    /// Texture images to put in the texture list; the first one is applied.
    /// A model file (.obj, .stl, .ply, .gltf, .glb) among them opens as the model.
    #[arg(value_name = "IMAGE|MODEL")]
    pub images: Vec<PathBuf>,
}

/// Moves the model files among positional `files` (known by their
/// extension) to `model`: the first one is opened; a note says when there
/// were more. Images stay in `files`.
pub fn models_from_positional(files: &mut Vec<PathBuf>, model: &mut ModelChoice) -> Vec<String> {
    let (models, images): (Vec<PathBuf>, Vec<PathBuf>) = std::mem::take(files)
        .into_iter()
        .partition(|p| relief_scene::model_file::is_model_path(p));
    *files = images;
    let mut notes = Vec::new();
    let mut models = models.into_iter();
    if let Some(first) = models.next() {
        let rest = models.count();
        if rest > 0 {
            notes.push(format!(
                "{} opened as the model; {rest} other model file(s) ignored",
                relief_core::sanitize::display_path(&first)
            ));
        }
        *model = ModelChoice::File(first);
    }
    notes
}

// Parsed once at start: boxing the render flags would save nothing.
#[allow(clippy::large_enum_variant)]
#[derive(Subcommand, Debug)]
pub enum Command {
    /// Render one frame headless and write it as a PNG (or as terminal text with --ansi).
    Render(RenderArgs),
    /// Write the built-in textures as PNGs into DIR (how `assets/` is made).
    #[command(hide = true)]
    Assets {
        #[arg(value_name = "DIR")]
        dir: PathBuf,
    },
    /// Measure what each quality setting costs in time and accuracy (`relief bench --quick` for a smoke run).
    Bench(relief_bench::BenchArgs),
}

#[derive(Args, Debug)]
pub struct RenderArgs {
    /// Output picture, in the format its extension names (.png, .jpg, .bmp, .tga, .tif,
    /// .ppm, .qoi, .ff; PNG without one); written to a temporary file and renamed.
    /// `-` writes the picture to standard output; a symbolic link is written
    /// through (the file it names is replaced); a read-only file is refused.
    #[arg(long, value_name = "FILE.png", required_unless_present = "ansi")]
    pub out: Option<PathBuf>,
    /// Print the frame to stdout as text (in the symbols --symbols names and the depth
    /// --color names, rows ending in LF) instead of writing a picture.
    #[arg(long, conflicts_with = "out")]
    pub ansi: bool,
    /// Glyphs of the text (--ansi) or of the picture a terminal shows (--out with --color):
    /// half, quad, sextant or octant.
    #[arg(long, value_enum, default_value_t = Symbols::Half)]
    pub symbols: Symbols,
    /// What --ansi writes: text cells of --symbols (auto, symbols), or the frame's pixels as
    /// a kitty graphics image, a sixel image (--dither: ordered dithering when the frame has
    /// more than 256 colours) or an iTerm2 inline PNG.
    #[arg(long, value_enum, default_value_t = Format::Auto)]
    pub format: Format,
    /// Colour depth of the PNG or the text: the picture a terminal with that depth shows.
    #[arg(long, value_enum, default_value_t = ColorDepthArg::Truecolor)]
    pub color: ColorDepthArg,
    /// Ordered dithering in 256 and 16 colours (where it lowers the error).
    #[arg(long)]
    pub dither: bool,
    /// The frame that fills COLSxROWS terminal cells (a file manager's preview area), in place
    /// of --width and --height: its pixels are the cells' (half: 1×2 a cell, quad 2×2, sextant
    /// 2×3, octant 2×4), so the text has exactly ROWS lines of COLS cells; with a pixel --format,
    /// the terminal's cell size in pixels (8×16 when it cannot be asked), kitty and iTerm2
    /// images placed to fill the cells.
    #[arg(long, value_name = "COLSxROWS", value_parser = parse_cells, conflicts_with_all = ["width", "height"])]
    pub cells: Option<Cells>,
    /// Width in pixels.
    #[arg(long, default_value_t = 320, value_parser = clap::value_parser!(u32).range(1..=16384))]
    pub width: u32,
    /// Height in pixels.
    #[arg(long, default_value_t = 240, value_parser = clap::value_parser!(u32).range(1..=16384))]
    pub height: u32,
    #[command(flatten)]
    pub view: ViewArgs,
    /// An animated model (glTF) at this many seconds into its clip (a clip loops).
    #[arg(long, value_name = "SECONDS", value_parser = parse_seconds)]
    pub time: Option<f32>,
    /// Which of an animated model's clips: its index in the file's animations, from 0.
    #[arg(long, value_name = "N")]
    pub clip: Option<usize>,
    /// See a glTF model through its own camera N (from 0, in the order the
    /// scene's nodes are met), the model as the file places it.
    #[arg(long, value_name = "N")]
    pub camera: Option<usize>,
    /// Plasma scene: the light's position in pixels, (0,0) top left (default: the centre).
    #[arg(long, value_name = "X,Y", value_parser = parse_point, allow_hyphen_values = true)]
    pub light: Option<Vec2>,
    /// Texture image (RGB = colour, alpha = height; without alpha, the mean of R, G, B),
    /// or a model file (.obj, .stl, .ply, .gltf, .glb) to draw as the model. `-` reads
    /// either from standard input, its format found by its bytes (an OBJ's material
    /// libraries and a glTF's other files are not read: there is no folder).
    #[arg(value_name = "IMAGE|MODEL")]
    pub image: Option<PathBuf>,
}

/// `--cells COLSxROWS`: a terminal area in cells.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Cells {
    pub cols: u16,
    pub rows: u16,
}

/// Largest `--cells` side: the frame stays within 16384 pixels a side for
/// every symbol set (octants are 4 pixels tall).
pub const MAX_CELLS: u16 = 4096;

/// `--time`: a finite number of seconds, not negative.
pub fn parse_seconds(text: &str) -> Result<f32, String> {
    match text.trim().parse::<f32>() {
        Ok(s) if s.is_finite() && s >= 0.0 => Ok(s),
        _ => Err(format!(
            "expected a number of seconds, 0 or more, got '{text}'"
        )),
    }
}

/// `COLSxROWS` (`80x24`), each from 1 to [`MAX_CELLS`].
pub fn parse_cells(text: &str) -> Result<Cells, String> {
    let bad = || format!("expected COLSxROWS in cells, such as 80x24, got '{text}'");
    let (cols, rows) = text.trim().split_once(['x', 'X']).ok_or_else(bad)?;
    let side = |t: &str| match t.trim().parse::<u16>() {
        Ok(n) if (1..=MAX_CELLS).contains(&n) => Ok(n),
        Ok(_) => Err(format!(
            "cells must be from 1 to {MAX_CELLS} a side, got '{text}'"
        )),
        Err(_) => Err(bad()),
    };
    Ok(Cells {
        cols: side(cols)?,
        rows: side(rows)?,
    })
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ColorDepthArg {
    Truecolor,
    #[value(name = "256")]
    Palette256,
    #[value(name = "16")]
    Palette16,
}

/// What a frame shows: shared by the interactive view and `relief render`.
/// The options of the table ([`relief_options::OPTIONS`]) come first;
/// the fields here are the ones the table does not hold (files, the
/// scene, the rotation, the camera).
#[derive(Args, Debug, Clone)]
pub struct ViewArgs {
    #[command(flatten)]
    pub options: OptionArgs,
    /// Model rotation in degrees about X, then Y, then Z (default 25,35,0; a model file's
    /// start view 0,-35,0, seen from 20° above: docs/models.md).
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_rotation, allow_hyphen_values = true)]
    pub rotate: Option<Vec3>,
    /// Map the texture on all six faces of the cube (default: front and back).
    #[arg(long)]
    pub all_faces: bool,
    /// Separate height (bump) map for the texture: its alpha, or the mean of its RGB.
    #[arg(long, value_name = "PATH")]
    pub height_map: Option<PathBuf>,
    /// Scene: one model (`cube`, see --model), the cube over a floor with its shadow, or the 2D plasma.
    #[arg(long, value_enum, default_value_t = SceneKind::Cube)]
    pub scene: SceneKind,
    /// Model of the cube scene: a built-in shape or a model file (OBJ with its MTL, STL, PLY,
    /// glTF 2.0; docs/models.md).
    #[arg(
        long,
        value_name = "triangle|plane|cube|sphere|FILE",
        default_value = "cube"
    )]
    pub model: ModelChoice,
    /// Grey image whose value (mean of R, G, B) scales the highlight, read with the texture coordinates.
    #[arg(long, value_name = "PATH")]
    pub specular_map: Option<PathBuf>,
    /// RGB tangent-space normal map (n = 2·rgb − 1, green up the picture) that dot3 reads instead of the one derived from the height map (docs/bump-dot3.md).
    #[arg(long, value_name = "PATH")]
    pub normal_map: Option<PathBuf>,
    /// Equirectangular (latitude-longitude) picture of the environment: 360° across, 180° down.
    #[arg(long, value_name = "PATH")]
    pub environment_map: Option<PathBuf>,
    /// Plasma scene: the article's Z² lookup table or the exact per-pixel normal.
    #[arg(long, value_enum, default_value_t = PlasmaNormal::Table)]
    pub plasma_normal: PlasmaNormal,
    /// Camera distance (zoom), 5 being the reference view; from 2.5 (closest: never inside the model) to 40.
    #[arg(long, value_name = "D", default_value_t = relief_scene::camera::REFERENCE_DISTANCE, value_parser = parse_distance)]
    pub distance: f32,
}

impl ViewArgs {
    /// The settings these flags describe.
    pub fn settings(&self) -> Settings {
        let mut s = self.options.settings;
        // A model file starts in the model view's three-quarter turn.
        let model_file =
            matches!(self.model, ModelChoice::File(_)) && self.scene == SceneKind::Cube;
        s.rotation = self.rotate.unwrap_or(if model_file {
            relief_scene::model_view::START_ROTATION
        } else {
            relief_core::settings::DEFAULT_ROTATION
        });
        s.normal_map_file = self.normal_map.is_some();
        // The environment is on by itself when a map is given.
        if !self.options.given(relief_options::OptId::Environment) {
            s.environment = self.environment_map.is_some();
        }
        s
    }
}

/// `X,Y,Z` in degrees, each a finite number.
pub fn parse_rotation(text: &str) -> Result<Vec3, String> {
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    if parts.len() != 3 {
        return Err(format!(
            "expected three angles X,Y,Z in degrees, got '{text}'"
        ));
    }
    let mut v = [0.0f32; 3];
    for (slot, part) in v.iter_mut().zip(&parts) {
        *slot = parse_finite(part)?;
    }
    Ok(Vec3::from_array(v))
}

/// `X,Y`, two finite numbers (a position in pixels).
pub fn parse_point(text: &str) -> Result<Vec2, String> {
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    if parts.len() != 2 {
        return Err(format!("expected a position X,Y in pixels, got '{text}'"));
    }
    Ok(Vec2::new(parse_finite(parts[0])?, parse_finite(parts[1])?))
}

fn parse_distance(text: &str) -> Result<f32, String> {
    use relief_scene::camera::{MAX_DISTANCE, MIN_DISTANCE};
    let d = parse_finite(text)?;
    if !(MIN_DISTANCE..=MAX_DISTANCE).contains(&d) {
        return Err(format!(
            "distance must be from {MIN_DISTANCE} to {MAX_DISTANCE}, got {d}"
        ));
    }
    Ok(d)
}

#[cfg(test)]
mod tests {
    use super::*;
    use relief_core::settings::{AntiAlias, Display, LightVector, Technique};

    #[test]
    fn rotation_parses_and_refuses_garbage() {
        assert_eq!(parse_rotation("25,35,0"), Ok(Vec3::new(25.0, 35.0, 0.0)));
        assert_eq!(
            parse_rotation(" 1, -2.5 ,1e3"),
            Ok(Vec3::new(1.0, -2.5, 1000.0))
        );
        assert!(parse_rotation("1,2").is_err());
        assert!(parse_rotation("1,NaN,2").is_err());
        assert!(parse_rotation("1,inf,2").is_err());
        assert!(parse_rotation("a,b,c").is_err());
    }

    #[test]
    fn defaults_are_the_reference_settings() {
        let cli = Cli::try_parse_from(["relief", "render", "--out", "x.png"]).unwrap();
        let Some(Command::Render(args)) = cli.command else {
            panic!("render expected")
        };
        assert_eq!(args.view.settings(), Settings::default());
        assert_eq!((args.width, args.height), (320, 240));
    }

    #[test]
    fn technique_aa_and_display_flags_reach_the_settings() {
        let cli = Cli::try_parse_from([
            "relief",
            "render",
            "--out",
            "x.png",
            "--technique",
            "dot3",
            "--light-vector",
            "vertex",
            "--aa",
            "4x4",
            "--display",
            "lines",
        ])
        .unwrap();
        let Some(Command::Render(args)) = cli.command else {
            panic!("render expected")
        };
        let s = args.view.settings();
        assert_eq!(s.technique, Technique::Dot3);
        assert_eq!(s.light_vector, LightVector::Vertex);
        assert_eq!(s.aa, AntiAlias::Ssaa4);
        assert_eq!(s.display, Display::Lines);
        for (flag, value) in [
            ("--technique", "pom"),
            ("--technique", "emboss"),
            ("--technique", "parallax"),
            ("--technique", "blinn"),
            ("--aa", "2x2"),
            ("--aa", "msaa4"),
            ("--aa", "off"),
            ("--display", "points"),
            ("--display", "fill"),
            ("--light-vector", "pixel"),
        ] {
            assert!(
                Cli::try_parse_from(["relief", "render", "--out", "x.png", flag, value]).is_ok(),
                "{flag} {value}"
            );
        }
        assert!(Cli::try_parse_from(["relief", "--technique", "phong"]).is_err());
        assert!(Cli::try_parse_from(["relief", "--aa", "3x3"]).is_err());
    }

    #[test]
    fn scene_model_and_light_flags_parse() {
        let cli = Cli::try_parse_from([
            "relief",
            "render",
            "--out",
            "x.png",
            "--scene",
            "plasma",
            "--light",
            "-3,40.5",
            "--model",
            "Sphere",
            "--lights",
            "off",
            "--attenuation",
            "on",
            "--plasma-normal",
            "exact",
        ])
        .unwrap();
        let Some(Command::Render(args)) = cli.command else {
            panic!("render expected")
        };
        assert_eq!(args.view.scene, SceneKind::Plasma);
        assert_eq!(args.view.model, ModelChoice::Sphere);
        assert_eq!(args.light, Some(Vec2::new(-3.0, 40.5)));
        assert_eq!(args.view.plasma_normal, PlasmaNormal::Exact);
        let settings = args.view.settings();
        assert!(!settings.lights && settings.attenuation);
        let cli = Cli::try_parse_from(["relief", "--model", "monkey.OBJ"]).unwrap();
        assert_eq!(cli.view.model, ModelChoice::File("monkey.OBJ".into()));
        for file in ["part.STL", "scan.ply", "a.glb", "b.gltf"] {
            let cli = Cli::try_parse_from(["relief", "--model", file]).unwrap();
            assert_eq!(cli.view.model, ModelChoice::File(file.into()));
        }
        // A positional model file is the model; images stay textures.
        let mut cli = Cli::try_parse_from(["relief", "a.png", "scan.ply", "b.obj"]).unwrap();
        let notes = models_from_positional(&mut cli.images, &mut cli.view.model);
        assert_eq!(cli.images, vec![PathBuf::from("a.png")]);
        assert_eq!(cli.view.model, ModelChoice::File("scan.ply".into()));
        assert_eq!(notes.len(), 1);
        assert!(Cli::try_parse_from(["relief", "--model", "teapot"]).is_err());
        assert!(Cli::try_parse_from(["relief", "--scene", "shadows"]).is_err());
        assert!(parse_point("1,NaN").is_err());
        assert!(parse_point("1").is_err());
        assert!(parse_point("1,2,3").is_err());
    }

    #[test]
    fn cells_parse_as_cols_x_rows() {
        assert_eq!(parse_cells("80x24"), Ok(Cells { cols: 80, rows: 24 }));
        assert_eq!(parse_cells(" 1X1 "), Ok(Cells { cols: 1, rows: 1 }));
        for bad in [
            "80", "80x", "x24", "0x24", "80x0", "-1x5", "4097x2", "a x b", "80x24x2",
        ] {
            assert!(parse_cells(bad).is_err(), "{bad}");
        }
        assert!(
            Cli::try_parse_from([
                "relief", "render", "--ansi", "--cells", "8x4", "--width", "9"
            ])
            .is_err(),
            "--cells replaces --width"
        );
    }

    #[test]
    fn zero_size_is_refused() {
        assert!(
            Cli::try_parse_from(["relief", "render", "--out", "x.png", "--width", "0"]).is_err()
        );
    }
}
