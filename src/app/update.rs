//! The pure `update` every action goes through: it changes the [`State`]
//! and may ask the event loop for a [`Command`]. [`apply`] routes each
//! action to the function of its domain.

mod camera;
mod overlays;
mod panel;
mod prompt;
mod scene;
mod textures;

use super::action::Action;
use super::command::Command;
use super::playback;
use super::state::{State, UpChoice};
use relief_core::sanitize::clean;

/// Whether `action` comes from the user (a key, a click, a paste), not
/// from the loop reporting something: the user's next action clears the
/// last message.
fn from_user(action: &Action) -> bool {
    !matches!(
        action,
        Action::Saved(_)
            | Action::TextureResult(_)
            | Action::SceneBuilt(_)
            | Action::Loading(_)
            | Action::TexturesListed(_)
            | Action::TexturesFit(_)
            | Action::HelpFits(_)
            | Action::HelpPageFits(_)
            | Action::FrameStart { .. }
            | Action::FrameEnd { .. }
            | Action::Resize
            | Action::Pointer { .. }
            | Action::Tick { .. }
            | Action::MouseDrag { .. }
            | Action::MouseUp
            | Action::PromptCompleted(_)
    )
}

/// Applies one action. Pure: no I/O, no clock; what needs the outside
/// world comes back as a [`Command`]. The user's next action clears the
/// last message; a key that would change what the picture does not show
/// is refused with a message ([`super::feedback`]).
pub fn update(state: &mut State, action: Action) -> Option<Command> {
    if from_user(&action) {
        state.message = None;
        if action != Action::Escape {
            state.esc_closed = false;
        }
    }
    if let Some(text) = super::feedback::refusal(state, &action) {
        state.message = Some(text);
        return None;
    }
    let shown = super::feedback::effect_of(&action);
    let command = apply(state, action);
    if let Some(a) = shown
        && let Some(text) = super::feedback::effect(state, &a)
    {
        state.message = Some(text);
    }
    command
}

/// [`update`]'s work once the action is accepted: each domain's actions go
/// to its function; the few left are one line each.
fn apply(state: &mut State, action: Action) -> Option<Command> {
    use Action as A;
    match action {
        a @ (A::RotateStep { .. }
        | A::ZoomIn
        | A::ZoomOut
        | A::ToggleLightDrag
        | A::ResetView
        | A::ToggleAutoRotate
        | A::MouseDown { .. }
        | A::MouseDrag { .. }
        | A::MouseUp
        | A::Pointer { .. }) => camera::apply(state, a),
        a @ (A::NextTexture
        | A::PrevTexture
        | A::ReloadTexture
        | A::ToggleTextures
        | A::CloseTextures
        | A::TexturesMove(_)
        | A::TexturesChoose
        | A::TexturesHeights
        | A::TexturesClick { .. }
        | A::TexturesScroll(_)
        | A::TexturesListed(_)
        | A::TexturesFit(_)
        | A::TextureResult(_)
        | A::ToggleNormalMapFile) => return textures::apply(state, a),
        a @ (A::OpenPrompt
        | A::PromptInput(_)
        | A::PromptBackspace
        | A::PromptEdit(_)
        | A::PromptComplete
        | A::PromptCompleted(_)
        | A::PromptCancel
        | A::PromptSubmit
        | A::Paste(_)) => return prompt::apply(state, a),
        a @ (A::PanelNext
        | A::PanelPrev
        | A::PanelInput(_)
        | A::PanelBackspace
        | A::PanelApply
        | A::PanelCancel) => panel::apply(state, a),
        a @ (A::NextModel | A::NextScene | A::Loading(_) | A::SceneBuilt(_) | A::ModelNotes(_)) => {
            return scene::apply(state, a);
        }
        a @ (A::ToggleHelp
        | A::HelpScroll(_)
        | A::HelpPage(_)
        | A::HelpPageFits(_)
        | A::HelpFits(_)
        | A::ToggleCost
        | A::CloseHelp
        | A::Escape) => return overlays::apply(state, a),
        A::Tick { seconds } => {
            playback::tick(state, seconds);
            camera::apply(state, A::Tick { seconds });
        }
        A::TogglePlay => playback::toggle(state),
        A::NextClip => playback::next_clip(state),
        A::StepClip(frames) => playback::step(state, frames),
        A::NextCamera => super::file_cameras::next(state),
        A::FrameStart { .. } | A::FrameEnd { .. } => frame_report(state, action),
        A::Quit => state.quit = true,
        A::Suspend => return Some(Command::Suspend),
        A::SavePng => return Some(Command::SavePng),
        A::Saved(Ok(path)) => state.message = Some(format!("saved {}", clean(&path))),
        A::Saved(Err(e)) => state.message = Some(format!("not saved: {}", clean(&e))),
        a @ (A::Option { .. }
        | A::CycleSymbols
        | A::CycleFormat
        | A::ToggleLight(_)
        | A::TogglePlasmaNormal) => picture(state, a),
        A::Resize | A::Unbound => {}
    }
    None
}

/// The options of the picture and of its output.
fn picture(state: &mut State, action: Action) {
    match action {
        Action::Option { id, press } => {
            relief_options::get(id).press(&mut state.settings, press);
            // The user's up axis stays, whatever the next model's format says.
            if id == relief_options::OptId::Up {
                state.up = UpChoice::User;
            }
        }
        Action::CycleSymbols => state.symbols = state.symbols.next(),
        Action::CycleFormat => {
            state.output.cycle();
            state.message = state.output.choice.note.clone();
        }
        Action::ToggleLight(i) => {
            let count = state.light_names().len();
            if i >= count && i < state.light_on.len() {
                state.message = Some(format!("this view has {count} lights (1-{count})"));
            } else if let Some(on) = state.light_on.get_mut(i) {
                *on = !*on;
            }
        }
        Action::TogglePlasmaNormal => state.plasma_normal = state.plasma_normal.toggle(),
        // Not a picture option: `apply` routes none of the others here.
        _ => {}
    }
}

/// The loop's report of a frame: its start (a preview or not, idle) and its
/// end (the link's state, the frame's cost and time).
fn frame_report(state: &mut State, action: Action) {
    match action {
        Action::FrameStart { preview, idle } => {
            state.frame.preview = preview;
            if idle {
                state.frame.fps = None;
            }
        }
        Action::FrameEnd { link, frame } => {
            state.link = link;
            if let Some(f) = frame {
                state.costs.push(f.cost);
                state.frame.frame_time = f.time;
                state.frame.bytes = f.bytes;
                state.frame.fps = f.fps;
            }
        }
        // Not a frame report: `apply` routes none of the others here.
        _ => {}
    }
}
