//! A glTF primitive that bounds a convex body is found convex when loaded,
//! as an OBJ, STL or PLY model is: alone, it is drawn without a depth
//! buffer and without a self-shadow pass, to the same pixels.

use glam::Vec3;
use relief_core::settings::Settings;
use relief_pipeline::plan::Plan;

use crate::glb_writer::Bin;

use super::models_gltf::{Doc, Prim, encode, face_on, load_ok, render, scene_of, write};

/// A latitude-longitude sphere of radius 1, `rings` bands of `segments`
/// quads, wound counter-clockwise seen from outside; each ring's first
/// and last vertex coincide (the texture's seam) and each pole is a
/// vertex per segment, as exporters write it.
fn sphere(rings: usize, segments: usize) -> Prim {
    let mut prim = Prim::default();
    // The seam's twins and the poles' copies share their position's bits
    // (sin π and sin 2π are not 0 in f32).
    let angle = |i: usize, n: usize, full: f32| {
        if i == n {
            0.0
        } else {
            full * i as f32 / n as f32
        }
    };
    for r in 0..=rings {
        let theta = std::f32::consts::PI * r as f32 / rings as f32;
        let (ring, y) = if r == 0 || r == rings {
            (0.0, theta.cos().signum())
        } else {
            (theta.sin(), theta.cos())
        };
        for s in 0..=segments {
            let phi = angle(s, segments, std::f32::consts::TAU);
            let p = [ring * phi.cos(), y, -ring * phi.sin()];
            prim.pos.push(p);
            prim.nrm.push(p);
            prim.uv
                .push([s as f32 / segments as f32, r as f32 / rings as f32]);
        }
    }
    let at = |r: usize, s: usize| (r * (segments + 1) + s) as u16;
    for r in 0..rings {
        for s in 0..segments {
            let (a, b, c, d) = (at(r, s), at(r + 1, s), at(r + 1, s + 1), at(r, s + 1));
            if r > 0 {
                prim.idx.extend([a, b, d]);
            }
            if r + 1 < rings {
                prim.idx.extend([b, c, d]);
            }
        }
    }
    prim
}

fn convex_flags(test: &str, doc: &Doc) -> Vec<bool> {
    let path = write(test, &format!("{test}.glb"), &encode(doc));
    let model = load_ok(&path);
    model.parts.iter().map(|p| p.mesh.convex).collect()
}

#[test]
fn a_closed_sphere_is_convex_and_draws_alike_without_the_depth_buffer() {
    let doc = Doc::new(vec![sphere(12, 24)]);
    let path = write("convex_sphere", "sphere.glb", &encode(&doc));
    let scene = scene_of(load_ok(&path));
    assert_eq!(scene.objects.len(), 1);
    assert!(scene.objects[0].mesh.convex, "a closed sphere is convex");
    let settings = face_on();
    assert!(!Plan::new(&scene, &settings).depth);
    let mut flagged = scene.clone();
    flagged.objects[0].mesh.convex = false;
    assert!(Plan::new(&flagged, &settings).depth);
    // Unlit, nothing but the depth buffer differs: the same pixels. Lit,
    // the flagged model also takes the self-shadow pass, which a convex
    // body cannot need: its map only darkens a few pixels at the terminator.
    for rotation in [
        Vec3::ZERO,
        Vec3::new(25.0, 35.0, 0.0),
        Vec3::new(-60.0, 200.0, 10.0),
    ] {
        for lights in [false, true] {
            let settings = Settings {
                rotation,
                lights,
                ..face_on()
            };
            let (a, b) = (render(&scene, &settings), render(&flagged, &settings));
            let pairs = || a.pixels().iter().zip(b.pixels());
            let differ = pairs().filter(|(p, q)| p != q).count();
            if !lights {
                assert_eq!(
                    differ, 0,
                    "at {rotation}, unlit: the depth buffer changed pixels"
                );
            }
            let brighter = pairs().filter(|(p, q)| (0..3).any(|k| q[k] > p[k])).count();
            assert_eq!(brighter, 0, "at {rotation}: the shadow pass only darkens");
            assert!(
                differ < a.pixels().len() / 100,
                "at {rotation}: {differ} pixels"
            );
        }
    }
}

/// A convex sphere with a green line behind it, across the whole view:
/// the sphere hides the line's middle (the frame keeps its depth buffer
/// for the line), the line shows beyond the silhouette.
#[test]
fn a_line_behind_a_convex_sphere_is_hidden_by_it() {
    let line = Prim {
        pos: vec![[-2.0, 0.0, -1.1], [2.0, 0.0, -1.1]],
        col: vec![[0.0, 1.0, 0.0]; 2],
        idx: vec![0, 1],
        mode: Some(1),
        ..Prim::default()
    };
    let doc = Doc::new(vec![sphere(12, 24), line]);
    let path = write("convex_line", "line.glb", &encode(&doc));
    let scene = scene_of(load_ok(&path));
    assert!(scene.objects.len() == 1 && scene.objects[0].mesh.convex);
    assert!(Plan::new(&scene, &face_on()).depth);
    let fb = render(&scene, &face_on());
    let green = |p: [u8; 3]| p[1] > 150 && p[0] < 80 && p[2] < 80;
    let (w, h) = (fb.width(), fb.height());
    let row = |y: usize| {
        (0..w)
            .filter(|&x| green(fb.pixels()[y * w + x]))
            .collect::<Vec<_>>()
    };
    let seen: Vec<usize> = (h / 2 - 2..=h / 2 + 2).flat_map(row).collect();
    // The fitted sphere spans about w/2 ± w/10 here, the line w/2 ± w/6.
    assert!(
        seen.iter().any(|&x| x < w / 2 - w / 8),
        "the line shows left of the sphere"
    );
    assert!(seen.iter().any(|&x| x > w / 2 + w / 8), "and right of it");
    assert!(
        seen.iter().all(|&x| x.abs_diff(w / 2) > w / 16),
        "the sphere hides the line's middle: green at {seen:?}"
    );
}

#[test]
fn a_dent_a_double_sided_material_or_a_morph_target_is_not_taken_as_convex() {
    assert_eq!(
        convex_flags("convex_plain", &Doc::new(vec![sphere(8, 16)])),
        [true]
    );
    // One vertex of the equator (and its seam twin, at s = 0) pushed in.
    let mut dented = sphere(8, 16);
    let equator = 4 * 17;
    for k in [equator, equator + 16] {
        dented.pos[k] = dented.pos[k].map(|c| 0.5 * c);
    }
    assert_eq!(
        convex_flags("convex_dent", &Doc::new(vec![dented])),
        [false]
    );
    let mut sided = Doc::new(vec![Prim {
        material: Some(0),
        ..sphere(8, 16)
    }]);
    sided.materials = r#"[{"doubleSided":true}]"#.into();
    assert_eq!(convex_flags("convex_two_sided", &sided), [false]);
    // An open hemisphere: its edges do not close.
    let mut open = sphere(8, 16);
    open.idx.truncate(open.idx.len() / 2);
    assert_eq!(convex_flags("convex_open", &Doc::new(vec![open])), [false]);
    // A morph target may bend it, whatever its rest pose.
    let path = write("convex_morph", "morph.glb", &morphing_sphere());
    let model = load_ok(&path);
    assert!(model.motion.is_some(), "the morph target is read");
    assert!(!model.parts[0].mesh.convex);
}

/// The sphere with one morph target that pushes its vertices halfway in,
/// its weight 0 at 0 s and 1 at 1 s.
fn morphing_sphere() -> Vec<u8> {
    let prim = sphere(8, 16);
    let flat = |v: &[[f32; 3]]| v.iter().flatten().copied().collect::<Vec<f32>>();
    let mut bin = Bin::default();
    let position = bin.positions(&flat(&prim.pos));
    let normal = bin.floats(&flat(&prim.nrm), "VEC3");
    let inward: Vec<[f32; 3]> = prim.pos.iter().map(|p| p.map(|c| -0.5 * c)).collect();
    let target = bin.positions(&flat(&inward));
    let indices = bin.shorts(&prim.idx, "SCALAR");
    let times = bin.floats(&[0.0, 1.0], "SCALAR");
    let weights = bin.floats(&[0.0, 1.0], "SCALAR");
    bin.glb(&format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],
        "nodes":[{{"mesh":0}}],
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":{position},"NORMAL":{normal}}},
            "indices":{indices},"targets":[{{"POSITION":{target}}}]}}]}}],
        "animations":[{{"samplers":[{{"input":{times},"output":{weights}}}],
            "channels":[{{"sampler":0,"target":{{"node":0,"path":"weights"}}}}]}}]"#
    ))
}
