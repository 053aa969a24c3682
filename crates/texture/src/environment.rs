//! Environments for reflection mapping (docs/environment.md): a picture of
//! everything around the scene, stored as a latitude–longitude
//! (equirectangular) image and read by direction.
//!
//! Conventions, in world space (the camera at +Z looking down −Z, +Y up):
//! u = 1/2 + atan2(x, −z) / 2π, so the direction the camera looks (−Z) is
//! the middle of the picture, +X three quarters across and +Z (behind the
//! camera) the left and right edges, which meet at the seam;
//! v = acos(y) / π, so the top row is straight up (+Y) and the bottom row
//! straight down. Reads are bilinear, wrapping across the seam and clamped
//! at the poles.

use std::f32::consts::{PI, TAU};
use std::path::Path;
use std::sync::{Arc, OnceLock};

use glam::{Vec2, Vec3};

use super::ibl::Ibl;
use super::ibl::irradiance;
use super::ibl::prefilter::OctMap;
use super::ibl::radiance::RadianceLevels;
use super::ibl::source::Source;
use super::lat_long::{direction, lat_long};
use super::studio::{STUDIO_SIZE, studio};
use super::{Level, Range, Texture, TextureError, load_picture};

/// A latitude–longitude environment: RGB read by direction.
#[derive(Debug)]
pub struct Environment {
    /// The picture (its base level; the height channel is unused). Loaded
    /// pictures hold their memory budget here.
    texture: Texture,
    /// Its image-based light, computed on first use (`texture::ibl`).
    light: OnceLock<Ibl>,
    /// Its exact irradiance map (`--ibl-diffuse integrated`), computed on
    /// first use.
    irradiance: OnceLock<OctMap>,
    /// Its radiance as octahedral levels (`--ibl-specular sampled`),
    /// computed on first use.
    radiance: OnceLock<RadianceLevels>,
}

impl PartialEq for Environment {
    fn eq(&self, other: &Self) -> bool {
        std::ptr::eq(self, other)
            || (self.texture.name == other.texture.name
                && self.texture.base() == other.texture.base())
    }
}

/// Width and height of the procedural sky's picture (about 0.7° a texel).
const SKY_SIZE: (usize, usize) = (512, 256);

impl Environment {
    /// The texture's base level read as an equirectangular picture.
    pub fn from_texture(texture: Texture) -> Environment {
        Environment {
            texture,
            light: OnceLock::new(),
            irradiance: OnceLock::new(),
            radiance: OnceLock::new(),
        }
    }

    /// The picture at `path` (any format the texture loader reads, within
    /// its size limits and memory budget) as an equirectangular environment:
    /// a float picture's radiance as the file has it (a texture's would be
    /// clamped to 1, and an HDR environment's sun and windows with it).
    pub fn load(path: &Path) -> Result<Environment, TextureError> {
        Ok(Environment::from_texture(load_picture(
            path,
            Range::Radiance,
        )?))
    }

    /// `--environment-map`: the picture at `path` when one is given.
    pub fn load_optional(path: Option<&Path>) -> Result<Option<Arc<Environment>>, TextureError> {
        path.map(|p| Environment::load(p).map(Arc::new)).transpose()
    }

    /// A `width × height` environment whose texel centres take `colour` of
    /// their direction (tests build their own environments with it).
    pub fn from_fn(
        name: &str,
        width: usize,
        height: usize,
        colour: impl Fn(Vec3) -> Vec3,
    ) -> Environment {
        let (width, height) = (width.max(1), height.max(1));
        let mut texels = Vec::with_capacity(width * height);
        for y in 0..height {
            for x in 0..width {
                let u = (x as f32 + 0.5) / width as f32;
                let v = (y as f32 + 0.5) / height as f32;
                let c = colour(direction(Vec2::new(u, v)));
                texels.push([c.x, c.y, c.z, 0.0]);
            }
        }
        Environment::from_texture(Texture::new(
            name,
            Level {
                wrap: Default::default(),
                width,
                height,
                texels: texels.into(),
            },
        ))
    }

    /// The built-in environment, made once and shared: see [`sky`].
    pub fn sky() -> Arc<Environment> {
        static SKY: OnceLock<Arc<Environment>> = OnceLock::new();
        SKY.get_or_init(|| Arc::new(Environment::from_fn("sky", SKY_SIZE.0, SKY_SIZE.1, sky)))
            .clone()
    }

    /// The built-in studio, made once and shared: the model view's light
    /// when no map is given (see [`studio`]).
    pub fn studio() -> Arc<Environment> {
        static STUDIO: OnceLock<Arc<Environment>> = OnceLock::new();
        STUDIO
            .get_or_init(|| {
                let (w, h) = STUDIO_SIZE;
                Arc::new(Environment::from_fn("studio", w, h, studio))
            })
            .clone()
    }

    /// Its image-based light: computed on the first call (a few tens of
    /// milliseconds), then kept with the environment.
    pub fn light(&self) -> &Ibl {
        self.light.get_or_init(|| Ibl::new(self.texture.base()))
    }

    /// Its irradiance map (`texture::ibl::irradiance`): E(N)/π summed
    /// over every texel, computed on the first call (tens of milliseconds),
    /// then kept with the environment.
    pub fn irradiance_map(&self) -> &OctMap {
        self.irradiance
            .get_or_init(|| irradiance::integrate(&Source::of(self.texture.base())))
    }

    /// Its radiance as octahedral levels for sampled reads
    /// (`texture::ibl::radiance`), computed on the first call (a few
    /// milliseconds), then kept with the environment.
    pub fn radiance_levels(&self) -> &RadianceLevels {
        self.radiance
            .get_or_init(|| RadianceLevels::new(&Source::of(self.texture.base())))
    }

    pub fn name(&self) -> &str {
        &self.texture.name
    }

    /// The picture's texels (for readers other than `lookup`, such as the
    /// bench's ray-cast truth).
    pub fn picture(&self) -> &crate::Level {
        self.texture.base()
    }

    /// Size of the picture in texels.
    pub fn size(&self) -> (usize, usize) {
        (self.texture.width(), self.texture.height())
    }

    /// The colour seen in direction `d` (any length): bilinear between the
    /// four nearest texel centres, wrapping across the seam, clamped at the
    /// poles. A zero or non-finite direction reads the front (−Z).
    #[inline]
    pub fn lookup(&self, d: Vec3) -> Vec3 {
        let level = self.texture.base();
        let (w, h) = (level.width, level.height);
        let uv = lat_long(d);
        // Texel-space positions, shifted by one so they are ≥ 0.5 and a
        // truncation is floor + 1 (no libm floor, no division to wrap).
        let x = uv.x * w as f32 + 0.5;
        let y = uv.y * h as f32 + 0.5;
        let (xi, yi) = ((x as usize).min(w), (y as usize).min(h));
        let (fx, fy) = (x - xi as f32, y - yi as f32);
        // Columns xi − 1 and xi, wrapped; rows yi − 1 and yi, clamped.
        let c0 = if xi == 0 { w - 1 } else { xi - 1 };
        let c1 = if xi == w { 0 } else { xi };
        let (r0, r1) = (yi.saturating_sub(1), yi.min(h - 1));
        let at = |r: usize, c: usize| {
            let t = level.texels.at(r * w + c);
            Vec3::new(t[0], t[1], t[2])
        };
        let top = at(r0, c0) * (1.0 - fx) + at(r0, c1) * fx;
        let bottom = at(r1, c0) * (1.0 - fx) + at(r1, c1) * fx;
        top * (1.0 - fy) + bottom * fy
    }
}

/// Where the built-in sun is: above, behind and to the right of the
/// reference camera, so the faces turned toward the camera can mirror it.
pub const SUN: Vec3 = Vec3::new(0.45, 0.55, 0.7);

/// The built-in environment: a sky darkening toward the zenith with a sun,
/// six coloured hills around the horizon (one per 60° of azimuth, so a
/// turn of the model shows as a change of colour) and a chequered ground
/// fading into haze, so bumps show as wobbles in straight lines.
pub fn sky(d: Vec3) -> Vec3 {
    let d = d.normalize_or(Vec3::NEG_Z);
    let haze = Vec3::new(0.78, 0.84, 0.92);
    let azimuth = d.x.atan2(-d.z) / TAU + 0.5;
    if d.y >= 0.0 {
        let zenith = Vec3::new(0.12, 0.3, 0.75);
        let mut c = haze.lerp(zenith, d.y.sqrt());
        // Hills: a band whose height rises and falls with the azimuth.
        let sector = (azimuth * 6.0).floor();
        let within = azimuth * 6.0 - sector;
        let hill = 0.05 + 0.12 * (within * PI).sin();
        if d.y < hill {
            c = HILLS[(sector as usize) % HILLS.len()] * (0.7 + 0.3 * d.y / hill);
        }
        let sun = SUN.normalize();
        let cos = d.dot(sun);
        let glow = cos.max(0.0).powi(64) * 0.5;
        let disk = if cos > 0.995 { 1.0 } else { 0.0 };
        c + Vec3::new(1.0, 0.9, 0.6) * (glow + disk)
    } else {
        // The ground one unit below: squares of side 1/2.
        let t = 1.0 / -d.y;
        let (gx, gz) = (d.x * t * 2.0, d.z * t * 2.0);
        let odd = ((gx.floor() + gz.floor()) as i64).rem_euclid(2) == 1;
        let ground = if odd {
            Vec3::new(0.2, 0.22, 0.18)
        } else {
            Vec3::new(0.55, 0.5, 0.4)
        };
        // Far squares are smaller than a texel: fade them into the haze.
        ground.lerp(haze * 0.8, (d.y * 8.0).exp())
    }
}

/// The hills' colours, from the seam (+Z, behind the camera) eastward.
const HILLS: [Vec3; 6] = [
    Vec3::new(0.8, 0.2, 0.2),
    Vec3::new(0.85, 0.55, 0.15),
    Vec3::new(0.25, 0.65, 0.25),
    Vec3::new(0.2, 0.6, 0.7),
    Vec3::new(0.3, 0.3, 0.85),
    Vec3::new(0.7, 0.3, 0.7),
];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lat_long_and_direction_are_inverse() {
        for &(u, v) in &[(0.5, 0.5), (0.1, 0.3), (0.9, 0.8), (0.75, 0.5)] {
            let uv = lat_long(direction(Vec2::new(u, v)));
            assert!((uv - Vec2::new(u, v)).length() < 1e-5, "{u},{v}: {uv}");
        }
    }

    #[test]
    fn sky_is_finite_everywhere() {
        let env = Environment::sky();
        assert_eq!(env.size(), SKY_SIZE);
        for d in [Vec3::Y, Vec3::NEG_Y, Vec3::Z, Vec3::NEG_Z, SUN, Vec3::ZERO] {
            assert!(env.lookup(d).is_finite(), "{d}");
        }
    }
}
