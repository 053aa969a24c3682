//! Eight pixels of a row shaded at once: the lane arithmetic of the kernels.
//!
//! Every operation here is the one the single-pixel kernel does, in the same
//! order and on the same `f32` values (IEEE add, multiply, divide and square
//! root round the same in every lane and on every instruction set, and Rust
//! never fuses a multiply and an add behind our back), so a packet gives the
//! very bits the one-pixel path gives. Only texel fetches are per lane.

use std::ops::{Add, Div, Mul, Neg, Sub};

use glam::Vec3;
use wide::{f32x4, f32x8, i32x8};

use relief_core::framebuffer::Rgb;
use relief_core::stats::Counters;
use relief_texture::sample::level::around;
use relief_texture::sample::texels::Fetch;
use relief_texture::with_fetch;
use relief_texture::{Level, NormalMap};

/// Pixels per packet.
pub const LANES: usize = 8;

/// Eight 3-vectors, one component per register.
#[derive(Clone, Copy, Debug)]
pub struct V3 {
    pub x: f32x8,
    pub y: f32x8,
    pub z: f32x8,
}

impl V3 {
    #[inline(always)]
    pub fn splat(v: Vec3) -> V3 {
        V3 {
            x: f32x8::splat(v.x),
            y: f32x8::splat(v.y),
            z: f32x8::splat(v.z),
        }
    }

    /// glam's `Vec3::dot`: (x·x') + (y·y') + (z·z').
    #[inline(always)]
    pub fn dot(self, o: V3) -> f32x8 {
        self.x * o.x + self.y * o.y + self.z * o.z
    }

    /// glam's `Vec3::cross`, term for term.
    #[inline(always)]
    pub fn cross(self, o: V3) -> V3 {
        V3 {
            x: self.y * o.z - o.y * self.z,
            y: self.z * o.x - o.z * self.x,
            z: self.x * o.y - o.x * self.y,
        }
    }

    #[inline(always)]
    pub fn scale(self, s: f32x8) -> V3 {
        V3 {
            x: self.x * s,
            y: self.y * s,
            z: self.z * s,
        }
    }

    #[inline(always)]
    pub fn plus(self, o: V3) -> V3 {
        V3 {
            x: self.x + o.x,
            y: self.y + o.y,
            z: self.z + o.z,
        }
    }

    #[inline(always)]
    pub fn minus(self, o: V3) -> V3 {
        V3 {
            x: self.x - o.x,
            y: self.y - o.y,
            z: self.z - o.z,
        }
    }

    #[inline(always)]
    pub fn times(self, o: V3) -> V3 {
        V3 {
            x: self.x * o.x,
            y: self.y * o.y,
            z: self.z * o.z,
        }
    }

    /// Lane-wise choice: `mask` lanes from `a`, the others from `b`.
    #[inline(always)]
    pub fn select(mask: f32x8, a: V3, b: V3) -> V3 {
        V3 {
            x: mask.select(a.x, b.x),
            y: mask.select(a.y, b.y),
            z: mask.select(a.z, b.z),
        }
    }
}

impl Neg for V3 {
    type Output = V3;
    #[inline(always)]
    fn neg(self) -> V3 {
        V3 {
            x: -self.x,
            y: -self.y,
            z: -self.z,
        }
    }
}

impl Add for V3 {
    type Output = V3;
    #[inline(always)]
    fn add(self, o: V3) -> V3 {
        self.plus(o)
    }
}

impl Sub for V3 {
    type Output = V3;
    #[inline(always)]
    fn sub(self, o: V3) -> V3 {
        self.minus(o)
    }
}

impl Mul for V3 {
    type Output = V3;
    #[inline(always)]
    fn mul(self, o: V3) -> V3 {
        self.times(o)
    }
}

impl Mul<f32x8> for V3 {
    type Output = V3;
    #[inline(always)]
    fn mul(self, s: f32x8) -> V3 {
        self.scale(s)
    }
}

impl Div<f32x8> for V3 {
    type Output = V3;
    #[inline(always)]
    fn div(self, s: f32x8) -> V3 {
        V3 {
            x: self.x / s,
            y: self.y / s,
            z: self.z / s,
        }
    }
}

/// Quantises eight colours as `finish` does (clamped, rounded, NaN to 0),
/// counting the non-finite ones among the `live` lanes.
#[inline(always)]
pub fn finish(c: V3, live: u32, counters: &mut Counters) -> [Rgb; LANES] {
    let inf = f32x8::splat(f32::INFINITY);
    let finite = c.x.abs().simd_lt(inf) & c.y.abs().simd_lt(inf) & c.z.abs().simd_lt(inf);
    let bad = !(finite.to_bitmask()) & live;
    counters.nonfinite += bad.count_ones() as u64;
    let q = |v: f32x8| -> i32x8 {
        // `ge` is false for NaN, which then becomes 0 like `f32::max` makes it.
        let v = v.simd_ge(f32x8::ZERO).select(v, f32x8::ZERO);
        let v = v.fast_min(f32x8::ONE) * f32x8::splat(255.0) + f32x8::splat(0.5);
        v.fast_trunc_int()
    };
    // Each lane's 0..=255 channels packed as R | G << 8 | B << 16, written
    // four bytes at a time three bytes apart (each store's top byte is
    // overwritten by the next lane's red).
    let packed: [i32; LANES] = (q(c.x) | (q(c.y) << 8_i32) | (q(c.z) << 16_i32)).to_array();
    let mut bytes = [0u8; 3 * LANES + 1];
    for (lane, p) in packed.iter().enumerate() {
        bytes[3 * lane..3 * lane + 4].copy_from_slice(&p.to_le_bytes());
    }
    let mut out = [[0u8; 3]; LANES];
    out.as_flattened_mut().copy_from_slice(&bytes[..3 * LANES]);
    out
}

/// What a packet reads from the texture: bilinear colour, the filtered
/// height gradient, or both (they share one neighbourhood of texels).
pub struct TexelPacket {
    pub color: V3,
    pub fu: f32x8,
    pub fv: f32x8,
}

/// The fraction of t in [0, 1) as `level::fract01` computes it.
#[inline(always)]
fn fract01(t: f32x8) -> f32x8 {
    let valid = t.abs().simd_lt(f32x8::splat(8_388_608.0));
    let t = valid.select(t, f32x8::ZERO);
    let f = t - f32x8::from_i32x8(t.fast_trunc_int());
    let f = f.simd_lt(f32x8::ZERO).select(f + f32x8::ONE, f);
    f.simd_ge(f32x8::ONE).select(f32x8::ZERO, f)
}

/// The texel-space position minus a half texel, its floor (clamped as the
/// one-pixel read clamps it) and the fraction past that floor; and whether
/// every lane's floor is at least one texel from either end (1 ..= n − 3),
/// where the neighbourhood needs no wrapping.
#[inline(always)]
fn axis(t: f32x8, n: usize) -> ([i32; LANES], f32x8, bool) {
    let size = f32x8::splat(n as f32);
    let x = fract01(t) * size;
    let x = x.simd_lt(size).select(x, f32x8::ZERO) - f32x8::splat(0.5);
    // x ≥ −0.5: its floor is −1 below 0, else its truncation.
    let i = x
        .simd_lt(f32x8::ZERO)
        .select(f32x8::splat(-1.0), f32x8::from_i32x8(x.fast_trunc_int()));
    let i = i.fast_min(f32x8::splat(n as f32 - 1.0));
    let interior =
        (i.simd_ge(f32x8::ONE) & i.simd_le(f32x8::splat(n as f32 - 3.0))).to_bitmask() == 0xff;
    let ii: i32x8 = i.fast_trunc_int();
    (ii.to_array(), x - i, interior)
}

/// Bilinear colour (when `COLOR`) and the filtered height gradient (when
/// `GRADIENT`) at eight points of `level`: `Level::bilinear_with_gradient`,
/// lane-wise. Each lane reads its texels and blends its four channels (or
/// its four height quads) in one 4-wide register, the very operations of
/// the one-pixel read; the results are then transposed to one register per
/// channel.
#[inline(always)]
pub fn bilinear<const COLOR: bool, const GRADIENT: bool>(
    level: &Level,
    u: f32x8,
    v: f32x8,
) -> TexelPacket {
    if !level.wrap.repeats() {
        return bilinear_wrapped::<COLOR, GRADIENT>(level, u, v);
    }
    let (w, h) = (level.width, level.height);
    let (xi, fx, x_inside) = axis(u, w);
    let (yi, fy, y_inside) = axis(v, h);
    let (fx, fy) = (fx.to_array(), fy.to_array());
    let inside = x_inside && y_inside;
    let (color, heights) = with_fetch!(&level.texels, t => {
        lane_reads::<COLOR, GRADIENT, _>(t, (w, h), (&xi, &yi), (&fx, &fy), inside)
    });
    let color = if COLOR {
        let [r, g, b, _] = channels(&color);
        V3 { x: r, y: g, z: b }
    } else {
        V3::splat(Vec3::ZERO)
    };
    let (mut fu, mut fv) = (f32x8::ZERO, f32x8::ZERO);
    if GRADIENT {
        let [east, west, north, south] = channels(&heights);
        let half = f32x8::splat(0.5);
        fu = (east - west) * half * f32x8::splat(w as f32);
        fv = (north - south) * half * f32x8::splat(h as f32);
    }
    TexelPacket { color, fu, fv }
}

/// `bilinear` on a level that does not repeat on both axes (a model's
/// clamped or mirrored map): each lane read by the one-pixel read, so both
/// give the same bits.
#[inline(never)]
fn bilinear_wrapped<const COLOR: bool, const GRADIENT: bool>(
    level: &Level,
    u: f32x8,
    v: f32x8,
) -> TexelPacket {
    let (u, v) = (u.to_array(), v.to_array());
    /// One lane's colour and height gradient.
    type Read = ([f32; 4], (f32, f32));
    let reads: [Read; LANES] = std::array::from_fn(|i| {
        if GRADIENT {
            level.bilinear_with_gradient(u[i], v[i])
        } else {
            (level.bilinear(u[i], v[i]), (0.0, 0.0))
        }
    });
    let lane = |f: &dyn Fn(&Read) -> f32| f32x8::new(reads.each_ref().map(f));
    let color = if COLOR {
        V3 {
            x: lane(&|r| r.0[0]),
            y: lane(&|r| r.0[1]),
            z: lane(&|r| r.0[2]),
        }
    } else {
        V3::splat(Vec3::ZERO)
    };
    TexelPacket {
        color,
        fu: lane(&|r| r.1.0),
        fv: lane(&|r| r.1.1),
    }
}

/// `NormalMap::bilinear` at eight points, in the lanes of `live` (0 in
/// the others). On a repeating map the texel positions and fractions are
/// found eight at a time (as `bilinear`'s `axis`, the one-point read's
/// bits), each lane's four normals read by index and blended; a clamped or
/// mirrored map is read lane by lane by the one-point read.
#[inline(always)]
pub fn normal_bilinear(map: &NormalMap, u: f32x8, v: f32x8, live: u32) -> [f32x8; 3] {
    let mut normals = [[0.0f32; LANES]; 3];
    let lanes = (0..LANES).filter(|l| live & (1 << l) != 0);
    if !map.wrap.repeats() {
        let (u, v) = (u.to_array(), v.to_array());
        for lane in lanes {
            let n = map.bilinear(u[lane], v[lane]);
            for k in 0..3 {
                normals[k][lane] = n[k];
            }
        }
        return normals.map(f32x8::from);
    }
    let (w, h) = (map.width, map.height);
    let (xi, fx, _) = axis(u, w);
    let (yi, fy, _) = axis(v, h);
    let (fx, fy) = (fx.to_array(), fy.to_array());
    let texel = |i: usize| {
        let [x, y, z] = map.normals.at(i);
        f32x4::from([x, y, z, 0.0])
    };
    // The texels around each floor, wrapped as the one-point read wraps
    // them (`around`): the second and third are the bilinear pair. Each
    // lane blends its texels' three values at once: t = a + (b − a)·f
    // along u, then along v.
    for lane in lanes {
        let [_, c0, c1, _] = around(xi[lane] as i64, w);
        let [_, r0, r1, _] = around(yi[lane] as i64, h);
        let (r0, r1) = (r0 * w, r1 * w);
        let (a, b) = (texel(r0 + c0), texel(r0 + c1));
        let (c, d) = (texel(r1 + c0), texel(r1 + c1));
        let (x, y) = (f32x4::splat(fx[lane]), f32x4::splat(fy[lane]));
        let top = a + (b - a) * x;
        let bottom = c + (d - c) * x;
        let n = (top + (bottom - top) * y).to_array();
        for k in 0..3 {
            normals[k][lane] = n[k];
        }
    }
    normals.map(f32x8::from)
}

/// Every lane's bilinear colour and its four bilinear heights, from
/// texels read through `t` (one compiled copy per storage kind).
#[inline(always)]
fn lane_reads<const COLOR: bool, const GRADIENT: bool, F: Fetch>(
    t: F,
    (w, h): (usize, usize),
    (xi, yi): (&[i32; LANES], &[i32; LANES]),
    (fx, fy): (&[f32; LANES], &[f32; LANES]),
    inside: bool,
) -> ([f32x4; LANES], [f32x4; LANES]) {
    let mut color = [f32x4::ZERO; LANES];
    // East, west, north and south bilinear heights of each lane.
    let mut heights = [f32x4::ZERO; LANES];
    if inside {
        // No lane wraps: texel (row r, column c) of the 4×4 neighbourhood
        // is at a fixed offset from the lane's (x0, y0).
        assert!(w >= 4 && h >= 4 && t.len() == w * h);
        for lane in 0..LANES {
            let centre = yi[lane] as usize * w + xi[lane] as usize;
            let index = |r: usize, c: usize| {
                let k = centre + r * w + c - w - 1;
                debug_assert!(centre > w && k < t.len());
                k
            };
            // SAFETY (both): 1 ≤ x0 ≤ w − 3 and 1 ≤ y0 ≤ h − 3 (checked by
            // `axis` for every lane), so for r, c in 0..4 the index
            // (y0 + r − 1)·w + x0 + c − 1 lies in 0..w·h = t.len().
            let at = |r: usize, c: usize| unsafe { t.at_unchecked(index(r, c)) };
            let height = |r: usize, c: usize| unsafe { t.height_unchecked(index(r, c)) };
            (color[lane], heights[lane]) = blend::<COLOR, GRADIENT>(at, height, fx[lane], fy[lane]);
        }
    } else {
        for lane in 0..LANES {
            let cols = around(xi[lane] as i64, w);
            let rows = row_starts(yi[lane] as i64, h, w);
            let at = |r: usize, c: usize| t.at(rows[r] + cols[c]);
            let height = |r: usize, c: usize| t.height(rows[r] + cols[c]);
            (color[lane], heights[lane]) = blend::<COLOR, GRADIENT>(at, height, fx[lane], fy[lane]);
        }
    }
    (color, heights)
}

/// The starts of the four rows around row `y` of a `w`-wide level `h` rows
/// high, wrapped (not generic: `lane_reads` is compiled once per reader).
#[inline(always)]
fn row_starts(y: i64, h: usize, w: usize) -> [usize; 4] {
    around(y, h).map(|r| r * w)
}

/// One lane's bilinear colour (RGBA) and its east, west, north and south
/// bilinear heights, from its 4×4 neighbourhood `at(row, column)` (the
/// point between rows 1, 2 and columns 1, 2) and fractions. `height` reads
/// channel 3 alone, which compact storage converts without the others.
#[inline(always)]
fn blend<const COLOR: bool, const GRADIENT: bool>(
    at: impl Fn(usize, usize) -> [f32; 4],
    height: impl Fn(usize, usize) -> f32,
    fx: f32,
    fy: f32,
) -> (f32x4, f32x4) {
    let lerp = |a: f32x4, b: f32x4, f: f32x4| a + (b - a) * f;
    let (fx, fy) = (f32x4::splat(fx), f32x4::splat(fy));
    let mut color = f32x4::ZERO;
    let mut heights = f32x4::ZERO;
    if COLOR {
        let (t00, t10, t01, t11) = (at(1, 1), at(1, 2), at(2, 1), at(2, 2));
        let top = lerp(f32x4::from(t00), f32x4::from(t10), fx);
        let bottom = lerp(f32x4::from(t01), f32x4::from(t11), fx);
        color = lerp(top, bottom, fy);
    }
    if GRADIENT {
        let hh = height;
        let (h00, h10, h01, h11) = (hh(1, 1), hh(1, 2), hh(2, 1), hh(2, 2));
        // Corner k of the east, west, north and south quads.
        let c00 = f32x4::new([h10, hh(1, 0), h01, hh(0, 1)]);
        let c10 = f32x4::new([hh(1, 3), h00, h11, hh(0, 2)]);
        let c01 = f32x4::new([h11, hh(2, 0), hh(3, 1), h00]);
        let c11 = f32x4::new([hh(2, 3), h01, hh(3, 2), h10]);
        heights = lerp(lerp(c00, c10, fx), lerp(c01, c11, fx), fy);
    }
    (color, heights)
}

/// Eight lanes of four values each, as four registers of eight lanes.
#[inline(always)]
fn channels(lanes: &[f32x4; LANES]) -> [f32x8; 4] {
    let lo = f32x4::transpose([lanes[0], lanes[1], lanes[2], lanes[3]]);
    let hi = f32x4::transpose([lanes[4], lanes[5], lanes[6], lanes[7]]);
    std::array::from_fn(|c| {
        let (a, b) = (lo[c].to_array(), hi[c].to_array());
        f32x8::new([a[0], a[1], a[2], a[3], b[0], b[1], b[2], b[3]])
    })
}
