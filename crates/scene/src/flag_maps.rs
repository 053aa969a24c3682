//! The pictures the view's flags give every 3D scene (`--specular-map`,
//! `--normal-map`, `--environment-map`): read once, at start, by `relief
//! render` and the interactive view alike, and put on a scene when it is
//! built, not on every frame.

use std::path::Path;
use std::sync::Arc;

use super::Scene;
use relief_texture::environment::Environment;
use relief_texture::normal_map_file::{FileNormalMap, load_normal_map};
use relief_texture::specular_map::load_specular_map;
use relief_texture::{Level, TextureError};

/// The flags' maps (each `None` when its flag is not given).
#[derive(Clone, Debug, Default)]
pub struct FlagMaps {
    pub specular: Option<Arc<Level>>,
    pub normal: Option<Arc<FileNormalMap>>,
    pub environment: Option<Arc<Environment>>,
}

/// Each map as read, its error kept apart: `relief render` stops at the
/// first one in this order, the view says a normal map's and goes on.
pub struct ReadMaps {
    pub specular: Result<Option<Arc<Level>>, TextureError>,
    pub normal: Result<Option<Arc<FileNormalMap>>, TextureError>,
    pub environment: Result<Option<Arc<Environment>>, TextureError>,
}

impl ReadMaps {
    /// The maps, or the first error (specular, normal, environment).
    pub fn all(self) -> Result<FlagMaps, TextureError> {
        Ok(FlagMaps {
            specular: self.specular?,
            normal: self.normal?,
            environment: self.environment?,
        })
    }
}

impl FlagMaps {
    /// Whether a specular or normal map is named: a texture the user chose
    /// (`ModelView::texture_chosen`), as a picture is.
    pub fn name_surface_maps(&self) -> bool {
        self.specular.is_some() || self.normal.is_some()
    }

    /// Reads the maps the flags name.
    pub fn read(
        specular: Option<&Path>,
        normal: Option<&Path>,
        environment: Option<&Path>,
    ) -> ReadMaps {
        ReadMaps {
            specular: specular
                .map(|path| load_specular_map(path).map(Arc::new))
                .transpose(),
            normal: normal
                .map(|path| load_normal_map(path).map(Arc::new))
                .transpose(),
            environment: Environment::load_optional(environment),
        }
    }

    /// Puts the maps on `scene`'s material: the flags' specular and normal
    /// maps win over the model's own (MTL `map_Ks`, `norm`); the
    /// environment is the flag's or none (the built-in sky).
    pub fn dress(&self, scene: &mut Scene) {
        if let Some(map) = &self.specular {
            scene.material.specular_map = Some(map.clone());
        }
        if let Some(map) = &self.normal {
            scene.material.normal_map = Some(map.clone());
        }
        scene.material.environment = self.environment.clone();
    }
}
