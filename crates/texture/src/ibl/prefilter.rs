//! Specular light from an environment prefiltered by roughness: for each
//! of `LEVELS` roughnesses from 0 to 1, the environment seen through the
//! GGX lobe around each direction R, with N = V = R as the split sum
//! assumes (Karis, "Real Shading in Unreal Engine 4", 2013). Computed by a
//! direct weighted sum over the source's texels rather than by sampling:
//! with h = normalize(R + L), the lobe's weight is D(N·H)·(N·L)·dω(L)
//! (the GGX sampling density in L is D/4 when N = V, times N·L), so the
//! result has no sampling noise. Levels are stored as octahedral maps
//! (Engelhardt and Dachsbacher, 2008): a direction to a texel is a few
//! adds and a division, no trigonometry, which the kernel pays per pixel.

use glam::{Vec2, Vec3};
use wide::f32x8;

use super::source::Source;

/// The roughnesses of the levels: level i is roughness i/(LEVELS − 1).
pub const LEVELS: usize = 6;
/// Side of each level's octahedral map: the mirror's sharp, the rough
/// ones' small (their light changes slowly with R).
const LEVEL_SIZES: [usize; LEVELS] = [128, 64, 32, 32, 16, 16];
/// Width of the source each level sums (height half of it): texels well
/// inside the lobe's width, so the sum is smooth and cheap.
const SOURCE_WIDTHS: [usize; LEVELS] = [512, 128, 64, 64, 32, 32];

/// One level: a square octahedral map of linear radiance, top row first.
pub struct OctMap {
    pub size: usize,
    pub texels: Vec<Vec3>,
}

impl std::fmt::Debug for OctMap {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("OctMap").field("size", &self.size).finish()
    }
}

/// The octahedral coordinates of unit direction `d` in 0..=1: the upper
/// half (+Z) in the diamond at the centre, the lower half folded into the
/// corners. (The first lane of [`oct_uv_lanes`], the formula's one source.)
#[inline]
pub fn oct_uv(d: Vec3) -> Vec2 {
    let [u, v] = oct_uv_lanes([f32x8::splat(d.x), f32x8::splat(d.y), f32x8::splat(d.z)]);
    Vec2::new(u.as_array()[0], v.as_array()[0])
}

/// [`oct_uv`] of eight directions (x, y, z per lane): for directions
/// without NaN, each lane's bits are the one-direction formula's (the same
/// IEEE operations in the same order).
#[inline(always)]
pub fn oct_uv_lanes([x, y, z]: [f32x8; 3]) -> [f32x8; 2] {
    let l1 = x.abs() + y.abs() + z.abs();
    let positive = l1.simd_gt(f32x8::ZERO);
    let px = positive.select(x / l1, f32x8::ZERO);
    let py = positive.select(y / l1, f32x8::ZERO);
    // The lower half folds over the diamond's edges: (1 − |y|, 1 − |x|)
    // with the signs of (x, y) (signum: +1 for +0, −1 for −0).
    let signum = |t: f32x8| (t & f32x8::splat(-0.0)) | f32x8::ONE;
    let fx = (f32x8::ONE - py.abs()) * signum(px);
    let fy = (f32x8::ONE - px.abs()) * signum(py);
    let below = z.simd_lt(f32x8::ZERO);
    let half = f32x8::splat(0.5);
    [
        below.select(fx, px) * half + half,
        below.select(fy, py) * half + half,
    ]
}

/// The unit direction at octahedral coordinates `uv` (the inverse of
/// [`oct_uv`]).
pub fn oct_direction(uv: Vec2) -> Vec3 {
    let p = uv * 2.0 - 1.0;
    let z = 1.0 - p.x.abs() - p.y.abs();
    let p = if z < 0.0 {
        let sign = Vec2::new(p.x.signum(), p.y.signum());
        (Vec2::ONE - Vec2::new(p.y.abs(), p.x.abs())) * sign
    } else {
        p
    };
    Vec3::new(p.x, p.y, z).normalize_or(Vec3::Z)
}

impl OctMap {
    /// A `size²` map whose texels take `f` of their centre's direction.
    pub fn from_fn(size: usize, f: impl Fn(Vec3) -> Vec3) -> OctMap {
        let mut texels = Vec::with_capacity(size * size);
        for y in 0..size {
            for x in 0..size {
                let uv = Vec2::new(x as f32 + 0.5, y as f32 + 0.5) / size as f32;
                texels.push(f(oct_direction(uv)));
            }
        }
        OctMap { size, texels }
    }

    /// The radiance at `uv` (0..=1), bilinear between texel centres and
    /// clamped at the edges. (The first lane of [`OctMap::read_lanes`].)
    #[inline]
    pub fn read(&self, uv: Vec2) -> Vec3 {
        let [r, g, b] = self.read_lanes([f32x8::splat(uv.x), f32x8::splat(uv.y)], 1);
        Vec3::new(r.as_array()[0], g.as_array()[0], b.as_array()[0])
    }

    /// [`OctMap::read`] at eight points (u, v per lane): the lanes whose
    /// bit is set in `live` read their texels, the others are 0. The
    /// coordinates are clamped to the map (a NaN to its first texel), so
    /// every read is inside it.
    #[inline(always)]
    pub fn read_lanes(&self, [u, v]: [f32x8; 2], live: u32) -> [f32x8; 3] {
        let n = self.size;
        let (size, last) = (f32x8::splat(n as f32), f32x8::splat((n - 1) as f32));
        let half = f32x8::splat(0.5);
        let x = (u * size - half).max(f32x8::ZERO).min(last);
        let y = (v * size - half).max(f32x8::ZERO).min(last);
        let (xi, yi) = (x.trunc_int(), y.trunc_int());
        let (fx, fy) = (x - f32x8::from_i32x8(xi), y - f32x8::from_i32x8(yi));
        let (xi, yi) = (xi.to_array(), yi.to_array());
        // The four corners' texels, lane by lane, channel by channel.
        let mut corners = [[[0.0f32; 8]; 3]; 4];
        for lane in (0..8).filter(|l| live & (1 << l) != 0) {
            let (x0, y0) = (xi[lane] as usize, yi[lane] as usize);
            let (x1, y1) = ((x0 + 1).min(n - 1), (y0 + 1).min(n - 1));
            for (corner, (r, c)) in [(y0, x0), (y0, x1), (y1, x0), (y1, x1)]
                .into_iter()
                .enumerate()
            {
                let t = self.texels[r * n + c];
                for k in 0..3 {
                    corners[corner][k][lane] = t[k];
                }
            }
        }
        // glam's `lerp`: a·(1 − s) + b·s.
        let lerp = |a: f32x8, b: f32x8, s: f32x8| a * (f32x8::ONE - s) + b * s;
        let channel = |k: usize| {
            let at = |corner: usize| f32x8::from(corners[corner][k]);
            lerp(lerp(at(0), at(1), fx), lerp(at(2), at(3), fx), fy)
        };
        [channel(0), channel(1), channel(2)]
    }

    /// The radiance at `uv` (0..=1), bilinear between texel centres across
    /// the map's edges too: a texel's neighbour beyond an edge is the texel
    /// mirrored about that edge's midpoint (the octahedron folds there), and
    /// beyond a corner the opposite corner, so the read is continuous over
    /// the whole sphere. (`read` clamps at the edges instead, which holds
    /// the value half a texel from the edge: an error of the first order in
    /// the texel's size, which the prefiltered levels keep.)
    #[inline]
    pub fn read_seamless(&self, uv: Vec2) -> Vec3 {
        let n = self.size as f32;
        // Texel positions shifted by one, ≥ 0.5, so truncation is floor + 1.
        let x = (uv.x * n + 0.5).clamp(0.5, n + 0.5);
        let y = (uv.y * n + 0.5).clamp(0.5, n + 0.5);
        let (xi, yi) = (x as usize, y as usize);
        let (fx, fy) = (x - xi as f32, y - yi as f32);
        let size = self.size;
        let [a, b, c, d] = if xi >= 1 && yi >= 1 && xi < size && yi < size {
            // All four inside: the common case, read directly.
            let i = (yi - 1) * size + xi - 1;
            let t = &self.texels;
            [t[i], t[i + 1], t[i + size], t[i + size + 1]]
        } else {
            let (xi, yi) = (xi as i64, yi as i64);
            [
                self.texel(xi - 1, yi - 1),
                self.texel(xi, yi - 1),
                self.texel(xi - 1, yi),
                self.texel(xi, yi),
            ]
        };
        let top = a.lerp(b, fx);
        let bottom = c.lerp(d, fx);
        top.lerp(bottom, fy)
    }

    /// Texel (x, y) for x and y in −1..=size: one beyond an edge is the
    /// texel mirrored about the edge's midpoint on the edge's own row or
    /// column.
    #[inline]
    fn texel(&self, x: i64, y: i64) -> Vec3 {
        let last = self.size as i64 - 1;
        let (mut x, mut y) = (x, y);
        if y < 0 || y > last {
            y = y.clamp(0, last);
            x = last - x;
        }
        if x < 0 || x > last {
            x = x.clamp(0, last);
            y = last - y;
        }
        self.texels[(y * (last + 1) + x) as usize]
    }
}

/// The `LEVELS` prefiltered maps of `source`: level 0 the environment
/// itself (a mirror), the others its GGX-weighted sums.
pub fn prefilter(source: &Source) -> Vec<OctMap> {
    (0..LEVELS)
        .map(|i| {
            if i == 0 {
                return OctMap::from_fn(LEVEL_SIZES[0], |d| source.lookup(d));
            }
            let w = SOURCE_WIDTHS[i];
            let texels = source.shrunk((w, w / 2)).texels_with_solid_angles();
            let roughness = i as f32 / (LEVELS - 1) as f32;
            let alpha = roughness * roughness;
            OctMap::from_fn(LEVEL_SIZES[i], |r| lobe_mean(&texels, r, alpha * alpha))
        })
        .collect()
}

/// The GGX-weighted mean of `texels` around `r` for α² = `alpha2`.
fn lobe_mean(texels: &[(Vec3, f32, Vec3)], r: Vec3, alpha2: f32) -> Vec3 {
    let mut sum = Vec3::ZERO;
    let mut weight = 0.0f32;
    for &(l, d_omega, radiance) in texels {
        let nl = r.dot(l);
        if nl <= 0.0 {
            continue;
        }
        let h = (r + l).normalize();
        let w = distribution(alpha2, r.dot(h)) * nl * d_omega;
        sum += radiance * w;
        weight += w;
    }
    if weight > 0.0 {
        sum / weight
    } else {
        Vec3::ZERO
    }
}

/// GGX's D for α² = `alpha2` at N·H = `nh` (the formula of
/// `shade::brdf::distribution`, which `texture` does not import).
fn distribution(alpha2: f32, nh: f32) -> f32 {
    let d = nh * nh * (alpha2 - 1.0) + 1.0;
    alpha2 / (std::f32::consts::PI * d * d)
}
