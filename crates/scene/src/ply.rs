//! PLY models: ASCII, binary little endian and binary big endian.
//!
//! The header declares elements and their properties; relief reads the
//! `vertex` element's `x y z`, normals `nx ny nz`, colours `red green blue`
//! (or `r g b`, `diffuse_red …`; unsigned bytes are divided by 255, floats
//! taken as they are), texture coordinates under their usual names (`u v`,
//! `s t`, `texture_u texture_v`, `texture_s texture_t`), and the `face`
//! element's `vertex_indices` (or `vertex_index`) list of any count and
//! index type. Other elements and properties are skipped.
//!
//! A first pass walks the body without keeping anything: counts are
//! checked against the bytes that remain (a binary element of 2^31 items
//! needs that many records), and the triangles are counted, so the memory
//! budget is asked before anything of the model's size exists. Errors say
//! the header line, the body line (ASCII) or the byte offset (binary).
//!
//! The vertices are read into shared arrays (a position, and a normal, UV
//! or colour only when the element has them) and the faces, fanned into
//! triangles, into corners indexing them, as an OBJ's `v` lines and faces
//! are: 36 bytes a triangle and 12 to 48 a vertex. A file read from disk
//! is freed before the model is built ([`load`]).
//!
//! A PLY with vertices and no faces is a point cloud: each point becomes a
//! triangle with three equal corners, which the points display draws.

use glam::{Vec2, Vec3};

use super::corners::{
    IndexedCorners, MAX_FACE_CORNERS, NO_INDEX, build_indexed, bytes_of, fit_of, fitted,
};
use super::loaded_model::{LoadedModel, ModelMaps, ModelPart};
use super::mesh::{Face, Mesh, Vertex};
use super::model_error::ObjError;
use super::model_io::{FileBytes, reserve};
use relief_core::budget::Reservation;

#[derive(Clone, Copy, Debug, PartialEq)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn parse(word: &str) -> Option<Scalar> {
        Some(match word {
            "char" | "int8" => Scalar::I8,
            "uchar" | "uint8" => Scalar::U8,
            "short" | "int16" => Scalar::I16,
            "ushort" | "uint16" => Scalar::U16,
            "int" | "int32" => Scalar::I32,
            "uint" | "uint32" => Scalar::U32,
            "float" | "float32" => Scalar::F32,
            "double" | "float64" => Scalar::F64,
            _ => return None,
        })
    }
    fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }
    /// The type's name in PLY headers.
    fn name(self) -> &'static str {
        match self {
            Scalar::I8 => "char",
            Scalar::U8 => "uchar",
            Scalar::I16 => "short",
            Scalar::U16 => "ushort",
            Scalar::I32 => "int",
            Scalar::U32 => "uint",
            Scalar::F32 => "float",
            Scalar::F64 => "double",
        }
    }
    fn is_float(self) -> bool {
        matches!(self, Scalar::F32 | Scalar::F64)
    }
}

#[derive(Clone, Debug)]
struct Property {
    name: String,
    /// The count's type for a list.
    list: Option<Scalar>,
    ty: Scalar,
}

#[derive(Clone, Debug)]
struct Element {
    name: String,
    count: u64,
    properties: Vec<Property>,
}

#[derive(Clone, Copy, PartialEq)]
enum Format {
    Ascii,
    Little,
    Big,
}

/// The body being read: a cursor with its line (ASCII) or byte offset.
struct Body<'a> {
    bytes: &'a [u8],
    pos: usize,
    line: usize,
    format: Format,
}

impl Body<'_> {
    fn remaining(&self) -> u64 {
        (self.bytes.len() - self.pos) as u64
    }

    /// The next value, as a double.
    fn value(&mut self, ty: Scalar) -> Result<f64, String> {
        if self.format == Format::Ascii {
            // Skip blanks, counting lines.
            while let Some(&b) = self.bytes.get(self.pos) {
                if !b.is_ascii_whitespace() {
                    break;
                }
                if b == b'\n' {
                    self.line += 1;
                }
                self.pos += 1;
            }
            let start = self.pos;
            while self
                .bytes
                .get(self.pos)
                .is_some_and(|b| !b.is_ascii_whitespace())
            {
                self.pos += 1;
            }
            let word = &self.bytes[start..self.pos];
            if word.is_empty() {
                return Err("the file ends before the data its header declares".into());
            }
            let text = std::str::from_utf8(word).unwrap_or("?");
            let value = if ty.is_float() {
                text.parse::<f64>().ok()
            } else {
                text.parse::<i64>().ok().map(|i| i as f64)
            };
            return value.ok_or_else(|| {
                let shown: String = relief_core::sanitize::clean(text)
                    .chars()
                    .take(24)
                    .collect();
                format!("'{shown}' is not a {} number", ty.name())
            });
        }
        let size = ty.size();
        let Some(raw) = self.bytes.get(self.pos..self.pos + size) else {
            return Err("the file ends before the data its header declares".into());
        };
        self.pos += size;
        let mut b = [0u8; 8];
        b[..size].copy_from_slice(raw);
        if self.format == Format::Big {
            b[..size].reverse();
        }
        Ok(match ty {
            Scalar::I8 => b[0] as i8 as f64,
            Scalar::U8 => b[0] as f64,
            Scalar::I16 => i16::from_le_bytes([b[0], b[1]]) as f64,
            Scalar::U16 => u16::from_le_bytes([b[0], b[1]]) as f64,
            Scalar::I32 => i32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
            Scalar::U32 => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
            Scalar::F32 => f32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
            Scalar::F64 => f64::from_le_bytes(b),
        })
    }

    /// A list's length.
    fn length(&mut self, ty: Scalar) -> Result<usize, String> {
        let n = self.value(ty)?;
        if !(n >= 0.0 && n.fract() == 0.0) {
            return Err(format!("a list length of {n}"));
        }
        if n > MAX_FACE_CORNERS as f64 {
            return Err(format!("a list of {n} items (limit {MAX_FACE_CORNERS})"));
        }
        Ok(n as usize)
    }
}

/// Reads a PLY file; `name` (already sanitised) is used in messages.
pub fn parse(name: &str, bytes: &[u8]) -> Result<LoadedModel, ObjError> {
    guarded(name, || {
        let (corners, held, warnings) = read(name, bytes)?;
        finish(name, corners, held, warnings)
    })
}

/// [`parse`] of a file's bytes read with the reservation `held` that
/// covers them: they are freed, with it, before the model is built.
pub(crate) fn load(
    name: &str,
    bytes: FileBytes,
    held: Reservation,
) -> Result<LoadedModel, ObjError> {
    guarded(name, move || {
        let read = read(name, &bytes);
        bytes.check(name)?;
        let (corners, read_held, warnings) = read?;
        drop(bytes);
        drop(held);
        finish(name, corners, read_held, warnings)
    })
}

/// `f`, a panic in it made an error like any other.
fn guarded(
    name: &str,
    f: impl FnOnce() -> Result<LoadedModel, ObjError>,
) -> Result<LoadedModel, ObjError> {
    relief_core::contain::contain(f).unwrap_or_else(|cause| {
        Err(ObjError::Parse {
            name: name.to_string(),
            reason: format!("the reader failed on it ({cause})"),
        })
    })
}

/// The header's words relief reads; a line that begins with another word
/// is skipped with a warning (Blender 2.4 wrote a "Created by Blender3D …"
/// line without `comment`, and assimp and Blender read such files), one
/// that begins with one of these but cannot be read refuses the file.
const HEADER_WORDS: &[&str] = &["ply", "format", "element", "property", "end_header"];

/// What the header says: format, elements, where the body starts, and the
/// lines skipped (as warnings).
struct Header {
    format: Format,
    elements: Vec<Element>,
    start: usize,
    warnings: Vec<String>,
}

/// The header: elements, format, and where the body starts.
fn header(name: &str, bytes: &[u8]) -> Result<Header, ObjError> {
    if !bytes.starts_with(b"ply") {
        return Err(line_error(
            name,
            1,
            "not a PLY file (it does not begin with 'ply')".into(),
        ));
    }
    let mut pos = 0;
    let mut reader = HeaderReader {
        name,
        format: None,
        elements: Vec::new(),
        warnings: Vec::new(),
    };
    for number in 1.. {
        let Some(end) = bytes[pos..].iter().position(|&b| b == b'\n') else {
            return Err(line_error(
                name,
                number,
                "the header has no 'end_header'".into(),
            ));
        };
        let line = String::from_utf8_lossy(&bytes[pos..pos + end]).into_owned();
        pos += end + 1;
        if reader.read_line(number, &line)? {
            return reader.finish(number, pos);
        }
    }
    unreachable!("the header loop returns")
}

/// The error of line `line` of model `name`.
fn line_error(name: &str, line: usize, problem: String) -> ObjError {
    ObjError::Line {
        name: name.to_string(),
        line,
        problem,
    }
}

/// `text` made safe to print and cut to `chars` characters, to be quoted
/// in a message.
fn shown(text: &str, chars: usize) -> String {
    relief_core::sanitize::clean(text)
        .chars()
        .take(chars)
        .collect()
}

/// The header of model `name` read so far, one line at a time.
struct HeaderReader<'a> {
    name: &'a str,
    format: Option<Format>,
    elements: Vec<Element>,
    warnings: Vec<String>,
}

impl HeaderReader<'_> {
    /// Reads header line `number`, `line`: true when it ends the header.
    fn read_line(&mut self, number: usize, line: &str) -> Result<bool, ObjError> {
        let words: Vec<&str> = line.split_whitespace().collect();
        match words.as_slice() {
            ["ply"] if number == 1 => {}
            ["format", kind, _version] => self.format = Some(self.format_of(number, kind)?),
            ["comment", ..] | ["obj_info", ..] | [] => {}
            ["element", element, count] => self.add_element(number, element, count)?,
            ["property", "list", count, item, property] => {
                self.add_list_property(number, count, item, property)?
            }
            ["property", ty, property] => self.add_property(number, ty, property)?,
            ["end_header"] => return Ok(true),
            [word, ..] if !HEADER_WORDS.contains(word) => {
                let shown = shown(line, 40);
                let name = self.name;
                self.warnings.push(format!(
                    "model {name}, line {number}: header line '{shown}' skipped (not a PLY keyword)"
                ));
            }
            _ => {
                let shown = shown(line, 40);
                return Err(self.at(number, format!("cannot read header line '{shown}'")));
            }
        }
        Ok(false)
    }

    /// The error of header line `number`.
    fn at(&self, number: usize, problem: String) -> ObjError {
        line_error(self.name, number, problem)
    }

    /// The format a `format` line names.
    fn format_of(&self, number: usize, kind: &str) -> Result<Format, ObjError> {
        Ok(match kind {
            "ascii" => Format::Ascii,
            "binary_little_endian" => Format::Little,
            "binary_big_endian" => Format::Big,
            other => {
                let shown = shown(other, 24);
                return Err(self.at(number, format!("unknown format '{shown}'")));
            }
        })
    }

    /// An `element` line: a new element, without properties yet.
    fn add_element(&mut self, number: usize, element: &str, count: &str) -> Result<(), ObjError> {
        let count = count
            .parse::<u64>()
            .map_err(|_| self.at(number, format!("element {element}: bad count")))?;
        self.elements.push(Element {
            name: element.to_string(),
            count,
            properties: Vec::new(),
        });
        Ok(())
    }

    /// A `property list` line, added to the last element.
    fn add_list_property(
        &mut self,
        number: usize,
        count: &str,
        item: &str,
        property: &str,
    ) -> Result<(), ObjError> {
        let (Some(count), Some(item)) = (Scalar::parse(count), Scalar::parse(item)) else {
            return Err(self.at(number, "unknown type in a list property".into()));
        };
        if count.is_float() {
            return Err(self.at(number, "a list's count must be an integer type".into()));
        }
        self.last_element(number)?.properties.push(Property {
            name: property.to_string(),
            list: Some(count),
            ty: item,
        });
        Ok(())
    }

    /// A `property` line of one value, added to the last element.
    fn add_property(&mut self, number: usize, ty: &str, property: &str) -> Result<(), ObjError> {
        let ty =
            Scalar::parse(ty).ok_or_else(|| self.at(number, "unknown property type".into()))?;
        self.last_element(number)?.properties.push(Property {
            name: property.to_string(),
            list: None,
            ty,
        });
        Ok(())
    }

    /// The element a property line at `number` belongs to.
    fn last_element(&mut self, number: usize) -> Result<&mut Element, ObjError> {
        let name = self.name;
        self.elements
            .last_mut()
            .ok_or_else(|| line_error(name, number, "a property before any element".into()))
    }

    /// The header, ended at line `number` with the body from `start`.
    fn finish(self, number: usize, start: usize) -> Result<Header, ObjError> {
        let format = self
            .format
            .ok_or_else(|| self.at(number, "no 'format' line".into()))?;
        Ok(Header {
            format,
            elements: self.elements,
            start,
            warnings: self.warnings,
        })
    }
}

/// Which of a vertex's properties relief reads, by index.
#[derive(Default)]
struct VertexLayout {
    position: [Option<usize>; 3],
    normal: [Option<usize>; 3],
    color: [Option<usize>; 3],
    uv: [Option<usize>; 2],
}

fn vertex_layout(e: &Element) -> VertexLayout {
    let find = |names: &[&str]| {
        e.properties
            .iter()
            .position(|p| p.list.is_none() && names.contains(&p.name.as_str()))
    };
    VertexLayout {
        position: [find(&["x"]), find(&["y"]), find(&["z"])],
        normal: [find(&["nx"]), find(&["ny"]), find(&["nz"])],
        color: [
            find(&["red", "r", "diffuse_red"]),
            find(&["green", "g", "diffuse_green"]),
            find(&["blue", "b", "diffuse_blue"]),
        ],
        uv: [
            find(&["u", "s", "texture_u", "texture_s"]),
            find(&["v", "t", "texture_v", "texture_t"]),
        ],
    }
}

/// The face list property relief reads.
fn face_list(e: &Element) -> Option<usize> {
    e.properties
        .iter()
        .position(|p| p.list.is_some() && (p.name == "vertex_indices" || p.name == "vertex_index"))
}

/// The least bytes one item of `e` takes in the body.
fn least_item_bytes(e: &Element, format: Format) -> u64 {
    e.properties
        .iter()
        .map(|p| match (format, p.list) {
            // A word and a blank.
            (Format::Ascii, _) => 2,
            (_, Some(count)) => count.size() as u64,
            (_, None) => p.ty.size() as u64,
        })
        .sum()
}

/// Reads the file's vertices into shared arrays and its faces, fanned into
/// triangles, as corners indexing them, with the reservation covering both.
fn read(name: &str, bytes: &[u8]) -> Result<(IndexedCorners, Reservation, Vec<String>), ObjError> {
    let Header {
        format,
        elements,
        start,
        warnings,
    } = header(name, bytes)?;
    let vertex_element = elements.iter().position(|e| e.name == "vertex");
    let Some(vertex_element) = vertex_element else {
        return Err(ObjError::Empty {
            name: name.to_string(),
        });
    };
    let mut body = Body {
        bytes,
        pos: start,
        line: bytes[..start].iter().filter(|&&b| b == b'\n').count() + 1,
        format,
    };
    check_counts(name, &elements, &body)?;
    let triangles = count_triangles(name, &elements, Body { ..body })?;
    let vertices = &elements[vertex_element];
    if vertices.count >= NO_INDEX as u64 {
        return Err(ObjError::Unsupported {
            name: name.to_string(),
            what: format!("more than {} vertices", NO_INDEX - 1),
        });
    }
    let has = Has::of(&vertex_layout(vertices));
    let (mut c, held) = reserve_arrays(name, vertices.count, has, triangles)?;
    // Second pass: read.
    for e in &elements {
        read_element(name, e, has, &mut body, &mut c)?;
    }
    if c.positions.is_empty() {
        return Err(ObjError::Empty {
            name: name.to_string(),
        });
    }
    Ok((c, held, warnings))
}

impl Body<'_> {
    /// The error `problem` at the body's place: a line in ASCII, a byte
    /// offset in binary.
    fn fail(&self, name: &str, problem: String) -> ObjError {
        match self.format {
            Format::Ascii => ObjError::Line {
                name: name.to_string(),
                line: self.line,
                problem,
            },
            _ => ObjError::Byte {
                name: name.to_string(),
                offset: self.pos as u64,
                problem,
            },
        }
    }
}

/// Checks the header's counts against the bytes that remain, before
/// anything is read.
fn check_counts(name: &str, elements: &[Element], body: &Body) -> Result<(), ObjError> {
    let mut least = 0u64;
    for e in elements {
        least = least.saturating_add(e.count.saturating_mul(least_item_bytes(e, body.format)));
    }
    if least <= body.remaining() {
        return Ok(());
    }
    let e = elements
        .iter()
        .max_by_key(|e| e.count)
        .map(|e| (e.name.clone(), e.count))
        .unwrap_or_default();
    Err(body.fail(
        name,
        format!(
            "the header declares {} {} items, more than the {} bytes after it can hold",
            e.1,
            relief_core::sanitize::clean(&e.0),
            body.remaining()
        ),
    ))
}

/// First pass: counts the triangles the faces fan into, keeping nothing.
fn count_triangles(name: &str, elements: &[Element], mut walk: Body) -> Result<u64, ObjError> {
    let mut triangles = 0u64;
    for e in elements {
        let list = face_list(e).filter(|_| e.name == "face");
        for _ in 0..e.count {
            for (k, p) in e.properties.iter().enumerate() {
                match p.list {
                    Some(count) => {
                        let n = walk.length(count).map_err(|m| walk.fail(name, m))?;
                        if Some(k) == list {
                            triangles += n.saturating_sub(2) as u64;
                        }
                        for _ in 0..n {
                            walk.value(p.ty).map_err(|m| walk.fail(name, m))?;
                        }
                    }
                    None => {
                        walk.value(p.ty).map_err(|m| walk.fail(name, m))?;
                    }
                }
            }
        }
    }
    Ok(triangles)
}

/// Which attributes the vertex element has.
#[derive(Clone, Copy)]
struct Has {
    normal: bool,
    color: bool,
    uv: bool,
}

impl Has {
    fn of(layout: &VertexLayout) -> Has {
        let has = |idx: &[Option<usize>]| idx.iter().all(Option::is_some);
        Has {
            normal: has(&layout.normal),
            color: has(&layout.color),
            uv: has(&layout.uv),
        }
    }
}

/// Reserves the arrays: the vertices' attributes go into shared arrays (the
/// faces index them, as an OBJ's `v` lines are), an array only for what
/// the vertex element has; the triangles' corners.
fn reserve_arrays(
    name: &str,
    vertex_count: u64,
    has: Has,
    triangles: u64,
) -> Result<(IndexedCorners, Reservation), ObjError> {
    let per_vertex = bytes_of::<Vec3>(1)
        + if has.normal { bytes_of::<Vec3>(1) } else { 0 }
        + if has.color {
            bytes_of::<Option<Vec3>>(1)
        } else {
            0
        }
        + if has.uv { bytes_of::<Vec2>(1) } else { 0 };
    let held = reserve(
        name,
        "the vertices and triangles",
        vertex_count
            .saturating_mul(per_vertex)
            .saturating_add(bytes_of::<[u32; 3]>(triangles.saturating_mul(3))),
    )?;
    let with = |yes: bool, n: u64| if yes { n as usize } else { 0 };
    let c = IndexedCorners {
        positions: Vec::with_capacity(vertex_count as usize),
        colors: Vec::with_capacity(with(has.color, vertex_count)),
        uvs: Vec::with_capacity(with(has.uv, vertex_count)),
        normals: Vec::with_capacity(with(has.normal, vertex_count)),
        corners: Vec::with_capacity(triangles as usize * 3),
        part_of: Vec::new(),
    };
    Ok((c, held))
}

/// Reads every item of element `e`: a vertex into the shared arrays, a face
/// fanned into corners; other elements are read past. `has`: what the
/// vertex element has.
fn read_element(
    name: &str,
    e: &Element,
    has: Has,
    body: &mut Body,
    c: &mut IndexedCorners,
) -> Result<(), ObjError> {
    let is_vertex = e.name == "vertex";
    let layout = vertex_layout(e);
    let list = face_list(e).filter(|_| e.name == "face");
    if is_vertex && layout.position.iter().any(Option::is_none) {
        return Err(body.fail(name, "the vertex element has no x, y and z".into()));
    }
    let mut polygon: Vec<usize> = Vec::new();
    let mut values: Vec<f64> = Vec::new();
    for item in 0..e.count {
        values.clear();
        polygon.clear();
        for (k, p) in e.properties.iter().enumerate() {
            match p.list {
                Some(count) => {
                    let n = body.length(count).map_err(|m| body.fail(name, m))?;
                    for _ in 0..n {
                        let v = body.value(p.ty).map_err(|m| body.fail(name, m))?;
                        if Some(k) == list {
                            let read = c.positions.len();
                            if !(v >= 0.0 && v < read as f64 && v.fract() == 0.0) {
                                return Err(body.fail(
                                    name,
                                    format!(
                                        "face {}: vertex index {v} is out of range (there are {read} vertices)",
                                        item + 1,
                                    ),
                                ));
                            }
                            polygon.push(v as usize);
                        }
                    }
                    values.push(0.0);
                }
                None => values.push(body.value(p.ty).map_err(|m| body.fail(name, m))?),
            }
        }
        if is_vertex {
            push_vertex(c, e, &layout, has, &values)
                .map_err(|m| body.fail(name, format!("vertex {}: {m}", item + 1)))?;
        } else if list.is_some() {
            push_face(c, &polygon, has.normal);
        }
    }
    Ok(())
}

/// One vertex's values into the shared arrays; an error for a position
/// that is not finite.
fn push_vertex(
    c: &mut IndexedCorners,
    e: &Element,
    layout: &VertexLayout,
    has: Has,
    values: &[f64],
) -> Result<(), String> {
    let get = |i: Option<usize>| i.map(|i| values[i] as f32);
    let three = |idx: [Option<usize>; 3]| Some(Vec3::new(get(idx[0])?, get(idx[1])?, get(idx[2])?));
    let position = three(layout.position).unwrap_or(Vec3::ZERO);
    if !position.is_finite() {
        return Err("a position is not a finite number".into());
    }
    c.positions.push(position);
    if has.normal {
        // An unusable normal is computed, as a missing one.
        let normal = three(layout.normal).filter(|n| n.is_finite());
        c.normals.push(normal.unwrap_or(Vec3::ZERO));
    }
    if has.color {
        let scale = if e.properties[layout.color[0].unwrap_or(0)].ty.is_float() {
            1.0
        } else {
            1.0 / 255.0
        };
        let color = three(layout.color).map(|c| c * scale);
        c.colors.push(color.filter(|c| c.is_finite()));
    }
    if has.uv {
        let uv = match layout.uv {
            [Some(u), Some(v)] => Vec2::new(values[u] as f32, values[v] as f32),
            _ => Vec2::NAN,
        };
        // An unusable UV is marked, and its corners take none.
        c.uvs.push(if uv.is_finite() { uv } else { Vec2::NAN });
    }
    Ok(())
}

/// One face, fanned into triangles, as corners indexing the shared arrays.
fn push_face(c: &mut IndexedCorners, polygon: &[usize], has_normal: bool) {
    let corner = |i: usize| {
        let uv = c.uvs.get(i).is_some_and(|t| t.is_finite());
        [
            i as u32,
            if uv { i as u32 } else { NO_INDEX },
            if has_normal { i as u32 } else { NO_INDEX },
        ]
    };
    for k in 1..polygon.len().saturating_sub(1) {
        for i in [polygon[0], polygon[k], polygon[k + 1]] {
            let corner = corner(i);
            c.corners.push(corner);
        }
    }
}

/// The model of what [`read`] read: a point cloud when there are no
/// faces, else the built triangles.
fn finish(
    name: &str,
    c: IndexedCorners,
    mut held: Reservation,
    warnings: Vec<String>,
) -> Result<LoadedModel, ObjError> {
    let parts = if c.corners.is_empty() {
        vec![ModelPart {
            mesh: point_cloud(name, &c)?,
            material: None,
            own_maps: None,
            opacity_map: None,
            pbr_maps: Default::default(),
        }]
    } else {
        build_indexed(name, c, &[], &[true], &mut held)?
            .into_iter()
            .map(|(_, mesh)| ModelPart {
                mesh,
                material: None,
                own_maps: None,
                opacity_map: None,
                pbr_maps: Default::default(),
            })
            .collect()
    };
    drop(held);
    Ok(LoadedModel {
        points: parts.iter().all(|p| {
            p.mesh
                .triangles
                .iter()
                .all(|t| t.indices[0] == t.indices[1])
        }),
        parts,
        maps: ModelMaps::default(),
        warnings,
        z_up: false,
    })
}

/// Points as triangles with three equal corners (drawn by the points
/// display; they cover no pixel when filled), fitted like any model.
fn point_cloud(name: &str, c: &IndexedCorners) -> Result<Mesh, ObjError> {
    let positions = &c.positions;
    let fit = match fit_of(|| positions.iter().copied()) {
        Some(fit) => fit,
        // Every point at one place: kept there, at scale 1.
        None if positions
            .iter()
            .all(|p| p.is_finite() && *p == positions[0]) =>
        {
            (positions[0].as_dvec3(), 1.0)
        }
        None => {
            return Err(ObjError::Degenerate {
                name: name.to_string(),
            });
        }
    };
    let mesh_vertices: Vec<Vertex> = positions
        .iter()
        .enumerate()
        .map(|(i, &p)| {
            let normal = c.normals.get(i).and_then(|n| n.try_normalize());
            Vertex {
                position: fitted(p, fit),
                normal: normal.unwrap_or(Vec3::Z),
                uv: c
                    .uvs
                    .get(i)
                    .copied()
                    .filter(|t| t.is_finite())
                    .unwrap_or(Vec2::ZERO),
                color: c
                    .colors
                    .get(i)
                    .copied()
                    .flatten()
                    .map(|c| c.clamp(Vec3::ZERO, Vec3::ONE))
                    .unwrap_or(Vec3::ONE),
                tangent_u: Vec3::ZERO,
                tangent_v: Vec3::ZERO,
            }
        })
        .collect();
    let faces: Vec<Face> = mesh_vertices
        .iter()
        .enumerate()
        .map(|(i, v)| Face {
            indices: [i as u32; 3],
            face_normal: v.normal,
            face_tangent_u: Vec3::ZERO,
            face_tangent_v: Vec3::ZERO,
            facet_center: v.position,
            facet_color: v.color,
            textured: false,
        })
        .collect();
    Ok(Mesh::new(mesh_vertices, &faces, false, false))
}
