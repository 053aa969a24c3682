//! The file's cameras (glTF 2.0 §3.10), as relief cameras in the fitted
//! model's space: each camera node of the scene drawn, at its place in the
//! scene (for an animated model, its rest place), looking down its −Z with
//! +Y up, with its vertical field of view (perspective) or its half height
//! `ymag` (orthographic), and near and far planes, fitted like the model.
//! Both keep the picture's aspect, not the file's (`aspectRatio`, `xmag`),
//! so that nothing is stretched.

use glam::{DVec3, Mat3, Mat4, Vec3};

use super::fitted_nodes::fitted_nodes;
use crate::Camera;

/// Every camera of the scene drawn, in the order its nodes
/// are met (depth first, in the file's order), with the model's fit
/// (centre and scale) applied.
pub(super) fn cameras(document: &::gltf::Document, fit: (DVec3, f64)) -> Vec<Camera> {
    let scale = fit.1 as f32;
    fitted_nodes(document, fit)
        .into_iter()
        .filter_map(|(node, place)| match node.camera()?.projection() {
            ::gltf::camera::Projection::Perspective(p) => {
                placed(place, p.yfov(), (p.znear(), p.zfar()), scale)
            }
            ::gltf::camera::Projection::Orthographic(o) => {
                orthographic(place, o.ymag(), (o.znear(), o.zfar()), scale)
            }
        })
        .collect()
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
        orthographic: None,
    })
}

/// The orthographic camera at `place` whose view is `ymag` tall on either
/// side of its axis, its planes (and `ymag`) scaled by `scale`; none when
/// the place or `ymag` cannot make one. Its field of view, which the
/// projection does not read, is left at 60°.
fn orthographic(place: Mat4, ymag: f32, (znear, zfar): (f32, f32), scale: f32) -> Option<Camera> {
    let half = ymag.abs() * scale;
    if !(half.is_finite() && half > 0.0) {
        return None;
    }
    let camera = placed(
        place,
        60f32.to_radians(),
        (znear.max(0.0), Some(zfar)),
        scale,
    )?;
    Some(Camera {
        // The near plane may be at the eye (znear = 0 is allowed).
        near: znear.max(0.0) * scale,
        orthographic: Some(half),
        ..camera
    })
}
