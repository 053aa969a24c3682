//! The view's actions: turning, zooming, panning the model and the lights.

use glam::{Vec2, Vec3};

use super::super::action::{Action, DragButton};
use super::super::state::{
    AUTO_ROTATE_SPEED, DEG_PER_COL, DEG_PER_ROW, Drag, PAN_MAX, PAN_PER_COL, PAN_PER_ROW, State,
    ZOOM_STEP,
};
use relief_core::settings::normalize_degrees;
use relief_scene::SceneKind;
use relief_scene::camera::{MAX_DISTANCE, MIN_DISTANCE, REFERENCE_DISTANCE};

/// Applies a camera action (the ones [`super::apply`] routes here).
pub(super) fn apply(state: &mut State, action: Action) {
    match action {
        Action::RotateStep { axis, degrees } => {
            let mut d = Vec3::ZERO;
            d[axis.min(2)] = degrees;
            state.rotate(d);
        }
        Action::ZoomIn => state.distance = (state.distance / ZOOM_STEP).max(MIN_DISTANCE),
        Action::ZoomOut => state.distance = (state.distance * ZOOM_STEP).min(MAX_DISTANCE),
        Action::ToggleLightDrag => {
            state.light_drag = !state.light_drag;
            state.message = Some(
                if state.light_drag {
                    "a left drag turns the lights (D again: the model)"
                } else {
                    "a left drag turns the model"
                }
                .into(),
            );
        }
        Action::ResetView => reset_view(state),
        Action::ToggleAutoRotate => state.auto_rotate = !state.auto_rotate,
        Action::Tick { seconds } if state.auto_rotate && seconds.is_finite() && seconds > 0.0 => {
            // A long stall (a slow link) is not made up for in one leap.
            let dt = seconds.min(0.25);
            state.rotate(Vec3::new(0.0, AUTO_ROTATE_SPEED * dt, 0.0));
        }
        Action::MouseDown { button, col, row } => state.drag = Some(Drag { button, col, row }),
        Action::MouseDrag { button, col, row } => drag_to(state, button, col, row),
        Action::MouseUp => state.drag = None,
        Action::Pointer { col, row } if state.scene == SceneKind::Plasma => {
            state.pointer = Some((col, row));
        }
        // A tick while nothing turns, a pointer outside the plasma (`apply`
        // routes no other action here).
        _ => {}
    }
}

/// `r`: the start view back, nothing turning or held.
fn reset_view(state: &mut State) {
    state.settings.rotation = super::super::file_cameras::reset_rotation(state);
    state.distance = state.start_distance;
    state.pan = Vec2::ZERO;
    state.light_turn = Vec2::ZERO;
    state.auto_rotate = false;
    state.drag = None;
}

/// A drag moved to (`col`, `row`): turn, pan or turn the lights by the move
/// since the last position of the same button.
fn drag_to(state: &mut State, button: DragButton, col: u16, row: u16) {
    match state.drag {
        Some(d) if d.button == button => {
            let dx = col as f32 - d.col as f32;
            let dy = row as f32 - d.row as f32;
            match button {
                DragButton::Left => {
                    state.rotate(Vec3::new(dy * DEG_PER_ROW, dx * DEG_PER_COL, 0.0))
                }
                DragButton::Right => {
                    state.rotate(Vec3::new(dy * DEG_PER_ROW, 0.0, -dx * DEG_PER_COL))
                }
                DragButton::Pan => {
                    // World units per cell at the camera's distance.
                    let scale = state.distance / REFERENCE_DISTANCE;
                    let moved = Vec2::new(dx * PAN_PER_COL, -dy * PAN_PER_ROW) * scale;
                    state.pan = (state.pan + moved).clamp(-PAN_MAX, PAN_MAX);
                }
                DragButton::Light => {
                    let turn = state.light_turn + Vec2::new(dx * DEG_PER_COL, dy * DEG_PER_ROW);
                    state.light_turn = turn.map(normalize_degrees);
                }
            }
        }
        // The press was missed (or the other button): start from here.
        _ => {}
    }
    state.drag = Some(Drag { button, col, row });
}
