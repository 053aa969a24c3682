//! The environment behind the model (`--backdrop`, key `B`): each pixel
//! takes the environment's colour in the direction its ray leaves the
//! camera, turned as the environment's light is (`J`), through the same
//! exposure, tone map and sRGB encoding as the shaded pixels. Made once
//! for a camera direction, frame size and setting, then reused: a drag
//! turns the model, not the camera.

use std::sync::Arc;

use glam::{Mat4, Vec3, Vec4};
use rayon::prelude::*;

use crate::plan::Plan;
use crate::raster::backdrop::Backdrop;
use crate::shade::brdf::display;
use crate::shade::lighting::to_rgb8;
use crate::shade::pbr::turned;
use relief_core::framebuffer::Rgb;
use relief_scene::Camera;

/// What the picture depends on.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Key {
    size: (usize, usize),
    /// The camera's rotation and projection (not its place).
    view: [u32; 12],
    turn: [u32; 2],
    exposure: u32,
    tone_map: relief_core::settings::ToneMap,
    environment: usize,
}

/// The last backdrop made, and what it was made for.
#[derive(Default)]
pub(super) struct BackdropCache {
    made: Option<(Key, Backdrop)>,
}

impl BackdropCache {
    /// The frame's backdrop: the plan's environment when the model view
    /// asks for it and the display fills, else `background`.
    pub(super) fn of(
        &mut self,
        plan: &Plan,
        background: Rgb,
        (width, height, aspect): (usize, usize, f32),
    ) -> &Backdrop {
        let shown = plan
            .physical
            .as_ref()
            .filter(|p| p.backdrop && plan.display == relief_core::settings::Display::Fill)
            .and_then(|p| Some((p, p.environment.as_ref()?)));
        let Some((physical, environment)) = shown else {
            self.made = Some((Key::plain(), Backdrop::Plain(background)));
            return &self.made.as_ref().expect("just set").1;
        };
        let view_proj = plan.camera.projection(aspect) * plan.camera.view();
        let rotation = glam::Mat3::from_mat4(plan.camera.view());
        let key = Key {
            size: (width, height),
            view: rotation_key(rotation, &plan.camera, aspect),
            turn: [physical.turn.0.to_bits(), physical.turn.1.to_bits()],
            exposure: physical.exposure.to_bits(),
            tone_map: physical.tone_map,
            environment: Arc::as_ptr(environment) as usize,
        };
        if !matches!(&self.made, Some((k, _)) if *k == key) {
            let inverse = view_proj.inverse();
            let pixel = |x: usize, y: usize| {
                let d = ray(inverse, (x, y), (width, height));
                let c = environment.lookup(turned(d, physical.turn.0, physical.turn.1));
                to_rgb8(display(c, physical.exposure, physical.tone_map))
            };
            let mut picture = vec![[0u8; 3]; width * height];
            picture
                .par_chunks_mut(width.max(1))
                .enumerate()
                .for_each(|(y, row)| {
                    for (x, p) in row.iter_mut().enumerate() {
                        *p = pixel(x, y);
                    }
                });
            self.made = Some((key, Backdrop::Picture(picture)));
        }
        &self.made.as_ref().expect("just set").1
    }
}

impl Key {
    /// The key of a plain backdrop (never equal to a picture's).
    fn plain() -> Key {
        Key {
            size: (0, 0),
            view: [0; 12],
            turn: [0; 2],
            exposure: 0,
            tone_map: relief_core::settings::ToneMap::None,
            environment: 0,
        }
    }
}

/// The bits of the camera's rotation, field of view (or orthographic
/// height, whose rays are all one direction) and aspect.
fn rotation_key(rotation: glam::Mat3, camera: &Camera, aspect: f32) -> [u32; 12] {
    let m = rotation.to_cols_array();
    let mut key = [0; 12];
    let ortho = camera.orthographic.unwrap_or(0.0);
    let rest = [camera.fov_y_degrees, aspect, ortho];
    for (k, v) in key.iter_mut().zip(m.iter().chain(&rest)) {
        *k = v.to_bits();
    }
    key
}

/// The direction of the ray through the centre of pixel `(x, y)`, from
/// the inverse of the view-projection: far point less near point.
fn ray(inverse: Mat4, (x, y): (usize, usize), (width, height): (usize, usize)) -> Vec3 {
    let nx = 2.0 * (x as f32 + 0.5) / width as f32 - 1.0;
    let ny = 1.0 - 2.0 * (y as f32 + 0.5) / height as f32;
    let at = |z: f32| {
        let p = inverse * Vec4::new(nx, ny, z, 1.0);
        p.truncate() / p.w
    };
    (at(1.0) - at(-1.0)).normalize_or(Vec3::NEG_Z)
}
