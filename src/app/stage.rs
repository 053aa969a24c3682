//! What the interactive view shows: the built scene (3D or plasma), rebuilt
//! when the user picks another scene or model, kept when that fails.

use std::sync::Arc;
use std::time::Instant;

use glam::Vec3;

use crate::framebuffer::Framebuffer;
use crate::render::Renderer;
use crate::sanitize::clean;
use crate::scene::camera::light_turn;
use crate::scene::obj::ObjError;
use crate::scene::{Built, Camera, LoadedNotes, ModelChoice, SceneKind, build_scene_noting};
use crate::stats::FrameStats;
use crate::texture::environment::Environment;
use crate::texture::normal_map_file::FileNormalMap;
use crate::texture::{Level, Texture};

use super::state::{State, plasma_light};

/// The shown scene, with what it was built from.
pub struct Stage {
    built: Built,
    kind: SceneKind,
    model: ModelChoice,
    /// Kept across the plasma (which has none) for the next 3D scene.
    texture: Arc<Texture>,
    all_faces: bool,
    /// `--specular-map`, given to every 3D scene shown.
    specular_map: Option<Arc<Level>>,
    /// `--normal-map`, given to every 3D scene shown.
    normal_map: Option<Arc<FileNormalMap>>,
    /// `--environment-map`, given to every 3D scene shown.
    environment: Option<Arc<Environment>>,
    /// The scene's own camera, which the zoom moves along its line of sight.
    camera: Camera,
    /// Where the scene's lights were built: a light drag turns them from here.
    light_positions: Vec<Vec3>,
    /// What the last model load had to say, until taken.
    notes: LoadedNotes,
}

/// Where a built scene's lights are (the plasma has none).
fn lights_of(built: &Built) -> Vec<Vec3> {
    match built {
        Built::Scene(scene) => scene.lights.iter().map(|l| l.position).collect(),
        Built::Plasma(_) => Vec::new(),
    }
}

/// The camera a built scene comes with (the plasma has none).
fn camera_of(built: &Built) -> Camera {
    match built {
        Built::Scene(scene) => scene.camera,
        Built::Plasma(_) => Camera::default(),
    }
}

impl Stage {
    /// Builds the starting scene (a bad `--model` file is an error).
    pub fn new(
        kind: SceneKind,
        model: ModelChoice,
        texture: Arc<Texture>,
        all_faces: bool,
    ) -> Result<Stage, ObjError> {
        let (built, notes) = build_scene_noting(kind, &model, texture.clone(), all_faces)?;
        Ok(Stage {
            notes,
            camera: camera_of(&built),
            light_positions: lights_of(&built),
            built,
            kind,
            model,
            texture,
            all_faces,
            specular_map: None,
            normal_map: None,
            environment: None,
        })
    }

    /// Gives the 3D scenes this specular map.
    pub fn with_specular_map(mut self, map: Option<Arc<Level>>) -> Stage {
        self.specular_map = map;
        self
    }

    /// Gives the 3D scenes this normal map file.
    pub fn with_normal_map(mut self, map: Option<Arc<FileNormalMap>>) -> Stage {
        self.normal_map = map;
        self
    }

    /// Gives the 3D scenes this environment to reflect.
    pub fn with_environment(mut self, environment: Option<Arc<Environment>>) -> Stage {
        self.environment = environment;
        self
    }

    /// The scene and model shown.
    pub fn shown(&self) -> (SceneKind, &ModelChoice) {
        (self.kind, &self.model)
    }

    pub fn built(&self) -> &Built {
        &self.built
    }

    /// Shows `kind` with `model` (the texture stays). On error the scene
    /// shown stays and the error comes back one line long, sanitised.
    pub fn build(&mut self, kind: SceneKind, model: &ModelChoice) -> Result<(), String> {
        if (kind, model) == (self.kind, &self.model) {
            return Ok(());
        }
        let (built, notes) = build_scene_noting(kind, model, self.texture.clone(), self.all_faces)
            .map_err(|e| clean(&e.to_string()))?;
        self.notes = notes;
        self.camera = camera_of(&built);
        self.light_positions = lights_of(&built);
        self.built = built;
        self.kind = kind;
        self.model = model.clone();
        Ok(())
    }

    /// The shown model file's own textures, a line per map of each
    /// material (none for the built-in models and the plasma).
    pub fn model_textures(&self) -> Vec<String> {
        match (&self.built, &self.model) {
            (Built::Scene(scene), ModelChoice::File(_)) => {
                crate::scene::model_textures::model_textures(scene)
            }
            _ => Vec::new(),
        }
    }

    /// The warnings of the last model loaded (and whether it is a point
    /// cloud), once.
    pub fn take_notes(&mut self) -> LoadedNotes {
        std::mem::take(&mut self.notes)
    }

    /// Applies another texture to the shown scene and to those built later.
    pub fn set_texture(&mut self, texture: Arc<Texture>) {
        if let Built::Scene(scene) = &mut self.built {
            scene.material.texture = texture.clone();
        }
        self.texture = texture;
    }

    /// Draws the state's picture: the 3D scene with the state's light
    /// switches, or the plasma lit from the pointer.
    /// What it cost goes to the cost panel (the plasma is all "raster").
    pub fn render(
        &mut self,
        renderer: &mut Renderer,
        state: &State,
        fb: &mut Framebuffer,
    ) -> FrameStats {
        match &mut self.built {
            Built::Scene(scene) => {
                // The flags' maps win over the model's own (MTL map_Ks, norm).
                if let Some(map) = &self.specular_map {
                    scene.material.specular_map = Some(map.clone());
                }
                if let Some(map) = &self.normal_map {
                    scene.material.normal_map = Some(map.clone());
                }
                scene.material.environment = self.environment.clone();
                for (light, on) in scene.lights.iter_mut().zip(state.light_on) {
                    light.enabled = on;
                }
                let turn = light_turn(state.light_turn);
                for (light, at) in scene.lights.iter_mut().zip(&self.light_positions) {
                    light.position = turn * *at;
                }
                scene.camera = self.camera.at_distance(state.distance).panned(state.pan);
                scene.camera.fov_y_degrees = state.settings.fov;
                renderer.render(scene, &state.settings, fb)
            }
            Built::Plasma(plasma) => {
                let start = Instant::now();
                let light = plasma_light(state.pointer, fb.width(), fb.height());
                let counters = plasma.render(light, state.plasma_normal, fb);
                FrameStats {
                    counters,
                    raster_time: start.elapsed(),
                    ..FrameStats::default()
                }
            }
        }
    }
}
