//! The node tree at one instant of one clip.

use glam::{Mat4, Quat, Vec3};

use super::rig::{Local, Rig, Target};

/// Every node's world matrix and morph weights at one instant.
#[derive(Clone, Debug, PartialEq)]
pub struct Pose {
    pub world: Vec<Mat4>,
    pub weights: Vec<Vec<f32>>,
}

impl Rig {
    /// The pose at `time` seconds into `clip` (none, or past the last:
    /// the rest pose). The clip loops: its time is taken modulo its
    /// duration.
    pub fn pose(&self, clip: Option<usize>, time: f32) -> Pose {
        let mut locals: Vec<Local> = self.nodes.iter().map(|n| n.rest).collect();
        let mut weights: Vec<Vec<f32>> = self.nodes.iter().map(|n| n.weights.clone()).collect();
        if let Some(clip) = clip.and_then(|c| self.clips.get(c)) {
            let time = looped(time, clip.duration);
            let mut values = Vec::new();
            for channel in &clip.channels {
                let sampler = &channel.sampler;
                values.resize(sampler.width, 0.0);
                sampler.sample(time, channel.target == Target::Rotation, &mut values);
                let node = channel.node;
                match channel.target {
                    Target::Weights => weights[node].clone_from(&values),
                    target => set(&mut locals[node], target, &values),
                }
            }
        }
        let mut world = vec![Mat4::IDENTITY; self.nodes.len()];
        for &n in &self.order {
            let parent = self.nodes[n].parent.map_or(Mat4::IDENTITY, |p| world[p]);
            world[n] = parent * locals[n].matrix();
        }
        Pose { world, weights }
    }
}

/// `time` within a clip of `duration` seconds, which loops: each lap
/// ends on its last instant (a clip asked at its duration shows its end).
fn looped(time: f32, duration: f32) -> f32 {
    if !(duration > 0.0 && time.is_finite()) {
        return 0.0;
    }
    let t = time.rem_euclid(duration);
    if t == 0.0 && time > 0.0 { duration } else { t }
}

/// Sets one of `local`'s translation, rotation or scale to `v` (a matrix
/// node is first taken apart; glTF does not animate those).
fn set(local: &mut Local, target: Target, v: &[f32]) {
    let (mut scale, mut rotation, mut translation) = match *local {
        Local::Trs {
            translation,
            rotation,
            scale,
        } => (scale, rotation, translation),
        Local::Matrix(m) => m.to_scale_rotation_translation(),
    };
    let finite3 = |v: &[f32]| Some(Vec3::new(v[0], v[1], v[2])).filter(|v| v.is_finite());
    match target {
        Target::Translation => translation = finite3(v).unwrap_or(translation),
        Target::Scale => scale = finite3(v).unwrap_or(scale),
        Target::Rotation => {
            let q = Quat::from_xyzw(v[0], v[1], v[2], v[3]);
            rotation = if q.is_finite() { q } else { rotation };
        }
        Target::Weights => {}
    }
    *local = Local::Trs {
        translation,
        rotation,
        scale,
    };
}

#[cfg(test)]
mod tests {
    use super::super::rig::{Channel, Clip, Node};
    use super::super::sampler::{Interpolation, Sampler};
    use super::*;

    fn trs(translation: Vec3) -> Local {
        Local::Trs {
            translation,
            rotation: Quat::IDENTITY,
            scale: Vec3::ONE,
        }
    }

    /// A root at x = 1 turning a quarter about Y in a clip of 4 s, and a
    /// child 2 along its X.
    fn arm() -> Rig {
        let q = |deg: f32| Quat::from_rotation_y(deg.to_radians()).to_array();
        let turn = Sampler {
            times: vec![0.0, 4.0],
            values: [q(0.0), q(90.0)].concat(),
            width: 4,
            interpolation: Interpolation::Linear,
        };
        Rig {
            nodes: vec![
                Node {
                    parent: Some(1),
                    rest: trs(Vec3::X * 2.0),
                    weights: vec![],
                },
                Node {
                    parent: None,
                    rest: trs(Vec3::X),
                    weights: vec![],
                },
            ],
            order: vec![1, 0],
            clips: vec![Clip {
                name: "turn".into(),
                duration: 4.0,
                channels: vec![Channel {
                    node: 1,
                    target: Target::Rotation,
                    sampler: turn,
                }],
            }],
            skins: vec![],
            parts: vec![],
            fit: Mat4::IDENTITY,
        }
    }

    #[test]
    fn a_child_follows_its_parent_turning() {
        let rig = arm();
        let at = |clip, t| rig.pose(clip, t).world[0].transform_point3(Vec3::ZERO);
        // Rest: 1 + 2 along X.
        assert!((at(None, 0.0) - Vec3::new(3.0, 0.0, 0.0)).length() < 1e-6);
        // A quarter turn about Y (at the end, 4 s) takes +X to −Z.
        assert!((at(Some(0), 4.0) - Vec3::new(1.0, 0.0, -2.0)).length() < 1e-5);
        // Halfway, 45°.
        let h = std::f32::consts::FRAC_PI_4;
        let want = Vec3::new(1.0 + 2.0 * h.cos(), 0.0, -2.0 * h.sin());
        assert!((at(Some(0), 2.0) - want).length() < 1e-5);
        // The clip loops: 6 s is 2 s again.
        assert!((at(Some(0), 6.0) - at(Some(0), 2.0)).length() < 1e-5);
    }
}
