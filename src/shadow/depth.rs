//! The depth-only rasterizer of the shadow pass: no colour, no attributes,
//! just the nearest distance along the light's axis per texel.

use glam::{Mat4, Vec2, Vec3};

use crate::scene::Mesh;
use crate::scene::repeats::RepeatSkipper;
use crate::scene::terms::Cutout;
use crate::scene::world::Placed;

/// What the pass draws into: the map's texels (`size × size`, row 0 at the
/// top) and the light's view (the map keeps them; the pass needs no more).
pub(super) struct Target<'a> {
    pub size: usize,
    /// Distance along the light's axis of the nearest caster, per texel.
    pub depth: &'a mut [f32],
    /// Which object that nearest caster is, per texel.
    pub owner: &'a mut [u32],
    pub view_proj: Mat4,
    pub light: Vec3,
    pub near: f32,
}

/// Triangles drawn into the map between two questions to `stop`.
pub const CHECK_EVERY: usize = 4096;

/// Draws `mesh` (object `object`) placed as `placed` into the map, but for
/// the triangles `repeats` skips and the points `cutout` drops, until
/// `stop` (asked every [`CHECK_EVERY`] triangles) says so; returns the
/// texels written.
pub(super) fn draw_mesh(
    map: &mut Target,
    mesh: &Mesh,
    placed: &Placed,
    object: u32,
    cutout: Option<&Cutout>,
    mut repeats: RepeatSkipper,
    stop: &dyn Fn() -> bool,
) -> u64 {
    let size = map.size as f32;
    // Per vertex: texel coordinates and 1/w (None when too near the light).
    let projected: Vec<Option<(f32, f32, f32, Vec3)>> = placed
        .positions
        .iter()
        .map(|&world| {
            let clip = map.view_proj * world.extend(1.0);
            (clip.w > map.near * 0.5 && clip.is_finite()).then(|| {
                let inv_w = 1.0 / clip.w;
                let x = (clip.x * inv_w * 0.5 + 0.5) * size;
                let y = (0.5 - clip.y * inv_w * 0.5) * size;
                (x, y, inv_w, world)
            })
        })
        .collect();
    let mut written = 0;
    for (i, tri) in mesh.triangles.iter().enumerate() {
        if repeats.skip(i, &mesh.triangles) {
            continue;
        }
        if i % CHECK_EVERY == CHECK_EVERY - 1 && stop() {
            break;
        }
        let [a, b, c] = tri
            .indices
            .map(|i| projected.get(i as usize).copied().flatten());
        let (Some(a), Some(b), Some(c)) = (a, b, c) else {
            continue;
        };
        let v = [a, b, c];
        if mesh.closed {
            // Second depth: keep the faces turned away from the light.
            let n = placed.facets[i];
            if n.dot(map.light - v[0].3) > 0.0 {
                continue;
            }
        }
        let mask = cutout.map(|c| (c, tri.indices.map(|i| mesh.vertices[i as usize].uv)));
        written += fill(
            map,
            [v[0], v[1], v[2]].map(|(x, y, q, _)| (x, y, q)),
            object,
            mask,
        );
    }
    written
}

/// Fills one triangle (texel centres inside, either winding), keeping the
/// nearest depth. `q` is 1/w, which is linear across the projected triangle.
/// With a `mask` (the alpha mask and the corners' UVs), a texel whose
/// point it cuts out is left as it is; its UV is perspective-correct
/// (uv·q is linear too), as the main pass reads it.
fn fill(
    map: &mut Target,
    v: [(f32, f32, f32); 3],
    object: u32,
    mask: Option<(&Cutout, [Vec2; 3])>,
) -> u64 {
    let [(x0, y0, q0), (x1, y1, q1), (x2, y2, q2)] = v;
    let area = (x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0);
    // Also refuses NaN.
    if area.abs().partial_cmp(&1e-12) != Some(std::cmp::Ordering::Greater) {
        return 0;
    }
    let size = map.size;
    let lo_x = x0.min(x1).min(x2).floor().max(0.0) as usize;
    let hi_x = (x0.max(x1).max(x2).ceil().min(size as f32)) as usize;
    let lo_y = y0.min(y1).min(y2).floor().max(0.0) as usize;
    let hi_y = (y0.max(y1).max(y2).ceil().min(size as f32)) as usize;
    let inv_area = 1.0 / area;
    let mut written = 0;
    for ty in lo_y..hi_y {
        let py = ty as f32 + 0.5;
        let row = &mut map.depth[ty * size..(ty + 1) * size];
        let owners = &mut map.owner[ty * size..(ty + 1) * size];
        for ((tx, texel), owner) in row
            .iter_mut()
            .enumerate()
            .zip(owners.iter_mut())
            .take(hi_x)
            .skip(lo_x)
        {
            let px = tx as f32 + 0.5;
            // Barycentric weights, positive inside for either winding.
            let b0 = ((x1 - px) * (y2 - py) - (x2 - px) * (y1 - py)) * inv_area;
            let b1 = ((x2 - px) * (y0 - py) - (x0 - px) * (y2 - py)) * inv_area;
            let b2 = 1.0 - b0 - b1;
            if b0 < 0.0 || b1 < 0.0 || b2 < 0.0 {
                continue;
            }
            let q = b0 * q0 + b1 * q1 + b2 * q2;
            let depth = 1.0 / q;
            if depth < *texel {
                if let Some((cutout, uv)) = &mask {
                    let uv = (uv[0] * (b0 * q0) + uv[1] * (b1 * q1) + uv[2] * (b2 * q2)) * depth;
                    if !cutout.opaque(uv) {
                        continue;
                    }
                }
                *texel = depth;
                *owner = object;
                written += 1;
            }
        }
    }
    written
}
