//! Which stages a frame runs, decided once from the scene and the settings,
//! so that an effect that is off, or cannot show, costs nothing.

use std::sync::Arc;

use glam::{Mat3, Mat4, Vec3};

use relief_core::settings::{
    AntiAlias, Display, Filter, HeightDerivative, IblDiffuse, IblSpecular, LightVector, Settings,
    Shading, Technique, ToneMap,
};
use relief_scene::casters::{Caster, casters, enclose};
use relief_scene::light::{Falloff, Light};
use relief_scene::terms::MaterialTerms;
use relief_scene::{Material, Scene};
use relief_texture::environment::Environment;
use relief_texture::sample::normal_map::normal_map_scale;
use relief_texture::{Level, NormalMap};

/// A light that can change a pixel: enabled, with a non-black colour.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ActiveLight {
    pub position: Vec3,
    pub color: Vec3,
    /// How its strength falls off on the way to a point (`Setting`: as the
    /// plan's `attenuation` says).
    pub falloff: Falloff,
}

/// The lights that contribute (on, not black, at a finite place), a model
/// file's own carried by the model's `rotation`.
fn active_lights(lights: &[Light], rotation: Mat4) -> Vec<ActiveLight> {
    let turn = Mat3::from_mat4(rotation);
    lights
        .iter()
        .filter(|l| l.enabled && l.color.max_element() > 0.0)
        .map(|l| {
            if l.turns_with_model {
                l.moved(turn)
            } else {
                *l
            }
        })
        .filter(|l| l.position.is_finite() && l.color.is_finite())
        .map(|l| ActiveLight {
            position: l.position,
            color: l.color,
            falloff: l.falloff,
        })
        .collect()
}

/// The brightest active light (the first on ties), or `None` when no light
/// is on: the one emboss follows and the one whose shadows are drawn.
pub fn strongest_light(lights: &[ActiveLight]) -> Option<usize> {
    let mut best: Option<(usize, f32)> = None;
    for (i, l) in lights.iter().enumerate() {
        let power = l.color.element_sum();
        if best.is_none_or(|(_, p)| power > p) {
            best = Some((i, power));
        }
    }
    best.map(|(i, _)| i)
}

/// Blinn-Phong highlights, when the plan draws them (docs/specular.md).
#[derive(Clone, Debug, PartialEq)]
pub struct Specular {
    /// The exponent s of (N·H)^s: finite and > 0.
    pub shininess: f32,
    /// Grey map scaling the highlight on triangles with texture coordinates.
    pub map: Option<Arc<Level>>,
}

/// Environment mapping, when the plan draws it (docs/environment.md).
#[derive(Clone, Debug, PartialEq)]
pub struct Reflection {
    /// The scene's environment, or the built-in sky.
    pub map: Arc<Environment>,
    /// k of c = (1 − k)·lit + k·env(R): in (0, 1].
    pub reflectivity: f32,
}

/// The model view's physically based shading of metallic-roughness
/// materials (docs/shading.md, "Metallic-roughness").
#[derive(Clone, Debug, PartialEq)]
pub struct Physical {
    pub tone_map: ToneMap,
    /// Multiplies the light before the tone map: finite and > 0.
    pub exposure: f32,
    /// Normal maps applied (key `b`, on by default).
    pub normal_maps: bool,
    /// The environment that lights the materials (docs/shading.md,
    /// "Image-based light"): `--environment-map`'s or the built-in studio;
    /// none in a scene without ambient light.
    pub environment: Option<Arc<Environment>>,
    /// The environment's turn about +Y: its cosine and sine.
    pub turn: (f32, f32),
    /// The environment drawn behind the model (`--backdrop`, key `B`).
    pub backdrop: bool,
    /// How the environment's diffuse light is computed (`--ibl-diffuse`).
    pub ibl_diffuse: IblDiffuse,
    /// How the environment's specular light is computed (`--ibl-specular`).
    pub ibl_specular: IblSpecular,
}

/// The stages of one frame.
#[derive(Clone, Debug, PartialEq)]
pub struct Plan {
    pub shading: Shading,
    /// Gouraud and Phong use facet normals instead of vertex normals.
    pub face_normals: bool,
    /// Per-vertex colours (off: `uncoloured`).
    pub colors: bool,
    /// The albedo with the vertex colours off: white, or an object's own
    /// material colour (`MaterialTerms::colour_factor`).
    pub uncoloured: Vec3,
    /// Texture colour fetches on textured triangles.
    pub texture: bool,
    /// Blinn bump per pixel on textured triangles: Phong only, strength > 0,
    /// and a height map that is not flat.
    pub bump: bool,
    pub bump_strength: f32,
    /// The bump kernel (Blinn when bump is off).
    pub technique: Technique,
    /// Dot3's light vector: interpolated from the vertices or per pixel.
    pub light_vector: LightVector,
    /// Dot3's normal map, built (once per texture and strength) only when
    /// dot3 runs: the file's (`--normal-map`, tilted for the strength) when
    /// one is loaded and `normal_map_file` is on, else the height map's.
    pub normal_map: Option<Arc<NormalMap>>,
    /// `normal_map` is the file's.
    pub normal_map_from_file: bool,
    /// The camera position in world space (parallax needs the view vector).
    pub eye: Vec3,
    /// The camera the frame is seen with: the scene's, or in the model
    /// view the one that frames the model (`scene::model_view`).
    pub camera: relief_scene::Camera,
    pub height_derivative: HeightDerivative,
    pub filter: Filter,
    /// Screen-space UV derivatives per pixel, for the filters that pick a mip level.
    pub footprint: bool,
    /// A depth buffer: only when two drawn surfaces can cover the same pixel,
    /// or points and lines must hide behind a surface.
    pub depth: bool,
    pub ambient: Vec3,
    /// Lights that contribute (disabled and black lights are dropped here).
    pub lights: Vec<ActiveLight>,
    /// Distance attenuation of the lights.
    pub attenuation: bool,
    /// Highlights: only when asked for, with a usable exponent and a light
    /// to reflect (and filled triangles: points and lines show none).
    pub specular: Option<Specular>,
    /// Reflection of the environment: only when asked for, in fill display
    /// and Phong shading, with a reflectivity above 0.
    pub environment: Option<Reflection>,
    pub display: Display,
    /// Anti-aliasing; multisampling only in fill display (lines and points
    /// have no coverage to sample).
    pub aa: AntiAlias,
    /// The user's rotation of the model.
    pub rotation: Mat4,
    /// The light (index in `lights`) whose shadows are drawn: only when
    /// something can cast onto something else (see `shadow`).
    pub shadow_light: Option<usize>,
    /// What casts the shadows of `shadow_light` (empty without one).
    pub shadow_casters: Vec<Caster>,
    /// The tangent frames drawn over the picture: only when asked for and
    /// some triangle has texture coordinates (the frames come from them).
    pub tangent_frames: bool,
    /// A model material's extra terms (emission, occlusion, specular
    /// colour), only when they change a pixel (`Plan::with_terms`).
    pub terms: Option<Arc<MaterialTerms>>,
    /// The model view shades metallic-roughness materials physically:
    /// `None` for the reference scenes, whose pictures are defined in sRGB
    /// values.
    pub physical: Option<Physical>,
}

/// Whether the settings let a bump show at all: Phong, bump on and a
/// strength above 0 (the scene must also have texture coordinates and a
/// height map that is not flat: see [`Plan::new`]).
pub fn bump_shows(settings: &Settings) -> bool {
    bump_can_show(settings) && settings.bump_strength.is_finite() && settings.bump_strength > 0.0
}

/// Whether a bump could show with some strength: Phong with bump on (the
/// strength keys act only then).
pub fn bump_can_show(settings: &Settings) -> bool {
    settings.shading == Shading::Phong && settings.bump
}

/// Whether dot3 reads the `--normal-map` file (key `N`): asked for, with
/// dot3 chosen and a file loaded (`loaded`).
pub fn normal_map_file_shows(settings: &Settings, loaded: bool) -> bool {
    loaded && settings.normal_map_file && settings.technique == Technique::Dot3
}

/// Whether the bump technique (`e`) changes the picture: it is the bump's kernel.
pub fn technique_shows(settings: &Settings) -> bool {
    bump_shows(settings)
}

/// Whether dot3's light vector (`v`) is read: dot3 is the bump's kernel.
pub fn light_vector_shows(settings: &Settings) -> bool {
    bump_shows(settings) && settings.technique == Technique::Dot3
}

/// Whether the height derivative (`h`) is read: by the bump's kernel,
/// but by dot3 and emboss only through a filter with mip levels (they
/// read the full-size map otherwise: `normal_reads_base`,
/// `height_sampler`).
pub fn height_derivative_shows(settings: &Settings) -> bool {
    let reads_base = matches!(settings.technique, Technique::Dot3 | Technique::Emboss);
    bump_shows(settings) && (!reads_base || settings.filter.uses_mips())
}

/// Whether highlights can show (their shininess then too): asked for, in
/// fill display, with some light on (`lights_on`: the scene's switches).
pub fn specular_shows(settings: &Settings, lights_on: bool) -> bool {
    settings.specular
        && settings.shininess.is_finite()
        && settings.shininess > 0.0
        && settings.lights
        && lights_on
        && settings.display == Display::Fill
}

/// Whether the environment's reflection is drawn: asked for, in Phong and
/// fill display, with a reflectivity above 0 (docs/environment.md).
pub fn environment_shows(settings: &Settings) -> bool {
    settings.environment && environment_can_show(settings)
}

/// Whether these settings would draw the environment if it were on.
pub fn environment_can_show(settings: &Settings) -> bool {
    settings.display == Display::Fill
        && settings.shading == Shading::Phong
        && settings.reflectivity.is_finite()
        && settings.reflectivity > 0.0
}

impl Plan {
    pub fn new(scene: &Scene, settings: &Settings) -> Plan {
        let any_textured = scene.has_texture_coordinates();
        // The scene's material dresses the objects without their own; a
        // model file's are plain until the user chooses a texture.
        let dressed = any_textured && scene.model_view.is_none_or(|v| v.dresses_bare_parts());
        let stages = MaterialStages::new(&scene.material, dressed, settings, false);
        // Points and lines go behind the surfaces by the depth the triangles
        // leave, so a lone convex mesh keeps its depth buffer beside them.
        let depth = scene.objects.len() > 1
            || scene.objects.iter().any(|o| !o.mesh.convex)
            || !scene.strokes.is_empty();
        // A Z-up model is first turned so +Z is up, then the user's rotation.
        let rotation = relief_scene::model_view::view_rotation(settings.rotation, settings.up);
        let lights = if settings.lights {
            active_lights(&scene.lights, rotation)
        } else {
            Vec::new()
        };
        let aa = if settings.aa == AntiAlias::Msaa4 && settings.display != Display::Fill {
            AntiAlias::Off
        } else {
            settings.aa
        };
        let (shadow_light, shadow_casters) =
            shadow_light(scene, settings.display, rotation, &lights).unzip();
        let specular = specular_of(settings, &lights, &stages);
        let environment = reflection_of(scene, settings);
        Plan {
            shading: settings.shading,
            face_normals: settings.normals == relief_core::settings::Normals::Face,
            colors: settings.colors,
            uncoloured: Vec3::ONE,
            texture: stages.texture,
            bump: stages.bump,
            bump_strength: stages.bump_strength,
            technique: stages.technique,
            light_vector: settings.light_vector,
            normal_map: stages.normal_map,
            normal_map_from_file: stages.normal_map_from_file,
            eye: scene.camera.eye,
            camera: scene.camera,
            height_derivative: settings.height_derivative,
            filter: settings.filter,
            footprint: stages.footprint,
            depth,
            ambient: scene.ambient,
            lights,
            attenuation: settings.attenuation,
            specular,
            environment,
            display: settings.display,
            aa,
            rotation,
            shadow_light,
            shadow_casters: shadow_casters.unwrap_or_default(),
            tangent_frames: settings.tangent_frames && any_textured,
            terms: None,
            physical: scene.model_view.map(|_| physical_of(scene, settings)),
        }
    }
}

/// The Blinn highlight of the frame, when the settings ask for one and
/// something lights a filled surface.
fn specular_of(
    settings: &Settings,
    lights: &[ActiveLight],
    stages: &MaterialStages,
) -> Option<Specular> {
    (settings.specular
        && settings.shininess.is_finite()
        && settings.shininess > 0.0
        && !lights.is_empty()
        && settings.display == Display::Fill)
        .then(|| Specular {
            shininess: settings.shininess,
            map: stages.specular_map.clone(),
        })
}

/// The mirrored environment of the frame, when it shows.
fn reflection_of(scene: &Scene, settings: &Settings) -> Option<Reflection> {
    environment_shows(settings).then(|| Reflection {
        map: scene
            .material
            .environment
            .clone()
            .unwrap_or_else(Environment::sky),
        reflectivity: settings.reflectivity.min(1.0),
    })
}

/// The model view's physical terms: tone map, exposure (1 unless positive
/// and finite), the image-based light (the studio unless the scene has its
/// own; none without ambient light) and its turn.
fn physical_of(scene: &Scene, settings: &Settings) -> Physical {
    Physical {
        tone_map: settings.tone_map,
        exposure: if settings.exposure.is_finite() && settings.exposure > 0.0 {
            settings.exposure
        } else {
            1.0
        },
        normal_maps: settings.bump,
        environment: (scene.ambient != Vec3::ZERO).then(|| {
            scene
                .material
                .environment
                .clone()
                .unwrap_or_else(Environment::studio)
        }),
        turn: {
            let a = settings.environment_turn.to_radians();
            if a.is_finite() {
                (a.cos(), a.sin())
            } else {
                (1.0, 0.0)
            }
        },
        backdrop: settings.backdrop,
        ibl_diffuse: settings.ibl_diffuse,
        ibl_specular: settings.ibl_specular,
    }
}

impl Plan {
    /// The plan of the triangles drawn with `material` (an object's own,
    /// not the scene's): this frame's plan with the stages that depend on
    /// the material decided again for it, so each material runs only what
    /// it needs; dot3 reads its normal map whatever `normal_map_file` says.
    /// `any_textured`: some triangle with this material has texture
    /// coordinates.
    pub fn for_material(
        &self,
        material: &Material,
        any_textured: bool,
        settings: &Settings,
    ) -> Plan {
        let stages = MaterialStages::new(material, any_textured, settings, true);
        Plan {
            texture: stages.texture,
            bump: stages.bump,
            bump_strength: stages.bump_strength,
            technique: stages.technique,
            normal_map: stages.normal_map,
            normal_map_from_file: stages.normal_map_from_file,
            footprint: stages.footprint,
            specular: self.specular.as_ref().map(|s| Specular {
                shininess: s.shininess,
                map: stages.specular_map,
            }),
            ..self.clone()
        }
    }
}

impl Plan {
    /// The plan of an object whose material has extra `terms`: the file's
    /// filter and exponent replace the view's, and the shading terms ride
    /// along only when they change a pixel.
    pub fn with_terms(&self, terms: &Arc<MaterialTerms>) -> Plan {
        let mut plan = self.clone();
        plan.uncoloured = terms.colour_factor;
        if let Some(filter) = terms.filter {
            plan.filter = filter;
            plan.footprint = filter.uses_mips()
                && (plan.texture
                    || (plan.bump && plan.height_derivative == HeightDerivative::Filtered));
        }
        if let (Some(s), Some(spec)) = (terms.shininess, plan.specular.as_mut())
            && s.is_finite()
            && s > 0.0
        {
            spec.shininess = s;
        }
        // The model view shades a metallic-roughness material physically,
        // its normal maps (its own, its clearcoat's) applied on the
        // triangles with texture coordinates.
        if let (Some(physical), Some(pbr)) = (&plan.physical, &terms.pbr)
            && plan.display == Display::Fill
            && plan.shading == Shading::Phong
        {
            let coat_normal = pbr.clearcoat.as_ref().is_some_and(|c| c.normal.is_some());
            plan.bump = physical.normal_maps && (pbr.normal.is_some() || coat_normal);
            plan.terms = Some(terms.clone());
            return plan;
        }
        // Flat and Gouraud read only the alpha mask of the terms, and where
        // the specular map is read.
        let shades = plan.display == Display::Fill
            && match plan.shading {
                Shading::Phong => terms.shade(plan.ambient, plan.specular.is_some()),
                Shading::Flat | Shading::Gouraud => {
                    terms.cutout.is_some()
                        || (plan.specular.is_some() && !terms.uvs.specular.is_vertex_uv())
                }
            };
        plan.terms = shades.then(|| terms.clone());
        plan
    }
}

/// What a plan decides from one material: texture fetches, the bump and its
/// normal map, footprints, the specular map.
struct MaterialStages {
    texture: bool,
    bump: bool,
    bump_strength: f32,
    technique: Technique,
    normal_map: Option<Arc<NormalMap>>,
    normal_map_from_file: bool,
    footprint: bool,
    specular_map: Option<Arc<Level>>,
}

impl MaterialStages {
    /// `own`: an object's own material, whose normal map dot3 always reads
    /// (`normal_map_file` chooses between `--normal-map` and the height
    /// map for the scene's material only).
    fn new(material: &Material, any_textured: bool, settings: &Settings, own: bool) -> Self {
        let texture = settings.texture && any_textured;
        let strength = settings.bump_strength;
        // The file's normal map, when dot3 is asked for and is to read it:
        // it shows even on a texture whose height map is flat.
        let file_map = material
            .normal_map
            .as_ref()
            .filter(|_| (own || settings.normal_map_file) && settings.technique == Technique::Dot3);
        let bump = bump_shows(settings)
            && any_textured
            && (file_map.is_some() || !material.texture.height_is_flat());
        let footprint = settings.filter.uses_mips()
            && (texture || (bump && settings.height_derivative == HeightDerivative::Filtered));
        let technique = if bump {
            settings.technique
        } else {
            Technique::Blinn
        };
        let file_map = file_map.filter(|_| technique == Technique::Dot3);
        let normal_map = (technique == Technique::Dot3).then(|| match file_map {
            Some(file) => file.for_strength(strength).0,
            None => {
                let scale = normal_map_scale(strength);
                material.texture.normal_map(scale).0
            }
        });
        MaterialStages {
            texture,
            bump,
            bump_strength: if bump { strength } else { 0.0 },
            technique,
            normal_map,
            normal_map_from_file: file_map.is_some(),
            footprint,
            specular_map: material.specular_map.clone().filter(|_| any_textured),
        }
    }
}

/// The light (index in `lights`) whose shadows are drawn this frame and
/// what casts them, or `None` when no shadow pass is needed.
fn shadow_light(
    scene: &Scene,
    display: Display,
    rotation: Mat4,
    lights: &[ActiveLight],
) -> Option<(usize, Vec<Caster>)> {
    // The cheap exit first: a lone convex object never needs the pass.
    if scene.objects.len() < 2 && scene.objects.iter().all(|o| o.mesh.convex) {
        return None;
    }
    // Points and lines are coloured without the map.
    if display != Display::Fill {
        return None;
    }
    // The light emboss follows too (the first of equally bright ones).
    let index = strongest_light(lights)?;
    let light = lights[index].position;
    let casters = casters(scene, rotation, light);
    let (centre, radius) = enclose(&casters)?;
    // A light inside the casters' bounds cannot see them through one frustum.
    (light.distance(centre) > radius * 1.01).then_some((index, casters))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn light(c: f32) -> ActiveLight {
        ActiveLight {
            position: Vec3::ONE,
            color: Vec3::splat(c),
            falloff: relief_scene::light::Falloff::Setting,
        }
    }

    #[test]
    fn strongest_is_the_brightest_first_on_ties() {
        assert_eq!(strongest_light(&[]), None);
        assert_eq!(
            strongest_light(&[light(0.3), light(1.0), light(1.0)]),
            Some(1)
        );
    }
}
