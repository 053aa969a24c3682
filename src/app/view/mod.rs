//! What the screen shows: the picture, the line above the status
//! ([`fields`]), the status line ([`status`]), the panels over the picture
//! ([`panels`]), the texture panel ([`textures`]) and the help overlay
//! ([`help`]). Drawing only: every
//! decision is in `State`.

pub mod cost;
mod fields;
pub mod help;
mod panels;
pub mod status;
pub mod textures;
mod wrap;

use ratatui::Frame;
use ratatui::buffer::Buffer;
use ratatui::layout::Rect;
use ratatui::style::{Modifier, Style};
use ratatui::text::Line;
use ratatui::widgets::{Clear, Paragraph, Widget};

use super::state::State;
use fields::{message_above, panel_line, prompt_line, with_message};
use help::help;
pub use help::{help_lines, help_max_scroll, help_page};
use panels::cost_panel;
use relief_core::framebuffer::{Framebuffer, Rgb};
use relief_term::{SymbolCells, Symbols};
use status::status_choice;
pub use status::{HELP_HINT, cost_text, format_bytes, status_line, status_rows};
use textures::texture_panel;
pub use textures::texture_panel_area;

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

/// Splits the screen with a status line of one row (see [`layout`]).
pub fn areas(screen: Rect) -> Areas {
    split(screen, 1)
}

/// Splits the screen as `state` draws it: the status line takes the rows
/// its fields need on this screen (see [`status_rows`]).
pub fn layout(state: &State, screen: Rect) -> Areas {
    split(screen, status_rows(state, screen.width, screen.height))
}

/// Splits the screen: picture on top, then the orientation line, then the
/// status line of `rows` rows. Small terminals drop the orientation line
/// (height 2) and the status line too (height 1: the picture wins).
fn split(screen: Rect, rows: u16) -> Areas {
    let row = |y: u16, h: u16| Rect::new(screen.x, screen.y + y, screen.width, h);
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
            status: Some(row(1, 1)),
        },
        h => {
            // The picture keeps a row at least.
            let rows = rows.clamp(1, h - 2);
            Areas {
                viewport: Rect {
                    height: h - 1 - rows,
                    ..screen
                },
                panel: Some(row(h - 1 - rows, 1)),
                status: Some(row(h - rows, rows)),
            }
        }
    }
}

/// Framebuffer size for a viewport drawn with `symbols`: a half-block
/// column is a pixel wide and a row two pixels tall (pixels about square);
/// the finer sets have two columns and their rows of pixels per cell (the
/// renderer corrects the projection for their taller pixels).
pub fn framebuffer_size(viewport: Rect, symbols: Symbols) -> (usize, usize) {
    (
        viewport.width as usize * symbols.columns(),
        viewport.height as usize * symbols.rows(),
    )
}

/// Draws the whole screen.
pub fn view(frame: &mut Frame, state: &State, fb: &Framebuffer, background: Rgb) {
    let screen = frame.area();
    let buf = frame.buffer_mut();
    draw(state, fb, background, screen, buf);
}

/// [`view`] on a bare buffer (the benchmark and tests use it directly).
pub fn draw(state: &State, fb: &Framebuffer, background: Rgb, screen: Rect, buf: &mut Buffer) {
    let a = layout(state, screen);
    SymbolCells {
        fb,
        symbols: state.symbols,
        depth: state.depth,
        dither: state.dither,
        pad: background,
    }
    .render(a.viewport, buf);
    let rows = a.status.map_or(1, |r| r.height);
    let (status_text, status_cost) = status_choice(state, screen.width as usize, rows);
    // Narrow screens shorten the fields; a status line without the frame
    // cost leaves it to the line above.
    let compact = screen.width < COMPACT_BELOW;
    let cost_above = !status_cost;
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
            .message_line()
            .filter(|m| line.width() + 2 + m.chars().count() > panel.width as usize);
        match long {
            // Too long for the rest of the line: the whole message, wrapped,
            // on the rows just above it.
            Some(msg) => {
                line.render(panel, buf);
                message_above(&msg, panel, a.viewport, buf);
            }
            None => with_message(line, state).render(panel, buf),
        }
    } else if let (Some(status), Some(_)) = (a.status, state.panel.focus) {
        // No room for both: while editing, the fields take the status line.
        panel_line(state, true, false).render(status, buf);
        return help(state, screen, buf);
    }
    if let Some(status) = a.status {
        let lines: Vec<Line> = status_text.into_iter().map(Line::from).collect();
        Paragraph::new(lines)
            .style(Style::new().add_modifier(Modifier::REVERSED))
            .render(status, buf);
    }
    cost_panel(state, a.viewport, buf);
    texture_panel(state, a.viewport, buf);
    help(state, screen, buf);
}
