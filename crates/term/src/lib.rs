//! Framebuffer → terminal: half-block and finer symbol cells, colour depth, a byte-frugal
//! backend with synchronized frames, input decoding, pacing by the
//! terminal's replies and terminal hygiene.

pub mod ansi;
pub mod backend;
pub mod backlog;
pub mod cell_rects;
pub mod cells;
pub mod color;
pub mod counting;
pub mod depth;
pub mod fit;
pub mod format;
pub mod guard;
pub mod halfblock;
pub mod hold;
pub mod input;
pub mod iterm;
pub mod kitty;
pub mod median_cut;
pub mod modes;
pub mod oklab;
pub mod pacing;
pub mod palette;
pub mod pixel_view;
pub mod probe;
pub mod sixel;
pub mod symbols;
pub mod wait;

pub use backend::SgrBackend;
pub use cells::SymbolCells;
pub use color::ColorDepth;
pub use format::Format;
pub use halfblock::HalfBlocks;
pub use symbols::Symbols;
