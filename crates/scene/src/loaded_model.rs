//! What a model reader gives back: its parts (each a mesh and the plain
//! description of its material), the maps the scene's one material takes,
//! and the warnings met on the way.

use std::path::PathBuf;
use std::sync::Arc;

use glam::Vec3;

use super::mesh::Mesh;
use relief_texture::Texture;
use relief_texture::normal_map_file::FileNormalMap;

/// One part of a model: the triangles of one material.
#[derive(Clone, Debug)]
pub struct ModelPart {
    pub mesh: Mesh,
    /// The material's description (none: the faces named no known material).
    pub material: Option<MaterialDesc>,
    /// The maps of this part's own material, when it has a texture that
    /// loaded and is not the one the scene's material shows (`LoadedModel::maps`):
    /// the part is then drawn with them (docs/models.md).
    pub own_maps: Option<ModelMaps>,
    /// MTL `map_d`: the material's opacity (grey), when it loaded.
    pub opacity_map: Option<Arc<relief_texture::Level>>,
    /// MTL `map_Pr` and `map_Pm`, when they loaded.
    pub pbr_maps: PbrMaps,
}

/// An MTL material's roughness and metallic maps (grey, any size each).
#[derive(Clone, Debug, Default)]
pub struct PbrMaps {
    pub roughness: Option<Arc<relief_texture::Level>>,
    pub metallic: Option<Arc<relief_texture::Level>>,
}

/// The maps the single scene material takes from the model's textured
/// material (see docs/models.md, "OBJ and MTL").
#[derive(Clone, Debug, Default)]
pub struct ModelMaps {
    /// `map_Kd` with `bump` as its height (scaled by `-bm`).
    pub texture: Option<Arc<Texture>>,
    /// `map_Ks`, as the specular map.
    pub specular_map: Option<Arc<relief_texture::Level>>,
    /// `norm`, as the normal map file dot3 reads.
    pub normal_map: Option<Arc<FileNormalMap>>,
}

/// A loaded model.
#[derive(Clone, Debug)]
pub struct LoadedModel {
    pub parts: Vec<ModelPart>,
    /// The maps the scene's one material shows.
    pub maps: ModelMaps,
    /// A point cloud (a PLY without faces): best seen in the points display.
    pub points: bool,
    /// One line each, already safe to print, naming the file.
    pub warnings: Vec<String>,
    /// The format stands its models with +Z up (STL: CAD and 3D printing
    /// tools write it so): the view turns them upright unless `--up` says.
    pub z_up: bool,
}

impl LoadedModel {
    /// All parts as one mesh (what a single-object scene draws).
    pub fn merged(&self) -> Mesh {
        let mut parts = self.parts.iter();
        let Some(first) = parts.next() else {
            return Mesh::default();
        };
        let mut mesh = first.mesh.clone();
        for part in parts {
            let base = mesh.vertices.len() as u32;
            mesh.vertices.extend_from_slice(&part.mesh.vertices);
            mesh.triangles.extend(part.mesh.triangles.iter().map(|t| {
                let mut t = *t;
                t.indices = t.indices.map(|i| i + base);
                t
            }));
            mesh.closed &= part.mesh.closed;
            mesh.colours_invented &= part.mesh.colours_invented;
        }
        mesh
    }
}

/// One material as an MTL file describes it.
#[derive(Clone, Debug, PartialEq)]
pub struct MaterialDesc {
    pub name: String,
    /// `Kd`: diffuse colour.
    pub diffuse: Option<Vec3>,
    /// `Ks`: specular colour.
    pub specular: Option<Vec3>,
    /// `Ns`: specular exponent.
    pub shininess: Option<f32>,
    /// `d`, or 1 − `Tr`: opacity.
    pub opacity: Option<f32>,
    /// `map_Kd`: diffuse colour texture.
    pub diffuse_map: Option<TexturePath>,
    /// `map_Ks`: specular colour (or level) texture.
    pub specular_map: Option<TexturePath>,
    /// `map_d`: opacity texture.
    pub opacity_map: Option<TexturePath>,
    /// `bump`, `map_Bump`, `map_bump`: height map.
    pub bump_map: Option<TexturePath>,
    /// `-bm` of the bump map: the heights are multiplied by it (1 when absent).
    pub bump_multiplier: f32,
    /// `norm`: tangent-space normal map.
    pub normal_map: Option<TexturePath>,
    /// `Pr` (the PBR extension): roughness, 0..=1.
    pub roughness: Option<f32>,
    /// `Pm`: metallic, 0..=1.
    pub metallic: Option<f32>,
    /// `map_Pr`: roughness map (grey).
    pub roughness_map: Option<TexturePath>,
    /// `map_Pm`: metallic map (grey).
    pub metallic_map: Option<TexturePath>,
}

impl MaterialDesc {
    pub(crate) fn named(name: String) -> Self {
        MaterialDesc {
            name,
            diffuse: None,
            specular: None,
            shininess: None,
            opacity: None,
            diffuse_map: None,
            specular_map: None,
            opacity_map: None,
            bump_map: None,
            bump_multiplier: 1.0,
            normal_map: None,
            roughness: None,
            metallic: None,
            roughness_map: None,
            metallic_map: None,
        }
    }
}

/// A texture as the MTL names it, and the file it was found at (none: not found).
#[derive(Clone, Debug, PartialEq)]
pub struct TexturePath {
    pub written: String,
    pub file: Option<PathBuf>,
}
