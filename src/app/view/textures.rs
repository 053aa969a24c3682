//! The texture panel (key `T`) over the top-left of the picture: per
//! entry a marker (▶ the applied texture), a half-block thumbnail drawn by
//! the picture's own encoder at the screen's colour depth, the name, and
//! below it the size and whether it gives the heights.

use ratatui::buffer::Buffer;
use ratatui::layout::Rect;
use ratatui::style::{Modifier, Style};
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Clear, Widget};

use crate::app::state::State;
use crate::app::textures::{ENTRY_ROWS, TEXT_COLUMN, model_area, panel_area, visible_entries};
use crate::app::thumbnail::{THUMB_HEIGHT, THUMB_WIDTH};
use relief_term::HalfBlocks;

/// Marks the applied texture.
pub const CURRENT_MARK: &str = "▶";
/// Says which entry gives the heights.
pub const HEIGHTS_MARK: &str = "◆ heights";

/// Where the panel goes over `viewport` (`None`: closed, or no room).
pub fn texture_panel_area(viewport: Rect, state: &State) -> Option<Rect> {
    if !state.textures.open {
        return None;
    }
    panel_area(viewport, &state.textures.listing)
}

/// `text` cut to `width` characters, its end kept (a path's file name).
fn tail(text: &str, width: usize) -> String {
    let n = text.chars().count();
    if n <= width {
        return text.to_string();
    }
    let keep = width.saturating_sub(1);
    let mut out = String::from("…");
    out.extend(text.chars().skip(n - keep));
    out
}

/// `text` cut to `width` characters, its start kept.
fn head(text: &str, width: usize) -> String {
    if text.chars().count() <= width {
        return text.to_string();
    }
    let mut out: String = text.chars().take(width.saturating_sub(1)).collect();
    out.push('…');
    out
}

pub(super) fn texture_panel(state: &State, viewport: Rect, buf: &mut Buffer) {
    let Some(area) = texture_panel_area(viewport, state) else {
        return;
    };
    let panel = &state.textures;
    let listing = &panel.listing;
    let n = listing.rows.len();
    Clear.render(area, buf);
    let title = if n > 0 {
        format!(" textures {}/{} ", panel.cursor + 1, n)
    } else {
        " textures ".to_string()
    };
    let block = Block::bordered()
        .title(title)
        .title_bottom(" Enter use · H heights · Esc ");
    let inner = block.inner(area);
    block.render(area, buf);
    model_textures(state, viewport, area, buf);
    let first = panel.first_shown();
    let text_x = inner.x + TEXT_COLUMN;
    let text_w = inner.width.saturating_sub(TEXT_COLUMN);
    for (slot, i) in (first..n).take(visible_entries(area)).enumerate() {
        let row = &listing.rows[i];
        let y = inner.y + slot as u16 * ENTRY_ROWS;
        let current = i == listing.current;
        let mut style = Style::new();
        if current {
            style = style.add_modifier(Modifier::BOLD);
        }
        if i == panel.cursor {
            style = style.add_modifier(Modifier::REVERSED);
        }
        if current {
            buf.set_string(inner.x, y, CURRENT_MARK, Style::new());
        }
        if let Some(preview) = &row.preview {
            HalfBlocks {
                fb: &preview.thumb,
                depth: state.depth,
                dither: state.dither,
                pad: [0, 0, 0],
            }
            .render(
                Rect::new(
                    inner.x + 2,
                    y,
                    THUMB_WIDTH as u16,
                    THUMB_HEIGHT.div_ceil(2) as u16,
                ),
                buf,
            );
        }
        let name = tail(&row.label, text_w as usize);
        Line::from(Span::styled(
            format!("{name:<w$}", w = text_w as usize),
            style,
        ))
        .render(Rect::new(text_x, y, text_w, 1), buf);
        if ENTRY_ROWS > 1 {
            let size = match &row.preview {
                Some(p) => format!("{}×{}", p.width, p.height),
                None => "—".to_string(),
            };
            let mut spans = vec![Span::raw(size)];
            if listing.heights == Some(i) {
                spans.push(Span::styled(
                    format!("  {HEIGHTS_MARK}"),
                    Style::new().add_modifier(Modifier::BOLD),
                ));
            }
            Line::from(spans).render(Rect::new(text_x, y + 1, text_w, 1), buf);
        }
    }
}

/// The shown model's own textures, in a box under the panel `above`.
fn model_textures(state: &State, viewport: Rect, above: Rect, buf: &mut Buffer) {
    let listing = &state.textures.listing;
    let Some(area) = model_area(viewport, above, listing) else {
        return;
    };
    Clear.render(area, buf);
    let block = Block::bordered().title(" model textures ");
    let inner = block.inner(area);
    block.render(area, buf);
    for (k, line) in listing.model.iter().take(inner.height as usize).enumerate() {
        let text = head(line, inner.width as usize);
        Line::from(text).render(Rect::new(inner.x, inner.y + k as u16, inner.width, 1), buf);
    }
}

#[cfg(test)]
mod tests {
    use super::{head, tail};

    #[test]
    fn model_lines_keep_their_start() {
        assert_eq!(head("material 1: base", 30), "material 1: base");
        assert_eq!(
            head("material 1: base 4×4 a/long/name.png", 20),
            "material 1: base 4×…"
        );
    }

    #[test]
    fn long_names_keep_their_end() {
        assert_eq!(tail("brick", 8), "brick");
        assert_eq!(tail("/a/long/path/photo.png", 10), "…photo.png");
    }
}
