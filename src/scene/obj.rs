//! Wavefront OBJ models (`--model file.obj`).
//!
//! The file is read line by line by relief's own reader (`read`: what it
//! accepts is listed there), so a bad file gets a one-line error with its
//! line number, and counts, face sizes and the memory budget are checked
//! before anything of the model's size is allocated. Then:
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

mod read;

use std::collections::HashMap;
use std::io::Read;
use std::path::Path;

use glam::{DVec3, Vec2, Vec3};
use thiserror::Error;

use super::cube::{FACES, corner_color};
use super::mesh::{Mesh, Triangle, Vertex};
use super::tangents::{accumulate, face_frame};
use crate::sanitize::{clean, display_path};

/// Files larger than this are refused before reading.
pub const MAX_FILE_BYTES: u64 = 64 << 20;
/// Most `v` lines a model may have.
pub const MAX_POSITIONS: usize = 1_000_000;
/// Most triangles a model may have after triangulation (the memory budget
/// may allow fewer: see `read::MODEL_BYTES_PER_TRIANGLE`).
pub const MAX_TRIANGLES: usize = 1_000_000;
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

/// Why a model could not be loaded: one line, already safe to print.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum ObjError {
    #[error("cannot read model {name}: {reason}")]
    Read { name: String, reason: String },
    #[error("model {name} is not a regular file")]
    NotAFile { name: String },
    #[error("model {name} is too large: {size} bytes (limit {limit})")]
    TooLarge { name: String, size: u64, limit: u64 },
    #[error("model {name} is not a text file (a NUL byte at offset {at})")]
    NotText { name: String, at: usize },
    #[error("model {name}, line {line}: {problem}")]
    Line {
        name: String,
        line: usize,
        problem: String,
    },
    #[error("model {name} has more than {limit} {what}")]
    TooMany {
        name: String,
        what: &'static str,
        limit: usize,
    },
    #[error("model {name} has no faces")]
    Empty { name: String },
    #[error("model {name} has no face with an area (all points coincide or lie on a line)")]
    Degenerate { name: String },
    #[error("model {name} could not be parsed: {reason}")]
    Parse { name: String, reason: String },
    /// `reason` names the model and the limit.
    #[error("{reason}")]
    Budget { name: String, reason: String },
}

/// Loads an OBJ file as a mesh fitted to the unit view.
pub fn load(path: &Path) -> Result<Mesh, ObjError> {
    let name = display_path(path);
    let read_error = |e: std::io::Error| ObjError::Read {
        name: name.clone(),
        reason: clean(&e.to_string()),
    };
    let meta = std::fs::metadata(path).map_err(read_error)?;
    if !meta.is_file() {
        return Err(ObjError::NotAFile { name });
    }
    if meta.len() > MAX_FILE_BYTES {
        return Err(ObjError::TooLarge {
            name,
            size: meta.len(),
            limit: MAX_FILE_BYTES,
        });
    }
    let mut bytes = Vec::new();
    std::fs::File::open(path)
        .and_then(|f| f.take(MAX_FILE_BYTES + 1).read_to_end(&mut bytes))
        .map_err(read_error)?;
    if bytes.len() as u64 > MAX_FILE_BYTES {
        // It grew between the size check and the read.
        return Err(ObjError::TooLarge {
            name,
            size: bytes.len() as u64,
            limit: MAX_FILE_BYTES,
        });
    }
    // Text in any 8-bit encoding is read (names and comments are not
    // used); a NUL byte says it is not text at all.
    if let Some(at) = bytes.iter().position(|&b| b == 0) {
        return Err(ObjError::NotText { name, at });
    }
    parse(&name, &bytes)
}

/// Builds a mesh from OBJ text (any 8-bit encoding); `name` (already
/// sanitised) is used in errors. A panic while reading or building becomes
/// an error like any other.
pub fn parse(name: &str, text: impl AsRef<[u8]>) -> Result<Mesh, ObjError> {
    let text = text.as_ref();
    crate::contain::contain(|| parse_unguarded(name, text)).unwrap_or_else(|cause| {
        Err(ObjError::Parse {
            name: name.to_string(),
            reason: format!("the reader failed on it ({cause})"),
        })
    })
}

fn parse_unguarded(name: &str, text: &[u8]) -> Result<Mesh, ObjError> {
    let model = read::read(name, text)?;
    // The reservation covers building too.
    let mesh = build(name, model.corners);
    drop(model.reservation);
    mesh
}

/// A short, printable quote of a token from the file.
fn quote(token: &str) -> String {
    let mut s: String = clean(token).chars().take(24).collect();
    if token.chars().count() > 24 {
        s.push('…');
    }
    format!("'{s}'")
}

/// One triangle corner as read from the file.
#[derive(Clone, Copy)]
struct Corner {
    position: Vec3,
    uv: Option<Vec2>,
    normal: Option<Vec3>,
    color: Option<Vec3>,
}

/// Bits of a position, with −0 and +0 alike: the key that says two corners
/// are the same point.
fn position_key(p: Vec3) -> [u32; 3] {
    (p + Vec3::ZERO).to_array().map(f32::to_bits)
}

/// Centre and scale so the farthest point is `FIT_RADIUS` away (in f64:
/// coordinates near f32::MAX would overflow when subtracted).
fn fit(corners: &mut [Corner]) -> bool {
    let mut lo = DVec3::splat(f64::INFINITY);
    let mut hi = DVec3::splat(f64::NEG_INFINITY);
    for c in corners.iter() {
        let p = c.position.as_dvec3();
        lo = lo.min(p);
        hi = hi.max(p);
    }
    let center = (lo + hi) * 0.5;
    let radius = corners
        .iter()
        .map(|c| (c.position.as_dvec3() - center).length())
        .fold(0.0f64, f64::max);
    if !(radius > 0.0 && radius.is_finite()) {
        return false;
    }
    let scale = FIT_RADIUS as f64 / radius;
    for c in corners.iter_mut() {
        c.position = ((c.position.as_dvec3() - center) * scale).as_vec3();
    }
    true
}

/// What makes two corners one vertex: position id, UV and normal bits, and
/// whether the face's texture axes are mirrored.
type VertexKey = (u32, [u32; 2], [u32; 3], bool);

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
}

fn build(name: &str, mut corners: Vec<Corner>) -> Result<Mesh, ObjError> {
    if !fit(&mut corners) {
        return Err(ObjError::Degenerate {
            name: name.to_string(),
        });
    }
    // Keep the triangles that have an area (and so a normal).
    let mut ids: HashMap<[u32; 3], u32> = HashMap::new();
    let mut tris: Vec<Tri> = corners
        .chunks_exact(3)
        .filter_map(|c| {
            let c = [c[0], c[1], c[2]];
            let [a, b, d] = c.map(|c| c.position);
            let n = (b - a).cross(d - a).normalize_or_zero();
            (n != Vec3::ZERO).then_some((c, n))
        })
        .map(|(c, normal)| {
            let position_ids = c.map(|corner| {
                let next = ids.len() as u32;
                *ids.entry(position_key(corner.position)).or_insert(next)
            });
            Tri {
                corners: c,
                normal,
                position_ids,
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
            textured: true,
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
    Ok(mesh)
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
    let computed: Vec<[Vec3; 3]> = tris
        .iter()
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
