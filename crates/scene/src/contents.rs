//! Everything the renderer draws: the objects, their materials, the
//! lights and the camera.

use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

use glam::Vec3;

use super::camera::Camera;
use super::light::Light;
use super::material::Material;
use super::object::Object;
use super::strokes;
use relief_core::framebuffer::Rgb;

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
    pub object_terms: Vec<Option<Arc<crate::terms::MaterialTerms>>>,
    /// A model's points and lines, drawn over the objects (following the
    /// user's rotation as they do).
    pub strokes: strokes::Strokes,
    pub lights: Vec<Light>,
    pub ambient: Vec3,
    pub camera: Camera,
    pub background: Rgb,
    /// Shown as a model file is (`scene::model_view`): framed, lit by the
    /// neutral rig, its glTF materials shaded physically; `None` for the
    /// reference scenes.
    pub model_view: Option<ModelView>,
    /// An animated model's rig and the instant its objects show
    /// (`scene::anim`); `None` for everything else.
    pub motion: Option<crate::anim::Motion>,
    /// A model file's own cameras (glTF), in the scene's space; the model
    /// view shows the one its `camera` names.
    pub cameras: Vec<Camera>,
    /// A model file's own lights (glTF KHR_lights_punctual), in the scene's
    /// space: the model view lights the model with them instead of its rig.
    pub file_lights: Vec<Light>,
}

impl Scene {
    /// Object `index`'s own material, if it has one.
    pub fn own_material(&self, index: usize) -> Option<&Arc<Material>> {
        self.object_materials.get(index).and_then(Option::as_ref)
    }

    /// Object `index`'s extra material terms, if it has any.
    pub fn own_terms(&self, index: usize) -> Option<&Arc<crate::terms::MaterialTerms>> {
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

/// A scene shown in the model view (`scene::model_view`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ModelView {
    /// Which model (made once per scene built): framings are kept per model.
    pub id: u64,
    /// The rotation (degrees) the camera frames the model at; `None`: the
    /// frame's own rotation (a still frame is its own start view). The
    /// interactive view sets its start rotation, so turning the model
    /// does not move the camera; `r`, a resize or another model frame it again.
    pub pose: Option<Vec3>,
    /// Which of the scene's cameras it is seen through (`V`; none: the
    /// framing camera).
    pub camera: Option<usize>,
    /// Whether the user chose the scene's texture (an image or a map
    /// named, or one applied in the view: the interactive view and `relief
    /// render` say so; a scene made here takes it as chosen).
    pub texture_chosen: bool,
    /// Whether the file gave the scene's material its maps (an OBJ's first
    /// `map_Kd`, `map_Ks` or `norm`).
    pub file_texture: bool,
}

impl ModelView {
    /// Whether the parts without a material of their own (an STL, a PLY,
    /// an OBJ part that names none) take the scene's material, texture and
    /// bump: when the file gave it its maps or the user chose a texture;
    /// else they are drawn plain, as a model viewer draws a file that
    /// names no material.
    pub fn dresses_bare_parts(&self) -> bool {
        self.texture_chosen || self.file_texture
    }

    pub fn new() -> Self {
        static NEXT: AtomicU64 = AtomicU64::new(1);
        ModelView {
            id: NEXT.fetch_add(1, Ordering::Relaxed),
            pose: None,
            camera: None,
            texture_chosen: true,
            file_texture: false,
        }
    }
}

impl Default for ModelView {
    fn default() -> Self {
        ModelView::new()
    }
}
