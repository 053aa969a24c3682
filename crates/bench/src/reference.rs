//! The reference image: the most accurate frame relief can make of a view.
//!
//! Per-pixel lighting, the filtered height derivative and anisotropic
//! filtering, rendered `factor` times larger on both axes and box-resolved
//! (see `resolve`). The renderer's own AA is left off so the reference does not
//! depend on the AA code it is used to judge.

use std::path::Path;
use std::sync::Arc;

use glam::Vec3;

use super::config::reference_image_setting;
use super::resolve::box_downsample;
use relief_core::framebuffer::Framebuffer;
use relief_core::settings::Settings;
use relief_pipeline::render::Renderer;
use relief_scene::Scene;
use relief_texture::Texture;
use relief_texture::decode::load;
use relief_texture::decode::procedural;

/// The reference frame at `rotation`, `width × height`, supersampled `factor × factor`.
pub fn render(
    scene: &Scene,
    rotation: Vec3,
    width: usize,
    height: usize,
    factor: usize,
) -> Framebuffer {
    let settings = Settings {
        rotation,
        ..reference_image_setting()
    };
    let mut large = Framebuffer::new(width * factor, height * factor);
    Renderer::new().render(scene, &settings, &mut large);
    box_downsample(&large, factor)
}

/// Where the repository keeps the reference texture (known at build time; an
/// installed binary may not find it and falls back to the built-in brick).
const REFERENCE_TEXTURE: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../tests/data/reference-brick.png"
);

/// The bench's texture and a line saying which it is.
pub fn texture() -> (Arc<Texture>, String) {
    match load::load_texture(Path::new(REFERENCE_TEXTURE)) {
        Ok(t) => (Arc::new(t), "reference-brick.png (tests/data)".into()),
        Err(_) => (
            Arc::new(procedural::brick()),
            "built-in brick (tests/data/reference-brick.png not found)".into(),
        ),
    }
}
