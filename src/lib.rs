//! relief: bump-mapped 3D scenes rendered on the CPU, shown in the terminal.
//!
//! Data flows one way: scene → plan → raster/shade → framebuffer → term.

pub mod app;
pub mod bench;
pub mod budget;
pub mod cli;
pub mod contain;
pub mod framebuffer;
pub mod options;
pub mod plan;
pub mod plasma;
pub mod raster;
pub mod render;
pub mod sanitize;
pub mod scene;
pub mod settings;
pub mod shade;
pub mod shadow;
pub mod stats;
pub mod still;
pub mod term;
pub mod texture;

pub use framebuffer::{Framebuffer, Rgb};
pub use render::Renderer;
pub use scene::Scene;
pub use settings::Settings;
pub use stats::{Counters, FrameStats};
