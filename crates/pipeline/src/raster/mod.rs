//! Rasterization: homogeneous clipping, fixed-point setup with the top-left
//! fill rule, and the perspective-correct pixel loop.

pub mod aa;
pub mod alpha;
pub mod backdrop;
pub mod clip;
pub mod fill;
pub mod frames;
pub mod pending;
pub mod scan;
pub mod setup;
pub mod strokes;
pub mod wire;

pub use clip::{ClipVertex, Clipped, clip_triangle};
pub use scan::{Band, raster_triangle};
pub use setup::{ScreenTri, setup, setup_reaching};
