//! What a loaded model's material adds to a Phong-family pixel beyond
//! relief's own material (docs/models.md): light it gives off (glTF
//! emissive), an ambient occlusion map, a specular colour and exponent
//! (MTL `Ks`, `Ns`), the filter its sampler asks for (glTF). The plan
//! carries the terms only for the objects whose material has them and only
//! when they change the picture, so every other pixel runs as before.

use std::sync::Arc;

use glam::{Vec2, Vec3};

use super::map_uv::{MapUv, MapUvs};
use relief_core::settings::Filter;
use relief_texture::Level;

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
    /// The material's own colour, in 0..=1 (glTF `baseColorFactor`),
    /// which the loader multiplies into the vertex colours: the albedo when
    /// they are off (`--colors off` drops a file's vertex colours only).
    pub colour_factor: Vec3,
    /// The highlight's exponent instead of `--shininess` (MTL `Ns`).
    pub shininess: Option<f32>,
    /// The filter the model's sampler asks for instead of the view's.
    pub filter: Option<Filter>,
    /// Where the emissive and occlusion maps came from, for the texture
    /// panel: (which map, its name).
    pub map_names: Vec<(&'static str, String)>,
    /// The material's opacity: an alpha mask (pixels below the cutoff are
    /// not drawn) or translucency (pixels composited, `Cutout::blend`).
    pub cutout: Option<Cutout>,
    /// Where the normal, specular, occlusion and emissive maps read their
    /// texture coordinates (glTF `texCoord` and `KHR_texture_transform`
    /// per map; all the vertices' `uv` for every other material).
    pub uvs: MapUvs,
    /// A metallic-roughness material (glTF's), shaded physically in the
    /// model view (`shade::pbr`); the other views draw it as before.
    pub pbr: Option<PbrMaterial>,
    /// Shaded as its base colour alone, no light (glTF
    /// `KHR_materials_unlit`), in the model view.
    pub unlit: bool,
}

/// A metallic-roughness material's own values (docs/shading.md).
#[derive(Clone, Debug, PartialEq)]
pub struct PbrMaterial {
    /// `metallicFactor`: 0 dielectric, 1 metal.
    pub metallic: f32,
    /// `roughnessFactor`: 0 mirror-smooth, 1 rough.
    pub roughness: f32,
    /// The roughness map and the channel read (glTF's metallic-roughness
    /// map: green; MTL `map_Pr`: grey), multiplied into the factor; read
    /// with the specular map's coordinates.
    pub roughness_map: Option<(Arc<Level>, usize)>,
    /// The metallic map and its channel (glTF's: blue; MTL `map_Pm`: grey).
    pub metallic_map: Option<(Arc<Level>, usize)>,
    /// The tangent-space normal map (its `scale` applied), read with the
    /// normal map's coordinates.
    pub normal: Option<Arc<relief_texture::NormalMap>>,
    /// A dielectric's reflectance head on, per channel, weight included:
    /// [`DIELECTRIC_F0`] by default (index of refraction 1.5); glTF's
    /// `KHR_materials_ior` and `KHR_materials_specular` change it.
    pub dielectric_f0: Vec3,
    /// A dielectric's reflectance at grazing angles: `KHR_materials_specular`'s
    /// weight, 1 by default. Metals reflect 1 there whatever it is.
    pub specular_weight: f32,
    /// `KHR_materials_specular`'s textures, when it has any: then
    /// `dielectric_f0` and `specular_weight` are made per pixel from them.
    pub specular_maps: Option<SpecularMaps>,
    /// A clear varnish over the material (`KHR_materials_clearcoat`).
    pub clearcoat: Option<Clearcoat>,
    /// A velvet-like sheen over the material, under the clearcoat
    /// (`KHR_materials_sheen`).
    pub sheen: Option<Sheen>,
}

/// A sheen layer (docs/shading.md, "Sheen"): the Charlie lobe of its
/// colour and roughness over the material, which is scaled by 1 −
/// max(colour)·E(N·V), E the lobe's directional albedo.
#[derive(Clone, Debug, PartialEq)]
pub struct Sheen {
    /// `sheenColorFactor`, linear, each channel held in 0..=1 (so the
    /// layered material never reflects more than it receives).
    pub colour: Vec3,
    /// `sheenRoughnessFactor`, 0 to 1.
    pub roughness: f32,
    /// `sheenColorTexture`: RGB, sRGB-encoded, the picture as it is.
    pub colour_map: Option<Arc<Level>>,
    /// `sheenRoughnessTexture`'s alpha, kept alone in one channel (read:
    /// red).
    pub roughness_map: Option<Arc<Level>>,
}

/// `KHR_materials_specular`'s textures (docs/shading.md): per pixel, F0 =
/// min(`f0_colour` × the colour map decoded from sRGB, 1) × w and F90 = w,
/// w = `specular_weight` × the strength map.
#[derive(Clone, Debug, PartialEq)]
pub struct SpecularMaps {
    /// f0 of the index of refraction times `specularColorFactor`, before
    /// the clamp to 1 (which follows the colour map).
    pub f0_colour: Vec3,
    /// `specularTexture`'s alpha, kept alone in one channel (read: red).
    pub strength: Option<Arc<Level>>,
    /// `specularColorTexture`: RGB, sRGB-encoded, the picture as it is.
    pub colour: Option<Arc<Level>>,
}

/// A clearcoat layer: a dielectric (F0 0.04) of its own roughness over the
/// material, on the surface's own normal or its own normal map
/// (docs/shading.md).
#[derive(Clone, Debug, PartialEq)]
pub struct Clearcoat {
    /// `clearcoatFactor`: how much of the layer there is, 0 to 1.
    pub factor: f32,
    /// `clearcoatRoughnessFactor`, 0 to 1.
    pub roughness: f32,
    /// `clearcoatTexture` and the channel read (red), multiplied into
    /// `factor`.
    pub factor_map: Option<(Arc<Level>, usize)>,
    /// `clearcoatRoughnessTexture` and the channel read (green; red when
    /// kept alone), multiplied into `roughness`.
    pub roughness_map: Option<(Arc<Level>, usize)>,
    /// `clearcoatNormalTexture`, its `scale` applied: the layer's own
    /// tangent-space normal map (none: the surface's normal, whatever the
    /// base's normal map).
    pub normal: Option<Arc<relief_texture::NormalMap>>,
}

impl Clearcoat {
    /// A layer of these factors, without maps.
    pub fn of_factors(factor: f32, roughness: f32) -> Self {
        Clearcoat {
            factor,
            roughness,
            factor_map: None,
            roughness_map: None,
            normal: None,
        }
    }
}

/// A dielectric's reflectance head on at glTF's default index of
/// refraction, 1.5: ((1.5 − 1)/(1.5 + 1))².
pub const DIELECTRIC_F0: f32 = 0.04;

/// A dielectric's reflectance head on at index of refraction `ior`:
/// ((ior − 1)/(ior + 1))², exactly [`DIELECTRIC_F0`] at 1.5; glTF's
/// `ior` 0 stands for an infinite index (1). Other values below 1, and
/// values not finite, are glTF's default.
pub fn f0_of_ior(ior: f32) -> f32 {
    if ior == 0.0 {
        1.0
    } else if ior == 1.5 || ior.is_nan() || ior < 1.0 || ior.is_infinite() {
        DIELECTRIC_F0
    } else {
        ((ior - 1.0) / (ior + 1.0)).powi(2)
    }
}

impl PbrMaterial {
    /// glTF's default material: white, fully metallic, fully rough.
    pub fn gltf_default() -> Self {
        PbrMaterial {
            metallic: 1.0,
            roughness: 1.0,
            roughness_map: None,
            metallic_map: None,
            normal: None,
            dielectric_f0: Vec3::splat(DIELECTRIC_F0),
            specular_weight: 1.0,
            specular_maps: None,
            clearcoat: None,
            sheen: None,
        }
    }
}

/// A material's opacity: an alpha mask (glTF `alphaMode` MASK; MTL
/// `d`/`Tr` and `map_d` at 0.5), or translucency composited over what is
/// behind (glTF BLEND; docs/models.md, "Transparency").
#[derive(Clone, Debug, PartialEq)]
pub struct Cutout {
    /// The constant opacity (glTF base colour factor's alpha, MTL `d`).
    pub factor: f32,
    /// Opacity per texel in the red channel (glTF base colour alpha, MTL
    /// `map_d`'s grey), read bilinearly; none: `factor` everywhere.
    pub map: Option<Arc<Level>>,
    /// Opacity below this is not drawn (a mask), or casts no shadow (a
    /// blend).
    pub cutoff: f32,
    /// Composited with its opacity, behind the opaque surfaces' depth and
    /// far to near, instead of cut at `cutoff`.
    pub blend: bool,
    /// `KHR_materials_transmission`'s texture, when the material has one
    /// (its factor is then not in `factor`).
    pub transmission: Option<TransmissionMap>,
    /// The linear colour what shows through a blended pixel is multiplied
    /// by: a transmitting glTF material's base colour factor (thin glass
    /// tints the light it lets through), else white.
    pub tint: Vec3,
}

/// How much of the light behind a thin transmitting surface comes
/// through, per texel: `strength` times the map's red, read bilinearly at
/// the map's own coordinate (from the vertices' `uv` or the second set).
#[derive(Clone, Debug, PartialEq)]
pub struct TransmissionMap {
    /// The transmission factor times what a dielectric lets through head
    /// on (1 − F0).
    pub strength: f32,
    pub map: Arc<Level>,
    /// The map's set and transform.
    pub uv: MapUv,
}

/// Below this opacity a blended pixel would change no 8-bit channel by a
/// whole step: it is not drawn.
pub const BLEND_MIN_OPACITY: f32 = 0.5 / 255.0;

impl Cutout {
    /// The opacity at a point whose coordinates are `uv` (the vertices')
    /// and `uv2` (the second set, read only by a transmission map on it),
    /// 0 to 1 (or beyond, as the factor gives).
    #[inline]
    pub fn opacity(&self, uv: Vec2, uv2: Vec2) -> f32 {
        let alpha = match &self.map {
            Some(map) => self.factor * map.bilinear(uv.x, uv.y)[0],
            None => self.factor,
        };
        match &self.transmission {
            Some(t) => {
                let at = t.uv.at(uv, uv2);
                alpha * (1.0 - t.strength * t.map.bilinear(at.x, at.y)[0])
            }
            None => alpha,
        }
    }

    /// Whether the point at `uv` (and `uv2`) is solid: drawn by a mask,
    /// casting a shadow for both kinds.
    #[inline]
    pub fn opaque(&self, uv: Vec2, uv2: Vec2) -> bool {
        self.opacity(uv, uv2) >= self.cutoff
    }

    /// Whether the opacity reads the second coordinate set.
    pub fn reads_second_set(&self) -> bool {
        self.transmission.as_ref().is_some_and(|t| t.uv.second)
    }
}

impl Default for MaterialTerms {
    fn default() -> Self {
        MaterialTerms {
            emissive: Vec3::ZERO,
            emissive_map: None,
            occlusion: None,
            specular_color: Vec3::ONE,
            colour_factor: Vec3::ONE,
            shininess: None,
            filter: None,
            map_names: Vec::new(),
            cutout: None,
            uvs: MapUvs::default(),
            pbr: None,
            unlit: false,
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
            || !self.uvs.normal.is_vertex_uv()
            || (specular && !self.uvs.specular.is_vertex_uv())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
