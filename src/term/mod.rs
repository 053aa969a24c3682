//! Framebuffer → terminal: half-block cells, colour depth, a byte-frugal
//! backend with synchronized frames, input decoding, pacing by the
//! terminal's replies and terminal hygiene.

pub mod ansi;
pub mod backend;
pub mod color;
pub mod counting;
pub mod depth;
pub mod guard;
pub mod halfblock;
pub mod input;
pub mod modes;
pub mod oklab;
pub mod pacing;
pub mod palette;
pub mod probe;
pub mod wait;

pub use backend::SgrBackend;
pub use color::ColorDepth;
pub use halfblock::HalfBlocks;
