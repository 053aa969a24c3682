//! What relief draws a glTF file without, named once in one plain line
//! (docs/models.md, "What is not drawn"): the extensions the file uses
//! that relief does not read, and maps on a third
//! texture coordinate set (only two are stored per primitive: such a map
//! reads the first).

use super::sampling::{Reading, maps_of};

/// The extensions relief reads when a file uses them.
pub(super) const READ: &[&str] = &[
    "EXT_meshopt_compression",
    "EXT_texture_webp",
    "KHR_draco_mesh_compression",
    "KHR_lights_punctual",
    "KHR_materials_clearcoat",
    "KHR_materials_emissive_strength",
    "KHR_materials_ior",
    "KHR_materials_sheen",
    "KHR_materials_specular",
    "KHR_materials_transmission",
    "KHR_materials_unlit",
    "KHR_mesh_quantization",
    "KHR_meshopt_compression",
    "KHR_texture_basisu",
    "KHR_texture_transform",
];

/// The line naming what `document` has that is not drawn, if anything.
pub(super) fn note(name: &str, document: &::gltf::Document) -> Option<String> {
    let mut parts: Vec<String> = Vec::new();
    let third = document
        .materials()
        .filter(|m| third_set(document, m))
        .filter_map(|m| m.index())
        .map(|i| format!("materials[{i}]"))
        .collect::<Vec<_>>();
    if !third.is_empty() {
        parts.push(format!(
            "a third texture coordinate set ({}: its maps read the first)",
            third.join(", ")
        ));
    }
    let skipped: Vec<String> = document
        .extensions_used()
        .filter(|e| !READ.contains(e))
        .map(relief_core::sanitize::clean)
        .collect();
    if !skipped.is_empty() {
        let word = if skipped.len() == 1 {
            "extension"
        } else {
            "extensions"
        };
        parts.push(format!("the {word} {}", skipped.join(", ")));
    }
    (!parts.is_empty()).then(|| format!("model {name}: drawn without {}", parts.join("; ")))
}

/// Whether material `m`'s maps read more than two texture coordinate sets.
fn third_set(document: &::gltf::Document, m: &::gltf::Material) -> bool {
    let mut sets: Vec<u32> = maps_of(document, m)
        .iter()
        .map(|r| Reading::of_map(r).set)
        .collect();
    sets.sort_unstable();
    sets.dedup();
    sets.len() > 2
}
