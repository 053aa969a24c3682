//! The scene's points and lines (`scene::strokes`) over the drawn frame,
//! tested against the depth its triangles left.

use super::Renderer;
use crate::plan::Plan;
use crate::raster::strokes::{DepthCanvas, draw_strokes};
use crate::raster::wire::point_size;
use relief_core::framebuffer::Framebuffer;
use relief_core::settings::{AntiAlias, Display};
use relief_core::stats::Counters;
use relief_scene::Scene;

impl Renderer {
    /// Draws the scene's strokes over `fb` (the frame as drawn, `brush`
    /// times the shown size when supersampled). The depth is the frame's
    /// own (with multisampling, each pixel's farthest sample); the points
    /// and lines displays, drawn without depth, leave the strokes in front
    /// of every surface (a frame with strokes keeps its depth buffer even
    /// for one convex mesh: `Plan::depth`).
    pub(super) fn strokes(
        &mut self,
        scene: &Scene,
        plan: &Plan,
        fb: &mut Framebuffer,
        brush: usize,
    ) -> Counters {
        if scene.strokes.is_empty() {
            return Counters::default();
        }
        let (width, height) = (fb.width(), fb.height());
        let n = width * height;
        let filled = plan.display == Display::Fill && plan.depth;
        let msaa = plan.aa == AntiAlias::Msaa4;
        let mut own: Vec<f32>;
        let depth: &mut [f32] = if filled && !msaa && self.depth.len() == n {
            &mut self.depth
        } else {
            own = if filled && msaa && self.msaa_depth.len() == n {
                self.msaa_depth
                    .iter()
                    .map(|s| s.iter().copied().fold(f32::NEG_INFINITY, f32::max))
                    .collect()
            } else {
                vec![f32::INFINITY; n]
            };
            &mut own
        };
        let aspect = width as f32 / height as f32 * self.pixel_aspect.unwrap_or(1.0);
        let view_proj = plan.camera.projection(aspect) * plan.camera.view();
        let point = point_size(width / brush, height / brush) * brush;
        let mut canvas = DepthCanvas::new(width, height, fb.pixels_mut(), depth);
        draw_strokes(
            &scene.strokes,
            plan.rotation,
            view_proj,
            plan.colors,
            (point, brush),
            &mut canvas,
        )
    }
}
