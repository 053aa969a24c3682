//! What is drawn: meshes, material, lights, camera.

pub mod build;
pub mod camera;
pub mod cube;
pub mod light;
pub mod mesh;
pub mod obj;
pub mod plane;
pub mod sphere;
pub mod tangents;
pub mod triangle;

pub use build::{Built, ModelChoice, SceneKind, build_scene};
pub use camera::Camera;
pub use light::{AMBIENT, Light};
pub use mesh::{Mesh, Triangle, Vertex};

use std::sync::Arc;

use glam::{Mat4, Vec3};

use crate::framebuffer::Rgb;
use crate::settings::normalize_degrees;
use crate::texture::Texture;

/// The colour texture (RGB) and height map (alpha) of textured triangles.
#[derive(Clone, Debug)]
pub struct Material {
    pub texture: Arc<Texture>,
    /// Grey map scaling the specular highlight (docs/specular.md); none: 1 everywhere.
    pub specular_map: Option<Arc<crate::texture::Level>>,
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

/// Everything the renderer draws.
#[derive(Clone, Debug)]
pub struct Scene {
    pub objects: Vec<Object>,
    pub material: Material,
    pub lights: Vec<Light>,
    pub ambient: Vec3,
    pub camera: Camera,
    pub background: Rgb,
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
