//! Panels drawn over the picture: the cost panel (key `k`).

use ratatui::buffer::Buffer;
use ratatui::layout::Rect;
use ratatui::widgets::{Clear, Widget};

use crate::app::state::State;
use crate::app::view::cost::CostPanel;

/// The sixel limit's line of the cost panel, when the terminal answered one.
fn sixel_limit(state: &State, viewport: Rect) -> Option<String> {
    use relief_term::pixel_view::{cell_pixels, sixel_limit_line, window_size};
    state.output.sixel_max?;
    let (cell, _) = cell_pixels(window_size(), state.output.cell_reply);
    sixel_limit_line(&state.output, viewport, cell)
}

/// The cost panel (key `k`) in the top-right corner of the picture.
pub(super) fn cost_panel(state: &State, viewport: Rect, buf: &mut Buffer) {
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
    CostPanel {
        history: &state.costs,
        link: &state.link,
        colour: match &state.output.choice {
            // A pixel format, or the reason one is not in use.
            c if c.format.is_pixels() || state.output.wanted.is_pixels() => {
                format!("{}: {}", c.format.name(), c.source)
            }
            _ => crate::app::view::cost::colour_line(state.depth, &state.depth_source),
        },
        pixels: sixel_limit(state, viewport),
    }
    .render(area, buf);
}
