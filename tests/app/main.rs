//! The application: keys, update, the loop, the view, panels.
//!
//! One test crate per area (each file a module) so the suite links a few
//! binaries instead of one per file.

#[path = "../hostile/mod.rs"]
mod hostile;
#[path = "../common/screen.rs"]
mod screen;

mod contained_panics;
mod event_loop;
mod huge_terminal;
mod keys;
mod modes;
mod resizes;
mod stage;
mod texture_app;
mod texture_panel;
mod update;
mod view;
mod zoom;
