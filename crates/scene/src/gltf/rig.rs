//! A glTF file's animation read into a [`Rig`] (glTF 2.0 §3.7.3 skins,
//! §3.7.2.2 morph targets, §3.11 animations): its node tree, skins, clips,
//! and each drawn part's morph offsets and joint weights. Every accessor
//! is checked as the vertex data's are before it is read.

use ::gltf::Semantic;
use ::gltf::animation::{Interpolation as FileInterpolation, Property};
use ::gltf::scene::Transform;
use glam::{Mat4, Quat, Vec3, Vec4};

use super::accessor;
use super::data::Problem;
use super::reading::{MAX_DEPTH, bytes_of, check_accessor, hold};
use super::validate::Role;
use crate::anim::sampler::{Interpolation, Sampler, unit};
use crate::anim::{Channel, Clip, Influences, Local, MorphTarget, Node, Skin, Target};
use relief_core::budget::Reservation;

/// Whether the file has something that moves or poses its meshes: an
/// animation, a skin, or morph targets with weights set.
pub(super) fn wanted(document: &::gltf::Document) -> bool {
    let weighted = |w: Option<&[f32]>| w.is_some_and(|w| w.iter().any(|&x| x != 0.0));
    document.animations().next().is_some()
        || document.skins().next().is_some()
        || document.nodes().any(|n| weighted(n.weights()))
        || document.meshes().any(|m| weighted(m.weights()))
}

/// Every node, and an order in which each comes after its parent (nodes
/// in a cycle, or deeper than `MAX_DEPTH`, are left out: they stay at the
/// origin).
pub(super) fn nodes(document: &::gltf::Document) -> (Vec<Node>, Vec<usize>) {
    let count = document.nodes().count();
    let mut parent = vec![None; count];
    for node in document.nodes() {
        for child in node.children() {
            parent[child.index()] = Some(node.index());
        }
    }
    let nodes = document
        .nodes()
        .map(|node| Node {
            parent: parent[node.index()],
            rest: local(node.transform()),
            weights: node
                .weights()
                .or_else(|| node.mesh().and_then(|m| m.weights()))
                .map(<[f32]>::to_vec)
                .unwrap_or_default(),
        })
        .collect();
    let mut order = Vec::with_capacity(count);
    let mut stack: Vec<(usize, usize)> = (0..count)
        .filter(|&n| parent[n].is_none())
        .map(|n| (n, 0))
        .collect();
    let mut seen = vec![false; count];
    while let Some((n, depth)) = stack.pop() {
        if depth > MAX_DEPTH || std::mem::replace(&mut seen[n], true) {
            continue;
        }
        order.push(n);
        let node = document.nodes().nth(n).expect("a node's index is in range");
        stack.extend(node.children().map(|c| (c.index(), depth + 1)));
    }
    (nodes, order)
}

/// A node's transform as the file gives it.
fn local(t: Transform) -> Local {
    match t {
        Transform::Matrix { matrix } => Local::Matrix(Mat4::from_cols_array_2d(&matrix)),
        Transform::Decomposed {
            translation,
            rotation,
            scale,
        } => Local::Trs {
            translation: Vec3::from(translation),
            rotation: unit(Quat::from_array(rotation)),
            scale: Vec3::from(scale),
        },
    }
}

/// The file's skins: joints and inverse bind matrices (the identity when
/// the file gives none).
pub(super) fn skins(
    document: &::gltf::Document,
    buffers: &[Vec<u8>],
    held: (&str, &mut Reservation),
) -> Result<Vec<Skin>, Problem> {
    let (name, held) = held;
    let mut out = Vec::new();
    for skin in document.skins() {
        let place = format!("skins[{}]", skin.index());
        let joints: Vec<usize> = skin.joints().map(|j| j.index()).collect();
        hold(
            held,
            name,
            "the skins",
            bytes_of::<Mat4>(joints.len() as u64),
        )?;
        let inverse_bind = match skin.inverse_bind_matrices() {
            None => vec![Mat4::IDENTITY; joints.len()],
            Some(acc) => {
                check_accessor(
                    &acc,
                    buffers,
                    (Role::Data("inverseBindMatrices"), false),
                    &place,
                )?;
                let kind = (acc.dimensions(), acc.data_type());
                if kind
                    != (
                        ::gltf::accessor::Dimensions::Mat4,
                        ::gltf::accessor::DataType::F32,
                    )
                    || acc.sparse().is_some()
                {
                    return Err(format!(
                        "{place}: its inverseBindMatrices are not a dense MAT4 of floats"
                    ));
                }
                if acc.count() < joints.len() {
                    return Err(format!(
                        "{place}: {} inverseBindMatrices for {} joints",
                        acc.count(),
                        joints.len()
                    ));
                }
                accessor::matrices(&acc, buffers)
                    .take(joints.len())
                    .collect()
            }
        };
        if inverse_bind.iter().any(|m| !m.is_finite()) {
            return Err(format!("{place}: an inverse bind matrix is not finite"));
        }
        out.push(Skin {
            joints,
            inverse_bind,
        });
    }
    Ok(out)
}

/// The file's animations, each a clip.
pub(super) fn clips(
    document: &::gltf::Document,
    buffers: &[Vec<u8>],
    held: (&str, &mut Reservation),
) -> Result<Vec<Clip>, Problem> {
    let (name, held) = held;
    let mut out = Vec::new();
    for anim in document.animations() {
        let mut channels = Vec::new();
        for channel in anim.channels() {
            let place = format!("animations[{}].channels[{}]", anim.index(), channel.index());
            let target = match channel.target().property() {
                Property::Translation => Target::Translation,
                Property::Rotation => Target::Rotation,
                Property::Scale => Target::Scale,
                Property::MorphTargetWeights => Target::Weights,
            };
            let sampler = sampler(&channel.sampler(), target, buffers, &place)?;
            hold(
                held,
                name,
                "the animations",
                bytes_of::<f32>((sampler.times.len() + sampler.values.len()) as u64),
            )?;
            channels.push(Channel {
                node: channel.target().node().index(),
                target,
                sampler,
            });
        }
        let duration = channels
            .iter()
            .map(|c| c.sampler.end())
            .fold(0.0f32, f32::max);
        out.push(Clip {
            name: anim
                .name()
                .map(relief_core::sanitize::clean)
                .filter(|n| !n.is_empty())
                .unwrap_or_else(|| format!("animation {}", anim.index())),
            duration,
            channels,
        });
    }
    Ok(out)
}

/// One channel's sampler: key times finite and never decreasing, and as
/// many values as the keys, the interpolation and the target call for.
fn sampler(
    s: &::gltf::animation::Sampler,
    target: Target,
    buffers: &[Vec<u8>],
    place: &str,
) -> Result<Sampler, Problem> {
    let (input, output) = (s.input(), s.output());
    check_accessor(&input, buffers, (Role::Data("sampler input"), false), place)?;
    check_accessor(
        &output,
        buffers,
        (Role::Data("sampler output"), false),
        place,
    )?;
    let times: Vec<f32> = accessor::floats(&input, buffers).map(|v| v[0]).collect();
    if times.is_empty() || times.iter().any(|t| !t.is_finite()) || !times.is_sorted() {
        return Err(format!(
            "{place}: its key times are not finite numbers in increasing order"
        ));
    }
    let interpolation = match s.interpolation() {
        FileInterpolation::Step => Interpolation::Step,
        FileInterpolation::Linear => Interpolation::Linear,
        FileInterpolation::CubicSpline => Interpolation::CubicSpline,
    };
    let groups = if interpolation == Interpolation::CubicSpline {
        3
    } else {
        1
    };
    let per_key = groups * times.len();
    let (width, components) = match target {
        Target::Translation | Target::Scale => (3, 3),
        Target::Rotation => (4, 4),
        // One scalar per morph target.
        Target::Weights => (output.count() / per_key, 1),
    };
    let elements = match target {
        Target::Weights => width * per_key,
        _ => per_key,
    };
    if width == 0 || output.count() != elements || output.dimensions().multiplicity() != components
    {
        return Err(format!(
            "{place}: its sampler has {} outputs for {} keys",
            output.count(),
            times.len()
        ));
    }
    let mut values = Vec::with_capacity(width * per_key);
    values.extend(accessor::floats(&output, buffers).flat_map(|v| v.into_iter().take(components)));
    Ok(Sampler {
        times,
        values,
        width,
        interpolation,
    })
}

/// A primitive's morph targets (positions and normals, one per vertex of
/// its `n`) and its joints and weights, checked against a skin of
/// `joints` joints.
pub(super) fn part_data(
    prim: &::gltf::Primitive,
    (n, joints, quantized): (usize, Option<usize>, bool),
    buffers: &[Vec<u8>],
    place: &str,
    held: (&str, &mut Reservation),
) -> Result<(Vec<MorphTarget>, Influences), Problem> {
    let (name, held) = held;
    let mut targets = Vec::new();
    for (t, target) in prim.morph_targets().enumerate() {
        let mut read = |acc: Option<::gltf::Accessor>, what: &'static str| {
            let Some(acc) = acc else {
                return Ok(Vec::new());
            };
            check_accessor(&acc, buffers, (Role::Data(what), quantized), place)?;
            if acc.count() != n || acc.dimensions().multiplicity() != 3 {
                return Err(format!(
                    "{place}: morph target {t} has {} {what} offsets for {n} positions",
                    acc.count()
                ));
            }
            hold(held, name, "the morph targets", bytes_of::<Vec3>(n as u64))?;
            Ok(accessor::floats(&acc, buffers)
                .map(|v| Vec4::from(v).truncate())
                .map(|v| if v.is_finite() { v } else { Vec3::ZERO })
                .collect())
        };
        targets.push(MorphTarget {
            positions: read(target.positions(), "POSITION")?,
            normals: read(target.normals(), "NORMAL")?,
        });
    }
    let influences = match joints {
        Some(joints) => influences(prim, (n, joints), buffers, place, (name, held))?,
        None => Influences::default(),
    };
    Ok((targets, influences))
}

/// JOINTS_k and WEIGHTS_k of each vertex, every set the primitive has.
fn influences(
    prim: &::gltf::Primitive,
    (n, joints): (usize, usize),
    buffers: &[Vec<u8>],
    place: &str,
    (name, held): (&str, &mut Reservation),
) -> Result<Influences, Problem> {
    let mut out = Influences::default();
    let mut sets = Vec::new();
    while let (Some(j), Some(w)) = (
        prim.get(&Semantic::Joints(sets.len() as u32)),
        prim.get(&Semantic::Weights(sets.len() as u32)),
    ) {
        sets.push((j, w));
    }
    if sets.is_empty() {
        return Ok(out);
    }
    out.sets = sets.len();
    hold(
        held,
        name,
        "the joint weights",
        bytes_of::<([u16; 4], [f32; 4])>((n * sets.len()) as u64),
    )?;
    let mut per_set = Vec::new();
    for (j, w) in &sets {
        if j.count() != n || w.count() != n {
            return Err(format!(
                "{place}: its JOINTS and WEIGHTS are not one per vertex"
            ));
        }
        let joints_of: Vec<[u16; 4]> = accessor::floats(j, buffers)
            .map(|v| v.map(|x| x as u16))
            .collect();
        if let Some(bad) = joints_of.iter().flatten().find(|&&k| k as usize >= joints) {
            return Err(format!(
                "{place}: joint {bad} is past the skin's {joints} joints"
            ));
        }
        let weights_of: Vec<[f32; 4]> = accessor::floats(w, buffers)
            .map(|v| v.map(|x| if x.is_finite() { x.max(0.0) } else { 0.0 }))
            .collect();
        per_set.push((joints_of, weights_of));
    }
    // Vertex by vertex, its sets one after the other.
    for v in 0..n {
        for (js, ws) in &per_set {
            out.joints.push(js[v]);
            out.weights.push(ws[v]);
        }
    }
    Ok(out)
}
