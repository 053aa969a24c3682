//! Terminal events become actions: keys through the key table
//! ([`super::keys`]), mouse reports by where they land and what the state
//! makes a drag do.

use crossterm::event::{Event, KeyModifiers, MouseButton, MouseEventKind};

use super::action::{Action, DragButton};
use super::keys::action_for_key;
use super::state::State;
use relief_scene::SceneKind;

/// The action a terminal event asks for in this state, if any.
pub fn action_for_event(state: &State, event: &Event) -> Option<Action> {
    match event {
        Event::Key(key) => action_for_key(state, key),
        Event::Mouse(mouse) => {
            let mods = mouse.modifiers;
            let button = |b: MouseButton| match b {
                MouseButton::Left if mods.contains(KeyModifiers::SHIFT) => Some(DragButton::Pan),
                MouseButton::Left if mods.contains(KeyModifiers::CONTROL) || state.light_drag => {
                    Some(DragButton::Light)
                }
                MouseButton::Left => Some(DragButton::Left),
                MouseButton::Right => Some(DragButton::Right),
                MouseButton::Middle => Some(DragButton::Pan),
            };
            let (col, row) = (mouse.column, mouse.row);
            if state.textures.contains(col, row) {
                // Over the open texture panel: the rows take the clicks and
                // the wheel scrolls them (a drag from outside goes on).
                return match mouse.kind {
                    MouseEventKind::Down(b) => {
                        button(b).map(|button| Action::TexturesClick { button, col, row })
                    }
                    MouseEventKind::ScrollUp => Some(Action::TexturesScroll(-1)),
                    MouseEventKind::ScrollDown => Some(Action::TexturesScroll(1)),
                    MouseEventKind::Drag(b) if state.drag.is_some() => {
                        button(b).map(|button| Action::MouseDrag { button, col, row })
                    }
                    MouseEventKind::Up(_) => Some(Action::MouseUp),
                    _ => None,
                };
            }
            if state.scene == SceneKind::Plasma {
                // The light follows the pointer, pressed or not; nothing turns.
                return match mouse.kind {
                    MouseEventKind::Moved | MouseEventKind::Down(_) | MouseEventKind::Drag(_) => {
                        Some(Action::Pointer { col, row })
                    }
                    _ => None,
                };
            }
            match mouse.kind {
                MouseEventKind::Down(b) => {
                    button(b).map(|button| Action::MouseDown { button, col, row })
                }
                MouseEventKind::Drag(b) => {
                    button(b).map(|button| Action::MouseDrag { button, col, row })
                }
                MouseEventKind::Up(_) => Some(Action::MouseUp),
                MouseEventKind::ScrollUp => Some(Action::ZoomIn),
                MouseEventKind::ScrollDown => Some(Action::ZoomOut),
                _ => None,
            }
        }
        Event::Paste(text) => Some(Action::Paste(text.clone())),
        Event::Resize(..) => Some(Action::Resize),
        _ => None,
    }
}
