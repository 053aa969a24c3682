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

use glam::{Vec2, Vec3, Vec3A};
use rayon::prelude::*;
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

/// One level: a square octahedral map of linear radiance, top row first;
/// each texel 16 bytes, so that a read loads one in one instruction.
pub struct OctMap {
    pub size: usize,
    pub texels: Vec<Vec3A>,
}

/// Where eight points fall among the texel centres of their maps: the
/// upper-left texel and the weights towards the next, per lane.
pub struct Bilinear {
    xi: [i32; 8],
    yi: [i32; 8],
    fx: [f32; 8],
    fy: [f32; 8],
}

impl Bilinear {
    /// The points at `u`, `v` (0..=1) in maps of `size`² texels (per lane),
    /// clamped to the maps (a NaN to their first texel).
    #[inline(always)]
    pub fn at([u, v]: [f32x8; 2], size: f32x8) -> Bilinear {
        let (half, last) = (f32x8::splat(0.5), size - f32x8::ONE);
        let x = (u * size - half).max(f32x8::ZERO).min(last);
        let y = (v * size - half).max(f32x8::ZERO).min(last);
        let (xi, yi) = (x.trunc_int(), y.trunc_int());
        let (fx, fy) = (x - f32x8::from_i32x8(xi), y - f32x8::from_i32x8(yi));
        Bilinear {
            xi: xi.to_array(),
            yi: yi.to_array(),
            fx: fx.to_array(),
            fy: fy.to_array(),
        }
    }
}

/// Eight lanes' colours as three channels of eight (0 in the lanes not
/// written).
#[derive(Default)]
pub struct LaneColours([[f32; 8]; 3]);

impl LaneColours {
    #[inline(always)]
    pub fn set(&mut self, lane: usize, c: Vec3A) {
        self.0[0][lane] = c.x;
        self.0[1][lane] = c.y;
        self.0[2][lane] = c.z;
    }

    #[inline(always)]
    pub fn channels(self) -> [f32x8; 3] {
        self.0.map(f32x8::from)
    }
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
    /// A `size²` map whose texels take `f` of their centre's direction,
    /// its rows computed in parallel (a level's texels are independent).
    pub fn from_fn(size: usize, f: impl Fn(Vec3) -> Vec3 + Sync) -> OctMap {
        let mut texels = vec![Vec3A::ZERO; size * size];
        texels
            .par_chunks_mut(size.max(1))
            .enumerate()
            .for_each(|(y, row)| {
                for (x, texel) in row.iter_mut().enumerate() {
                    let uv = Vec2::new(x as f32 + 0.5, y as f32 + 0.5) / size as f32;
                    *texel = Vec3A::from(f(oct_direction(uv)));
                }
            });
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
    pub fn read_lanes(&self, uv: [f32x8; 2], live: u32) -> [f32x8; 3] {
        let at = Bilinear::at(uv, f32x8::splat(self.size as f32));
        let mut out = LaneColours::default();
        for lane in (0..8).filter(|l| live & (1 << l) != 0) {
            out.set(lane, self.blend(&at, lane));
        }
        out.channels()
    }

    /// Lane `lane` of `at`'s bilinear read (`at` made for this map's size).
    #[inline(always)]
    pub fn blend(&self, at: &Bilinear, lane: usize) -> Vec3A {
        let n = self.size;
        let (x0, y0) = (at.xi[lane] as usize, at.yi[lane] as usize);
        let (x1, y1) = ((x0 + 1).min(n - 1), (y0 + 1).min(n - 1));
        let t = &self.texels;
        let fx = at.fx[lane];
        // glam's `lerp`, a·(1 − s) + b·s, three channels at once.
        let top = t[y0 * n + x0].lerp(t[y0 * n + x1], fx);
        let bottom = t[y1 * n + x0].lerp(t[y1 * n + x1], fx);
        top.lerp(bottom, at.fy[lane])
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
        Vec3::from(top.lerp(bottom, fy))
    }

    /// Texel (x, y) for x and y in −1..=size: one beyond an edge is the
    /// texel mirrored about the edge's midpoint on the edge's own row or
    /// column.
    #[inline]
    fn texel(&self, x: i64, y: i64) -> Vec3A {
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
            let texels = TexelLanes::of(&source.shrunk((w, w / 2)));
            let roughness = i as f32 / (LEVELS - 1) as f32;
            let alpha = roughness * roughness;
            OctMap::from_fn(LEVEL_SIZES[i], |r| texels.lobe_mean(r, alpha * alpha))
        })
        .collect()
}

/// A source's texels eight at a time: centre direction, solid angle and
/// radiance, the last group padded with texels of no solid angle.
struct TexelLanes {
    direction: Vec<[f32x8; 3]>,
    d_omega: Vec<f32x8>,
    radiance: Vec<[f32x8; 3]>,
}

impl TexelLanes {
    fn of(source: &Source) -> TexelLanes {
        let texels = source.texels_with_solid_angles();
        let groups = texels.chunks(8);
        let lane = |chunk: &[(Vec3, f32, Vec3)], f: &dyn Fn(&(Vec3, f32, Vec3)) -> f32| {
            f32x8::from(std::array::from_fn::<f32, 8, _>(|i| {
                chunk.get(i).map_or(0.0, f)
            }))
        };
        let triple = |chunk: &[(Vec3, f32, Vec3)], pick: fn(&(Vec3, f32, Vec3)) -> Vec3| {
            [0, 1, 2].map(|k| lane(chunk, &|t| pick(t)[k]))
        };
        TexelLanes {
            direction: groups.clone().map(|c| triple(c, |t| t.0)).collect(),
            d_omega: groups.clone().map(|c| lane(c, &|t| t.1)).collect(),
            radiance: groups.map(|c| triple(c, |t| t.2)).collect(),
        }
    }

    /// The GGX-weighted mean of the texels around `r` for α² = `alpha2`:
    /// each texel L weighs D(N·H)·(N·L)·dω with N = R. With H the unit
    /// half vector of R and L, (R·H)² = (1 + R·L)/2, so D needs no square
    /// root; its constant factor α²/π cancels in the mean.
    fn lobe_mean(&self, r: Vec3, alpha2: f32) -> Vec3 {
        let [rx, ry, rz] = [r.x, r.y, r.z].map(f32x8::splat);
        let (half, k) = (f32x8::splat(0.5), f32x8::splat(alpha2 - 1.0));
        let mut sum = [f32x8::ZERO; 3];
        let mut weight = f32x8::ZERO;
        for ((l, d_omega), radiance) in self.direction.iter().zip(&self.d_omega).zip(&self.radiance)
        {
            let nl = rx * l[0] + ry * l[1] + rz * l[2];
            let d = (f32x8::ONE + nl) * half * k + f32x8::ONE;
            let w = nl
                .simd_gt(f32x8::ZERO)
                .select(nl * *d_omega / (d * d), f32x8::ZERO);
            for (s, c) in sum.iter_mut().zip(radiance) {
                *s += *c * w;
            }
            weight += w;
        }
        let weight = weight.reduce_add();
        if weight > 0.0 {
            Vec3::from(sum.map(|s| s.reduce_add())) / weight
        } else {
            Vec3::ZERO
        }
    }
}
