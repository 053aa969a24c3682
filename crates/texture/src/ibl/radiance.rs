//! The environment's radiance as octahedral levels from `BASE`² texels
//! down to one, each texel the mean of four of the level above: what
//! sampled specular light (`--ibl-specular sampled`, docs/shading.md,
//! "Image-based light") reads, at a level chosen from each sample's
//! density ("filtered importance sampling", Křivánek and Colbert 2008),
//! so a few samples of a rough lobe read the environment already averaged
//! over their share of it instead of aliasing single texels. A direction to
//! a texel costs no trigonometry, and a texel's solid angle is a cube of
//! the direction's L1 norm (`texel_solid_angle`). Made once per
//! environment, only when the setting asks for it
//! (`Environment::radiance_levels`).

use glam::Vec3;

use super::prefilter::{OctMap, oct_uv};
use super::source::Source;

/// Side of the sharpest level: about 0.8° a texel, the detail of a
/// 512-wide source at the equator (whose texels shrink toward the poles).
pub const BASE: usize = 256;

/// The levels, `BASE`² first, each half the side of the one before.
pub struct RadianceLevels {
    levels: Vec<OctMap>,
}

impl std::fmt::Debug for RadianceLevels {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("RadianceLevels")
            .field("levels", &self.levels.len())
            .finish()
    }
}

impl RadianceLevels {
    /// The levels of `source`: the sharpest read from it bilinearly at each
    /// texel's centre direction, the others boxed down 2 × 2.
    pub fn new(source: &Source) -> RadianceLevels {
        let mut levels = vec![OctMap::from_fn(BASE, |d| source.lookup(d))];
        while let Some(above) = levels.last().filter(|l| l.size > 1) {
            let (n, size) = (above.size, above.size / 2);
            let at = |x: usize, y: usize| above.texels[y * n + x];
            let mut texels = Vec::with_capacity(size * size);
            for y in 0..size {
                for x in 0..size {
                    let (x2, y2) = (2 * x, 2 * y);
                    let sum = at(x2, y2) + at(x2 + 1, y2) + at(x2, y2 + 1) + at(x2 + 1, y2 + 1);
                    texels.push(sum * 0.25);
                }
            }
            levels.push(OctMap { size, texels });
        }
        RadianceLevels { levels }
    }

    /// The solid angle of a texel of the sharpest level at the octahedron's
    /// vertices (±X, ±Y, ±Z), 4/BASE²: the map's square is 2 × 2 in the
    /// octahedron's coordinates p = d/|d|₁, and a unit of p's area covers
    /// |d|₁³ steradians at unit direction d (1 at a vertex, 3√3 at a face's
    /// centre, π on average), so a texel at d covers this times |d|₁³.
    pub fn texel_solid_angle(&self) -> f32 {
        4.0 / (BASE * BASE) as f32
    }

    /// How many levels there are (log₂ BASE + 1).
    pub fn count(&self) -> usize {
        self.levels.len()
    }

    /// Level `i` (0: the sharpest).
    pub fn level(&self, i: usize) -> &OctMap {
        &self.levels[i]
    }

    /// The radiance around unit direction `d` at level of detail `lod`
    /// (0: the sharpest; clamped to the levels there are): bilinear in the
    /// two levels around it, mixed linearly.
    #[inline]
    pub fn read(&self, d: Vec3, lod: f32) -> Vec3 {
        let last = self.levels.len() - 1;
        let x = lod.clamp(0.0, last as f32);
        let i = (x as usize).min(last);
        let t = x - i as f32;
        let uv = oct_uv(d);
        let here = self.levels[i].read_seamless(uv);
        if t > 0.0 && i < last {
            here.lerp(self.levels[i + 1].read_seamless(uv), t)
        } else {
            here
        }
    }
}
