//! The scene and model actions: switching, loading, what the load reported.

use super::super::action::Action;
use super::super::command::Command;
use super::super::playback;
use super::super::state::{Panel, State, UpChoice};
use relief_core::sanitize::clean;
use relief_scene::model_view::ModelFeatures;
use relief_scene::{LoadedNotes, ModelChoice, SceneKind};

/// Applies a scene action (the ones [`super::apply`] routes here).
pub(super) fn apply(state: &mut State, action: Action) -> Option<Command> {
    match action {
        Action::NextModel => {
            // From another scene, `o` first goes back to the model.
            let model = if state.scene == SceneKind::Cube {
                state.next_model()
            } else {
                state.model.clone()
            };
            return Some(Command::BuildScene(SceneKind::Cube, model));
        }
        Action::NextScene => {
            return Some(Command::BuildScene(state.scene.next(), state.model.clone()));
        }
        Action::Loading(status) => state.loading = Some(status),
        Action::SceneBuilt(Ok((scene, model))) => built(state, scene, model),
        Action::SceneBuilt(Err(e)) => {
            state.loading = None;
            state.message = Some(clean(&e));
        }
        Action::ModelNotes(notes) => model_notes(state, &notes),
        // Not a scene action: `apply` routes none of the others here.
        _ => {}
    }
    None
}

/// The loop built this scene and model: show them.
fn built(state: &mut State, scene: SceneKind, model: ModelChoice) {
    state.loading = None;
    if scene != state.scene {
        // A new scene starts with its light in the middle and no drag.
        state.pointer = None;
        state.drag = None;
    }
    if scene == SceneKind::Plasma {
        // Nothing turns in the plasma: no frames for nothing.
        state.auto_rotate = false;
        state.panel = Panel::default();
    }
    state.scene = scene;
    // Its clips and cameras, if any, come with its notes.
    playback::take_clips(state, Vec::new());
    super::super::file_cameras::take(state, 0);
    state.file_lights = 0;
    state.physical = false;
    // The built-in plane and triangle are flat; a file says with its notes.
    state.features = ModelFeatures {
        varied_normals: !matches!(model, ModelChoice::Plane | ModelChoice::Triangle),
        ..ModelFeatures::default()
    };
    state.texture_reach = None;
    if state.up == UpChoice::File {
        state.settings.up = relief_core::settings::UpAxis::Y;
        state.up = UpChoice::Default;
    }
    // A model file opened from the prompt or a paste joins the `o` cycle.
    if let ModelChoice::File(path) = &model {
        state.obj = Some(path.clone());
    }
    state.model = model;
}

/// What the model's reader noted: a point cloud is drawn as points, the
/// first warning is shown (with how many more).
fn model_notes(state: &mut State, notes: &LoadedNotes) {
    if notes.points {
        state.settings.display = relief_core::settings::Display::Points;
    }
    playback::take_clips(state, notes.clips.clone());
    super::super::file_cameras::take(state, notes.cameras);
    state.file_lights = notes.lights;
    state.physical = notes.physical;
    state.features = notes.features;
    state.texture_reach = notes.texture_reach;
    // An STL stands Z up, unless the user set the axis.
    if notes.z_up && state.up == UpChoice::Default {
        state.settings.up = relief_core::settings::UpAxis::Z;
        state.up = UpChoice::File;
    }
    let mut lines = notes.warnings.iter();
    if let Some(first) = lines.next() {
        let more = lines.count();
        state.message = Some(if more > 0 {
            format!("{} (and {more} more warnings)", clean(first))
        } else {
            clean(first)
        });
    } else if notes.points {
        state.message = Some("a point cloud: drawn as points (d)".into());
    }
}
