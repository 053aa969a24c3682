//! The integration tests, one module per area, in one test binary: each
//! binary instantiates and links the workspace's generic code again.
//! `memory_budget` (a counting global allocator) and `contained_panics`
//! (a process-wide panic hook) are binaries of their own.

// Helpers shared by the areas.
mod common;
#[path = "common/glb_writer.rs"]
mod glb_writer;
mod hostile;
#[path = "common/ktx2_writer.rs"]
mod ktx2_writer;
#[path = "common/screen.rs"]
mod screen;
mod ssh;
mod techniques_scenes;

mod app;
mod architecture;
mod cli;
mod e2e_tmux;
mod inputs;
mod render;
mod ssh_link;
mod term;
mod texture;
