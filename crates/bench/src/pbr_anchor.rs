//! `relief bench --anchors --model FILE --pbr`: the model file of
//! `mesh_anchor` in the same fit, pose and camera, shaded as the model view
//! shades a glTF metallic-roughness material, which
//! `docs/tools/llvmpipe_mesh.py bench --pbr` draws with llvmpipe
//! (docs/bench.md, "The physically based frame side by side with llvmpipe").
//!
//! What changes from the Phong view: one material given by its factors
//! (the base colour as the vertices' colour, linear), one white point
//! light at the reference key light's place, no falloff, and the image-based
//! light of an equirectangular picture (`--environment-map`; the built-in
//! studio without one): nine spherical-harmonic coefficients, the
//! prefiltered levels and the split-sum table (docs/shading.md, "Image-based
//! light"); then PBR Neutral and the sRGB encoding. The camera stays the
//! reference camera: the scene is put in the model view (which is what
//! shades materials physically) seen through that camera as a file's own,
//! so no framing moves it.

use std::path::Path;
use std::sync::Arc;

use glam::Vec3;

use relief_scene::contents::ModelView;
use relief_scene::terms::{MaterialTerms, PbrMaterial};
use relief_scene::{Light, Scene};
use relief_texture::environment::Environment;

/// Where the one white light stands: the reference rig's key light.
pub const KEY_LIGHT: Vec3 = Vec3::new(3.0, 4.0, 6.0);

/// The material of the frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Look {
    /// Gold: base (1, 0.71, 0.29) linear, metallic 1, roughness 0.4.
    Metal,
    /// Blue paint: base (0.05, 0.2, 0.6) linear, metallic 0, roughness 0.5.
    Dielectric,
}

/// A metallic-roughness material by its factors.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Factors {
    /// Linear base colour.
    pub base: Vec3,
    pub metallic: f32,
    pub roughness: f32,
}

impl Look {
    pub fn factors(self) -> Factors {
        match self {
            Look::Metal => Factors {
                base: Vec3::new(1.0, 0.71, 0.29),
                metallic: 1.0,
                roughness: 0.4,
            },
            Look::Dielectric => Factors {
                base: Vec3::new(0.05, 0.2, 0.6),
                metallic: 0.0,
                roughness: 0.5,
            },
        }
    }
}

impl std::fmt::Display for Factors {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let b = self.base;
        write!(
            f,
            "base {},{},{} (linear), metallic {}, roughness {}",
            b.x, b.y, b.z, self.metallic, self.roughness
        )
    }
}

/// `scene` (`mesh_anchor::scene`'s) shaded physically with `factors`,
/// the key light alone and `environment`'s light.
pub fn physical(mut scene: Scene, factors: Factors, environment: Arc<Environment>) -> Scene {
    for object in &mut scene.objects {
        for v in &mut object.mesh.vertices {
            v.color = factors.base;
        }
        // The base colour is given to every corner here.
        object.mesh.colours_invented = false;
    }
    let terms = Arc::new(MaterialTerms {
        pbr: Some(PbrMaterial {
            metallic: factors.metallic,
            roughness: factors.roughness,
            ..PbrMaterial::gltf_default()
        }),
        ..MaterialTerms::default()
    });
    scene.object_terms = vec![Some(terms); scene.objects.len()];
    scene.lights = vec![Light::new(KEY_LIGHT, Vec3::ONE)];
    // The model view's environment is on while the ambient light is not 0
    // (the reference's 0.1 stays: the physical kernel reads only the map).
    scene.material.environment = Some(environment);
    scene.cameras = vec![scene.camera];
    scene.model_view = Some(ModelView {
        camera: Some(0),
        ..ModelView::new()
    });
    scene
}

/// What `--pbr` asks for.
#[derive(Clone, Copy, Debug)]
pub struct Request<'a> {
    pub look: Look,
    /// `--environment-map`: the equirectangular picture of the light.
    pub environment: Option<&'a Path>,
}

impl Request<'_> {
    /// The environment the request names (the studio without one).
    pub fn environment(&self) -> anyhow::Result<Arc<Environment>> {
        Ok(Environment::load_optional(self.environment)?.unwrap_or_else(Environment::studio))
    }

    /// The header's account of the shading.
    pub fn describe(&self) -> String {
        let environment = match self.environment {
            Some(path) => relief_core::sanitize::display_path(path).to_string(),
            None => "the built-in studio".into(),
        };
        let k = KEY_LIGHT;
        format!(
            "glTF metallic-roughness ({}), one white point light at ({},{},{}), the image-based light of {environment} (9 SH coefficients, prefiltered levels, split-sum table), PBR Neutral, sRGB",
            self.look.factors(),
            k.x,
            k.y,
            k.z
        )
    }
}
