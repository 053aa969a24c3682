//! The path prompt's actions, and pastes (into the prompt, the orientation
//! fields or the texture list).

use super::super::action::Action;
use super::super::command::Command;
use super::super::line_edit::{self, Edit};
use super::super::state::{Panel, State};
use relief_core::sanitize::clean;

/// Longest path the prompt takes.
const PROMPT_MAX: usize = 4096;

/// Applies a prompt action (the ones [`super::apply`] routes here).
pub(super) fn apply(state: &mut State, action: Action) -> Option<Command> {
    match action {
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
        Action::PromptCompleted(found) => completed(state, found),
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
        Action::Paste(text) => return paste(state, text),
        // Not a prompt action: `apply` routes none of the others here.
        _ => {}
    }
    None
}

/// The loop completed the path before the cursor: replace it, and say how
/// many files matched.
fn completed(state: &mut State, found: line_edit::Completion) {
    let Some(text) = &mut state.prompt else {
        return;
    };
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

/// A paste goes into the open prompt, else the focused orientation field,
/// else the texture list.
fn paste(state: &mut State, text: String) -> Option<Command> {
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
            // Typed into the focused field (the paste, a key of the user,
            // already cleared the message).
            for c in shown.chars() {
                super::panel::apply(state, Action::PanelInput(c));
            }
            None
        }
        // A file dragged onto the terminal: into the texture list
        // (the loop replaces this line with the outcome).
        None => {
            state.message = Some(format!("pasted: {shown}"));
            Some(Command::AddPaths(text))
        }
    }
}
