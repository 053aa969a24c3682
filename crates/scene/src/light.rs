//! Point lights and the ambient term.

use glam::Vec3;

/// A diffuse point light in world space (lights stay put while the model turns).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Light {
    pub position: Vec3,
    pub color: Vec3,
    pub enabled: bool,
}

impl Light {
    pub const fn new(position: Vec3, color: Vec3) -> Self {
        Light {
            position,
            color,
            enabled: true,
        }
    }
}

/// Ambient term of the reference scene.
pub const AMBIENT: Vec3 = Vec3::splat(0.1);

/// One strong white light and three weak coloured ones far apart.
pub fn reference_lights() -> Vec<Light> {
    vec![
        Light::new(Vec3::new(3.0, 4.0, 6.0), Vec3::new(1.0, 1.0, 1.0)),
        Light::new(Vec3::new(-8.0, 1.0, 3.0), Vec3::new(0.3, 0.0, 0.0)),
        Light::new(Vec3::new(8.0, -2.0, 3.0), Vec3::new(0.0, 0.3, 0.0)),
        Light::new(Vec3::new(0.0, -8.0, 2.0), Vec3::new(0.0, 0.0, 0.3)),
    ]
}
