//! Helpers shared by the integration tests.
#![allow(dead_code)]

use std::sync::Arc;

pub mod minified;
pub mod scratch;

use relief_core::framebuffer::Framebuffer;
use relief_core::settings::Settings;
use relief_core::stats::FrameStats;
use relief_pipeline::render::render_frame;
use relief_scene::Scene;
use relief_texture::Texture;
use relief_texture::decode::procedural;

/// The reference scene with the built-in brick texture.
pub fn reference_scene(all_faces: bool) -> Scene {
    Scene::cube(Arc::new(procedural::brick()), all_faces)
}

/// The reference scene with a texture of uniform colour and height.
pub fn plain_scene(texel: [f32; 4], all_faces: bool) -> Scene {
    let level = relief_texture::Level::solid(4, 4, texel);
    Scene::cube(Arc::new(Texture::new("plain", level)), all_faces)
}

pub fn render(scene: &Scene, settings: &Settings, w: usize, h: usize) -> (Framebuffer, FrameStats) {
    render_frame(scene, settings, w, h)
}

/// Pixels that are not the background. A shaded pixel may by chance take
/// the background's exact colour; where that matters use [`coverage`].
pub fn covered(scene: &Scene, fb: &Framebuffer) -> usize {
    fb.pixels()
        .iter()
        .filter(|&&p| p != scene.background)
        .count()
}

/// Pixels the renderer writes, counted exactly: the frame is drawn over two
/// different backgrounds, and no shaded pixel can equal both.
pub fn coverage(scene: &Scene, settings: &Settings, w: usize, h: usize) -> usize {
    let mut other = scene.clone();
    other.background = scene.background.map(|c| c ^ 0x80);
    let (a, _) = render(scene, settings, w, h);
    let (b, _) = render(&other, settings, w, h);
    a.pixels()
        .iter()
        .zip(b.pixels())
        .filter(|&(&pa, &pb)| pa != scene.background || pb != other.background)
        .count()
}
