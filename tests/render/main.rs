//! The renderer on the raw framebuffer: coverage, reference pixels, hard cases, techniques, packets.
//!
//! One test crate per area (each file a module) so the suite links a few
//! binaries instead of one per file.

#[path = "../common/mod.rs"]
mod common;
#[path = "../hostile/mod.rs"]
mod hostile;
#[path = "../techniques_scenes/mod.rs"]
mod techniques_scenes;

mod aa;
mod anchors;
mod coverage;
mod display;
mod environment;
mod flags;
mod hard_cases;
mod ibl;
mod model_view;
mod overdraw;
mod packets;
mod pbr;
mod plan;
mod plasma;
mod reference;
mod shadow;
mod specular;
mod tangent_frames;
mod techniques;
mod truth;
