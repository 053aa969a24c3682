//! The terminal side: encoder bytes, colours, input decoding.
//!
//! One test crate per area (each file a module) so the suite links a few
//! binaries instead of one per file.

#[path = "../common/screen.rs"]
mod screen;

mod bytes;
mod colour;
mod encoder;
mod input;
mod pixels;
