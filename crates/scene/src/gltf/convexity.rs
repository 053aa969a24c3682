//! Whether a glTF primitive bounds a convex body (`crate::convex`), as an
//! OBJ, STL or PLY model is tested when built: a lone convex part is drawn
//! without a depth buffer and without a self-shadow pass.

use glam::Vec3;

use crate::convex;
use crate::corners::position_ids;
use crate::mesh::{Triangle, Vertex};
use relief_core::budget::Reservation;

use super::reading::bytes_of;

/// Whether `tris` over `vertices` bound a convex body, their corners
/// welded by position (a glTF vertex is split wherever its UV or normal
/// changes). Only a culled primitive (`closed`: not double-sided) that
/// does not deform is tested: a skin or morph targets may bend it, while a
/// node's motion, affine, keeps a convex body convex. The test only saves
/// work, so one that would not fit the memory budget says no.
pub(super) fn convex_part(
    vertices: &[Vertex],
    tris: &[Triangle],
    (closed, deforms): (bool, bool),
    (name, held): (&str, &mut Reservation),
) -> bool {
    if !closed || deforms || tris.len() < 4 {
        return false;
    }
    let n = vertices.len() as u64;
    // The positions, their sort keys and ids (`position_ids`), then the
    // test's own scratch (at most one id per vertex).
    let ids_bytes = bytes_of::<Vec3>(n) + bytes_of::<u128>(n) + bytes_of::<u32>(n);
    let bytes = ids_bytes + convex::scratch_bytes(tris.len(), vertices.len());
    let what = format!("the convexity test of model {name}");
    if held.grow(&what, bytes).is_err() {
        return false;
    }
    let positions: Vec<Vec3> = vertices.iter().map(|v| v.position).collect();
    let (id, points) = position_ids(&positions);
    drop(positions);
    let convex = convex::is_convex(
        tris.len(),
        points,
        &|t| tris[t].indices.map(|i| id[i as usize]),
        &|t| tris[t].indices.map(|i| vertices[i as usize].position),
    );
    held.shrink(bytes);
    convex
}
