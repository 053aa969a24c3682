//! The textures a loaded model's materials draw with, one line each, for
//! the texture panel (docs/models.md): per material its base colour,
//! height, normal, specular, occlusion and emissive maps, and the maps of
//! its glTF extensions (specular strength and colour, clearcoat, sheen).

use std::sync::Arc;

use super::{Material, Scene};
use crate::terms::MaterialTerms;

/// One line per map of each material the scene's objects draw with, in
/// order of first use: the material's number on its first line, which map,
/// its size, and its name (last, so a narrow panel cuts only the name).
pub fn model_textures(scene: &Scene) -> Vec<String> {
    let mut seen: Vec<(*const Material, Option<*const MaterialTerms>)> = Vec::new();
    let mut lines = Vec::new();
    for i in 0..scene.objects.len() {
        let material: &Material = scene.own_material(i).map_or(&scene.material, Arc::as_ref);
        let terms = scene.own_terms(i);
        let key = (material as *const Material, terms.map(Arc::as_ptr));
        if seen.contains(&key) {
            continue;
        }
        seen.push(key);
        let maps = maps_of(material, terms.map(Arc::as_ref));
        for (k, (what, text)) in maps.into_iter().enumerate() {
            let head = if k == 0 {
                format!("material {}:", seen.len())
            } else {
                String::new()
            };
            lines.push(format!("{head:<12}{what:<10}{text}"));
        }
    }
    lines
}

/// (which map, its name and size) of one material.
fn maps_of(m: &Material, terms: Option<&MaterialTerms>) -> Vec<(&'static str, String)> {
    let size = |w: usize, h: usize| format!("{w}×{h}");
    let t = &m.texture;
    let mut out = vec![(
        "base",
        format!("{} {}", size(t.width(), t.height()), t.name),
    )];
    if !t.height_is_flat() {
        out.push(("height", format!("the base's alpha ({})", t.name)));
    }
    if let Some(n) = &m.normal_map {
        let g = n.given();
        out.push(("normal", format!("{} {}", size(g.width, g.height), n.name)));
    }
    if let Some(s) = &m.specular_map
        && (s.width, s.height) != (1, 1)
    {
        out.push(("specular", size(s.width, s.height)));
    }
    if let Some(terms) = terms {
        for (what, level) in [
            ("occlusion", terms.occlusion.as_ref().map(|(l, _)| l)),
            ("emissive", terms.emissive_map.as_ref()),
        ] {
            if let Some(level) = level {
                let name = terms
                    .map_names
                    .iter()
                    .find(|(w, _)| *w == what)
                    .map_or("", |(_, n)| n.as_str());
                out.push((what, format!("{} {name}", size(level.width, level.height))));
            }
        }
        // The extensions' maps of a metallic-roughness material, each named
        // when it was read (a clearcoat picture read whole for intensity
        // and roughness is one line, "coat").
        let pbr = terms.pbr.as_ref();
        let spec = pbr.and_then(|p| p.specular_maps.as_ref());
        let coat = pbr.and_then(|p| p.clearcoat.as_ref());
        let sheen = pbr.and_then(|p| p.sheen.as_ref());
        let dims = |l: &relief_texture::Level| (l.width, l.height);
        for (what, dims) in [
            (
                "spec. str",
                spec.and_then(|s| s.strength.as_deref()).map(dims),
            ),
            (
                "spec. col",
                spec.and_then(|s| s.colour.as_deref()).map(dims),
            ),
            (
                "coat",
                coat.and_then(|c| c.factor_map.as_ref())
                    .map(|(l, _)| dims(l)),
            ),
            (
                "coat rough",
                coat.and_then(|c| c.roughness_map.as_ref())
                    .map(|(l, _)| dims(l)),
            ),
            (
                "coat norm",
                coat.and_then(|c| c.normal.as_deref())
                    .map(|n| (n.width, n.height)),
            ),
            (
                "sheen",
                sheen.and_then(|s| s.colour_map.as_deref()).map(dims),
            ),
            (
                "sheen rgh",
                sheen.and_then(|s| s.roughness_map.as_deref()).map(dims),
            ),
        ] {
            let name = terms.map_names.iter().find(|(w, _)| *w == what);
            if let (Some((w, h)), Some((_, name))) = (dims, name) {
                out.push((what, format!("{} {name}", size(w, h))));
            }
        }
    }
    out
}
