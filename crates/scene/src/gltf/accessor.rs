//! Vertex attributes read from their accessors whatever their component
//! type: floats, and the integers `KHR_mesh_quantization` allows (signed
//! and unsigned bytes and shorts, normalized or not), dequantized as the
//! glTF specification says (§3.11: a normalized signed byte c is
//! max(c / 127, −1), an unsigned one c / 255; shorts over 32767 and
//! 65535; not normalized, the integer as it is). Sparse accessors (core
//! glTF) are read here too: the base elements (zeros without a
//! bufferView) with the substitutions laid over them. `check_accessor`
//! and `check_sparse` have checked every range before anything reads.

use ::gltf::accessor::{Accessor, DataType};

use super::data::Problem;

/// A run of elements in a buffer: `count` of `width` components of type
/// `ty`, each `stride` bytes from the last.
#[derive(Clone, Copy)]
struct Run<'a> {
    bytes: &'a [u8],
    stride: usize,
    ty: DataType,
    normalized: bool,
    width: usize,
}

impl Run<'_> {
    /// Element `k` as up to four floats (the rest 0).
    fn at(&self, k: usize) -> [f32; 4] {
        let size = component_size(self.ty);
        let mut out = [0.0; 4];
        for (c, slot) in out.iter_mut().enumerate().take(self.width) {
            let start = k * self.stride + c * size;
            if let Some(b) = self.bytes.get(start..start + size) {
                *slot = component(b, self.ty, self.normalized);
            }
        }
        out
    }

    /// Element `k`'s first component as an unsigned integer (indices:
    /// unsigned bytes, shorts or ints; 0 for any other type, or past the
    /// run, which the checks exclude).
    fn uint(&self, k: usize) -> u32 {
        let start = k * self.stride;
        let b = |n: usize| self.bytes.get(start..start + n);
        match self.ty {
            DataType::U8 => b(1).map_or(0, |b| b[0] as u32),
            DataType::U16 => b(2).map_or(0, |b| u16::from_le_bytes([b[0], b[1]]) as u32),
            DataType::U32 => b(4).map_or(0, |b| u32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            _ => 0,
        }
    }
}

/// A sparse accessor's substitutions, taken in order as the elements are
/// read (their positions strictly increase).
struct Substitutions<'a> {
    at: Run<'a>,
    values: Run<'a>,
    count: usize,
    next: usize,
}

impl Substitutions<'_> {
    /// The position in `values` of the substitution for element `k`, if
    /// there is one.
    fn take(&mut self, k: usize) -> Option<usize> {
        let here = self.next < self.count && self.at.uint(self.next) as usize == k;
        self.next += here as usize;
        here.then_some(self.next - 1)
    }
}

/// Bytes of one component of type `ty`.
fn component_size(ty: DataType) -> usize {
    match ty {
        DataType::I8 | DataType::U8 => 1,
        DataType::I16 | DataType::U16 => 2,
        DataType::U32 | DataType::F32 => 4,
    }
}

/// One component's value from its little-endian bytes.
fn component(b: &[u8], ty: DataType, normalized: bool) -> f32 {
    let (value, max) = match ty {
        DataType::F32 => return f32::from_le_bytes([b[0], b[1], b[2], b[3]]),
        DataType::I8 => (b[0] as i8 as f32, 127.0),
        DataType::U8 => (b[0] as f32, 255.0),
        DataType::I16 => (i16::from_le_bytes([b[0], b[1]]) as f32, 32767.0),
        DataType::U16 => (u16::from_le_bytes([b[0], b[1]]) as f32, 65535.0),
        DataType::U32 => (
            u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f32,
            u32::MAX as f32,
        ),
    };
    if normalized {
        (value / max).max(-1.0)
    } else {
        value
    }
}

/// The bytes of a buffer view from `offset` on, if they are there.
fn view_from<'a>(view: &::gltf::buffer::View, offset: usize, buffers: &'a [Vec<u8>]) -> &'a [u8] {
    let buffer = buffers
        .get(view.buffer().index())
        .map_or(&[][..], Vec::as_slice);
    let start = view.offset().saturating_add(offset);
    let end = view
        .offset()
        .saturating_add(view.length())
        .min(buffer.len());
    buffer.get(start..end).unwrap_or(&[])
}

/// An accessor's elements, as up to four floats each, sparse
/// substitutions applied.
pub(super) fn floats<'a>(
    acc: &Accessor<'a>,
    buffers: &'a [Vec<u8>],
) -> impl Iterator<Item = [f32; 4]> + use<'a> {
    let (base, mut sparse) = runs(acc, buffers);
    (0..acc.count()).map(move |k| match sparse.as_mut().and_then(|s| s.take(k)) {
        Some(i) => sparse.as_ref().map_or([0.0; 4], |s| s.values.at(i)),
        None => base.map_or([0.0; 4], |b| b.at(k)),
    })
}

/// An index accessor's elements (unsigned bytes, shorts or ints), sparse
/// substitutions applied: read here rather than through the `gltf`
/// crate's reader, which the build compiles unoptimised (docs: Cargo.toml)
/// and which took 50 ms over a model of 100 k triangles.
pub(super) fn indices<'a>(
    acc: &Accessor<'a>,
    buffers: &'a [Vec<u8>],
) -> impl Iterator<Item = u32> + use<'a> {
    let (base, mut sparse) = runs(acc, buffers);
    (0..acc.count()).map(move |k| match sparse.as_mut().and_then(|s| s.take(k)) {
        Some(i) => sparse.as_ref().map_or(0, |s| s.values.uint(i)),
        None => base.map_or(0, |b| b.uint(k)),
    })
}

/// An accessor's base elements (none without a bufferView) and its sparse
/// substitutions, if any.
fn runs<'a>(
    acc: &Accessor<'a>,
    buffers: &'a [Vec<u8>],
) -> (Option<Run<'a>>, Option<Substitutions<'a>>) {
    let width = acc.dimensions().multiplicity();
    let ty = acc.data_type();
    let element = component_size(ty) * width;
    let base = acc.view().map(|view| Run {
        bytes: view_from(&view, acc.offset(), buffers),
        stride: view.stride().unwrap_or(element),
        ty,
        normalized: acc.normalized(),
        width,
    });
    let sparse = acc.sparse().map(|s| {
        let indices = s.indices();
        let size = indices.index_type().size();
        let at = Run {
            bytes: view_from(&indices.view(), indices.offset(), buffers),
            stride: size,
            ty: index_type(indices.index_type()),
            normalized: false,
            width: 1,
        };
        let values = s.values();
        let values = Run {
            bytes: view_from(&values.view(), values.offset(), buffers),
            stride: element,
            ..base.unwrap_or(Run {
                bytes: &[],
                stride: element,
                ty,
                normalized: acc.normalized(),
                width,
            })
        };
        Substitutions {
            at,
            values,
            count: s.count(),
            next: 0,
        }
    });
    (base, sparse)
}

/// The component type of a sparse accessor's indices.
fn index_type(t: ::gltf::accessor::sparse::IndexType) -> DataType {
    use ::gltf::accessor::sparse::IndexType;
    match t {
        IndexType::U8 => DataType::U8,
        IndexType::U16 => DataType::U16,
        IndexType::U32 => DataType::U32,
    }
}

/// A sparse accessor's substitutions lie inside their views, their
/// indices within the accessor's count and strictly increasing (as the
/// specification asks: the reader lays them over the base in one pass).
pub(super) fn check_sparse(acc: &Accessor, buffers: &[Vec<u8>], path: &str) -> Result<(), Problem> {
    let Some(sparse) = acc.sparse() else {
        return Ok(());
    };
    let (n, count) = (sparse.count(), acc.count());
    if n == 0 || n > count {
        return Err(format!(
            "{path}: its sparse count {n} is not within 1 to its count {count}"
        ));
    }
    let indices = sparse.indices();
    let size = indices.index_type().size();
    let bytes = view_from(&indices.view(), indices.offset(), buffers);
    if bytes.len() / size < n
        || indices.view().offset() + indices.view().length() > buffer_len(&indices.view(), buffers)
    {
        return Err(format!(
            "{path}: its {n} sparse indices are past the end of their bufferView"
        ));
    }
    let ty = index_type(indices.index_type());
    let mut last = None;
    for k in 0..n {
        let b = &bytes[k * size..(k + 1) * size];
        let i = match ty {
            DataType::U8 => b[0] as u64,
            DataType::U16 => u16::from_le_bytes([b[0], b[1]]) as u64,
            _ => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as u64,
        };
        if i >= count as u64 {
            return Err(format!(
                "{path}: sparse index {k} is {i}, past its {count} elements"
            ));
        }
        if last.is_some_and(|l| i <= l) {
            return Err(format!(
                "{path}: sparse index {k} ({i}) does not follow the one before it"
            ));
        }
        last = Some(i);
    }
    let values = sparse.values();
    let element = acc.size();
    let bytes = view_from(&values.view(), values.offset(), buffers);
    if bytes.len() / element < n
        || values.view().offset() + values.view().length() > buffer_len(&values.view(), buffers)
    {
        return Err(format!(
            "{path}: its {n} sparse values are past the end of their bufferView"
        ));
    }
    Ok(())
}

/// The length of a view's buffer (0 if it has none).
fn buffer_len(view: &::gltf::buffer::View, buffers: &[Vec<u8>]) -> usize {
    buffers.get(view.buffer().index()).map_or(0, Vec::len)
}

/// A MAT4 accessor's matrices (column-major, as glTF stores them), sparse
/// substitutions not read (the caller refuses a sparse one).
pub(super) fn matrices<'a>(
    acc: &Accessor<'a>,
    buffers: &'a [Vec<u8>],
) -> impl Iterator<Item = glam::Mat4> + use<'a> {
    let ty = acc.data_type();
    let size = component_size(ty);
    let columns = acc.view().map(|view| Run {
        bytes: view_from(&view, acc.offset(), buffers),
        stride: view.stride().unwrap_or(16 * size),
        ty,
        normalized: acc.normalized(),
        width: 4,
    });
    (0..acc.count()).map(move |k| {
        let Some(run) = columns else {
            return glam::Mat4::ZERO;
        };
        // Column c of element k starts 4c components in: a run of four
        // components whose element is at k·stride + 4c·size.
        let column = |c: usize| {
            let shifted = Run {
                bytes: run.bytes.get(4 * c * size..).unwrap_or(&[]),
                ..run
            };
            glam::Vec4::from(shifted.at(k))
        };
        glam::Mat4::from_cols(column(0), column(1), column(2), column(3))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn components_dequantize_as_the_specification_says() {
        assert_eq!(component(&[127], DataType::I8, true), 1.0);
        assert_eq!(component(&[0x81], DataType::I8, true), -1.0);
        assert_eq!(component(&[0x80], DataType::I8, true), -1.0);
        assert_eq!(component(&[0x80], DataType::I8, false), -128.0);
        assert_eq!(component(&[51], DataType::U8, true), 0.2);
        assert_eq!(component(&[200], DataType::U8, false), 200.0);
        assert_eq!(component(&32767i16.to_le_bytes(), DataType::I16, true), 1.0);
        assert_eq!(
            component(&(-300i16).to_le_bytes(), DataType::I16, false),
            -300.0
        );
        assert_eq!(component(&65535u16.to_le_bytes(), DataType::U16, true), 1.0);
        assert_eq!(component(&1.5f32.to_le_bytes(), DataType::F32, false), 1.5);
    }
}
