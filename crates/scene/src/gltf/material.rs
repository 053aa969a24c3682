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
//! - `doubleSided` false culls back faces.

use std::borrow::Cow;
use std::collections::HashMap;
use std::path::Path;
use std::sync::{Arc, Mutex};

use glam::Vec3;

use super::data::{self, Problem, Uri};
use super::opacity;
use super::sampling::{Kind, Reading, Sets, maps_of};
use crate::Material;
use crate::terms::{Cutout, MaterialTerms, PbrMaterial};
use relief_texture::decode::load::load_texture_from_bytes;
use relief_texture::decode::size_cap;
use relief_texture::normal_map_file::{FileNormalMap, tilt};
use relief_texture::{Level, Texture};

/// What a primitive takes from its material.
#[derive(Clone)]
pub(super) struct Look {
    pub material: Arc<Material>,
    /// `baseColorFactor` (RGB): multiplies the vertex colours.
    pub base_color: Vec3,
    pub double_sided: bool,
    /// The material has a normal map: the primitive needs tangents.
    pub normal_mapped: bool,
    /// Emission, occlusion and the sampler's filter, when it has any.
    pub terms: Option<Arc<MaterialTerms>>,
    /// Where its maps read their texture coordinates.
    pub sets: Sets,
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
                terms: Some(Arc::new(MaterialTerms {
                    pbr: Some(PbrMaterial::gltf_default()),
                    ..MaterialTerms::default()
                })),
                sets: Sets::default(),
            },
        };
        self.looks.insert(index, look.clone());
        Ok(look)
    }

    fn build(&self, m: &::gltf::Material) -> Result<Look, Problem> {
        self.decode_ahead(m);
        let pbr = m.pbr_metallic_roughness();
        let reading = Reading::of(m);
        // Each map read with its own sampler's wrap modes.
        let maps = maps_of(m);
        let read = |kind: Kind| {
            maps.iter()
                .find(|r| r.kind == kind)
                .map_or(reading, Reading::of_map)
        };
        let sets = Sets::of(m);
        // MASK draws the pixels whose alpha reaches the cutoff; BLEND and
        // transmission composite each pixel with its opacity.
        let opacity = opacity::of(m);
        let mut alpha_map = None;
        let texture = match pbr.base_color_texture() {
            Some(info) => {
                let decoded = self.decode(&info.texture(), &read(Kind::BaseColor))?;
                if opacity.reads_alpha && decoded.has_alpha {
                    alpha_map = Some(Arc::new(alpha_of(decoded.texture.base())));
                }
                Arc::new(flat_height(decoded.texture)?)
            }
            None => white(format!("{} material {}", self.name, m.index().unwrap_or(0))),
        };
        let normal_map = match m.normal_texture() {
            Some(info) if info.scale() != 0.0 && info.scale().is_finite() => {
                let image = self.image_of(&info.texture())?;
                let name = self.image_name(&image);
                let reading = read(Kind::Normal);
                let wrap = reading.wrap();
                let texture = match self.take_ready(&image) {
                    Some(t) => t,
                    None => load_texture_from_bytes(&name, &self.image_bytes(&image)?)
                        .map_err(|e| e.to_string())?,
                };
                let map = FileNormalMap::from_texture(texture.with_wrap(wrap))
                    .map_err(|e| e.to_string())?;
                Some(Arc::new(if info.scale() == 1.0 {
                    map
                } else {
                    FileNormalMap::new(name, tilt(map.given(), info.scale()))
                }))
            }
            _ => None,
        };
        let roughness = finite_unit(pbr.roughness_factor());
        let metal_rough = match pbr.metallic_roughness_texture() {
            Some(info) => {
                let t = self
                    .decode(&info.texture(), &read(Kind::MetallicRoughness))?
                    .texture;
                Some(Arc::new(t.base().clone()))
            }
            None => None,
        };
        // The highlight's map where the material is not shaded physically.
        let specular_map = match &metal_rough {
            Some(base) => Level {
                wrap: base.wrap,
                width: base.width,
                height: base.height,
                texels: base
                    .texels
                    .iter()
                    .map(|t| [gloss(roughness * t[1]); 4])
                    .collect(),
            },
            None => Level::solid(1, 1, [gloss(roughness); 4]),
        };
        let physical = PbrMaterial {
            metallic: finite_unit(pbr.metallic_factor()),
            roughness,
            roughness_map: metal_rough.clone().map(|m| (m, 1)),
            metallic_map: metal_rough.map(|m| (m, 2)),
            normal: normal_map.as_ref().map(|m| m.given().clone()),
        };
        let mut map_names = Vec::new();
        let occlusion = match m.occlusion_texture() {
            Some(info) if info.strength().is_finite() && info.strength() != 0.0 => {
                let t = self
                    .decode(&info.texture(), &read(Kind::Occlusion))?
                    .texture;
                map_names.push(("occlusion", t.name.clone()));
                Some((Arc::new(t.base().clone()), info.strength().clamp(0.0, 1.0)))
            }
            _ => None,
        };
        let strength = m
            .extension_value("KHR_materials_emissive_strength")
            .and_then(|e| e.get("emissiveStrength"))
            .and_then(|v| v.as_f64())
            .map_or(1.0, |v| v as f32);
        let emissive = Vec3::from(m.emissive_factor()) * strength;
        let emissive = if emissive.is_finite() {
            emissive.max(Vec3::ZERO)
        } else {
            Vec3::ZERO
        };
        let emissive_map = match m.emissive_texture() {
            Some(info) if emissive.max_element() > 0.0 => {
                let t = self.decode(&info.texture(), &read(Kind::Emissive))?.texture;
                map_names.push(("emissive", t.name.clone()));
                Some(Arc::new(t.base().clone()))
            }
            _ => None,
        };
        // A constant opacity that a mask keeps, or that a blend draws
        // whole, needs no cutout.
        let (blend, factor) = (opacity.blend, opacity.factor);
        let whole = |c: f32| if blend { 1.0 } else { c };
        let cutout = opacity
            .cutoff
            .filter(|c| c.is_finite() && (alpha_map.is_some() || factor < whole(*c)))
            .map(|cutoff| Cutout {
                factor,
                map: alpha_map,
                cutoff,
                blend,
            });
        let terms = MaterialTerms {
            cutout,
            emissive,
            emissive_map,
            occlusion,
            filter: reading.filter,
            map_names,
            uvs: sets.uvs,
            pbr: Some(physical),
            unlit: m.extension_value("KHR_materials_unlit").is_some(),
            ..MaterialTerms::default()
        };
        let [r, g, b, _] = pbr.base_color_factor();
        Ok(Look {
            normal_mapped: normal_map.is_some(),
            material: Arc::new(Material {
                texture,
                specular_map: Some(Arc::new(specular_map)),
                normal_map,
                environment: None,
            }),
            base_color: Vec3::new(r, g, b),
            double_sided: m.double_sided(),
            sets,
            terms: (terms != MaterialTerms::default()).then(|| Arc::new(terms)),
        })
    }

    /// A texture's image decoded, read with the map's wrap modes.
    fn decode(&self, texture: &::gltf::Texture, reading: &Reading) -> Result<Decoded, Problem> {
        let image = self.image_of(texture)?;
        let name = self.image_name(&image);
        let bytes = self.image_bytes(&image)?;
        let has_alpha = has_alpha(&bytes);
        let decoded = match self.take_ready(&image) {
            Some(t) => t,
            None => load_texture_from_bytes(&name, &bytes).map_err(|e| e.to_string())?,
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
    fn decode_ahead(&self, m: &::gltf::Material) {
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
        .filter_map(|t| self.image_of(&t).ok())
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
                    .map(|t| (image.index(), t))
            })
            .collect();
        self.ready
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .extend(decoded);
    }

    /// The image `texture` reads: its WebP image when it names one
    /// (`EXT_texture_webp`, which relief decodes), else its source.
    fn image_of(&self, texture: &::gltf::Texture) -> Result<::gltf::Image<'a>, Problem> {
        let webp = texture
            .extension_value("EXT_texture_webp")
            .and_then(|e| e.get("source"))
            .and_then(|v| v.as_u64())
            .and_then(|i| usize::try_from(i).ok())
            .filter(|&i| i < self.document.images().len());
        let index = webp.unwrap_or(texture.source().index());
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

/// Whether an encoded image has an alpha channel (its header says).
fn has_alpha(bytes: &[u8]) -> bool {
    use image::ImageDecoder;
    image::ImageReader::new(std::io::Cursor::new(bytes))
        .with_guessed_format()
        .ok()
        .and_then(|r| r.into_decoder().ok())
        .is_some_and(|d| d.color_type().has_alpha())
}

/// A level's alpha as opacity in every channel.
fn alpha_of(level: &Level) -> Level {
    Level {
        wrap: level.wrap,
        width: level.width,
        height: level.height,
        texels: level.texels.iter().map(|t| [t[3]; 4]).collect(),
    }
}

/// A name ending for an image's MIME type, so the decoder knows the format.
fn mime_ext(mime: &str) -> &'static str {
    match mime {
        "image/png" => ".png",
        "image/jpeg" => ".jpg",
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

/// The texture with every height 0 (glTF's alpha is opacity, not height),
/// its memory reserved before the decoded copy is given back.
fn flat_height(decoded: Texture) -> Result<Texture, Problem> {
    let mut level = decoded.base().clone();
    for t in &mut level.texels {
        t[3] = 0.0;
    }
    let bytes = relief_core::budget::texture_bytes(level.width as u64, level.height as u64);
    let held = relief_core::budget::reserve(&decoded.name, bytes).map_err(|e| e.to_string())?;
    Ok(Texture::new(decoded.name.clone(), level).holding(held))
}
