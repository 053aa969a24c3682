//! What the interactive view draws: the built scene (3D or plasma), rebuilt
//! when the user picks another scene or model, kept when that fails. Which
//! scene and model are shown is the state's to say (`State::scene`,
//! `State::model`); the stage holds what was built from them and from the
//! pictures the flags gave, which it puts on each scene once, as it is built.

use std::sync::Arc;
use std::time::Instant;

use relief_core::framebuffer::Framebuffer;
use relief_core::sanitize::clean;
use relief_core::stats::FrameStats;
use relief_pipeline::render::Renderer;
use relief_scene::camera::light_turn;
use relief_scene::flag_maps::FlagMaps;
use relief_scene::light::Light;
use relief_scene::model_error::ObjError;
use relief_scene::{Built, Camera, LoadedNotes, ModelChoice, SceneKind, build_scene_noting};
use relief_texture::Texture;

use super::state::{State, plasma_light};

/// Everything a scene build needs, apart from the stage: built on any
/// thread, then shown with [`Stage::install`].
#[derive(Clone, Debug)]
pub struct BuildOrder {
    pub kind: SceneKind,
    pub model: ModelChoice,
    texture: Arc<Texture>,
    all_faces: bool,
}

impl BuildOrder {
    /// Builds the scene, or the error in one sanitised line.
    pub fn build(self) -> Result<Ready, String> {
        let (built, notes) =
            build_scene_noting(self.kind, &self.model, self.texture.clone(), self.all_faces)
                .map_err(|e| clean(&e.to_string()))?;
        Ok(Ready {
            built,
            notes,
            texture: self.texture,
        })
    }
}

/// A scene built from a [`BuildOrder`], for [`Stage::install`].
pub struct Ready {
    built: Built,
    notes: LoadedNotes,
    /// The texture it was built with.
    texture: Arc<Texture>,
}

impl std::fmt::Debug for Ready {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Ready").field("notes", &self.notes).finish()
    }
}

/// The shown scene, with the pictures it was built with.
pub struct Stage {
    built: Built,
    /// Kept across the plasma (which has none) for the next 3D scene.
    texture: Arc<Texture>,
    all_faces: bool,
    /// `--specular-map`, `--normal-map`, `--environment-map`, given to
    /// every 3D scene built.
    maps: FlagMaps,
    /// The scene's own camera, which the zoom moves along its line of sight.
    camera: Camera,
    /// Where the scene's lights were built: a light drag turns them from here.
    light_places: Vec<Light>,
    /// What the last model load had to say, until taken.
    notes: LoadedNotes,
}

/// A built scene's lights as built, before any turn (the plasma has none).
fn lights_of(built: &Built) -> Vec<Light> {
    match built {
        Built::Scene(scene) => scene.lights.clone(),
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
        model: &ModelChoice,
        texture: Arc<Texture>,
        all_faces: bool,
    ) -> Result<Stage, ObjError> {
        let (built, notes) = build_scene_noting(kind, model, texture.clone(), all_faces)?;
        Ok(Stage {
            notes,
            camera: camera_of(&built),
            light_places: lights_of(&built),
            built,
            texture,
            all_faces,
            maps: FlagMaps::default(),
        })
    }

    /// Gives the shown 3D scene and every one built later the flags' maps.
    pub fn with_maps(mut self, maps: FlagMaps) -> Stage {
        if let Built::Scene(scene) = &mut self.built {
            maps.dress(scene);
        }
        self.maps = maps;
        self
    }

    pub fn built(&self) -> &Built {
        &self.built
    }

    /// Builds `kind` with `model` (the texture and the flags' maps stay).
    /// On error the scene built before stays and the error comes back one
    /// line long, sanitised.
    pub fn build(&mut self, kind: SceneKind, model: &ModelChoice) -> Result<(), String> {
        let ready = self.order(kind, model).build()?;
        self.install(ready);
        Ok(())
    }

    /// What building `kind` with `model` needs, to build it on another
    /// thread (the view keeps drawing this stage meanwhile).
    pub fn order(&self, kind: SceneKind, model: &ModelChoice) -> BuildOrder {
        BuildOrder {
            kind,
            model: model.clone(),
            texture: self.texture.clone(),
            all_faces: self.all_faces,
        }
    }

    /// Shows a scene built from [`Stage::order`], with the flags' maps; a
    /// texture applied while it was built is applied to it too.
    pub fn install(&mut self, ready: Ready) {
        let Ready {
            mut built,
            notes,
            texture,
        } = ready;
        if let Built::Scene(scene) = &mut built {
            if !Arc::ptr_eq(&texture, &self.texture) {
                scene.material.texture = self.texture.clone();
            }
            self.maps.dress(scene);
        }
        self.notes = notes;
        self.camera = camera_of(&built);
        self.light_places = lights_of(&built);
        self.built = built;
    }

    /// The own textures of `model` (the state's, which this stage was
    /// built from) when it is a file, a line per map of each material
    /// (none for the built-in models and the plasma).
    pub fn model_textures(&self, model: &ModelChoice) -> Vec<String> {
        match (&self.built, model) {
            (Built::Scene(scene), ModelChoice::File(_)) => {
                relief_scene::model_textures::model_textures(scene)
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
                for (light, on) in scene.lights.iter_mut().zip(state.light_on) {
                    light.enabled = on;
                }
                let turn = light_turn(state.light_turn);
                for (light, built) in scene.lights.iter_mut().zip(&self.light_places) {
                    *light = Light {
                        enabled: light.enabled,
                        ..built.moved(turn)
                    };
                }
                scene.camera = self.camera.at_distance(state.distance).panned(state.pan);
                // The model view frames the model at the start rotation, so
                // turning it does not move the camera (`r` comes back to it).
                if let Some(view) = &mut scene.model_view {
                    view.pose = Some(state.start_rotation);
                    view.camera = state.camera;
                    // A model file's parts without a material take the
                    // texture once the user has chosen one.
                    view.texture_chosen = state.texture_chosen;
                }
                if let Some(motion) = &mut scene.motion {
                    let (clip, time) = state.playback.shown().unzip();
                    motion.show(&mut scene.objects, clip, time.unwrap_or(0.0));
                }
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
