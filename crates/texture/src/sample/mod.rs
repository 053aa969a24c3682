//! How pixels read a texture: the texels' storage, levels and their
//! nearest and bilinear reads, mip chains, the one sampler every filter
//! goes through, and the maps derived from the height map (dot3 normals).

pub mod filter;
pub mod level;
pub mod mip;
pub mod normal_map;
pub mod sampler;
pub mod texels;
pub mod texture;
pub mod wrap;
