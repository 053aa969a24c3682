//! A model view scene skinned and animated, for the rows that price
//! posing: `relief bench --physical`'s skinned row and the animation
//! micro-benchmark.

use glam::{Mat4, Quat, Vec3};

use relief_scene::anim::sampler::{Interpolation, Sampler};
use relief_scene::anim::{
    Channel, Clip, Influences, Local, Motion, Node, PartRig, Rig, Skin, Target,
};
use relief_scene::{Scene, Vertex};

/// How far the skinned sphere's upper half turns about Z over
/// `BEND_SECONDS`, in degrees.
pub const BEND_DEGREES: f32 = 40.0;
pub const BEND_SECONDS: f32 = 2.0;

/// `scene`'s first object (the physical bench's sphere) skinned to two joints at its centre, the upper one
/// turning `BEND_DEGREES` about Z over its one clip, the weights blending
/// across the equator (|y| < 0.3); shown at the clip's start, its rest
/// pose, so its pictures are the sphere's.
pub fn skinned(scene: &Scene) -> Scene {
    let mut scene = scene.clone();
    let rest = scene.objects[0].mesh.vertices.clone();
    let rig = bend_rig(
        rest,
        |y| ((y + 0.3) / 0.6).clamp(0.0, 1.0),
        BEND_DEGREES,
        BEND_SECONDS,
    );
    let mut motion = Motion::new(rig);
    motion.show(&mut scene.objects, Some(0), 0.0);
    scene.motion = Some(motion);
    scene
}

/// A rig for one object of vertices `rest`: two joints at the origin,
/// the second, child of the first, turning `degrees` about Z over
/// `seconds` in the one clip ("bend"); a vertex at height y follows the
/// second joint with weight `upper(y)` and the first with the rest.
pub fn bend_rig(rest: Vec<Vertex>, upper: impl Fn(f32) -> f32, degrees: f32, seconds: f32) -> Rig {
    let influences = Influences {
        sets: 1,
        joints: vec![[0, 1, 0, 0]; rest.len()],
        weights: rest
            .iter()
            .map(|v| upper(v.position.y))
            .map(|w| [1.0 - w, w, 0.0, 0.0])
            .collect(),
    };
    let turn = |deg: f32| Quat::from_rotation_z(deg.to_radians()).to_array();
    let node = |parent| Node {
        parent,
        rest: Local::Trs {
            translation: Vec3::ZERO,
            rotation: Quat::IDENTITY,
            scale: Vec3::ONE,
        },
        weights: Vec::new(),
    };
    Rig {
        nodes: vec![node(None), node(Some(0)), node(None)],
        order: vec![0, 1, 2],
        clips: vec![Clip {
            name: "bend".into(),
            duration: seconds,
            channels: vec![Channel {
                node: 1,
                target: Target::Rotation,
                sampler: Sampler {
                    times: vec![0.0, seconds],
                    values: [turn(0.0), turn(degrees)].concat(),
                    width: 4,
                    interpolation: Interpolation::Linear,
                },
            }],
        }],
        skins: vec![Skin {
            joints: vec![0, 1],
            inverse_bind: vec![Mat4::IDENTITY; 2],
        }],
        parts: vec![PartRig {
            node: Some(2),
            skin: Some(0),
            rest,
            source: Vec::new(),
            targets: Vec::new(),
            influences,
            flat: false,
        }],
        fit: Mat4::IDENTITY,
    }
}
