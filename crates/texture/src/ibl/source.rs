//! The environment as the image-based light reads it: linear radiance in
//! an equirectangular grid of at most `MAX_SOURCE` texels, boxed down
//! from the picture (`texture::environment` conventions).

use std::f32::consts::PI;

use glam::{Vec2, Vec3};

use crate::Level;
use crate::lat_long::{direction, lat_long};

/// The largest grid kept (0.7° a texel): finer detail than this is lost
/// in every level but the mirror's, which shows it at 128² anyway.
pub const MAX_SOURCE: (usize, usize) = (512, 256);
/// The brightest radiance kept (half-float's largest): sums of a few
/// thousand texels stay finite in f32.
const MAX_RADIANCE: f32 = 65504.0;

/// Linear radiance on a latitude–longitude grid, top row first.
pub struct Source {
    pub width: usize,
    pub height: usize,
    pub texels: Vec<Vec3>,
}

/// An sRGB-encoded value as linear light (the exact curve).
fn srgb_decode(x: f32) -> f32 {
    if x <= 0.040_45 {
        x / 12.92
    } else {
        ((x + 0.055) / 1.055).powf(2.4)
    }
}

impl Source {
    /// `level` boxed down to at most `MAX_SOURCE`; texels stored as f32
    /// (Radiance, OpenEXR, built-in) are linear already, others (8 and 16
    /// bits) are decoded from sRGB. NaN and negative values read as 0.
    pub fn of(level: &Level) -> Source {
        let linear = level.texels.is_f32();
        let (w, h) = (level.width.max(1), level.height.max(1));
        let to = (w.min(MAX_SOURCE.0), h.min(MAX_SOURCE.1));
        Source::boxed(w, h, to, |i| {
            let t = level.texels.at(i);
            let c = Vec3::new(t[0], t[1], t[2]);
            let c = if linear { c } else { c.map(srgb_decode) };
            c.map(|x| if x > 0.0 { x.min(MAX_RADIANCE) } else { 0.0 })
        })
    }

    /// This grid boxed down to `to` (each side no larger than this one's).
    pub fn shrunk(&self, to: (usize, usize)) -> Source {
        let to = (to.0.min(self.width), to.1.min(self.height));
        Source::boxed(self.width, self.height, to, |i| self.texels[i])
    }

    /// The mean of the `w × h` texels `at` falling in each cell of `to`.
    fn boxed(w: usize, h: usize, to: (usize, usize), at: impl Fn(usize) -> Vec3) -> Source {
        let (tw, th) = (to.0.max(1), to.1.max(1));
        let mut sums = vec![Vec3::ZERO; tw * th];
        let mut counts = vec![0u32; tw * th];
        for y in 0..h {
            let ty = y * th / h;
            for x in 0..w {
                let cell = ty * tw + x * tw / w;
                sums[cell] += at(y * w + x);
                counts[cell] += 1;
            }
        }
        let texels = sums
            .iter()
            .zip(&counts)
            .map(|(s, &n)| *s / n.max(1) as f32)
            .collect();
        Source {
            width: tw,
            height: th,
            texels,
        }
    }

    /// Each texel's centre direction, solid angle and radiance. The solid
    /// angles are scaled to sum to exactly 4π.
    pub fn texels_with_solid_angles(&self) -> Vec<(Vec3, f32, Vec3)> {
        let (w, h) = (self.width, self.height);
        let mut out = Vec::with_capacity(w * h);
        for (y, d_omega) in self.row_solid_angles().into_iter().enumerate() {
            for x in 0..w {
                let uv = Vec2::new((x as f32 + 0.5) / w as f32, (y as f32 + 0.5) / h as f32);
                out.push((direction(uv), d_omega, self.texels[y * w + x]));
            }
        }
        out
    }

    /// The solid angle of a texel of each row, sin θ·Δθ·Δφ, scaled so
    /// that the texels' sum to exactly 4π.
    pub fn row_solid_angles(&self) -> Vec<f32> {
        let (w, h) = (self.width, self.height);
        let row_angle = |y: usize| {
            let theta = (y as f32 + 0.5) / h as f32 * PI;
            theta.sin() * (2.0 * PI / w as f32) * (PI / h as f32)
        };
        let total: f32 = (0..h).map(|y| row_angle(y) * w as f32).sum();
        let scale = 4.0 * PI / total;
        (0..h).map(|y| row_angle(y) * scale).collect()
    }

    /// The radiance in direction `d`, bilinear between texel centres
    /// (columns wrap, rows clamp), as `Environment::lookup` reads.
    pub fn lookup(&self, d: Vec3) -> Vec3 {
        let (w, h) = (self.width, self.height);
        let uv = lat_long(d);
        let x = uv.x * w as f32 - 0.5;
        let y = (uv.y * h as f32 - 0.5).clamp(0.0, (h - 1) as f32);
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let col = |c: f32| (c as i64).rem_euclid(w as i64) as usize;
        let (c0, c1) = (col(x0), col(x0 + 1.0));
        let (r0, r1) = (y0 as usize, (y0 as usize + 1).min(h - 1));
        let at = |r: usize, c: usize| self.texels[r * w + c];
        let top = at(r0, c0).lerp(at(r0, c1), fx);
        let bottom = at(r1, c0).lerp(at(r1, c1), fx);
        top.lerp(bottom, fy)
    }
}
