//! What the truth draws: the ideal picture of a renderer setting.
//!
//! A setting's truth is what its technique approximates, evaluated from the
//! technique's own definition in docs/ (see docs/bench.md, "One truth per
//! setting"). Choices that only trade accuracy for speed (filter, height
//! derivative, anti-aliasing, threads, the depth buffer, dot3's per-vertex
//! light vector, an 8-bit normal-map file) do not change the truth: they all
//! approximate the same picture.

use std::sync::Arc;

use relief_core::settings::{Normals, Settings, Shading, Technique};
use relief_scene::Scene;
use relief_texture::environment::Environment;

use super::physical::Physical;

/// The bump a truth draws, each from its own definition.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Bump {
    None,
    /// Blinn's perturbed normal (docs/bump-blinn.md).
    Blinn,
    /// The height shifted toward the strongest light and subtracted, added
    /// to that light's N·L (docs/bump-emboss.md).
    Emboss,
    /// The normal map of the heights in the tangent frame (docs/bump-dot3.md).
    Dot3,
    /// The height field carved below the face, met by each ray (marched
    /// finely), lit with Blinn's normal there: what parallax and POM both
    /// approximate (docs/bump-parallax.md).
    Relief,
}

/// Everything the truth needs to know besides the scene and the rotation.
#[derive(Clone, Debug)]
pub struct Setting {
    /// The triangle's own normal instead of the interpolated vertex normals.
    pub face_normals: bool,
    /// Vertex colours (off: white).
    pub colors: bool,
    /// The colour texture multiplies the albedo.
    pub texture: bool,
    pub bump: Bump,
    /// Blinn's k (the same k scales every technique).
    pub bump_strength: f64,
    /// The scene's lights (off: ambient only).
    pub lights: bool,
    /// 1 / (1 + 0.01 d²) per light.
    pub attenuation: bool,
    /// Blinn-Phong highlight of this exponent.
    pub shininess: Option<f64>,
    /// Mirror reflection of this picture, mixed in with this reflectivity.
    pub environment: Option<(Arc<Environment>, f64)>,
    /// The strongest light's shadow rays against the scene's triangles.
    pub shadows: bool,
    /// A model view: its metallic-roughness materials drawn physically
    /// (`truth::physical`), whatever the shading setting.
    pub physical: Option<Physical>,
}

impl PartialEq for Setting {
    fn eq(&self, other: &Self) -> bool {
        let env = |s: &Setting| s.environment.as_ref().map(|(e, k)| (Arc::as_ptr(e), *k));
        self.face_normals == other.face_normals
            && self.colors == other.colors
            && self.texture == other.texture
            && self.bump == other.bump
            && self.bump_strength == other.bump_strength
            && self.lights == other.lights
            && self.attenuation == other.attenuation
            && self.shininess == other.shininess
            && env(self) == env(other)
            && self.shadows == other.shadows
            && self.physical == other.physical
    }
}

impl Setting {
    /// The bench's reference setting: Phong, vertex normals, texture, Blinn
    /// bump at `k`, no highlight, environment or shadow.
    pub fn reference(k: f64) -> Setting {
        Setting {
            face_normals: false,
            colors: true,
            texture: true,
            bump: Bump::Blinn,
            bump_strength: k,
            lights: true,
            attenuation: false,
            shininess: None,
            environment: None,
            shadows: false,
            physical: None,
        }
    }

    /// The ideal picture `settings` approximate on `scene`.
    ///
    /// Flat and Gouraud approximate per-pixel lighting of the smooth
    /// surface: their truth is the Phong picture with what they can show
    /// (no bump and no environment, which are per-pixel only; the highlight
    /// evaluated per ray). Parallax and POM share one truth, the carved
    /// height field met exactly. Shadows are the renderer's: the strongest
    /// light's, wherever the scene is more than one convex object.
    pub fn of(settings: &Settings, scene: &Scene) -> Setting {
        let phong = settings.shading == Shading::Phong;
        let k = settings.bump_strength as f64;
        let bump_on = phong
            && settings.bump
            && k.is_finite()
            && k > 0.0
            && !scene.material.texture.height_is_flat();
        let bump = if !bump_on {
            Bump::None
        } else {
            match settings.technique {
                Technique::Blinn => Bump::Blinn,
                Technique::Emboss => Bump::Emboss,
                Technique::Dot3 => Bump::Dot3,
                Technique::Parallax | Technique::Pom => Bump::Relief,
            }
        };
        let shininess = (settings.specular
            && settings.lights
            && settings.shininess.is_finite()
            && settings.shininess > 0.0)
            .then_some(settings.shininess as f64);
        let environment = (settings.environment
            && phong
            && settings.reflectivity.is_finite()
            && settings.reflectivity > 0.0)
            .then(|| {
                let map = scene
                    .material
                    .environment
                    .clone()
                    .unwrap_or_else(Environment::sky);
                (map, settings.reflectivity.min(1.0) as f64)
            });
        let shadows = scene.objects.len() > 1 || scene.objects.iter().any(|o| !o.mesh.convex);
        if scene.model_view.is_some() {
            // What the materials are, whatever the row draws them with:
            // the bump, highlight and mirror settings have no say.
            return Setting {
                colors: settings.colors,
                texture: settings.texture,
                lights: settings.lights,
                attenuation: settings.attenuation,
                shadows: shadows && settings.lights,
                physical: Some(Physical::of(settings, scene)),
                bump: Bump::None,
                ..Setting::reference(0.0)
            };
        }
        Setting {
            face_normals: settings.normals == Normals::Face,
            colors: settings.colors,
            texture: settings.texture,
            bump,
            bump_strength: if bump_on { k } else { 0.0 },
            lights: settings.lights,
            attenuation: settings.attenuation,
            shininess,
            environment,
            shadows: shadows && settings.lights,
            physical: None,
        }
    }

    /// A short name for the table and the logs.
    pub fn label(&self) -> String {
        if let Some(p) = &self.physical {
            let mut label = p.label();
            if !self.lights {
                label.push_str(", no lights");
            }
            return label;
        }
        let mut parts = vec![
            match self.bump {
                Bump::None => "no bump",
                Bump::Blinn => "Blinn",
                Bump::Emboss => "emboss",
                Bump::Dot3 => "dot3",
                Bump::Relief => "relief",
            }
            .to_string(),
        ];
        if self.face_normals {
            parts.push("face normals".into());
        }
        if !self.texture {
            parts.push("no texture".into());
        }
        if !self.colors {
            parts.push("no colours".into());
        }
        if !self.lights {
            parts.push("no lights".into());
        }
        if self.attenuation {
            parts.push("attenuation".into());
        }
        if let Some(s) = self.shininess {
            parts.push(format!("specular s={s}"));
        }
        if let Some((_, k)) = &self.environment {
            parts.push(format!("environment k={k:.2}"));
        }
        if self.shadows {
            parts.push("shadows".into());
        }
        parts.join(", ")
    }
}
