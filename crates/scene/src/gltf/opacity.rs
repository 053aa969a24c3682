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
    /// The base colour factor's alpha where it counts (else 1).
    pub alpha: f32,
    /// `transmissionFactor` t: of the light behind, t·(1 − F0) comes
    /// through (times the transmission texture's red, where it has one).
    pub transmission: f32,
}

impl Opacity {
    /// The constant opacity: the alpha times what transmission leaves.
    pub fn factor(&self) -> f32 {
        self.alpha * (1.0 - self.through())
    }

    /// The fraction of the light behind that transmission lets through
    /// where its texture (if any) reads 1: t·(1 − F0).
    pub fn through(&self) -> f32 {
        self.transmission * (1.0 - THIN_REFLECTANCE)
    }
}

/// What a thin transmitting surface still reflects head on, as a
/// dielectric does (F0 = 0.04): the opacity it keeps when it transmits
/// everything, so clear glass stays faintly visible.
pub(super) const THIN_REFLECTANCE: f32 = 0.04;

/// The opacity of material `m`.
pub(super) fn of(m: &::gltf::Material) -> Opacity {
    let alpha = m.pbr_metallic_roughness().base_color_factor()[3];
    let t = transmission(m);
    match m.alpha_mode() {
        AlphaMode::Opaque if t > 0.0 => Opacity {
            blend: true,
            cutoff: Some(0.5),
            reads_alpha: false,
            alpha: 1.0,
            transmission: t,
        },
        AlphaMode::Opaque => Opacity {
            blend: false,
            cutoff: None,
            reads_alpha: false,
            alpha: 1.0,
            transmission: 0.0,
        },
        AlphaMode::Mask => Opacity {
            blend: false,
            cutoff: Some(m.alpha_cutoff().unwrap_or(0.5)),
            reads_alpha: true,
            alpha,
            transmission: 0.0,
        },
        AlphaMode::Blend => Opacity {
            blend: true,
            cutoff: Some(0.5),
            reads_alpha: true,
            alpha,
            transmission: t,
        },
    }
}

/// `KHR_materials_transmission`'s `transmissionFactor`, 0 to 1 (0 without
/// the extension).
fn transmission(m: &::gltf::Material) -> f32 {
    m.extension_value("KHR_materials_transmission")
        .and_then(|e| e.get("transmissionFactor"))
        .and_then(|v| v.as_f64())
        .map(|v| v as f32)
        .filter(|v| v.is_finite())
        .map_or(0.0, |v| v.clamp(0.0, 1.0))
}
