//! The one builder every model format feeds: triangle corners as read
//! become mesh parts.
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

use std::sync::atomic::{AtomicU32, Ordering};

// Maps of vertex keys, only looked up (never iterated): a fast hash.
use foldhash::{HashMap, HashMapExt};
use glam::{DVec3, Vec2, Vec3};
use rayon::prelude::*;

use super::convex;
use super::cube::{FACES, corner_color};
use super::load_progress::{self, LoadStep};
use super::mesh::{Face, Facet, Mesh, Triangle, Vertex};
use super::model_error::ObjError;
use super::model_io::reserve;
use super::tangents::{accumulate, face_frame, sum_bytes};
use crate::budget::Reservation;

/// Most corners one face may have: a polygon is split into a fan, and a
/// fan of a million corners is a million thin triangles.
pub const MAX_FACE_CORNERS: usize = 65_536;
/// Distance from the model's centre to its farthest point once loaded.
pub const FIT_RADIUS: f32 = 1.5;
/// Faces meeting at a larger angle keep separate normals when normals are computed.
pub const CREASE_DEGREES: f32 = 60.0;
/// Beyond this many faces around one position, computed normals ignore the crease angle.
const MAX_VALENCE: usize = 256;
/// Beyond this many vertices at one point, a hash table finds them (not a walk).
const CROWDED: usize = 32;

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
type VertexKey = [u32; 6];

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
    let mut held = reserve(name, "the corners", need)?;
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

/// The steps of [`build`] the progress line counts: the face normals, the
/// vertex normals, the facet data, the vertices, the closed and convex
/// tests, the mesh; the tangent sums come after the last.
const BUILD_STEPS: u64 = 6;

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
    // The view's progress line counts the steps below; a cancel stops
    // the build between them.
    load_progress::check(name)?;
    load_progress::begin(LoadStep::Building, BUILD_STEPS);
    let step_done = || {
        if let Some(p) = load_progress::current() {
            p.advance(1);
        }
        load_progress::check(name)
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
    step_done()?;
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
    step_done()?;
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
    step_done()?;
    // Vertices: one per distinct key, in order of first use.
    let (vertices, vertex_of) =
        split_vertices(name, &c, &triangles, part_colors, (&position_id, ids), held)?;
    triangles
        .par_iter_mut()
        .zip(vertex_of.par_chunks_exact(3))
        .for_each(|(tri, v)| tri.indices = [v[0], v[1], v[2]]);
    drop(vertex_of);
    held.shrink(bytes_of::<u32>(c.corners.len() as u64));
    step_done()?;
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
    step_done()?;
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
        sum_bytes(mesh.vertices.len() as u64, mesh.triangles.len() as u64),
    )?;
    step_done()?;
    accumulate(&mut mesh);
    Ok((mesh, tri_parts))
}

/// The vertices of the model, one per distinct key (position id, UV bits,
/// normal bits, part and mirroring), in order of first use, each made from
/// its first corner; and each corner's vertex. `held` grows by what is
/// allocated, and keeps the corners' vertices (a `u32` each) when done.
///
/// Only corners at the same point can share a vertex, so the corners are
/// listed per point (a counting sort, in corner order) and each point's
/// corners are matched in parallel; numbering the first corner of each key
/// in corner order then gives the vertices the order one pass over the
/// triangles would.
fn split_vertices(
    name: &str,
    c: &IndexedCorners,
    triangles: &[Face],
    part_colors: &[Option<Vec3>],
    (position_id, ids): (&[u32], usize),
    held: &mut Reservation,
) -> Result<(Vec<Vertex>, Vec<u32>), ObjError> {
    let corners = c.corners.len();
    let lists =
        bytes_of::<u32>(2 * (ids as u64 + 1)).saturating_add(bytes_of::<u32>(corners as u64));
    hold(
        held,
        name,
        "the vertex lists",
        lists.saturating_add(bytes_of::<u32>(corners as u64)),
    )?;
    let id = |i: usize| position_id[c.corners[i][0] as usize] as usize;
    let mut start = vec![0u32; ids + 1];
    for i in 0..corners {
        start[id(i) + 1] += 1;
    }
    for i in 0..ids {
        start[i + 1] += start[i];
    }
    let mut fill = start.clone();
    let mut around = vec![0u32; corners];
    for i in 0..corners {
        let p = id(i);
        around[fill[p] as usize] = i as u32;
        fill[p] += 1;
    }
    drop(fill);
    // What makes corner `i` a vertex of its own, besides its point.
    let key = |i: usize| -> VertexKey {
        let t = i / 3;
        let tri = &triangles[t];
        let mirrored = tri
            .face_tangent_u
            .cross(tri.face_tangent_v)
            .dot(tri.face_normal)
            < 0.0;
        let tag = c.part_of[t] << 1 | mirrored as u32;
        let [u, w] = uvs_of(c, t, tri.face_normal)[i % 3]
            .to_array()
            .map(f32::to_bits);
        let [x, y, z] = c.normals[c.corners[i][2] as usize]
            .to_array()
            .map(f32::to_bits);
        [u, w, x, y, z, tag]
    };
    // Each corner's first corner of the same key (itself when it is the
    // first), point by point, the points cut into runs matched in parallel.
    let first: Vec<AtomicU32> = (0..corners).map(|_| AtomicU32::new(0)).collect();
    let runs = (4 * rayon::current_num_threads()).min(ids.max(1));
    (0..runs)
        .into_par_iter()
        .for_each_init(Vec::new, |keys, r| {
            let (from, to) = (r * ids / runs, (r + 1) * ids / runs);
            for p in from..to {
                let list = &around[start[p] as usize..start[p + 1] as usize];
                keys.clear();
                keys.extend(list.iter().map(|&i| (key(i as usize), i)));
                if keys.len() <= CROWDED {
                    for (e, &(k, i)) in keys.iter().enumerate() {
                        let at = keys[..e].iter().find(|(k2, _)| *k2 == k).map_or(i, |f| f.1);
                        first[i as usize].store(at, Ordering::Relaxed);
                    }
                } else {
                    // Too many to compare pairwise: sorted, the first of each run.
                    keys.sort_unstable();
                    let mut at = 0;
                    for e in 0..keys.len() {
                        if keys[e].0 != keys[at].0 {
                            at = e;
                        }
                        first[keys[e].1 as usize].store(keys[at].1, Ordering::Relaxed);
                    }
                }
            }
        });
    drop(around);
    drop(start);
    // Each corner's vertex: first corners numbered in corner order.
    let mut vertex_of: Vec<u32> = first.into_iter().map(AtomicU32::into_inner).collect();
    let mut count = 0u32;
    for i in 0..corners {
        let f = vertex_of[i] as usize;
        vertex_of[i] = if f == i {
            count += 1;
            count - 1
        } else {
            vertex_of[f]
        };
    }
    held.shrink(lists);
    hold(
        held,
        name,
        "the vertices",
        bytes_of::<Vertex>(count as u64).saturating_add(bytes_of::<u32>(count as u64)),
    )?;
    let mut firsts = Vec::with_capacity(count as usize);
    let mut next = 0;
    for (i, &v) in vertex_of.iter().enumerate() {
        if v == next {
            firsts.push(i as u32);
            next += 1;
        }
    }
    let vertices: Vec<Vertex> = firsts
        .par_iter()
        .map(|&i| {
            let (i, t, k) = (i as usize, i as usize / 3, i as usize % 3);
            let corner = c.corners[i];
            let normal = c.normals[corner[2] as usize];
            Vertex {
                position: c.positions[corner[0] as usize],
                normal,
                uv: uvs_of(c, t, triangles[t].face_normal)[k],
                color: color_of(c, part_colors, t, k),
                tangent_u: Vec3::ZERO,
                tangent_v: Vec3::ZERO,
            }
        })
        .collect();
    drop(firsts);
    held.shrink(bytes_of::<u32>(count as u64));
    Ok((vertices, vertex_of))
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
