//! A model file of any format relief reads, chosen by its extension:
//! `.obj` (with its MTL), `.stl` (binary or ASCII), `.ply` (ASCII or
//! binary). `.gltf`/`.glb` keep their node tree and materials and are read
//! by `scene::gltf` (`build_scene` sends them there), not as parts here.
//!
//! Every reader turns the file into triangle corners and hands them to the
//! one builder (`obj::build_parts`), so fitting, normals, UVs, vertex
//! splitting and tangents are the same for every format. A model comes
//! back as parts (one per OBJ material used), each a mesh with the plain
//! description of its material, and the warnings met on the way (a missing
//! MTL or texture, a dropped attribute): the model still opens with them.

use std::io::Read;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::mesh::Mesh;
use super::obj::{self, ObjError};
use crate::budget::{self, Reservation};
use crate::sanitize::{clean, display_path};
use crate::texture::Texture;
use crate::texture::normal_map_file::FileNormalMap;

pub use super::obj::mtl::MaterialDesc;

/// The formats a model file may have.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ModelFormat {
    Obj,
    Stl,
    Ply,
    Gltf,
}

impl ModelFormat {
    /// The format a file name says (its extension, any case).
    pub fn of(path: &Path) -> Option<ModelFormat> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        Some(match ext.as_str() {
            "obj" => ModelFormat::Obj,
            "stl" => ModelFormat::Stl,
            "ply" => ModelFormat::Ply,
            "gltf" | "glb" => ModelFormat::Gltf,
            _ => return None,
        })
    }
}

/// Whether `path` names a model file (by its extension).
pub fn is_model_path(path: &Path) -> bool {
    ModelFormat::of(path).is_some()
}

/// One part of a model: the triangles of one material.
#[derive(Clone, Debug)]
pub struct ModelPart {
    pub mesh: Mesh,
    /// The material's description (none: the faces named no known material).
    pub material: Option<MaterialDesc>,
    /// The maps of this part's own material, when it has a texture that
    /// loaded and is not the one the scene's material shows (`LoadedModel::maps`):
    /// the part is then drawn with them (docs/models.md).
    pub own_maps: Option<ModelMaps>,
    /// MTL `map_d`: the material's opacity (grey), when it loaded.
    pub opacity_map: Option<Arc<crate::texture::Level>>,
}

/// The maps the single scene material takes from the model's textured
/// material (see docs/models.md, "OBJ and MTL").
#[derive(Clone, Debug, Default)]
pub struct ModelMaps {
    /// `map_Kd` with `bump` as its height (scaled by `-bm`).
    pub texture: Option<Arc<Texture>>,
    /// `map_Ks`, as the specular map.
    pub specular_map: Option<Arc<crate::texture::Level>>,
    /// `norm`, as the normal map file dot3 reads.
    pub normal_map: Option<Arc<FileNormalMap>>,
}

/// A loaded model.
#[derive(Clone, Debug)]
pub struct LoadedModel {
    pub parts: Vec<ModelPart>,
    /// The maps the scene's one material shows.
    pub maps: ModelMaps,
    /// A point cloud (a PLY without faces): best seen in the points display.
    pub points: bool,
    /// One line each, already safe to print, naming the file.
    pub warnings: Vec<String>,
}

impl LoadedModel {
    /// All parts as one mesh (what a single-object scene draws).
    pub fn merged(&self) -> Mesh {
        let mut parts = self.parts.iter();
        let Some(first) = parts.next() else {
            return Mesh::default();
        };
        let mut mesh = first.mesh.clone();
        for part in parts {
            let base = mesh.vertices.len() as u32;
            mesh.vertices.extend_from_slice(&part.mesh.vertices);
            mesh.triangles.extend(part.mesh.triangles.iter().map(|t| {
                let mut t = *t;
                t.indices = t.indices.map(|i| i + base);
                t
            }));
            mesh.closed &= part.mesh.closed;
        }
        mesh
    }
}

/// Loads a model file of any supported format.
pub fn load(path: &Path) -> Result<LoadedModel, ObjError> {
    let name = display_path(path);
    match ModelFormat::of(path) {
        Some(ModelFormat::Obj) => obj::load_model(path),
        Some(ModelFormat::Stl) => {
            let (bytes, held) = read_model_file(path)?;
            let model = super::stl::parse(&name, &bytes)?;
            drop(held);
            Ok(model)
        }
        Some(ModelFormat::Ply) => {
            let (bytes, held) = read_model_file(path)?;
            let model = super::ply::parse(&name, &bytes)?;
            drop(held);
            Ok(model)
        }
        Some(ModelFormat::Gltf) => Err(ObjError::Unsupported {
            name,
            what: "a glTF file is read with its scene (scene::gltf), not as parts".into(),
        }),
        None => Err(ObjError::Unsupported {
            name,
            what: "unknown model format (expected .obj, .stl, .ply, .gltf or .glb)".into(),
        }),
    }
}

/// Reads a whole model file, its bytes reserved against the memory budget
/// before they are read (there is no fixed size limit).
pub(crate) fn read_model_file(path: &Path) -> Result<(Vec<u8>, Reservation), ObjError> {
    let name = display_path(path);
    let read_error = |e: std::io::Error| ObjError::Read {
        name: name.clone(),
        reason: clean(&e.to_string()),
    };
    let meta = std::fs::metadata(path).map_err(read_error)?;
    if !meta.is_file() {
        return Err(ObjError::NotAFile { name });
    }
    let held = reserve(&name, "the file", meta.len())?;
    let mut bytes = Vec::with_capacity(meta.len() as usize);
    std::fs::File::open(path)
        .and_then(|f| f.take(meta.len()).read_to_end(&mut bytes))
        .map_err(read_error)?;
    Ok((bytes, held))
}

/// Reserves `bytes` for `what` of model `name`, or the budget's error.
pub(crate) fn reserve(name: &str, what: &str, bytes: u64) -> Result<Reservation, ObjError> {
    budget::reserve(&format!("{what} of model {name}"), bytes).map_err(|e| ObjError::Budget {
        name: name.to_string(),
        reason: e.to_string(),
    })
}

/// The model's path with another file name resolved next to it: `\` read as
/// `/`, and when that file is not there, each part of the path matched
/// without regard to case (files from Windows name their textures loosely).
pub fn resolve_beside(dir: &Path, written: &str) -> Option<PathBuf> {
    let written = written.trim().trim_matches('"').replace('\\', "/");
    if written.is_empty() {
        return None;
    }
    let direct = dir.join(&written);
    if direct.is_file() {
        return Some(direct);
    }
    let mut at = if Path::new(&written).is_absolute() {
        PathBuf::from("/")
    } else {
        dir.to_path_buf()
    };
    for part in written.split('/').filter(|p| !p.is_empty() && *p != ".") {
        if part == ".." {
            at.push("..");
            continue;
        }
        let exact = at.join(part);
        if exact.exists() {
            at = exact;
            continue;
        }
        let lower = part.to_lowercase();
        let found = std::fs::read_dir(&at).ok()?.flatten().find(|entry| {
            entry
                .file_name()
                .to_str()
                .is_some_and(|n| n.to_lowercase() == lower)
        })?;
        at.push(found.file_name());
    }
    at.is_file().then_some(at)
}
