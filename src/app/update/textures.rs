//! The texture actions: cycling, the texture panel, the normal map file.

use super::super::action::{Action, DragButton};
use super::super::command::Command;
use super::super::state::State;
use relief_core::sanitize::clean;

/// Applies a texture action (the ones [`super::apply`] routes here).
pub(super) fn apply(state: &mut State, action: Action) -> Option<Command> {
    match action {
        Action::NextTexture => return Some(Command::CycleTexture(true)),
        Action::PrevTexture => return Some(Command::CycleTexture(false)),
        Action::ReloadTexture => return Some(Command::ReloadTexture),
        Action::ToggleTextures if state.textures.open => state.textures.open = false,
        Action::ToggleTextures => {
            let t = &mut state.textures;
            t.open = true;
            t.cursor = t.listing.current;
            t.show_cursor();
            return Some(Command::ListTextures);
        }
        Action::CloseTextures => {
            state.textures.open = false;
            state.esc_closed = true;
        }
        Action::TexturesMove(delta) => state.textures.move_cursor(delta),
        Action::TexturesChoose => {
            let t = &state.textures;
            if t.cursor < t.listing.rows.len() {
                return Some(Command::SelectTexture(t.cursor));
            }
        }
        Action::TexturesHeights => {
            let t = &state.textures;
            if t.cursor < t.listing.rows.len() {
                return Some(Command::SetHeights(t.heights_for(t.cursor)));
            }
        }
        Action::TexturesClick { button, col, row } => {
            let t = &mut state.textures;
            if let Some(i) = t.entry_at(col, row) {
                t.cursor = i;
                return Some(match button {
                    DragButton::Right => Command::SetHeights(t.heights_for(i)),
                    _ => Command::SelectTexture(i),
                });
            }
        }
        Action::TexturesScroll(delta) => state.textures.scroll_by(delta),
        Action::TexturesListed(listing) => state.textures.set_listing(listing),
        Action::TexturesFit(area) => {
            state.textures.area = area;
            state.textures.scroll = state.textures.first_shown();
        }
        // Texture errors are one line, already sanitised, naming the file.
        Action::TextureResult(Ok(label)) => {
            state.message = Some(format!("texture {}", clean(&label)));
            state.texture_chosen = true;
        }
        Action::TextureResult(Err(e)) => state.message = Some(clean(&e)),
        Action::ToggleNormalMapFile => toggle_normal_map_file(state),
        // Not a texture action: `apply` routes none of the others here.
        _ => {}
    }
    None
}

/// `N`: dot3 reads the file's normal map, or the height-derived one again.
/// Showing the file switches the technique to dot3 (the only one that reads
/// a normal map), and the message says so; while another technique is on,
/// `N` shows the file rather than turning it off unseen.
fn toggle_normal_map_file(state: &mut State) {
    let Some(name) = &state.normal_map_file else {
        state.message = Some("no normal map file: start relief with --normal-map PATH".into());
        return;
    };
    let s = &mut state.settings;
    // Off when dot3 reads the file now; else on (switching to dot3 below).
    s.normal_map_file = !relief_pipeline::plan::normal_map_file_shows(s, true);
    let mut text = if s.normal_map_file {
        format!("normal map: file {}", clean(name))
    } else {
        "normal map: derived from the height map".to_string()
    };
    if s.normal_map_file && s.technique != relief_core::settings::Technique::Dot3 {
        s.technique = relief_core::settings::Technique::Dot3;
        text.push_str(" (technique switched to dot3)");
    }
    if !relief_pipeline::plan::bump_can_show(s) {
        text.push_str("; shows in Phong with bump on (m, b)");
    }
    state.message = Some(text);
}
