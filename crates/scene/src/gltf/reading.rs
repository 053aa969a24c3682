//! What every reader of a glTF file's data shares: the memory it
//! reserves before it allocates, and the checks an accessor passes before
//! it is read.

use ::gltf::accessor::Accessor;

use super::accessor;
use super::data::Problem;
use super::validate::{self, Role};
use relief_core::budget::Reservation;

/// Deepest node hierarchy walked (a file with a cycle would never end).
pub(super) const MAX_DEPTH: usize = 64;

/// Bytes of `n` values of `T`.
pub(super) fn bytes_of<T>(n: u64) -> u64 {
    n.saturating_mul(std::mem::size_of::<T>() as u64)
}

/// Reserves `bytes` more in `held` for `what` of model `name`, before it
/// is allocated.
pub(super) fn hold(
    held: &mut Reservation,
    name: &str,
    what: &str,
    bytes: u64,
) -> Result<(), Problem> {
    held.grow(&format!("{what} of model {name}"), bytes)
        .map_err(|e| e.to_string())
}

/// Checks that an accessor's elements lie inside its view and the view
/// inside its buffer.
pub(super) fn check_accessor(
    acc: &Accessor,
    buffers: &[Vec<u8>],
    (role, quantized): (Role, bool),
    place: &str,
) -> Result<(), Problem> {
    let path = format!("accessors[{}] ({} of {place})", acc.index(), role.name());
    validate::check_kind(acc, role, quantized, &path)?;
    accessor::check_sparse(acc, buffers, &path)?;
    let Some(view) = acc.view() else {
        // A sparse accessor without one starts from zeros.
        if acc.sparse().is_some() {
            return Ok(());
        }
        return Err(format!("{path}: it has no bufferView"));
    };
    let have = buffers.get(view.buffer().index()).map_or(0, |b| b.len()) as u64;
    let (start, length) = (view.offset() as u64, view.length() as u64);
    if start.saturating_add(length) > have {
        return Err(format!(
            "bufferViews[{}]: bytes {start}..{} are past the end of buffers[{}] ({have} bytes)",
            view.index(),
            start.saturating_add(length),
            view.buffer().index()
        ));
    }
    let size = acc.size() as u64;
    let stride = view.stride().map_or(size, |s| s as u64);
    let count = acc.count() as u64;
    if count == 0 {
        return Ok(());
    }
    let end = (count - 1)
        .saturating_mul(stride)
        .saturating_add(acc.offset() as u64)
        .saturating_add(size);
    if end > length {
        return Err(format!(
            "{path}: {count} elements reach byte {end} of bufferViews[{}], which has {length}",
            view.index()
        ));
    }
    Ok(())
}

/// Appends `bytes` as a new buffer, in the JSON and beside the others.
pub(super) fn push_buffer(
    root: &mut ::gltf::json::Root,
    buffers: &mut Vec<Vec<u8>>,
    bytes: Vec<u8>,
) {
    root.buffers.push(::gltf::json::Buffer {
        byte_length: ::gltf::json::validation::USize64(bytes.len() as u64),
        name: None,
        uri: None,
        extensions: None,
        extras: Default::default(),
    });
    buffers.push(bytes);
}
