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
use foldhash::HashMap;
use glam::{DVec3, Vec2, Vec3};
use rayon::prelude::*;

use super::convex;
use super::cube::{FACES, corner_color};
use super::face_frame::uv_mirrored;
use super::load_progress::{self, LoadStep};
use super::mesh::{Facet, Mesh, Triangle, Vertex};
use super::model_error::ObjError;
use super::point_lists::PointLists;
use super::tangents::{accumulate, sum_bytes};
use crate::face_frame::face_frame;
use relief_core::budget::Reservation;

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

/// Bits of a position, with −0 and +0 alike: the key that says two corners
/// are the same point.
fn position_key(p: Vec3) -> [u32; 3] {
    (p + Vec3::ZERO).to_array().map(f32::to_bits)
}

/// Each position's id, equal points (by [`position_key`]) sharing one, the
/// ids numbered in order of first appearance, and how many there are: what
/// one pass with a hash table gives, found by sorting the keys with their
/// indices in parallel instead (a key's run starts at its first index).
pub fn position_ids(positions: &[Vec3]) -> (Vec<u32>, usize) {
    // Key and index in one integer, the key above: sorting the integers
    // sorts by key, then index, with one comparison each.
    let mut keyed: Vec<u128> = positions
        .par_iter()
        .enumerate()
        .map(|(i, &p)| {
            let [x, y, z] = position_key(p).map(u128::from);
            x << 96 | y << 64 | z << 32 | i as u128
        })
        .collect();
    keyed.par_sort_unstable();
    let (key, index) = (|e: u128| e >> 32, |e: u128| e as u32);
    // Each run of a key starts at its first position.
    let mut id = vec![0u32; positions.len()];
    let mut run = 0;
    for j in 0..keyed.len() {
        if key(keyed[j]) != key(keyed[run]) {
            run = j;
        }
        id[index(keyed[j]) as usize] = index(keyed[run]);
    }
    drop(keyed);
    let count = number_firsts(&mut id);
    (id, count as usize)
}

/// Turns "the first index with my key" (each entry at most its own index)
/// into numbers 0, 1, 2… given to the first ones in order and shared by
/// the others; returns how many.
fn number_firsts(first: &mut [u32]) -> u32 {
    let mut count = 0u32;
    for i in 0..first.len() {
        let f = first[i] as usize;
        first[i] = if f == i {
            count += 1;
            count - 1
        } else {
            first[f]
        };
    }
    count
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

/// [`fit_of`] of the positions the corners use, walked in parallel: the
/// same bits, since the bounds keep the later of equal values (`min` and
/// `max` take their second argument on a tie, as one walk does, and the
/// pieces are joined in order) and the farthest distance is a maximum.
/// Also says whether any corner passes `test`, asked in the same walk.
fn fit_of_corners(
    positions: &[Vec3],
    corners: &[[u32; 3]],
    test: impl Fn(&[u32; 3]) -> bool + Sync,
) -> (Option<(DVec3, f64)>, bool) {
    type Bounds = (DVec3, DVec3);
    let at = |k: &[u32; 3]| positions[k[0] as usize].as_dvec3();
    let join = |(lo1, hi1): Bounds, (lo2, hi2): Bounds| (lo1.min(lo2), hi1.max(hi2));
    let none = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    let ((lo, hi), any) = corners
        .par_chunks(PIECE)
        .map(|piece| {
            let bounds = piece.iter().fold(none, |b, k| join(b, (at(k), at(k))));
            (bounds, piece.iter().any(&test))
        })
        .reduce(
            || (none, false),
            |(b1, t1), (b2, t2)| (join(b1, b2), t1 || t2),
        );
    let center = (lo + hi) * 0.5;
    let radius = corners
        .par_iter()
        .map(|k| (at(k) - center).length())
        .reduce(|| 0.0f64, f64::max);
    let fit = (radius > 0.0 && radius.is_finite()).then(|| (center, FIT_RADIUS as f64 / radius));
    (fit, any)
}

/// Items a parallel walk takes at a time where it tests or folds plainly.
const PIECE: usize = 1 << 14;

/// Whether any item passes `test`, in parallel: a slice cut into pieces
/// each walked plainly (rayon's own `any` checks for an early stop at
/// every item, which costs more than these tests).
fn any_of<T: Sync>(items: &[T], test: impl Fn(&T) -> bool + Sync) -> bool {
    items.par_chunks(PIECE).any(|piece| piece.iter().any(&test))
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

/// Reserves `bytes` more for `what` of model `name` in `held`.
pub(crate) fn hold(
    held: &mut Reservation,
    name: &str,
    what: &str,
    bytes: u64,
) -> Result<(), ObjError> {
    held.grow(&format!("{what} of model {name}"), bytes)
        .map_err(|e| ObjError::Budget {
            name: name.to_string(),
            reason: e.to_string(),
        })
}

/// Builds the model from indexed corners (three per triangle, in any
/// format's reading), `textured` saying whether each part's triangles take
/// the scene's texture; `part_colors` colours the corners
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
    let count = textured.len().max(1);
    let invented = invented_colours(&corners, part_colors, count);
    let (mut mesh, tri_parts) = build(name, corners, part_colors, textured, held)?;
    // No part numbers: all in part 0.
    let first = tri_parts.first().copied().unwrap_or(0);
    if count == 1 || tri_parts.iter().all(|&p| p == first) {
        mesh.colours_invented = invented.get(first as usize).copied().unwrap_or(false);
        return Ok(vec![(first as usize, mesh)]);
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
        piece.colours_invented = invented[part as usize];
        out.push((part as usize, piece));
    }
    Ok(out)
}

/// Per part (of `count`), whether the file colours none of its corners:
/// no part colour (an MTL's `Kd`) and no vertex colour at any corner.
fn invented_colours(c: &IndexedCorners, part_colors: &[Option<Vec3>], count: usize) -> Vec<bool> {
    let mut invented: Vec<bool> = (0..count)
        .map(|p| part_colors.get(p).copied().flatten().is_none())
        .collect();
    if c.colors.iter().any(Option::is_some) {
        for (i, corner) in c.corners.iter().enumerate() {
            let given = c
                .colors
                .get(corner[0] as usize)
                .copied()
                .flatten()
                .is_some();
            if given && let Some(slot) = invented.get_mut(part(c, i / 3) as usize) {
                *slot = false;
            }
        }
    }
    invented
}

/// The cube face a triangle of unit normal `normal` is projected on when
/// its UVs are made: the one whose normal is closest (the last of equals).
fn box_side(normal: Vec3) -> u8 {
    let along = FACES.map(|(n, _, _)| normal.dot(n));
    (0..FACES.len())
        .max_by(|&x, &y| along[x].total_cmp(&along[y]))
        .unwrap_or(4) as u8
}

/// A triangle's flags: its [`box_side`], whether its texture axes are
/// mirrored, and whether its UVs are made by projection.
const SIDE: u8 = 7;
const MIRRORED: u8 = 8;
const PROJECTED: u8 = 16;

/// The UV of corner `k` of triangle `t`: the file's, or (when a corner of
/// the triangle has none) a box projection on the cube face `side`, with
/// its texture axes.
fn uv_of(c: &IndexedCorners, t: usize, k: usize, side: u8) -> Vec2 {
    if has_file_uvs(c, t) {
        return c.uvs[c.corners[3 * t + k][1] as usize];
    }
    let (_, u_axis, v_axis) = FACES[side as usize];
    let p = c.positions[c.corners[3 * t + k][0] as usize] / FIT_RADIUS;
    Vec2::new(0.5 + 0.5 * p.dot(u_axis), 0.5 + 0.5 * p.dot(v_axis))
}

/// Whether every corner of triangle `t` has a UV in the file (else its
/// UVs are all made by projection).
fn has_file_uvs(c: &IndexedCorners, t: usize) -> bool {
    c.corners[3 * t..3 * t + 3].iter().all(|k| k[1] != NO_INDEX)
}

/// The UVs of triangle `t` ([`uv_of`]).
fn uvs_of(c: &IndexedCorners, t: usize, side: u8) -> [Vec2; 3] {
    [0, 1, 2].map(|k| uv_of(c, t, k, side))
}

/// The colour of corner `k` of triangle `t`: the file's, else its part's,
/// else one computed from the position.
fn color_of(c: &IndexedCorners, part_colors: &[Option<Vec3>], t: usize, k: usize) -> Vec3 {
    let p = c.corners[3 * t + k][0] as usize;
    let part = part(c, t) as usize;
    c.colors
        .get(p)
        .copied()
        .flatten()
        .or_else(|| part_colors.get(part).copied().flatten())
        .map(|k| k.clamp(Vec3::ZERO, Vec3::ONE))
        .unwrap_or_else(|| corner_color(c.positions[p] / FIT_RADIUS).min(Vec3::ONE))
}

/// The steps of [`build`] the progress line counts: the face normals and
/// triangle flags, the vertex normals, the vertex keys, the closed and
/// convex tests, the triangles and their side table, the vertices; the
/// tangent sums come after the last.
const BUILD_STEPS: u64 = 6;

/// Builds one mesh of all the parts, step by step (each named below), and
/// returns it with each triangle's part (empty: all in part 0).
fn build(
    name: &str,
    mut c: IndexedCorners,
    part_colors: &[Option<Vec3>],
    textured: &[bool],
    held: &mut Reservation,
) -> Result<(Mesh, Vec<u32>), ObjError> {
    // The view's progress line counts the steps below; a cancel stops
    // the build between them.
    load_progress::check(name)?;
    load_progress::begin(LoadStep::Building, BUILD_STEPS);
    let keep_normals = normalise_and_fit(name, &mut c, held)?;
    let all = c.corners.len() / 3;
    let (mut face_normals, mut flags) = face_normals_and_flags(name, &c, keep_normals, held)?;
    // A model of one part keeps no part numbers.
    if c.part_of.len() != all || c.part_of.iter().all(|&p| p == 0) {
        let_go(held, std::mem::take(&mut c.part_of));
    }
    let kept = keep_triangles_with_area(&mut c, &mut flags, &mut face_normals, keep_normals);
    step_done(name)?;
    if kept == 0 {
        return Err(degenerate(name));
    }
    c.corners.truncate(3 * kept);
    flags.truncate(kept);
    face_normals.truncate(kept);
    c.part_of.truncate(kept);
    let (position_id, ids) = held_position_ids(name, &c.positions, held)?;
    let missing = keep_normals && any_of(&c.corners, |k| lacks_normal(&c.normals, k));
    if missing {
        fill_normals(name, &mut c, &face_normals, &position_id, ids, held)?;
    }
    // The face normals go: what needs one again computes the same bits
    // from the corners.
    let_go(held, face_normals);
    step_done(name)?;
    // Each corner's vertex: one per distinct key, in order of first use.
    let (vertex_of, firsts) = split_vertices(name, &c, &flags, (&position_id, ids), held)?;
    step_done(name)?;
    let closed = is_closed(name, &c.corners, &position_id, held)?;
    let convex = closed && convex_within_budget(name, &c, kept, (&position_id, ids), held);
    let_go(held, position_id);
    step_done(name)?;
    let triangles = make_triangles(name, &c, kept, vertex_of, textured, held)?;
    let sources = vertex_sources(name, &c, part_colors, &flags, firsts, held)?;
    let side = side_facets(name, &c, part_colors, flags, &triangles, &sources, held)?;
    step_done(name)?;
    let (vertices, tri_parts) = make_vertices(name, &mut c, sources, held)?;
    let mut mesh = Mesh::with_side_facets(vertices, triangles, &side, convex, closed);
    let_go(held, side);
    hold(
        held,
        name,
        "the tangent sums",
        sum_bytes(mesh.vertices.len() as u64, mesh.triangles.len() as u64),
    )?;
    step_done(name)?;
    accumulate(&mut mesh);
    Ok((mesh, tri_parts))
}

/// The error of a model with nothing to draw: no extent, or no triangle
/// with an area.
fn degenerate(name: &str) -> ObjError {
    ObjError::Degenerate {
        name: name.to_string(),
    }
}

/// Counts one of the [`BUILD_STEPS`] on the progress line; a cancel stops
/// the build here.
fn step_done(name: &str) -> Result<(), ObjError> {
    if let Some(p) = load_progress::current() {
        p.advance(1);
    }
    load_progress::check(name)
}

/// Whether corner `k` has no usable normal in the file (`normals` once
/// normalised, an unusable one zero), so its normal is computed.
fn lacks_normal(normals: &[Vec3], k: &[u32; 3]) -> bool {
    k[2] == NO_INDEX || normals[k[2] as usize] == Vec3::ZERO
}

/// The first step of [`build`]: lets go of colours no point has,
/// normalises the file's normals and fits the positions
/// ([`fit_of_corners`]). Returns whether the face normals are to be kept,
/// that is whether any corner lacks a normal or a UV.
fn normalise_and_fit(
    name: &str,
    c: &mut IndexedCorners,
    held: &mut Reservation,
) -> Result<bool, ObjError> {
    // Colours no point has are not kept.
    if c.colors.iter().all(Option::is_none) {
        let_go(held, std::mem::take(&mut c.colors));
    }
    // File normals are normalised; a missing or unusable one is computed.
    c.normals
        .par_iter_mut()
        .for_each(|n| *n = n.try_normalize().unwrap_or(Vec3::ZERO));
    // The face normals are kept only for what needs them again: computed
    // normals, and UVs made by projection (a box side). Otherwise they only
    // say which triangles have an area, computed where asked. Whether any
    // corner needs them is asked in the walk that bounds the points.
    let (fit, keep_normals) = fit_of_corners(&c.positions, &c.corners, |k| {
        lacks_normal(&c.normals, k) || k[1] == NO_INDEX
    });
    let fit = fit.ok_or_else(|| degenerate(name))?;
    c.positions
        .par_iter_mut()
        .for_each(|p| *p = fitted(*p, fit));
    Ok(keep_normals)
}

/// A triangle's flags, [`DROPPED`] when it has no area.
const DROPPED: u8 = u8::MAX;

/// The flags of triangle `t` of unit normal `normal`: its box side (for
/// UVs made by projection), whether its texture axes are mirrored (its
/// corners' vertices are told apart by it) and whether its UVs are
/// projected; [`DROPPED`] when it has no area (a zero normal).
fn triangle_flags(c: &IndexedCorners, t: usize, normal: Vec3) -> u8 {
    if normal == Vec3::ZERO {
        return DROPPED;
    }
    // The side only matters to a triangle without the file's UVs.
    let (side, projected) = if has_file_uvs(c, t) {
        (0, 0)
    } else {
        (box_side(normal), PROJECTED)
    };
    let mirrored = uv_mirrored(uvs_of(c, t, side));
    side | projected | if mirrored { MIRRORED } else { 0 }
}

/// Each triangle's flags ([`triangle_flags`]), in the pass that finds
/// which have an area (and so a normal), with the face normals when
/// `keep_normals` (else none). `held` grows by both before they are made.
fn face_normals_and_flags(
    name: &str,
    c: &IndexedCorners,
    keep_normals: bool,
    held: &mut Reservation,
) -> Result<(Vec<Vec3>, Vec<u8>), ObjError> {
    let all = c.corners.len() / 3;
    hold(held, name, "the triangle flags", bytes_of::<u8>(all as u64))?;
    if keep_normals {
        hold(held, name, "the face normals", bytes_of::<Vec3>(all as u64))?;
        let (face_normals, flags): (Vec<Vec3>, Vec<u8>) = (0..all)
            .into_par_iter()
            .map(|t| {
                let normal = normal_of(c, t);
                (normal, triangle_flags(c, t, normal))
            })
            .unzip();
        Ok((face_normals, flags))
    } else {
        let flags = (0..all)
            .into_par_iter()
            .map(|t| triangle_flags(c, t, normal_of(c, t)))
            .collect();
        Ok((Vec::new(), flags))
    }
}

/// Moves the triangles with an area (not [`DROPPED`]) down over the
/// others, with their flags, face normals (when `keep_normals`) and parts,
/// and returns how many there are; up to the first without an area, each
/// stays where it is. The arrays keep their lengths (the caller truncates).
fn keep_triangles_with_area(
    c: &mut IndexedCorners,
    flags: &mut [u8],
    face_normals: &mut [Vec3],
    keep_normals: bool,
) -> usize {
    let all = c.corners.len() / 3;
    let first_dropped = memchr::memchr(DROPPED, flags).unwrap_or(all);
    let mut kept = first_dropped;
    for t in first_dropped..all {
        if flags[t] != DROPPED {
            c.corners.copy_within(3 * t..3 * t + 3, 3 * kept);
            flags[kept] = flags[t];
            if keep_normals {
                face_normals[kept] = face_normals[t];
            }
            if !c.part_of.is_empty() {
                c.part_of[kept] = c.part_of[t];
            }
            kept += 1;
        }
    }
    kept
}

/// [`position_ids`] (equal points get one id, in order of first
/// appearance), `held` growing first by the table it sorts (given back once
/// sorted) and the ids it keeps.
fn held_position_ids(
    name: &str,
    positions: &[Vec3],
    held: &mut Reservation,
) -> Result<(Vec<u32>, usize), ObjError> {
    let table = bytes_of::<u128>(positions.len() as u64);
    hold(
        held,
        name,
        "the position ids",
        table + bytes_of::<u32>(positions.len() as u64),
    )?;
    let ids = position_ids(positions);
    held.shrink(table);
    Ok(ids)
}

/// Whether the closed model of the `kept` triangles of `c` is convex. The
/// convexity test only saves the depth buffer: a model whose test would
/// not fit the budget is drawn with one (false).
fn convex_within_budget(
    name: &str,
    c: &IndexedCorners,
    kept: usize,
    (position_id, ids): (&[u32], usize),
    held: &mut Reservation,
) -> bool {
    let bytes = convex::scratch_bytes(kept, ids);
    held.grow(&format!("the convexity test of model {name}"), bytes)
        .is_ok()
        && {
            let convex = convex::is_convex(
                kept,
                ids,
                &|t| [0, 1, 2].map(|k| position_id[c.corners[3 * t + k][0] as usize]),
                &|t| positions_of(c, t),
            );
            held.shrink(bytes);
            convex
        }
}

/// The `kept` triangles, from each corner's vertex (`vertex_of`, let go
/// once read), each textured as its part says.
fn make_triangles(
    name: &str,
    c: &IndexedCorners,
    kept: usize,
    vertex_of: Vec<u32>,
    textured: &[bool],
    held: &mut Reservation,
) -> Result<Vec<Triangle>, ObjError> {
    hold(
        held,
        name,
        "the triangles",
        bytes_of::<Triangle>(kept as u64),
    )?;
    let triangles: Vec<Triangle> = vertex_of
        .par_chunks_exact(3)
        .enumerate()
        .map(|(t, v)| {
            let textured = textured.get(part(c, t) as usize).copied().unwrap_or(true);
            Triangle::new([v[0], v[1], v[2]], textured)
        })
        .collect();
    let_go(held, vertex_of);
    Ok(triangles)
}

/// What each vertex takes from its first corner (`firsts`, let go once
/// read), so the corners can go before the vertices are made.
fn vertex_sources(
    name: &str,
    c: &IndexedCorners,
    part_colors: &[Option<Vec3>],
    flags: &[u8],
    firsts: Vec<u32>,
    held: &mut Reservation,
) -> Result<Vec<Source>, ObjError> {
    let count = firsts.len() as u64;
    hold(
        held,
        name,
        "the vertices' sources",
        bytes_of::<Source>(count),
    )?;
    let sources: Vec<Source> = firsts
        .par_iter()
        .map(|&i| {
            let (i, t, k) = (i as usize, i as usize / 3, i as usize % 3);
            let corner = c.corners[i];
            Source {
                position: corner[0],
                normal: corner[2],
                uv: uv_of(c, t, k, flags[t] & SIDE),
                color: color_of(c, part_colors, t, k),
            }
        })
        .collect();
    let_go(held, firsts);
    Ok(sources)
}

/// What tells a triangle's facet as its corners give it from the facet
/// its vertices give when drawn (see [`side_facets`]).
struct FacetCheck<'a> {
    c: &'a IndexedCorners,
    part_colors: &'a [Option<Vec3>],
    flags: &'a [u8],
    triangles: &'a [Triangle],
    sources: &'a [Source],
}

impl FacetCheck<'_> {
    /// Triangle `t`'s facet as its corners give it ([`read_facet`]).
    fn read(&self, t: usize) -> Facet {
        read_facet(self.c, self.part_colors, t, self.flags[t] & SIDE)
    }

    /// Triangle `t`'s facet as its vertices give it when drawn.
    fn drawn(&self, t: usize) -> Facet {
        let v = self.triangles[t]
            .indices
            .map(|i| self.sources[i as usize].facet_vertex(&self.c.positions));
        Facet::of_triangle([&v[0], &v[1], &v[2]])
    }

    /// Whether triangle `t`'s vertices have its corners' inputs bit for
    /// bit. A facet is computed from its corners' positions, UVs and
    /// colours alone, by the same expressions here and when drawn: a
    /// triangle whose vertices give those bit for bit (nearly always) has
    /// its facet again. A vertex made from a corner of the same position
    /// gives all three (the UV's bits and the part, which colours it, are
    /// in its key).
    fn same_inputs(&self, t: usize) -> bool {
        let c = self.c;
        let side = self.flags[t] & SIDE;
        (0..3).all(|k| {
            let i = 3 * t + k;
            let s = &self.sources[self.triangles[t].indices[k] as usize];
            let bits = |v: Vec3| v.to_array().map(f32::to_bits);
            s.position == c.corners[i][0]
                || (bits(c.positions[s.position as usize])
                    == bits(c.positions[c.corners[i][0] as usize])
                    && s.uv.to_array().map(f32::to_bits)
                        == uv_of(c, t, k, side).to_array().map(f32::to_bits)
                    && bits(s.color) == bits(color_of(c, self.part_colors, t, k)))
        })
    }

    /// Whether triangle `t`'s facet is not given again, bit for bit, by
    /// its vertices, and so is kept beside the triangles.
    fn differs(&self, t: usize) -> bool {
        !self.same_inputs(t) && self.read(t).bits() != self.drawn(t).bits()
    }
}

/// The facets the vertices would not give again bit for bit (a point at
/// −0 and +0, a colour its vertex does not keep), kept beside the
/// triangles; there are usually none. The triangles' `flags` are let go
/// once read.
fn side_facets(
    name: &str,
    c: &IndexedCorners,
    part_colors: &[Option<Vec3>],
    flags: Vec<u8>,
    triangles: &[Triangle],
    sources: &[Source],
    held: &mut Reservation,
) -> Result<Vec<(u32, Facet)>, ObjError> {
    let check = FacetCheck {
        c,
        part_colors,
        flags: &flags,
        triangles,
        sources,
    };
    let kept = triangles.len();
    hold(held, name, "the side flags", bytes_of::<bool>(kept as u64))?;
    let differs: Vec<bool> = (0..kept)
        .into_par_iter()
        .map(|t| check.differs(t))
        .collect();
    let side_count = differs.iter().filter(|&&d| d).count() as u64;
    hold(
        held,
        name,
        "the side table",
        bytes_of::<(u32, Facet)>(side_count).saturating_add(bytes_of::<Facet>(side_count)),
    )?;
    let side: Vec<(u32, Facet)> = (0..kept)
        .filter(|&t| differs[t])
        .map(|t| (t as u32, check.read(t)))
        .collect();
    let_go(held, differs);
    let_go(held, flags);
    Ok(side)
}

/// The vertices, made from their `sources` (let go once read) after the
/// corners go, and the triangles' parts, taken from `c`: all its arrays
/// are let go.
fn make_vertices(
    name: &str,
    c: &mut IndexedCorners,
    sources: Vec<Source>,
    held: &mut Reservation,
) -> Result<(Vec<Vertex>, Vec<u32>), ObjError> {
    let tri_parts = std::mem::take(&mut c.part_of);
    let positions = std::mem::take(&mut c.positions);
    let normals = std::mem::take(&mut c.normals);
    let_go(held, std::mem::take(&mut c.corners));
    let_go(held, std::mem::take(&mut c.uvs));
    let_go(held, std::mem::take(&mut c.colors));
    let count = sources.len() as u64;
    hold(held, name, "the vertices", bytes_of::<Vertex>(count))?;
    let vertices: Vec<Vertex> = sources
        .par_iter()
        .map(|s| Vertex {
            position: positions[s.position as usize],
            normal: normals[s.normal as usize],
            uv: s.uv,
            color: s.color,
            tangent_u: Vec3::ZERO,
            tangent_v: Vec3::ZERO,
        })
        .collect();
    let_go(held, sources);
    let_go(held, positions);
    let_go(held, normals);
    Ok((vertices, tri_parts))
}

/// What a vertex takes from the first corner of its key.
struct Source {
    position: u32,
    normal: u32,
    uv: Vec2,
    color: Vec3,
}

impl Source {
    /// The vertex as far as its triangles' facets go (position, UV, colour).
    fn facet_vertex(&self, positions: &[Vec3]) -> Vertex {
        Vertex {
            position: positions[self.position as usize],
            normal: Vec3::ZERO,
            uv: self.uv,
            color: self.color,
            tangent_u: Vec3::ZERO,
            tangent_v: Vec3::ZERO,
        }
    }
}

/// Frees `v` and gives its bytes back to `held`.
fn let_go<T>(held: &mut Reservation, v: Vec<T>) {
    let bytes = bytes_of::<T>(v.capacity() as u64);
    drop(v);
    held.shrink(bytes);
}

/// Triangle `t`'s part.
fn part(c: &IndexedCorners, t: usize) -> u32 {
    c.part_of.get(t).copied().unwrap_or(0)
}

/// The positions of triangle `t`'s corners.
fn positions_of(c: &IndexedCorners, t: usize) -> [Vec3; 3] {
    [0, 1, 2].map(|k| c.positions[c.corners[3 * t + k][0] as usize])
}

/// The unit normal of triangle `t` (zero when it has no area): always
/// this expression, so computing it again gives the same bits.
fn normal_of(c: &IndexedCorners, t: usize) -> Vec3 {
    let [a, b, d] = positions_of(c, t);
    (b - a).cross(d - a).normalize_or_zero()
}

/// Triangle `t`'s facet as its corners give it: its normal, the texture
/// axes of its UVs, the mean of its corners and of their colours.
fn read_facet(c: &IndexedCorners, part_colors: &[Option<Vec3>], t: usize, side: u8) -> Facet {
    let normal = normal_of(c, t);
    let positions = positions_of(c, t);
    let colors = [0, 1, 2].map(|k| color_of(c, part_colors, t, k));
    let frame = face_frame(positions, uvs_of(c, t, side), normal);
    Facet {
        normal,
        tangent_u: frame.tangent_u,
        tangent_v: frame.tangent_v,
        center: positions.iter().sum::<Vec3>() / 3.0,
        color: colors.iter().sum::<Vec3>() / 3.0,
    }
}

/// What makes corner `i` a vertex of its own, besides its point.
fn vertex_key(c: &IndexedCorners, flags: &[u8], i: usize) -> VertexKey {
    let t = i / 3;
    let tag = part(c, t) << 1 | (flags[t] & MIRRORED != 0) as u32;
    let [u, w] = uv_of(c, t, i % 3, flags[t] & SIDE)
        .to_array()
        .map(f32::to_bits);
    let [x, y, z] = c.normals[c.corners[i][2] as usize]
        .to_array()
        .map(f32::to_bits);
    [u, w, x, y, z, tag]
}

/// Each corner's vertex, one per distinct key (position id, UV bits,
/// normal bits, part and mirroring) numbered in order of first use, and
/// each vertex's first corner. `held` grows by what is allocated, and
/// keeps both arrays (a `u32` a corner and a vertex) when done.
///
/// Only corners at the same point can share a vertex. Each point's first
/// corner is found (the least index, so any order of search gives it), and
/// a corner with the key of its point's first shares its vertex: on a
/// smooth surface that is every corner, matched in parallel with no list.
/// The others (at seams and creases) can only share with each other; they
/// are listed per point (a counting sort, in corner order) and matched
/// point by point. Numbering the first corner of each key in corner order
/// then gives the vertices the order one pass over the triangles would.
fn split_vertices(
    name: &str,
    c: &IndexedCorners,
    flags: &[u8],
    (position_id, ids): (&[u32], usize),
    held: &mut Reservation,
) -> Result<(Vec<u32>, Vec<u32>), ObjError> {
    let corners = c.corners.len();
    let heads = bytes_of::<u32>(ids as u64);
    hold(
        held,
        name,
        "the points' first corners",
        heads.saturating_add(bytes_of::<u32>(corners as u64)),
    )?;
    let keys = CornerKeys {
        c,
        flags,
        position_id,
    };
    let piece = corners.div_ceil(4 * rayon::current_num_threads()).max(1);
    let head = first_corners_of_points(&keys, ids, piece);
    let (mut first, odd) = match_point_firsts(&keys, &head, piece);
    drop(head);
    held.shrink(heads);
    if odd > 0 {
        // The odd corners, listed per point and matched among themselves.
        // Besides the lists: the odd corners and what each matches.
        let lists = PointLists::bytes(odd as u64, ids as u64)
            .saturating_add(bytes_of::<u32>(odd as u64).saturating_mul(2));
        hold(held, name, "the vertex lists", lists)?;
        match_odd_corners(&keys, &mut first, odd, ids);
        held.shrink(lists);
    }
    number_vertices(name, first, held)
}

/// What [`split_vertices`] reads of each corner: its point and its key.
struct CornerKeys<'a> {
    c: &'a IndexedCorners,
    flags: &'a [u8],
    position_id: &'a [u32],
}

impl CornerKeys<'_> {
    /// Corner `i`'s point (its position's id).
    fn point(&self, i: usize) -> usize {
        self.position_id[self.c.corners[i][0] as usize] as usize
    }

    /// Corner `i`'s key besides its point ([`vertex_key`]).
    fn key(&self, i: usize) -> VertexKey {
        vertex_key(self.c, self.flags, i)
    }

    /// Whether corners `i` and `h` have the same key for want of
    /// difference: corners of the same point with the same indices, flags
    /// and part have the same key (their UVs are read or projected alike).
    fn alike(&self, i: usize, h: usize) -> bool {
        let (c, flags) = (self.c, self.flags);
        let (t, u) = (i / 3, h / 3);
        c.corners[i] == c.corners[h] && flags[t] == flags[u] && part(c, t) == part(c, u)
    }
}

/// The corner a point's head from [`first_corners_of_points`] holds,
/// stored as `u32::MAX - corner` (a zeroed head reads as `u32::MAX`, no
/// corner yet), so the least corner is the greatest value.
fn least(h: &AtomicU32) -> u32 {
    u32::MAX - h.load(Ordering::Relaxed)
}

/// Each of the `ids` points' first corner (see [`least`]): the least of
/// its corners, however the threads meet them (zeroed pages, read as
/// `u32::MAX - 0`). The corners are walked `piece` at a time.
fn first_corners_of_points(keys: &CornerKeys, ids: usize, piece: usize) -> Vec<AtomicU32> {
    let head: Vec<AtomicU32> = bytemuck::zeroed_vec(ids);
    (0..keys.c.corners.len())
        .into_par_iter()
        .with_min_len(piece)
        .for_each(|i| {
            let h = &head[keys.point(i)];
            if least(h) > i as u32 {
                h.fetch_max(u32::MAX - i as u32, Ordering::Relaxed);
            }
        });
    head
}

/// A corner whose key is not its point's first corner's.
const ODD: u32 = u32::MAX;

/// Each corner's first corner of the same key (itself when it is the
/// first) where that is its point's first corner (`head`), else [`ODD`];
/// and how many are odd. Written `piece` corners at a time.
fn match_point_firsts(keys: &CornerKeys, head: &[AtomicU32], piece: usize) -> (Vec<u32>, usize) {
    let mut first: Vec<u32> = bytemuck::zeroed_vec(keys.c.corners.len());
    let odd = first
        .par_chunks_mut(piece)
        .enumerate()
        .map(|(k, out)| {
            let mut odd = 0usize;
            for (j, f) in out.iter_mut().enumerate() {
                let i = k * piece + j;
                let h = least(&head[keys.point(i)]);
                *f = if h as usize == i
                    || keys.alike(i, h as usize)
                    || keys.key(i) == keys.key(h as usize)
                {
                    h
                } else {
                    odd += 1;
                    ODD
                };
            }
            odd
        })
        .sum::<usize>();
    (first, odd)
}

/// Gives each of the `odd` corners marked [`ODD`] in `first` the first
/// corner of its key among the odd corners of its point: they are listed
/// per point (of `ids`) and the points, cut into runs, matched in parallel.
fn match_odd_corners(keys: &CornerKeys, first: &mut [u32], odd: usize, ids: usize) {
    let odds: Vec<u32> = (0..first.len() as u32)
        .into_par_iter()
        .filter(|&i| first[i as usize] == ODD)
        .collect();
    let around = PointLists::new(odd, ids, |j| keys.point(odds[j] as usize));
    let found: Vec<AtomicU32> = bytemuck::zeroed_vec(odd);
    let runs = (4 * rayon::current_num_threads()).min(ids.max(1));
    (0..runs)
        .into_par_iter()
        .for_each_init(Vec::new, |point_keys, r| {
            let (from, to) = (r * ids / runs, (r + 1) * ids / runs);
            for p in from..to {
                point_keys.clear();
                point_keys.extend(around.at(p).iter().map(|&j| {
                    let i = odds[j as usize];
                    (keys.key(i as usize), j, i)
                }));
                match_keys_at_point(point_keys, &found);
            }
        });
    drop(around);
    for (&i, f) in odds.iter().zip(found) {
        first[i as usize] = f.into_inner();
    }
}

/// Stores in `found`, for each odd corner of one point (its key, its
/// number among the odd corners, its index), the first of them with its
/// key: compared pairwise when they are few, else sorted, the first of
/// each run.
fn match_keys_at_point(keys: &mut [(VertexKey, u32, u32)], found: &[AtomicU32]) {
    if keys.len() <= CROWDED {
        for (e, &(k, j, i)) in keys.iter().enumerate() {
            let at = keys[..e].iter().find(|f| f.0 == k).map_or(i, |f| f.2);
            found[j as usize].store(at, Ordering::Relaxed);
        }
    } else {
        // Too many to compare pairwise: sorted, the first of each run.
        keys.sort_unstable();
        let mut at = 0;
        for e in 0..keys.len() {
            if keys[e].0 != keys[at].0 {
                at = e;
            }
            found[keys[e].1 as usize].store(keys[at].2, Ordering::Relaxed);
        }
    }
}

/// Each corner's vertex, from each corner's `first` corner of the same
/// key: first corners numbered in corner order; and each vertex's first
/// corner, for which `held` grows.
fn number_vertices(
    name: &str,
    first: Vec<u32>,
    held: &mut Reservation,
) -> Result<(Vec<u32>, Vec<u32>), ObjError> {
    let mut vertex_of = first;
    let count = number_firsts(&mut vertex_of);
    hold(
        held,
        name,
        "the vertices' first corners",
        bytes_of::<u32>(count as u64),
    )?;
    let mut firsts = Vec::with_capacity(count as usize);
    let mut next = 0;
    for (i, &v) in vertex_of.iter().enumerate() {
        if v == next {
            firsts.push(i as u32);
            next += 1;
        }
    }
    Ok((vertex_of, firsts))
}

/// Computes every corner's normal into a new normal array (the file's,
/// normalised, where it has a usable one): by angle weighting, from the
/// faces around the same position within the crease angle. Corners of one
/// point whose normals are equal, bit for bit, share one entry, so a
/// smooth surface keeps about one normal per point, not one per corner.
fn fill_normals(
    name: &str,
    c: &mut IndexedCorners,
    face_normals: &[Vec3],
    position_id: &[u32],
    positions: usize,
    held: &mut Reservation,
) -> Result<(), ObjError> {
    let corners = c.corners.len() as u64;
    // Besides the lists: each corner's angle, and each corner's number.
    let lists = PointLists::bytes(corners, positions as u64)
        .saturating_add(bytes_of::<f32>(corners))
        .saturating_add(bytes_of::<u32>(corners));
    hold(held, name, "the normal lists", lists)?;
    let around_points = CornerNormals::new(c, face_normals, position_id, positions);
    let (number, made) = number_normals(&around_points);
    let total: u64 = made.iter().map(|&n| n as u64).sum();
    hold(held, name, "the normals", bytes_of::<Vec3>(total))?;
    let normals = make_normals(&around_points, &number, &made, total as usize);
    let CornerNormals {
        big,
        around,
        angles,
        ..
    } = around_points;
    drop(big);
    drop(around);
    drop(angles);
    let_go(held, std::mem::replace(&mut c.normals, normals));
    c.corners
        .par_iter_mut()
        .zip(number.par_iter())
        .for_each(|(k, n)| k[2] = n.load(Ordering::Relaxed));
    drop(number);
    held.shrink(lists);
    Ok(())
}

/// What each corner's computed normal is worked out from, and how the
/// points are cut into runs for [`number_normals`] and [`make_normals`].
struct CornerNormals<'a> {
    c: &'a IndexedCorners,
    face_normals: &'a [Vec3],
    position_id: &'a [u32],
    cos_crease: f32,
    /// The corners around each point.
    around: PointLists,
    /// Each corner's angle ([`corner_angle`]).
    angles: Vec<f32>,
    /// The weighted sum of all faces around each point of more than
    /// `MAX_VALENCE` faces.
    big: HashMap<u32, Vec3>,
    /// How many points there are, and how many runs they are cut into.
    points: usize,
    runs: usize,
}

impl<'a> CornerNormals<'a> {
    /// Lists the corners around each of the `points` points and works out
    /// each corner's angle and the sums around crowded points.
    fn new(
        c: &'a IndexedCorners,
        face_normals: &'a [Vec3],
        position_id: &'a [u32],
        points: usize,
    ) -> Self {
        let cos_crease = CREASE_DEGREES.to_radians().cos();
        let id = |i: usize| position_id[c.corners[i][0] as usize];
        let around = PointLists::new(c.corners.len(), points, |i| id(i) as usize);
        // A corner's angle is asked by every corner around its point: it is
        // worked out once.
        let triangle = |t: usize| [0, 1, 2].map(|k| c.positions[c.corners[3 * t + k][0] as usize]);
        let angles: Vec<f32> = (0..c.corners.len())
            .into_par_iter()
            .map(|i| corner_angle(triangle(i / 3), i % 3))
            .collect();
        // Around a position shared by very many faces (a cone's apex), the
        // per-corner crease test would cost valence²: there all faces are
        // averaged once instead.
        let weighted = |&i: &u32| weighted_normal(&angles, face_normals, i);
        let big: HashMap<u32, Vec3> = (0..points)
            .filter(|&p| around.at(p).len() > MAX_VALENCE)
            .map(|p| (p as u32, around.at(p).iter().map(weighted).sum::<Vec3>()))
            .collect();
        let runs = (4 * rayon::current_num_threads()).min(points.max(1));
        CornerNormals {
            c,
            face_normals,
            position_id,
            cos_crease,
            around,
            angles,
            big,
            points,
            runs,
        }
    }

    /// The points of run `r`.
    fn points_of(&self, r: usize) -> std::ops::Range<usize> {
        r * self.points / self.runs..(r + 1) * self.points / self.runs
    }

    /// Corner `i`'s normal: the file's when usable, else the angle-weighted
    /// sum of the faces around its point within the crease angle (all of
    /// them at a crowded point), normalised. It reads only the triangles
    /// around the corner.
    fn normal_at(&self, i: usize) -> Vec3 {
        let (c, face_normals) = (self.c, self.face_normals);
        let normal = face_normals[i / 3];
        let given = c.corners[i][2];
        if given != NO_INDEX && c.normals[given as usize] != Vec3::ZERO {
            return c.normals[given as usize];
        }
        let p = self.position_id[c.corners[i][0] as usize];
        let weighted = |&j: &u32| weighted_normal(&self.angles, face_normals, j);
        let sum = match self.big.get(&p) {
            Some(sum) => *sum,
            None => self
                .around
                .at(p as usize)
                .iter()
                .filter(|&&i2| normal.dot(face_normals[i2 as usize / 3]) >= self.cos_crease)
                .map(weighted)
                .sum(),
        };
        sum.normalize_or(normal)
    }
}

/// Corner `i`'s face normal weighted by the corner's angle.
fn weighted_normal(angles: &[f32], face_normals: &[Vec3], i: u32) -> Vec3 {
    angles[i as usize] * face_normals[i as usize / 3]
}

/// Marks, in a corner's number from [`number_normals`], the first corner
/// of its normal.
const FIRST_USE: u32 = 1 << 31;

/// The points, cut into runs, in parallel: each corner learns its normal's
/// number within its run (a normal met before at the same point, among its
/// first `CROWDED`, is shared), flagged [`FIRST_USE`] when it is the first.
/// Returns each corner's number and how many normals each run makes.
fn number_normals(at: &CornerNormals) -> (Vec<AtomicU32>, Vec<u32>) {
    let number: Vec<AtomicU32> = bytemuck::zeroed_vec(at.c.corners.len());
    let made: Vec<u32> = (0..at.runs)
        .into_par_iter()
        .map_init(Vec::new, |seen: &mut Vec<[u32; 3]>, r| {
            let mut count = 0u32;
            for p in at.points_of(r) {
                seen.clear();
                for &i in at.around.at(p) {
                    let bits = at.normal_at(i as usize).to_array().map(f32::to_bits);
                    let found = seen.iter().position(|&b| b == bits);
                    let n = match found {
                        Some(j) => count - seen.len() as u32 + j as u32,
                        None => {
                            if seen.len() < CROWDED {
                                seen.push(bits);
                            } else {
                                // Beyond the first few, each keeps its own.
                                seen.clear();
                            }
                            count += 1;
                            (count - 1) | FIRST_USE
                        }
                    };
                    number[i as usize].store(n, Ordering::Relaxed);
                }
            }
            count
        })
        .collect();
    (number, made)
}

/// The `total` normals, made once each into their run's slice, the runs in
/// parallel; each corner's `number` becomes its normal's index.
fn make_normals(at: &CornerNormals, number: &[AtomicU32], made: &[u32], total: usize) -> Vec<Vec3> {
    let mut normals = vec![Vec3::ZERO; total];
    {
        let mut rest = &mut normals[..];
        let mut slices = Vec::with_capacity(at.runs);
        for &n in made {
            let (head, tail) = std::mem::take(&mut rest).split_at_mut(n as usize);
            slices.push(head);
            rest = tail;
        }
        let offsets: Vec<u32> = made
            .iter()
            .scan(0u32, |sum, &n| {
                *sum += n;
                Some(*sum - n)
            })
            .collect();
        slices.into_par_iter().enumerate().for_each(|(r, out)| {
            for p in at.points_of(r) {
                for &i in at.around.at(p) {
                    let n = number[i as usize].load(Ordering::Relaxed);
                    if n & FIRST_USE != 0 {
                        out[(n & !FIRST_USE) as usize] = at.normal_at(i as usize);
                    }
                    number[i as usize].store(offsets[r] + (n & !FIRST_USE), Ordering::Relaxed);
                }
            }
        });
    }
    normals
}

/// `x`'s bits mixed (the SplitMix64 finaliser): nearby edges get unrelated
/// hashes.
fn mix(x: u64) -> u64 {
    let x = (x ^ (x >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    let x = (x ^ (x >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    x ^ (x >> 31)
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
    if !edge_hashes_balance(corners, position_id) {
        return Ok(false);
    }
    let bytes = bytes_of::<u64>(corners.len() as u64);
    hold(held, name, "the edges", bytes)?;
    let edges = sorted_edges(corners, position_id);
    if has_repeated_edge(&edges) {
        held.shrink(bytes);
        return Ok(false);
    }
    let points = edges.last().map_or(0, |&e| (e >> 32) as usize + 1);
    let index = bytes_of::<u32>(points as u64);
    hold(held, name, "the edges' index", index)?;
    let closed = every_edge_reversed(&edges, points);
    drop(edges);
    held.shrink(bytes.saturating_add(index));
    Ok(closed)
}

/// Whether a sum of a hash of each edge equals the same sum over the
/// reversed edges. A closed surface's edges, reversed, are its edges
/// again, so any sum over its edges equals the same sum over the reversed
/// ones: sums that differ say "open" without sorting anything.
fn edge_hashes_balance(corners: &[[u32; 3]], position_id: &[u32]) -> bool {
    let edge = |t: &[[u32; 3]], k: usize| {
        let p = |k: usize| position_id[t[k % 3][0] as usize] as u64;
        (p(k) << 32 | p(k + 1), p(k + 1) << 32 | p(k))
    };
    let (forth, back) = corners
        .par_chunks_exact(3)
        .map(|t| {
            (0..3).fold((0u64, 0u64), |(f, b), k| {
                let (e, r) = edge(t, k);
                (f.wrapping_add(mix(e)), b.wrapping_add(mix(r)))
            })
        })
        .reduce(
            || (0, 0),
            |(f1, b1), (f2, b2)| (f1.wrapping_add(f2), b1.wrapping_add(b2)),
        );
    forth == back
}

/// Every triangle's edges, each as its start and end position ids in one
/// integer (start in the high half), sorted.
fn sorted_edges(corners: &[[u32; 3]], position_id: &[u32]) -> Vec<u64> {
    let mut edges: Vec<u64> = corners
        .par_chunks_exact(3)
        .flat_map_iter(|t| {
            let p = [0, 1, 2].map(|k| position_id[t[k][0] as usize]);
            (0..3).map(move |k| (p[k] as u64) << 32 | p[(k + 1) % 3] as u64)
        })
        .collect();
    edges.par_sort_unstable();
    edges
}

/// Whether an edge of the sorted `edges` is there twice: tested by pieces
/// (see [`any_of`]), each piece also against the edge before it.
fn has_repeated_edge(edges: &[u64]) -> bool {
    edges.par_chunks(PIECE).enumerate().any(|(k, piece)| {
        let before = (k * PIECE).checked_sub(1).map(|j| edges[j]);
        before == Some(piece[0]) || piece.windows(2).any(|w| w[0] == w[1])
    })
}

/// Whether every edge of the sorted `edges` (starting at points below
/// `points`) has its reverse among them. Where each point's edges start in
/// the list (0: none, else the index + 1) is noted first: an edge's
/// reverse is looked for among the few edges of its end, not by a search
/// of the whole list.
fn every_edge_reversed(edges: &[u64], points: usize) -> bool {
    let starts: Vec<AtomicU32> = bytemuck::zeroed_vec(points);
    (0..edges.len()).into_par_iter().for_each(|j| {
        let from = edges[j] >> 32;
        if j == 0 || edges[j - 1] >> 32 != from {
            starts[from as usize].store(j as u32 + 1, Ordering::Relaxed);
        }
    });
    let has = |e: u64| {
        let from = e >> 32;
        let start = match starts.get(from as usize) {
            Some(s) => s.load(Ordering::Relaxed) as usize,
            None => 0,
        };
        start != 0
            && edges[start - 1..]
                .iter()
                .take_while(|&&f| f >> 32 == from)
                .any(|&f| f == e)
    };
    !any_of(edges, |&e| !has(e.rotate_right(32)))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Corners at a few points with UVs, normals, parts and flags drawn
    /// from small sets, so most points are seams and some crowded.
    fn corners(seed: u64, points: u32, triangles: usize) -> (IndexedCorners, Vec<u8>) {
        let mut state = seed;
        let mut next = |n: u32| {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 33) as u32 % n
        };
        let pick = |n: u32, next: &mut dyn FnMut(u32) -> u32| {
            let r = next(8);
            if r < 6 { r % n } else { next(n) }
        };
        let positions = (0..points)
            .map(|p| Vec3::new(p as f32, (p % 3) as f32, 0.5))
            .collect();
        let uvs = (0..4).map(|k| Vec2::new(k as f32 * 0.25, 0.5)).collect();
        let normals = (0..3).map(|k| Vec3::new(0.0, k as f32, 1.0)).collect();
        let mut corner_list = Vec::with_capacity(3 * triangles);
        let mut flags = Vec::with_capacity(triangles);
        for _ in 0..triangles {
            let projected = next(5) == 0;
            for _ in 0..3 {
                let uv = if projected {
                    NO_INDEX
                } else {
                    pick(4, &mut next)
                };
                corner_list.push([pick(points, &mut next), uv, pick(3, &mut next)]);
            }
            let side = if projected { next(6) as u8 } else { 0 };
            let mirrored = if next(4) == 0 { MIRRORED } else { 0 };
            flags.push(side | mirrored | if projected { PROJECTED } else { 0 });
        }
        let part_of = (0..triangles).map(|_| pick(3, &mut next)).collect();
        let c = IndexedCorners {
            positions,
            colors: Vec::new(),
            uvs,
            normals,
            corners: corner_list,
            part_of,
        };
        (c, flags)
    }

    #[test]
    fn vertices_are_split_as_one_pass_with_a_table_would() {
        for (seed, points, triangles) in [(1, 1, 40), (2, 3, 200), (3, 50, 300), (4, 400, 2000)] {
            let (c, flags) = corners(seed, points, triangles);
            let (position_id, ids) = position_ids(&c.positions);
            // One pass in corner order: a new key is the next vertex.
            let mut table = HashMap::default();
            let (mut vertex_of, mut firsts) = (Vec::new(), Vec::new());
            for i in 0..c.corners.len() {
                let point = position_id[c.corners[i][0] as usize];
                let count = table.len() as u32;
                let v = *table
                    .entry((point, vertex_key(&c, &flags, i)))
                    .or_insert(count);
                if v == count {
                    firsts.push(i as u32);
                }
                vertex_of.push(v);
            }
            for threads in [1, 2, 5] {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .unwrap();
                let mut held = crate::model_io::reserve("t", "test", 0).unwrap();
                let split = pool
                    .install(|| split_vertices("t", &c, &flags, (&position_id, ids), &mut held))
                    .unwrap();
                assert_eq!(
                    split,
                    (vertex_of.clone(), firsts.clone()),
                    "seed {seed}, {threads} threads"
                );
            }
        }
    }
}
