//! The file's perspective cameras (glTF 2.0 §3.10), as relief cameras in
//! the fitted model's space: each camera node of the scene drawn, at its
//! place in the scene (for an animated model, its rest place), looking
//! down its −Z with +Y up, with its vertical field of view and near and
//! far planes fitted like the model.

use glam::{DVec3, Mat3, Mat4, Vec3};

use super::reading::MAX_DEPTH;
use crate::Camera;

/// Every perspective camera of the scene drawn, in the order its nodes
/// are met (depth first, in the file's order), with the model's fit
/// (centre and scale) applied.
pub(super) fn cameras(document: &::gltf::Document, (centre, scale): (DVec3, f64)) -> Vec<Camera> {
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
        if let Some(camera) = node.camera()
            && let ::gltf::camera::Projection::Perspective(p) = camera.projection()
            && let Some(c) = placed(fit * world, p.yfov(), (p.znear(), p.zfar()), scale as f32)
        {
            out.push(c);
        }
        let children: Vec<_> = node.children().collect();
        stack.extend(children.into_iter().rev().map(|c| (c, world, depth + 1)));
    }
    out
}

/// The camera at `place` (looking down its −Z, +Y up) with a vertical
/// field of view of `yfov` radians and its planes scaled by `scale`; none
/// when the place or the field of view cannot make one.
fn placed(place: Mat4, yfov: f32, (znear, zfar): (f32, Option<f32>), scale: f32) -> Option<Camera> {
    let linear = Mat3::from_mat4(place);
    let eye = place.transform_point3(Vec3::ZERO);
    let forward = (linear * Vec3::NEG_Z).try_normalize()?;
    let up = (linear * Vec3::Y).try_normalize()?;
    let fov = yfov.to_degrees();
    if !(eye.is_finite() && fov > 0.0 && fov < 180.0) {
        return None;
    }
    let near = (znear * scale).max(1e-3);
    let far = zfar.map_or(100.0, |f| (f * scale).max(near * 2.0));
    Some(Camera {
        eye,
        target: eye + forward,
        up,
        fov_y_degrees: fov,
        near,
        far,
    })
}
