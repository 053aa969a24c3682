//! What is drawn: meshes, material, lights, camera.

pub mod build;
pub mod camera;
pub mod casters;
pub mod contents;
pub mod convex;
pub mod corners;
pub mod cube;
pub mod flag_maps;
pub mod gltf;
pub mod light;
pub mod loaded_model;
pub mod material;
pub mod mesh;
pub mod model_error;
pub mod model_file;
pub mod model_io;
pub mod model_textures;
pub mod obj;
pub mod object;
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
pub use contents::{BACKGROUND, Scene};
pub use light::{AMBIENT, Light};
pub use material::Material;
pub use mesh::{Face, Facet, Mesh, Triangle, Vertex};
pub use object::{Object, normal_matrix, rotation_matrix};
