//! The renderer on the raw framebuffer: coverage, reference pixels, hard cases, techniques, packets.

mod aa;
mod anchors;
mod coverage;
mod display;
mod environment;
mod flags;
mod hard_cases;
mod ibl;
mod layers;
mod model_view;
mod overdraw;
mod packets;
pub mod pbr;
mod pbr_anchor;
mod plan;
mod plasma;
mod reference;
mod shadow;
mod shared_packets;
mod specular;
mod tangent_frames;
mod techniques;
mod truth;
