//! The built-in textures, drawn by code. `relief assets` writes them to
//! `assets/`; a test checks that the shipped files match this code.

use super::Texture;

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
