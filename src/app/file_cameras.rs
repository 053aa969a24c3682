//! `V`: a model file's own cameras (glTF) and the framing camera, in
//! turn. Seen through the file's camera, the model stands as the file
//! places it (no start turn), as its author framed it.

use glam::Vec3;

use super::state::State;

/// A new model's cameras: the framing camera first.
pub fn take(state: &mut State, count: usize) {
    state.cameras = count;
    if state.camera.take().is_some() {
        state.settings.rotation = state.start_rotation;
    }
}

/// `V`: the next of the file's cameras, then the framing camera again.
pub fn next(state: &mut State) {
    let n = state.cameras;
    if n == 0 {
        state.message = Some("this model has no camera of its own".into());
        return;
    }
    state.camera = match state.camera {
        None => Some(0),
        Some(k) if k + 1 < n => Some(k + 1),
        Some(_) => None,
    };
    state.message = Some(match state.camera {
        Some(k) => {
            state.settings.rotation = Vec3::ZERO;
            format!("the file's camera {} of {n} (V: the next)", k + 1)
        }
        None => {
            state.settings.rotation = state.start_rotation;
            "the framing camera (V: the file's cameras)".into()
        }
    });
}

/// The rotation `r` goes back to: the file's own through its camera.
pub fn reset_rotation(state: &State) -> Vec3 {
    if state.camera.is_some() {
        Vec3::ZERO
    } else {
        state.start_rotation
    }
}
