//! Per-pixel colour: flat, Gouraud and Phong kernels, Blinn bump, texturing.
//!
//! A `TriShader` is built once per visible triangle with everything its
//! pixels need; the rasterizer then runs one monomorphised loop per kind, so
//! the choice of stages is made per draw, never per pixel.

pub mod brdf;
pub mod bump;
pub mod core;
pub mod dot3;
pub mod emboss;
pub mod environment;
pub mod interpolate;
pub mod kernels;
pub mod lanes;
pub mod lighting;
pub mod map_uv;
pub mod material;
pub mod packet;
pub mod parallax;
pub mod pbr;
pub mod sampled;
pub mod shader;
pub mod sheen;
pub mod specular;
pub mod split_sum;
pub mod table;
pub mod tangent;

pub use shader::{GouraudTri, PhongTri, PixelShader, ShadeCtx, TexturedFlatTri, TriShader};
