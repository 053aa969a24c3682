//! Animated models (docs/models.md, "Animation"): a model's node tree, its
//! clips, skins and morph targets, posed at any instant. Format-free: the
//! glTF reader fills a [`Rig`]; [`Motion`] poses the scene's objects.
//!
//! Per instant: each clip's channels set their nodes' translation,
//! rotation, scale or morph weights (`sampler`); world matrices follow the
//! tree (`pose`); then each part's vertices are made again from its rest
//! vertices (`deform`): morph targets added, then skinned by its joints'
//! matrices or carried by its node's, then fitted to the unit view.

mod deform;
mod motion;
mod pose;
mod rig;
pub mod sampler;

pub use motion::Motion;
pub use pose::Pose;
pub use rig::{Channel, Clip, Influences, Local, MorphTarget, Node, PartRig, Rig, Skin, Target};
