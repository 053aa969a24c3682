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

use super::cube::{FACES, corner_color};
use super::mesh::{Mesh, Triangle, Vertex};
use super::model_file::{LoadedModel, ModelMaps, ModelPart, read_model_file};
use super::tangents::{accumulate, face_frame};
use crate::sanitize::{clean, display_path};
use mtl::MaterialDesc;

/// Most corners one face may have: a polygon is split into a fan, and a
/// fan of a million corners is a million thin triangles.
pub const MAX_FACE_CORNERS: usize = 65_536;
pub use read::MODEL_BYTES_PER_TRIANGLE;
/// Distance from the model's centre to its farthest point once loaded.
pub const FIT_RADIUS: f32 = 1.5;
/// Faces meeting at a larger angle keep separate normals when normals are computed.
pub const CREASE_DEGREES: f32 = 60.0;
/// Beyond this many faces around one position, computed normals ignore the crease angle.
const MAX_VALENCE: usize = 256;

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
    let model = parse_model(&name, &bytes, Some(dir));
    drop(held);
    model
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
    text: &[u8],
    dir: Option<&Path>,
    chunks: Option<usize>,
) -> Result<LoadedModel, ObjError> {
    let text = utf8_text(text);
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
    for (corners, &part) in model.corners.chunks_exact_mut(3).zip(&model.part_of) {
        if let Some(kd) = materials[part as usize].as_ref().and_then(|m| m.diffuse) {
            for c in corners {
                c.color.get_or_insert(kd);
            }
        }
    }
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
    let meshes = build_parts(name, model.corners, &model.part_of, &textured)?;
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

/// Centre and scale the corners so the farthest is `FIT_RADIUS` away.
fn fit(corners: &mut [Corner]) -> bool {
    let Some(fit) = fit_of(|| corners.iter().map(|c| c.position)) else {
        return false;
    };
    for c in corners.iter_mut() {
        c.position = fitted(c.position, fit);
    }
    true
}

/// What makes two corners one vertex: position id, UV and normal bits,
/// whether the face's texture axes are mirrored, and the part (whose
/// material may colour it).
type VertexKey = (u32, [u32; 2], [u32; 3], bool, u32);

/// Angle of a triangle at corner `k`.
fn corner_angle(p: [Vec3; 3], k: usize) -> f32 {
    let a = p[(k + 1) % 3] - p[k];
    let b = p[(k + 2) % 3] - p[k];
    a.angle_between(b)
}

/// A triangle being built: its corners, its normal, and the ids of its
/// corners' positions (equal ids for equal points).
struct Tri {
    corners: [Corner; 3],
    normal: Vec3,
    position_ids: [u32; 3],
    part: u32,
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
    let (mesh, tri_parts) = build(name, corners, part_of, textured)?;
    let count = textured.len().max(1);
    if count == 1 || tri_parts.iter().all(|&p| p == tri_parts[0]) {
        return Ok(vec![(tri_parts[0] as usize, mesh)]);
    }
    // Split: each part keeps the vertices its triangles use, renumbered.
    let mut out = Vec::new();
    let mut new_index = vec![u32::MAX; mesh.vertices.len()];
    for part in 0..count as u32 {
        let mut vertices = Vec::new();
        let mut used: Vec<u32> = Vec::new();
        let mut triangles = Vec::new();
        for (t, _) in mesh
            .triangles
            .iter()
            .zip(&tri_parts)
            .filter(|(_, p)| **p == part)
        {
            let mut t = *t;
            for i in t.indices.iter_mut() {
                let slot = &mut new_index[*i as usize];
                if *slot == u32::MAX {
                    *slot = vertices.len() as u32;
                    vertices.push(mesh.vertices[*i as usize]);
                    used.push(*i);
                }
                *i = *slot;
            }
            triangles.push(t);
        }
        for &i in &used {
            new_index[i as usize] = u32::MAX;
        }
        if triangles.is_empty() {
            continue;
        }
        out.push((
            part as usize,
            Mesh {
                vertices,
                triangles,
                convex: false,
                // A part of a closed model shows only its front faces too.
                closed: mesh.closed,
            },
        ));
    }
    Ok(out)
}

fn build(
    name: &str,
    mut corners: Vec<Corner>,
    part_of: &[u32],
    textured: &[bool],
) -> Result<(Mesh, Vec<u32>), ObjError> {
    if !fit(&mut corners) {
        return Err(ObjError::Degenerate {
            name: name.to_string(),
        });
    }
    // Keep the triangles that have an area (and so a normal).
    let mut ids: HashMap<[u32; 3], u32> = HashMap::new();
    let mut tris: Vec<Tri> = corners
        .chunks_exact(3)
        .enumerate()
        .filter_map(|(t, c)| {
            let c = [c[0], c[1], c[2]];
            let [a, b, d] = c.map(|c| c.position);
            let n = (b - a).cross(d - a).normalize_or_zero();
            let part = part_of.get(t).copied().unwrap_or(0);
            (n != Vec3::ZERO).then_some((c, n, part))
        })
        .map(|(c, normal, part)| {
            let position_ids = c.map(|corner| {
                let next = ids.len() as u32;
                *ids.entry(position_key(corner.position)).or_insert(next)
            });
            Tri {
                corners: c,
                normal,
                position_ids,
                part,
            }
        })
        .collect();
    // The triangles hold copies of the corners: free them before the mesh grows.
    drop(corners);
    if tris.is_empty() {
        return Err(ObjError::Degenerate {
            name: name.to_string(),
        });
    }
    fill_normals(&mut tris, ids.len());
    // Missing UVs: box projection with the cube's texture axes.
    for tri in tris.iter_mut() {
        if tri.corners.iter().any(|c| c.uv.is_none()) {
            let n = tri.normal;
            let (_, u_axis, v_axis) = FACES
                .iter()
                .copied()
                .max_by(|x, y| n.dot(x.0).total_cmp(&n.dot(y.0)))
                .unwrap_or(FACES[4]);
            for corner in tri.corners.iter_mut() {
                let p = corner.position / FIT_RADIUS;
                corner.uv = Some(Vec2::new(
                    0.5 + 0.5 * p.dot(u_axis),
                    0.5 + 0.5 * p.dot(v_axis),
                ));
            }
        }
    }
    let mut vertices: Vec<Vertex> = Vec::new();
    let mut triangles = Vec::with_capacity(tris.len());
    let mut index_of: HashMap<VertexKey, u32> = HashMap::new();
    for tri in &tris {
        let c = &tri.corners;
        let positions = c.map(|c| c.position);
        let uvs = c.map(|c| c.uv.unwrap_or(Vec2::ZERO));
        // Colours belong to positions (the file's, or computed from the position).
        let colors = c.map(|c| {
            c.color
                .map(|k| k.clamp(Vec3::ZERO, Vec3::ONE))
                .unwrap_or_else(|| corner_color(c.position / FIT_RADIUS).min(Vec3::ONE))
        });
        let frame = face_frame(positions, uvs, tri.normal);
        let mirrored = frame.handedness(tri.normal) < 0.0;
        let mut indices = [0u32; 3];
        for k in 0..3 {
            let normal = c[k].normal.unwrap_or(tri.normal);
            let key = (
                tri.position_ids[k],
                uvs[k].to_array().map(f32::to_bits),
                normal.to_array().map(f32::to_bits),
                mirrored,
                tri.part,
            );
            indices[k] = *index_of.entry(key).or_insert_with(|| {
                vertices.push(Vertex {
                    position: positions[k],
                    normal,
                    uv: uvs[k],
                    color: colors[k],
                    tangent_u: Vec3::ZERO,
                    tangent_v: Vec3::ZERO,
                });
                (vertices.len() - 1) as u32
            });
        }
        triangles.push(Triangle {
            indices,
            face_normal: tri.normal,
            face_tangent_u: frame.tangent_u,
            face_tangent_v: frame.tangent_v,
            facet_center: positions.iter().sum::<Vec3>() / 3.0,
            facet_color: colors.iter().sum::<Vec3>() / 3.0,
            textured: textured.get(tri.part as usize).copied().unwrap_or(true),
        });
    }
    let closed = is_closed(&tris);
    let mut mesh = Mesh {
        vertices,
        triangles,
        convex: false,
        closed,
    };
    accumulate(&mut mesh);
    Ok((mesh, tris.iter().map(|t| t.part).collect()))
}

/// File normals are normalised (an unusable one is recomputed); missing ones
/// are computed by angle weighting within the crease angle.
fn fill_normals(tris: &mut [Tri], positions: usize) {
    let cos_crease = CREASE_DEGREES.to_radians().cos();
    // The corners around each position, as one flat list (counting sort).
    let mut start = vec![0u32; positions + 1];
    for tri in tris.iter() {
        for &p in &tri.position_ids {
            start[p as usize + 1] += 1;
        }
    }
    for i in 0..positions {
        start[i + 1] += start[i];
    }
    let mut fill = start.clone();
    let mut around = vec![(0u32, 0u8); start[positions] as usize];
    for (t, tri) in tris.iter().enumerate() {
        for (k, &p) in tri.position_ids.iter().enumerate() {
            around[fill[p as usize] as usize] = (t as u32, k as u8);
            fill[p as usize] += 1;
        }
    }
    let weighted = |&(t, k): &(u32, u8)| {
        let tri = &tris[t as usize];
        corner_angle(tri.corners.map(|c| c.position), k as usize) * tri.normal
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
    // Each triangle's normals read only the triangles around it: in parallel.
    let computed: Vec<[Vec3; 3]> = tris
        .par_iter()
        .map(|tri| {
            let normal_at = |k: usize| {
                if let Some(given) = tri.corners[k].normal.and_then(|g| g.try_normalize()) {
                    return given;
                }
                let p = tri.position_ids[k];
                let sum = match big.get(&p) {
                    Some(sum) => *sum,
                    None => around[start[p as usize] as usize..start[p as usize + 1] as usize]
                        .iter()
                        .filter(|&&(t2, _)| tri.normal.dot(tris[t2 as usize].normal) >= cos_crease)
                        .map(weighted)
                        .sum(),
                };
                sum.normalize_or(tri.normal)
            };
            [normal_at(0), normal_at(1), normal_at(2)]
        })
        .collect();
    for (tri, normals) in tris.iter_mut().zip(computed) {
        for (corner, normal) in tri.corners.iter_mut().zip(normals) {
            corner.normal = Some(normal);
        }
    }
}

/// True when every edge (between positions) is used exactly twice, in
/// opposite directions: a closed, consistently wound surface whose back
/// faces can be culled.
fn is_closed(tris: &[Tri]) -> bool {
    let mut edges: Vec<u64> = tris
        .iter()
        .flat_map(|t| {
            let p = t.position_ids;
            (0..3).map(move |k| (p[k] as u64) << 32 | p[(k + 1) % 3] as u64)
        })
        .collect();
    edges.sort_unstable();
    let unique = edges.windows(2).all(|w| w[0] != w[1]);
    unique
        && edges
            .iter()
            .all(|&e| edges.binary_search(&e.rotate_right(32)).is_ok())
}
