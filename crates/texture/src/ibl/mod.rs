//! Image-based light (docs/shading.md, "Image-based light"): what the
//! metallic-roughness kernel reads of an environment, computed once per
//! environment and kept with it (`Environment::light`): its diffuse light
//! as nine spherical-harmonic coefficients (`sh`), its specular light
//! prefiltered by roughness into levels (`prefilter`), and the split-sum
//! table shared by every environment (`shade::split_sum`).

pub mod irradiance;
pub mod prefilter;
pub mod radiance;
pub mod sh;
pub mod source;

use glam::Vec3;
use wide::{f32x8, i32x8};

use crate::Level;
use prefilter::{LEVELS, OctMap, oct_uv_lanes};
use source::Source;

/// An environment's light, ready for the kernel.
pub struct Ibl {
    /// Irradiance over π as SH coefficients (`sh::irradiance` reads them).
    pub sh: [Vec3; 9],
    /// The prefiltered levels, roughness 0 to 1.
    levels: Vec<OctMap>,
}

impl std::fmt::Debug for Ibl {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Ibl")
            .field("levels", &self.levels.len())
            .finish()
    }
}

impl Ibl {
    /// The light of the equirectangular picture `level`.
    pub fn new(level: &Level) -> Ibl {
        let source = Source::of(level);
        Ibl {
            sh: sh::project(&source),
            levels: prefilter::prefilter(&source),
        }
    }

    /// The prefiltered radiance around unit direction `r` for `roughness`
    /// (0..=1): the two nearest levels, mixed linearly. (The first lane of
    /// [`Ibl::specular_lanes`].)
    #[inline]
    pub fn specular(&self, r: Vec3, roughness: f32) -> Vec3 {
        let r = [f32x8::splat(r.x), f32x8::splat(r.y), f32x8::splat(r.z)];
        let [x, y, z] = self.specular_lanes(r, f32x8::splat(roughness), 1);
        Vec3::new(x.as_array()[0], y.as_array()[0], z.as_array()[0])
    }

    /// [`Ibl::specular`] of eight unit directions and roughnesses, in the
    /// lanes whose bit is set in `live` (0 in the others). A roughness
    /// outside 0..=1 is clamped to it (a NaN to 0). The lanes of one level
    /// pair are read together: usually one pair for all.
    #[inline(always)]
    pub fn specular_lanes(&self, r: [f32x8; 3], roughness: f32x8, live: u32) -> [f32x8; 3] {
        let x = roughness.max(f32x8::ZERO).min(f32x8::ONE) * f32x8::splat((LEVELS - 1) as f32);
        let i = x.trunc_int().min(i32x8::splat(LEVELS as i32 - 2));
        let t = x - f32x8::from_i32x8(i);
        let uv = oct_uv_lanes(r);
        let levels = i.to_array();
        let mut out = [f32x8::ZERO; 3];
        let mut todo = live & 0xff;
        while todo != 0 {
            let level = levels[todo.trailing_zeros() as usize];
            let lanes = (0..8)
                .filter(|&l| todo & (1 << l) != 0 && levels[l] == level)
                .fold(0, |m, l| m | 1 << l);
            todo &= !lanes;
            let level = level as usize;
            let a = self.levels[level].read_lanes(uv, lanes);
            let b = self.levels[level + 1].read_lanes(uv, lanes);
            // glam's `lerp`, a·(1 − t) + b·t, selected into these lanes.
            let mask = f32x8::from(std::array::from_fn::<f32, 8, _>(|l| {
                if lanes & (1 << l) != 0 {
                    f32::from_bits(!0)
                } else {
                    0.0
                }
            }));
            for k in 0..3 {
                let mixed = a[k] * (f32x8::ONE - t) + b[k] * t;
                out[k] = mask.select(mixed, out[k]);
            }
        }
        out
    }

    /// Every level's texels (for tests).
    pub fn level_texels(&self) -> impl Iterator<Item = &Vec3> {
        self.levels.iter().flat_map(|l| l.texels.iter())
    }
}

#[cfg(test)]
mod tests;
