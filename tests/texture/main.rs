//! Textures: loading every format, filters, filtered bump techniques, normal-map files.
//!
//! One test crate per area (each file a module) so the suite links a few
//! binaries instead of one per file.

#[path = "../common/mod.rs"]
mod common;
#[path = "../techniques_scenes/mod.rs"]
mod techniques_scenes;

mod dot3_filtered;
mod emboss_filtered;
mod filter;
mod normal_map_file;
mod picture;
mod render;
mod textures;
