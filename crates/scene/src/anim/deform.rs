//! A part's vertices made again for a pose: morph targets added to its
//! rest vertices, then carried by its skin's joints (blended by the
//! vertex's weights) or by its node, then fitted to the unit view.

use glam::{Mat3, Mat4, Vec3};
use rayon::prelude::*;

use super::pose::Pose;
use super::rig::{PartRig, Rig};
use crate::mesh::triangle_normal;
use crate::{Triangle, Vertex, normal_matrix};

/// Below this many vertices a part is posed on one thread.
const PARALLEL_MIN: usize = 16_384;

/// What carries a part's vertices for one pose.
enum Carry {
    /// One matrix for all (its node's, fitted), with its normal matrix.
    Rigid(Mat4, Mat3),
    /// Per vertex, the blend of these joint matrices (fitted).
    Skinned(Vec<Mat4>),
}

impl Rig {
    /// Part `p` at `pose` into `out` (as many vertices as its rest), its
    /// `triangles` giving the faces of flat normals.
    pub(super) fn deform(&self, p: usize, pose: &Pose, triangles: &[Triangle], out: &mut [Vertex]) {
        let part = &self.parts[p];
        let node_world = part.node.map_or(Mat4::IDENTITY, |n| pose.world[n]);
        let carry = match part.skin.and_then(|s| self.skins.get(s)) {
            Some(skin) => Carry::Skinned(
                skin.joints
                    .iter()
                    .zip(&skin.inverse_bind)
                    .map(|(&j, ibm)| self.fit * pose.world[j] * *ibm)
                    .collect(),
            ),
            None => {
                let m = self.fit * node_world;
                Carry::Rigid(m, normal_matrix(m))
            }
        };
        let rigid_fallback = self.fit * node_world;
        let weights = part.node.map_or(&[][..], |n| pose.weights[n].as_slice());
        let one = |i: usize, v: &mut Vertex| {
            let rest = &part.rest[i];
            let src = part.source.get(i).map_or(i, |&s| s as usize);
            let (position, normal) = morphed(part, weights, rest, src);
            let (m, nm) = match &carry {
                Carry::Rigid(m, nm) => (*m, *nm),
                Carry::Skinned(joints) => {
                    let m = skin_matrix(part, joints, src).unwrap_or(rigid_fallback);
                    (m, Mat3::from_mat4(m))
                }
            };
            let linear = Mat3::from_mat4(m);
            *v = Vertex {
                position: m.transform_point3(position),
                normal: (nm * normal).normalize_or(Vec3::Z),
                tangent_u: linear * rest.tangent_u,
                tangent_v: linear * rest.tangent_v,
                ..*rest
            };
        };
        if out.len() < PARALLEL_MIN {
            out.iter_mut().enumerate().for_each(|(i, v)| one(i, v));
        } else {
            out.par_iter_mut().enumerate().for_each(|(i, v)| one(i, v));
        }
        if part.flat {
            flat_normals(triangles, out);
        }
    }
}

/// Vertex `rest`'s position and normal with the morph targets' offsets of
/// the file's vertex `src` added at `weights`.
fn morphed(part: &PartRig, weights: &[f32], rest: &Vertex, src: usize) -> (Vec3, Vec3) {
    let (mut position, mut normal) = (rest.position, rest.normal);
    for (target, &w) in part.targets.iter().zip(weights) {
        if w == 0.0 {
            continue;
        }
        if let Some(d) = target.positions.get(src) {
            position += w * *d;
        }
        if let Some(d) = target.normals.get(src) {
            normal += w * *d;
        }
    }
    (position, normal)
}

/// The blend of `joints`' matrices by the file's vertex `src`'s weights,
/// which are made to sum to one; none without weight.
fn skin_matrix(part: &PartRig, joints: &[Mat4], src: usize) -> Option<Mat4> {
    let sets = part.influences.sets;
    let mut sum = Mat4::ZERO;
    let mut total = 0.0;
    for k in src * sets..(src + 1) * sets {
        let (Some(js), Some(ws)) = (
            part.influences.joints.get(k),
            part.influences.weights.get(k),
        ) else {
            continue;
        };
        for (&j, &w) in js.iter().zip(ws) {
            if let Some(m) = joints.get(j as usize).filter(|_| w > 0.0) {
                sum += *m * w;
                total += w;
            }
        }
    }
    (total > 0.0).then(|| sum * (1.0 / total))
}

/// Each triangle's corners take its face's normal (their vertices are
/// their own: a part without normals has one per corner).
fn flat_normals(triangles: &[Triangle], out: &mut [Vertex]) {
    for t in triangles {
        let [a, b, c] = t.indices.map(|i| i as usize);
        if let (Some(pa), Some(pb), Some(pc)) = (out.get(a), out.get(b), out.get(c)) {
            let n = triangle_normal([pa.position, pb.position, pc.position]);
            let n = if n == Vec3::ZERO { Vec3::Z } else { n };
            for i in [a, b, c] {
                out[i].normal = n;
            }
        }
    }
}
