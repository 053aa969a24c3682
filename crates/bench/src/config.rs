//! Which settings the bench measures.
//!
//! Not the full cross product: one axis at a time is varied away from the
//! reference setting (Phong, vertex normals, bilinear texture, Blinn bump),
//! plus a few combinations people actually pick. Axes are enumerated from the
//! `Settings` enums, so a technique, filter or AA level added there gets its
//! row without touching this file.

use clap::ValueEnum;
use glam::Vec3;

use relief_core::settings::{
    AntiAlias, Filter, HeightDerivative, LightVector, Settings, Shading, Technique,
};
use relief_options::{Bench, OPTIONS, OptId};
use relief_scene::Scene;
use relief_texture::normal_map_file::{FileNormalMap, decode_level, encode_rgb8};
use relief_texture::sample::normal_map::normal_map_scale;
use relief_texture::{Level, NormalMap};

/// How many threads a row renders with.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Threads {
    /// A pool of one thread.
    One,
    /// A pool of the bench's thread count (`--threads`, default: every core).
    All,
}

/// The scene a row draws.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum SceneVariant {
    /// The reference cube.
    #[default]
    Reference,
    /// The same cube flagged as not convex, so the plan keeps the depth buffer
    /// it otherwise skips: same image, and the row shows what skipping saves.
    ForcedDepth,
    /// The cube with a normal map file: its texture's own dot3 normal map
    /// at the reference strength, through 8-bit RGB as a file holds it
    /// (`--normal-map`), so the row shows what reading a file costs and
    /// what 8 bits lose.
    NormalMapFile,
    /// A model view's materials drawn as the reference scenes draw them
    /// (their metallic-roughness terms dropped): Blinn-Phong against the
    /// physical truth.
    BlinnPhong,
    /// A model view without its environment (no ambient light): the
    /// lights alone, against the truth lit by them alone.
    NoEnvironment,
    /// A model view's first object skinned to two joints
    /// (`skinned::skinned`): its pictures are the rest pose's, and the
    /// timed frames pose it at a new instant each.
    Skinned,
}

impl SceneVariant {
    pub fn apply(self, scene: &Scene) -> Scene {
        let mut scene = scene.clone();
        match self {
            SceneVariant::Reference => {}
            SceneVariant::ForcedDepth => {
                for object in &mut scene.objects {
                    object.mesh.convex = false;
                }
            }
            SceneVariant::NormalMapFile => {
                scene.material.normal_map = Some(std::sync::Arc::new(eight_bit_normal_map(&scene)));
            }
            SceneVariant::BlinnPhong => {
                for terms in scene.object_terms.iter_mut().flatten() {
                    let mut t = (**terms).clone();
                    t.pbr = None;
                    *terms = std::sync::Arc::new(t);
                }
            }
            SceneVariant::NoEnvironment => scene.ambient = Vec3::ZERO,
            SceneVariant::Skinned => scene = super::skinned::skinned(&scene),
        }
        scene
    }

    pub fn label(self) -> &'static str {
        match self {
            SceneVariant::Reference => "reference",
            SceneVariant::ForcedDepth => "forced-depth",
            SceneVariant::NormalMapFile => "normal-map-file",
            SceneVariant::BlinnPhong => "blinn-phong",
            SceneVariant::NoEnvironment => "no-environment",
            SceneVariant::Skinned => "skinned",
        }
    }
}

/// The scene texture's dot3 normal map at the reference strength, written
/// to 8-bit RGB and read back as a normal-map file is.
fn eight_bit_normal_map(scene: &Scene) -> FileNormalMap {
    let texture = &scene.material.texture;
    let derived = NormalMap::build(
        texture.base(),
        normal_map_scale(relief_core::settings::DEFAULT_BUMP_STRENGTH),
    );
    let rgba: Vec<u8> = encode_rgb8(&derived)
        .chunks_exact(3)
        .flat_map(|c| [c[0], c[1], c[2], 255])
        .collect();
    let level = Level::from_rgba8_top_down(derived.width, derived.height, &rgba);
    FileNormalMap::new("8-bit normal map", decode_level(&level))
}

/// One row of the table.
#[derive(Clone, Debug, PartialEq)]
pub struct Config {
    /// What differs from the reference setting, in the command line's spelling
    /// (`filter=nearest`), or `reference setting`.
    pub name: String,
    pub settings: Settings,
    pub threads: Threads,
    pub variant: SceneVariant,
}

impl Config {
    pub fn new(name: impl Into<String>, settings: Settings, threads: Threads) -> Self {
        Config {
            name: name.into(),
            settings,
            threads,
            variant: SceneVariant::Reference,
        }
    }
}

/// The command-line spelling of an enum value (`nearest`, `2x2`, `pom`).
pub fn value_name<E: ValueEnum>(value: E) -> String {
    value
        .to_possible_value()
        .map(|v| v.get_name().to_string())
        .unwrap_or_else(|| "?".into())
}

/// The setting every row starts from: Phong, vertex normals, bilinear texture,
/// Blinn bump with the filtered derivative, no AA.
pub fn reference_setting() -> Settings {
    Settings::default()
}

/// The settings of the reference image (before its supersampling): per-pixel
/// lighting, the finest filter and the filtered derivative.
pub fn reference_image_setting() -> Settings {
    Settings {
        shading: Shading::Phong,
        filter: Filter::Anisotropic,
        height_derivative: HeightDerivative::Filtered,
        light_vector: LightVector::Pixel,
        aa: AntiAlias::Off,
        ..reference_setting()
    }
}

/// Every variant of `E` but `skip`, each applied to the reference setting by `apply`.
fn axis<E: ValueEnum + PartialEq + Copy>(
    key: &str,
    skip: E,
    apply: impl Fn(&mut Settings, E),
) -> Vec<Config> {
    E::value_variants()
        .iter()
        .filter(|&&v| v != skip)
        .map(|&v| {
            let mut s = reference_setting();
            apply(&mut s, v);
            Config::new(format!("{key}={}", value_name(v)), s, Threads::All)
        })
        .collect()
}

/// Flat lighting, no texture, no bump: the cheapest frame.
fn flat_untextured() -> Settings {
    Settings {
        shading: Shading::Flat,
        texture: false,
        bump: false,
        ..reference_setting()
    }
}

/// The rows of a full run.
pub fn full() -> Vec<Config> {
    let r = reference_setting();
    let mut rows = vec![
        Config::new("reference setting", r, Threads::All),
        Config::new("reference setting, 1 thread", r, Threads::One),
    ];
    // The options' rows (their entries' `bench`), in the order the
    // README's row numbers cite; an option not placed here gets its rows
    // at the end.
    let mut placed = Vec::new();
    let mut option = |id: OptId| {
        placed.push(id);
        option_rows(id)
    };
    rows.extend(option(OptId::Shading));
    rows.extend(option(OptId::Normals));
    rows.extend(option(OptId::Texture));
    rows.extend(option(OptId::Filter));
    rows.extend(option(OptId::Bump));
    rows.extend(option(OptId::Specular));
    rows.extend(option(OptId::Technique));
    rows.extend(option(OptId::HeightDerivative));
    // The light vector only matters to dot3: measured there, against dot3's default.
    rows.extend(
        axis("light-vector", r.light_vector, |s, v: LightVector| {
            s.technique = Technique::Dot3;
            s.light_vector = v
        })
        .into_iter()
        .map(|c| Config {
            name: format!("technique=dot3, {}", c.name),
            ..c
        }),
    );
    rows.extend(option(OptId::Aa));
    // Work the plan leaves out: lights, and the depth buffer a convex cube does not need.
    rows.extend(option(OptId::Lights));
    rows.push(Config {
        variant: SceneVariant::ForcedDepth,
        ..Config::new("depth buffer forced", r, Threads::All)
    });
    // A few combinations.
    rows.push(Config::new(
        "flat, no texture, no bump",
        flat_untextured(),
        Threads::All,
    ));
    rows.push(Config::new(
        "flat, no texture, no bump, 1 thread",
        flat_untextured(),
        Threads::One,
    ));
    rows.push(Config::new(
        "Gouraud, nearest, no bump",
        Settings {
            shading: Shading::Gouraud,
            filter: Filter::Nearest,
            bump: false,
            ..r
        },
        Threads::All,
    ));
    // Emboss and dot3 read the footprint's mip level with trilinear filtering.
    rows.push(Config::new(
        "emboss, trilinear",
        Settings {
            technique: Technique::Emboss,
            filter: Filter::Trilinear,
            ..r
        },
        Threads::All,
    ));
    rows.push(Config::new(
        "dot3, trilinear",
        Settings {
            technique: Technique::Dot3,
            filter: Filter::Trilinear,
            ..r
        },
        Threads::All,
    ));
    // The closest a frame at the target size gets to the reference image.
    rows.push(Config::new(
        "filter=anisotropic, aa=4x4",
        Settings {
            aa: AntiAlias::Ssaa4,
            ..reference_image_setting()
        },
        Threads::All,
    ));
    // Dot3 reading a normal map file instead of deriving one (last, so the
    // rows above keep their numbers).
    rows.push(Config {
        variant: SceneVariant::NormalMapFile,
        ..Config::new(
            "dot3, normal map file (8-bit)",
            Settings {
                technique: Technique::Dot3,
                normal_map_file: true,
                ..r
            },
            Threads::All,
        )
    });
    // The debug overlay: what drawing the tangent frames adds (last, so
    // the row numbers the README cites stay valid).
    rows.extend(option(OptId::TangentFrames));
    rows.extend(option(OptId::Environment));
    // New options: after every row above, so their numbers stay.
    for opt in OPTIONS {
        if !placed.contains(&opt.id) {
            rows.extend(option_rows(opt.id));
        }
    }
    rows
}

/// The rows of option `id` ([`Bench`] of its entry): each value but
/// the default applied to the reference setting.
fn option_rows(id: OptId) -> Vec<Config> {
    let opt = relief_options::get(id);
    let r = reference_setting();
    let away = opt.all_values().into_iter().filter(|&v| v != opt.get(&r));
    let row = |v, name: String| {
        let mut s = r;
        opt.set(&mut s, v);
        Config::new(name, s, Threads::All)
    };
    match opt.bench {
        Bench::None => Vec::new(),
        Bench::Axis(column) => away
            .map(|v| row(v, format!("{column}={}", opt.spell(v))))
            .collect(),
        Bench::Row(label) => away.map(|v| row(v, label.to_string())).collect(),
    }
}

/// The rows of `--quick`: enough to see the table work, and the two speed goals.
pub fn quick() -> Vec<Config> {
    let r = reference_setting();
    vec![
        Config::new("reference setting", r, Threads::All),
        Config::new("reference setting, 1 thread", r, Threads::One),
        Config::new("bump=off", Settings { bump: false, ..r }, Threads::All),
        Config::new(
            "filter=nearest",
            Settings {
                filter: Filter::Nearest,
                ..r
            },
            Threads::All,
        ),
        Config::new("flat, no texture, no bump", flat_untextured(), Threads::All),
    ]
}

/// Seed of the orientations: the same views on every run and machine.
pub const SEED: u64 = 0x5EED_CAFE;

/// `n` model rotations (degrees about X, Y, Z) drawn from a fixed-seed
/// SplitMix64 stream; the first is the reference scene's own rotation.
pub fn orientations(n: usize, seed: u64) -> Vec<Vec3> {
    let mut state = seed;
    let mut next = move || {
        state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        // 24 random bits → [0, 360).
        (z >> 40) as f32 / (1u64 << 24) as f32 * 360.0
    };
    let mut out = Vec::with_capacity(n);
    if n > 0 {
        out.push(relief_core::settings::DEFAULT_ROTATION);
    }
    while out.len() < n {
        out.push(Vec3::new(next(), next(), next()));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use relief_core::settings::Normals;
    use std::collections::HashSet;

    fn check_well_formed(rows: &[Config]) {
        assert!(!rows.is_empty());
        let names: HashSet<&str> = rows.iter().map(|c| c.name.as_str()).collect();
        assert_eq!(names.len(), rows.len(), "row names are unique");
        // No two rows measure the same thing.
        for (i, a) in rows.iter().enumerate() {
            for b in &rows[i + 1..] {
                assert!(
                    a.settings != b.settings || a.threads != b.threads || a.variant != b.variant,
                    "{} and {} are the same row",
                    a.name,
                    b.name
                );
            }
            assert!(a.name.chars().all(|c| !c.is_control()));
        }
        assert_eq!(rows[0].name, "reference setting");
        assert_eq!(rows[0].settings, reference_setting());
    }

    #[test]
    fn full_list_is_well_formed_and_covers_every_axis_value() {
        let rows = full();
        check_well_formed(&rows);
        let has = |f: &dyn Fn(&Config) -> bool| rows.iter().any(f);
        for &v in Shading::value_variants() {
            assert!(has(&|c| c.settings.shading == v), "{v:?}");
        }
        for &v in Normals::value_variants() {
            assert!(has(&|c| c.settings.normals == v), "{v:?}");
        }
        for &v in Filter::value_variants() {
            assert!(
                has(&|c| c.settings.texture && c.settings.filter == v),
                "{v:?}"
            );
        }
        assert!(has(&|c| c.settings.specular), "specular");
        assert!(has(&|c| c.settings.tangent_frames), "tangent frames");
        assert!(has(&|c| c.settings.environment), "environment");
        for &v in Technique::value_variants() {
            assert!(
                has(&|c| c.settings.bump && c.settings.technique == v),
                "{v:?}"
            );
        }
        for &v in HeightDerivative::value_variants() {
            assert!(
                has(&|c| c.settings.bump && c.settings.height_derivative == v),
                "{v:?}"
            );
        }
        for &v in LightVector::value_variants() {
            assert!(
                has(&|c| c.settings.technique == Technique::Dot3 && c.settings.light_vector == v),
                "{v:?}"
            );
        }
        for &v in AntiAlias::value_variants() {
            assert!(has(&|c| c.settings.aa == v), "{v:?}");
        }
        assert!(has(&|c| !c.settings.texture));
        assert!(has(&|c| !c.settings.bump));
        assert!(has(&|c| c.threads == Threads::One));
        assert!(has(&|c| c.variant == SceneVariant::ForcedDepth));
        assert!(has(&|c| !c.settings.lights));
        assert!(has(&|c| c.variant == SceneVariant::NormalMapFile
            && c.settings.normal_map_file
            && c.settings.technique == Technique::Dot3));
        // Single-axis rows differ from the reference setting in the named axis only.
        let one = rows.iter().find(|c| c.name == "filter=nearest").unwrap();
        assert_eq!(
            one.settings,
            Settings {
                filter: Filter::Nearest,
                ..reference_setting()
            }
        );
    }

    #[test]
    fn quick_list_is_well_formed_and_short() {
        let rows = quick();
        check_well_formed(&rows);
        assert!(rows.len() <= 6);
        assert!(rows.len() < full().len());
    }

    #[test]
    fn forced_depth_changes_only_the_convex_flag() {
        let scene = Scene::cube(
            std::sync::Arc::new(relief_texture::decode::procedural::brick()),
            true,
        );
        let forced = SceneVariant::ForcedDepth.apply(&scene);
        assert!(scene.objects.iter().all(|o| o.mesh.convex));
        assert!(forced.objects.iter().all(|o| !o.mesh.convex));
        assert_eq!(
            forced.objects[0].mesh.vertices,
            scene.objects[0].mesh.vertices
        );
        assert!(SceneVariant::Reference.apply(&scene).objects[0].mesh.convex);
    }

    #[test]
    fn the_normal_map_file_row_reads_an_8_bit_copy_of_the_derived_map() {
        let scene = Scene::cube(
            std::sync::Arc::new(relief_texture::decode::procedural::brick()),
            false,
        );
        let with_file = SceneVariant::NormalMapFile.apply(&scene);
        let file = with_file.material.normal_map.as_ref().unwrap();
        let derived = NormalMap::build(
            scene.material.texture.base(),
            normal_map_scale(relief_core::settings::DEFAULT_BUMP_STRENGTH),
        );
        let worst = file
            .given()
            .normals
            .iter()
            .zip(&derived.normals)
            .flat_map(|(a, b)| (0..3).map(move |c| (a[c] - b[c]).abs()))
            .fold(0.0f32, f32::max);
        assert!(worst > 0.0 && worst <= 0.006, "{worst}");
        assert!(scene.material.normal_map.is_none());
    }

    #[test]
    fn orientations_are_fixed_and_in_range() {
        let a = orientations(8, SEED);
        assert_eq!(a, orientations(8, SEED));
        assert_ne!(a, orientations(8, SEED + 1));
        assert_eq!(a[0], relief_core::settings::DEFAULT_ROTATION);
        assert_eq!(a.len(), 8);
        for r in &a[1..] {
            assert!(r.to_array().iter().all(|d| (0.0..360.0).contains(d)));
        }
        assert!(orientations(0, SEED).is_empty());
    }
}
