//! The dot3 normal map: tangent-space unit normals derived from the height
//! map (seeds 000 §1.3.2, 003 "obtention de la carte de normales").
//!
//! One derivation serves colour and grey images alike, since the height is
//! the alpha channel (or the mean of R, G, B when an image has none).

use super::Level;

/// Unit normals in tangent space (x along +u, y along +v, z out of the
/// surface), one per texel, bottom row first like `Level`.
#[derive(Clone, Debug, PartialEq)]
pub struct NormalMap {
    pub width: usize,
    pub height: usize,
    /// The slope scale the map was built with (see [`NormalMap::build`]).
    pub scale: f32,
    pub normals: Vec<[f32; 3]>,
}

impl NormalMap {
    /// n = normalize(−s·∂F/∂u, −s·∂F/∂v, 1), with ∂F/∂u, ∂F/∂v the central
    /// difference one texel either side (wrapped, as the texture repeats), per
    /// unit of texture coordinate: at texel centres the same derivative as the
    /// filtered Blinn gradient. `scale` is s; a non-finite or negative scale
    /// counts as 0 (a flat map).
    pub fn build(level: &Level, scale: f32) -> NormalMap {
        let s = NormalMap::effective_scale(scale);
        let (w, h) = (level.width, level.height);
        let at = |x: i64, y: i64| level.texel(x, y)[3];
        let mut normals = Vec::with_capacity(w * h);
        for y in 0..h as i64 {
            for x in 0..w as i64 {
                let fu = (at(x + 1, y) - at(x - 1, y)) * 0.5 * w as f32;
                let fv = (at(x, y + 1) - at(x, y - 1)) * 0.5 * h as f32;
                let (nx, ny, nz) = (-s * fu, -s * fv, 1.0f32);
                let len = (nx * nx + ny * ny + nz * nz).sqrt();
                normals.push([nx / len, ny / len, nz / len]);
            }
        }
        NormalMap {
            width: w,
            height: h,
            scale: s,
            normals,
        }
    }

    /// The scale a map built for `scale` uses: non-finite or negative is 0.
    pub fn effective_scale(scale: f32) -> f32 {
        if scale.is_finite() && scale > 0.0 {
            scale
        } else {
            0.0
        }
    }

    /// Bilinear fetch between the four texel centres around (u, v), wrapped.
    /// Like a filtered normal-map texture, the result is *not* renormalised:
    /// between texels of different normals it is a little shorter than 1.
    #[inline]
    pub fn bilinear(&self, u: f32, v: f32) -> [f32; 3] {
        let tx = |t: f32, n: usize| {
            if t.is_finite() {
                (t - t.floor()) * n as f32 - 0.5
            } else {
                -0.5
            }
        };
        let (x, y) = (tx(u, self.width), tx(v, self.height));
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let wrap = |i: i64, n: usize| i.rem_euclid(n as i64) as usize;
        let (xi, yi) = (x0 as i64, y0 as i64);
        let xa = wrap(xi, self.width);
        let xb = wrap(xi + 1, self.width);
        let ra = wrap(yi, self.height) * self.width;
        let rb = wrap(yi + 1, self.height) * self.width;
        let (t00, t10) = (self.normals[ra + xa], self.normals[ra + xb]);
        let (t01, t11) = (self.normals[rb + xa], self.normals[rb + xb]);
        let mut out = [0.0; 3];
        for c in 0..3 {
            let top = t00[c] + (t10[c] - t00[c]) * fx;
            let bottom = t01[c] + (t11[c] - t01[c]) * fx;
            out[c] = top + (bottom - top) * fy;
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ramp_u(n: usize) -> Level {
        let mut level = Level::solid(n, n, [0.5; 4]);
        for y in 0..n {
            for x in 0..n {
                level.texels[y * n + x][3] = x as f32 / n as f32;
            }
        }
        level
    }

    #[test]
    fn flat_height_gives_straight_up_normals() {
        let map = NormalMap::build(&Level::solid(8, 4, [0.2, 0.3, 0.4, 0.7]), 0.5);
        assert!(
            map.normals
                .iter()
                .all(|&n| n == [0.0, 0.0, 1.0] || n == [-0.0, -0.0, 1.0])
        );
        assert_eq!(map.bilinear(0.37, 0.91)[2], 1.0);
    }

    #[test]
    fn rising_u_tilts_toward_minus_u_like_blinn() {
        // F = x/n: ∂F/∂u = 1 per unit of u away from the wrap seam.
        let map = NormalMap::build(&ramp_u(16), 0.5);
        let n = map.normals[5 * 16 + 7];
        let expected = glam::Vec3::new(-0.5, 0.0, 1.0).normalize();
        assert!((glam::Vec3::from(n) - expected).length() < 1e-6, "{n:?}");
    }

    #[test]
    fn bad_scale_is_flat_and_every_fetch_is_finite() {
        let map = NormalMap::build(&ramp_u(4), f32::NAN);
        assert_eq!(map.scale, 0.0);
        for uv in [f32::NAN, f32::INFINITY, -1e30, 1e30, -0.0, 1.0] {
            assert!(map.bilinear(uv, 0.3).iter().all(|c| c.is_finite()));
        }
    }
}
