//! Input files: models, parser messages, mutated files.

mod etc1s_pictures;
mod meshopt_streams;
mod models;
mod models_formats;
mod models_gltf;
mod models_gltf_accessors;
mod models_gltf_anim;
mod models_gltf_blend;
mod models_gltf_cameras;
mod models_gltf_convex;
mod models_gltf_draco;
mod models_gltf_etc1s;
mod models_gltf_hostile;
mod models_gltf_ktx2;
mod models_gltf_lights;
mod models_gltf_meshopt;
mod models_props;
mod models_render;
mod mutation;
mod obj_chunks;
mod obj_corpus;
mod octahedron;
mod parser_messages;
