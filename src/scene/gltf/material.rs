//! glTF materials as relief materials (docs/models.md):
//! - `baseColorTexture` is the colour texture (its alpha is opacity in glTF,
//!   not height: the height map is flat, so only a normal map bumps it);
//!   `baseColorFactor` multiplies the vertex colours (COLOR_0, else white);
//! - `normalTexture` is a file normal map for dot3, its `scale` applied to
//!   the normals' x and y as the specification says (scale 0: no map);
//! - metallic-roughness becomes the specular map: gloss = (1 − roughness)²,
//!   roughness = `roughnessFactor` × the texture's green channel;
//! - `doubleSided` false culls back faces.

use std::borrow::Cow;
use std::collections::HashMap;
use std::path::Path;
use std::sync::Arc;

use glam::Vec3;

use super::data::{self, Problem, Uri};
use crate::scene::Material;
use crate::texture::load::load_texture_from_bytes;
use crate::texture::normal_map_file::{FileNormalMap, load_normal_map_from_bytes, tilt};
use crate::texture::{Level, Texture};

/// What a primitive takes from its material.
#[derive(Clone)]
pub(super) struct Look {
    pub material: Arc<Material>,
    /// `baseColorFactor` (RGB): multiplies the vertex colours.
    pub base_color: Vec3,
    pub double_sided: bool,
    /// The material has a normal map: the primitive needs tangents.
    pub normal_mapped: bool,
}

/// The texture coordinate set a material's textures read (the base
/// colour's, else the normal map's; one set per primitive).
pub(super) fn uv_set(m: &::gltf::Material) -> u32 {
    m.pbr_metallic_roughness()
        .base_color_texture()
        .map(|t| t.tex_coord())
        .or_else(|| m.normal_texture().map(|t| t.tex_coord()))
        .unwrap_or(0)
}

/// The model's materials, each built once when first used.
pub(super) struct Materials<'a> {
    name: &'a str,
    document: &'a ::gltf::Document,
    buffers: &'a [Vec<u8>],
    dir: &'a Path,
    looks: HashMap<Option<usize>, Look>,
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
            },
        };
        self.looks.insert(index, look.clone());
        Ok(look)
    }

    fn build(&self, m: &::gltf::Material) -> Result<Look, Problem> {
        let pbr = m.pbr_metallic_roughness();
        let texture = match pbr.base_color_texture() {
            Some(info) => {
                let image = info.texture().source();
                let name = self.image_name(&image);
                let bytes = self.image_bytes(&image)?;
                let decoded = load_texture_from_bytes(&name, &bytes).map_err(|e| e.to_string())?;
                Arc::new(flat_height(decoded)?)
            }
            None => white(format!("{} material {}", self.name, m.index().unwrap_or(0))),
        };
        let normal_map = match m.normal_texture() {
            Some(info) if info.scale() != 0.0 && info.scale().is_finite() => {
                let image = info.texture().source();
                let name = self.image_name(&image);
                let bytes = self.image_bytes(&image)?;
                let map = load_normal_map_from_bytes(&name, &bytes).map_err(|e| e.to_string())?;
                Some(Arc::new(if info.scale() == 1.0 {
                    map
                } else {
                    FileNormalMap::new(name, tilt(map.given(), info.scale()))
                }))
            }
            _ => None,
        };
        let roughness = pbr.roughness_factor().clamp(0.0, 1.0);
        let specular_map = match pbr.metallic_roughness_texture() {
            Some(info) => {
                let image = info.texture().source();
                let name = self.image_name(&image);
                let bytes = self.image_bytes(&image)?;
                let t = load_texture_from_bytes(&name, &bytes).map_err(|e| e.to_string())?;
                let base = t.base();
                Level {
                    width: base.width,
                    height: base.height,
                    texels: base
                        .texels
                        .iter()
                        .map(|t| [gloss(roughness * t[1]); 4])
                        .collect(),
                }
            }
            None => Level::solid(1, 1, [gloss(roughness); 4]),
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
        })
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
                    Uri::File(rel) => data::read_file(&self.dir.join(&rel), &what)
                        .map(|(b, _)| Cow::Owned(b))
                        .map_err(|p| format!("{at}: file '{}': {p}", crate::sanitize::clean(&rel))),
                }
            }
        }
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
    let bytes = crate::budget::texture_bytes(level.width as u64, level.height as u64);
    let held = crate::budget::reserve(&decoded.name, bytes).map_err(|e| e.to_string())?;
    Ok(Texture::new(decoded.name.clone(), level).holding(held))
}
