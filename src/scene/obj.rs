//! Wavefront OBJ models (`--model file.obj`), and the builder every model
//! format shares.
//!
//! The file is read line by line by relief's own reader (`read`: what it
//! accepts is listed there), so a bad file gets a one-line error with its
//! line number, and counts, face sizes and the memory budget are checked
//! before anything of the model's size is allocated. Its material libraries
//! are read by `mtl`. Then (for every format):
//! - polygons are split into fans;
//! - the model is centred on its bounding box and scaled so its farthest
//!   point is `FIT_RADIUS` from the centre;
//! - missing normals are computed per corner, weighted by the corner's angle,
//!   from the faces around the same position that turn less than
//!   `CREASE_DEGREES` from the corner's own face: curved surfaces come out
//!   smooth and a cube's edges stay hard (the smoothed-cube pitfall of seed
//!   004 §III-B);
//! - missing UVs come from a box projection: each face is projected along
//!   the axis its normal is closest to, with the cube's texture axes for that
//!   side, so the texture keeps one scale everywhere and is never mirrored;
//! - vertices are split wherever position, UV, normal, colour or the
//!   handedness of the texture axes differ, so hard edges and UV seams stay
//!   hard;
//! - tangents are accumulated per vertex (see `tangents`).

pub mod mtl;
mod read;

use std::path::Path;
use std::sync::Arc;

// Maps of vertex keys, only looked up (never iterated): a fast hash.
use foldhash::{HashMap, HashMapExt};
use glam::{DVec3, Vec2, Vec3};
use rayon::prelude::*;
use thiserror::Error;

use super::convex;
use super::cube::{FACES, corner_color};
use super::mesh::{Face, Facet, Mesh, Triangle, Vertex};
use super::model_file::{LoadedModel, ModelMaps, ModelPart, read_model_file};
use super::tangents::{accumulate, face_frame};
use crate::budget::Reservation;
use crate::sanitize::{clean, display_path};
use mtl::MaterialDesc;

/// Most corners one face may have: a polygon is split into a fan, and a
/// fan of a million corners is a million thin triangles.
pub const MAX_FACE_CORNERS: usize = 65_536;
pub use read::READ_BYTES_PER_TRIANGLE;
/// Bytes per triangle a glTF model reserves for building its meshes (an
/// upper bound measured on its worst cases).
pub const MODEL_BYTES_PER_TRIANGLE: u64 = 920;
/// Distance from the model's centre to its farthest point once loaded.
pub const FIT_RADIUS: f32 = 1.5;
/// Faces meeting at a larger angle keep separate normals when normals are computed.
pub const CREASE_DEGREES: f32 = 60.0;
/// Beyond this many faces around one position, computed normals ignore the crease angle.
const MAX_VALENCE: usize = 256;
/// Beyond this many vertices at one point, a hash table finds them (not a walk).
const CROWDED: usize = 32;

/// Why a model (of any format) could not be loaded: one line, already safe to print.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum ObjError {
    #[error("cannot read model {name}: {reason}")]
    Read { name: String, reason: String },
    #[error("model {name} is not a regular file")]
    NotAFile { name: String },
    #[error("model {name} is not a text file (a NUL byte at offset {at})")]
    NotText { name: String, at: usize },
    #[error("model {name}, line {line}: {problem}")]
    Line {
        name: String,
        line: usize,
        problem: String,
    },
    /// A binary file's problem, at its byte offset.
    #[error("model {name}, byte {offset}: {problem}")]
    Byte {
        name: String,
        offset: u64,
        problem: String,
    },
    #[error("model {name} has no faces")]
    Empty { name: String },
    #[error("model {name} has no face with an area (all points coincide or lie on a line)")]
    Degenerate { name: String },
    #[error("model {name} could not be parsed: {reason}")]
    Parse { name: String, reason: String },
    #[error("model {name}: {what}")]
    Unsupported { name: String, what: String },
    /// `reason` names the model and the limit.
    #[error("{reason}")]
    Budget { name: String, reason: String },
}

/// Loads an OBJ file as one mesh fitted to the unit view (all its parts
/// together; warnings are dropped: see [`load_model`]).
pub fn load(path: &Path) -> Result<Mesh, ObjError> {
    load_model(path).map(|m| m.merged())
}

/// Loads an OBJ file with its material libraries: a part per material, the
/// maps the scene's one material shows, and the warnings.
pub fn load_model(path: &Path) -> Result<LoadedModel, ObjError> {
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
    Owned { bytes: Vec<u8>, _held: Reservation },
}

impl Text<'_> {
    fn bytes(&self) -> &[u8] {
        match self {
            Text::Borrowed(b) => b,
            Text::Owned { bytes, .. } => bytes,
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
    crate::contain::contain(|| parse_unguarded(name, text, dir, chunks)).unwrap_or_else(|cause| {
        Err(ObjError::Parse {
            name: name.to_string(),
            reason: format!("the reader failed on it ({cause})"),
        })
    })
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

fn parse_unguarded(
    name: &str,
    file: Text,
    dir: Option<&Path>,
    chunks: Option<usize>,
) -> Result<LoadedModel, ObjError> {
    // UTF-16 is decoded to at most 3 bytes of UTF-8 for each 2 bytes.
    let raw = file.bytes();
    let _decoded = match raw {
        [0xFF, 0xFE, ..] | [0xFE, 0xFF, ..] => Some(super::model_file::reserve(
            name,
            "the decoded text",
            (raw.len() as u64 / 2).saturating_mul(3),
        )?),
        _ => None,
    };
    let text = utf8_text(raw);
    // Text in any 8-bit encoding is read (names and comments are not
    // used); a NUL byte says it is not text at all.
    if let Some(at) = text.iter().position(|&b| b == 0) {
        return Err(ObjError::NotText {
            name: name.to_string(),
            at,
        });
    }
    let mut model = match chunks {
        Some(parts) => read::read_in_chunks(name, &text, parts)?,
        None => read::read(name, &text)?,
    };
    drop(text);
    drop(_decoded);
    drop(file);
    let mut warnings = std::mem::take(&mut model.warnings);
    let library = match dir {
        Some(dir) => load_libraries(name, dir, &model.libraries, &mut warnings),
        None => Vec::new(),
    };
    // Each part's material, when a library describes it.
    let mut unknown = Vec::new();
    let materials: Vec<Option<MaterialDesc>> = model
        .parts
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
    if !unknown.is_empty() && dir.is_some() {
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
    // The scene has one texture: the first material with a diffuse map
    // that loads gives it (see docs/models.md).
    let mut own = material_maps(&materials, &mut warnings);
    let shown = own.iter().position(Option::is_some);
    let maps = shown.and_then(|i| own[i].take()).unwrap_or_default();
    let textured: Vec<bool> = materials
        .iter()
        .enumerate()
        .map(|(i, m)| match m {
            // No material, or one whose map could not be shown: the scene's texture.
            None => true,
            Some(m) => {
                Some(i) == shown || own[i].is_some() || (shown.is_none() && m.diffuse_map.is_some())
            }
        })
        .collect();
    // Kd is the corner colour where the file gives none.
    let part_colors: Vec<Option<Vec3>> = materials
        .iter()
        .map(|m| m.as_ref().and_then(|m| m.diffuse))
        .collect();
    // `map_d`: each material's opacity, read once.
    let opacity: Vec<Option<Arc<crate::texture::Level>>> = materials
        .iter()
        .map(|m| {
            let path = m.as_ref()?.opacity_map.as_ref()?.file.as_ref()?;
            match crate::texture::specular_map::load_specular_map(path) {
                Ok(level) => Some(Arc::new(level)),
                Err(e) => {
                    warnings.push(clean(&e.to_string()));
                    None
                }
            }
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
        })
        .collect();
    Ok(LoadedModel {
        parts,
        maps,
        points: false,
        warnings,
    })
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
        let files: Vec<String> = match super::model_file::resolve_beside(dir, line) {
            Some(_) => vec![line.clone()],
            None => line.split_whitespace().map(str::to_string).collect(),
        };
        for file in files {
            let Some(path) = super::model_file::resolve_beside(dir, &file) else {
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
    use crate::texture::load;
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
                        .unwrap_or_else(|_| crate::texture::procedural::brick())
                }
            },
            None => texture,
        };
        let specular_map = m
            .specular_map
            .as_ref()
            .and_then(|t| t.file.as_ref())
            .and_then(
                |p| match crate::texture::specular_map::load_specular_map(p) {
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
                |p| match crate::texture::normal_map_file::load_normal_map(p) {
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
pub fn scale_heights(texture: crate::texture::Texture, multiplier: f32) -> crate::texture::Texture {
    if multiplier == 1.0 {
        return texture;
    }
    let mut level = texture.base().clone();
    for t in level.texels.iter_mut() {
        t[3] *= multiplier;
    }
    crate::texture::Texture::new(texture.name.clone(), level)
}

/// A short, printable quote of a token from the file.
fn quote(token: &str) -> String {
    let mut s: String = clean(token).chars().take(24).collect();
    if token.chars().count() > 24 {
        s.push('…');
    }
    format!("'{s}'")
}

/// One triangle corner as read from a model file (of any format).
#[derive(Clone, Copy)]
pub(crate) struct Corner {
    pub position: Vec3,
    pub uv: Option<Vec2>,
    pub normal: Option<Vec3>,
    pub color: Option<Vec3>,
}

/// Bytes a format that reads corner by corner holds per triangle before
/// building (its three [`Corner`]s); the builder reserves the rest itself.
pub const CORNER_BYTES_PER_TRIANGLE: u64 = 3 * std::mem::size_of::<Corner>() as u64;

/// The index of a corner's missing UV or normal.
pub(crate) const NO_INDEX: u32 = u32::MAX;

/// Bytes of `n` values of `T`.
pub(crate) fn bytes_of<T>(n: u64) -> u64 {
    n.saturating_mul(std::mem::size_of::<T>() as u64)
}

/// Triangle corners as indices into attribute arrays, what the builder
/// reads: an OBJ's `v`, `vt` and `vn` as written (shared ones stay shared,
/// 12 bytes a corner), other formats one entry per corner.
#[derive(Default)]
pub(crate) struct IndexedCorners {
    pub positions: Vec<Vec3>,
    /// Per position, when the file gives colours (else empty).
    pub colors: Vec<Option<Vec3>>,
    pub uvs: Vec<Vec2>,
    pub normals: Vec<Vec3>,
    /// Three per triangle: position, UV and normal indices ([`NO_INDEX`]: none).
    pub corners: Vec<[u32; 3]>,
    /// Each triangle's part (empty: all in part 0).
    pub part_of: Vec<u32>,
}

impl IndexedCorners {
    /// Each corner with entries of its own.
    fn from_corners(corners: Vec<Corner>, part_of: &[u32]) -> IndexedCorners {
        let n = corners.len();
        let any_color = corners.iter().any(|c| c.color.is_some());
        let mut out = IndexedCorners {
            positions: corners.iter().map(|c| c.position).collect(),
            colors: if any_color {
                corners.iter().map(|c| c.color).collect()
            } else {
                Vec::new()
            },
            uvs: Vec::with_capacity(n),
            normals: Vec::with_capacity(n),
            corners: Vec::with_capacity(n),
            part_of: part_of.to_vec(),
        };
        for c in &corners {
            let mut index = [out.corners.len() as u32, NO_INDEX, NO_INDEX];
            if let Some(uv) = c.uv {
                index[1] = out.uvs.len() as u32;
                out.uvs.push(uv);
            }
            if let Some(normal) = c.normal {
                index[2] = out.normals.len() as u32;
                out.normals.push(normal);
            }
            out.corners.push(index);
        }
        out
    }

    /// Bytes the arrays of `corners` corners with entries of their own hold.
    fn bytes_for(corners: u64, triangles: u64) -> u64 {
        bytes_of::<Vec3>(corners)
            .saturating_add(bytes_of::<Option<Vec3>>(corners))
            .saturating_add(bytes_of::<Vec2>(corners))
            .saturating_add(bytes_of::<Vec3>(corners))
            .saturating_add(bytes_of::<[u32; 3]>(corners))
            .saturating_add(bytes_of::<u32>(triangles))
    }
}

/// Bits of a position, with −0 and +0 alike: the key that says two corners
/// are the same point.
fn position_key(p: Vec3) -> [u32; 3] {
    (p + Vec3::ZERO).to_array().map(f32::to_bits)
}

/// The centre (of the bounding box) and the scale that put the farthest of
/// `points` at `FIT_RADIUS`, worked out in f64 (coordinates near f32::MAX
/// would overflow when subtracted); none when the points coincide or are
/// not finite. `points` is walked twice. Every model format is fitted by it.
pub(crate) fn fit_of<I: Iterator<Item = Vec3>>(points: impl Fn() -> I) -> Option<(DVec3, f64)> {
    let mut lo = DVec3::splat(f64::INFINITY);
    let mut hi = DVec3::splat(f64::NEG_INFINITY);
    for p in points() {
        let p = p.as_dvec3();
        lo = lo.min(p);
        hi = hi.max(p);
    }
    let center = (lo + hi) * 0.5;
    let radius = points()
        .map(|p| (p.as_dvec3() - center).length())
        .fold(0.0f64, f64::max);
    (radius > 0.0 && radius.is_finite()).then(|| (center, FIT_RADIUS as f64 / radius))
}

/// A point moved by the fit [`fit_of`] found.
pub(crate) fn fitted(p: Vec3, (center, scale): (DVec3, f64)) -> Vec3 {
    ((p.as_dvec3() - center) * scale).as_vec3()
}

/// What makes two corners one vertex: position id, UV bits, normal bits,
/// and the part (whose material may colour it) times two plus whether the
/// face's texture axes are mirrored.
type VertexKey = [u32; 7];

/// Angle of a triangle at corner `k`.
fn corner_angle(p: [Vec3; 3], k: usize) -> f32 {
    let a = p[(k + 1) % 3] - p[k];
    let b = p[(k + 2) % 3] - p[k];
    a.angle_between(b)
}

/// Bytes of a hash table of `capacity` entries of `E`: buckets (a power of
/// two at most 7/8 full) of one entry and one control byte, and a group of
/// control bytes more.
fn table_bytes<E>(capacity: u64) -> u64 {
    if capacity == 0 {
        return 0;
    }
    let buckets = match capacity {
        0..4 => 4,
        4..8 => 8,
        _ => (capacity.saturating_mul(8) / 7).next_power_of_two(),
    };
    bytes_of::<E>(buckets)
        .saturating_add(buckets)
        .saturating_add(32)
}

/// Reserves `bytes` more for `what` of model `name` in `held`.
fn hold(held: &mut Reservation, name: &str, what: &str, bytes: u64) -> Result<(), ObjError> {
    held.grow(&format!("{what} of model {name}"), bytes)
        .map_err(|e| ObjError::Budget {
            name: name.to_string(),
            reason: e.to_string(),
        })
}

/// Makes room for `more` items in `v`, reserving first what the move
/// allocates (old and new blocks together) and giving back the old block.
fn grow_vec<T>(
    v: &mut Vec<T>,
    more: usize,
    held: &mut Reservation,
    name: &str,
    what: &str,
) -> Result<(), ObjError> {
    let old = bytes_of::<T>(v.capacity() as u64);
    hold(
        held,
        name,
        what,
        old + bytes_of::<T>((v.capacity() + more) as u64),
    )?;
    v.reserve_exact(more);
    held.shrink(old);
    Ok(())
}

/// Builds the model from its triangle corners (three per triangle, in any
/// format's reading), `part_of` giving each triangle's part (empty: all in
/// part 0) and `textured` whether each part's triangles take the scene's
/// texture. Returns each non-empty part's mesh, with its part number.
pub(crate) fn build_parts(
    name: &str,
    corners: Vec<Corner>,
    part_of: &[u32],
    textured: &[bool],
) -> Result<Vec<(usize, Mesh)>, ObjError> {
    let need = IndexedCorners::bytes_for(corners.len() as u64, part_of.len() as u64);
    let mut held = super::model_file::reserve(name, "the corners", need)?;
    let indexed = IndexedCorners::from_corners(corners, part_of);
    build_indexed(name, indexed, &[], textured, &mut held)
}

/// [`build_parts`] from indexed corners; `part_colors` colours the corners
/// of each part that have no colour of their own (an MTL's `Kd`). `held`
/// covers `corners` and grows by what building allocates, step by step,
/// before it is allocated.
pub(crate) fn build_indexed(
    name: &str,
    corners: IndexedCorners,
    part_colors: &[Option<Vec3>],
    textured: &[bool],
    held: &mut Reservation,
) -> Result<Vec<(usize, Mesh)>, ObjError> {
    let (mesh, tri_parts) = build(name, corners, part_colors, textured, held)?;
    let count = textured.len().max(1);
    if count == 1 || tri_parts.iter().all(|&p| p == tri_parts[0]) {
        return Ok(vec![(tri_parts[0] as usize, mesh)]);
    }
    // Split: each part keeps the vertices its triangles use, renumbered
    // (each vertex belongs to one part: the part is in its key).
    hold(
        held,
        name,
        "the parts",
        bytes_of::<Vertex>(mesh.vertices.len() as u64)
            .saturating_add(bytes_of::<Triangle>(mesh.triangles.len() as u64))
            .saturating_add(mesh.side_bytes() as u64)
            .saturating_add(bytes_of::<u32>(mesh.vertices.len() as u64) * 2),
    )?;
    let mut out = Vec::new();
    let mut new_index = vec![u32::MAX; mesh.vertices.len()];
    for part in 0..count as u32 {
        // A part of a closed model shows only its front faces too.
        let mut piece = Mesh::new(Vec::new(), &[], false, mesh.closed);
        let mut used: Vec<u32> = Vec::new();
        for (t, _) in tri_parts.iter().enumerate().filter(|(_, p)| **p == part) {
            let indices = mesh.triangles[t].indices.map(|i| {
                let slot = &mut new_index[i as usize];
                if *slot == u32::MAX {
                    *slot = piece.vertices.len() as u32;
                    piece.vertices.push(mesh.vertices[i as usize]);
                    used.push(i);
                }
                *slot
            });
            piece.push_from(&mesh, t, indices);
        }
        for &i in &used {
            new_index[i as usize] = u32::MAX;
        }
        if piece.triangles.is_empty() {
            continue;
        }
        piece.vertices.shrink_to_fit();
        piece.triangles.shrink_to_fit();
        out.push((part as usize, piece));
    }
    Ok(out)
}

/// The UVs of triangle `t`: the file's, or (when a corner has none) a box
/// projection with the cube's texture axes.
fn uvs_of(c: &IndexedCorners, t: usize, normal: Vec3) -> [Vec2; 3] {
    let corners = &c.corners[3 * t..3 * t + 3];
    if corners.iter().all(|k| k[1] != NO_INDEX) {
        return [0, 1, 2].map(|k| c.uvs[corners[k][1] as usize]);
    }
    let (_, u_axis, v_axis) = FACES
        .iter()
        .copied()
        .max_by(|x, y| normal.dot(x.0).total_cmp(&normal.dot(y.0)))
        .unwrap_or(FACES[4]);
    [0, 1, 2].map(|k| {
        let p = c.positions[corners[k][0] as usize] / FIT_RADIUS;
        Vec2::new(0.5 + 0.5 * p.dot(u_axis), 0.5 + 0.5 * p.dot(v_axis))
    })
}

/// The colour of corner `k` of triangle `t`: the file's, else its part's,
/// else one computed from the position.
fn color_of(c: &IndexedCorners, part_colors: &[Option<Vec3>], t: usize, k: usize) -> Vec3 {
    let p = c.corners[3 * t + k][0] as usize;
    let part = c.part_of.get(t).copied().unwrap_or(0) as usize;
    c.colors
        .get(p)
        .copied()
        .flatten()
        .or_else(|| part_colors.get(part).copied().flatten())
        .map(|k| k.clamp(Vec3::ZERO, Vec3::ONE))
        .unwrap_or_else(|| corner_color(c.positions[p] / FIT_RADIUS).min(Vec3::ONE))
}

fn build(
    name: &str,
    mut c: IndexedCorners,
    part_colors: &[Option<Vec3>],
    textured: &[bool],
    held: &mut Reservation,
) -> Result<(Mesh, Vec<u32>), ObjError> {
    let degenerate = || ObjError::Degenerate {
        name: name.to_string(),
    };
    let fit = {
        let (positions, corners) = (&c.positions, &c.corners);
        fit_of(|| corners.iter().map(|k| positions[k[0] as usize])).ok_or_else(degenerate)?
    };
    c.positions
        .par_iter_mut()
        .for_each(|p| *p = fitted(*p, fit));
    // Keep the triangles that have an area (and so a normal).
    let all = c.corners.len() / 3;
    hold(
        held,
        name,
        "the face normals",
        bytes_of::<Vec3>(all as u64) + bytes_of::<u32>(all as u64),
    )?;
    let mut face_normals: Vec<Vec3> = c
        .corners
        .par_chunks_exact(3)
        .map(|k| {
            let [a, b, d] = [0, 1, 2].map(|i| c.positions[k[i][0] as usize]);
            (b - a).cross(d - a).normalize_or_zero()
        })
        .collect();
    if c.part_of.len() != all {
        c.part_of = vec![0; all];
    }
    let mut kept = 0;
    for t in 0..all {
        if face_normals[t] != Vec3::ZERO {
            c.corners.copy_within(3 * t..3 * t + 3, 3 * kept);
            face_normals[kept] = face_normals[t];
            c.part_of[kept] = c.part_of[t];
            kept += 1;
        }
    }
    if kept == 0 {
        return Err(degenerate());
    }
    c.corners.truncate(3 * kept);
    face_normals.truncate(kept);
    c.part_of.truncate(kept);
    // Equal points get one id.
    let table = table_bytes::<([u32; 3], u32)>(c.positions.len() as u64);
    hold(
        held,
        name,
        "the position ids",
        table + bytes_of::<u32>(c.positions.len() as u64),
    )?;
    let (position_id, ids) = {
        let mut ids: HashMap<[u32; 3], u32> = HashMap::with_capacity(c.positions.len());
        let position_id: Vec<u32> = c
            .positions
            .iter()
            .map(|&p| {
                let next = ids.len() as u32;
                *ids.entry(position_key(p)).or_insert(next)
            })
            .collect();
        (position_id, ids.len())
    };
    held.shrink(table);
    // File normals are normalised; a missing or unusable one is computed.
    c.normals
        .par_iter_mut()
        .for_each(|n| *n = n.try_normalize().unwrap_or(Vec3::ZERO));
    let missing = c
        .corners
        .par_iter()
        .any(|k| k[2] == NO_INDEX || c.normals[k[2] as usize] == Vec3::ZERO);
    if missing {
        fill_normals(name, &mut c, &face_normals, &position_id, ids, held)?;
    }
    // The triangles' facet data, in parallel.
    hold(held, name, "the faces", bytes_of::<Face>(kept as u64))?;
    let mut triangles: Vec<Face> = (0..kept)
        .into_par_iter()
        .map(|t| {
            let normal = face_normals[t];
            let positions = [0, 1, 2].map(|k| c.positions[c.corners[3 * t + k][0] as usize]);
            let uvs = uvs_of(&c, t, normal);
            let colors = [0, 1, 2].map(|k| color_of(&c, part_colors, t, k));
            let frame = face_frame(positions, uvs, normal);
            Face {
                indices: [0; 3],
                face_normal: normal,
                face_tangent_u: frame.tangent_u,
                face_tangent_v: frame.tangent_v,
                facet_center: positions.iter().sum::<Vec3>() / 3.0,
                facet_color: colors.iter().sum::<Vec3>() / 3.0,
                textured: textured.get(c.part_of[t] as usize).copied().unwrap_or(true),
            }
        })
        .collect();
    drop(face_normals);
    // Vertices: one per distinct key, in order of first use. Only corners
    // at the same point can share a vertex, so each point keeps the list of
    // its vertices (most have one or two); a point with many (a fan's
    // centre with a UV per face) moves to a hash table.
    let mut vertices: Vec<Vertex> = Vec::new();
    // Per vertex: the next vertex at the same point, and its part and mirroring.
    let (mut next, mut tags): (Vec<u32>, Vec<u32>) = (Vec::new(), Vec::new());
    let lists = bytes_of::<u32>(ids as u64) + bytes_of::<bool>(ids as u64);
    hold(held, name, "the vertex lists", lists)?;
    let mut head = vec![u32::MAX; ids];
    let mut crowded = vec![false; ids];
    let mut index_of: HashMap<VertexKey, u32> = HashMap::new();
    let mut table = 0;
    let key_of = |v: &Vertex, id: u32, tag: u32| -> VertexKey {
        let [u, w] = v.uv.to_array().map(f32::to_bits);
        let [x, y, z] = v.normal.to_array().map(f32::to_bits);
        [id, u, w, x, y, z, tag]
    };
    for (t, tri) in triangles.iter_mut().enumerate() {
        let mirrored = tri
            .face_tangent_u
            .cross(tri.face_tangent_v)
            .dot(tri.face_normal)
            < 0.0;
        let tag = c.part_of[t] << 1 | mirrored as u32;
        let uvs = uvs_of(&c, t, tri.face_normal);
        for (k, uv) in uvs.into_iter().enumerate() {
            let corner = c.corners[3 * t + k];
            let id = position_id[corner[0] as usize];
            let normal = c.normals[corner[2] as usize];
            let same = |v: &Vertex| {
                v.uv.to_array().map(f32::to_bits) == uv.to_array().map(f32::to_bits)
                    && v.normal.to_array().map(f32::to_bits) == normal.to_array().map(f32::to_bits)
            };
            let candidate = Vertex {
                position: c.positions[corner[0] as usize],
                normal,
                uv,
                color: Vec3::ZERO,
                tangent_u: Vec3::ZERO,
                tangent_v: Vec3::ZERO,
            };
            let found = if crowded[id as usize] {
                index_of.get(&key_of(&candidate, id, tag)).copied()
            } else {
                let (mut at, mut length) = (head[id as usize], 0);
                while at != u32::MAX && !(tags[at as usize] == tag && same(&vertices[at as usize]))
                {
                    at = next[at as usize];
                    length += 1;
                }
                if at == u32::MAX && length >= CROWDED {
                    // Too many to walk: this point's vertices go to the table.
                    let need = index_of.len() + length;
                    if need > index_of.capacity() {
                        let more = need.max(2 * index_of.capacity()).max(1024) - index_of.len();
                        let bigger =
                            table_bytes::<(VertexKey, u32)>((index_of.len() + more) as u64);
                        hold(held, name, "the vertex map", bigger)?;
                        index_of.reserve(more);
                        held.shrink(table);
                        table = bigger;
                    }
                    let mut v = head[id as usize];
                    while v != u32::MAX {
                        index_of.insert(key_of(&vertices[v as usize], id, tags[v as usize]), v);
                        v = next[v as usize];
                    }
                    crowded[id as usize] = true;
                }
                (at != u32::MAX).then_some(at)
            };
            tri.indices[k] = match found {
                Some(i) => i,
                None => {
                    if vertices.len() == vertices.capacity() {
                        let more = vertices.len().max(1024);
                        grow_vec(&mut vertices, more, held, name, "the vertices")?;
                        grow_vec(&mut next, more, held, name, "the vertices")?;
                        grow_vec(&mut tags, more, held, name, "the vertices")?;
                    }
                    let i = vertices.len() as u32;
                    if crowded[id as usize] {
                        if index_of.len() == index_of.capacity() {
                            let more = index_of.len().max(1024);
                            let bigger =
                                table_bytes::<(VertexKey, u32)>((index_of.len() + more) as u64);
                            hold(held, name, "the vertex map", bigger)?;
                            index_of.reserve(more);
                            held.shrink(table);
                            table = bigger;
                        }
                        index_of.insert(key_of(&candidate, id, tag), i);
                    }
                    vertices.push(Vertex {
                        color: color_of(&c, part_colors, t, k),
                        ..candidate
                    });
                    next.push(head[id as usize]);
                    tags.push(tag);
                    head[id as usize] = i;
                    i
                }
            };
        }
    }
    let side = bytes_of::<u32>(next.capacity() as u64 + tags.capacity() as u64);
    drop((index_of, head, crowded, next, tags));
    held.shrink(table + lists + side);
    let spare = bytes_of::<Vertex>((vertices.capacity() - vertices.len()) as u64);
    vertices.shrink_to_fit();
    held.shrink(spare);
    let closed = is_closed(name, &c.corners, &position_id, held)?;
    let convex = closed && {
        let bytes = convex::scratch_bytes(kept, ids);
        hold(held, name, "the convexity test", bytes)?;
        let convex = convex::is_convex(
            kept,
            ids,
            &|t| [0, 1, 2].map(|k| position_id[c.corners[3 * t + k][0] as usize]),
            &|t| [0, 1, 2].map(|k| c.positions[c.corners[3 * t + k][0] as usize]),
        );
        held.shrink(bytes);
        convex
    };
    let tri_parts = std::mem::take(&mut c.part_of);
    drop(c);
    drop(position_id);
    // Facet data that the corners give again is not kept.
    let side = Mesh::side_facets(&vertices, &triangles);
    let compact = bytes_of::<Triangle>(kept as u64) + bytes_of::<Facet>(side as u64);
    hold(held, name, "the triangles", compact)?;
    let mut mesh = Mesh::new(vertices, &triangles, convex, closed);
    drop(triangles);
    held.shrink(bytes_of::<Face>(kept as u64));
    hold(
        held,
        name,
        "the tangent sums",
        bytes_of::<[f32; 10]>(mesh.vertices.len() as u64),
    )?;
    accumulate(&mut mesh);
    Ok((mesh, tri_parts))
}

/// Computes every corner's normal into a new normal array (the file's,
/// normalised, where it has a usable one): by angle weighting, from the
/// faces around the same position within the crease angle.
fn fill_normals(
    name: &str,
    c: &mut IndexedCorners,
    face_normals: &[Vec3],
    position_id: &[u32],
    positions: usize,
    held: &mut Reservation,
) -> Result<(), ObjError> {
    let cos_crease = CREASE_DEGREES.to_radians().cos();
    let corners = c.corners.len() as u64;
    hold(
        held,
        name,
        "the normals",
        bytes_of::<u32>(2 * (positions as u64 + 1))
            .saturating_add(bytes_of::<(u32, u8)>(corners))
            .saturating_add(bytes_of::<Vec3>(corners)),
    )?;
    let id = |i: usize| position_id[c.corners[i][0] as usize];
    // The corners around each position, as one flat list (counting sort).
    let mut start = vec![0u32; positions + 1];
    for i in 0..c.corners.len() {
        start[id(i) as usize + 1] += 1;
    }
    for i in 0..positions {
        start[i + 1] += start[i];
    }
    let mut fill = start.clone();
    let mut around = vec![(0u32, 0u8); start[positions] as usize];
    for i in 0..c.corners.len() {
        let p = id(i) as usize;
        around[fill[p] as usize] = ((i / 3) as u32, (i % 3) as u8);
        fill[p] += 1;
    }
    drop(fill);
    let triangle = |t: usize| [0, 1, 2].map(|k| c.positions[c.corners[3 * t + k][0] as usize]);
    let weighted = |&(t, k): &(u32, u8)| {
        corner_angle(triangle(t as usize), k as usize) * face_normals[t as usize]
    };
    // Around a position shared by very many faces (a cone's apex), the
    // per-corner crease test would cost valence²: there all faces are
    // averaged once instead.
    let big: HashMap<u32, Vec3> = (0..positions)
        .filter(|&p| (start[p + 1] - start[p]) as usize > MAX_VALENCE)
        .map(|p| {
            let list = &around[start[p] as usize..start[p + 1] as usize];
            (p as u32, list.iter().map(weighted).sum::<Vec3>())
        })
        .collect();
    // Each corner's normal reads only the triangles around it: in parallel.
    let normals: Vec<Vec3> = (0..c.corners.len())
        .into_par_iter()
        .map(|i| {
            let normal = face_normals[i / 3];
            let given = c.corners[i][2];
            if given != NO_INDEX && c.normals[given as usize] != Vec3::ZERO {
                return c.normals[given as usize];
            }
            let p = id(i);
            let sum = match big.get(&p) {
                Some(sum) => *sum,
                None => around[start[p as usize] as usize..start[p as usize + 1] as usize]
                    .iter()
                    .filter(|&&(t2, _)| normal.dot(face_normals[t2 as usize]) >= cos_crease)
                    .map(weighted)
                    .sum(),
            };
            sum.normalize_or(normal)
        })
        .collect();
    drop(big);
    drop(around);
    drop(start);
    c.normals = normals;
    c.corners
        .par_iter_mut()
        .enumerate()
        .for_each(|(i, k)| k[2] = i as u32);
    Ok(())
}

/// True when every edge (between positions) is used exactly twice, in
/// opposite directions: a closed, consistently wound surface whose back
/// faces can be culled.
fn is_closed(
    name: &str,
    corners: &[[u32; 3]],
    position_id: &[u32],
    held: &mut Reservation,
) -> Result<bool, ObjError> {
    let bytes = bytes_of::<u64>(corners.len() as u64);
    hold(held, name, "the edges", bytes)?;
    let mut edges: Vec<u64> = corners
        .par_chunks_exact(3)
        .flat_map_iter(|t| {
            let p = [0, 1, 2].map(|k| position_id[t[k][0] as usize]);
            (0..3).map(move |k| (p[k] as u64) << 32 | p[(k + 1) % 3] as u64)
        })
        .collect();
    edges.par_sort_unstable();
    let unique = edges.par_windows(2).all(|w| w[0] != w[1]);
    let closed = unique
        && edges
            .par_iter()
            .all(|&e| edges.binary_search(&e.rotate_right(32)).is_ok());
    drop(edges);
    held.shrink(bytes);
    Ok(closed)
}
