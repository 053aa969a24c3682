//! The status line: every mode and the last frame's cost, in the longest
//! form that fits the screen's width.

use crate::app::state::{LIGHT_NAMES, State, plasma_light};
use crate::plasma::PlasmaNormal;
use crate::scene::SceneKind;
use crate::scene::camera::REFERENCE_DISTANCE;
use crate::settings::{AntiAlias, Filter, LightVector, Settings, Shading, Technique};

/// The status line: the longest form that fits in `width` columns. The
/// shorter forms leave the frame cost to the line above; the shortest keeps
/// the modes and colour depth.
pub fn status_line(state: &State, width: usize) -> String {
    status_choice(state, width).0
}

/// The status text and its detail (`None`: the abbreviated form).
pub(super) fn status_choice(state: &State, width: usize) -> (String, Option<Detail>) {
    [
        Detail::Full,
        Detail::NoHint,
        Detail::NoStrength,
        Detail::Short,
        Detail::Modes,
    ]
    .into_iter()
    .map(|d| (status_text(state, d), Some(d)))
    .find(|(t, _)| t.chars().count() <= width)
    .unwrap_or_else(|| (status_modes(state), None))
}

/// How much the status line says.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Detail {
    /// Everything, with the bump strength and a pointer to `?`.
    Full,
    /// Without the `? help` hint.
    NoHint,
    /// Without the hint and the bump strength.
    NoStrength,
    /// Short words.
    Short,
    /// Short words without the frame cost (it moves to the line above).
    Modes,
}

impl Detail {
    /// Whether this form carries the frame cost.
    pub fn has_cost(self) -> bool {
        self != Detail::Modes
    }
}

/// Frame time, frames per second and bytes of the last frame; a preview
/// says "preview" in place of its time. Every figure has a fixed width,
/// so the status line keeps its layout whatever the figures: the form
/// that fits is chosen by the screen width, never by a digit more.
pub fn cost_text(state: &State, compact: bool) -> String {
    let f = &state.frame;
    let ms = f.frame_time.as_secs_f64() * 1e3;
    let ms = if ms < 99.95 {
        format!("{ms:.1}")
    } else {
        format!("{ms:.0}")
    };
    // No rate while idle (or for a lone frame).
    let fps = f.fps.map_or_else(|| "—".to_string(), |r| format!("{r:.0}"));
    if compact {
        let time = if f.preview {
            "preview".to_string()
        } else {
            format!("{ms:>5}ms")
        };
        let bytes = format_bytes(f.bytes).replace(' ', "");
        format!("{time} {fps:>3}fps {bytes:>6}")
    } else {
        let time = if f.preview {
            "preview".to_string()
        } else {
            format!("{ms:>4} ms")
        };
        format!("{time} │ {fps:>3} fps │ {:>7}", format_bytes(f.bytes))
    }
}

/// What is shown: the model, the shadow scene or the plasma.
fn scene_label(state: &State, short: bool) -> String {
    match state.scene {
        SceneKind::Cube if short => state.model.label(),
        SceneKind::Cube => format!("model {}", state.model.label()),
        SceneKind::Shadow => "shadow".into(),
        SceneKind::Plasma => "plasma".into(),
    }
}

/// The lights: all on, all off, or which are off (`l`, `1`–`4`).
fn lights_text(state: &State, short: bool) -> String {
    if !state.settings.lights {
        return "lights off".into();
    }
    if state.light_on.iter().all(|&on| on) {
        return "lights on".into();
    }
    if short {
        let keys: String = (0..LIGHT_NAMES.len())
            .map(|i| {
                if state.light_on[i] {
                    char::from(b'1' + i as u8)
                } else {
                    '·'
                }
            })
            .collect();
        return format!("lights {keys}");
    }
    let off: Vec<&str> = LIGHT_NAMES
        .iter()
        .zip(state.light_on)
        .filter(|(_, on)| !on)
        .map(|(name, _)| *name)
        .collect();
    format!("lights on ({} off)", off.join(", "))
}

/// Dot3 reads the `--normal-map` file's normal map (key `N`).
fn file_map_in_use(state: &State) -> bool {
    let s = &state.settings;
    s.technique == Technique::Dot3 && s.normal_map_file && state.normal_map_file.is_some()
}

/// The bump technique, with dot3's light vector and, when it reads one,
/// the normal map file.
fn technique_text(state: &State) -> String {
    let s = &state.settings;
    if file_map_in_use(state) {
        format!("dot3 ({}, map file)", s.light_vector.label())
    } else if s.technique == Technique::Dot3 {
        format!("dot3 ({})", s.light_vector.label())
    } else {
        s.technique.label().into()
    }
}

/// The plasma's own line: its normal mode and where the light is.
fn plasma_text(state: &State, detail: Detail) -> String {
    let light = match state.pointer {
        Some(_) => {
            let (x, y) = plasma_light(state.pointer, 0, 0);
            format!("light {x:.0},{y:.0}")
        }
        None => "light centre".into(),
    };
    let cost = if detail.has_cost() {
        format!(" │ {}", cost_text(state, false))
    } else {
        String::new()
    };
    let hint = if detail == Detail::Full {
        " │ ? help"
    } else {
        ""
    };
    format!(
        "plasma │ {} │ {light} │ {}{cost}{hint}",
        state.plasma_normal.label(),
        state.depth.label(),
    )
}

/// The abbreviated status line: the 3D modes, the scene, the modes that
/// differ from their defaults, and the colour depth.
pub fn status_modes(state: &State) -> String {
    if state.scene == SceneKind::Plasma {
        let normal = match state.plasma_normal {
            PlasmaNormal::Table => "Z²",
            PlasmaNormal::Exact => "exact",
        };
        return format!("plasma {normal} {}", short_depth(state));
    }
    let s = &state.settings;
    let d = Settings::default();
    let flag = |b: bool| if b { '+' } else { '-' };
    let mut extras = String::new();
    let mut add = |t: &str| {
        extras.push(' ');
        extras.push_str(t);
    };
    if s.technique != d.technique {
        add(s.technique.label());
    }
    if s.technique == Technique::Dot3 && s.light_vector == LightVector::Vertex {
        add("Lv");
    }
    if file_map_in_use(state) {
        add("Nfile");
    }
    if s.filter != d.filter {
        add(match s.filter {
            Filter::Nearest => "near",
            Filter::Bilinear => "bil",
            Filter::NearestMip => "nmip",
            Filter::Trilinear => "tri",
            Filter::Anisotropic => "aniso",
        });
    }
    if s.height_derivative != d.height_derivative {
        add(&format!("dH {}", s.height_derivative.label()));
    }
    if s.aa != d.aa {
        add(match s.aa {
            AntiAlias::Off => "AA-",
            AntiAlias::Ssaa2 => "2x2",
            AntiAlias::Ssaa4 => "4x4",
            AntiAlias::Msaa4 => "MS4",
        });
    }
    if s.display != d.display {
        add(s.display.label());
    }
    if s.tangent_frames {
        add("TBN");
    }
    if !s.lights {
        add("L-");
    } else if !state.light_on.iter().all(|&on| on) {
        add(&lights_text(state, true).replace("lights ", "L"));
    }
    if s.attenuation {
        add("att");
    }
    if s.specular {
        add(&format!("spec{}", format_shininess(s.shininess)));
    }
    if environment_shows(s) {
        add("env");
    }
    if state.distance != REFERENCE_DISTANCE {
        add(&format!("d{}", format_distance(state.distance)));
    }
    if let Some(h) = heights_text(state, true) {
        add(&h);
    }
    let what: String = scene_label(state, true).chars().take(12).collect();
    // What the status line must always show comes first (the colour depth
    // included, and auto-rotation); the scene and the changed modes follow
    // and are what a narrow screen cuts.
    format!(
        "{} {} T{} C{} B{}{} {}{} {what}{extras}",
        s.shading.label(),
        if s.normals == crate::settings::Normals::Vertex {
            "V"
        } else {
            "F"
        },
        flag(s.texture),
        flag(s.colors),
        flag(s.bump),
        if s.bump && s.shading != Shading::Phong {
            " (Phong only)"
        } else {
            ""
        },
        short_depth(state),
        if state.auto_rotate { " auto" } else { "" },
    )
}

fn on_off(b: bool) -> &'static str {
    if b { "on" } else { "off" }
}

/// Every mode and (unless `Modes`) the last frame's cost.
pub fn status_text(state: &State, detail: Detail) -> String {
    if state.scene == SceneKind::Plasma {
        return plasma_text(state, detail);
    }
    let s = &state.settings;
    let phong_only = s.bump && s.shading != Shading::Phong;
    let strength = match detail {
        Detail::Full | Detail::NoHint => format!(" k={}", format_strength(s.bump_strength)),
        _ => String::new(),
    };
    let hint = if detail == Detail::Full {
        " │ ? help"
    } else {
        ""
    };
    let cost = if detail.has_cost() {
        format!(" │ {}", cost_text(state, false))
    } else {
        String::new()
    };
    let auto = if state.auto_rotate { " │ auto" } else { "" };
    let po = if phong_only { " (Phong only)" } else { "" };
    // Short words in the short forms, whole words otherwise.
    let short = matches!(detail, Detail::Short | Detail::Modes);
    let named = |long: &str, brief: &str, value: &str| {
        format!("{} {value}", if short { brief } else { long })
    };
    let fields = [
        s.shading.label().to_string(),
        if short {
            s.normals.label().to_string()
        } else {
            format!("normals {}", s.normals.label())
        },
        named("texture", "tex", on_off(s.texture)),
        named("colours", "col", on_off(s.colors)),
        format!("bump {}{po}{strength}", on_off(s.bump)),
        technique_text(state),
        s.filter.label().to_string(),
        format!("dH {}", s.height_derivative.label()),
        format!("AA {}", s.aa.label()),
        s.display.label().to_string(),
        scene_label(state, short),
        lights_text(state, short),
        named("attenuation", "att", on_off(s.attenuation)),
        depth_label(state),
    ];
    // The zoom shows once it leaves the reference view.
    let zoom = if state.distance != REFERENCE_DISTANCE {
        format!(
            " │ {}",
            named("distance", "dist", &format_distance(state.distance))
        )
    } else {
        String::new()
    };
    // Highlights show only when on: the reference picture has none.
    let specular = if s.specular {
        format!(
            " │ {} s={}",
            if short { "spec" } else { "specular" },
            format_shininess(s.shininess)
        )
    } else {
        String::new()
    };
    // The tangent frames show only when drawn.
    let frames = if s.tangent_frames {
        format!(" │ {}", if short { "TBN" } else { "tangent frames" })
    } else {
        String::new()
    };
    let heights = heights_text(state, short).map_or(String::new(), |h| format!(" │ {h}"));
    let environment = if environment_shows(s) {
        format!(
            " │ {} k={}",
            if short { "env" } else { "environment" },
            format_shininess(s.reflectivity)
        )
    } else {
        String::new()
    };
    format!(
        "{}{heights}{specular}{environment}{frames}{zoom}{cost}{auto}{hint}",
        fields.join(" │ ")
    )
}

/// Where the heights come from, when another texture of the list gives
/// them (texture panel, `H`): its name, cut to a few words.
fn heights_text(state: &State, short: bool) -> Option<String> {
    let label = state.textures.listing.heights_label()?;
    let label = label.strip_suffix(" (built-in)").unwrap_or(label);
    let max = if short { 12 } else { 24 };
    let n = label.chars().count();
    let cut: String = if n > max {
        let tail: String = label.chars().skip(n - (max - 1)).collect();
        format!("…{tail}")
    } else {
        label.to_string()
    };
    Some(if short {
        format!("H:{cut}")
    } else {
        format!("heights {cut}")
    })
}

/// Whether the environment's reflection is in the picture: asked for, in
/// Phong and fill display, with the Blinn kernel (docs/environment.md).
fn environment_shows(s: &Settings) -> bool {
    s.environment
        && s.shading == Shading::Phong
        && s.display == crate::settings::Display::Fill
        && s.reflectivity > 0.0
}

/// The specular exponent without needless decimals.
fn format_shininess(s: f32) -> String {
    format!("{}", (s * 100.0).round() / 100.0)
}

/// The colour depth, and the symbol set when it is not half blocks.
fn depth_label(state: &State) -> String {
    match state.symbols {
        crate::term::Symbols::Half => state.depth.label().to_string(),
        s => format!("{} {}", state.depth.label(), s.name()),
    }
}

fn short_depth(state: &State) -> String {
    let depth = match state.depth {
        crate::term::ColorDepth::Truecolor => "24b",
        crate::term::ColorDepth::Palette256 => "256c",
        crate::term::ColorDepth::Palette16 => "16c",
    };
    match state.symbols {
        crate::term::Symbols::Half => depth.to_string(),
        s => format!("{depth} {}", s.name()),
    }
}

/// The camera distance with one decimal.
fn format_distance(d: f32) -> String {
    format!("{d:.1}")
}

fn format_strength(k: f32) -> String {
    let s = format!("{k:.4}");
    let s = s.trim_end_matches('0');
    s.strip_suffix('.').unwrap_or(s).to_string()
}

/// Bytes as the status line shows them: three significant digits, at
/// most 7 characters below 1 GB.
pub fn format_bytes(n: u64) -> String {
    let three = |v: f64, unit: &str| {
        if v < 9.995 {
            format!("{v:.2} {unit}")
        } else if v < 99.95 {
            format!("{v:.1} {unit}")
        } else {
            format!("{v:.0} {unit}")
        }
    };
    if n < 1000 {
        format!("{n} B")
    } else if n < 999_500 {
        three(n as f64 / 1e3, "kB")
    } else {
        three(n as f64 / 1e6, "MB")
    }
}
