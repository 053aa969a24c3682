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
/// corners.
#[inline]
pub fn oct_uv(d: Vec3) -> Vec2 {
    let l1 = d.x.abs() + d.y.abs() + d.z.abs();
    let p = if l1 > 0.0 {
        Vec2::new(d.x, d.y) / l1
    } else {
        Vec2::ZERO
    };
    let p = if d.z < 0.0 {
        let sign = Vec2::new(p.x.signum(), p.y.signum());
        (Vec2::ONE - Vec2::new(p.y.abs(), p.x.abs())) * sign
    } else {
        p
    };
    p * 0.5 + 0.5
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
    /// clamped at the edges.
    #[inline]
    pub fn read(&self, uv: Vec2) -> Vec3 {
        let n = self.size;
        let last = (n - 1) as f32;
        let x = (uv.x * n as f32 - 0.5).clamp(0.0, last);
        let y = (uv.y * n as f32 - 0.5).clamp(0.0, last);
        let (x0, y0) = (x as usize, y as usize);
        let (x1, y1) = ((x0 + 1).min(n - 1), (y0 + 1).min(n - 1));
        let (fx, fy) = (x - x0 as f32, y - y0 as f32);
        let at = |r: usize, c: usize| self.texels[r * n + c];
        let top = at(y0, x0).lerp(at(y0, x1), fx);
        let bottom = at(y1, x0).lerp(at(y1, x1), fx);
        top.lerp(bottom, fy)
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
