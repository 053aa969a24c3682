//! The scene and model choices (`--scene`, `--model`, keys `p` and `o`) and
//! what they build.

use std::f32::consts::FRAC_PI_2;
use std::fmt;
use std::path::{Path, PathBuf};
use std::str::FromStr;
use std::sync::Arc;

use clap::ValueEnum;
use glam::{Mat4, Vec3};

use super::model_file;
use super::{AMBIENT, BACKGROUND, Camera, Material, Mesh, Object, Scene, cube, light, plane};
use super::{sphere, triangle};
use crate::loaded_model::LoadedModel;
use crate::loaded_model::MaterialDesc;
use crate::loaded_model::ModelMaps;
use crate::loaded_model::ModelPart;
use crate::loaded_model::PbrMaps;
use crate::model_error::ObjError;
use crate::terms::{Cutout, MaterialTerms, PbrMaterial};
use relief_core::sanitize::display_path;
use relief_plasma::Plasma;
use relief_texture::Texture;
use relief_texture::normal_map_file::FileNormalMap;

/// Which scene is shown.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, ValueEnum)]
pub enum SceneKind {
    /// One model (`--model`), lit by the reference lights.
    #[default]
    Cube,
    /// The cube over a floor: the strong white light casts its shadow.
    Shadow,
    /// The 2D bump effect (docs/plasma.md), lit from the pointer.
    Plasma,
}

impl SceneKind {
    pub fn next(self) -> Self {
        match self {
            SceneKind::Cube => SceneKind::Shadow,
            SceneKind::Shadow => SceneKind::Plasma,
            SceneKind::Plasma => SceneKind::Cube,
        }
    }
    pub fn label(self) -> &'static str {
        match self {
            SceneKind::Cube => "model",
            SceneKind::Shadow => "shadow",
            SceneKind::Plasma => "plasma",
        }
    }
}

/// Which model the cube scene shows.
#[derive(Clone, Debug, Default, PartialEq, Eq, Hash)]
pub enum ModelChoice {
    Triangle,
    Plane,
    #[default]
    Cube,
    Sphere,
    /// A model file: OBJ (with its MTL), STL, PLY, or glTF 2.0 (`.gltf`, `.glb`).
    File(PathBuf),
}

impl ModelChoice {
    /// The next built-in model (key `o`): triangle → plane → cube → sphere →
    /// triangle; from a model file, the triangle.
    pub fn next(&self) -> Self {
        match self {
            ModelChoice::Triangle => ModelChoice::Plane,
            ModelChoice::Plane => ModelChoice::Cube,
            ModelChoice::Cube => ModelChoice::Sphere,
            ModelChoice::Sphere | ModelChoice::File(_) => ModelChoice::Triangle,
        }
    }

    /// For the status line: the name, or the model file's name (sanitised).
    pub fn label(&self) -> String {
        match self {
            ModelChoice::Triangle => "triangle".into(),
            ModelChoice::Plane => "plane".into(),
            ModelChoice::Cube => "cube".into(),
            ModelChoice::Sphere => "sphere".into(),
            ModelChoice::File(path) => path
                .file_name()
                .map(|n| display_path(Path::new(n)))
                .unwrap_or_else(|| display_path(path)),
        }
    }

    /// The model's mesh (the cube's texture on all faces or front and
    /// back; a file's parts together).
    pub fn mesh(&self, all_faces: bool) -> Result<Mesh, ObjError> {
        Ok(self.load(all_faces)?.merged())
    }

    /// The model with its parts, maps and warnings.
    pub fn load(&self, all_faces: bool) -> Result<LoadedModel, ObjError> {
        let mesh = match self {
            ModelChoice::Triangle => triangle::triangle(),
            ModelChoice::Plane => plane::plane(),
            ModelChoice::Cube => cube::cube(all_faces),
            ModelChoice::Sphere => sphere::sphere(),
            ModelChoice::File(path) => return model_file::load(path),
        };
        Ok(LoadedModel {
            parts: vec![ModelPart {
                mesh,
                material: None,
                own_maps: None,
                opacity_map: None,
                pbr_maps: Default::default(),
            }],
            maps: ModelMaps::default(),
            points: false,
            warnings: Vec::new(),
            z_up: false,
        })
    }
}

impl fmt::Display for ModelChoice {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.label())
    }
}

impl FromStr for ModelChoice {
    type Err = String;

    /// `triangle`, `plane`, `cube`, `sphere` (any case), or a path ending in
    /// a model file's extension (`.obj`, `.stl`, `.ply`, `.gltf`, `.glb`).
    fn from_str(text: &str) -> Result<Self, String> {
        let lower = text.trim().to_ascii_lowercase();
        Ok(match lower.as_str() {
            "triangle" => ModelChoice::Triangle,
            "plane" => ModelChoice::Plane,
            "cube" => ModelChoice::Cube,
            "sphere" => ModelChoice::Sphere,
            _ if model_file::is_model_path(Path::new(&lower)) => {
                ModelChoice::File(PathBuf::from(text))
            }
            _ => {
                return Err(format!(
                    "unknown model '{}': expected triangle, plane, cube, sphere or a file ending in .obj, .stl, .ply, .gltf or .glb",
                    relief_core::sanitize::clean(text)
                ));
            }
        })
    }
}

/// What a scene choice builds: a 3D scene for the renderer, or the 2D effect.
#[derive(Clone, Debug)]
pub enum Built {
    Scene(Box<Scene>),
    Plasma(Plasma),
}

/// Builds the chosen scene. Only `Cube` reads `model`; a file that cannot be
/// loaded is an error (the caller keeps what it had).
pub fn build_scene(
    kind: SceneKind,
    model: &ModelChoice,
    texture: Arc<Texture>,
    all_faces: bool,
) -> Result<Built, ObjError> {
    build_scene_noting(kind, model, texture, all_faces).map(|(built, _)| built)
}

/// [`build_scene`], with the warnings met while loading the model (one
/// line each, safe to print) and whether it is a point cloud. A model whose
/// material has a texture shows it instead of `texture` (docs/models.md).
pub fn build_scene_noting(
    kind: SceneKind,
    model: &ModelChoice,
    texture: Arc<Texture>,
    all_faces: bool,
) -> Result<(Built, LoadedNotes), ObjError> {
    Ok(match kind {
        SceneKind::Cube => match model {
            // glTF keeps its node tree and materials (`scene::gltf`). A
            // file that cannot be opened is said as for every format.
            ModelChoice::File(path) if super::gltf::is_gltf(path) => {
                super::model_io::check_openable(path)?;
                let model = super::gltf::load(path)?;
                let notes = LoadedNotes::of_gltf(&model);
                let scene = Scene::gltf(model, texture).into_model_view();
                let notes = notes.shown_in(&scene);
                (Built::Scene(Box::new(scene)), notes)
            }
            _ => {
                let loaded = model.load(all_faces)?;
                let notes = LoadedNotes::of_parts(&loaded);
                // A model file is shown in the model view; the built-in
                // models keep the reference scene's camera and lights.
                let scene = match model {
                    ModelChoice::File(_) => Scene::loaded_model_view(loaded, texture),
                    _ => Scene::loaded(loaded, texture),
                };
                let notes = notes.shown_in(&scene);
                (Built::Scene(Box::new(scene)), notes)
            }
        },
        SceneKind::Shadow => (
            Built::Scene(Box::new(Scene::shadow(texture, all_faces))),
            LoadedNotes::default(),
        ),
        SceneKind::Plasma => (Built::Plasma(Plasma::new(0)), LoadedNotes::default()),
    })
}

/// What loading a model had to say.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LoadedNotes {
    /// One line each, safe to print.
    pub warnings: Vec<String>,
    /// A point cloud: the points display shows it.
    pub points: bool,
    /// An animated model's clips: each one's name and length in seconds.
    pub clips: Vec<(String, f32)>,
    /// How many cameras of its own the model has (`V` cycles them).
    pub cameras: usize,
    /// How many lights of its own it has (`KHR_lights_punctual`): they
    /// light the model view instead of the neutral rig.
    pub lights: usize,
    /// Every part is shaded physically in the model view
    /// (`Scene::all_physical`).
    pub physical: bool,
    /// What its parts have that the keys act on (`Scene::features`).
    pub features: super::model_view::ModelFeatures,
    /// Which parts can show a texture (`Scene::texture_reach`).
    pub texture_reach: Option<super::model_view::TextureReach>,
    /// The format stands its models Z up (`LoadedModel::z_up`).
    pub z_up: bool,
}

impl LoadedNotes {
    /// What a glTF model's loading noted (before it moves into a scene).
    pub(crate) fn of_gltf(model: &super::gltf::Model) -> Self {
        LoadedNotes {
            warnings: model.warnings.clone(),
            clips: model.clips(),
            cameras: model.cameras.len(),
            lights: model.lights.len(),
            ..LoadedNotes::default()
        }
    }

    /// What an OBJ, STL or PLY model's loading noted.
    pub(crate) fn of_parts(model: &LoadedModel) -> Self {
        LoadedNotes {
            warnings: model.warnings.clone(),
            points: model.points,
            z_up: model.z_up,
            ..LoadedNotes::default()
        }
    }

    /// These notes, with what the scene built of the model shows.
    pub(crate) fn shown_in(self, scene: &Scene) -> Self {
        LoadedNotes {
            physical: scene.all_physical(),
            features: scene.features(),
            texture_reach: scene.texture_reach(),
            ..self
        }
    }
}

/// What an MTL material adds to relief's material: `Ks` tints the
/// highlight, `Ns` (above 0) is its exponent, and an opacity (`d`, or
/// 1 − `Tr`, times `map_d`) below 0.5 cuts the pixel out; in the model
/// view, its metallic-roughness reading (`mtl_pbr`) (docs/models.md).
fn mtl_terms(
    desc: Option<&MaterialDesc>,
    opacity_map: Option<Arc<relief_texture::Level>>,
    pbr_maps: &PbrMaps,
    normal: Option<Arc<FileNormalMap>>,
) -> Option<Arc<MaterialTerms>> {
    let desc = desc?;
    let factor = desc.opacity.filter(|d| d.is_finite()).unwrap_or(1.0);
    let cutout = (opacity_map.is_some() || factor < MTL_CUTOFF).then_some(Cutout {
        factor,
        map: opacity_map,
        cutoff: MTL_CUTOFF,
        blend: false,
        transmission: None,
        tint: Vec3::ONE,
    });
    let terms = MaterialTerms {
        specular_color: desc
            .specular
            .filter(|ks| ks.is_finite())
            .map_or(Vec3::ONE, |ks| ks.max(Vec3::ZERO)),
        shininess: desc.shininess.filter(|ns| ns.is_finite() && *ns > 0.0),
        cutout,
        pbr: Some(mtl_pbr(desc, pbr_maps, normal)),
        ..MaterialTerms::default()
    };
    (terms != MaterialTerms::default()).then(|| Arc::new(terms))
}

/// An MTL material as metallic-roughness: the PBR extension's `Pr`, `Pm`,
/// `map_Pr` and `map_Pm` as they are (a map alone: factor 1; both: their
/// product, as glTF does); a plain Phong material is a dielectric whose
/// roughness is read back from `Ns` as Blender writes it,
/// Ns = 1000·(1 − roughness)², and rough (1) without `Ns`. `Kd` is already
/// the corner colour, `map_Kd` the colour texture, `norm` the normal map.
fn mtl_pbr(desc: &MaterialDesc, maps: &PbrMaps, normal: Option<Arc<FileNormalMap>>) -> PbrMaterial {
    let from_ns = |ns: f32| 1.0 - (ns.clamp(0.0, 1000.0) / 1000.0).sqrt();
    let roughness = match (desc.roughness, &maps.roughness, desc.shininess) {
        (Some(r), _, _) => r,
        (None, Some(_), _) => 1.0,
        (None, None, Some(ns)) if ns.is_finite() => from_ns(ns),
        _ => 1.0,
    };
    let metallic = match (desc.metallic, &maps.metallic) {
        (Some(m), _) => m,
        (None, Some(_)) => 1.0,
        (None, None) => 0.0,
    };
    PbrMaterial {
        metallic,
        roughness,
        roughness_map: maps.roughness.clone().map(|m| (m, 0)),
        metallic_map: maps.metallic.clone().map(|m| (m, 0)),
        normal: normal.map(|n| n.given().clone()),
        ..PbrMaterial::gltf_default()
    }
}

/// MTL opacity below this is not drawn (relief draws no translucency).
const MTL_CUTOFF: f32 = 0.5;

/// Height of the shadow scene's floor (the turning cube reaches √3 ≈ 1.73).
pub const FLOOR_Y: f32 = -1.8;
/// Half the side of the floor: wide enough for the cube's shadow.
pub const FLOOR_HALF: f32 = 6.0;
/// The floor is a grid of this many cells across (flat and Gouraud shading
/// light it per cell or per vertex, so one quad would look wrong).
pub const FLOOR_CELLS: u32 = 12;

/// The floor's colour: a light neutral grey, so the shadow reads clearly.
fn floor_color(_unit: Vec3) -> Vec3 {
    Vec3::new(0.78, 0.76, 0.72)
}

impl Scene {
    /// A loaded model file in the model view (`loaded`, then
    /// `into_model_view`), noting whether the file gave the scene's
    /// material its maps (`ModelView::file_texture`).
    pub fn loaded_model_view(model: LoadedModel, texture: Arc<Texture>) -> Self {
        let maps = &model.maps;
        let file_texture =
            maps.texture.is_some() || maps.specular_map.is_some() || maps.normal_map.is_some();
        let mut scene = Scene::loaded(model, texture).into_model_view();
        if let Some(view) = &mut scene.model_view {
            view.file_texture = file_texture;
        }
        scene
    }

    /// A loaded model at the origin: an object per part, turning, with the
    /// model's maps (when it has any) in place of `texture`.
    pub fn loaded(model: LoadedModel, texture: Arc<Texture>) -> Self {
        let LoadedModel { parts, maps, .. } = model;
        let mut parts = parts.into_iter();
        let first = parts.next().unwrap_or_else(|| ModelPart {
            mesh: Mesh::default(),
            material: None,
            own_maps: None,
            opacity_map: None,
            pbr_maps: Default::default(),
        });
        let mut scene = Scene::model(first.mesh, maps.texture.unwrap_or(texture));
        scene.material.specular_map = maps.specular_map;
        // A part drawn with the scene's material reads its normal map.
        let shared_normal = maps.normal_map.clone();
        scene.material.normal_map = maps.normal_map;
        let normal_of = |own: &Option<ModelMaps>| match own {
            Some(m) => m.normal_map.clone(),
            None => shared_normal.clone(),
        };
        let terms_of = |material: &Option<MaterialDesc>,
                        opacity: &Option<Arc<relief_texture::Level>>,
                        pbr_maps: &PbrMaps,
                        own: &Option<ModelMaps>| {
            mtl_terms(material.as_ref(), opacity.clone(), pbr_maps, normal_of(own))
        };
        let mut terms = vec![terms_of(
            &first.material,
            &first.opacity_map,
            &first.pbr_maps,
            &first.own_maps,
        )];
        let mut own = vec![first.own_maps];
        for p in parts {
            terms.push(terms_of(
                &p.material,
                &p.opacity_map,
                &p.pbr_maps,
                &p.own_maps,
            ));
            scene.objects.push(Object {
                mesh: p.mesh,
                transform: Mat4::IDENTITY,
                rotates: true,
            });
            own.push(p.own_maps);
        }
        if terms.iter().any(Option::is_some) {
            scene.object_terms = terms;
        }
        // A part whose material has its own texture draws with it; the
        // others with the scene's material (which the texture keys change).
        let environment = scene.material.environment.clone();
        scene.object_materials = own
            .into_iter()
            .map(|m| {
                let m = m?;
                Some(Arc::new(Material {
                    texture: m.texture?,
                    specular_map: m.specular_map,
                    normal_map: m.normal_map,
                    environment: environment.clone(),
                }))
            })
            .collect();
        if scene.object_materials.iter().all(Option::is_none) {
            scene.object_materials.clear();
        }
        scene
    }

    /// The documented cube scene with the given texture.
    pub fn cube(texture: Arc<Texture>, all_faces: bool) -> Self {
        Scene::model(cube::cube(all_faces), texture)
    }

    /// One model at the origin, turning, in the reference lighting and camera.
    pub fn model(mesh: Mesh, texture: Arc<Texture>) -> Self {
        Scene {
            objects: vec![Object {
                mesh,
                transform: Mat4::IDENTITY,
                rotates: true,
            }],
            material: Material {
                texture,
                specular_map: None,
                normal_map: None,
                environment: None,
            },
            object_materials: Vec::new(),
            object_terms: Vec::new(),
            strokes: Default::default(),
            lights: light::reference_lights(),
            ambient: AMBIENT,
            camera: Camera::default(),
            background: BACKGROUND,
            model_view: None,
            motion: None,
            cameras: Vec::new(),
            file_lights: Vec::new(),
        }
    }

    /// The reference cube, turning, over a still floor at `FLOOR_Y`, seen
    /// from higher up so the shadow behind the cube is in view.
    pub fn shadow(texture: Arc<Texture>, all_faces: bool) -> Self {
        let mut floor = plane::grid(FLOOR_HALF, FLOOR_HALF, FLOOR_CELLS, floor_color);
        for tri in &mut floor.triangles {
            tri.textured = false;
        }
        let mut scene = Scene::model(cube::cube(all_faces), texture);
        scene.objects.push(Object {
            mesh: floor,
            // Face +Z turned to face +Y, then lowered.
            transform: Mat4::from_translation(Vec3::new(0.0, FLOOR_Y, 0.0))
                * Mat4::from_rotation_x(-FRAC_PI_2),
            rotates: false,
        });
        scene.camera = shadow_camera();
        scene
    }
}

/// Above, in front and to the left: the strong light at (3, 4, 6) throws
/// the cube's shadow back and to the left, and a camera next to the light
/// would see it hidden behind the cube, so this one looks across the
/// light's direction (about 70° from it).
pub fn shadow_camera() -> Camera {
    Camera {
        eye: Vec3::new(-4.7, 4.1, 5.4),
        target: Vec3::new(-0.3, -1.1, -0.9),
        ..Camera::default()
    }
}
