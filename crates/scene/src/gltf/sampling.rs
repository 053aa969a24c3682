//! How a glTF material's textures are read (docs/models.md): the UV set,
//! `KHR_texture_transform` and the sampler's wrap modes and filters.
//!
//! Each map is read with its sampler's wrap modes (repeat, mirrored
//! repeat, clamp to edge: `texture::sample::wrap`, in the addressing, so
//! no map is laid out larger than it is); its coordinate is its set
//! through its texture transform, one affine matrix (`Reading::matrix`):
//! - the material's first texture (base colour, else normal, occlusion,
//!   emissive, metallic-roughness, then the extensions' maps in the order
//!   of [`maps_of`]) decides the set stored in the vertices' UVs, and its matrix is applied to them when loading (interpolating
//!   transformed UVs is transforming interpolated ones), at no cost per
//!   pixel;
//! - a map on another set reads the mesh's second set, stored only for such
//!   a material, through the matrix of the first map on that set;
//! - a map whose matrix differs from its stored set's applies the rest
//!   (its matrix after the inverse of the set's) where it is sampled
//!   (`scene::map_uv`); a third set is not stored: its maps read the first;
//! - the filters become the material's filter (`MaterialTerms::filter`).

use glam::{Affine2, Mat3, Vec2};

use crate::map_uv::{MapUv, MapUvs};
use ::gltf::texture::{MagFilter, MinFilter, WrappingMode};
use relief_core::settings::Filter;
use relief_texture::sample::wrap::{Wrap, WrapMode};

/// How a material's textures are read.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Reading {
    /// The TEXCOORD_n set.
    pub set: u32,
    /// `KHR_texture_transform` as a matrix on (u, v, 1).
    pub transform: Mat3,
    /// S and T wrap modes.
    pub wrap: [WrappingMode; 2],
    /// The filter the sampler asks for (none: the view's).
    pub filter: Option<Filter>,
}

impl Default for Reading {
    fn default() -> Self {
        Reading {
            set: 0,
            transform: Mat3::IDENTITY,
            wrap: [WrappingMode::Repeat; 2],
            filter: None,
        }
    }
}

/// Which map of a material a texture reference is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    BaseColor,
    Normal,
    Occlusion,
    Emissive,
    MetallicRoughness,
    /// `KHR_materials_specular`'s `specularTexture` (its alpha).
    SpecularStrength,
    /// `KHR_materials_specular`'s `specularColorTexture`.
    SpecularColour,
    /// `KHR_materials_clearcoat`'s `clearcoatTexture` (its red).
    Coat,
    /// `KHR_materials_clearcoat`'s `clearcoatRoughnessTexture` (its green).
    CoatRoughness,
    /// `KHR_materials_clearcoat`'s `clearcoatNormalTexture`.
    CoatNormal,
    /// `KHR_materials_sheen`'s `sheenColorTexture`.
    SheenColour,
    /// `KHR_materials_sheen`'s `sheenRoughnessTexture` (its alpha).
    SheenRoughness,
    /// `KHR_materials_transmission`'s `transmissionTexture` (its red).
    Transmission,
}

/// The material extensions' maps relief draws: (kind, extension, key).
pub const EXTENSION_MAPS: &[(Kind, &str, &str)] = &[
    (
        Kind::SpecularStrength,
        "KHR_materials_specular",
        "specularTexture",
    ),
    (
        Kind::SpecularColour,
        "KHR_materials_specular",
        "specularColorTexture",
    ),
    (Kind::Coat, "KHR_materials_clearcoat", "clearcoatTexture"),
    (
        Kind::CoatRoughness,
        "KHR_materials_clearcoat",
        "clearcoatRoughnessTexture",
    ),
    (
        Kind::CoatNormal,
        "KHR_materials_clearcoat",
        "clearcoatNormalTexture",
    ),
    (
        Kind::SheenColour,
        "KHR_materials_sheen",
        "sheenColorTexture",
    ),
    (
        Kind::SheenRoughness,
        "KHR_materials_sheen",
        "sheenRoughnessTexture",
    ),
    (
        Kind::Transmission,
        "KHR_materials_transmission",
        "transmissionTexture",
    ),
];

/// A texture reference (`textureInfo`) inside material `m`'s extension
/// `ext` under `key`: the texture it names and the reference's JSON. None
/// when absent, or when its index names no texture of `document` (the map
/// is then not drawn: the extension's factor acts alone).
pub fn extension_map<'a>(
    document: &'a ::gltf::Document,
    m: &::gltf::Material<'a>,
    ext: &str,
    key: &str,
) -> Option<(::gltf::Texture<'a>, ::gltf::json::Value)> {
    let info = m.extension_value(ext)?.get(key)?;
    let index = usize::try_from(info.get("index")?.as_u64()?).ok()?;
    Some((document.textures().nth(index)?, info.clone()))
}

/// One texture reference of a material, whatever its kind.
pub struct MapRef<'a> {
    pub kind: Kind,
    pub texture: ::gltf::Texture<'a>,
    pub tex_coord: u32,
    /// The `KHR_texture_transform` object, if any.
    pub transform: Option<::gltf::json::Value>,
}

/// A material's texture references, base colour first, then the core
/// maps, then the extensions' ([`EXTENSION_MAPS`]).
pub fn maps_of<'a>(document: &'a ::gltf::Document, m: &::gltf::Material<'a>) -> Vec<MapRef<'a>> {
    let ext = "KHR_texture_transform";
    let pbr = m.pbr_metallic_roughness();
    let info = |kind: Kind, i: ::gltf::texture::Info<'a>| MapRef {
        kind,
        texture: i.texture(),
        tex_coord: i.tex_coord(),
        transform: i.extension_value(ext).cloned(),
    };
    let mut out = Vec::new();
    out.extend(pbr.base_color_texture().map(|i| info(Kind::BaseColor, i)));
    out.extend(m.normal_texture().map(|n| MapRef {
        kind: Kind::Normal,
        texture: n.texture(),
        tex_coord: n.tex_coord(),
        transform: n.extension_value(ext).cloned(),
    }));
    out.extend(m.occlusion_texture().map(|o| MapRef {
        kind: Kind::Occlusion,
        texture: o.texture(),
        tex_coord: o.tex_coord(),
        transform: o.extension_value(ext).cloned(),
    }));
    out.extend(m.emissive_texture().map(|i| info(Kind::Emissive, i)));
    out.extend(
        pbr.metallic_roughness_texture()
            .map(|i| info(Kind::MetallicRoughness, i)),
    );
    for &(kind, extension, key) in EXTENSION_MAPS {
        if let Some((texture, json)) = extension_map(document, m, extension, key) {
            out.push(MapRef {
                kind,
                texture,
                tex_coord: json
                    .get("texCoord")
                    .and_then(|v| v.as_u64())
                    .and_then(|v| u32::try_from(v).ok())
                    .unwrap_or(0),
                transform: json.get("extensions").and_then(|e| e.get(ext)).cloned(),
            });
        }
    }
    out
}

impl Reading {
    /// How material `m`'s first texture is read (its filter is the
    /// material's).
    pub fn of(document: &::gltf::Document, m: &::gltf::Material) -> Reading {
        maps_of(document, m)
            .first()
            .map_or_else(Reading::default, Reading::of_map)
    }

    /// How one map is read: its set, transform, wrap modes and filter.
    pub fn of_map(map: &MapRef) -> Reading {
        let sampler = map.texture.sampler();
        let (transform, set) = map
            .transform
            .as_ref()
            .map_or((Mat3::IDENTITY, None), transform_of);
        Reading {
            set: set.unwrap_or(map.tex_coord),
            transform,
            wrap: [sampler.wrap_s(), sampler.wrap_t()],
            filter: filter_of(sampler.mag_filter(), sampler.min_filter()),
        }
    }

    /// The matrix from a coordinate of the set to the map's: the texture
    /// transform.
    pub fn matrix(&self) -> Mat3 {
        self.transform
    }

    /// A vertex's texture coordinate as relief reads the map.
    pub fn uv(&self, uv: Vec2) -> Vec2 {
        self.transform.transform_point2(uv)
    }

    /// The sampler's wrap modes as the texture reads them.
    pub fn wrap(&self) -> Wrap {
        let mode = |w: WrappingMode| match w {
            WrappingMode::Repeat => WrapMode::Repeat,
            WrappingMode::MirroredRepeat => WrapMode::MirroredRepeat,
            WrappingMode::ClampToEdge => WrapMode::ClampToEdge,
        };
        Wrap::new(mode(self.wrap[0]), mode(self.wrap[1]))
    }
}

/// Where a material's maps read their texture coordinates from a primitive.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Sets {
    /// The first texture's reading: its set is stored in the vertices' UVs
    /// through its `Reading::uv`.
    pub first: Reading,
    /// The first reading on another set, when a map reads one: that set is
    /// stored as the mesh's second set through its `Reading::uv`.
    pub second: Option<Reading>,
    /// Each map's coordinate from the stored ones.
    pub uvs: MapUvs,
}

impl Sets {
    pub fn of(document: &::gltf::Document, m: &::gltf::Material) -> Sets {
        let readings: Vec<(Kind, Reading)> = maps_of(document, m)
            .iter()
            .map(|r| (r.kind, Reading::of_map(r)))
            .collect();
        let Some(&(_, first)) = readings.first() else {
            return Sets::default();
        };
        let second = readings
            .iter()
            .map(|(_, r)| *r)
            .find(|r| r.set != first.set);
        let mut uvs = MapUvs::default();
        for (kind, r) in &readings {
            let (stored, on_second) = match second {
                Some(s) if r.set == s.set => (s, true),
                _ => (first, false),
            };
            let map = MapUv {
                second: on_second,
                transform: relative(r, &stored),
            };
            match kind {
                Kind::BaseColor => {}
                Kind::Normal => uvs.normal = map,
                Kind::Occlusion => uvs.occlusion = map,
                Kind::Emissive => uvs.emissive = map,
                Kind::MetallicRoughness => uvs.specular = map,
                Kind::SpecularStrength => uvs.specular_strength = map,
                Kind::SpecularColour => uvs.specular_colour = map,
                Kind::Coat => uvs.coat = map,
                Kind::CoatRoughness => uvs.coat_roughness = map,
                Kind::CoatNormal => uvs.coat_normal = map,
                Kind::SheenColour => uvs.sheen_colour = map,
                Kind::SheenRoughness => uvs.sheen_roughness = map,
                Kind::Transmission => uvs.transmission = map,
            }
        }
        Sets { first, second, uvs }
    }
}

/// Reading `r`'s matrix after the inverse of the one its set was stored
/// with: none when the two are the same (or the stored one cannot be
/// undone, a texture transform of scale 0).
fn relative(r: &Reading, stored: &Reading) -> Option<Affine2> {
    let (m, s) = (r.matrix(), stored.matrix());
    let det = s.determinant();
    if m == s || det == 0.0 || !det.is_finite() {
        return None;
    }
    let rest = m * s.inverse();
    rest.is_finite().then(|| Affine2::from_mat3(rest))
}

/// `KHR_texture_transform`'s matrix (offset · rotation · scale) and its
/// texCoord override. Missing or malformed numbers keep their defaults.
/// The rotation is the extension's matrix R = [[cos, sin], [−sin, cos]] on
/// the column (u, v): with v pointing down the picture, the image turns
/// clockwise as the extension says.
pub fn transform_of(json: &::gltf::json::Value) -> (Mat3, Option<u32>) {
    let num = |v: &::gltf::json::Value| v.as_f64().map(|x| x as f32).filter(|x| x.is_finite());
    let pair = |key: &str, default: Vec2| {
        json.get(key)
            .and_then(|v| v.as_array())
            .filter(|a| a.len() == 2)
            .and_then(|a| Some(Vec2::new(num(&a[0])?, num(&a[1])?)))
            .unwrap_or(default)
    };
    let offset = pair("offset", Vec2::ZERO);
    let scale = pair("scale", Vec2::ONE);
    let rotation = json.get("rotation").and_then(num).unwrap_or(0.0);
    let (s, c) = rotation.sin_cos();
    // u' = c·u + s·v + offset.x, v' = −s·u + c·v + offset.y (columns below).
    let rotate = Mat3::from_cols_array(&[c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0]);
    let m = Mat3::from_translation(offset) * rotate * Mat3::from_scale(scale);
    let set = json
        .get("texCoord")
        .and_then(|v| v.as_u64())
        .and_then(|v| u32::try_from(v).ok());
    (m, set)
}

/// relief's filter for a sampler's filters: the minification filter
/// decides when given (it is what most pixels of a model need), else the
/// magnification one; LINEAR magnification alone is the view's choice.
pub fn filter_of(mag: Option<MagFilter>, min: Option<MinFilter>) -> Option<Filter> {
    match min {
        Some(MinFilter::Nearest) => Some(Filter::Nearest),
        Some(MinFilter::Linear) => Some(Filter::Bilinear),
        Some(MinFilter::NearestMipmapNearest | MinFilter::LinearMipmapNearest) => {
            Some(Filter::NearestMip)
        }
        Some(MinFilter::NearestMipmapLinear | MinFilter::LinearMipmapLinear) => {
            Some(Filter::Trilinear)
        }
        None => (mag == Some(MagFilter::Nearest)).then_some(Filter::Nearest),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn reading(s: WrappingMode, t: WrappingMode) -> Reading {
        Reading {
            wrap: [s, t],
            ..Reading::default()
        }
    }

    /// The texel a nearest read of a 4 × 1 level, read with `r`'s wrap
    /// modes, gives at u.
    fn at(r: &Reading, u: f32) -> u32 {
        let row = [10.0, 11.0, 12.0, 13.0].map(|x| [x / 100.0; 4]);
        let level = relief_texture::Level::from_texels(4, 1, row.to_vec()).with_wrap(r.wrap());
        (level.nearest(r.uv(Vec2::new(u, 0.0)).x, 0.5)[0] * 100.0).round() as u32
    }

    #[test]
    fn mirrored_repeat_at_1_25_reads_0_75() {
        let r = reading(WrappingMode::MirroredRepeat, WrappingMode::Repeat);
        // The mirror image of u in 1..2 is 2 − u: u = 1.25 + 0.01 reads
        // 0.75 − 0.01 (texel 2), 1.875 + 0.01 reads 0.115 (texel 0),
        // −0.24 reads 0.24 (texel 0), and 0.31 is itself (texel 1).
        for (u, want) in [(1.26, 12), (1.885, 10), (-0.24, 10), (0.31, 11)] {
            assert_eq!(at(&r, u), want, "u = {u}");
        }
    }

    #[test]
    fn clamp_to_edge_reads_the_edge_texels_past_the_edges() {
        let r = reading(WrappingMode::ClampToEdge, WrappingMode::Repeat);
        // Within half the map of its edges and far beyond (where the
        // doubled layout used to repeat): the edge texel.
        for (u, want) in [(1.2, 13), (1.45, 13), (1.7, 13), (9.5, 13), (-0.2, 10)] {
            assert_eq!(at(&r, u), want, "u = {u}");
        }
        for (u, want) in [(-0.45, 10), (-0.8, 10), (-12.0, 10), (0.6, 12)] {
            assert_eq!(at(&r, u), want, "u = {u}");
        }
    }

    #[test]
    fn a_quarter_turn_maps_a_known_texel() {
        // The extension's example: offset (0, 1), rotation π/2, scale ½
        // reads "only the lower left quadrant of the image, rotated
        // clockwise 90°". By hand, R = [[0, 1], [−1, 0]]: (u, v) ↦
        // (v/2, 1 − u/2), so the corners (0,0), (1,0), (0,1), (1,1) read
        // (0,1), (0,½), (½,1), (½,½): inside the lower left quadrant.
        let json: ::gltf::json::Value = ::gltf::json::deserialize::from_str(
            r#"{"rotation": 1.57079632679, "offset": [0, 1], "scale": [0.5, 0.5], "texCoord": 1}"#,
        )
        .unwrap();
        let (m, set) = transform_of(&json);
        assert_eq!(set, Some(1));
        let corners = [(0.0, 0.0, 0.0, 1.0), (1.0, 0.0, 0.0, 0.5)];
        let corners = corners
            .into_iter()
            .chain([(0.0, 1.0, 0.5, 1.0), (1.0, 1.0, 0.5, 0.5)]);
        for (u, v, wu, wv) in corners {
            let uv = m.transform_point2(Vec2::new(u, v));
            assert!(
                (uv - Vec2::new(wu, wv)).abs().max_element() < 1e-6,
                "({u}, {v}) reads {uv}"
            );
        }
        // A texel off the diagonal: (0.25, 0.5) at π/2 alone is (0.5, −0.25).
        let json: ::gltf::json::Value =
            ::gltf::json::deserialize::from_str(r#"{"rotation": 1.5707964}"#).unwrap();
        let uv = transform_of(&json).0.transform_point2(Vec2::new(0.25, 0.5));
        assert!(
            (uv - Vec2::new(0.5, -0.25)).abs().max_element() < 1e-6,
            "{uv}"
        );
        // Scale applies first: (0.25, 0.5) scaled by (2, 4) is (0.5, 2).
        let json: ::gltf::json::Value =
            ::gltf::json::deserialize::from_str(r#"{"scale": [2, 4], "offset": [0.1, 0.2]}"#)
                .unwrap();
        let uv = transform_of(&json).0.transform_point2(Vec2::new(0.25, 0.5));
        assert!(
            (uv - Vec2::new(0.6, 2.2)).abs().max_element() < 1e-6,
            "{uv}"
        );
    }

    #[test]
    fn filters_follow_the_minification_filter() {
        assert_eq!(filter_of(None, None), None);
        assert_eq!(filter_of(Some(MagFilter::Linear), None), None);
        assert_eq!(
            filter_of(Some(MagFilter::Nearest), None),
            Some(Filter::Nearest)
        );
        assert_eq!(
            filter_of(None, Some(MinFilter::LinearMipmapLinear)),
            Some(Filter::Trilinear)
        );
        assert_eq!(
            filter_of(None, Some(MinFilter::LinearMipmapNearest)),
            Some(Filter::NearestMip)
        );
        assert_eq!(
            filter_of(Some(MagFilter::Nearest), Some(MinFilter::Linear)),
            Some(Filter::Bilinear)
        );
    }
}
