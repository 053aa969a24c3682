//! Wavefront OBJ models (`--model file.obj`).
//!
//! The file is read line by line by relief's own reader (`read`: what it
//! accepts is listed there), so a bad file gets a one-line error with its
//! line number, and counts, face sizes and the memory budget are checked
//! before anything of the model's size is allocated. Its material libraries
//! are read by `mtl`. The corners then go to the builder every format
//! shares (`scene::corners`).

pub mod mtl;
mod plain_lines;
pub mod read;

use std::path::Path;
use std::sync::Arc;

use glam::Vec3;

use super::corners::build_indexed;
use super::load_memory::KeepFreed;
use super::loaded_model::{LoadedModel, MaterialDesc, ModelMaps, ModelPart};
use super::mesh::Mesh;
use super::model_error::quote;
use super::model_io::{FileBytes, read_model_file};
use relief_core::budget::Reservation;
use relief_core::sanitize::{clean, display_path};

use super::model_error::ObjError;

/// Loads an OBJ file as one mesh fitted to the unit view (all its parts
/// together; warnings are dropped: see [`load_model`]).
pub fn load(path: &Path) -> Result<Mesh, ObjError> {
    load_model(path).map(|m| m.merged())
}

/// Loads an OBJ file with its material libraries: a part per material, the
/// maps the scene's one material shows, and the warnings.
pub fn load_model(path: &Path) -> Result<LoadedModel, ObjError> {
    let _keep = KeepFreed::new();
    let name = display_path(path);
    let (bytes, held) = read_model_file(path)?;
    let dir = path.parent().unwrap_or(Path::new("."));
    // The text is freed once read, before the mesh is built.
    parse_guarded(&name, Text::Owned { bytes, _held: held }, Some(dir), None)
}

/// The OBJ text: borrowed, or read from its file (and freed, with its
/// reservation, once read).
enum Text<'a> {
    Borrowed(&'a [u8]),
    Owned {
        bytes: FileBytes,
        _held: Reservation,
    },
}

impl Text<'_> {
    fn bytes(&self) -> &[u8] {
        match self {
            Text::Borrowed(b) => b,
            Text::Owned { bytes, .. } => bytes,
        }
    }

    /// [`FileBytes::check`] for a file's text.
    fn check(&self, name: &str) -> Result<(), ObjError> {
        match self {
            Text::Borrowed(_) => Ok(()),
            Text::Owned { bytes, .. } => bytes.check(name),
        }
    }
}

/// Builds a mesh from OBJ text (any 8-bit encoding, or UTF-16 with its
/// byte-order mark); `name` (already sanitised) is used in errors.
/// Material libraries are not opened (there is no directory to find them in).
pub fn parse(name: &str, text: impl AsRef<[u8]>) -> Result<Mesh, ObjError> {
    parse_model(name, text.as_ref(), None).map(|m| m.merged())
}

/// [`parse`] with the directory the material libraries are in (none: not
/// opened). A panic while reading or building becomes an error like any other.
pub fn parse_model(name: &str, text: &[u8], dir: Option<&Path>) -> Result<LoadedModel, ObjError> {
    parse_in_chunks(name, text, dir, None)
}

/// [`parse_model`] with the text read in at most `chunks` line-aligned
/// pieces in parallel (`None`: as many as its size calls for). Whatever the
/// cut, the model, its warnings and its first error are the same.
pub fn parse_in_chunks(
    name: &str,
    text: &[u8],
    dir: Option<&Path>,
    chunks: Option<usize>,
) -> Result<LoadedModel, ObjError> {
    parse_guarded(name, Text::Borrowed(text), dir, chunks)
}

/// [`parse_unguarded`], a panic made an error.
fn parse_guarded(
    name: &str,
    text: Text,
    dir: Option<&Path>,
    chunks: Option<usize>,
) -> Result<LoadedModel, ObjError> {
    relief_core::contain::contain(|| parse_unguarded(name, text, dir, chunks)).unwrap_or_else(
        |cause| {
            Err(ObjError::Parse {
                name: name.to_string(),
                reason: format!("the reader failed on it ({cause})"),
            })
        },
    )
}

/// UTF-16 text (known by its byte-order mark) as UTF-8; other text as it is.
fn utf8_text(text: &[u8]) -> std::borrow::Cow<'_, [u8]> {
    let big = match text {
        [0xFF, 0xFE, ..] => false,
        [0xFE, 0xFF, ..] => true,
        _ => return text.into(),
    };
    let units = text[2..].chunks_exact(2).map(|p| {
        if big {
            u16::from_be_bytes([p[0], p[1]])
        } else {
            u16::from_le_bytes([p[0], p[1]])
        }
    });
    let decoded: String = char::decode_utf16(units)
        .map(|c| c.unwrap_or(char::REPLACEMENT_CHARACTER))
        .collect();
    decoded.into_bytes().into()
}

/// Where the first NUL byte of `text` is, its pieces searched in parallel.
fn first_nul(text: &[u8]) -> Option<usize> {
    use rayon::prelude::*;
    const PIECE: usize = 1 << 20;
    text.par_chunks(PIECE)
        .enumerate()
        .find_map_first(|(k, piece)| memchr::memchr(0, piece).map(|at| k * PIECE + at))
}

fn parse_unguarded(
    name: &str,
    file: Text,
    dir: Option<&Path>,
    chunks: Option<usize>,
) -> Result<LoadedModel, ObjError> {
    let mut model = read_text(name, file, chunks)?;
    let mut warnings = std::mem::take(&mut model.warnings);
    let library = match dir {
        Some(dir) => load_libraries(name, dir, &model.libraries, &mut warnings),
        None => Vec::new(),
    };
    let materials = part_materials(name, &model.parts, &library, dir.is_some(), &mut warnings);
    // The scene has one texture: the first material with a diffuse map
    // that loads gives it (see docs/models.md).
    let mut own = material_maps(&materials, &mut warnings);
    let shown = own.iter().position(Option::is_some);
    let maps = shown.and_then(|i| own[i].take()).unwrap_or_default();
    let textured = textured_parts(&materials, &own, shown);
    // Kd is the corner colour where the file gives none.
    let part_colors: Vec<Option<Vec3>> = materials
        .iter()
        .map(|m| m.as_ref().and_then(|m| m.diffuse))
        .collect();
    // `map_d`: each material's opacity, read once.
    let opacity: Vec<Option<Arc<relief_texture::Level>>> = materials
        .iter()
        .map(|m| {
            grey_map(
                m.as_ref().and_then(|m| m.opacity_map.as_ref()),
                &mut warnings,
            )
        })
        .collect();
    // `map_Pr` and `map_Pm`: each material's roughness and metallic, read once.
    let pbr_maps: Vec<crate::loaded_model::PbrMaps> = materials
        .iter()
        .map(|m| match m {
            Some(m) => crate::loaded_model::PbrMaps {
                roughness: grey_map(m.roughness_map.as_ref(), &mut warnings),
                metallic: grey_map(m.metallic_map.as_ref(), &mut warnings),
            },
            None => Default::default(),
        })
        .collect();
    let meshes = build_indexed(
        name,
        model.corners,
        &part_colors,
        &textured,
        &mut model.reservation,
    )?;
    drop(model.reservation);
    let parts = meshes
        .into_iter()
        .map(|(part, mesh)| ModelPart {
            mesh,
            material: materials[part].clone(),
            own_maps: own[part].clone(),
            opacity_map: opacity[part].clone(),
            pbr_maps: pbr_maps[part].clone(),
        })
        .collect();
    Ok(LoadedModel {
        parts,
        maps,
        points: false,
        warnings,
        z_up: false,
    })
}

/// The file's text read into its model (in `chunks` pieces when given);
/// the text, and what it holds of the memory budget, are freed on return,
/// before the mesh is built.
fn read_text(name: &str, file: Text, chunks: Option<usize>) -> Result<read::ReadModel, ObjError> {
    // UTF-16 is decoded to at most 3 bytes of UTF-8 for each 2 bytes.
    let raw = file.bytes();
    let _decoded = match raw {
        [0xFF, 0xFE, ..] | [0xFE, 0xFF, ..] => Some(super::model_io::reserve(
            name,
            "the decoded text",
            (raw.len() as u64 / 2).saturating_mul(3),
        )?),
        _ => None,
    };
    let text = utf8_text(raw);
    // Text in any 8-bit encoding is read (names and comments are not
    // used); a NUL byte says it is not text at all.
    if let Some(at) = first_nul(&text) {
        file.check(name)?;
        return Err(ObjError::NotText {
            name: name.to_string(),
            at,
        });
    }
    let read = match chunks {
        Some(parts) => read::read_in_chunks(name, &text, parts),
        None => read::read(name, &text),
    };
    file.check(name)?;
    let model = read?;
    drop(text);
    drop(_decoded);
    drop(file);
    Ok(model)
}

/// Each part's material, when a library describes it; the parts whose
/// material none describes are a warning when libraries were looked for.
fn part_materials(
    name: &str,
    parts: &[Option<String>],
    library: &[MaterialDesc],
    looked: bool,
    warnings: &mut Vec<String>,
) -> Vec<Option<MaterialDesc>> {
    let mut unknown = Vec::new();
    let materials: Vec<Option<MaterialDesc>> = parts
        .iter()
        .map(|part| {
            let wanted = part.as_ref()?;
            let found = library.iter().find(|m| &m.name == wanted).cloned();
            if found.is_none() {
                unknown.push(quote(wanted));
            }
            found
        })
        .collect();
    if !unknown.is_empty() && looked {
        let more = unknown.len().saturating_sub(3);
        unknown.truncate(3);
        let more = if more > 0 {
            format!(" and {more} more")
        } else {
            String::new()
        };
        warnings.push(format!(
            "model {name}: material {}{more} in no material library (drawn with the scene's texture)",
            unknown.join(", ")
        ));
    }
    materials
}

/// Which parts are drawn with the scene's texture: those with no
/// material, the one whose map is `shown`, those with maps of their own,
/// and, when no map loaded, those that name a diffuse map.
fn textured_parts(
    materials: &[Option<MaterialDesc>],
    own: &[Option<ModelMaps>],
    shown: Option<usize>,
) -> Vec<bool> {
    materials
        .iter()
        .enumerate()
        .map(|(i, m)| match m {
            // No material, or one whose map could not be shown: the scene's texture.
            None => true,
            Some(m) => {
                Some(i) == shown || own[i].is_some() || (shown.is_none() && m.diffuse_map.is_some())
            }
        })
        .collect()
}

/// A one-channel map (`map_d`, `map_Pr`, `map_Pm`) read from its file; one
/// that cannot be read is a warning.
fn grey_map(
    path: Option<&crate::loaded_model::TexturePath>,
    warnings: &mut Vec<String>,
) -> Option<Arc<relief_texture::Level>> {
    let file = path?.file.as_ref()?;
    match relief_texture::specular_map::load_specular_map(file) {
        Ok(level) => Some(Arc::new(level)),
        Err(e) => {
            warnings.push(clean(&e.to_string()));
            None
        }
    }
}

/// The materials of every `mtllib`, relative to the OBJ's directory; a
/// library that cannot be read is a warning.
fn load_libraries(
    name: &str,
    dir: &Path,
    libraries: &[String],
    warnings: &mut Vec<String>,
) -> Vec<MaterialDesc> {
    let mut out = Vec::new();
    for line in libraries {
        // One name with spaces, or several names.
        let files: Vec<String> = match super::model_io::resolve_beside(dir, line) {
            Some(_) => vec![line.clone()],
            None => line.split_whitespace().map(str::to_string).collect(),
        };
        for file in files {
            let Some(path) = super::model_io::resolve_beside(dir, &file) else {
                warnings.push(format!(
                    "model {name}: material library {} not found",
                    quote(&file)
                ));
                continue;
            };
            let shown = display_path(&path);
            match read_model_file(&path) {
                Ok((bytes, _held)) => {
                    let lib_dir = path.parent().unwrap_or(dir);
                    let (materials, more) = mtl::parse(&shown, &bytes, lib_dir);
                    if let Err(e) = bytes.check(&shown) {
                        warnings.push(clean(&e.to_string()));
                        continue;
                    }
                    out.extend(materials);
                    warnings.extend(more);
                }
                Err(e) => warnings.push(clean(&e.to_string())),
            }
        }
    }
    out
}

/// The maps of every material whose `map_Kd` loads (none for the others):
/// its colour with its `bump` as height (times `-bm`), its `map_Ks` as
/// specular map and its `norm` as normal map. Each file is read once per
/// material that names it.
fn material_maps(
    materials: &[Option<MaterialDesc>],
    warnings: &mut Vec<String>,
) -> Vec<Option<ModelMaps>> {
    materials
        .iter()
        .map(|m| m.as_ref().and_then(|m| maps_of(m, warnings)))
        .collect()
}

/// One material's maps, or none when it has no colour map that loads.
fn maps_of(m: &MaterialDesc, warnings: &mut Vec<String>) -> Option<ModelMaps> {
    use relief_texture::decode::load;
    {
        let color = m.diffuse_map.as_ref().and_then(|t| t.file.as_ref())?;
        let texture = match load::load_texture(color) {
            Ok(t) => t,
            Err(e) => {
                warnings.push(clean(&e.to_string()));
                return None;
            }
        };
        let texture = match m.bump_map.as_ref().and_then(|t| t.file.as_ref()) {
            Some(bump) => match load::load_texture(bump)
                .and_then(|h| load::with_height_map(texture, &scale_heights(h, m.bump_multiplier)))
            {
                Ok(t) => t,
                Err(e) => {
                    warnings.push(clean(&e.to_string()));
                    load::load_texture(color)
                        .unwrap_or_else(|_| relief_texture::decode::procedural::brick())
                }
            },
            None => texture,
        };
        let specular_map = m
            .specular_map
            .as_ref()
            .and_then(|t| t.file.as_ref())
            .and_then(
                |p| match relief_texture::specular_map::load_specular_map(p) {
                    Ok(level) => Some(Arc::new(level)),
                    Err(e) => {
                        warnings.push(clean(&e.to_string()));
                        None
                    }
                },
            );
        let normal_map = m
            .normal_map
            .as_ref()
            .and_then(|t| t.file.as_ref())
            .and_then(
                |p| match relief_texture::normal_map_file::load_normal_map(p) {
                    Ok(map) => Some(Arc::new(map)),
                    Err(e) => {
                        warnings.push(clean(&e.to_string()));
                        None
                    }
                },
            );
        Some(ModelMaps {
            texture: Some(Arc::new(texture)),
            specular_map,
            normal_map,
        })
    }
}

/// A height map's heights times `multiplier` (MTL `-bm`).
pub fn scale_heights(texture: relief_texture::Texture, multiplier: f32) -> relief_texture::Texture {
    if multiplier == 1.0 {
        return texture;
    }
    let mut level = texture.base().clone();
    for t in level.texels.iter_mut() {
        t[3] *= multiplier;
    }
    relief_texture::Texture::new(texture.name.clone(), level)
}
