//! Lights and the ambient term.

use glam::{Mat3, Vec3};

/// A light in world space: the reference scenes' and the model view's rig
/// stay put while the model turns; a model file's own lights turn with it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Light {
    pub position: Vec3,
    /// Its colour times its intensity.
    pub color: Vec3,
    pub enabled: bool,
    /// How its strength falls off on the way to a point.
    pub falloff: Falloff,
    /// A model file's own light: placed in the model, it turns with it.
    pub turns_with_model: bool,
}

/// How a light's strength falls off on its way to a point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Falloff {
    /// As the view's attenuation setting says: not at all, or 1 / (1 + c·d²).
    /// The reference scenes' lights and the model view's rig.
    Setting,
    /// Not at all: a directional light (glTF `directional`), placed
    /// `DIRECTIONAL_DISTANCE` away against its direction.
    None,
    /// 1 / d², brought smoothly to zero at `range` (infinite: never), times
    /// a spot light's cone: glTF `point` and `spot` lights (KHR_lights_punctual).
    InverseSquare { range: f32, cone: Option<Cone> },
}

/// A spot light's cone: full strength within the inner angle, none beyond
/// the outer, and t² between, t = cos θ · `scale` + `offset` clamped to 0…1
/// (θ the angle from the axis).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cone {
    /// Where the light points (unit).
    pub axis: Vec3,
    pub scale: f32,
    pub offset: f32,
}

impl Cone {
    /// The cone between `inner` and `outer` angles (radians) about `axis`.
    pub fn new(axis: Vec3, inner: f32, outer: f32) -> Cone {
        let (cos_inner, cos_outer) = (inner.cos(), outer.cos());
        let scale = 1.0 / (cos_inner - cos_outer).max(1e-3);
        Cone {
            axis,
            scale,
            offset: -cos_outer * scale,
        }
    }
}

/// How far a directional light is placed from the fitted model (whose
/// radius is about 1): its rays then meet the model within 0.06°.
pub const DIRECTIONAL_DISTANCE: f32 = 1000.0;

impl Light {
    pub const fn new(position: Vec3, color: Vec3) -> Self {
        Light {
            position,
            color,
            enabled: true,
            falloff: Falloff::Setting,
            turns_with_model: false,
        }
    }

    /// The light carried by `m` (a rotation, or a turn of the lights): its
    /// place and its cone's axis.
    pub fn moved(mut self, m: Mat3) -> Light {
        self.position = m * self.position;
        if let Falloff::InverseSquare {
            cone: Some(cone), ..
        } = &mut self.falloff
        {
            cone.axis = (m * cone.axis).normalize_or(cone.axis);
        }
        self
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
