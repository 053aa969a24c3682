//! Triangle setup: projection to fixed-point screen coordinates, edge
//! functions with the top-left fill rule, and the constants the pixel loop needs.

use glam::{Vec2, Vec3, Vec4};

use super::clip::ClipVertex;
use crate::shade::interpolate::{lerp2_at, lerp3_at};

/// Sub-pixel precision: 8 bits (1/256 of a pixel), with i64 edge maths.
pub const SUBPIXEL_BITS: u32 = 8;
pub const ONE: i64 = 1 << SUBPIXEL_BITS;
const HALF: i64 = ONE / 2;
/// Bounds of at most this many pixels are tested centre by centre at setup.
const SMALL_BOUNDS: i64 = 4;

/// A triangle ready to rasterize, in screen space (y down).
#[derive(Clone, Debug, PartialEq)]
pub struct ScreenTri {
    /// Index of the per-triangle shader data.
    pub shader: u32,
    /// Fixed-point vertex positions.
    pub x: [i64; 3],
    pub y: [i64; 3],
    /// 1/w per vertex (for perspective-correct interpolation).
    pub q: [f32; 3],
    /// NDC depth per vertex (affine in screen space).
    pub z: [f32; 3],
    /// Barycentric coordinates of each vertex in the source triangle.
    pub bary: [Vec3; 3],
    /// `bary` is the identity (the triangle was not clipped).
    pub unclipped: bool,
    /// Inclusive pixel bounds, already inside the viewport.
    pub x0: i32,
    pub x1: i32,
    pub y0: i32,
    pub y1: i32,
    /// Twice the signed area in fixed point, > 0.
    pub area: i64,
    /// −1 for edges that are neither top nor left, 0 otherwise (fill rule).
    pub bias: [i64; 3],
}

impl ScreenTri {
    /// Edge function of edge `i` (opposite vertex `i`) at a fixed-point point.
    #[inline]
    pub fn edge(&self, i: usize, px: i64, py: i64) -> i64 {
        let (a, b) = ((i + 1) % 3, (i + 2) % 3);
        (self.y[b] - self.y[a]) * (px - self.x[a]) - (self.x[b] - self.x[a]) * (py - self.y[a])
    }

    /// All three edge functions at a fixed-point point.
    #[inline]
    pub fn edges(&self, px: i64, py: i64) -> [i64; 3] {
        [
            self.edge(0, px, py),
            self.edge(1, px, py),
            self.edge(2, px, py),
        ]
    }

    /// Change of edge `i` for one pixel step in x and in y.
    #[inline]
    pub fn edge_steps(&self, i: usize) -> (i64, i64) {
        let (a, b) = ((i + 1) % 3, (i + 2) % 3);
        (
            (self.y[b] - self.y[a]) * ONE,
            -(self.x[b] - self.x[a]) * ONE,
        )
    }

    /// Screen-space derivatives of the barycentrics λ (per pixel).
    pub fn lambda_steps(&self) -> ([f32; 3], [f32; 3]) {
        let inv = 1.0 / self.area as f64;
        let mut dx = [0.0; 3];
        let mut dy = [0.0; 3];
        for i in 0..3 {
            let (sx, sy) = self.edge_steps(i);
            dx[i] = (sx as f64 * inv) as f32;
            dy[i] = (sy as f64 * inv) as f32;
        }
        (dx, dy)
    }

    /// Texture coordinates at this triangle's vertices, from the source's.
    pub fn vertex_uvs(&self, source: &[Vec2; 3]) -> [Vec2; 3] {
        let [a, b, c] = self.bary;
        [
            lerp2_at(a, source),
            lerp2_at(b, source),
            lerp2_at(c, source),
        ]
    }

    /// Barycentrics `b` on this triangle as barycentrics on the source
    /// triangle (the same unless the triangle was clipped).
    #[inline(always)]
    pub fn source_barycentrics(&self, b: [f32; 3]) -> Vec3 {
        let b = Vec3::from_array(b);
        if self.unclipped {
            b
        } else {
            lerp3_at(b, &self.bary)
        }
    }
}

/// Is the directed edge a→b a top or left edge, for triangles of positive
/// area in this orientation (counter-clockwise on a y-down screen)?
#[inline]
fn is_top_left(ax: i64, ay: i64, bx: i64, by: i64) -> bool {
    (ay == by && bx < ax) || by > ay
}

/// Projects three clip-space vertices to the viewport and sets the triangle
/// up. Returns `None` for zero area, or when no pixel centre can be inside.
/// Either winding is accepted (the caller has already culled back faces).
pub fn setup(v: [ClipVertex; 3], width: usize, height: usize, shader: u32) -> Option<ScreenTri> {
    setup_reaching(v, width, height, shader, 0)
}

/// [`setup`] for a rasterizer whose samples lie up to `reach` (in 1/[`ONE`]
/// pixel) from the pixel centres: the bounds take every pixel one of whose
/// samples can be inside, so a sliver between two rows of centres is kept
/// (multisampling covers it).
pub fn setup_reaching(
    v: [ClipVertex; 3],
    width: usize,
    height: usize,
    shader: u32,
    reach: i64,
) -> Option<ScreenTri> {
    let p = [0, 1, 2].map(|i| Projected::of(v[i].pos, width, height));
    let bary = [v[0].bary, v[1].bary, v[2].bary];
    setup_projected([p[0]?, p[1]?, p[2]?], bary, width, height, shader, reach)
}

/// A clip-space vertex projected to the viewport as setup needs it: fixed-
/// point position, 1/w and NDC depth. Computed once per vertex and frame
/// for the triangles clipping leaves whole.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Projected {
    pub x: i64,
    pub y: i64,
    pub q: f32,
    pub z: f32,
}

impl Projected {
    /// `p` on a `width × height` viewport, or `None` when not finite.
    #[inline]
    pub fn of(p: Vec4, width: usize, height: usize) -> Option<Projected> {
        // Clipping guarantees w ≥ near > 0 and coordinates within the guard band.
        let inv_w = 1.0 / p.w as f64;
        let sx = (p.x as f64 * inv_w + 1.0) * 0.5 * width as f64;
        let sy = (1.0 - p.y as f64 * inv_w) * 0.5 * height as f64;
        if !sx.is_finite() || !sy.is_finite() {
            return None;
        }
        Some(Projected {
            x: round(sx * ONE as f64),
            y: round(sy * ONE as f64),
            q: inv_w as f32,
            z: (p.z as f64 * inv_w) as f32,
        })
    }
}

/// `x.round() as i64` for a finite `x` (halves away from zero), without
/// the library call `round` is on targets without SSE4.1: once per vertex
/// of every mesh, every frame.
#[inline]
fn round(x: f64) -> i64 {
    // From 2^52 on every f64 is an integer (and the cast saturates alike).
    if x.abs() >= 4_503_599_627_370_496.0 {
        return x as i64;
    }
    let whole = x as i64; // towards zero
    // Exact: below 2^52 the fraction of x is representable.
    let fraction = x - whole as f64;
    // Without branches: the fraction of a screen position is as good as
    // random, and a mispredicted branch costs more than the library call.
    whole + i64::from(fraction >= 0.5) - i64::from(fraction <= -0.5)
}

/// [`setup_reaching`] from vertices already projected, with their
/// barycentrics in the source triangle. A triangle that holds no pixel
/// centre (a sub-pixel one) is refused before anything else is set up,
/// here, where the caller's loop is: most triangles of a big mesh stop at
/// their bounds.
#[inline]
pub fn setup_projected(
    v: [Projected; 3],
    bary: [Vec3; 3],
    width: usize,
    height: usize,
    shader: u32,
    reach: i64,
) -> Option<ScreenTri> {
    let x = v.map(|p| p.x);
    let y = v.map(|p| p.y);
    // Pixel px is covered only if its centre px·ONE + HALF lies within the bounds
    // With samples off the centre, within `reach` of it.
    let lo = |m: i64| (m - reach - HALF + ONE - 1).div_euclid(ONE);
    let hi = |m: i64| (m + reach - HALF).div_euclid(ONE);
    let x0 = lo(x[0].min(x[1]).min(x[2])).max(0);
    let x1 = hi(x[0].max(x[1]).max(x[2])).min(width as i64 - 1);
    let y0 = lo(y[0].min(y[1]).min(y[2])).max(0);
    let y1 = hi(y[0].max(y[1]).max(y[2])).min(height as i64 - 1);
    if x0 > x1 || y0 > y1 {
        return None;
    }
    setup_bounded(v, bary, [x0, x1, y0, y1], shader, reach)
}

/// The rest of [`setup_projected`], for a triangle whose pixel bounds
/// `[x0, x1, y0, y1]` (inside the viewport) hold a pixel centre.
fn setup_bounded(
    v: [Projected; 3],
    mut bary: [Vec3; 3],
    [x0, x1, y0, y1]: [i64; 4],
    shader: u32,
    reach: i64,
) -> Option<ScreenTri> {
    let mut x = v.map(|p| p.x);
    let mut y = v.map(|p| p.y);
    let mut area = (y[1] - y[0]) * (x[2] - x[0]) - (x[1] - x[0]) * (y[2] - y[0]);
    if area == 0 {
        return None;
    }
    let mut q = v.map(|p| p.q);
    let mut z = v.map(|p| p.z);
    if area < 0 {
        // Make the area positive by swapping two vertices.
        x.swap(1, 2);
        y.swap(1, 2);
        q.swap(1, 2);
        z.swap(1, 2);
        bary.swap(1, 2);
        area = -area;
    }
    let mut bias = [0i64; 3];
    for (i, b) in bias.iter_mut().enumerate() {
        let (a, c) = ((i + 1) % 3, (i + 2) % 3);
        if !is_top_left(x[a], y[a], x[c], y[c]) {
            *b = -1;
        }
    }
    // A small triangle (most of a big mesh seen small) whose bounds hold a
    // few pixel centres and that covers none of them draws nothing: it is
    // refused here, before its shader is built and its rows are estimated.
    if reach == 0 && (x1 - x0 + 1) * (y1 - y0 + 1) <= SMALL_BOUNDS {
        let covers = |px: i64, py: i64| {
            let (cx, cy) = (px * ONE + HALF, py * ONE + HALF);
            (0..3).all(|i| {
                let (a, b) = ((i + 1) % 3, (i + 2) % 3);
                let e = (y[b] - y[a]) * (cx - x[a]) - (x[b] - x[a]) * (cy - y[a]);
                e + bias[i] >= 0
            })
        };
        if !(y0..=y1).any(|py| (x0..=x1).any(|px| covers(px, py))) {
            return None;
        }
    }
    let unclipped = bary == [Vec3::X, Vec3::Y, Vec3::Z];
    Some(ScreenTri {
        shader,
        x,
        y,
        q,
        z,
        bary,
        unclipped,
        x0: x0 as i32,
        x1: x1 as i32,
        y0: y0 as i32,
        y1: y1 as i32,
        area,
        bias,
    })
}

#[cfg(test)]
mod tests {
    use super::{ONE, Projected, round, setup_projected};
    use glam::Vec3;

    /// The pixel centres a triangle covers, by the edge functions and the
    /// top-left rule worked here from their definitions.
    fn centres_covered(x: [i64; 3], y: [i64; 3], width: i64, height: i64) -> usize {
        // Twice the signed area, positive for the order the edge functions
        // below take as inside.
        let area = (y[1] - y[0]) * (x[2] - x[0]) - (x[1] - x[0]) * (y[2] - y[0]);
        let order = if area > 0 { [0, 1, 2] } else { [0, 2, 1] };
        let (x, y) = (order.map(|i| x[i]), order.map(|i| y[i]));
        let mut count = 0;
        for py in 0..height {
            for px in 0..width {
                let (cx, cy) = (px * ONE + ONE / 2, py * ONE + ONE / 2);
                let inside = (0..3).all(|i| {
                    let (a, b) = ((i + 1) % 3, (i + 2) % 3);
                    let e = (y[b] - y[a]) * (cx - x[a]) - (x[b] - x[a]) * (cy - y[a]);
                    // On the edge: drawn only for a top edge (flat, going
                    // left) or a left edge (going down).
                    let top_left = (y[a] == y[b] && x[b] < x[a]) || y[b] > y[a];
                    e > 0 || (e == 0 && top_left)
                });
                count += usize::from(inside);
            }
        }
        count
    }

    #[test]
    fn a_small_triangle_is_set_up_only_when_it_covers_a_pixel_centre() {
        let mut seed = 0x9e37_79b9_u64;
        let mut next = |range: i64| {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed % range as u64) as i64
        };
        let (width, height) = (6, 5);
        let (mut kept, mut refused, mut covering) = (0, 0, 0);
        for k in 0..40_000 {
            // Corners within about two pixels of each other, some on
            // pixel centres and edges exactly (multiples of 128).
            let (ox, oy) = (next(4 * ONE), next(3 * ONE));
            let snap = |v: i64| if k % 3 == 0 { v / 128 * 128 } else { v };
            let x = [0, 1, 2].map(|_| snap(ox + next(2 * ONE)));
            let y = [0, 1, 2].map(|_| snap(oy + next(2 * ONE)));
            let p = [0, 1, 2].map(|i| Projected {
                x: x[i],
                y: y[i],
                q: 1.0,
                z: 0.5,
            });
            let area = (x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0]);
            if area == 0 {
                continue;
            }
            let tri = setup_projected(p, Vec3::AXES, width as usize, height as usize, 0, 0);
            let covered = centres_covered(x, y, width, height);
            covering += usize::from(covered > 0);
            match tri {
                None => {
                    assert_eq!(covered, 0, "{x:?} {y:?} refused");
                    refused += 1;
                }
                Some(t) => {
                    let pixels = (t.x1 - t.x0 + 1) * (t.y1 - t.y0 + 1);
                    assert!(pixels > 4 || covered > 0, "{x:?} {y:?} kept");
                    kept += 1;
                }
            }
        }
        // Both cases occur often.
        assert!(
            kept > 1000 && refused > 1000 && covering > 1000,
            "{kept} {refused} {covering}"
        );
    }

    #[test]
    fn round_matches_the_library_round() {
        let mut values = vec![
            0.0,
            -0.0,
            0.5,
            -0.5,
            1.5,
            -1.5,
            2.5,
            -2.5,
            0.49999999999999994,
            -0.49999999999999994,
            4503599627370495.5,
            -4503599627370495.5,
            4503599627370496.0,
            1e19,
            -1e19,
            1e300,
        ];
        // Halves, and the floats either side of them, over a wide range.
        for k in -5000..5000 {
            let half = k as f64 + 0.5;
            values.extend([half, half.next_up(), half.next_down()]);
            values.push(k as f64 * 256.0 + 0.5);
            values.push((k as f64 * 0.37).exp2().copysign(k as f64));
        }
        for x in values {
            assert_eq!(round(x), x.round() as i64, "{x:e}");
        }
    }
}
