//! What relief checks in a glTF file before anything reads it: the `gltf`
//! crate panics, or reaches code it marks unreachable, on some invalid
//! files (an attribute naming a missing accessor, indices of a kind glTF
//! does not allow, a stride shorter than an element, an embedded image
//! without a MIME type). Each such file gets one plain sentence instead.

use ::gltf::Semantic;
use ::gltf::accessor::{Accessor, DataType, Dimensions};
use ::gltf::json;

use super::data::Problem;

/// Checks and mends the parsed JSON before the crate validates it:
/// - every accessor a primitive names exists (the crate's own validation
///   indexes the POSITION accessor without checking);
/// - every required extension is one relief reads (`supported`); the list
///   is then emptied, since the crate refuses those it does not parse
///   itself, which relief reads from the raw extension objects;
/// - an image in a bufferView without a MIME type (the specification asks
///   for one) is decoded by its bytes, as an image file is.
pub(super) fn before_parse(root: &mut json::Root, supported: &[&str]) -> Result<(), Problem> {
    for ext in &root.extensions_required {
        if !supported.contains(&ext.as_str()) {
            return Err(format!(
                "it requires the extension '{}', which relief does not read",
                relief_core::sanitize::clean(ext)
            ));
        }
    }
    root.extensions_required.clear();
    check_primitive_accessors(root)?;
    for image in &mut root.images {
        if image.buffer_view.is_some() && image.mime_type.is_none() {
            image.mime_type = Some(json::image::MimeType(String::new()));
        }
    }
    // A texture given only as KTX2 or WebP (`KHR_texture_basisu`,
    // `EXT_texture_webp`, no fallback `source`) reads that image.
    for texture in &mut root.textures {
        if texture.source.value() == u32::MAX as usize
            && let Some(index) = extension_source(texture, "KHR_texture_basisu")
                .or_else(|| extension_source(texture, "EXT_texture_webp"))
        {
            texture.source = json::Index::new(index);
        }
    }
    Ok(())
}

/// The image index extension `name` gives a texture, if any.
fn extension_source(texture: &json::Texture, name: &str) -> Option<u32> {
    let ext = texture.extensions.as_ref()?.others.get(name)?;
    let index = ext.get("source")?.as_u64()?;
    u32::try_from(index).ok().filter(|&i| i != u32::MAX)
}

/// Every accessor index of every primitive (attributes, indices, morph
/// targets) lies inside the file's accessors.
fn check_primitive_accessors(root: &json::Root) -> Result<(), Problem> {
    let count = root.accessors.len();
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, prim) in mesh.primitives.iter().enumerate() {
            let place = format!("meshes[{m}].primitives[{p}]");
            let attributes = prim.attributes.iter().map(|(semantic, index)| {
                let name = match semantic {
                    json::validation::Checked::Valid(s) => s.to_string(),
                    json::validation::Checked::Invalid => "an attribute".into(),
                };
                (name, index.value())
            });
            let indices = prim.indices.iter().map(|i| ("indices".into(), i.value()));
            let targets = prim.targets.iter().flatten().flat_map(|t| {
                [t.positions, t.normals, t.tangents]
                    .into_iter()
                    .flatten()
                    .map(|i| ("a morph target".into(), i.value()))
            });
            for (what, index) in attributes.chain(indices).chain(targets) {
                if index >= count {
                    return Err(format!(
                        "{place}: {} names accessors[{index}], but the file has {}",
                        relief_core::sanitize::clean(&what),
                        accessors_count(count)
                    ));
                }
            }
        }
    }
    Ok(())
}

/// "no accessors", "1 accessor", "N accessors".
fn accessors_count(n: usize) -> String {
    match n {
        0 => "no accessors".into(),
        1 => "1 accessor".into(),
        n => format!("{n} accessors"),
    }
}

/// What a primitive's accessor is read as.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Role<'a> {
    Attribute(&'a Semantic),
    Indices,
    /// Anything else relief reads (animation keys, skins, morph
    /// targets), named as the specification names it; its kind is
    /// checked where it is read.
    Data(&'static str),
}

impl Role<'_> {
    /// The name the specification gives it.
    pub(super) fn name(self) -> String {
        match self {
            Role::Attribute(s) => s.to_string(),
            Role::Indices => "indices".into(),
            Role::Data(what) => what.into(),
        }
    }

    /// The element kinds glTF 2.0 allows for it (§3.7.2.1, §3.7.2.2), as
    /// (dimensions, component types); None: any (relief does not read it).
    fn allowed(self, quantized: bool) -> Option<(&'static [Dimensions], &'static [DataType])> {
        use DataType::{F32, I8, I16, U8, U16, U32};
        use Dimensions::{Scalar, Vec2, Vec3, Vec4};
        // KHR_mesh_quantization's table: positions and texture coordinates
        // of any byte or short, normals and tangents of signed ones
        // (normalized, checked in `check_kind`).
        Some(match self {
            Role::Indices => (&[Scalar], &[U8, U16, U32]),
            Role::Attribute(Semantic::Positions) if quantized => {
                (&[Vec3], &[F32, I8, U8, I16, U16])
            }
            Role::Attribute(Semantic::Normals) if quantized => (&[Vec3], &[F32, I8, I16]),
            Role::Attribute(Semantic::Tangents) if quantized => (&[Vec4], &[F32, I8, I16]),
            Role::Attribute(Semantic::TexCoords(_)) if quantized => {
                (&[Vec2], &[F32, I8, U8, I16, U16])
            }
            Role::Attribute(Semantic::Positions | Semantic::Normals) => (&[Vec3], &[F32]),
            Role::Attribute(Semantic::Tangents) => (&[Vec4], &[F32]),
            Role::Attribute(Semantic::TexCoords(_)) => (&[Vec2], &[F32, U8, U16]),
            Role::Attribute(Semantic::Colors(_)) => (&[Vec3, Vec4], &[F32, U8, U16]),
            Role::Attribute(_) | Role::Data(_) => return None,
        })
    }
}

/// The accessor's element kind is one glTF allows for `role`, and its
/// view's stride holds a whole element.
pub(super) fn check_kind(
    acc: &Accessor,
    role: Role,
    quantized: bool,
    path: &str,
) -> Result<(), Problem> {
    if let Some((dims, types)) = role.allowed(quantized)
        && !(dims.contains(&acc.dimensions()) && types.contains(&acc.data_type()))
    {
        return Err(format!(
            "{path}: {} cannot be {} of {}",
            role.name(),
            dimensions_name(acc.dimensions()),
            type_name(acc.data_type())
        ));
    }
    if role == Role::Indices && acc.normalized() {
        return Err(format!("{path}: indices cannot be normalized"));
    }
    let directions = matches!(
        role,
        Role::Attribute(Semantic::Normals | Semantic::Tangents)
    );
    if directions && acc.data_type() != DataType::F32 && !acc.normalized() {
        return Err(format!(
            "{path}: {} of {} must be normalized",
            role.name(),
            type_name(acc.data_type())
        ));
    }
    let size = acc.size();
    if let Some(stride) = acc.view().and_then(|v| v.stride())
        && stride < size
    {
        return Err(format!(
            "{path}: its bufferView's byteStride {stride} is shorter than one element ({size} bytes)"
        ));
    }
    Ok(())
}

/// The specification's name of an element shape.
fn dimensions_name(d: Dimensions) -> &'static str {
    match d {
        Dimensions::Scalar => "SCALAR",
        Dimensions::Vec2 => "VEC2",
        Dimensions::Vec3 => "VEC3",
        Dimensions::Vec4 => "VEC4",
        Dimensions::Mat2 => "MAT2",
        Dimensions::Mat3 => "MAT3",
        Dimensions::Mat4 => "MAT4",
    }
}

/// A component type in words.
fn type_name(t: DataType) -> &'static str {
    match t {
        DataType::I8 => "signed bytes",
        DataType::U8 => "unsigned bytes",
        DataType::I16 => "signed shorts",
        DataType::U16 => "unsigned shorts",
        DataType::U32 => "unsigned ints",
        DataType::F32 => "floats",
    }
}
