//! The dot3 normal map: tangent-space unit normals derived from the height
//! map (docs/bump-dot3.md).
//!
//! One derivation serves colour and grey images alike, since the height is
//! the alpha channel (or the mean of R, G, B when an image has none).
//!
//! Minified reads go through a mip chain of the map, built the first time a
//! minified pixel asks for it: each level is the area-weighted mean of the
//! finer one's vectors, *not* renormalised, so a level holds the mean unit
//! normal of the base texels it covers. Where the relief is rough at the
//! pixel's scale that mean is short, and N·L with it is the mean of the
//! texels' N·L (what supersampling integrates) instead of a renormalised,
//! too bright, single direction.

use std::sync::OnceLock;

use glam::Vec2;

use super::level::Level;
use super::level::{downsample_from, neighbourhood};
use super::texels::{Fetch, MipKind, Xyz16s, Xyz32s, to_snorm16};
use super::wrap::Wrap;
use crate::with_fetch;

/// A map's unit normals: f32 for maps derived from f32 textures (their
/// pictures unchanged), three signed 16-bit channels otherwise (6 bytes a
/// texel instead of 12; a step of 1/32767 in each component).
#[derive(Clone, Debug, PartialEq)]
pub enum Normals {
    F32(Vec<[f32; 3]>),
    Snorm16(Vec<[i16; 3]>),
}

impl Normals {
    /// Snorm16 normals from `n` f32 ones.
    pub fn snorm16(n: usize, normal: impl Fn(usize) -> [f32; 3]) -> Normals {
        Normals::Snorm16((0..n).map(|i| normal(i).map(to_snorm16)).collect())
    }

    pub fn len(&self) -> usize {
        match self {
            Normals::F32(v) => v.len(),
            Normals::Snorm16(v) => v.len(),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Bytes one normal takes in this storage.
    pub fn bytes_per_texel(&self) -> usize {
        match self {
            Normals::F32(_) => 12,
            Normals::Snorm16(_) => 6,
        }
    }

    /// Normal `i` as floats.
    #[inline]
    pub fn at(&self, i: usize) -> [f32; 3] {
        match self {
            Normals::F32(v) => v[i],
            Normals::Snorm16(v) => {
                let t = Xyz16s(v).at(i);
                [t[0], t[1], t[2]]
            }
        }
    }

    /// Every normal as floats, in storage order.
    pub fn iter(&self) -> impl Iterator<Item = [f32; 3]> + '_ {
        (0..self.len()).map(move |i| self.at(i))
    }

    /// Normals like these (same storage) from `n` f32 ones.
    pub(crate) fn like(&self, n: usize, normal: impl Fn(usize) -> [f32; 3]) -> Normals {
        match self {
            Normals::F32(_) => Normals::F32((0..n).map(normal).collect()),
            Normals::Snorm16(_) => Normals::snorm16(n, normal),
        }
    }
}

impl From<Vec<[f32; 3]>> for Normals {
    fn from(v: Vec<[f32; 3]>) -> Self {
        Normals::F32(v)
    }
}

/// Equal when every normal reads the same (whatever the storage).
impl PartialEq<Vec<[f32; 3]>> for Normals {
    fn eq(&self, other: &Vec<[f32; 3]>) -> bool {
        self.len() == other.len() && self.iter().zip(other).all(|(a, b)| a == *b)
    }
}

impl<'a> IntoIterator for &'a Normals {
    type Item = [f32; 3];
    type IntoIter = Box<dyn Iterator<Item = [f32; 3]> + 'a>;
    fn into_iter(self) -> Self::IntoIter {
        Box::new(self.iter())
    }
}

/// |∂P/∂u| of the reference cube's faces: the normal map's slope scale is
/// Blinn's k times this, so both techniques show the same relief there.
pub const REFERENCE_TANGENT_LENGTH: f32 = 2.0;

/// The normal map's slope scale for bump strength `k`.
pub fn normal_map_scale(k: f32) -> f32 {
    k * REFERENCE_TANGENT_LENGTH
}

/// Unit normals in tangent space (x along +u, y along +v, z out of the
/// surface), one per texel, in the same order as `Level`.
#[derive(Clone, Debug)]
pub struct NormalMap {
    pub width: usize,
    pub height: usize,
    /// The slope scale the map was built with (see [`NormalMap::build`]).
    pub scale: f32,
    pub normals: Normals,
    /// How coordinates outside 0..1 read it (a model's sampler; repeat
    /// otherwise).
    pub wrap: Wrap,
    /// Levels 1.. (x, y, z in the first three channels, the fourth 0),
    /// built on the first minified read; same sizes as the texture's chain.
    mips: OnceLock<Vec<Level>>,
}

/// Equal when the base maps are: the chain is a cache derived from them.
impl PartialEq for NormalMap {
    fn eq(&self, other: &Self) -> bool {
        self.width == other.width
            && self.height == other.height
            && self.scale.to_bits() == other.scale.to_bits()
            && self.normals == other.normals
            && self.wrap == other.wrap
    }
}

impl NormalMap {
    /// n = normalize(−s·∂F/∂u, −s·∂F/∂v, 1), with ∂F/∂u, ∂F/∂v the central
    /// difference one texel either side (wrapped, as the texture repeats), per
    /// unit of texture coordinate: at texel centres the same derivative as the
    /// filtered Blinn gradient. `scale` is s; a non-finite or negative scale
    /// counts as 0 (a flat map). The normals are f32 when the level is,
    /// 16-bit otherwise.
    pub fn build(level: &Level, scale: f32) -> NormalMap {
        let s = NormalMap::effective_scale(scale);
        let (w, h) = (level.width, level.height);
        let normals = with_fetch!(&level.texels, t => {
            let normal = |(x, y): (usize, usize)| {
                // Neighbours wrapped, as the texture repeats.
                let (xp, xn) = ((x + w - 1) % w, (x + 1) % w);
                let (yp, yn) = ((y + h - 1) % h, (y + 1) % h);
                let fu = (t.height(y * w + xn) - t.height(y * w + xp)) * 0.5 * w as f32;
                let fv = (t.height(yn * w + x) - t.height(yp * w + x)) * 0.5 * h as f32;
                let (nx, ny, nz) = (-s * fu, -s * fv, 1.0f32);
                let len = (nx * nx + ny * ny + nz * nz).sqrt();
                [nx / len, ny / len, nz / len]
            };
            let texels = (0..h).flat_map(|y| (0..w).map(move |x| (x, y))).map(normal);
            if level.texels.is_f32() {
                Normals::F32(texels.collect())
            } else {
                Normals::Snorm16(texels.map(|n| n.map(to_snorm16)).collect())
            }
        });
        NormalMap {
            width: w,
            height: h,
            scale: s,
            normals,
            wrap: Wrap::REPEAT,
            mips: OnceLock::new(),
        }
    }

    /// A map of given unit normals (a normal-map file's, see
    /// [`crate::normal_map_file`]); `scale` records how much its tilt was
    /// scaled (1: as given).
    pub fn from_normals(
        width: usize,
        height: usize,
        scale: f32,
        normals: impl Into<Normals>,
    ) -> NormalMap {
        let normals = normals.into();
        assert_eq!(normals.len(), width * height, "one normal per texel");
        NormalMap {
            width,
            height,
            scale,
            normals,
            wrap: Wrap::REPEAT,
            mips: OnceLock::new(),
        }
    }

    /// The map read with these wrap modes (before its chain is built).
    pub fn with_wrap(mut self, wrap: Wrap) -> Self {
        self.wrap = wrap;
        self.mips = OnceLock::new();
        self
    }

    /// True once the mip chain has been built (tests use it to show that
    /// nothing builds it while no pixel is minified).
    pub fn mips_built(&self) -> bool {
        self.mips.get().is_some()
    }

    /// Levels 1.. of the map's mip chain, built once on first call by the
    /// texture's own downsampling rule (area-weighted means): the vectors
    /// are averaged as they are, never renormalised.
    pub fn mip_levels(&self) -> &[Level] {
        self.mips.get_or_init(|| {
            let (w, h) = (self.width, self.height);
            if w <= 1 && h <= 1 {
                return Vec::new();
            }
            let first = match &self.normals {
                Normals::F32(v) => downsample_from(Xyz32s(v), w, h, MipKind::F32),
                Normals::Snorm16(v) => downsample_from(Xyz16s(v), w, h, MipKind::Xyz16),
            };
            let first = first.with_wrap(self.wrap);
            let rest = first.build_chain();
            std::iter::once(first).chain(rest).collect()
        })
    }

    /// Level `i` of the map read bilinearly at `uv` (0: the base map; past
    /// the end of the chain, the smallest level).
    #[inline]
    pub fn level_bilinear(&self, i: usize, uv: Vec2) -> [f32; 3] {
        let chain = if i == 0 { &[][..] } else { self.mip_levels() };
        match chain.get((i.wrapping_sub(1)).min(chain.len().wrapping_sub(1))) {
            Some(level) => {
                let t = level.bilinear(uv.x, uv.y);
                [t[0], t[1], t[2]]
            }
            None => self.bilinear(uv.x, uv.y),
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
        let (cols, rows, fx, fy) = neighbourhood(&self.wrap, self.width, self.height, u, v);
        let quad = [
            rows[1] + cols[1],
            rows[1] + cols[2],
            rows[2] + cols[1],
            rows[2] + cols[2],
        ];
        self.blend(quad, fx, fy)
    }

    /// The normals at storage indices `quad` (top left, top right, bottom
    /// left, bottom right) blended by the fractions.
    #[inline]
    fn blend(&self, quad: [usize; 4], fx: f32, fy: f32) -> [f32; 3] {
        // Written out, not `quad.map`: that was left a call per pixel.
        let [t00, t10, t01, t11] = match &self.normals {
            Normals::F32(v) => [v[quad[0]], v[quad[1]], v[quad[2]], v[quad[3]]],
            Normals::Snorm16(v) => {
                let at = |i: usize| {
                    let t = Xyz16s(v).at(i);
                    [t[0], t[1], t[2]]
                };
                [at(quad[0]), at(quad[1]), at(quad[2]), at(quad[3])]
            }
        };
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
                level.texels.as_mut_slice()[y * n + x][3] = x as f32 / n as f32;
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
                .all(|n| n == [0.0, 0.0, 1.0] || n == [-0.0, -0.0, 1.0])
        );
        assert_eq!(map.bilinear(0.37, 0.91)[2], 1.0);
    }

    #[test]
    fn rising_u_tilts_toward_minus_u_like_blinn() {
        // F = x/n: ∂F/∂u = 1 per unit of u away from the wrap seam.
        let map = NormalMap::build(&ramp_u(16), 0.5);
        let n = map.normals.at(5 * 16 + 7);
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
