//! The overlays' actions: the help, the cost panel, and Esc.

use super::super::action::Action;
use super::super::command::Command;
use super::super::state::State;

/// More lines than the help can ever have (the view clamps to what the
/// screen needs; the loop clamps the state with it).
const HELP_SCROLL_MAX: u16 = 1000;

/// Applies an overlay action (the ones [`super::apply`] routes here).
pub(super) fn apply(state: &mut State, action: Action) -> Option<Command> {
    match action {
        Action::ToggleHelp => {
            state.help = !state.help;
            state.help_scroll = 0;
        }
        Action::HelpScroll(lines) => scroll_help(state, i64::from(lines)),
        Action::HelpPage(pages) => {
            scroll_help(state, i64::from(pages) * i64::from(state.help_page.max(1)))
        }
        Action::HelpPageFits(lines) => state.help_page = lines.max(1),
        Action::HelpFits(max) => state.help_scroll = state.help_scroll.min(max),
        Action::ToggleCost => state.cost_panel = !state.cost_panel,
        Action::CloseHelp => {
            state.help = false;
            state.esc_closed = true;
        }
        Action::Escape => return escape(state),
        // Not an overlay action: `apply` routes none of the others here.
        _ => {}
    }
    None
}

/// Moves the help by `lines` (down when positive), within its bounds.
fn scroll_help(state: &mut State, lines: i64) {
    let to = i64::from(state.help_scroll) + lines;
    state.help_scroll = to.clamp(0, i64::from(HELP_SCROLL_MAX)) as u16;
}

/// Esc stops a load, else closes the top overlay; it quits only when none
/// is open and the Esc before it did not just close one.
fn escape(state: &mut State) -> Option<Command> {
    if let Some(load) = state.loading.take() {
        state.esc_closed = true;
        state.message = Some(format!(
            "stopped loading {}: the model shown stays",
            load.name
        ));
        return Some(Command::CancelLoad);
    } else if state.cost_panel {
        state.cost_panel = false;
        state.esc_closed = true;
    } else if state.esc_closed {
        state.esc_closed = false;
        state.message = Some("nothing left to close: Esc again or q quits".into());
    } else {
        state.quit = true;
    }
    None
}
