//! `KHR_draco_mesh_compression`: a primitive whose attributes and indices
//! are one Draco stream in a bufferView. Each such primitive is decoded
//! (by the `draco-core` crate, pure Rust) before the file is read, into a
//! new buffer of plain little-endian arrays and new accessors over it, so
//! that everything after reads it as an ordinary primitive.
//!
//! Draco renumbers the points, so the primitive's own indices accessor
//! is replaced by the decoded faces. An attribute keeps its accessor's
//! type and component type (a normalized `UNSIGNED_SHORT` texture
//! coordinate stays one); attributes the stream does not hold keep their
//! own accessors.

use ::gltf::json;
use draco_core::{DecodeLimits, DecoderBuffer, Mesh, MeshDecoder};
use json::accessor::{ComponentType, GenericComponentType};
use json::validation::{Checked, USize64};

use super::data::Problem;
use super::reading::{hold, push_buffer};
use relief_core::budget::Reservation;

/// The extension's name, as files write it.
pub(super) const NAME: &str = "KHR_draco_mesh_compression";

/// What a primitive's extension object says.
struct Stream {
    view: usize,
    /// glTF attribute name → Draco unique id.
    ids: Vec<(String, u32)>,
}

/// Decodes every Draco primitive of `root` into new buffers appended to
/// `buffers` (and to `root.buffers`), and points the primitives at new
/// accessors over them.
pub(super) fn unpack(
    root: &mut json::Root,
    buffers: &mut Vec<Vec<u8>>,
    (name, held): (&str, &mut Reservation),
) -> Result<(), Problem> {
    for m in 0..root.meshes.len() {
        for p in 0..root.meshes[m].primitives.len() {
            let place = format!("meshes[{m}].primitives[{p}]");
            let Some(stream) = stream_of(&root.meshes[m].primitives[p], &place)? else {
                continue;
            };
            let at = (m, p);
            let mesh = decode(root, buffers, (at, &stream), (&place, name, held))?;
            replace(root, buffers, (at, &stream), &mesh);
        }
    }
    Ok(())
}

/// The primitive's Draco extension, if it has one.
fn stream_of(prim: &json::mesh::Primitive, place: &str) -> Result<Option<Stream>, Problem> {
    let Some(ext) = prim.extensions.as_ref().and_then(|e| e.others.get(NAME)) else {
        return Ok(None);
    };
    let bad = || format!("{place}: its {NAME} object is not valid");
    let view = ext
        .get("bufferView")
        .and_then(|v| v.as_u64())
        .ok_or_else(bad)? as usize;
    let ids = ext
        .get("attributes")
        .and_then(|a| a.as_object())
        .ok_or_else(bad)?
        .iter()
        .map(|(k, v)| {
            let id = v.as_u64().and_then(|id| u32::try_from(id).ok());
            id.map(|id| (k.clone(), id)).ok_or_else(bad)
        })
        .collect::<Result<_, _>>()?;
    Ok(Some(Stream { view, ids }))
}

/// Where a primitive is: its mesh and its place in the mesh.
type At = (usize, usize);

/// Decodes one primitive's stream, with the counts its accessors declare
/// as the decoder's limits and the memory budget asked first.
fn decode(
    root: &json::Root,
    buffers: &[Vec<u8>],
    (at, stream): (At, &Stream),
    (place, name, held): (&str, &str, &mut Reservation),
) -> Result<Mesh, Problem> {
    let bytes = view_bytes(root, buffers, stream.view)
        .ok_or_else(|| format!("{place}: its Draco bufferView is not inside its buffer"))?;
    let held_by: Vec<&json::Accessor> = stream
        .ids
        .iter()
        .filter_map(|(semantic, _)| accessor_of(root, at, semantic))
        .collect();
    let points = held_by.iter().map(|a| a.count.0).max().unwrap_or(0);
    let prim = &root.meshes[at.0].primitives[at.1];
    let corners = prim.indices.and_then(|i| root.accessors.get(i.value()));
    let faces = corners.map_or(points, |a| a.count.0) / 3;
    // Decoded values are at most 4 bytes a component; faces 12 bytes.
    let values: u64 = held_by
        .iter()
        .map(|a| a.count.0 * components(a) as u64 * 4)
        .sum();
    hold(held, name, "the decoded Draco data", values + faces * 12)?;
    let limits = DecodeLimits::default()
        .with_max_points(points)
        .with_max_faces(faces)
        .with_max_decoded_bytes(values.max(1));
    let mut mesh = Mesh::new();
    MeshDecoder::new()
        .decode(
            &mut DecoderBuffer::new(bytes).with_limits(limits),
            &mut mesh,
        )
        .map_err(|e| format!("{place}: its Draco data cannot be decoded ({e})"))?;
    Ok(mesh)
}

/// The bytes of bufferView `view`, if it lies inside its buffer.
fn view_bytes<'a>(root: &json::Root, buffers: &'a [Vec<u8>], view: usize) -> Option<&'a [u8]> {
    let v = root.buffer_views.get(view)?;
    let start = v.byte_offset.map_or(0, |o| o.0) as usize;
    let end = start.checked_add(v.byte_length.0 as usize)?;
    buffers.get(v.buffer.value())?.get(start..end)
}

/// The index of the accessor primitive `at` names for attribute `semantic`.
fn accessor_index(root: &json::Root, at: At, semantic: &str) -> Option<usize> {
    let prim = &root.meshes[at.0].primitives[at.1];
    let (_, index) = prim
        .attributes
        .iter()
        .find(|(s, _)| matches!(s, Checked::Valid(s) if s.to_string() == semantic))?;
    (index.value() < root.accessors.len()).then_some(index.value())
}

/// The accessor primitive `at` names for attribute `semantic`.
fn accessor_of<'a>(root: &'a json::Root, at: At, semantic: &str) -> Option<&'a json::Accessor> {
    accessor_index(root, at, semantic).map(|i| &root.accessors[i])
}

/// Components of one element of `a` (1 for SCALAR … 16 for MAT4).
fn components(a: &json::Accessor) -> usize {
    match a.type_ {
        Checked::Valid(t) => t.multiplicity(),
        Checked::Invalid => 0,
    }
}

/// Appends the decoded mesh as one buffer and rewrites primitive `at`'s
/// accessors in place over it (glTF leaves them without a bufferView):
/// its attributes in their own component types, its indices as
/// `UNSIGNED_INT` (a new accessor if it had none).
fn replace(
    root: &mut json::Root,
    buffers: &mut Vec<Vec<u8>>,
    (at, stream): (At, &Stream),
    mesh: &Mesh,
) {
    let n = mesh.num_points();
    let buffer = buffers.len();
    let mut bytes = Vec::new();
    for (semantic, id) in &stream.ids {
        let (Some(attribute), Some(index)) = (
            mesh.attribute_by_unique_id(*id),
            accessor_index(root, at, semantic),
        ) else {
            continue;
        };
        let old = &root.accessors[index];
        let Checked::Valid(GenericComponentType(kind)) = old.component_type else {
            continue;
        };
        let values = attribute.read_f32s(n, components(old));
        let start = bytes.len();
        write_as(&mut bytes, &values, kind);
        let view = push_view(root, buffer, start, bytes.len() - start);
        let a = &mut root.accessors[index];
        a.count = USize64(n as u64);
        a.sparse = None;
        a.buffer_view = Some(json::Index::new(view));
        a.byte_offset = None;
        // Views start on 4-byte boundaries, as glTF asks.
        bytes.resize(bytes.len().next_multiple_of(4), 0);
    }
    let start = bytes.len();
    for face in mesh.faces() {
        for corner in face {
            bytes.extend_from_slice(&corner.0.to_le_bytes());
        }
    }
    let view = push_view(root, buffer, start, bytes.len() - start);
    let indices = indices_accessor(view, mesh.num_faces() * 3);
    push_buffer(root, buffers, bytes);
    match root.meshes[at.0].primitives[at.1].indices {
        Some(i) if i.value() < root.accessors.len() => root.accessors[i.value()] = indices,
        _ => {
            root.accessors.push(indices);
            let index = json::Index::new((root.accessors.len() - 1) as u32);
            root.meshes[at.0].primitives[at.1].indices = Some(index);
        }
    }
}

/// Appends `values` as little-endian `kind`s (integers rounded and held
/// to their range; Draco gives them back as whole numbers).
fn write_as(bytes: &mut Vec<u8>, values: &[f32], kind: ComponentType) {
    for &v in values {
        match kind {
            ComponentType::F32 => bytes.extend_from_slice(&v.to_le_bytes()),
            ComponentType::I8 => bytes.push((v.round() as i8) as u8),
            ComponentType::U8 => bytes.push(v.round() as u8),
            ComponentType::I16 => bytes.extend_from_slice(&(v.round() as i16).to_le_bytes()),
            ComponentType::U16 => bytes.extend_from_slice(&(v.round() as u16).to_le_bytes()),
            ComponentType::U32 => bytes.extend_from_slice(&(v.round() as u32).to_le_bytes()),
        }
    }
}

/// A new bufferView of `length` bytes at `start` of buffer `buffer`.
fn push_view(root: &mut json::Root, buffer: usize, start: usize, length: usize) -> u32 {
    root.buffer_views.push(json::buffer::View {
        buffer: json::Index::new(buffer as u32),
        byte_length: USize64(length as u64),
        byte_offset: Some(USize64(start as u64)),
        byte_stride: None,
        name: None,
        target: None,
        extensions: None,
        extras: Default::default(),
    });
    (root.buffer_views.len() - 1) as u32
}

/// A SCALAR `UNSIGNED_INT` accessor of `count` indices over view `view`.
fn indices_accessor(view: u32, count: usize) -> json::Accessor {
    json::Accessor {
        buffer_view: Some(json::Index::new(view)),
        byte_offset: None,
        count: USize64(count as u64),
        component_type: Checked::Valid(GenericComponentType(ComponentType::U32)),
        extensions: None,
        extras: Default::default(),
        type_: Checked::Valid(json::accessor::Type::Scalar),
        min: None,
        max: None,
        name: None,
        normalized: false,
        sparse: None,
    }
}
