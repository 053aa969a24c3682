//! The help overlay (key `?`): the key table's lines, centred, in one or
//! two columns, wrapped or scrolled when the screen is small.

use ratatui::buffer::Buffer;
use ratatui::layout::Rect;
use ratatui::style::{Modifier, Style};
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Clear, Paragraph, Widget};

use super::wrap::wrap_words;
use crate::app::keys::HelpLine;
use crate::app::state::State;

/// The help overlay, centred; in two columns when one does not fit the
/// height but two fit the width; on a narrow screen each text wraps under
/// itself; when it is still too tall it scrolls (`state.help_scroll`).
pub(super) fn help(state: &State, screen: Rect, buf: &mut Buffer) {
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

/// Widest key column and widest text of the help's lines, in characters.
fn help_widths(entries: &[HelpLine]) -> (usize, usize) {
    let widest = |f: fn(&HelpLine) -> usize| entries.iter().map(f).max().unwrap_or(0);
    (
        widest(|(k, _)| k.chars().count()),
        widest(|(_, t)| t.chars().count()),
    )
}

/// The help's lines, from the key table (see [`crate::app::keys::help_lines`]).
pub fn help_lines() -> Vec<HelpLine> {
    crate::app::keys::help_lines()
}

/// A mode's heading is bold, a line of keys is plain.
fn text_style(key: &str) -> Style {
    if key.is_empty() {
        Style::new().add_modifier(Modifier::BOLD)
    } else {
        Style::new()
    }
}

fn help_layout(screen: Rect) -> HelpLayout {
    let entries = help_lines();
    let (key_w, text_w) = help_widths(&entries);
    let entry_w = key_w + 2 + text_w;
    let (sw, sh) = (screen.width as usize, screen.height as usize);
    let two = entries.len() + 2 > sh && 2 * entry_w + 3 + 4 <= sw;
    let (lines, inner_w) = if two {
        two_columns(&entries, key_w, text_w)
    } else if sw >= 4 + key_w + 2 + NARROW_HELP_TEXT {
        // The text beside its key, wrapped under itself.
        beside_keys(&entries, key_w, (sw - 4 - key_w - 2).min(text_w))
    } else {
        // Too narrow for two columns: each key on its line, its text below.
        below_keys(&entries, sw.saturating_sub(4 + 2).max(1))
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

/// A key right-aligned in `key_w` columns, in bold.
fn key_span(k: &str, key_w: usize) -> Span<'static> {
    Span::styled(
        format!("{k:>key_w$}"),
        Style::new().add_modifier(Modifier::BOLD),
    )
}

/// The entries in two columns, the second half on the right; and the
/// width they take.
fn two_columns(entries: &[HelpLine], key_w: usize, text_w: usize) -> (Vec<Line<'static>>, usize) {
    let rows = entries.len().div_ceil(2);
    let entry = |(k, t): &HelpLine| {
        vec![
            key_span(k, key_w),
            Span::styled(format!("  {t:<text_w$}"), text_style(k)),
        ]
    };
    let lines = (0..rows)
        .map(|r| {
            let mut spans = entry(&entries[r]);
            if let Some(right) = entries.get(r + rows) {
                spans.push(Span::raw("   "));
                spans.extend(entry(right));
            }
            Line::from(spans)
        })
        .collect();
    (lines, 2 * (key_w + 2 + text_w) + 3)
}

/// Each text beside its key, wrapped in `room` columns under itself; and
/// the width they take.
fn beside_keys(entries: &[HelpLine], key_w: usize, room: usize) -> (Vec<Line<'static>>, usize) {
    let mut lines = Vec::new();
    for (k, t) in entries {
        for (i, piece) in wrap_words(t, room).into_iter().enumerate() {
            let first = if i == 0 {
                key_span(k, key_w)
            } else {
                key_span("", key_w)
            };
            lines.push(Line::from(vec![
                first,
                Span::styled(format!("  {piece}"), text_style(k)),
            ]));
        }
    }
    (lines, key_w + 2 + room)
}

/// Each key on its own line, its text wrapped in `room` columns below;
/// and the width they take.
fn below_keys(entries: &[HelpLine], room: usize) -> (Vec<Line<'static>>, usize) {
    let mut lines = Vec::new();
    for (k, t) in entries {
        if !k.is_empty() {
            lines.push(Line::from(Span::styled(
                k.to_string(),
                Style::new().add_modifier(Modifier::BOLD),
            )));
        }
        for piece in wrap_words(t, room) {
            lines.push(Line::from(Span::styled(
                format!("  {piece}"),
                text_style(k),
            )));
        }
    }
    (lines, room + 2)
}

/// Fewest characters of text worth showing beside the keys.
const NARROW_HELP_TEXT: usize = 16;

/// How far the help can scroll on a screen of this size (the loop clamps
/// `State::help_scroll` with it, so scrolling back responds at once).
pub fn help_max_scroll(width: u16, height: u16) -> u16 {
    help_layout(Rect::new(0, 0, width, height)).max_scroll
}

/// Lines the help shows at once on a screen of this size: what PgUp and
/// PgDn scroll.
pub fn help_page(width: u16, height: u16) -> u16 {
    let layout = help_layout(Rect::new(0, 0, width, height));
    layout.area.height.saturating_sub(2).max(1)
}
