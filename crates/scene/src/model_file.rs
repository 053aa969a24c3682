//! A model file of any format relief reads, chosen by its extension:
//! `.obj` (with its MTL), `.stl` (binary or ASCII), `.ply` (ASCII or
//! binary). `.gltf`/`.glb` keep their node tree and materials and are read
//! by `scene::gltf` (`build_scene` sends them there), not as parts here.
//!
//! Every reader turns the file into triangle corners and hands them to the
//! one builder (`corners::build_indexed`), so fitting, normals, UVs, vertex
//! splitting and tangents are the same for every format. A model comes
//! back as parts (one per OBJ material used), each a mesh with the plain
//! description of its material, and the warnings met on the way (a missing
//! MTL or texture, a dropped attribute): the model still opens with them.

use std::path::Path;

use super::model_error::ObjError;
use super::model_io::read_model_file;
use super::obj;
use relief_core::sanitize::display_path;

use super::loaded_model::LoadedModel;

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

/// Loads a model file of any supported format.
pub fn load(path: &Path) -> Result<LoadedModel, ObjError> {
    let _keep = super::load_memory::KeepFreed::new();
    let name = display_path(path);
    match ModelFormat::of(path) {
        Some(ModelFormat::Obj) => obj::load_model(path),
        Some(ModelFormat::Stl) => {
            let (bytes, held) = read_model_file(path)?;
            let model = super::stl::parse(&name, &bytes);
            bytes.check(&name)?;
            drop(held);
            model
        }
        Some(ModelFormat::Ply) => {
            // The file's bytes are freed before the model is built.
            let (bytes, held) = read_model_file(path)?;
            super::ply::load(&name, bytes, held)
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
