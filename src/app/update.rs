//! The pure `update` every action goes through: it changes the [`State`]
//! and may ask the event loop for a [`Command`].

use glam::{Vec2, Vec3};

use super::action::{Action, DragButton};
use super::line_edit::{self, Edit};
use super::playback;
use super::state::{
    AUTO_ROTATE_SPEED, AXES, DEG_PER_COL, DEG_PER_ROW, Drag, PAN_MAX, PAN_PER_COL, PAN_PER_ROW,
    Panel, State, ZOOM_STEP, format_angle,
};
use crate::options::text::parse_finite;
use crate::sanitize::clean;
use crate::scene::camera::{MAX_DISTANCE, MIN_DISTANCE, REFERENCE_DISTANCE};
use crate::scene::{ModelChoice, SceneKind};
use crate::settings::normalize_degrees;

/// Longest text an orientation field takes.
const FIELD_MAX: usize = 24;

/// More lines than the help can ever have (the view clamps to what the
/// screen needs; the loop clamps the state with it).
const HELP_SCROLL_MAX: u16 = 1000;

/// Longest path the prompt takes.
const PROMPT_MAX: usize = 4096;

/// Something `update` asks the event loop to do.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Command {
    SavePng,
    /// Apply the next (true) or previous texture of the list.
    CycleTexture(bool),
    /// Re-read the current texture from disk.
    ReloadTexture,
    /// Report the texture list with its previews (the texture panel opened).
    ListTextures,
    /// Apply entry `i` of the texture list.
    SelectTexture(usize),
    /// Take the heights from this entry of the list (`None`: each texture's own).
    SetHeights(Option<usize>),
    /// Add the paths of a paste to the texture list and apply the last one.
    AddPaths(String),
    /// Build this scene (and model); the loop answers with [`Action::SceneBuilt`].
    BuildScene(SceneKind, ModelChoice),
    /// Complete this path from the files on disk (the prompt's text before
    /// its cursor); the loop answers with [`Action::PromptCompleted`].
    CompletePath(String),
    /// Ctrl-Z: give the terminal back and stop until resumed.
    Suspend,
    /// Esc while a model loads: stop the load, keep the scene shown.
    CancelLoad,
}

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

/// [`update`]'s work once the action is accepted.
fn apply(state: &mut State, action: Action) -> Option<Command> {
    let s = &mut state.settings;
    match action {
        Action::Quit => state.quit = true,
        Action::Option { name, press } => {
            if let Some(opt) = crate::options::find(name) {
                opt.press(s, press);
            }
        }
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
        Action::ResetView => {
            state.settings.rotation = state.start_rotation;
            state.distance = state.start_distance;
            state.pan = Vec2::ZERO;
            state.light_turn = Vec2::ZERO;
            state.auto_rotate = false;
            state.drag = None;
        }
        Action::ToggleAutoRotate => state.auto_rotate = !state.auto_rotate,
        Action::TogglePlay => playback::toggle(state),
        Action::NextClip => playback::next_clip(state),
        Action::StepClip(frames) => playback::step(state, frames),
        Action::Tick { seconds } => {
            playback::tick(state, seconds);
            if state.auto_rotate && seconds.is_finite() && seconds > 0.0 {
                // A long stall (a slow link) is not made up for in one leap.
                let dt = seconds.min(0.25);
                state.rotate(Vec3::new(0.0, AUTO_ROTATE_SPEED * dt, 0.0));
            }
        }
        Action::SavePng => return Some(Command::SavePng),
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
        Action::OpenPrompt => {
            state.panel = Panel::default();
            state.prompt = Some(String::new());
            state.prompt_cursor = 0;
        }
        Action::PromptInput(c) => {
            if let Some(text) = &mut state.prompt
                && text.len() < PROMPT_MAX
            {
                state.prompt_cursor =
                    line_edit::insert(text, state.prompt_cursor, c.encode_utf8(&mut [0; 4]));
            }
        }
        Action::PromptBackspace => return apply(state, Action::PromptEdit(Edit::Backspace)),
        Action::PromptEdit(edit) => {
            if let Some(text) = &mut state.prompt {
                state.prompt_cursor = line_edit::apply(text, state.prompt_cursor, edit);
            }
        }
        Action::PromptComplete => {
            if let Some(text) = &state.prompt {
                let at = line_edit::clamp(text, state.prompt_cursor);
                return Some(Command::CompletePath(text[..at].to_string()));
            }
        }
        Action::PromptCompleted(found) => {
            if let Some(text) = &mut state.prompt {
                let at = line_edit::clamp(text, state.prompt_cursor);
                text.replace_range(..at, &found.completed);
                state.prompt_cursor = found.completed.len();
                state.message = match found.matches {
                    0 => Some("no file matches".into()),
                    1 => None,
                    n => {
                        let more = if n > found.choices.len() { " …" } else { "" };
                        Some(clean(&format!(
                            "{n} matches: {}{more}",
                            found.choices.join("  ")
                        )))
                    }
                };
            }
        }
        Action::PromptCancel => {
            state.prompt = None;
            state.esc_closed = true;
        }
        Action::PromptSubmit => {
            let text = state.prompt.take().unwrap_or_default();
            if text.trim().is_empty() {
                state.message = Some("no path typed".to_string());
            } else {
                // The loop replaces this line with the outcome.
                state.message = Some(format!("loading {}", clean(text.trim())));
                return Some(Command::AddPaths(text));
            }
        }
        // Texture errors are one line, already sanitised, naming the file.
        Action::TextureResult(Ok(label)) => {
            state.message = Some(format!("texture {}", clean(&label)));
        }
        Action::TextureResult(Err(e)) => state.message = Some(clean(&e)),
        Action::ToggleNormalMapFile => toggle_normal_map_file(state),
        Action::CycleSymbols => state.symbols = state.symbols.next(),
        Action::CycleFormat => {
            state.output.cycle();
            state.message = state.output.choice.note.clone();
        }
        Action::ToggleLight(i) => {
            if let Some(on) = state.light_on.get_mut(i) {
                *on = !*on;
            }
        }
        Action::TogglePlasmaNormal => state.plasma_normal = state.plasma_normal.toggle(),
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
        Action::SceneBuilt(Ok((scene, model))) => {
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
            // Its clips, if any, come with its notes.
            playback::take_clips(state, Vec::new());
            // A model file opened from the prompt or a paste joins the `o` cycle.
            if let ModelChoice::File(path) = &model {
                state.obj = Some(path.clone());
            }
            state.model = model;
        }
        Action::ModelNotes(notes) => {
            if notes.points {
                s.display = crate::settings::Display::Points;
            }
            playback::take_clips(state, notes.clips);
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
        Action::SceneBuilt(Err(e)) => {
            state.loading = None;
            state.message = Some(clean(&e));
        }
        Action::Pointer { col, row } => {
            if state.scene == SceneKind::Plasma {
                state.pointer = Some((col, row));
            }
        }
        Action::Saved(Ok(path)) => state.message = Some(format!("saved {}", clean(&path))),
        Action::Saved(Err(e)) => state.message = Some(format!("not saved: {}", clean(&e))),
        Action::ToggleHelp => {
            state.help = !state.help;
            state.help_scroll = 0;
        }
        Action::HelpScroll(lines) => {
            let to = i64::from(state.help_scroll) + i64::from(lines);
            state.help_scroll = to.clamp(0, i64::from(HELP_SCROLL_MAX)) as u16;
        }
        Action::HelpPage(pages) => {
            let lines = i64::from(pages) * i64::from(state.help_page.max(1));
            let to = i64::from(state.help_scroll) + lines;
            state.help_scroll = to.clamp(0, i64::from(HELP_SCROLL_MAX)) as u16;
        }
        Action::HelpPageFits(lines) => state.help_page = lines.max(1),
        Action::ToggleCost => state.cost_panel = !state.cost_panel,
        Action::CloseHelp => {
            state.help = false;
            state.esc_closed = true;
        }
        Action::Escape => {
            // Esc stops a load, else closes the top overlay; it quits only
            // when none is open and the Esc before it did not just close one.
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
        }
        Action::Suspend => return Some(Command::Suspend),
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
        Action::PanelCancel => {
            let applied: Vec<String> = AXES
                .iter()
                .enumerate()
                .filter(|(axis, _)| state.panel.applied[*axis])
                .map(|(axis, name)| {
                    format!("{name} {}°", format_angle(state.settings.rotation[axis]))
                })
                .collect();
            state.panel = Panel::default();
            state.esc_closed = true;
            state.message = Some(if applied.is_empty() {
                "orientation unchanged".into()
            } else {
                format!("{} applied; the other edits dropped", applied.join(", "))
            });
        }
        Action::MouseDown { button, col, row } => state.drag = Some(Drag { button, col, row }),
        Action::MouseDrag { button, col, row } => {
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
                            let turn =
                                state.light_turn + Vec2::new(dx * DEG_PER_COL, dy * DEG_PER_ROW);
                            state.light_turn = turn.map(normalize_degrees);
                        }
                    }
                }
                // The press was missed (or the other button): start from here.
                _ => {}
            }
            state.drag = Some(Drag { button, col, row });
        }
        Action::MouseUp => state.drag = None,
        Action::Paste(text) => {
            if let Some(line) = &mut state.prompt {
                // Into the prompt as typed text; line breaks end nothing here.
                let room = PROMPT_MAX.saturating_sub(line.len());
                let typed: String = text
                    .chars()
                    .filter(|c| *c != '\n' && *c != '\r')
                    .take(room)
                    .collect();
                state.prompt_cursor = line_edit::insert(line, state.prompt_cursor, &typed);
                return None;
            }
            let shown: String = clean(&text).chars().take(200).collect();
            match state.panel.focus {
                Some(_) => {
                    for c in shown.chars() {
                        update(state, Action::PanelInput(c));
                    }
                }
                // A file dragged onto the terminal: into the texture list
                // (the loop replaces this line with the outcome).
                None => {
                    state.message = Some(format!("pasted: {shown}"));
                    return Some(Command::AddPaths(text));
                }
            }
        }
        Action::Resize | Action::Unbound => {}
        Action::HelpFits(max) => state.help_scroll = state.help_scroll.min(max),
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
    s.normal_map_file = !crate::plan::normal_map_file_shows(s, true);
    let mut text = if s.normal_map_file {
        format!("normal map: file {}", clean(name))
    } else {
        "normal map: derived from the height map".to_string()
    };
    if s.normal_map_file && s.technique != crate::settings::Technique::Dot3 {
        s.technique = crate::settings::Technique::Dot3;
        text.push_str(" (technique switched to dot3)");
    }
    if !crate::plan::bump_can_show(s) {
        text.push_str("; shows in Phong with bump on (m, b)");
    }
    state.message = Some(text);
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
