//! What is drawn: meshes, material, lights, camera.

pub mod build;
pub mod camera;
pub mod casters;
pub mod convex;
pub mod cube;
pub mod flag_maps;
pub mod gltf;
pub mod light;
pub mod mesh;
pub mod model_file;
pub mod model_textures;
pub mod obj;
pub mod plane;
pub mod ply;
pub mod repeats;
pub mod sphere;
pub mod stl;
pub mod strokes;
pub mod tangents;
pub mod terms;
pub mod triangle;
pub mod world;

pub use build::{Built, LoadedNotes, ModelChoice, SceneKind, build_scene, build_scene_noting};
pub use camera::Camera;
pub use light::{AMBIENT, Light};
pub use mesh::{Face, Facet, Mesh, Triangle, Vertex};

use std::sync::Arc;

use glam::{Mat3, Mat4, Vec3};

use crate::framebuffer::Rgb;
use crate::settings::normalize_degrees;
use crate::texture::Texture;

/// The colour texture (RGB) and height map (alpha) of textured triangles.
#[derive(Clone, Debug)]
pub struct Material {
    pub texture: Arc<Texture>,
    /// Grey map scaling the specular highlight (docs/specular.md); none: 1 everywhere.
    pub specular_map: Option<Arc<crate::texture::Level>>,
    /// Tangent-space normal map read from a file (`--normal-map`), which
    /// dot3 uses instead of the height-derived one while
    /// `Settings::normal_map_file` is on (docs/bump-dot3.md).
    pub normal_map: Option<Arc<crate::texture::normal_map_file::FileNormalMap>>,
    /// The environment reflections show (docs/environment.md); none: the built-in sky.
    pub environment: Option<Arc<crate::texture::environment::Environment>>,
}

/// A mesh placed in the world. `rotates` objects follow the user's rotation.
#[derive(Clone, Debug)]
pub struct Object {
    pub mesh: Mesh,
    /// Placement applied after the user's rotation (e.g. a floor's offset).
    pub transform: Mat4,
    /// Whether the user's rotation applies.
    pub rotates: bool,
}

impl Object {
    /// Object space to world space: its placement, after the user's
    /// rotation when it follows it.
    pub fn model_matrix(&self, user_rotation: Mat4) -> Mat4 {
        if self.rotates {
            self.transform * user_rotation
        } else {
            self.transform
        }
    }
}

/// The matrix that carries normals through `model` (the inverse transpose
/// of its linear part). A singular model (an object flattened to a plane
/// or a line) has none: its linear part is used instead, so normals stay
/// finite and the caller's normalisation decides what survives.
pub fn normal_matrix(model: Mat4) -> Mat3 {
    let linear = Mat3::from_mat4(model);
    let inverse_transpose = linear.inverse().transpose();
    if inverse_transpose.is_finite() {
        inverse_transpose
    } else {
        linear
    }
}

/// Everything the renderer draws.
#[derive(Clone, Debug)]
pub struct Scene {
    pub objects: Vec<Object>,
    /// The material of every object without its own.
    pub material: Material,
    /// Objects' own materials (a loaded model's), by object index: object
    /// i uses `object_materials[i]` when it is there and set, else
    /// `material`. Materials shared by objects are shared `Arc`s.
    pub object_materials: Vec<Option<Arc<Material>>>,
    /// Objects' extra material terms (a loaded model's emission,
    /// occlusion, specular colour…), by object index like `object_materials`.
    pub object_terms: Vec<Option<Arc<crate::scene::terms::MaterialTerms>>>,
    /// A model's points and lines, drawn over the objects (following the
    /// user's rotation as they do).
    pub strokes: strokes::Strokes,
    pub lights: Vec<Light>,
    pub ambient: Vec3,
    pub camera: Camera,
    pub background: Rgb,
}

impl Scene {
    /// Object `index`'s own material, if it has one.
    pub fn own_material(&self, index: usize) -> Option<&Arc<Material>> {
        self.object_materials.get(index).and_then(Option::as_ref)
    }

    /// Object `index`'s extra material terms, if it has any.
    pub fn own_terms(&self, index: usize) -> Option<&Arc<crate::scene::terms::MaterialTerms>> {
        self.object_terms.get(index).and_then(Option::as_ref)
    }

    /// The distinct own materials of the objects, in order of first use,
    /// and for each object the index in that list plus one (0: the
    /// scene's material).
    pub fn material_groups(&self) -> (Vec<&Arc<Material>>, Vec<usize>) {
        let mut distinct: Vec<&Arc<Material>> = Vec::new();
        let groups = (0..self.objects.len())
            .map(|i| match self.own_material(i) {
                None => 0,
                Some(m) => match distinct.iter().position(|d| Arc::ptr_eq(d, m)) {
                    Some(k) => k + 1,
                    None => {
                        distinct.push(m);
                        distinct.len()
                    }
                },
            })
            .collect();
        (distinct, groups)
    }
}

/// Background of the reference scene.
pub const BACKGROUND: Rgb = [16, 24, 32];

impl Scene {
    /// The documented cube scene with the given texture.
    pub fn cube(texture: Arc<Texture>, all_faces: bool) -> Self {
        Scene::model(cube::cube(all_faces), texture)
    }
}

/// Model rotation in degrees: about X first, then Y, then Z. Angles are
/// reduced modulo 360 in f64 first; NaN and infinities count as 0.
pub fn rotation_matrix(degrees: Vec3) -> Mat4 {
    let [x, y, z] = degrees
        .to_array()
        .map(|d| normalize_degrees(d).to_radians());
    Mat4::from_rotation_z(z) * Mat4::from_rotation_y(y) * Mat4::from_rotation_x(x)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normals_stay_perpendicular_under_a_stretch() {
        // A plane tilted 45° in XY, stretched 4× along X: its normal must
        // stay perpendicular to the stretched plane, not follow the stretch.
        let model = Mat4::from_scale(Vec3::new(4.0, 1.0, 1.0));
        let (along, normal) = (Vec3::new(1.0, 1.0, 0.0), Vec3::new(1.0, -1.0, 0.0));
        let n = normal_matrix(model) * normal;
        let a = Mat3::from_mat4(model) * along;
        assert!(n.dot(a).abs() < 1e-5, "{n} · {a}");
    }

    #[test]
    fn a_flattened_object_keeps_finite_normals() {
        let model = Mat4::from_scale(Vec3::new(1.0, 1.0, 0.0));
        let m = normal_matrix(model);
        assert!(m.is_finite());
        assert_eq!(m * Vec3::X, Vec3::X);
    }
}
