//! The maps a textured triangle is drawn with.

use std::sync::Arc;

use relief_texture::Texture;

/// The colour texture (RGB) and height map (alpha) of textured triangles.
#[derive(Clone, Debug)]
pub struct Material {
    pub texture: Arc<Texture>,
    /// Grey map scaling the specular highlight (docs/specular.md); none: 1 everywhere.
    pub specular_map: Option<Arc<relief_texture::Level>>,
    /// Tangent-space normal map read from a file (`--normal-map`), which
    /// dot3 uses instead of the height-derived one while
    /// `Settings::normal_map_file` is on (docs/bump-dot3.md).
    pub normal_map: Option<Arc<relief_texture::normal_map_file::FileNormalMap>>,
    /// The environment reflections show (docs/environment.md); none: the built-in sky.
    pub environment: Option<Arc<relief_texture::environment::Environment>>,
}
