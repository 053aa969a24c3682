//! What a loaded model's material adds to a Phong-family pixel beyond
//! relief's own material (docs/models.md): light it gives off (glTF
//! emissive), an ambient occlusion map, a specular colour and exponent
//! (MTL `Ks`, `Ns`), the filter its sampler asks for (glTF). The plan
//! carries the terms only for the objects whose material has them and only
//! when they change the picture, so every other pixel runs as before.

use std::sync::Arc;

use glam::{Vec2, Vec3};

use crate::settings::Filter;
use crate::texture::Level;

/// A model material's extra terms.
#[derive(Clone, Debug, PartialEq)]
pub struct MaterialTerms {
    /// Added to the shaded colour (glTF `emissiveFactor` × the
    /// `KHR_materials_emissive_strength`), times `emissive_map`'s RGB.
    pub emissive: Vec3,
    pub emissive_map: Option<Arc<Level>>,
    /// Ambient occlusion: the map's red channel and the strength s; the
    /// ambient term is scaled by 1 + s·(red − 1).
    pub occlusion: Option<(Arc<Level>, f32)>,
    /// Multiplies the highlight (MTL `Ks`; white: the highlight as it is).
    pub specular_color: Vec3,
    /// The highlight's exponent instead of `--shininess` (MTL `Ns`).
    pub shininess: Option<f32>,
    /// The filter the model's sampler asks for instead of the view's.
    pub filter: Option<Filter>,
    /// Where the emissive and occlusion maps came from, for the texture
    /// panel: (which map, its name).
    pub map_names: Vec<(&'static str, String)>,
    /// An alpha mask: pixels whose opacity is below the cutoff are not drawn.
    pub cutout: Option<Cutout>,
}

/// An alpha mask (glTF `alphaMode` MASK, and BLEND drawn as MASK at 0.5;
/// MTL `d`/`Tr` and `map_d` at 0.5): coverage, not blending.
#[derive(Clone, Debug, PartialEq)]
pub struct Cutout {
    /// The constant opacity (glTF base colour factor's alpha, MTL `d`).
    pub factor: f32,
    /// Opacity per texel in the red channel (glTF base colour alpha, MTL
    /// `map_d`'s grey), read bilinearly; none: `factor` everywhere.
    pub map: Option<Arc<Level>>,
    /// Opacity below this is not drawn.
    pub cutoff: f32,
}

impl Cutout {
    /// Whether the pixel at `uv` is drawn.
    #[inline]
    pub fn opaque(&self, uv: Vec2) -> bool {
        let a = match &self.map {
            Some(map) => self.factor * map.bilinear(uv.x, uv.y)[0],
            None => self.factor,
        };
        a >= self.cutoff
    }
}

impl Default for MaterialTerms {
    fn default() -> Self {
        MaterialTerms {
            emissive: Vec3::ZERO,
            emissive_map: None,
            occlusion: None,
            specular_color: Vec3::ONE,
            shininess: None,
            filter: None,
            map_names: Vec::new(),
            cutout: None,
        }
    }
}

impl MaterialTerms {
    /// Whether these terms change a pixel lit by `ambient`, with highlights
    /// drawn or not: otherwise the plan leaves them out.
    pub fn shade(&self, ambient: Vec3, specular: bool) -> bool {
        self.cutout.is_some()
            || self.emissive.max_element() > 0.0
            || self
                .occlusion
                .as_ref()
                .is_some_and(|(_, s)| *s != 0.0 && ambient.max_element() > 0.0)
            || (specular && self.specular_color != Vec3::ONE)
    }

    /// The diffuse light at `uv` with the ambient part occluded: `light`
    /// holds the plan's `ambient` once (the light loop starts from it).
    #[inline]
    pub fn occlude(&self, ambient: Vec3, uv: Vec2, light: Vec3) -> Vec3 {
        match &self.occlusion {
            Some((map, strength)) => {
                let occ = map.bilinear(uv.x, uv.y)[0];
                light - ambient * (strength * (1.0 - occ))
            }
            None => light,
        }
    }

    /// The light given off at `uv`.
    #[inline]
    pub fn emission(&self, uv: Vec2) -> Vec3 {
        match &self.emissive_map {
            Some(map) => {
                let t = map.bilinear(uv.x, uv.y);
                self.emissive * Vec3::new(t[0], t[1], t[2])
            }
            None => self.emissive,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn occlusion_strength_scales_the_ambient_part_only() {
        // A map of red 0.25: strength 1 keeps a quarter of the ambient,
        // strength 0.5 keeps 1 + 0.5·(0.25 − 1) = 0.625 of it.
        let map = Arc::new(Level::solid(1, 1, [0.25, 0.0, 0.0, 0.0]));
        let ambient = Vec3::splat(0.2);
        let light = Vec3::splat(0.2 + 0.5);
        let full = MaterialTerms {
            occlusion: Some((map.clone(), 1.0)),
            ..Default::default()
        };
        let half = MaterialTerms {
            occlusion: Some((map, 0.5)),
            ..Default::default()
        };
        let at = Vec2::new(0.3, 0.7);
        assert!(
            (full.occlude(ambient, at, light) - Vec3::splat(0.05 + 0.5))
                .abs()
                .max_element()
                < 1e-6
        );
        assert!(
            (half.occlude(ambient, at, light) - Vec3::splat(0.125 + 0.5))
                .abs()
                .max_element()
                < 1e-6
        );
    }

    #[test]
    fn terms_that_change_nothing_are_left_out() {
        let none = MaterialTerms::default();
        assert!(!none.shade(Vec3::splat(0.2), true));
        let occluded = MaterialTerms {
            occlusion: Some((Arc::new(Level::solid(1, 1, [0.0; 4])), 1.0)),
            ..Default::default()
        };
        assert!(occluded.shade(Vec3::splat(0.2), false));
        assert!(!occluded.shade(Vec3::ZERO, false), "no ambient to occlude");
        let tinted = MaterialTerms {
            specular_color: Vec3::new(1.0, 0.5, 0.5),
            ..Default::default()
        };
        assert!(tinted.shade(Vec3::ZERO, true));
        assert!(!tinted.shade(Vec3::ZERO, false), "no highlight to tint");
    }
}
