//! Scenes where a bump map is minified: a far cube and a grazing plane with
//! fine height detail, shared by the filtered-emboss and filtered-dot3 tests.

use std::sync::Arc;

use glam::{Mat4, Vec3};
use proptest::prelude::*;
use relief::Scene;
use relief::scene::{Object, plane};
use relief::texture::{Level, Texture};

/// A repeatable value in 0..1 per texel.
pub fn noise(x: usize, y: usize) -> f32 {
    let mut h = (x as u32).wrapping_mul(0x9E37_79B9) ^ (y as u32).wrapping_mul(0x85EB_CA6B);
    h ^= h >> 15;
    h = h.wrapping_mul(0x2C1B_3C6D);
    h ^= h >> 12;
    (h & 0xFFFF) as f32 / 65535.0
}

/// `n × n` texels: a coarse two-tone colour checker, `height` per texel.
pub fn texture(n: usize, height: impl Fn(usize, usize) -> f32) -> Arc<Texture> {
    let mut level = Level::solid(n, n, [0.0; 4]);
    for y in 0..n {
        for x in 0..n {
            let c = if (x / 16 + y / 16) % 2 == 0 {
                0.85
            } else {
                0.55
            };
            level.texels[y * n + x] = [c, 0.7, 1.0 - c, height(x, y)];
        }
    }
    Arc::new(Texture::new("test", level))
}

/// The reference cube, pulled back until its faces are a few texels per pixel.
pub fn far_cube() -> Scene {
    let mut scene = Scene::cube(texture(128, noise), true);
    scene.camera.eye = Vec3::new(0.0, 0.0, 14.0);
    scene
}

/// A large plane turned nearly edge-on, with a fine checker height.
pub fn grazing_plane() -> Scene {
    let checker = |x: usize, y: usize| {
        if (x / 2 + y / 2).is_multiple_of(2) {
            1.0
        } else {
            0.0
        }
    };
    let mut scene = Scene::model(plane::plane(), texture(128, checker));
    scene.objects = vec![Object {
        mesh: plane::plane(),
        transform: Mat4::from_scale(Vec3::splat(2.5)),
        rotates: true,
    }];
    scene
}

/// Any f32, the awkward ones often.
pub fn any_f32() -> impl Strategy<Value = f32> {
    prop_oneof![
        proptest::num::f32::ANY,
        -4.0f32..4.0,
        -0.05f32..0.05,
        Just(0.0),
        Just(f32::NAN),
        Just(f32::INFINITY),
        Just(f32::NEG_INFINITY),
        Just(f32::MAX),
    ]
}
