//! What a model's animation is made of, as read from its file.

use glam::{Mat4, Quat, Vec3};

use super::sampler::Sampler;
use crate::Vertex;

/// A node's own transform: a matrix, or translation, rotation and scale
/// (only the latter are animated).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Local {
    Matrix(Mat4),
    Trs {
        translation: Vec3,
        rotation: Quat,
        scale: Vec3,
    },
}

impl Local {
    pub fn matrix(&self) -> Mat4 {
        match *self {
            Local::Matrix(m) => m,
            Local::Trs {
                translation,
                rotation,
                scale,
            } => Mat4::from_scale_rotation_translation(scale, rotation, translation),
        }
    }
}

/// One node of the tree.
#[derive(Clone, Debug, PartialEq)]
pub struct Node {
    pub parent: Option<usize>,
    pub rest: Local,
    /// The morph weights of its mesh when no clip sets them (the node's,
    /// else its mesh's, else none).
    pub weights: Vec<f32>,
}

/// What a channel drives.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Target {
    Translation,
    Rotation,
    Scale,
    Weights,
}

/// One animated property of one node.
#[derive(Clone, Debug, PartialEq)]
pub struct Channel {
    pub node: usize,
    pub target: Target,
    pub sampler: Sampler,
}

/// One animation: its channels play together for `duration` seconds.
#[derive(Clone, Debug, PartialEq)]
pub struct Clip {
    pub name: String,
    pub duration: f32,
    pub channels: Vec<Channel>,
}

/// A skin: its joints (nodes) and the matrix that takes the mesh from its
/// bind pose into each joint's space.
#[derive(Clone, Debug, PartialEq)]
pub struct Skin {
    pub joints: Vec<usize>,
    pub inverse_bind: Vec<Mat4>,
}

/// One morph target's offsets, one per vertex of the file (empty when the
/// target does not move that attribute).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MorphTarget {
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
}

/// The joints and weights of each vertex of the file: `sets` groups of
/// four per vertex (JOINTS_0/WEIGHTS_0, then _1…), joint indices into the
/// skin's joints.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Influences {
    pub sets: usize,
    pub joints: Vec<[u16; 4]>,
    pub weights: Vec<[f32; 4]>,
}

/// How one part (one scene object) moves.
#[derive(Clone, Debug, PartialEq)]
pub struct PartRig {
    /// Its node (none: a file without scenes, drawn where it is).
    pub node: Option<usize>,
    pub skin: Option<usize>,
    /// Its vertices as built, in its mesh's own space.
    pub rest: Vec<Vertex>,
    /// The file's vertex each vertex was made from (empty: the same index).
    pub source: Vec<u32>,
    pub targets: Vec<MorphTarget>,
    pub influences: Influences,
    /// Its normals are those of its faces (the file has none): made again
    /// from the posed corners.
    pub flat: bool,
}

/// A model's tree, clips, skins and parts, and the fit that carries its
/// world space into the unit view.
#[derive(Clone, Debug, PartialEq)]
pub struct Rig {
    pub nodes: Vec<Node>,
    /// Every node after its parent.
    pub order: Vec<usize>,
    pub clips: Vec<Clip>,
    pub skins: Vec<Skin>,
    pub parts: Vec<PartRig>,
    pub fit: Mat4,
}

impl Rig {
    /// Whether anything moves when a clip plays or weights are set: some
    /// part is skinned or morphed, or some clip has a channel.
    pub fn moves(&self) -> bool {
        self.clips.iter().any(|c| !c.channels.is_empty())
    }
}
