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

use glam::{Vec3, Vec3A};
use wide::{f32x8, i32x8};

use crate::Level;
use prefilter::{Bilinear, LEVELS, LaneColours, OctMap, oct_uv_lanes};
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
        let t = (x - f32x8::from_i32x8(i)).to_array();
        let uv = oct_uv_lanes(r);
        let levels = i.to_array().map(|i| i as usize);
        let size = |step: usize| f32x8::from(levels.map(|i| self.levels[i + step].size as f32));
        let (below, above) = (Bilinear::at(uv, size(0)), Bilinear::at(uv, size(1)));
        let mut out = LaneColours::default();
        for lane in (0..8).filter(|l| live & (1 << l) != 0) {
            let (level, t) = (levels[lane], t[lane]);
            let a = self.levels[level].blend(&below, lane);
            // glam's `lerp`, a·(1 − t) + b·t; at t = 0 that is a, bit for
            // bit (the texels are finite), without reading the next level.
            let mixed = if t == 0.0 {
                a
            } else {
                a.lerp(self.levels[level + 1].blend(&above, lane), t)
            };
            out.set(lane, mixed);
        }
        out.channels()
    }

    /// Every level's texels (for tests).
    pub fn level_texels(&self) -> impl Iterator<Item = &Vec3A> {
        self.levels.iter().flat_map(|l| l.texels.iter())
    }
}

#[cfg(test)]
mod tests;
