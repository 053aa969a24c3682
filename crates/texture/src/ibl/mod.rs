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

use crate::Level;
use prefilter::{LEVELS, OctMap, oct_uv};
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
    /// (0..=1): the two nearest levels, mixed linearly.
    #[inline]
    pub fn specular(&self, r: Vec3, roughness: f32) -> Vec3 {
        let x = roughness.clamp(0.0, 1.0) * (LEVELS - 1) as f32;
        let i = (x as usize).min(LEVELS - 2);
        let t = x - i as f32;
        let uv = oct_uv(r);
        self.levels[i].read(uv).lerp(self.levels[i + 1].read(uv), t)
    }

    /// Every level's texels (for tests).
    pub fn level_texels(&self) -> impl Iterator<Item = &Vec3> {
        self.levels.iter().flat_map(|l| l.texels.iter())
    }
}

#[cfg(test)]
mod tests;
