//! How a glTF material covers what is behind it: `alphaMode` and
//! `alphaCutoff`, and `KHR_materials_transmission` drawn as a thin
//! see-through surface (docs/models.md, "Transparency").

use ::gltf::material::AlphaMode;

/// A material's opacity as relief draws it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Opacity {
    /// Composited over what is behind (BLEND, or transmission), not cut.
    pub blend: bool,
    /// MASK's cutoff; for a blend, the opacity from which it casts a
    /// shadow. `None`: opaque.
    pub cutoff: Option<f32>,
    /// Whether the base colour texture's alpha counts (not for OPAQUE).
    pub reads_alpha: bool,
    /// The constant opacity: the base colour factor's alpha where it
    /// counts, times what transmission leaves.
    pub factor: f32,
}

/// What a thin transmitting surface still reflects head on, as a
/// dielectric does (F0 = 0.04): the opacity it keeps when it transmits
/// everything, so clear glass stays faintly visible.
pub(super) const THIN_REFLECTANCE: f32 = 0.04;

/// The opacity of material `m`.
pub(super) fn of(m: &::gltf::Material) -> Opacity {
    let alpha = m.pbr_metallic_roughness().base_color_factor()[3];
    let t = transmission(m);
    // Of the light behind, a fraction t·(1 − F0) comes through.
    let kept = 1.0 - t * (1.0 - THIN_REFLECTANCE);
    match m.alpha_mode() {
        AlphaMode::Opaque if t > 0.0 => Opacity {
            blend: true,
            cutoff: Some(0.5),
            reads_alpha: false,
            factor: kept,
        },
        AlphaMode::Opaque => Opacity {
            blend: false,
            cutoff: None,
            reads_alpha: false,
            factor: 1.0,
        },
        AlphaMode::Mask => Opacity {
            blend: false,
            cutoff: Some(m.alpha_cutoff().unwrap_or(0.5)),
            reads_alpha: true,
            factor: alpha,
        },
        AlphaMode::Blend => Opacity {
            blend: true,
            cutoff: Some(0.5),
            reads_alpha: true,
            factor: alpha * kept,
        },
    }
}

/// `KHR_materials_transmission`'s `transmissionFactor`, 0 to 1 (0 without
/// the extension; its texture is not read).
fn transmission(m: &::gltf::Material) -> f32 {
    m.extension_value("KHR_materials_transmission")
        .and_then(|e| e.get("transmissionFactor"))
        .and_then(|v| v.as_f64())
        .map(|v| v as f32)
        .filter(|v| v.is_finite())
        .map_or(0.0, |v| v.clamp(0.0, 1.0))
}
