//! Where each map of a model material reads its texture coordinate
//! (docs/models.md). A glTF material may read its maps from two texture
//! coordinate sets and move each map by its own `KHR_texture_transform`:
//! the vertices' `uv` is what the colour texture reads, and every other map
//! reads either it or the mesh's second set (`Mesh::uv2`), then its own
//! affine transform. A map that reads the vertices' `uv` as it is costs
//! nothing per pixel.

use glam::{Affine2, Mat2, Vec2};

/// One map's texture coordinate: the set it reads and the transform after it.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MapUv {
    /// Reads the mesh's second set (`Mesh::uv2`) instead of the vertices' `uv`.
    pub second: bool,
    /// Applied to that coordinate (none: read as stored).
    pub transform: Option<Affine2>,
}

impl MapUv {
    /// The map reads the vertices' `uv` as it is.
    pub fn is_vertex_uv(&self) -> bool {
        !self.second && self.transform.is_none()
    }

    /// The map's coordinate at a point whose stored coordinates are `uv`
    /// (the vertices' set) and `uv2` (the second set).
    pub fn at(&self, uv: Vec2, uv2: Vec2) -> Vec2 {
        let read = if self.second { uv2 } else { uv };
        self.transform.map_or(read, |t| t.transform_point2(read))
    }

    /// The linear part of the map's transform (identity when it has none):
    /// how a footprint in the set it reads becomes one in the map.
    pub fn linear(&self) -> Mat2 {
        self.transform.map_or(Mat2::IDENTITY, |t| t.matrix2)
    }
}

/// The texture coordinates of a material's maps other than its colour
/// texture (which, with its alpha mask, reads the vertices' `uv`). Each
/// glTF map has its own entry: a file may give each its own set and
/// transform, the clearcoat's three maps included.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MapUvs {
    pub normal: MapUv,
    /// The metallic-roughness map (the highlight's map elsewhere).
    pub specular: MapUv,
    pub occlusion: MapUv,
    pub emissive: MapUv,
    /// `KHR_materials_specular`'s `specularTexture` (strength).
    pub specular_strength: MapUv,
    /// `KHR_materials_specular`'s `specularColorTexture`.
    pub specular_colour: MapUv,
    /// `KHR_materials_clearcoat`'s `clearcoatTexture`.
    pub coat: MapUv,
    /// `KHR_materials_clearcoat`'s `clearcoatRoughnessTexture`.
    pub coat_roughness: MapUv,
    /// `KHR_materials_clearcoat`'s `clearcoatNormalTexture`.
    pub coat_normal: MapUv,
    /// `KHR_materials_sheen`'s `sheenColorTexture`.
    pub sheen_colour: MapUv,
    /// `KHR_materials_sheen`'s `sheenRoughnessTexture`.
    pub sheen_roughness: MapUv,
    /// `KHR_materials_transmission`'s `transmissionTexture`.
    pub transmission: MapUv,
}

impl MapUvs {
    /// Every map reads the vertices' `uv` as it is.
    pub fn all_vertex_uv(&self) -> bool {
        self.all().iter().all(MapUv::is_vertex_uv)
    }

    /// Some map reads the mesh's second set.
    pub fn reads_second_set(&self) -> bool {
        self.all().iter().any(|m| m.second)
    }

    fn all(&self) -> [MapUv; 12] {
        [
            self.normal,
            self.specular,
            self.occlusion,
            self.emissive,
            self.specular_strength,
            self.specular_colour,
            self.coat,
            self.coat_roughness,
            self.coat_normal,
            self.sheen_colour,
            self.sheen_roughness,
            self.transmission,
        ]
    }
}

/// The linear map taking a triangle's change in `uv` to its change in
/// `uv2` (the two sets are both affine across the triangle), or `None`
/// when the `uv` triangle has no area: a footprint measured in `uv` then
/// says nothing about `uv2`.
pub fn second_set_jacobian(uv: &[Vec2; 3], uv2: &[Vec2; 3]) -> Option<Mat2> {
    let from = Mat2::from_cols(uv[1] - uv[0], uv[2] - uv[0]);
    let to = Mat2::from_cols(uv2[1] - uv2[0], uv2[2] - uv2[0]);
    let det = from.determinant();
    let scale = from.x_axis.length() * from.y_axis.length();
    if !det.is_finite() || det.abs() <= 1e-7 * scale || scale == 0.0 {
        return None;
    }
    let j = to * from.inverse();
    j.is_finite().then_some(j)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_map_reads_its_set_then_its_transform() {
        let uv = Vec2::new(0.25, 0.5);
        let uv2 = Vec2::new(0.75, 0.125);
        assert_eq!(MapUv::default().at(uv, uv2), uv);
        let second = MapUv {
            second: true,
            transform: None,
        };
        assert_eq!(second.at(uv, uv2), uv2);
        // Scale 2 then offset (0.5, 0): (0.75, 0.125) → (2.0, 0.25).
        let moved = MapUv {
            second: true,
            transform: Some(Affine2::from_scale_angle_translation(
                Vec2::splat(2.0),
                0.0,
                Vec2::new(0.5, 0.0),
            )),
        };
        assert_eq!(moved.at(uv, uv2), Vec2::new(2.0, 0.25));
        assert!(!moved.is_vertex_uv() && MapUv::default().is_vertex_uv());
    }

    #[test]
    fn the_jacobian_carries_uv_steps_to_the_second_set() {
        // uv2 = (2u + 0.5, v/2 − u): steps (1, 0) → (2, −1), (0, 1) → (0, ½).
        let uv = [Vec2::ZERO, Vec2::X, Vec2::Y];
        let f = |p: Vec2| Vec2::new(2.0 * p.x + 0.5, 0.5 * p.y - p.x);
        let j = second_set_jacobian(&uv, &uv.map(f)).unwrap();
        assert!((j * Vec2::X - Vec2::new(2.0, -1.0)).length() < 1e-6);
        assert!((j * Vec2::Y - Vec2::new(0.0, 0.5)).length() < 1e-6);
        // A uv triangle with no area gives none.
        assert_eq!(second_set_jacobian(&[Vec2::ZERO; 3], &uv), None);
    }
}
