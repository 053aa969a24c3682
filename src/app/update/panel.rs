//! The orientation fields' actions (the three angles typed in).

use super::super::action::Action;
use super::super::state::{AXES, Panel, State, format_angle};
use relief_core::sanitize::clean;
use relief_core::settings::normalize_degrees;
use relief_options::text::parse_finite;

/// Longest text an orientation field takes.
const FIELD_MAX: usize = 24;

/// Applies an orientation-field action (the ones [`super::apply`] routes here).
pub(super) fn apply(state: &mut State, action: Action) {
    match action {
        Action::PanelNext => {
            let next = state.panel.focus.map_or(0, |f| (f + 1) % 3);
            state.panel.focus = Some(next);
            state.panel.fresh = true;
        }
        Action::PanelPrev => {
            let prev = state.panel.focus.map_or(2, |f| (f + 2) % 3);
            state.panel.focus = Some(prev);
            state.panel.fresh = true;
        }
        Action::PanelInput(c) => {
            if let Some(f) = state.panel.focus
                && !c.is_control()
            {
                let replace = state.panel.fresh || state.panel.edits[f].is_none();
                let text = state.panel.edits[f].get_or_insert_with(String::new);
                if replace {
                    text.clear();
                }
                if text.chars().count() < FIELD_MAX {
                    text.push(c);
                }
                state.panel.fresh = false;
            }
        }
        Action::PanelBackspace => {
            if let Some(f) = state.panel.focus {
                let live = format_angle(state.settings.rotation[f]);
                let text = state.panel.edits[f].get_or_insert(live);
                if state.panel.fresh {
                    text.clear();
                }
                text.pop();
                state.panel.fresh = false;
            }
        }
        Action::PanelApply => apply_panel(state),
        Action::PanelCancel => cancel_panel(state),
        // Not a field action: `apply` routes none of the others here.
        _ => {}
    }
}

/// Esc in the orientation fields: the edits not applied are dropped, and
/// the message says which were applied.
fn cancel_panel(state: &mut State) {
    let applied: Vec<String> = AXES
        .iter()
        .enumerate()
        .filter(|(axis, _)| state.panel.applied[*axis])
        .map(|(axis, name)| format!("{name} {}°", format_angle(state.settings.rotation[axis])))
        .collect();
    state.panel = Panel::default();
    state.esc_closed = true;
    state.message = Some(if applied.is_empty() {
        "orientation unchanged".into()
    } else {
        format!("{} applied; the other edits dropped", applied.join(", "))
    });
}

/// Enter in the orientation fields: valid entries are applied, each invalid
/// one is refused with a message and keeps its old value (and the focus).
fn apply_panel(state: &mut State) {
    let mut refused = Vec::new();
    let mut first_bad = None;
    for (axis, name) in AXES.iter().enumerate() {
        let Some(text) = state.panel.edits[axis].take() else {
            continue;
        };
        match parse_finite(&text) {
            Ok(v) => {
                state.settings.rotation[axis] = normalize_degrees(v);
                state.panel.applied[axis] = true;
            }
            Err(e) => {
                refused.push(format!(
                    "{}: {} (kept {}°)",
                    name,
                    clean(&e),
                    format_angle(state.settings.rotation[axis])
                ));
                first_bad.get_or_insert(axis);
            }
        }
    }
    if refused.is_empty() {
        state.panel = Panel::default();
        state.message = None;
    } else {
        state.panel.focus = first_bad;
        state.panel.fresh = true;
        state.message = Some(refused.join("; "));
    }
}
