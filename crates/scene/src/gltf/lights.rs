//! The file's own lights (KHR_lights_punctual): directional, point and spot
//! lights placed by their nodes, in the fitted model's space, with their
//! colour times intensity in the specification's units (lux for a
//! directional light; candela for point and spot lights, which fall off as
//! 1 / d² in the file's metres, windowed to zero at their range).

use glam::{DVec3, Mat3, Mat4, Vec3};

use super::fitted_nodes::fitted_nodes;
use crate::light::{Cone, DIRECTIONAL_DISTANCE, Falloff, Light};

/// Every light of the scene drawn, in the order its nodes are met (depth
/// first, in the file's order), with the model's fit (centre and scale)
/// applied; the lights of an animated model at their rest place.
pub(super) fn lights(document: &::gltf::Document, fit: (DVec3, f64)) -> Vec<Light> {
    let scale = fit.1 as f32;
    fitted_nodes(document, fit)
        .into_iter()
        .filter_map(|(node, place)| placed(&node.light()?, place, scale))
        .collect()
}

/// `light` at `place` (shining down its −Z), in a model fitted by `scale`;
/// none when the place or the numbers cannot make one.
fn placed(light: &::gltf::khr_lights_punctual::Light, place: Mat4, scale: f32) -> Option<Light> {
    use ::gltf::khr_lights_punctual::Kind;
    let at = place.transform_point3(Vec3::ZERO);
    let axis = (Mat3::from_mat4(place) * Vec3::NEG_Z).try_normalize()?;
    let color = Vec3::from(light.color()).max(Vec3::ZERO) * light.intensity().max(0.0);
    // A range of 0 or less, or none, is no range.
    let range = light
        .range()
        .filter(|r| *r > 0.0)
        .map_or(f32::INFINITY, |r| r * scale);
    let (position, color, falloff) = match light.kind() {
        Kind::Directional => (-axis * DIRECTIONAL_DISTANCE, color, Falloff::None),
        // Distances shrink by the fit's scale: 1 / d² in the file's units
        // is scale² / d² in the fitted ones.
        Kind::Point => (
            at,
            color * scale * scale,
            Falloff::InverseSquare { range, cone: None },
        ),
        Kind::Spot {
            inner_cone_angle,
            outer_cone_angle,
        } => (
            at,
            color * scale * scale,
            Falloff::InverseSquare {
                range,
                cone: Some(Cone::new(axis, inner_cone_angle, outer_cone_angle)),
            },
        ),
    };
    (position.is_finite() && color.is_finite()).then_some(Light {
        position,
        color,
        enabled: true,
        falloff,
        turns_with_model: true,
    })
}
