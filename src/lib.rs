//! relief: bump-mapped 3D scenes rendered on the CPU, shown in the terminal.
//!
//! Data flows one way, one crate per stage: `relief-scene` → `relief-pipeline`
//! → `relief-core`'s framebuffer → `relief-term`. This crate holds the
//! application: its Elm-style core and runtime (`app`), the command line
//! (`cli`) and the headless commands (`still`).

pub mod app;
pub mod cli;
pub mod process;
pub mod still;
