//! The line above the status: the orientation fields, the texture path
//! prompt, and the last message (wrapped over the picture when long).

use ratatui::buffer::Buffer;
use ratatui::layout::Rect;
use ratatui::style::{Modifier, Style};
use ratatui::text::{Line, Span};
use ratatui::widgets::{Clear, Paragraph, Widget};

use super::status::cost_text;
use super::wrap::wrap_words;
use crate::app::state::{AXES, State};

/// The texture path prompt (key `/`), the cursor kept in view when the
/// text is long.
pub(super) fn prompt_line(state: &State) -> Option<Line<'static>> {
    let text = state.prompt.as_ref()?;
    let at = crate::app::line_edit::clamp(text, state.prompt_cursor);
    let before: Vec<char> = relief_core::sanitize::clean(&text[..at]).chars().collect();
    let after: Vec<char> = relief_core::sanitize::clean(&text[at..]).chars().collect();
    // The cell under the cursor shows unreversed (a blank past the end).
    let (under, rest) = match after.split_first() {
        Some((c, rest)) => (c.to_string(), rest.iter().collect::<String>()),
        None => ("_".to_string(), String::new()),
    };
    let head: String = before[before.len().saturating_sub(120)..].iter().collect();
    let reversed = Style::new().add_modifier(Modifier::REVERSED);
    Some(Line::from(vec![
        Span::styled(" texture path: ", Style::new().add_modifier(Modifier::BOLD)),
        Span::styled(head, reversed),
        Span::styled(
            under,
            Style::new().add_modifier(Modifier::BOLD | Modifier::UNDERLINED),
        ),
        Span::styled(rest, reversed),
        // A message (what Tab found) in place of the reminder.
        Span::raw(match &state.message {
            Some(msg) => format!("  {msg}"),
            None => "  Enter load · Tab complete · Esc cancel".to_string(),
        }),
    ]))
}

/// The orientation fields, then (on narrow screens) the frame cost, then the message.
pub(super) fn panel_line(state: &State, compact: bool, cost: bool) -> Line<'static> {
    let mut spans = Vec::new();
    // The plasma has no orientation: no fields.
    let axes = if state.scene == relief_scene::SceneKind::Plasma {
        &AXES[..0]
    } else {
        &AXES[..]
    };
    for (axis, name) in axes.iter().enumerate() {
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
pub(super) fn with_message(mut line: Line<'static>, state: &State) -> Line<'static> {
    if let Some(msg) = state.message_line() {
        line.spans.push(Span::raw(format!("  {msg}")));
    }
    line
}

/// A message too long for the panel line, wrapped at the screen width on
/// the rows just above `panel` (over the bottom of the picture).
pub(super) fn message_above(msg: &str, panel: Rect, viewport: Rect, buf: &mut Buffer) {
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
