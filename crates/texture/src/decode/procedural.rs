//! The built-in textures, drawn by code. `relief assets` writes them to
//! `assets/`; a test checks that the shipped files match this code.

use crate::Texture;

/// A small integer hash: deterministic noise without a random crate.
fn hash(mut x: u32) -> u32 {
    x ^= x >> 16;
    x = x.wrapping_mul(0x7feb_352d);
    x ^= x >> 15;
    x = x.wrapping_mul(0x846c_a68b);
    x ^ (x >> 16)
}

fn noise(x: usize, y: usize, seed: u32) -> f32 {
    (hash((x as u32).wrapping_mul(73_856_093) ^ (y as u32).wrapping_mul(19_349_663) ^ seed)
        & 0xffff) as f32
        / 65535.0
}

/// 256×256 brick wall, RGBA top row first: the alpha is the height, with
/// bevelled bricks standing out of recessed mortar.
pub fn brick_rgba() -> (usize, usize, Vec<u8>) {
    const SIZE: usize = 256;
    const BRICK_W: usize = 64;
    const BRICK_H: usize = 32;
    const MORTAR: f32 = 3.0;
    const BEVEL: f32 = 5.0;
    let mut rgba = Vec::with_capacity(SIZE * SIZE * 4);
    for y in 0..SIZE {
        let course = y / BRICK_H;
        let offset = if course % 2 == 1 { BRICK_W / 2 } else { 0 };
        for x in 0..SIZE {
            let xs = (x + offset) % SIZE;
            let column = xs / BRICK_W;
            // Distance (in texels) from this texel's centre to the nearest joint.
            let fx = (xs % BRICK_W) as f32 + 0.5;
            let fy = (y % BRICK_H) as f32 + 0.5;
            let edge = fx.min(BRICK_W as f32 - fx).min(fy).min(BRICK_H as f32 - fy);
            let inside = ((edge - MORTAR) / BEVEL).clamp(0.0, 1.0);
            // Smoothstep bevel, plus a little grain on the brick faces.
            let bevel = inside * inside * (3.0 - 2.0 * inside);
            let grain = noise(x, y, 7) * 0.08;
            let height = if edge <= MORTAR {
                0.1 + grain * 0.5
            } else {
                0.1 + 0.8 * bevel + grain
            };
            let id = hash((course * 97 + column) as u32 * 31 + 5);
            let tint = (id & 0xff) as f32 / 255.0;
            let speck = noise(x, y, 11) * 0.1 - 0.05;
            let (r, g, b) = if edge <= MORTAR {
                let m = 0.78 + speck;
                (m, m - 0.03, m - 0.08)
            } else {
                (
                    0.62 + 0.22 * tint + speck,
                    0.24 + 0.10 * tint + speck * 0.7,
                    0.16 + 0.06 * tint + speck * 0.5,
                )
            };
            for c in [r, g, b, height] {
                rgba.push((c.clamp(0.0, 1.0) * 255.0).round() as u8);
            }
        }
    }
    (SIZE, SIZE, rgba)
}

/// The default texture, straight from the generator.
pub fn brick() -> Texture {
    let (w, h, rgba) = brick_rgba();
    Texture::from_rgba8("brick (built-in)", w, h, &rgba)
}

/// sin(2π·t) from + and × alone, so the generated pictures (and the shipped
/// PNGs checked against them) are the same bits on every platform's libm.
/// Error below 4e-6.
fn sin_turns(t: f32) -> f32 {
    let mut t = t - (t + 0.5).floor(); // −½ ≤ t < ½
    if t > 0.25 {
        t = 0.5 - t;
    } else if t < -0.25 {
        t = -0.5 - t;
    }
    let x = t * std::f32::consts::TAU; // |x| ≤ π/2
    let x2 = x * x;
    x * (1.0 - x2 / 6.0 * (1.0 - x2 / 20.0 * (1.0 - x2 / 42.0 * (1.0 - x2 / 72.0))))
}

/// Smoothstep from 0 at `a` to 1 at `b`.
fn smoothstep(a: f32, b: f32, x: f32) -> f32 {
    let t = ((x - a) / (b - a)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

fn push_rgbh(rgba: &mut Vec<u8>, texel: [f32; 4]) {
    for c in texel {
        rgba.push((c.clamp(0.0, 1.0) * 255.0).round() as u8);
    }
}

/// 256×256 riveted metal tiles, RGBA top row first: 4×4 square plates with
/// bevelled edges in dark grooves, a domed rivet near each plate corner.
pub fn tiles_rgba() -> (usize, usize, Vec<u8>) {
    const SIZE: usize = 256;
    const TILE: usize = 64;
    const GROOVE: f32 = 2.5;
    const BEVEL: f32 = 4.0;
    const RIVET_INSET: f32 = 9.0;
    const RIVET_R: f32 = 4.5;
    let mut rgba = Vec::with_capacity(SIZE * SIZE * 4);
    for y in 0..SIZE {
        for x in 0..SIZE {
            let (tx, ty) = (x / TILE, y / TILE);
            let fx = (x % TILE) as f32 + 0.5;
            let fy = (y % TILE) as f32 + 0.5;
            let edge = fx.min(TILE as f32 - fx).min(fy).min(TILE as f32 - fy);
            let plate = smoothstep(GROOVE, GROOVE + BEVEL, edge);
            // Nearest rivet centre: one per plate corner, inset.
            let rx = if fx < TILE as f32 / 2.0 {
                RIVET_INSET
            } else {
                TILE as f32 - RIVET_INSET
            };
            let ry = if fy < TILE as f32 / 2.0 {
                RIVET_INSET
            } else {
                TILE as f32 - RIVET_INSET
            };
            let d = ((fx - rx).powi(2) + (fy - ry).powi(2)).sqrt() / RIVET_R;
            let dome = if d < 1.0 { (1.0 - d * d).sqrt() } else { 0.0 };
            let grain = noise(x, y, 23) * 0.04;
            let height = 0.15 + 0.45 * plate + 0.35 * dome + grain * plate;
            let tint = (hash((ty * 4 + tx) as u32 * 131 + 9) & 0xff) as f32 / 255.0;
            let brushed = noise(x / 3, y, 29) * 0.06;
            let metal = 0.48 + 0.12 * tint + brushed;
            let (r, g, b) = if dome > 0.0 {
                let shine = 0.62 + 0.3 * dome;
                (shine, shine * 0.95, shine * 0.85)
            } else {
                let groove = 0.12 + 0.88 * plate;
                (
                    metal * groove * 0.92,
                    metal * groove * 0.97,
                    metal * groove * 1.08,
                )
            };
            push_rgbh(&mut rgba, [r, g, b, height]);
        }
    }
    (SIZE, SIZE, rgba)
}

/// 256×256 rippled sand, RGBA top row first: a smooth height field made of
/// sines with whole numbers of periods across the picture (so it tiles),
/// coloured from the height (troughs darker and wetter).
pub fn waves_rgba() -> (usize, usize, Vec<u8>) {
    const SIZE: usize = 256;
    let mut rgba = Vec::with_capacity(SIZE * SIZE * 4);
    for y in 0..SIZE {
        for x in 0..SIZE {
            let (u, v) = (x as f32 / SIZE as f32, y as f32 / SIZE as f32);
            // Ripples along a diagonal, bent by a slow swell.
            let bend = 0.35 * sin_turns(u + 2.0 * v);
            let ripple = sin_turns(6.0 * u + 3.0 * v + 0.3 * bend);
            let swell = sin_turns(u - v) * sin_turns(2.0 * v + 0.25);
            let fine = noise(x, y, 41) * 0.05;
            let h = (0.5 + 0.3 * ripple + 0.15 * swell + fine).clamp(0.0, 1.0);
            let wet = 1.0 - smoothstep(0.2, 0.6, h);
            let r = 0.86 - 0.30 * wet + fine;
            let g = 0.74 - 0.28 * wet + fine;
            let b = 0.52 - 0.18 * wet + fine;
            push_rgbh(&mut rgba, [r, g, b, h]);
        }
    }
    (SIZE, SIZE, rgba)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sin_turns_matches_sin() {
        for i in -2000..2000 {
            let t = i as f32 / 397.0;
            let want = (t * std::f32::consts::TAU).sin();
            assert!((sin_turns(t) - want).abs() < 1e-5, "t = {t}");
        }
    }
}
