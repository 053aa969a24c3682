//! What a key says when it cannot act where the user is: a key that would
//! change something the picture does not show is refused with a message
//! and changes nothing. The "does it show" conditions are the plan's
//! ([`relief_pipeline::plan`]), named by each option's entry
//! ([`relief_options::OPTIONS`]); this file only words the message.

use super::action::Action;
use super::state::State;
use relief_options::{OptId, Press};
use relief_scene::SceneKind;

/// The key and what it changes, for the messages (`None`: the action
/// acts everywhere, or is not a key of the 3D scenes).
fn three_d_only(action: &Action) -> Option<String> {
    Some(
        match action {
            // Every option of the table is one of the 3D scenes.
            Action::Option { id, .. } => return Some(relief_options::get(*id).key_title()),
            Action::RotateStep { .. } => "the arrows (rotation)",
            Action::ResetView => "r (reset the view)",
            Action::ZoomIn | Action::ZoomOut => "i I (zoom)",
            Action::ToggleAutoRotate => "space (auto-rotation)",
            Action::PanelNext | Action::PanelPrev => "Tab (orientation fields)",
            Action::ToggleNormalMapFile => "N (normal map)",
            Action::ToggleLight(_) => "1-4 (lights)",
            _ => return None,
        }
        .into(),
    )
}

/// What a model shaded physically does without (`shaded_physically`): the
/// height map's bump techniques and strength (its normal maps are the
/// files' own, as given) and Blinn-Phong's highlight and reflection.
const PHONG_ONLY: [OptId; 6] = [
    OptId::BumpStrength,
    OptId::Technique,
    OptId::LightVector,
    OptId::Specular,
    OptId::Shininess,
    OptId::Environment,
];

/// What shows only on filled triangles: the lighting, the texture, the
/// bump and the highlight (points and lines take the vertices' colours).
const FILL_ONLY: [OptId; 7] = [
    OptId::Shading,
    OptId::Texture,
    OptId::Bump,
    OptId::Filter,
    OptId::Technique,
    OptId::HeightDerivative,
    OptId::Specular,
];

/// What shows only in the model view of a model file: its environment,
/// turned or drawn behind it.
const MODEL_VIEW_ONLY: [OptId; 2] = [OptId::EnvironmentTurn, OptId::Backdrop];

/// What only a textured surface shows: the shadow scene has none.
const TEXTURE_ONLY: [OptId; 8] = [
    OptId::Texture,
    OptId::Bump,
    OptId::BumpStrength,
    OptId::Filter,
    OptId::Technique,
    OptId::LightVector,
    OptId::HeightDerivative,
    OptId::TangentFrames,
];

/// What only the lights show anywhere: their falloff and highlight.
const LIGHTS_ONLY: [OptId; 2] = [OptId::Attenuation, OptId::Specular];

/// What only the surface's normal shows: nothing without a light, where
/// no environment lights the surface either.
const NORMAL_ONLY: [OptId; 4] = [
    OptId::Normals,
    OptId::Bump,
    OptId::Technique,
    OptId::HeightDerivative,
];

/// Why option `id` shows nothing where the picture is: points or lines,
/// a scene without the model view's environment, flat lighting for the
/// normals, every light off, a model without colours of its own. `None`:
/// this rule does not refuse it.
fn hidden_here(state: &State, id: OptId) -> Option<&'static str> {
    use relief_core::settings::{Display, Shading};
    let s = &state.settings;
    // Without a light only the ambient term is left, which no normal
    // changes, unless an environment is reflected (the model view's light,
    // the reference scenes' `E`). A model's own lights past the fourth
    // have no key and stay on.
    let unswitched = state.in_model_view() && state.file_lights > 4;
    let strength_shows = s.bump_strength.is_finite() && s.bump_strength > 0.0;
    let dark = !s.lights || !(state.ctx().lights_on || unswitched);
    let environment_lit = state.in_model_view() || relief_pipeline::plan::environment_shows(s);
    if s.display != Display::Fill && FILL_ONLY.contains(&id) {
        Some("shows with fill display (d)")
    } else if state.scene == SceneKind::Shadow && TEXTURE_ONLY.contains(&id) {
        Some("the shadow scene has no texture (p: the model scene)")
    } else if MODEL_VIEW_ONLY.contains(&id) && !state.in_model_view() {
        Some("shows in the model view of a model file (o)")
    } else if id == OptId::Normals && s.shading == Shading::Flat {
        Some("flat lighting takes each facet's own normal (m: Gouraud or Phong)")
    } else if id == OptId::Normals && !state.features.varied_normals {
        Some("this model is flat: each corner's normal is its facet's")
    } else if id == OptId::Bump && !strength_shows && !shaded_physically(state) {
        Some("shows with a bump strength above 0 (+)")
    } else if dark && (LIGHTS_ONLY.contains(&id) || (NORMAL_ONLY.contains(&id) && !environment_lit))
    {
        Some("shows with a light on (l, 1-4)")
    } else if id == OptId::Colors && state.in_model_view() && !state.features.vertex_colours {
        Some("the model has no vertex colours of its own")
    } else if id == OptId::Texture && state.in_model_view() && !state.features.colour_texture {
        Some("the model's materials have no colour texture")
    } else if id == OptId::Filter && state.in_model_view() && !state.features.pictures {
        Some("the model's materials read no picture")
    } else if id == OptId::TangentFrames && !state.features.texture_coordinates {
        Some("the model has no texture coordinates, which the frames are drawn from")
    } else {
        None
    }
}

/// Whether the picture is the model view's physical shading: a model file
/// whose every part has a metallic-roughness material, in Phong with the
/// fill display (flat and Gouraud light it with Blinn-Phong, highlight
/// included).
fn shaded_physically(state: &State) -> bool {
    use relief_core::settings::{Display, Shading};
    let s = &state.settings;
    state.physical && s.shading == Shading::Phong && s.display == Display::Fill
}

/// The message refusing `h` on a model shaded physically where the height
/// derivative changes nothing: no height map is read there, and its
/// normal maps are read from their full-size level unless the filter reads
/// mip levels and the derivative lets it (`texture::sample::filter::
/// normal_reads_base`).
fn derivative_unused(state: &State) -> Option<String> {
    use relief_core::settings::Filter;
    let s = &state.settings;
    let why = if !state.features.normal_maps {
        "the model has no normal maps"
    } else if !s.bump {
        "the model's normal maps are off (b)"
    } else if matches!(s.filter, Filter::Nearest | Filter::Bilinear) {
        "the model's normal maps are read from their full-size level with this filter \
         (f: nearest-mip, trilinear or anisotropic read their mip levels)"
    } else {
        return None;
    };
    Some(format!(
        "{}: {why}; unchanged",
        relief_options::get(OptId::HeightDerivative).key_title()
    ))
}

/// The message refusing the texture and bump keys on a model file whose
/// parts take no material until the user chooses a texture
/// (`Scene::texture_reach`).
fn no_texture(state: &State, id: OptId) -> Option<String> {
    let waits = state.ctx().texture_waits;
    (waits && TEXTURE_ONLY.contains(&id)).then(|| {
        format!(
            "{}: the model names no texture; x, T or a picture's path lays one on it",
            relief_options::get(id).key_title()
        )
    })
}

/// The message refusing `action` in this state, or `None` when it acts
/// (and its effect shows).
pub fn refusal(state: &State, action: &Action) -> Option<String> {
    if state.scene == SceneKind::Plasma {
        return three_d_only(action)
            .map(|keys| format!("{keys}: not in the plasma (2D); p or o go back to a 3D scene"));
    }
    if let Action::Option { id, .. } = action {
        // A model waiting for a texture says how to lay one first.
        if let Some(text) = no_texture(state, *id) {
            return Some(text);
        }
        if let Some(why) = hidden_here(state, *id) {
            let title = relief_options::get(*id).key_title();
            return Some(format!("{title}: {why}; unchanged"));
        }
    }
    match action {
        Action::TogglePlasmaNormal => {
            Some("z (plasma normal): only in the plasma scene (p)".into())
        }
        Action::Option {
            id: OptId::HeightDerivative,
            ..
        } if shaded_physically(state) => derivative_unused(state),
        Action::Option {
            id: OptId::Bump, ..
        } if shaded_physically(state) && !state.features.normal_maps => Some(format!(
            "{}: the model has no normal maps; unchanged",
            relief_options::get(OptId::Bump).key_title()
        )),
        Action::Option { id, .. } if shaded_physically(state) && PHONG_ONLY.contains(id) => {
            Some(format!(
                "{}: not used by the model's physical shading in Phong \
                 (metallic-roughness); unchanged",
                relief_options::get(*id).key_title()
            ))
        }
        Action::Option { id, .. } => relief_options::get(*id).refusal(&state.ctx()),
        _ => None,
    }
}

/// The action whose effect [`effect`] words once it is applied: a number
/// moved by a key.
pub fn effect_of(action: &Action) -> Option<Action> {
    matches!(
        action,
        Action::Option {
            press: Press::Up | Press::Down,
            ..
        }
    )
    .then(|| action.clone())
}

/// The message that shows an applied action's effect where the status
/// line may not (a narrow screen cuts the figures first).
pub fn effect(state: &State, action: &Action) -> Option<String> {
    match action {
        Action::Option { id, .. } => relief_options::get(*id).shown(&state.settings),
        _ => None,
    }
}
