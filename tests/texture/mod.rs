//! Textures: loading every format, filters, filtered bump techniques, normal-map files.

mod dot3_filtered;
mod emboss_filtered;
mod filter;
mod normal_map_file;
mod picture;
mod render;
mod textures;
