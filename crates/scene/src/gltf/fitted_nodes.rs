//! The nodes of the scene drawn, each with its place in the fitted model:
//! what the file's cameras and lights are placed by.

use glam::{DVec3, Mat4, Vec3};

use super::reading::MAX_DEPTH;

/// Every node of the default scene (else the first), depth first in the
/// file's order, with the model's fit (centre and scale) times its world
/// matrix; nodes deeper than `MAX_DEPTH` are left out.
pub(super) fn fitted_nodes(
    document: &::gltf::Document,
    (centre, scale): (DVec3, f64),
) -> Vec<(::gltf::Node<'_>, Mat4)> {
    let Some(scene) = document
        .default_scene()
        .or_else(|| document.scenes().next())
    else {
        return Vec::new();
    };
    let fit =
        Mat4::from_scale(Vec3::splat(scale as f32)) * Mat4::from_translation(-centre.as_vec3());
    let mut out = Vec::new();
    let mut stack: Vec<(::gltf::Node, Mat4, usize)> =
        scene.nodes().map(|n| (n, Mat4::IDENTITY, 0)).collect();
    // Popped from the end: the first root first.
    stack.reverse();
    while let Some((node, parent, depth)) = stack.pop() {
        if depth > MAX_DEPTH {
            continue;
        }
        let world = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
        let children: Vec<_> = node.children().collect();
        stack.extend(children.into_iter().rev().map(|c| (c, world, depth + 1)));
        out.push((node, fit * world));
    }
    out
}
