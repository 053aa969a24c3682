//! glTF materials as relief materials (docs/models.md):
//! - `baseColorTexture` is the colour texture (its alpha is opacity in glTF,
//!   not height: the height map is flat, so only a normal map bumps it);
//!   `baseColorFactor` multiplies the vertex colours (COLOR_0, else white);
//! - `normalTexture` is a file normal map for dot3, its `scale` applied to
//!   the normals' x and y as the specification says (scale 0: no map);
//! - metallic-roughness: in the model view, the factors and the map (green
//!   roughness, blue metallic) as they are, shaded by `shade::pbr`; elsewhere
//!   the specular map: gloss = (1 − roughness)², roughness =
//!   `roughnessFactor` × the texture's green channel;
//! - `doubleSided` false culls back faces;
//! - `KHR_materials_ior`, `KHR_materials_specular`,
//!   `KHR_materials_clearcoat` and `KHR_materials_sheen`: their factors
//!   and their textures, each map kept in the channels its reads need
//!   (`SpecularMaps`, `Clearcoat`, `Sheen`).

use std::borrow::Cow;
use std::collections::HashMap;
use std::path::Path;
use std::sync::{Arc, Mutex};

use glam::Vec3;

use super::data::{self, Problem, Uri};
use super::opacity;
use super::sampling::{Kind, Reading, Sets, extension_map, maps_of};
use crate::Material;
use crate::map_uv::MapUv;
use crate::terms::{
    Clearcoat, Cutout, MaterialTerms, PbrMaterial, Sheen, SpecularMaps, TransmissionMap, f0_of_ior,
};
use relief_texture::decode::load::load_texture_from_bytes;
use relief_texture::decode::size_cap;
use relief_texture::normal_map_file::{FileNormalMap, tilt};
use relief_texture::sample::wrap::Wrap;
use relief_texture::{Level, Texture};

/// What a primitive takes from its material.
#[derive(Clone)]
pub(super) struct Look {
    pub material: Arc<Material>,
    /// `baseColorFactor` (RGB): multiplies the vertex colours.
    pub base_color: Vec3,
    pub double_sided: bool,
    /// The material has a normal map (its own or its clearcoat's): the
    /// primitive needs tangents.
    pub normal_mapped: bool,
    /// The coordinates the tangents follow: the normal map's, else the
    /// clearcoat's normal map's.
    pub tangent_uv: MapUv,
    /// Emission, occlusion and the sampler's filter, when it has any.
    pub terms: Option<Arc<MaterialTerms>>,
}

/// The model's materials, each built once when first used.
pub(super) struct Materials<'a> {
    name: &'a str,
    document: &'a ::gltf::Document,
    buffers: &'a [Vec<u8>],
    dir: &'a Path,
    looks: HashMap<Option<usize>, Look>,
    /// Images decoded ahead ([`Materials::decode_ahead`]), by index, each
    /// taken by the first map that reads it.
    ready: Mutex<HashMap<usize, Texture>>,
    /// The maps made so far: materials that read an image alike share
    /// one copy of its map.
    made: Mutex<HashMap<MapKey, Made>>,
}

/// What a map is made for from its image.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum Product {
    /// The colour texture, heights flat.
    Colour,
    /// The colour picture's alpha, as opacity.
    Alpha,
    /// The normal map at a `scale` (its bits).
    Normal(u32),
    /// The picture as it is, one level (metallic-roughness, emissive, the
    /// specular colour, and any one-channel map of a picture read whole
    /// already).
    Plain,
    /// One channel alone, in 16 bits (occlusion's red, the specular
    /// strength's alpha, the clearcoat's red or green).
    Channel(u8),
}

/// A made map's image, wrap modes and product.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
struct MapKey {
    image: usize,
    wrap: Wrap,
    product: Product,
}

/// A made map.
#[derive(Clone)]
enum Made {
    Colour(Arc<Texture>),
    Normal(Arc<FileNormalMap>),
    Level(Arc<Level>),
}

impl Made {
    fn into_level(self) -> Option<Arc<Level>> {
        match self {
            Made::Level(level) => Some(level),
            _ => None,
        }
    }
}

/// How a material reads each of its maps: each map with its own sampler's
/// wrap modes and transform, else the material's first reading.
struct Readings<'a> {
    material: Reading,
    maps: Vec<super::sampling::MapRef<'a>>,
    sets: Sets,
}

impl<'a> Readings<'a> {
    fn new(document: &'a ::gltf::Document, m: &::gltf::Material<'a>) -> Self {
        Readings {
            material: Reading::of(document, m),
            maps: maps_of(document, m),
            sets: Sets::of(document, m),
        }
    }

    fn of(&self, kind: Kind) -> Reading {
        self.maps
            .iter()
            .find(|r| r.kind == kind)
            .map_or(self.material, Reading::of_map)
    }
}

impl<'a> Materials<'a> {
    pub fn new(
        name: &'a str,
        document: &'a ::gltf::Document,
        buffers: &'a [Vec<u8>],
        dir: &'a Path,
    ) -> Self {
        Materials {
            name,
            document,
            buffers,
            dir,
            looks: HashMap::new(),
            ready: Mutex::new(HashMap::new()),
            made: Mutex::new(HashMap::new()),
        }
    }

    /// The look of material `index` (`None`: glTF's default material).
    pub fn get(&mut self, index: Option<usize>) -> Result<Look, Problem> {
        if let Some(look) = self.looks.get(&index) {
            return Ok(look.clone());
        }
        let look = match index.and_then(|i| self.document.materials().nth(i)) {
            Some(m) => self
                .build(&m)
                .map_err(|p| format!("materials[{}]: {p}", m.index().unwrap_or(0)))?,
            None => Look {
                material: Arc::new(Material {
                    texture: white(format!("{} (no material)", self.name)),
                    specular_map: None,
                    normal_map: None,
                    environment: None,
                }),
                base_color: Vec3::ONE,
                double_sided: false,
                normal_mapped: false,
                tangent_uv: MapUv::default(),
                terms: Some(Arc::new(MaterialTerms {
                    pbr: Some(PbrMaterial::gltf_default()),
                    ..MaterialTerms::default()
                })),
            },
        };
        self.looks.insert(index, look.clone());
        Ok(look)
    }

    fn build(&self, m: &::gltf::Material<'a>) -> Result<Look, Problem> {
        self.decode_ahead(m);
        let look = self.build_look(m);
        // What was decoded ahead and not taken (a map made already) goes now.
        self.ready.lock().unwrap_or_else(|e| e.into_inner()).clear();
        look
    }

    fn build_look(&self, m: &::gltf::Material<'a>) -> Result<Look, Problem> {
        let pbr = m.pbr_metallic_roughness();
        let readings = Readings::new(self.document, m);
        // The maps read as they are come first and the normal maps last: a
        // normal map is made beside its picture, and by then the pictures
        // decoded ahead for the others are maps of their final size.
        let metal_rough = match pbr.metallic_roughness_texture() {
            Some(info) => {
                let reading = readings.of(Kind::MetallicRoughness);
                Some(self.plain_map(&info.texture(), &reading)?)
            }
            None => None,
        };
        let mut map_names = Vec::new();
        let occlusion = self.occlusion_map(m, &readings, &mut map_names)?;
        let emissive = emission(m);
        let emissive_map = self.emissive_map(m, emissive, &readings, &mut map_names)?;
        let mut physical = reflectance(m);
        self.specular_maps(m, &readings, &mut physical, &mut map_names)?;
        if let Some(coat) = &mut physical.clearcoat {
            self.coat_maps(m, &readings, coat, &mut map_names)?;
        }
        if let Some(sheen) = &mut physical.sheen {
            self.sheen_maps(m, &readings, sheen, &mut map_names)?;
        }
        // MASK draws the pixels whose alpha reaches the cutoff; BLEND and
        // transmission composite each pixel with its opacity.
        let opacity = opacity::of(m);
        let (texture, alpha_map) = self.colour_map(m, &readings, opacity.reads_alpha)?;
        let transmission = self.transmission_map(m, &opacity, &readings, &mut map_names)?;
        let normal_map = match m.normal_texture() {
            Some(info) => {
                self.normal_map(&info.texture(), info.scale(), &readings.of(Kind::Normal))?
            }
            None => None,
        };
        if let Some(coat) = &mut physical.clearcoat {
            coat.normal = self.coat_normal_map(m, &readings, &mut map_names)?;
        }
        let roughness = finite_unit(pbr.roughness_factor());
        let specular_map = Arc::new(match &metal_rough {
            Some(base) => gloss_map(base, roughness),
            None => Level::solid(1, 1, [gloss(roughness); 4]),
        });
        let coat_normal = physical
            .clearcoat
            .as_ref()
            .is_some_and(|c| c.normal.is_some());
        let physical = PbrMaterial {
            metallic: finite_unit(pbr.metallic_factor()),
            roughness,
            roughness_map: metal_rough.clone().map(|m| (m, 1)),
            metallic_map: metal_rough.map(|m| (m, 2)),
            normal: normal_map.as_ref().map(|m| m.given().clone()),
            ..physical
        };
        let uvs = readings.sets.uvs;
        let [r, g, b, _] = pbr.base_color_factor();
        let colour_factor: Vec3 = [r, g, b].map(finite_unit).into();
        let terms = MaterialTerms {
            colour_factor,
            cutout: cutout(&opacity, alpha_map, transmission, colour_factor),
            emissive,
            emissive_map,
            occlusion,
            filter: readings.material.filter,
            map_names,
            uvs,
            pbr: Some(physical),
            unlit: m.extension_value("KHR_materials_unlit").is_some(),
            ..MaterialTerms::default()
        };
        Ok(Look {
            normal_mapped: normal_map.is_some() || coat_normal,
            tangent_uv: if normal_map.is_some() || !coat_normal {
                uvs.normal
            } else {
                uvs.coat_normal
            },
            material: Arc::new(Material {
                texture,
                specular_map: Some(specular_map),
                normal_map,
                environment: None,
            }),
            base_color: Vec3::new(r, g, b),
            double_sided: m.double_sided(),
            terms: (terms != MaterialTerms::default()).then(|| Arc::new(terms)),
        })
    }

    /// `KHR_materials_specular`'s textures into `pbr` (the factors are
    /// there already): the strength's alpha kept alone, the colour as the
    /// picture is. A weight of 0 reads neither (nothing is reflected), a
    /// black colour factor not the colour map, a picture without alpha not
    /// the strength (its alpha is 1).
    fn specular_maps(
        &self,
        m: &::gltf::Material<'a>,
        readings: &Readings,
        pbr: &mut PbrMaterial,
        names: &mut Vec<(&'static str, String)>,
    ) -> Result<(), Problem> {
        let ext = "KHR_materials_specular";
        let f0_colour = specular_colour(m);
        if pbr.specular_weight == 0.0 {
            return Ok(());
        }
        let mut strength = None;
        if let Some((texture, _)) = extension_map(self.document, m, ext, "specularTexture")
            && self.image_has_alpha(&texture)?
        {
            let reading = readings.of(Kind::SpecularStrength);
            strength = Some(self.channel_map(&texture, &reading, 3)?);
            names.push(("spec. str", self.map_name(&texture)?));
        }
        let mut colour = None;
        if let Some((texture, _)) = extension_map(self.document, m, ext, "specularColorTexture")
            && f0_colour.max_element() > 0.0
        {
            colour = Some(self.plain_map(&texture, &readings.of(Kind::SpecularColour))?);
            names.push(("spec. col", self.map_name(&texture)?));
        }
        if strength.is_some() || colour.is_some() {
            pbr.specular_maps = Some(SpecularMaps {
                f0_colour,
                // Read from the red channel: kept alone.
                strength: strength.map(|(level, _)| level),
                colour,
            });
        }
        Ok(())
    }

    /// `KHR_materials_clearcoat`'s intensity (red) and roughness (green)
    /// maps into `coat`: one picture read the same way for both is kept
    /// whole and read once; otherwise each channel alone. A roughness
    /// factor of 0 reads no roughness map.
    fn coat_maps(
        &self,
        m: &::gltf::Material<'a>,
        readings: &Readings,
        coat: &mut Clearcoat,
        names: &mut Vec<(&'static str, String)>,
    ) -> Result<(), Problem> {
        let ext = "KHR_materials_clearcoat";
        let factor = extension_map(self.document, m, ext, "clearcoatTexture");
        let rough = extension_map(self.document, m, ext, "clearcoatRoughnessTexture")
            .filter(|_| coat.roughness > 0.0);
        let (r_factor, r_rough) = (readings.of(Kind::Coat), readings.of(Kind::CoatRoughness));
        if let (Some((a, _)), Some((b, _))) = (&factor, &rough)
            && self.image_of(a)?.index() == self.image_of(b)?.index()
            && r_factor == r_rough
        {
            let whole = self.plain_map(a, &r_factor)?;
            coat.factor_map = Some((whole.clone(), 0));
            coat.roughness_map = Some((whole, 1));
            names.push(("coat", self.map_name(a)?));
            return Ok(());
        }
        if let Some((texture, _)) = factor {
            coat.factor_map = Some(self.channel_map(&texture, &r_factor, 0)?);
            names.push(("coat", self.map_name(&texture)?));
        }
        if let Some((texture, _)) = rough {
            coat.roughness_map = Some(self.channel_map(&texture, &r_rough, 1)?);
            names.push(("coat rough", self.map_name(&texture)?));
        }
        Ok(())
    }

    /// `KHR_materials_transmission`'s texture (its red), for a material
    /// that transmits: none without one.
    fn transmission_map(
        &self,
        m: &::gltf::Material<'a>,
        opacity: &opacity::Opacity,
        readings: &Readings,
        names: &mut Vec<(&'static str, String)>,
    ) -> Result<Option<TransmissionMap>, Problem> {
        let ext = "KHR_materials_transmission";
        let uv = readings.sets.uvs.transmission;
        let Some((texture, _)) = extension_map(self.document, m, ext, "transmissionTexture")
            .filter(|_| opacity.transmission > 0.0)
        else {
            return Ok(None);
        };
        // The red channel, kept alone or read in the whole picture.
        let (map, _red) = self.channel_map(&texture, &readings.of(Kind::Transmission), 0)?;
        names.push(("transmission", self.map_name(&texture)?));
        Ok(Some(TransmissionMap {
            strength: opacity.through(),
            map,
            uv,
        }))
    }

    /// `KHR_materials_sheen`'s colour map (as the picture is) and roughness
    /// map (its alpha alone; a picture without alpha reads 1, no map; a
    /// roughness factor of 0 reads none).
    fn sheen_maps(
        &self,
        m: &::gltf::Material<'a>,
        readings: &Readings,
        sheen: &mut Sheen,
        names: &mut Vec<(&'static str, String)>,
    ) -> Result<(), Problem> {
        let ext = "KHR_materials_sheen";
        if let Some((texture, _)) = extension_map(self.document, m, ext, "sheenColorTexture") {
            sheen.colour_map = Some(self.plain_map(&texture, &readings.of(Kind::SheenColour))?);
            names.push(("sheen", self.map_name(&texture)?));
        }
        if let Some((texture, _)) = extension_map(self.document, m, ext, "sheenRoughnessTexture")
            && sheen.roughness > 0.0
            && self.image_has_alpha(&texture)?
        {
            let reading = readings.of(Kind::SheenRoughness);
            sheen.roughness_map = Some(self.channel_map(&texture, &reading, 3)?.0);
            names.push(("sheen rgh", self.map_name(&texture)?));
        }
        Ok(())
    }

    /// `clearcoatNormalTexture` with its `scale` (default 1; 0: none).
    fn coat_normal_map(
        &self,
        m: &::gltf::Material<'a>,
        readings: &Readings,
        names: &mut Vec<(&'static str, String)>,
    ) -> Result<Option<Arc<relief_texture::NormalMap>>, Problem> {
        let ext = "KHR_materials_clearcoat";
        let Some((texture, json)) = extension_map(self.document, m, ext, "clearcoatNormalTexture")
        else {
            return Ok(None);
        };
        let scale = json
            .get("scale")
            .and_then(|v| v.as_f64())
            .map_or(1.0, |v| v as f32);
        let map = self.normal_map(&texture, scale, &readings.of(Kind::CoatNormal))?;
        if map.is_some() {
            names.push(("coat norm", self.map_name(&texture)?));
        }
        Ok(map.map(|m| m.given().clone()))
    }

    /// The colour texture (heights flat: glTF's alpha is opacity) and, when
    /// the material reads opacity from it, its alpha.
    fn colour_map(
        &self,
        m: &::gltf::Material,
        readings: &Readings,
        reads_alpha: bool,
    ) -> Result<(Arc<Texture>, Option<Arc<Level>>), Problem> {
        let Some(info) = m.pbr_metallic_roughness().base_color_texture() else {
            let name = format!("{} material {}", self.name, m.index().unwrap_or(0));
            return Ok((white(name), None));
        };
        let texture = info.texture();
        let reading = readings.of(Kind::BaseColor);
        let key = self.key(&texture, &reading, Product::Colour)?;
        let alpha_key = MapKey {
            product: Product::Alpha,
            ..key
        };
        let made_colour = self.made(key);
        let made_alpha = self.made(alpha_key);
        // A picture without alpha has no opacity to read: its header says
        // so, without decoding it again.
        if let Some(Made::Colour(colour)) = &made_colour
            && (!reads_alpha || made_alpha.is_some() || !self.image_has_alpha(&texture)?)
        {
            return Ok((colour.clone(), made_alpha.and_then(Made::into_level)));
        }
        let decoded = self.decode(&texture, &reading)?;
        let alpha = match made_alpha {
            Some(made) => made.into_level(),
            None if reads_alpha && decoded.has_alpha => {
                let base = decoded.texture.base();
                let alpha = Arc::new(Level {
                    wrap: base.wrap,
                    width: base.width,
                    height: base.height,
                    texels: base.texels.fourth_everywhere(),
                });
                self.keep(alpha_key, Made::Level(alpha.clone()));
                Some(alpha)
            }
            None => None,
        };
        let colour = match made_colour {
            Some(Made::Colour(colour)) => colour,
            _ => {
                let colour = Arc::new(decoded.texture.without_height());
                self.keep(key, Made::Colour(colour.clone()));
                colour
            }
        };
        Ok((colour, alpha))
    }

    /// A normal map of `texture` with its `scale` applied (scale 0: none):
    /// the material's, or its clearcoat's (one map when both read the same
    /// picture at the same scale).
    fn normal_map(
        &self,
        texture: &::gltf::Texture,
        scale: f32,
        reading: &Reading,
    ) -> Result<Option<Arc<FileNormalMap>>, Problem> {
        if scale == 0.0 || !scale.is_finite() {
            return Ok(None);
        }
        let key = self.key(texture, reading, Product::Normal(scale.to_bits()))?;
        if let Some(Made::Normal(map)) = self.made(key) {
            return Ok(Some(map));
        }
        let image = self.image_of(texture)?;
        let name = self.image_name(&image);
        let decoded = match self.take_ready(&image) {
            Some(t) => t,
            None => load_texture_from_bytes(&name, &self.image_bytes(&image)?)
                .map_err(|e| e.to_string())?
                .read_as_map(),
        };
        let map = FileNormalMap::from_texture(decoded.with_wrap(reading.wrap()))
            .map_err(|e| e.to_string())?;
        let map = if scale == 1.0 {
            map
        } else {
            FileNormalMap::new(name, tilt(map.given(), scale))
        };
        let map = Arc::new(map);
        self.keep(key, Made::Normal(map.clone()));
        Ok(Some(map))
    }

    /// The occlusion map and its strength (strength 0: none), named for the
    /// texture panel.
    fn occlusion_map(
        &self,
        m: &::gltf::Material,
        readings: &Readings,
        names: &mut Vec<(&'static str, String)>,
    ) -> Result<Option<(Arc<Level>, f32)>, Problem> {
        let Some(info) = m.occlusion_texture() else {
            return Ok(None);
        };
        let strength = info.strength();
        if !strength.is_finite() || strength == 0.0 {
            return Ok(None);
        }
        let texture = info.texture();
        let reading = readings.of(Kind::Occlusion);
        // Only the red channel counts, unless the picture is a map read
        // whole already (an occlusion-roughness-metallic picture).
        let (map, _red) = self.channel_map(&texture, &reading, 0)?;
        names.push(("occlusion", self.map_name(&texture)?));
        Ok(Some((map, strength.clamp(0.0, 1.0))))
    }

    /// The emissive map, read only where the material emits.
    fn emissive_map(
        &self,
        m: &::gltf::Material,
        emissive: Vec3,
        readings: &Readings,
        names: &mut Vec<(&'static str, String)>,
    ) -> Result<Option<Arc<Level>>, Problem> {
        let Some(info) = m
            .emissive_texture()
            .filter(|_| emissive.max_element() > 0.0)
        else {
            return Ok(None);
        };
        let texture = info.texture();
        let map = self.plain_map(&texture, &readings.of(Kind::Emissive))?;
        names.push(("emissive", self.map_name(&texture)?));
        Ok(Some(map))
    }

    /// A map read at one level as the picture is (metallic-roughness,
    /// occlusion, emissive): one copy for every map and material that reads
    /// the image with the same wrap modes (an ORM picture is one map).
    fn plain_map(
        &self,
        texture: &::gltf::Texture,
        reading: &Reading,
    ) -> Result<Arc<Level>, Problem> {
        let key = self.key(texture, reading, Product::Plain)?;
        if let Some(level) = self.made(key).and_then(Made::into_level) {
            return Ok(level);
        }
        let level = Arc::new(self.decode(texture, reading)?.texture.into_base());
        self.keep(key, Made::Level(level.clone()));
        Ok(level)
    }

    /// Whether `texture`'s picture has an alpha channel (its header says).
    fn image_has_alpha(&self, texture: &::gltf::Texture) -> Result<bool, Problem> {
        Ok(relief_texture::decode::load::has_alpha(
            &self.image_bytes(&self.image_of(texture)?)?,
        ))
    }

    /// The name a map of `texture` shows in the texture panel: its
    /// image's, as the decoded picture carries it.
    fn map_name(&self, texture: &::gltf::Texture) -> Result<String, Problem> {
        Ok(relief_core::sanitize::clean(
            &self.image_name(&self.image_of(texture)?),
        ))
    }

    /// Channel `k` of a picture, and the channel to read: the picture whole
    /// when a map reads it whole already (an occlusion-roughness-metallic
    /// picture) and `k` is a colour channel, else that channel alone in 16 bits (an 8-bit k as 257·k,
    /// which reads back as k / 255 exactly), read as its red. The budget
    /// holds the channel's texels before they are made, beside the picture
    /// they are made from.
    fn channel_map(
        &self,
        texture: &::gltf::Texture,
        reading: &Reading,
        k: usize,
    ) -> Result<(Arc<Level>, usize), Problem> {
        // The packet read gives R, G and B: an alpha is always kept alone.
        let whole = self.key(texture, reading, Product::Plain)?;
        if k < 3
            && let Some(level) = self.made(whole).and_then(Made::into_level)
        {
            return Ok((level, k));
        }
        let key = self.key(texture, reading, Product::Channel(k as u8))?;
        if let Some(level) = self.made(key).and_then(Made::into_level) {
            return Ok((level, 0));
        }
        let decoded = self.decode(texture, reading)?.texture;
        let base = decoded.base();
        let what = format!("a {}x{} map", base.width, base.height);
        let _held = relief_core::budget::reserve(&what, base.texels.channel_grey_bytes())
            .map_err(|e| e.to_string())?;
        let channel = Arc::new(Level {
            wrap: base.wrap,
            width: base.width,
            height: base.height,
            texels: base.texels.channel_grey(k),
        });
        drop(decoded);
        self.keep(key, Made::Level(channel.clone()));
        Ok((channel, 0))
    }

    /// Where a map made from `texture` read this way is kept.
    fn key(
        &self,
        texture: &::gltf::Texture,
        reading: &Reading,
        product: Product,
    ) -> Result<MapKey, Problem> {
        Ok(MapKey {
            image: self.image_of(texture)?.index(),
            wrap: reading.wrap(),
            product,
        })
    }

    /// Whether a map was made from image `index` (the next that reads it
    /// may not need it decoded).
    fn any_made_from(&self, index: usize) -> bool {
        let made = self.made.lock().unwrap_or_else(|e| e.into_inner());
        made.keys().any(|k| k.image == index)
    }

    /// The map made already for `key`, if any.
    fn made(&self, key: MapKey) -> Option<Made> {
        self.made
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .get(&key)
            .cloned()
    }

    /// Keeps `made` for the maps after this one that read the same image
    /// the same way.
    fn keep(&self, key: MapKey, made: Made) {
        self.made
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .insert(key, made);
    }

    /// A texture's image decoded, read with the map's wrap modes.
    fn decode(&self, texture: &::gltf::Texture, reading: &Reading) -> Result<Decoded, Problem> {
        let image = self.image_of(texture)?;
        let name = self.image_name(&image);
        let bytes = self.image_bytes(&image)?;
        let has_alpha = relief_texture::decode::load::has_alpha(&bytes);
        let decoded = match self.take_ready(&image) {
            Some(t) => t,
            None => load_texture_from_bytes(&name, &bytes)
                .map_err(|e| e.to_string())?
                .read_as_map(),
        };
        // The sampler's wrap modes are read where the map is addressed:
        // the map is kept at its own size.
        Ok(Decoded {
            texture: decoded.with_wrap(reading.wrap()),
            has_alpha,
        })
    }

    /// Decodes the images `m`'s maps read side by side, one per core,
    /// before `build` takes them one by one: decoding is most of the time a
    /// textured model takes to load. An image that fails is left to
    /// `build`, which says why; the picture size cap in force
    /// (`size_cap`) holds on every core.
    fn decode_ahead(&self, m: &::gltf::Material<'a>) {
        use rayon::prelude::*;
        let pbr = m.pbr_metallic_roughness();
        // The maps `build` reads (a zero scale, strength or emission reads none).
        let used = |x: f32| x.is_finite() && x != 0.0;
        let emits = m.emissive_factor().iter().any(|&e| e > 0.0);
        let mut images: Vec<::gltf::Image> = [
            pbr.base_color_texture().map(|i| i.texture()),
            pbr.metallic_roughness_texture().map(|i| i.texture()),
            m.normal_texture()
                .filter(|i| used(i.scale()))
                .map(|i| i.texture()),
            m.occlusion_texture()
                .filter(|i| used(i.strength()))
                .map(|i| i.texture()),
            m.emissive_texture().filter(|_| emits).map(|i| i.texture()),
        ]
        .into_iter()
        .flatten()
        .chain(self.extension_textures(m))
        .filter_map(|t| self.image_of(&t).ok())
        .filter(|image| !self.any_made_from(image.index()))
        .collect();
        images.sort_by_key(::gltf::Image::index);
        images.dedup_by_key(|i| i.index());
        if images.len() < 2 {
            return;
        }
        let cap = size_cap::max_side();
        let decoded: Vec<(usize, Texture)> = images
            .par_iter()
            .filter_map(|image| {
                let bytes = self.image_bytes(image).ok()?;
                let name = self.image_name(image);
                size_cap::with_max_side(cap, || load_texture_from_bytes(&name, &bytes))
                    .ok()
                    .map(|t| (image.index(), t.read_as_map()))
            })
            .collect();
        self.ready
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .extend(decoded);
    }

    /// The extensions' textures `build` reads: none of a layer that is not
    /// there (a clearcoat factor of 0) or reflects nothing (a specular
    /// weight of 0).
    fn extension_textures(&self, m: &::gltf::Material<'a>) -> Vec<::gltf::Texture<'a>> {
        let pbr = reflectance(m);
        let keep = |ext: &str| match ext {
            "KHR_materials_specular" => pbr.specular_weight > 0.0,
            "KHR_materials_clearcoat" => pbr.clearcoat.is_some(),
            "KHR_materials_sheen" => pbr.sheen.is_some(),
            _ => true,
        };
        super::sampling::EXTENSION_MAPS
            .iter()
            .filter(|(_, ext, _)| keep(ext))
            .filter_map(|(_, ext, key)| extension_map(self.document, m, ext, key))
            .map(|(texture, _)| texture)
            .collect()
    }

    /// The image `texture` reads: its KTX2 image when it names one
    /// (`KHR_texture_basisu`), else its WebP one (`EXT_texture_webp`),
    /// else its source: relief decodes all three.
    fn image_of(&self, texture: &::gltf::Texture) -> Result<::gltf::Image<'a>, Problem> {
        let named_by = |ext: &str| {
            texture
                .extension_value(ext)
                .and_then(|e| e.get("source"))
                .and_then(|v| v.as_u64())
                .and_then(|i| usize::try_from(i).ok())
                .filter(|&i| i < self.document.images().len())
        };
        let index = named_by("KHR_texture_basisu")
            .or_else(|| named_by("EXT_texture_webp"))
            .unwrap_or(texture.source().index());
        self.document
            .images()
            .nth(index)
            .ok_or_else(|| format!("textures[{}]: no image {index}", texture.index()))
    }

    /// The image decoded ahead, if it was and no map took it yet.
    fn take_ready(&self, image: &::gltf::Image) -> Option<Texture> {
        self.ready
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .remove(&image.index())
    }

    /// A name for an image in messages and the texture panel.
    fn image_name(&self, image: &::gltf::Image) -> String {
        let ext = match image.source() {
            ::gltf::image::Source::View { mime_type, .. } => mime_ext(mime_type),
            ::gltf::image::Source::Uri { uri, mime_type } => match data::parse_uri(uri) {
                Ok(Uri::File(rel)) => return format!("{} {rel}", self.name),
                _ => mime_type.map_or("", mime_ext),
            },
        };
        format!("{} images[{}]{ext}", self.name, image.index())
    }

    /// The encoded bytes of an image: a slice of a buffer, a data URI or a
    /// file beside the model.
    fn image_bytes(&self, image: &::gltf::Image) -> Result<Cow<'a, [u8]>, Problem> {
        let at = format!("images[{}]", image.index());
        match image.source() {
            ::gltf::image::Source::View { view, .. } => {
                let buffer = &self.buffers[view.buffer().index()];
                let (start, len) = (view.offset(), view.length());
                start
                    .checked_add(len)
                    .and_then(|end| buffer.get(start..end))
                    .map(Cow::Borrowed)
                    .ok_or_else(|| {
                        format!(
                            "{at}: bufferViews[{}] is past the end of its buffer",
                            view.index()
                        )
                    })
            }
            ::gltf::image::Source::Uri { uri, .. } => {
                let what = format!("model {}, {at}", self.name);
                match data::parse_uri(uri).map_err(|p| format!("{at}: {p}"))? {
                    Uri::Data(payload) => data::decode_data(payload, &what)
                        .map(|(b, _)| Cow::Owned(b))
                        .map_err(|p| format!("{at}: {p}")),
                    Uri::File(rel) => {
                        let path =
                            data::beside(self.dir, &rel).map_err(|p| format!("{at}: {p}"))?;
                        data::read_file(&path, &what)
                            .map(|(b, _)| Cow::Owned(b))
                            .map_err(|p| {
                                format!("{at}: file '{}': {p}", relief_core::sanitize::clean(&rel))
                            })
                    }
                }
            }
        }
    }
}

/// A decoded image, and whether the file has an alpha channel (else the
/// decoder's alpha is relief's height from the colours, not opacity).
struct Decoded {
    texture: Texture,
    has_alpha: bool,
}

/// A name ending for an image's MIME type, so the decoder knows the format.
fn mime_ext(mime: &str) -> &'static str {
    match mime {
        "image/png" => ".png",
        "image/jpeg" => ".jpg",
        "image/ktx2" => ".ktx2",
        _ => "",
    }
}

/// A factor in 0..=1 (NaN: 0).
fn finite_unit(x: f32) -> f32 {
    if x.is_finite() {
        x.clamp(0.0, 1.0)
    } else {
        0.0
    }
}

/// The highlight's scale for a roughness in 0..1.
pub(super) fn gloss(roughness: f32) -> f32 {
    let r = roughness.clamp(0.0, 1.0);
    (1.0 - r) * (1.0 - r)
}

/// One white texel with a flat height: a material without a colour texture.
fn white(name: String) -> Arc<Texture> {
    Arc::new(Texture::new(name, Level::solid(1, 1, [1.0, 1.0, 1.0, 0.0])))
}

/// The highlight's map where the material is not shaded physically: gloss
/// from the metallic-roughness map's green channel times the factor, in 16
/// bits (one channel).
fn gloss_map(metal_rough: &Level, roughness: f32) -> Level {
    Level {
        wrap: metal_rough.wrap,
        width: metal_rough.width,
        height: metal_rough.height,
        texels: relief_texture::sample::texels::Texels::Grey16(
            metal_rough
                .texels
                .iter()
                .map(|t| relief_texture::sample::texels::to_unorm16(gloss(roughness * t[1])))
                .collect(),
        ),
    }
}

/// A number of material `m`'s extension `ext` (missing or not finite:
/// `default`).
fn extension_number(m: &::gltf::Material, ext: &str, key: &str, default: f32) -> f32 {
    m.extension_value(ext)
        .and_then(|e| e.get(key))
        .and_then(|v| v.as_f64())
        .map(|v| v as f32)
        .filter(|v| v.is_finite())
        .unwrap_or(default)
}

/// f0 of `KHR_materials_ior`'s index times `KHR_materials_specular`'s
/// `specularColorFactor` (each channel ≥ 0), before the clamp to 1.
fn specular_colour(m: &::gltf::Material) -> Vec3 {
    let f0 = f0_of_ior(extension_number(m, "KHR_materials_ior", "ior", 1.5));
    let colour = m
        .extension_value("KHR_materials_specular")
        .and_then(|e| e.get("specularColorFactor"))
        .and_then(|v| v.as_array())
        .filter(|a| a.len() == 3)
        .map(|a| Vec3::from_array([0, 1, 2].map(|k| a[k].as_f64().unwrap_or(1.0) as f32)))
        .filter(|c| c.is_finite())
        .map_or(Vec3::ONE, |c| c.max(Vec3::ZERO));
    f0 * colour
}

/// A material's dielectric reflectance (`KHR_materials_ior`,
/// `KHR_materials_specular`'s factors), the rest glTF's default: F0 =
/// min(f0(ior)·specularColorFactor, 1)·specularFactor and F90 =
/// specularFactor, as the Khronos sample renderer layers them; and the
/// clearcoat layer's factor and roughness (`KHR_materials_clearcoat`).
/// The extensions' textures are added by `Materials::specular_maps` and
/// `Materials::coat_maps`.
fn reflectance(m: &::gltf::Material) -> PbrMaterial {
    let weight =
        extension_number(m, "KHR_materials_specular", "specularFactor", 1.0).clamp(0.0, 1.0);
    // f0 ≤ 1, so a white colour and a weight of 1 leave it exact.
    let dielectric_f0 = specular_colour(m).min(Vec3::ONE) * weight;
    let coat_ext = "KHR_materials_clearcoat";
    let coat = extension_number(m, coat_ext, "clearcoatFactor", 0.0).clamp(0.0, 1.0);
    let clearcoat = (coat > 0.0).then(|| {
        let roughness = extension_number(m, coat_ext, "clearcoatRoughnessFactor", 0.0);
        Clearcoat::of_factors(coat, roughness.clamp(0.0, 1.0))
    });
    PbrMaterial {
        dielectric_f0,
        specular_weight: weight,
        clearcoat,
        sheen: sheen(m),
        ..PbrMaterial::gltf_default()
    }
}

/// `KHR_materials_sheen`'s factors: none when the colour is black (the
/// extension's default, which disables the layer). Each channel is held
/// in 0..=1, the roughness too.
fn sheen(m: &::gltf::Material) -> Option<Sheen> {
    let ext = "KHR_materials_sheen";
    let colour = m
        .extension_value(ext)?
        .get("sheenColorFactor")
        .and_then(|v| v.as_array())
        .filter(|a| a.len() == 3)
        .map(|a| Vec3::from_array([0, 1, 2].map(|k| a[k].as_f64().unwrap_or(0.0) as f32)))
        .filter(|c| c.is_finite())?
        .clamp(Vec3::ZERO, Vec3::ONE);
    (colour.max_element() > 0.0).then(|| Sheen {
        colour,
        roughness: extension_number(m, ext, "sheenRoughnessFactor", 0.0).clamp(0.0, 1.0),
        colour_map: None,
        roughness_map: None,
    })
}

/// The emissive factor times `KHR_materials_emissive_strength` (not finite: none).
fn emission(m: &::gltf::Material) -> Vec3 {
    let strength = m
        .extension_value("KHR_materials_emissive_strength")
        .and_then(|e| e.get("emissiveStrength"))
        .and_then(|v| v.as_f64())
        .map_or(1.0, |v| v as f32);
    let emissive = Vec3::from(m.emissive_factor()) * strength;
    if emissive.is_finite() {
        emissive.max(Vec3::ZERO)
    } else {
        Vec3::ZERO
    }
}

/// The cutout a material's opacity needs: none for a constant opacity that
/// a mask keeps, or that a blend draws whole. With a transmission map the
/// transmission is the map's, not in the constant factor. A transmitting
/// material tints what shows through by its base colour factor `colour`.
fn cutout(
    opacity: &opacity::Opacity,
    map: Option<Arc<Level>>,
    transmission: Option<TransmissionMap>,
    colour: Vec3,
) -> Option<Cutout> {
    let blend = opacity.blend;
    let factor = match transmission {
        Some(_) => opacity.alpha,
        None => opacity.factor(),
    };
    let varies = map.is_some() || transmission.is_some();
    let whole = |c: f32| if blend { 1.0 } else { c };
    opacity
        .cutoff
        .filter(|c| c.is_finite() && (varies || factor < whole(*c)))
        .map(|cutoff| Cutout {
            factor,
            map,
            cutoff,
            blend,
            transmission,
            tint: if opacity.transmission > 0.0 {
                colour
            } else {
                Vec3::ONE
            },
        })
}
