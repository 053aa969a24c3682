//! What the screen shows: the picture, the orientation fields, the status
//! line and the help overlay. Drawing only: every decision is in `State`.

use ratatui::Frame;
use ratatui::buffer::Buffer;
use ratatui::layout::Rect;
use ratatui::style::{Modifier, Style};
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Clear, Paragraph, Widget};

use super::state::{AXES, LIGHT_NAMES, State, plasma_light};
use crate::framebuffer::{Framebuffer, Rgb};
use crate::plasma::PlasmaNormal;
use crate::scene::SceneKind;
use crate::settings::{AntiAlias, Filter, LightVector, Settings, Shading, Technique};
use crate::term::HalfBlocks;

/// Every key and mouse action, as `?` lists them.
pub const HELP: &[(&str, &str)] = &[
    ("m", "lighting: flat → Gouraud → Phong"),
    ("n", "normals: vertex / face"),
    ("t", "texture on / off"),
    ("c", "colours on / off"),
    ("b", "bump on / off (shows in Phong only)"),
    ("+ -", "bump strength"),
    ("left drag", "rotate about X (up/down) and Y (left/right)"),
    ("right drag", "rotate about Z (left/right) and X (up/down)"),
    ("arrows", "rotate 5° about X (↑↓) or Y (←→)"),
    ("PgUp PgDn", "rotate 5° about Z"),
    ("Tab", "orientation fields X Y Z: type degrees,"),
    ("", "Tab next field, Enter applies, Esc cancels"),
    ("space", "auto-rotation on / off"),
    ("r", "reset the orientation"),
    ("s", "save the frame as a PNG"),
    (
        "f",
        "texture filter: nearest, bilinear, trilinear, anisotropic",
    ),
    ("x X", "next / previous texture of the list"),
    ("R", "re-read the current texture file"),
    ("/", "type a texture path (Enter loads, Esc cancels)"),
    ("paste", "a pasted (dragged) file joins the texture list"),
    (
        "k",
        "cost panel: time per stage, frame times, active stages",
    ),
    (
        "e",
        "bump technique: Blinn → emboss → dot3 → parallax → POM",
    ),
    ("v", "dot3 light vector: per pixel / per vertex"),
    ("h", "height derivative: filtered / per texel"),
    ("a", "anti-aliasing: off → SSAA 2x2 → SSAA 4x4 → MSAA 4"),
    ("d", "display: points → lines → fill"),
    ("l", "all lights on / off"),
    ("1 2 3 4", "white / red / green / blue light on / off"),
    ("L", "distance attenuation on / off"),
    ("o", "model: triangle → plane → cube → sphere → OBJ"),
    ("p", "scene: model → shadow → plasma"),
    ("z", "plasma: Z² table / exact normal"),
    ("pointer", "plasma: the light follows the mouse"),
    ("?", "this help (Esc closes it; ↑↓ PgUp PgDn scroll it)"),
    ("q Esc Ctrl-C", "quit"),
];

/// Screens narrower than this get the short orientation fields.
pub const COMPACT_BELOW: u16 = 80;

/// Where each part of the screen goes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Areas {
    /// The picture (may be empty).
    pub viewport: Rect,
    /// Orientation fields and messages.
    pub panel: Option<Rect>,
    pub status: Option<Rect>,
}

/// Splits the screen: picture on top, then the orientation line, then the
/// status line. Small terminals drop the orientation line (height 2) and
/// the status line too (height 1: the picture wins).
pub fn areas(screen: Rect) -> Areas {
    let row = |y: u16| Rect::new(screen.x, screen.y + y, screen.width, 1);
    match screen.height {
        0 | 1 => Areas {
            viewport: screen,
            panel: None,
            status: None,
        },
        2 => Areas {
            viewport: Rect {
                height: 1,
                ..screen
            },
            panel: None,
            status: Some(row(1)),
        },
        h => Areas {
            viewport: Rect {
                height: h - 2,
                ..screen
            },
            panel: Some(row(h - 2)),
            status: Some(row(h - 1)),
        },
    }
}

/// Framebuffer size for a viewport: a column is a pixel wide and a row two
/// pixels tall, so pixels are about square and the aspect is right.
pub fn framebuffer_size(viewport: Rect) -> (usize, usize) {
    (viewport.width as usize, viewport.height as usize * 2)
}

/// Draws the whole screen.
pub fn view(frame: &mut Frame, state: &State, fb: &Framebuffer, background: Rgb) {
    let screen = frame.area();
    let buf = frame.buffer_mut();
    draw(state, fb, background, screen, buf);
}

/// [`view`] on a bare buffer (the benchmark and tests use it directly).
pub fn draw(state: &State, fb: &Framebuffer, background: Rgb, screen: Rect, buf: &mut Buffer) {
    let a = areas(screen);
    HalfBlocks {
        fb,
        depth: state.depth,
        dither: state.dither,
        pad: background,
    }
    .render(a.viewport, buf);
    let (status_text, detail) = status_choice(state, screen.width as usize);
    // Narrow screens shorten the fields; a status line without the frame
    // cost leaves it to the line above.
    let compact = screen.width < COMPACT_BELOW;
    let cost_above = !detail.is_some_and(Detail::has_cost);
    if let Some(line) = prompt_line(state) {
        // The prompt takes the line above the status (or the status itself).
        if let Some(area) = a.panel.or(a.status) {
            Clear.render(area, buf);
            line.render(area, buf);
        }
        if a.panel.is_none() {
            return help(state, screen, buf);
        }
    } else if let Some(panel) = a.panel {
        let line = panel_line(state, compact, cost_above);
        let long = state
            .message
            .as_deref()
            .filter(|m| line.width() + 2 + m.chars().count() > panel.width as usize);
        match long {
            // Too long for the rest of the line: the whole message, wrapped,
            // on the rows just above it.
            Some(msg) => {
                line.render(panel, buf);
                message_above(msg, panel, a.viewport, buf);
            }
            None => with_message(line, state).render(panel, buf),
        }
    } else if let (Some(status), Some(_)) = (a.status, state.panel.focus) {
        // No room for both: while editing, the fields take the status line.
        panel_line(state, true, false).render(status, buf);
        return help(state, screen, buf);
    }
    if let Some(status) = a.status {
        Paragraph::new(status_text)
            .style(Style::new().add_modifier(Modifier::REVERSED))
            .render(status, buf);
    }
    cost_panel(state, a.viewport, buf);
    help(state, screen, buf);
}

/// The cost panel (key `k`) in the top-right corner of the picture.
fn cost_panel(state: &State, viewport: Rect, buf: &mut Buffer) {
    if !state.cost_panel {
        return;
    }
    let width = 44.min(viewport.width);
    let height = 18.min(viewport.height);
    let area = Rect::new(
        viewport.x + viewport.width - width,
        viewport.y,
        width,
        height,
    );
    Clear.render(area, buf);
    super::cost::CostPanel {
        history: &state.costs,
        link: &state.link,
    }
    .render(area, buf);
}

/// The texture path prompt (key `/`), its end kept in view when it is long.
fn prompt_line(state: &State) -> Option<Line<'static>> {
    let text = state.prompt.as_ref()?;
    let shown = crate::sanitize::clean(text);
    let tail: String = {
        let chars: Vec<char> = shown.chars().collect();
        chars[chars.len().saturating_sub(120)..].iter().collect()
    };
    Some(Line::from(vec![
        Span::styled(" texture path: ", Style::new().add_modifier(Modifier::BOLD)),
        Span::styled(
            format!("{tail}_"),
            Style::new().add_modifier(Modifier::REVERSED),
        ),
        Span::raw("  Enter load · Esc cancel"),
    ]))
}

/// The orientation fields, then (on narrow screens) the frame cost, then the message.
fn panel_line(state: &State, compact: bool, cost: bool) -> Line<'static> {
    let mut spans = Vec::new();
    for (axis, name) in AXES.iter().enumerate() {
        let focused = state.panel.focus == Some(axis);
        let mut text = state.field_text(axis);
        if focused {
            text.push('_');
        }
        let style = if focused {
            Style::new().add_modifier(Modifier::REVERSED | Modifier::BOLD)
        } else {
            Style::new().add_modifier(Modifier::BOLD)
        };
        if compact {
            spans.push(Span::raw(if axis == 0 { "" } else { " " }));
            spans.push(Span::raw(*name));
            spans.push(Span::styled(format!("{text}°"), style));
        } else {
            spans.push(Span::raw(format!(" {name} ")));
            spans.push(Span::styled(format!("{text:>6}°"), style));
        }
    }
    if state.panel.focus.is_some() {
        spans.push(Span::raw(if compact {
            " Enter/Esc"
        } else {
            "  Enter apply · Esc cancel"
        }));
    } else if cost && compact {
        spans.push(Span::raw(format!(" {}", cost_text(state, true))));
    } else if cost {
        spans.push(Span::raw(format!("  {}", cost_text(state, false))));
    }
    Line::from(spans)
}

/// The panel line with the message after it.
fn with_message(mut line: Line<'static>, state: &State) -> Line<'static> {
    if let Some(msg) = &state.message {
        line.spans.push(Span::raw(format!("  {msg}")));
    }
    line
}

/// A message too long for the panel line, wrapped at the screen width on
/// the rows just above `panel` (over the bottom of the picture).
fn message_above(msg: &str, panel: Rect, viewport: Rect, buf: &mut Buffer) {
    let width = (panel.width as usize).saturating_sub(2).max(1);
    let lines = wrap_words(msg, width);
    let rows = (lines.len() as u16).min(viewport.height);
    if rows == 0 {
        return;
    }
    let area = Rect::new(panel.x, panel.y - rows, panel.width, rows);
    Clear.render(area, buf);
    Paragraph::new(
        lines[..rows as usize]
            .iter()
            .map(|l| Line::from(format!(" {l}")))
            .collect::<Vec<_>>(),
    )
    .render(area, buf);
}

/// The status line: the longest form that fits in `width` columns. The
/// shorter forms leave the frame cost to the line above; the shortest keeps
/// the modes and colour depth.
pub fn status_line(state: &State, width: usize) -> String {
    status_choice(state, width).0
}

/// The status text and its detail (`None`: the abbreviated form).
fn status_choice(state: &State, width: usize) -> (String, Option<Detail>) {
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

/// The bump technique, with dot3's light vector.
fn technique_text(s: &Settings) -> String {
    if s.technique == Technique::Dot3 {
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
    if s.filter != d.filter {
        add(match s.filter {
            Filter::Nearest => "near",
            Filter::Bilinear => "bil",
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
    if !s.lights {
        add("L-");
    } else if !state.light_on.iter().all(|&on| on) {
        add(&lights_text(state, true).replace("lights ", "L"));
    }
    if s.attenuation {
        add("att");
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
        technique_text(s),
        s.filter.label().to_string(),
        format!("dH {}", s.height_derivative.label()),
        format!("AA {}", s.aa.label()),
        s.display.label().to_string(),
        scene_label(state, short),
        lights_text(state, short),
        named("attenuation", "att", on_off(s.attenuation)),
        state.depth.label().to_string(),
    ];
    format!("{}{cost}{auto}{hint}", fields.join(" │ "))
}

fn short_depth(state: &State) -> &'static str {
    match state.depth {
        crate::term::ColorDepth::Truecolor => "24b",
        crate::term::ColorDepth::Palette256 => "256c",
        crate::term::ColorDepth::Palette16 => "16c",
    }
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

/// The help overlay, centred; in two columns when one does not fit the
/// height but two fit the width; on a narrow screen each text wraps under
/// itself; when it is still too tall it scrolls (`state.help_scroll`).
fn help(state: &State, screen: Rect, buf: &mut Buffer) {
    if !state.help {
        return;
    }
    let layout = help_layout(screen);
    let scroll = state.help_scroll.min(layout.max_scroll);
    let title = if layout.max_scroll > 0 {
        let shown = layout.area.height.saturating_sub(2) as usize;
        let last = (scroll as usize + shown).min(layout.lines.len());
        let span = format!("{}-{}/{}", scroll as usize + 1, last, layout.lines.len());
        let long = format!(" help, lines {span} · ↑↓ PgUp PgDn ");
        if long.chars().count() + 2 <= layout.area.width as usize {
            long
        } else {
            format!(" {span} ")
        }
    } else {
        " relief: keys and mouse ".to_string()
    };
    Clear.render(layout.area, buf);
    Paragraph::new(layout.lines)
        .scroll((scroll, 0))
        .block(Block::bordered().title(title))
        .render(layout.area, buf);
}

/// Where the help goes on `screen`, its lines, and how far it can scroll.
struct HelpLayout {
    area: Rect,
    lines: Vec<Line<'static>>,
    max_scroll: u16,
}

/// Widest key name and widest text of [`HELP`], in characters.
fn help_widths() -> (usize, usize) {
    let widest = |f: fn(&(&str, &str)) -> usize| HELP.iter().map(f).max().unwrap_or(0);
    (
        widest(|(k, _)| k.chars().count()),
        widest(|(_, t)| t.chars().count()),
    )
}

fn help_layout(screen: Rect) -> HelpLayout {
    let (key_w, text_w) = help_widths();
    let entry_w = key_w + 2 + text_w;
    let (sw, sh) = (screen.width as usize, screen.height as usize);
    let two = HELP.len() + 2 > sh && 2 * entry_w + 3 + 4 <= sw;
    let key = |k: &str| {
        Span::styled(
            format!("{k:>key_w$}"),
            Style::new().add_modifier(Modifier::BOLD),
        )
    };
    let (lines, inner_w): (Vec<Line<'static>>, usize) = if two {
        let rows = HELP.len().div_ceil(2);
        let entry = |(k, t): &(&str, &str)| vec![key(k), Span::raw(format!("  {t:<text_w$}"))];
        let lines = (0..rows)
            .map(|r| {
                let mut spans = entry(&HELP[r]);
                if let Some(right) = HELP.get(r + rows) {
                    spans.push(Span::raw("   "));
                    spans.extend(entry(right));
                }
                Line::from(spans)
            })
            .collect();
        (lines, 2 * entry_w + 3)
    } else if sw >= 4 + key_w + 2 + NARROW_HELP_TEXT {
        // The text beside its key, wrapped under itself.
        let room = (sw - 4 - key_w - 2).min(text_w);
        let mut lines = Vec::new();
        for (k, t) in HELP {
            for (i, piece) in wrap_words(t, room).into_iter().enumerate() {
                let first = if i == 0 { key(k) } else { key("") };
                lines.push(Line::from(vec![first, Span::raw(format!("  {piece}"))]));
            }
        }
        (lines, key_w + 2 + room)
    } else {
        // Too narrow for two columns: each key on its line, its text below.
        let room = sw.saturating_sub(4 + 2).max(1);
        let mut lines = Vec::new();
        for (k, t) in HELP {
            lines.push(Line::from(Span::styled(
                k.to_string(),
                Style::new().add_modifier(Modifier::BOLD),
            )));
            for piece in wrap_words(t, room) {
                lines.push(Line::from(format!("  {piece}")));
            }
        }
        (lines, room + 2)
    };
    let width = ((inner_w + 4) as u16).min(screen.width);
    let height = ((lines.len() + 2) as u16).min(screen.height);
    let shown = height.saturating_sub(2) as usize;
    let max_scroll = lines.len().saturating_sub(shown) as u16;
    let area = Rect::new(
        screen.x + (screen.width - width) / 2,
        screen.y + (screen.height - height) / 2,
        width,
        height,
    );
    HelpLayout {
        area,
        lines,
        max_scroll,
    }
}

/// Fewest characters of text worth showing beside the keys.
const NARROW_HELP_TEXT: usize = 16;

/// How far the help can scroll on a screen of this size (the loop clamps
/// `State::help_scroll` with it, so scrolling back responds at once).
pub fn help_max_scroll(width: u16, height: u16) -> u16 {
    help_layout(Rect::new(0, 0, width, height)).max_scroll
}

/// `text` cut into lines of at most `width` characters, at spaces where it
/// can be (a word longer than a line is cut).
fn wrap_words(text: &str, width: usize) -> Vec<String> {
    let width = width.max(1);
    let mut lines = Vec::new();
    let mut line = String::new();
    for word in text.split(' ') {
        let mut word: Vec<char> = word.chars().collect();
        loop {
            let used = line.chars().count();
            let gap = usize::from(used > 0);
            if used + gap + word.len() <= width {
                if gap == 1 {
                    line.push(' ');
                }
                line.extend(word.iter());
                break;
            }
            if used > 0 {
                lines.push(std::mem::take(&mut line));
                continue;
            }
            // A word longer than a whole line.
            let rest = word.split_off(width);
            lines.push(word.iter().collect());
            word = rest;
        }
    }
    if !line.is_empty() || lines.is_empty() {
        lines.push(line);
    }
    lines
}
