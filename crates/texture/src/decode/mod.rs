//! Where a texture comes from: pictures in every format the `image` crate
//! reads, KTX2 (Basis Universal), the formats and variants it refuses (XPM, TIFF samples and
//! strips, rewritten headers), the limits that make a hostile file cost
//! nothing, and the built-in pictures (drawn by code, shipped as PNGs).

pub mod builtin;
pub mod ktx2;
pub mod load;
pub mod procedural;
pub mod resample;
pub mod size_cap;
pub mod tiff_picture;
pub mod tiff_samples;
pub mod tiff_strips;
pub mod variants;
pub mod xpm;
