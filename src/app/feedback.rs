//! What a key says when it cannot act where the user is: a key that would
//! change something the picture does not show is refused with a message
//! and changes nothing. The "does it show" conditions are the plan's
//! ([`crate::plan`]); this file only names the keys and words the message.

use super::action::Action;
use super::state::State;
use crate::plan::{environment_can_show, light_vector_shows, specular_shows, technique_shows};
use crate::scene::SceneKind;
use crate::settings::Shading;

/// The key and what it changes, for the messages (`None`: the action
/// acts everywhere, or is not a key of the 3D scenes).
fn three_d_only(action: &Action) -> Option<&'static str> {
    Some(match action {
        Action::CycleShading => "m (lighting)",
        Action::ToggleNormals => "n (normals)",
        Action::ToggleTexture => "t (texture)",
        Action::ToggleColors => "c (colours)",
        Action::ToggleBump => "b (bump)",
        Action::BumpStronger | Action::BumpWeaker => "+ - (bump strength)",
        Action::RotateStep { .. } => "the arrows (rotation)",
        Action::ResetView => "r (reset the view)",
        Action::ZoomIn | Action::ZoomOut => "i I (zoom)",
        Action::ToggleAutoRotate => "space (auto-rotation)",
        Action::PanelNext | Action::PanelPrev => "Tab (orientation fields)",
        Action::CycleFilter => "f (filter)",
        Action::CycleTechnique => "e (bump technique)",
        Action::ToggleLightVector => "v (dot3 light vector)",
        Action::ToggleNormalMapFile => "N (normal map)",
        Action::ToggleHeightDerivative => "h (height derivative)",
        Action::CycleAntiAlias => "a (anti-aliasing)",
        Action::CycleDisplay => "d (display)",
        Action::ToggleTangentFrames => "F (tangent frames)",
        Action::ToggleLights => "l (lights)",
        Action::ToggleLight(_) => "1-4 (lights)",
        Action::ToggleAttenuation => "L (attenuation)",
        Action::ToggleSpecular => "g (specular)",
        Action::ShinierSpecular | Action::DullerSpecular => "y Y (shininess)",
        Action::ToggleEnvironment => "E (environment)",
        _ => return None,
    })
}

/// The message refusing `action` in this state, or `None` when it acts
/// (and its effect shows).
pub fn refusal(state: &State, action: &Action) -> Option<String> {
    let s = &state.settings;
    if state.scene == SceneKind::Plasma {
        return three_d_only(action)
            .map(|keys| format!("{keys}: not in the plasma (2D); p or o go back to a 3D scene"));
    }
    let lights_on = state.light_on.iter().any(|&on| on);
    match action {
        Action::TogglePlasmaNormal => Some("z (plasma normal): only in the plasma scene (p)".into()),
        Action::ToggleEnvironment if !environment_can_show(s) => Some(
            "E (environment): shows in Phong with fill display (m, d); unchanged".into(),
        ),
        Action::ToggleLightVector if !light_vector_shows(s) => Some(
            "v (dot3 light vector): shows with the dot3 technique, in Phong with bump on (e, m, b); unchanged"
                .into(),
        ),
        Action::CycleTechnique if !technique_shows(s) => Some(
            "e (bump technique): shows in Phong with bump on and strength above 0 (m, b, +); unchanged"
                .into(),
        ),
        Action::BumpStronger | Action::BumpWeaker
            if s.shading != Shading::Phong || !s.bump =>
        {
            Some("+ - (bump strength): shows in Phong with bump on (m, b); unchanged".into())
        }
        Action::ShinierSpecular | Action::DullerSpecular if !specular_shows(s, lights_on) => {
            Some(
                "y Y (shininess): shows with specular on (g), a light on and fill display; unchanged"
                    .into(),
            )
        }
        _ => None,
    }
}

/// The action whose effect [`effect`] words once it is applied.
pub fn effect_of(action: &Action) -> Option<Action> {
    matches!(
        action,
        Action::BumpStronger
            | Action::BumpWeaker
            | Action::ShinierSpecular
            | Action::DullerSpecular
    )
    .then(|| action.clone())
}

/// The message that shows an applied action's effect where the status
/// line may not (a narrow screen cuts the figures first).
pub fn effect(state: &State, action: &Action) -> Option<String> {
    let s = &state.settings;
    match action {
        Action::BumpStronger | Action::BumpWeaker => Some(format!(
            "bump strength {}",
            super::view::status::format_strength(s.bump_strength)
        )),
        Action::ShinierSpecular | Action::DullerSpecular => Some(format!(
            "shininess {}",
            super::view::status::format_shininess(s.shininess)
        )),
        _ => None,
    }
}
