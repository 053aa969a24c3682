//! What `update` asks the event loop to do: the effects a pure update
//! cannot have itself.

use relief_scene::{ModelChoice, SceneKind};

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
