//! Every user-visible rendering choice, in one plain `Copy` struct.
//!
//! The command line, the interactive app and the benchmark all build a
//! `Settings`; the renderer only reads it. Most fields are options of the
//! option table (`crates/options/src/table.rs`), which makes their flags and
//! keys; a key cycles an enum's values in declaration order. Enums derive
//! `ValueEnum` so clap spells them exactly as the README does.

use clap::ValueEnum;
use glam::Vec3;

/// How lighting is evaluated (key `m` cycles the values in this order).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, ValueEnum)]
pub enum Shading {
    /// Lighting once per facet, at its centre.
    Flat,
    /// Lighting at the vertices, interpolated across the triangle.
    Gouraud,
    /// Normals interpolated, lighting per pixel (the only mode that shows bump).
    #[default]
    Phong,
}

impl Shading {
    pub fn label(self) -> &'static str {
        match self {
            Shading::Flat => "flat",
            Shading::Gouraud => "Gouraud",
            Shading::Phong => "Phong",
        }
    }
}

/// Which normals feed Gouraud and Phong (key `n`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, ValueEnum)]
pub enum Normals {
    /// Averaged corner normals: the cube looks rounded.
    #[default]
    Vertex,
    /// The facet's own normal: hard edges.
    Face,
}

impl Normals {
    pub fn label(self) -> &'static str {
        match self {
            Normals::Vertex => "vertex",
            Normals::Face => "face",
        }
    }
}

/// Texture filter.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, ValueEnum)]
pub enum Filter {
    Nearest,
    #[default]
    Bilinear,
    /// Bilinear on the one nearest mip level (GL's LINEAR_MIPMAP_NEAREST).
    NearestMip,
    /// Bilinear on the two nearest mip levels, blended.
    Trilinear,
    /// Several trilinear taps along the major axis of the pixel footprint.
    Anisotropic,
}

impl Filter {
    pub fn label(self) -> &'static str {
        match self {
            Filter::Nearest => "nearest",
            Filter::Bilinear => "bilinear",
            Filter::NearestMip => "nearest-mip",
            Filter::Trilinear => "trilinear",
            Filter::Anisotropic => "anisotropic",
        }
    }
    /// True when the filter reads a mip chain (and so needs UV derivatives).
    pub fn uses_mips(self) -> bool {
        matches!(
            self,
            Filter::NearestMip | Filter::Trilinear | Filter::Anisotropic
        )
    }
}

/// Bump-mapping technique.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, ValueEnum)]
pub enum Technique {
    /// Blinn's perturbed normal (the documented software renderer).
    #[default]
    Blinn,
    /// Height map shifted toward the light and subtracted.
    Emboss,
    /// Normal map dotted with the light vector in tangent space.
    Dot3,
    /// UV offset along the view direction.
    Parallax,
    /// Parallax occlusion mapping: ray-march the height field.
    Pom,
}

impl Technique {
    pub fn label(self) -> &'static str {
        match self {
            Technique::Blinn => "Blinn",
            Technique::Emboss => "emboss",
            Technique::Dot3 => "dot3",
            Technique::Parallax => "parallax",
            Technique::Pom => "POM",
        }
    }
}

/// How the bump stage differentiates the height map.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, ValueEnum)]
pub enum HeightDerivative {
    /// The documented code: nearest texel, neighbours clamped at the border.
    Texel,
    /// Central difference of filtered (bilinear) heights one texel apart: smooth when magnified.
    #[default]
    Filtered,
}

impl HeightDerivative {
    pub fn label(self) -> &'static str {
        match self {
            HeightDerivative::Texel => "texel",
            HeightDerivative::Filtered => "filtered",
        }
    }
}

/// Where dot3 normalises the tangent-space light vector.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, ValueEnum)]
pub enum LightVector {
    /// Computed per vertex and interpolated (shortens between vertices).
    Vertex,
    /// Recomputed and normalised per pixel.
    #[default]
    Pixel,
}

impl LightVector {
    pub fn label(self) -> &'static str {
        match self {
            LightVector::Vertex => "L per vertex",
            LightVector::Pixel => "L per pixel",
        }
    }
}

/// Anti-aliasing.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, ValueEnum)]
pub enum AntiAlias {
    #[default]
    Off,
    /// Supersampling, 2×2 samples per pixel.
    #[value(name = "2x2")]
    Ssaa2,
    /// Supersampling, 4×4 samples per pixel.
    #[value(name = "4x4")]
    Ssaa4,
    /// Four coverage samples, shaded once per pixel.
    Msaa4,
}

impl AntiAlias {
    pub fn label(self) -> &'static str {
        match self {
            AntiAlias::Off => "off",
            AntiAlias::Ssaa2 => "SSAA 2x2",
            AntiAlias::Ssaa4 => "SSAA 4x4",
            AntiAlias::Msaa4 => "MSAA 4",
        }
    }
}

/// Largest supersampled frame, in samples: beyond it the factor drops (to
/// 2×2, then off) instead of allocating gigabytes.
pub const MAX_SUPERSAMPLES: usize = 1 << 24;

/// The supersampling factor k for a frame of `width × height`: 1 for no
/// supersampling, or when even 2×2 would exceed [`MAX_SUPERSAMPLES`].
pub fn ssaa_factor(aa: AntiAlias, width: usize, height: usize) -> usize {
    let wanted = match aa {
        AntiAlias::Ssaa2 => 2,
        AntiAlias::Ssaa4 => 4,
        AntiAlias::Off | AntiAlias::Msaa4 => 1,
    };
    let mut k = wanted;
    while k > 1 && width.saturating_mul(height).saturating_mul(k * k) > MAX_SUPERSAMPLES {
        k /= 2;
    }
    k
}

/// How primitives are drawn.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, ValueEnum)]
pub enum Display {
    Points,
    Lines,
    #[default]
    Fill,
}

impl Display {
    pub fn label(self) -> &'static str {
        match self {
            Display::Points => "points",
            Display::Lines => "lines",
            Display::Fill => "fill",
        }
    }
}

/// Everything that decides what a frame looks like, apart from the scene's data.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settings {
    pub shading: Shading,
    pub normals: Normals,
    /// Key `t`.
    pub texture: bool,
    /// Key `c`: per-vertex colours; off means a white material.
    pub colors: bool,
    /// Key `b`: visible in Phong only.
    pub bump: bool,
    /// Blinn's k; the reference scene uses 0.006.
    pub bump_strength: f32,
    pub technique: Technique,
    pub filter: Filter,
    pub height_derivative: HeightDerivative,
    pub light_vector: LightVector,
    pub aa: AntiAlias,
    pub display: Display,
    /// All lights on or off (ambient stays).
    pub lights: bool,
    /// Distance attenuation of point lights.
    pub attenuation: bool,
    /// Key `g`: Blinn-Phong highlights (docs/specular.md); off keeps the
    /// documented picture.
    pub specular: bool,
    /// Blinn-Phong exponent s of (N·H)^s (keys `y`, `Y`): higher, smaller highlights.
    pub shininess: f32,
    /// Key `E`: reflection of the environment (docs/environment.md), Phong only.
    pub environment: bool,
    /// k of c = (1 − k)·lit + k·env(R), in 0..=1.
    pub reflectivity: f32,
    /// Model rotation in degrees about X, then Y, then Z.
    pub rotation: Vec3,
    /// Key `N`: dot3 reads the normal map loaded from a file
    /// (`--normal-map`) instead of the one derived from the height map;
    /// without a file loaded it changes nothing.
    pub normal_map_file: bool,
    /// Key `F`: the tangent frames (T, B, N) drawn at the vertices.
    pub tangent_frames: bool,
    /// Vertical field of view of the camera in degrees (keys `w`, `W`);
    /// the reference view's is 60.
    pub fov: f32,
    /// Key `U`, `--up`: the model's axis that points up (Z for CAD files).
    pub up: UpAxis,
    /// `--tone-map`: how physically shaded light (a model's glTF
    /// materials) is brought into the picture's range.
    pub tone_map: ToneMap,
    /// `--exposure`: multiplies physically shaded light before the tone map.
    pub exposure: f32,
    /// Key `J`, `--environment-turn`: the model view's environment turned
    /// about the vertical axis, in degrees (0 ≤ turn < 360).
    pub environment_turn: f32,
    /// Key `B`, `--backdrop`: the model view's environment drawn behind the
    /// model instead of the plain background (off: fewer bytes over a
    /// slow link, and the silhouette stands out).
    pub backdrop: bool,
    /// `--ibl-diffuse`: how the model view's environment lights glTF
    /// materials diffusely (docs/shading.md, "Image-based light").
    pub ibl_diffuse: IblDiffuse,
    /// `--ibl-specular`: how the model view's environment is reflected by
    /// glTF materials (docs/shading.md, "Image-based light").
    pub ibl_specular: IblSpecular,
}

/// The tone map of physically shaded pixels (docs/shading.md,
/// "Metallic-roughness").
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, ValueEnum)]
pub enum ToneMap {
    /// Khronos PBR Neutral: colours kept up to 0.76, brighter ones rolled off to white.
    #[default]
    PbrNeutral,
    /// ACES filmic (Narkowicz's fit): more contrast, highlights rolled off.
    Aces,
    /// None: linear light clamped at white.
    None,
}

/// The diffuse part of the image-based light (docs/shading.md,
/// "Image-based light").
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, ValueEnum)]
pub enum IblDiffuse {
    /// Nine spherical-harmonic coefficients: 27 multiply-adds a pixel, within a few per cent.
    #[default]
    Sh,
    /// An irradiance map integrated exactly over the environment's texels, read bilinearly.
    Integrated,
}

/// The specular part of the image-based light (docs/shading.md,
/// "Image-based light").
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, ValueEnum)]
pub enum IblSpecular {
    /// Levels prefiltered by roughness and the split-sum table: two map reads a pixel.
    #[default]
    Prefiltered,
    /// 32 samples of the GGX lobe a pixel, each read at a level of its own footprint.
    Sampled,
}

/// The model axis drawn upwards (docs/models.md, "Camera").
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, ValueEnum)]
pub enum UpAxis {
    /// +Y up, as glTF, OBJ and the built-in models have it.
    #[default]
    Y,
    /// +Z up (most CAD and 3D-printing files): turned −90° about X first.
    Z,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            shading: Shading::Phong,
            normals: Normals::Vertex,
            texture: true,
            colors: true,
            bump: true,
            bump_strength: DEFAULT_BUMP_STRENGTH,
            technique: Technique::Blinn,
            filter: Filter::Bilinear,
            height_derivative: HeightDerivative::Filtered,
            light_vector: LightVector::Pixel,
            aa: AntiAlias::Off,
            display: Display::Fill,
            lights: true,
            attenuation: false,
            specular: false,
            shininess: DEFAULT_SHININESS,
            environment: false,
            reflectivity: DEFAULT_REFLECTIVITY,
            rotation: DEFAULT_ROTATION,
            normal_map_file: false,
            tangent_frames: false,
            fov: DEFAULT_FOV,
            up: UpAxis::Y,
            tone_map: ToneMap::PbrNeutral,
            exposure: 1.0,
            environment_turn: 0.0,
            backdrop: false,
            ibl_diffuse: IblDiffuse::Sh,
            ibl_specular: IblSpecular::Prefiltered,
        }
    }
}

/// Blinn bump strength of the reference scene.
pub const DEFAULT_BUMP_STRENGTH: f32 = 0.006;
/// `+` and `-` multiply or divide the bump strength by this.
pub const BUMP_FACTOR: f32 = 1.25;
/// Strongest bump `+` reaches.
pub const BUMP_MAX: f32 = 1.0;
/// Below this `-` goes to 0 (no bump); from 0, `+` starts here.
pub const BUMP_MIN: f32 = 0.0005;
/// Blinn-Phong exponent when none is given.
pub const DEFAULT_SHININESS: f32 = 32.0;
/// The range keys `y` and `Y` keep the exponent in (each press doubles or halves it).
pub const SHININESS_RANGE: (f32, f32) = (1.0, 1024.0);
/// Share of the environment in a reflecting pixel when none is given.
pub const DEFAULT_REFLECTIVITY: f32 = 0.35;
/// Vertical field of view of the reference camera, in degrees.
pub const DEFAULT_FOV: f32 = 60.0;
/// The field of view `--fov` and keys `w`, `W` keep to, in degrees.
pub const FOV_RANGE: (f32, f32) = (10.0, 120.0);
/// Model rotation of the reference scene, in degrees.
pub const DEFAULT_ROTATION: Vec3 = Vec3::new(25.0, 35.0, 0.0);

/// Brings an angle in degrees into [0, 360) in f64, so 1e9° loses no precision
/// in f32 and NaN or infinity become 0.
pub fn normalize_degrees(deg: f32) -> f32 {
    if !deg.is_finite() {
        return 0.0;
    }
    let r = (deg as f64).rem_euclid(360.0);
    // rem_euclid can round up to exactly 360.0 for tiny negative inputs.
    if r >= 360.0 { 0.0 } else { r as f32 }
}
