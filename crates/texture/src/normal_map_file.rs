//! Normal maps read from image files: RGB tangent-space normal maps, as
//! painting and baking tools export them (docs/bump-dot3.md, "Normal maps
//! from files"), used by dot3 in place of the map derived from the height map.
//!
//! Channel mapping (the common "OpenGL" convention, green = up the picture):
//! n = 2·rgb − 1, red along +u (the tangent), green along *up the picture*,
//! blue out of the surface. relief's v grows *down* the picture (v = 0 is
//! the top row, see `texture`), so the green axis is −v here:
//! n_relief = (2r − 1, −(2g − 1), 2b − 1). A bump painted or baked by those
//! tools then shows raised, exactly as the height-derived map of the same
//! relief does.
//!
//! Pixels go through the texture loader (any format it reads, its limits,
//! its memory budget and its panic containment), keep 16 bits of precision
//! when the file has them, and are renormalised; a texel too short to have a
//! direction becomes (0, 0, 1).

use std::path::Path;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};

use glam::Vec3;

use super::{Level, NormalMap, Texture, TextureError, load_texture};
use crate::decode::load::load_texture_from_bytes;
use crate::sample::normal_map::Normals;
use relief_core::budget::{self, Reservation};
use relief_core::settings::DEFAULT_BUMP_STRENGTH;

/// Bytes per texel a file normal map may hold: the map as given and one copy
/// tilted for another strength, each three signed 16-bit channels (6) with
/// its mip chain (6/3).
pub const BYTES_PER_TEXEL: f64 = 2.0 * (6.0 + 6.0 / 3.0);

/// Texels shorter than this (before renormalising) have no direction.
const MIN_LENGTH: f32 = 1e-4;

/// A normal map read from a file, and the copy tilted for the current bump
/// strength (built on first use, kept until the strength changes).
#[derive(Debug)]
pub struct FileNormalMap {
    /// Where it came from, for the status line (already sanitised).
    pub name: String,
    /// The map as the file gives it (the default strength).
    given: Arc<NormalMap>,
    tilted: Mutex<Option<Arc<NormalMap>>>,
    /// Tilted copies built so far (for the counters and tests).
    builds: AtomicU64,
    _reservation: Option<Reservation>,
}

/// The unit normal an RGB texel (each channel in 0..1) encodes.
pub fn decode_texel(rgb: [f32; 3]) -> [f32; 3] {
    let n = Vec3::new(
        2.0 * rgb[0] - 1.0,
        -(2.0 * rgb[1] - 1.0),
        2.0 * rgb[2] - 1.0,
    );
    let len = n.length();
    if len.is_finite() && len >= MIN_LENGTH {
        (n / len).to_array()
    } else {
        [0.0, 0.0, 1.0]
    }
}

/// The RGB texel (each channel in 0..1) that encodes unit normal `n`:
/// the inverse of [`decode_texel`], for writing normal-map files.
pub fn encode_texel(n: [f32; 3]) -> [f32; 3] {
    let c = |x: f32| ((x + 1.0) * 0.5).clamp(0.0, 1.0);
    [c(n[0]), c(-n[1]), c(n[2])]
}

/// A level's RGB decoded as normals (its fourth channel is ignored), kept
/// as three signed 16-bit channels.
pub fn decode_level(level: &Level) -> NormalMap {
    let normals = Normals::snorm16(level.texels.len(), |i| {
        let t = level.texels.at(i);
        decode_texel([t[0], t[1], t[2]])
    });
    NormalMap::from_normals(level.width, level.height, 1.0, normals).with_wrap(level.wrap)
}

/// A normal map as 8-bit RGB rows, top row first (what a file holds).
pub fn encode_rgb8(map: &NormalMap) -> Vec<u8> {
    map.normals
        .iter()
        .flat_map(|n| encode_texel(n).map(|c| (c * 255.0).round() as u8))
        .collect()
}

/// A normal map as 16-bit RGB rows, top row first.
pub fn encode_rgb16(map: &NormalMap) -> Vec<u16> {
    map.normals
        .iter()
        .flat_map(|n| encode_texel(n).map(|c| (c * 65535.0).round() as u16))
        .collect()
}

/// Reads the normal map at `path`.
pub fn load_normal_map(path: &Path) -> Result<FileNormalMap, TextureError> {
    FileNormalMap::from_texture(load_texture(path)?)
}

/// Like [`load_normal_map`] from bytes in memory (`name` for messages and
/// as the format hint).
pub fn load_normal_map_from_bytes(name: &str, bytes: &[u8]) -> Result<FileNormalMap, TextureError> {
    FileNormalMap::from_texture(load_texture_from_bytes(name, bytes)?)
}

impl FileNormalMap {
    /// The normal map a loaded picture encodes; its memory is reserved
    /// before the picture's own is given back.
    pub fn from_texture(texture: Texture) -> Result<FileNormalMap, TextureError> {
        let (w, h) = (texture.width(), texture.height());
        let bytes = ((w * h) as f64 * BYTES_PER_TEXEL).ceil() as u64;
        let held = budget::reserve(&format!("a {w}x{h} normal map"), bytes).map_err(|e| {
            TextureError::OverBudget {
                file: texture.name.clone(),
                reason: e.to_string(),
            }
        })?;
        let mut map = FileNormalMap::new(texture.name.clone(), decode_level(texture.base()));
        map._reservation = Some(held);
        Ok(map)
    }

    /// A file map of these normals (already unit length), named `name`.
    pub fn new(name: impl Into<String>, map: NormalMap) -> FileNormalMap {
        FileNormalMap {
            name: name.into(),
            given: Arc::new(map),
            tilted: Mutex::new(None),
            builds: AtomicU64::new(0),
            _reservation: None,
        }
    }

    /// The map as the file gives it.
    pub fn given(&self) -> &Arc<NormalMap> {
        &self.given
    }

    /// The map for bump strength `k`: the file's own at the default
    /// strength; otherwise each normal's tilt scaled by k / default
    /// (x and y multiplied, then renormalised), so `+` and `-` deepen and
    /// flatten the file's relief as they do the derived one's. The tilted
    /// copy is built on first use and kept until another strength is asked
    /// for; the flag says whether this call built it.
    pub fn for_strength(&self, k: f32) -> (Arc<NormalMap>, bool) {
        let factor = tilt_factor(k);
        if factor == 1.0 {
            return (Arc::clone(&self.given), false);
        }
        let mut slot = self
            .tilted
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner());
        if let Some(map) = slot.as_ref()
            && map.scale.to_bits() == factor.to_bits()
        {
            return (Arc::clone(map), false);
        }
        let map = Arc::new(tilt(&self.given, factor));
        *slot = Some(Arc::clone(&map));
        self.builds.fetch_add(1, Ordering::Relaxed);
        (map, true)
    }

    /// How many tilted copies this map has built.
    pub fn builds(&self) -> u64 {
        self.builds.load(Ordering::Relaxed)
    }

    pub fn width(&self) -> usize {
        self.given.width
    }

    pub fn height(&self) -> usize {
        self.given.height
    }
}

/// How much strength `k` scales the file's tilt: k over the default; a
/// non-finite or negative strength is flat (0).
pub fn tilt_factor(k: f32) -> f32 {
    let f = k / DEFAULT_BUMP_STRENGTH;
    if f.is_finite() && f > 0.0 { f } else { 0.0 }
}

/// `map` with every normal's x and y scaled by `factor`, renormalised.
pub fn tilt(map: &NormalMap, factor: f32) -> NormalMap {
    let normals = map.normals.like(map.normals.len(), |i| {
        let [x, y, z] = map.normals.at(i);
        let n = Vec3::new(x * factor, y * factor, z);
        let len = n.length();
        if len.is_finite() && len >= MIN_LENGTH {
            (n / len).to_array()
        } else {
            [0.0, 0.0, 1.0]
        }
    });
    NormalMap::from_normals(map.width, map.height, factor, normals).with_wrap(map.wrap)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flat_blue_is_straight_up_and_zero_is_up_too() {
        let n = decode_texel([0.5, 0.5, 1.0]);
        assert_eq!(n, [0.0, 0.0, 1.0]);
        assert_eq!(decode_texel([0.5, 0.5, 0.5]), [0.0, 0.0, 1.0]);
        assert_eq!(decode_texel([f32::NAN, 0.5, 1.0]), [0.0, 0.0, 1.0]);
    }

    #[test]
    fn green_points_up_the_picture_which_is_minus_v() {
        let n = decode_texel([0.5, 1.0, 0.5]);
        assert_eq!(n, [0.0, -1.0, 0.0]);
        let back = encode_texel(n);
        assert_eq!(back, [0.5, 1.0, 0.5]);
    }

    #[test]
    fn decoded_normals_are_unit_length() {
        let n = Vec3::from(decode_texel([0.9, 0.2, 0.6]));
        assert!((n.length() - 1.0).abs() < 1e-6);
    }

    #[test]
    fn default_strength_is_the_file_itself_and_others_are_built_once() {
        let file = FileNormalMap::new(
            "m",
            NormalMap::from_normals(1, 1, 1.0, vec![Vec3::new(0.6, 0.0, 0.8).to_array()]),
        );
        let (given, built) = file.for_strength(DEFAULT_BUMP_STRENGTH);
        assert!(!built && Arc::ptr_eq(&given, file.given()));
        let (double, built) = file.for_strength(2.0 * DEFAULT_BUMP_STRENGTH);
        assert!(built);
        let expected = Vec3::new(1.2, 0.0, 0.8).normalize();
        assert!((Vec3::from(double.normals.at(0)) - expected).length() < 1e-6);
        assert!(!file.for_strength(2.0 * DEFAULT_BUMP_STRENGTH).1);
        assert_eq!(file.builds(), 1);
        let (flat, _) = file.for_strength(f32::NAN);
        assert_eq!(flat.normals.at(0), [0.0, 0.0, 1.0]);
    }
}
