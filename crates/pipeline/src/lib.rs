//! The frame pipeline: a scene and its settings become a plan, the plan is
//! rasterised and shaded (with its shadows) into the framebuffer.
//!
//! Data flows one way: plan → shadow → shade → raster → render.

pub mod plan;
pub mod raster;
pub mod render;
pub mod shade;
pub mod shadow;
