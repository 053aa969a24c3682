//! A model or a picture known by its bytes, not its name: what
//! `relief render -` reads from standard input.
//!
//! Such a model has no folder: an OBJ's material libraries are not read
//! (said in a warning, the model drawn without them), and a glTF that
//! names another file (a `.bin` buffer, an image beside it) is refused
//! with a sentence saying to open it by its path. A GLB, which holds
//! everything, reads as from its file.

use std::path::Path;
use std::sync::Arc;

use super::build::LoadedNotes;
use super::loaded_model::LoadedModel;
use super::model_error::ObjError;
use super::model_file::ModelFormat;
use super::{Scene, gltf, obj, ply, stl};
use relief_texture::Texture;

/// What a file's bytes are.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Content {
    Model(ModelFormat),
    /// A picture the texture loader reads (its signature found).
    Picture,
}

/// What `bytes` hold, by their signature (a picture, GLB, PLY, binary STL
/// by its exact length), else by how the text starts (glTF JSON, ASCII
/// STL, OBJ); `None` when they look like none of them.
pub fn content_of(bytes: &[u8]) -> Option<Content> {
    use ModelFormat::*;
    if bytes.starts_with(b"glTF") {
        return Some(Content::Model(Gltf));
    }
    if image::guess_format(bytes).is_ok()
        || relief_texture::decode::xpm::looks_like_xpm(bytes)
        || is_tga_2(bytes)
    {
        return Some(Content::Picture);
    }
    if bytes.starts_with(b"ply\n") || bytes.starts_with(b"ply\r\n") {
        return Some(Content::Model(Ply));
    }
    if is_binary_stl(bytes) {
        return Some(Content::Model(Stl));
    }
    let text = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    let text = text.trim_ascii_start();
    if text.starts_with(b"{") {
        return Some(Content::Model(Gltf));
    }
    if text.starts_with(b"solid") {
        return Some(Content::Model(Stl));
    }
    starts_like_obj(text).then_some(Content::Model(Obj))
}

/// A binary STL: an 80-byte header, a facet count, and exactly that many
/// 50-byte facets.
fn is_binary_stl(bytes: &[u8]) -> bool {
    let Some(count) = bytes.get(80..84) else {
        return false;
    };
    let n = u32::from_le_bytes([count[0], count[1], count[2], count[3]]) as u64;
    84 + n * 50 == bytes.len() as u64
}

/// A TGA picture of version 2, whose footer ends in its signature (older
/// TGA files have none, and are not known from their bytes).
fn is_tga_2(bytes: &[u8]) -> bool {
    bytes.ends_with(b"TRUEVISION-XFILE.\0")
}

/// OBJ statements that may open a file.
const OBJ_KEYWORDS: &[&[u8]] = &[
    b"v", b"vt", b"vn", b"vp", b"f", b"l", b"p", b"o", b"g", b"s", b"mtllib", b"usemtl",
];

/// Text whose first line that is not blank is a comment or an OBJ statement.
fn starts_like_obj(text: &[u8]) -> bool {
    let Some(line) = text
        .split(|&b| b == b'\n')
        .map(<[u8]>::trim_ascii)
        .find(|l| !l.is_empty())
    else {
        return false;
    };
    let word = line
        .split(|b| b.is_ascii_whitespace())
        .next()
        .unwrap_or_default();
    line.starts_with(b"#") || OBJ_KEYWORDS.contains(&word)
}

/// A model read from bytes: a glTF keeps its node tree and materials.
pub enum BytesModel {
    Gltf(gltf::Model),
    Parts(LoadedModel),
}

/// Reads a model of `format` from `bytes`; `name` (already safe to print)
/// is used in messages.
pub fn load_model(name: &str, format: ModelFormat, bytes: &[u8]) -> Result<BytesModel, ObjError> {
    let _keep = super::load_memory::KeepFreed::new();
    let model = match format {
        ModelFormat::Obj => {
            let mut model = obj::parse_model(name, bytes, None)?;
            if names_material_library(bytes) {
                model.warnings.push(format!(
                    "model {name}: its material libraries (mtllib) are not read, as a model read from standard input has no folder; open it by its path to see its materials"
                ));
            }
            model
        }
        ModelFormat::Stl => stl::parse(name, bytes)?,
        ModelFormat::Ply => ply::parse(name, bytes)?,
        ModelFormat::Gltf => return load_gltf(name, bytes).map(BytesModel::Gltf),
    };
    Ok(BytesModel::Parts(model))
}

/// Whether an OBJ's text has an `mtllib` statement.
fn names_material_library(text: &[u8]) -> bool {
    text.split(|&b| b == b'\n')
        .any(|l| l.trim_ascii_start().starts_with(b"mtllib"))
}

/// A glTF from its bytes alone: refused when it names another file.
fn load_gltf(name: &str, bytes: &[u8]) -> Result<gltf::Model, ObjError> {
    let fail = |reason: String| ObjError::Parse {
        name: name.to_string(),
        reason,
    };
    let read = relief_core::contain::contain(|| {
        if let Some(file) = other_file_named(bytes) {
            return Err(ObjError::Unsupported {
                name: name.to_string(),
                what: format!(
                    "{file}, and a model read from standard input has no folder to find it in: open the model by its path"
                ),
            });
        }
        // No file is opened: every buffer and image is in the bytes.
        gltf::load_bytes(name, bytes, Path::new(".")).map_err(fail)
    });
    read.unwrap_or_else(|cause| Err(fail(format!("the reader failed on it ({cause})"))))
}

/// The first buffer or image of a glTF that is in a file of its own
/// ("buffers[0] names the file 'scene.bin'"); none when the JSON does not
/// parse (the reader then says why).
fn other_file_named(bytes: &[u8]) -> Option<String> {
    let parsed = ::gltf::Gltf::from_slice_without_validation(bytes).ok()?;
    let document = &parsed.document;
    let in_file = |uri: &str| !uri.trim_start().starts_with("data:");
    let quote = |uri: &str| super::model_error::quote(uri);
    for b in document.buffers() {
        if let ::gltf::buffer::Source::Uri(uri) = b.source()
            && in_file(uri)
        {
            return Some(format!(
                "buffers[{}] names the file {}",
                b.index(),
                quote(uri)
            ));
        }
    }
    for i in document.images() {
        if let ::gltf::image::Source::Uri { uri, .. } = i.source()
            && in_file(uri)
        {
            return Some(format!(
                "images[{}] names the file {}",
                i.index(),
                quote(uri)
            ));
        }
    }
    None
}

impl BytesModel {
    /// The scene that draws it, and what its loading had to say.
    pub fn into_scene(self, texture: Arc<Texture>) -> (Scene, LoadedNotes) {
        match self {
            // A model read from bytes is a model file: the model view.
            BytesModel::Gltf(model) => {
                let notes = LoadedNotes::of_gltf(&model);
                let scene = Scene::gltf(model, texture).into_model_view();
                let notes = notes.shown_in(&scene);
                (scene, notes)
            }
            BytesModel::Parts(model) => {
                let notes = LoadedNotes::of_parts(&model);
                let scene = Scene::loaded_model_view(model, texture);
                let notes = notes.shown_in(&scene);
                (scene, notes)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_format_is_known_by_its_bytes() {
        use ModelFormat::*;
        let mut stl = vec![0u8; 84 + 50];
        stl[80] = 1;
        let cases: &[(&[u8], Option<Content>)] = &[
            (b"glTF\x02\0\0\0", Some(Content::Model(Gltf))),
            (
                b"  {\"asset\":{\"version\":\"2.0\"}}",
                Some(Content::Model(Gltf)),
            ),
            (b"ply\nformat ascii 1.0\n", Some(Content::Model(Ply))),
            (
                b"solid cube\nfacet normal 0 0 1\n",
                Some(Content::Model(Stl)),
            ),
            (&stl, Some(Content::Model(Stl))),
            (b"# made by hand\nv 0 0 0\n", Some(Content::Model(Obj))),
            (b"\nmtllib a.mtl\nv 0 0 0\n", Some(Content::Model(Obj))),
            (b"v 1 2 3\nf 1 2 3\n", Some(Content::Model(Obj))),
            (b"\x89PNG\r\n\x1a\n", Some(Content::Picture)),
            (b"\xFF\xD8\xFF\xE0", Some(Content::Picture)),
            (b"/* XPM */\nstatic char", Some(Content::Picture)),
            (b"hello world\n", None),
            (b"", None),
        ];
        for (bytes, want) in cases {
            assert_eq!(
                content_of(bytes),
                *want,
                "{:?}",
                String::from_utf8_lossy(bytes)
            );
        }
    }

    #[test]
    fn a_gltf_naming_another_file_is_refused_with_the_file_named() {
        let json = br#"{"asset":{"version":"2.0"},"buffers":[{"uri":"mesh.bin","byteLength":36}]}"#;
        let Err(e) = load_model("from standard input", ModelFormat::Gltf, json) else {
            panic!("refused")
        };
        let e = e.to_string();
        assert!(e.contains("buffers[0] names the file 'mesh.bin'"), "{e}");
        assert!(e.contains("open the model by its path"), "{e}");
    }
}
