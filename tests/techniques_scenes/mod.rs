//! Small scenes for the technique, anti-aliasing and display tests: a quad
//! facing the camera with chosen texture coordinates, texture and lights.
#![allow(dead_code)]

use std::sync::Arc;

use glam::{Mat4, Vec2, Vec3};
use relief_core::framebuffer::Framebuffer;
use relief_scene::Scene;
use relief_scene::{Camera, Face, Light, Material, Mesh, Object, Vertex};
use relief_texture::{Level, Texture};

/// A square of side 2·`half` in the z = `z` plane, facing +Z (the camera),
/// with texture coordinates running from `uv0` to `uv1` across it, white.
pub fn quad_mesh(half: f32, z: f32, uv0: Vec2, uv1: Vec2, color: Vec3) -> Mesh {
    let span = uv1 - uv0;
    let tu = Vec3::X * (2.0 * half / span.x);
    let tv = Vec3::Y * (2.0 * half / span.y);
    let corners = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)];
    let vertices = corners
        .iter()
        .map(|&(s, t)| Vertex {
            position: Vec3::new(half * (2.0 * s - 1.0), half * (2.0 * t - 1.0), z),
            normal: Vec3::Z,
            uv: uv0 + span * Vec2::new(s, t),
            color,
            tangent_u: tu,
            tangent_v: tv,
        })
        .collect();
    let facet = Face {
        indices: [0, 1, 2],
        face_normal: Vec3::Z,
        face_tangent_u: tu,
        face_tangent_v: tv,
        facet_center: Vec3::new(0.0, 0.0, z),
        facet_color: color,
        textured: true,
    };
    let faces = [
        facet,
        Face {
            indices: [0, 2, 3],
            ..facet
        },
    ];
    Mesh::new(vertices, &faces, true, false)
}

/// A scene of the given objects, texture and lights, reference camera.
pub fn scene_of(
    objects: Vec<Object>,
    texture: Texture,
    lights: Vec<Light>,
    ambient: Vec3,
) -> Scene {
    Scene {
        objects,
        material: Material {
            texture: Arc::new(texture),
            specular_map: None,
            normal_map: None,
            environment: None,
        },
        object_materials: Vec::new(),
        object_terms: Vec::new(),
        strokes: Default::default(),
        lights,
        ambient,
        camera: Camera::default(),
        background: relief_scene::BACKGROUND,
        model_view: None,
        motion: None,
        cameras: Vec::new(),
        file_lights: Vec::new(),
    }
}

pub fn fixed(mesh: Mesh) -> Object {
    Object {
        mesh,
        transform: Mat4::IDENTITY,
        rotates: false,
    }
}

pub fn turning(mesh: Mesh) -> Object {
    Object {
        mesh,
        transform: Mat4::IDENTITY,
        rotates: true,
    }
}

/// A `n × n` texture from a function of the texel (x, y) → [r, g, b, height].
pub fn texture_of(n: usize, f: impl Fn(usize, usize) -> [f32; 4]) -> Texture {
    let mut level = Level::solid(n, n, [0.0; 4]);
    for y in 0..n {
        for x in 0..n {
            level.texels.as_mut_slice()[y * n + x] = f(x, y);
        }
    }
    Texture::new("test", level)
}

/// One white light.
pub fn white_light(at: Vec3) -> Vec<Light> {
    vec![Light::new(at, Vec3::ONE)]
}

/// Largest channel difference between two frames of the same size.
pub fn max_diff(a: &Framebuffer, b: &Framebuffer) -> u8 {
    a.pixels()
        .iter()
        .zip(b.pixels())
        .flat_map(|(p, q)| (0..3).map(move |c| p[c].abs_diff(q[c])))
        .max()
        .unwrap_or(0)
}

/// The red channel of the pixel at (x, y).
pub fn red(fb: &Framebuffer, x: usize, y: usize) -> i32 {
    fb.get(x, y)[0] as i32
}
