//! What the screen shows: the picture, the orientation fields, the status
//! line and the help overlay. Drawing only: every decision is in `State`.

use ratatui::Frame;
use ratatui::buffer::Buffer;
use ratatui::layout::Rect;
use ratatui::style::{Modifier, Style};
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Clear, Paragraph, Widget};

use super::state::{AXES, State};
use crate::framebuffer::{Framebuffer, Rgb};
use crate::settings::Shading;
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
    ("paste", "a pasted (dragged) file joins the texture list"),
    (
        "k",
        "cost panel: time per stage, frame times, active stages",
    ),
    ("?", "this help (Esc closes it)"),
    ("q Esc Ctrl-C", "quit"),
];

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
    let status_text = status_line(state, screen.width as usize);
    // A compact status line leaves the frame cost to the line above.
    let compact = status_text == status_modes(state);
    if let Some(panel) = a.panel {
        panel_line(state, compact).render(panel, buf);
    } else if let (Some(status), Some(_)) = (a.status, state.panel.focus) {
        // No room for both: while editing, the fields take the status line.
        panel_line(state, true).render(status, buf);
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
    let height = 16.min(viewport.height);
    let area = Rect::new(
        viewport.x + viewport.width - width,
        viewport.y,
        width,
        height,
    );
    Clear.render(area, buf);
    super::cost::CostPanel {
        history: &state.costs,
    }
    .render(area, buf);
}

/// The orientation fields, then (on narrow screens) the frame cost, then the message.
fn panel_line(state: &State, compact: bool) -> Line<'static> {
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
    } else if compact {
        spans.push(Span::raw(format!(" {}", cost_text(state, true))));
    }
    if let Some(msg) = &state.message {
        spans.push(Span::raw(format!("  {msg}")));
    }
    Line::from(spans)
}

/// The status line: the longest form that fits in `width` columns. The
/// shortest form keeps the modes and colour depth; the frame cost then
/// moves to the orientation line.
pub fn status_line(state: &State, width: usize) -> String {
    [
        Detail::Full,
        Detail::NoHint,
        Detail::NoStrength,
        Detail::Short,
    ]
    .into_iter()
    .map(|d| status_text(state, d))
    .find(|t| t.chars().count() <= width)
    .unwrap_or_else(|| status_modes(state))
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
    /// Short words (fits 80 columns).
    Short,
}

/// Frame time, frames per second and bytes of the last frame.
pub fn cost_text(state: &State, compact: bool) -> String {
    let f = &state.frame;
    let ms = f.frame_time.as_secs_f64() * 1e3;
    if compact {
        format!(
            "{ms:.1}ms {:.0}fps {}",
            f.fps,
            format_bytes(f.bytes).replace(' ', "")
        )
    } else {
        format!("{ms:.1} ms │ {:.0} fps │ {}", f.fps, format_bytes(f.bytes))
    }
}

/// The abbreviated status line: every mode and the colour depth.
pub fn status_modes(state: &State) -> String {
    let s = &state.settings;
    let flag = |b: bool| if b { '+' } else { '-' };
    format!(
        "{} {} T{} C{} B{}{} {}{}",
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

/// Every mode and the last frame's cost.
pub fn status_text(state: &State, detail: Detail) -> String {
    let s = &state.settings;
    let phong_only = s.bump && s.shading != Shading::Phong;
    let strength = match detail {
        Detail::NoStrength | Detail::Short => String::new(),
        _ => format!(" k={}", format_strength(s.bump_strength)),
    };
    let hint = if detail == Detail::Full {
        " │ ? help"
    } else {
        ""
    };
    if detail == Detail::Short {
        return format!(
            "{} │ {} │ tex {} │ col {} │ bump {}{} │ {} │ {}{}",
            s.shading.label(),
            s.normals.label(),
            on_off(s.texture),
            on_off(s.colors),
            on_off(s.bump),
            if phong_only { " (Phong only)" } else { "" },
            state.depth.label(),
            cost_text(state, false),
            if state.auto_rotate { " │ auto" } else { "" },
        );
    }
    format!(
        "{} │ normals {} │ texture {} {} │ colours {} │ bump {}{}{} │ {} │ {}{}{}",
        s.shading.label(),
        s.normals.label(),
        on_off(s.texture),
        s.filter.label(),
        on_off(s.colors),
        on_off(s.bump),
        if phong_only { " (Phong only)" } else { "" },
        strength,
        state.depth.label(),
        cost_text(state, false),
        if state.auto_rotate { " │ auto" } else { "" },
        hint,
    )
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

/// Bytes as the status line shows them.
pub fn format_bytes(n: u64) -> String {
    if n < 1000 {
        format!("{n} B")
    } else if n < 1_000_000 {
        format!("{:.1} kB", n as f64 / 1e3)
    } else {
        format!("{:.2} MB", n as f64 / 1e6)
    }
}

/// The help overlay, centred, cut to the screen.
fn help(state: &State, screen: Rect, buf: &mut Buffer) {
    if !state.help {
        return;
    }
    let key_w = HELP
        .iter()
        .map(|(k, _)| k.chars().count())
        .max()
        .unwrap_or(0);
    let text_w = HELP
        .iter()
        .map(|(_, t)| t.chars().count())
        .max()
        .unwrap_or(0);
    let width = ((key_w + text_w + 6) as u16).min(screen.width);
    let height = ((HELP.len() + 2) as u16).min(screen.height);
    let area = Rect::new(
        screen.x + (screen.width - width) / 2,
        screen.y + (screen.height - height) / 2,
        width,
        height,
    );
    let lines: Vec<Line> = HELP
        .iter()
        .map(|(k, t)| {
            Line::from(vec![
                Span::styled(
                    format!("{k:>key_w$}"),
                    Style::new().add_modifier(Modifier::BOLD),
                ),
                Span::raw(format!("  {t}")),
            ])
        })
        .collect();
    Clear.render(area, buf);
    Paragraph::new(lines)
        .block(Block::bordered().title(" relief: keys and mouse "))
        .render(area, buf);
}
