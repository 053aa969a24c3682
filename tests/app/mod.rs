//! The application: keys, update, the loop, the view, panels.

mod event_loop;
mod huge_terminal;
mod key_sweep;
mod keys;
mod modes;
mod resizes;
mod stage;
mod texture_app;
mod texture_panel;
mod update;
mod view;
mod zoom;
