//! Overdraw: a triangle that repeats an earlier one of its mesh is skipped
//! behind the depth buffer (crates/scene/src/repeats.rs). The picture must be the
//! one the mesh without its repeats gives, and the repeats must cost no
//! depth test and no shadow texel. Distinct layers over the same pixels are
//! drawn depth first: the picture of one pass, each pixel shaded once.

use crate::common;

use common::*;
use glam::Vec3;
use proptest::prelude::*;
use relief_core::framebuffer::Framebuffer;
use relief_core::settings::{AntiAlias, Settings, Shading};
use relief_core::stats::Counters;
use relief_core::stats::FrameStats;
use relief_pipeline::plan::Plan;
use relief_pipeline::raster::Band;
use relief_pipeline::raster::pending::Pending;
use relief_pipeline::raster::scan::{OwnedBand, depth_prepass};
use relief_pipeline::render::Renderer;
use relief_pipeline::render::{draw_owned_triangle, draw_triangle};
use relief_pipeline::shade::ShadeCtx;
use relief_pipeline::shadow::{Shadow, ShadowMap};
use relief_scene::Scene;
use relief_scene::repeats::{RepeatSkipper, find_repeats};
use relief_scene::{Mesh, Triangle, obj};
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};

/// A mesh of `faces` over `points`, read as an OBJ (normals, UVs and
/// tangents from the builder), with no face repeated.
fn unique_mesh(points: &[[f32; 3]], faces: &[[u32; 3]]) -> Option<Mesh> {
    let mut text = String::new();
    for p in points {
        text += &format!("v {} {} {}\n", p[0], p[1], p[2]);
    }
    for f in faces {
        text += &format!("f {} {} {}\n", f[0] + 1, f[1] + 1, f[2] + 1);
    }
    obj::parse("random.obj", text).ok()
}

/// `mesh` with copies of its triangles: `copies[k]` = (which triangle, a
/// position after it among the triangles, as a fraction of what follows).
fn with_repeats(mesh: &Mesh, copies: &[(usize, f32)]) -> Mesh {
    let mut triangles: Vec<Triangle> = mesh.triangles.clone();
    for &(which, place) in copies {
        let src = which % mesh.triangles.len();
        // The copy goes after the first copy of triangle `src`.
        let first = triangles
            .iter()
            .position(|t| t.indices == mesh.triangles[src].indices)
            .expect("present");
        let after = first + 1 + ((triangles.len() - first) as f32 * place) as usize;
        triangles.insert(after.min(triangles.len()), mesh.triangles[src]);
    }
    // Copies within one mesh keep their facet data.
    let mut out = mesh.clone();
    out.triangles = triangles;
    out
}

fn scene_of(mesh: Mesh) -> Scene {
    let mut scene = reference_scene(true);
    scene.objects[0].mesh = mesh;
    scene
}

fn pixels_and_stats(scene: &Scene, settings: &Settings) -> (Vec<[u8; 3]>, FrameStats) {
    let (fb, stats) = render(scene, settings, 64, 40);
    (fb.pixels().to_vec(), stats)
}

fn point() -> impl Strategy<Value = [f32; 3]> {
    prop::array::uniform3(-1.0f32..1.0)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, ..ProptestConfig::default() })]

    /// Random overlapping triangles, some drawn again later: the same
    /// pixels as without the copies, and the copies do no depth work.
    #[test]
    fn repeated_triangles_change_no_pixel_and_cost_no_depth_test(
        points in prop::collection::vec(point(), 6..10),
        faces in prop::collection::vec(prop::array::uniform3(0u32..6), 4..14),
        copies in prop::collection::vec((0usize..64, 0.0f32..1.0), 1..24),
        msaa in any::<bool>(),
        rotation in prop::array::uniform3(-180.0f32..180.0),
    ) {
        let faces: Vec<[u32; 3]> = faces
            .into_iter()
            .filter(|f| f[0] != f[1] && f[1] != f[2] && f[0] != f[2])
            .fold(Vec::new(), |mut acc, f| {
                if !acc.contains(&f) {
                    acc.push(f);
                }
                acc
            });
        prop_assume!(!faces.is_empty());
        let Some(mesh) = unique_mesh(&points, &faces) else {
            return Err(TestCaseError::reject("degenerate model"));
        };
        prop_assume!(find_repeats(&mesh.triangles).is_empty());
        let repeated = with_repeats(&mesh, &copies);
        prop_assert!(!find_repeats(&repeated.triangles).is_empty());
        let settings = Settings {
            rotation: Vec3::from(rotation),
            aa: if msaa { AntiAlias::Msaa4 } else { AntiAlias::Off },
            ..Settings::default()
        };
        let (want, plain) = pixels_and_stats(&scene_of(mesh), &settings);
        let (got, skipped) = pixels_and_stats(&scene_of(repeated), &settings);
        prop_assert!(want == got, "the copies changed the picture");
        prop_assert_eq!(plain.counters.depth_tests, skipped.counters.depth_tests);
        prop_assert_eq!(plain.counters.shadow_texels, skipped.counters.shadow_texels);
        prop_assert_eq!(plain.counters.pixels_shaded, skipped.counters.pixels_shaded);
        prop_assert_eq!(plain.counters.triangles_drawn, skipped.counters.triangles_drawn);
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    /// The repeats found by sorting are those a walk in order with a table
    /// of first occurrences finds: each repeat once, with its first copy,
    /// in increasing order of the repeat. Few distinct corners make many
    /// repeats; rotated corners are distinct triangles.
    #[test]
    fn repeats_are_each_later_copy_with_its_first(
        corners in prop::collection::vec(prop::array::uniform3(0u32..4), 0..400),
    ) {
        let triangles: Vec<Triangle> =
            corners.iter().map(|&c| Triangle::new(c, false)).collect();
        let mut first = std::collections::HashMap::new();
        let mut expected = Vec::new();
        for (i, c) in corners.iter().enumerate() {
            let f = *first.entry(*c).or_insert(i as u32);
            if f != i as u32 {
                expected.push((i as u32, f));
            }
        }
        prop_assert_eq!(find_repeats(&triangles), expected);
    }
}

/// The skipper follows the pairs it was given only where the triangles
/// still match: a pair found on an older mesh never hides a triangle.
#[test]
fn stale_repeat_pairs_hide_no_triangle() {
    let tri = |indices| Triangle::new(indices, false);
    let old = [
        tri([0, 1, 2]),
        tri([1, 2, 3]),
        tri([0, 1, 2]),
        tri([1, 2, 3]),
    ];
    let pairs = find_repeats(&old);
    assert_eq!(pairs, vec![(2, 0), (3, 1)]);
    let skipped = |tris: &[Triangle]| {
        let mut s = RepeatSkipper::new(&pairs);
        (0..tris.len())
            .filter(|&i| s.skip(i, tris))
            .collect::<Vec<_>>()
    };
    assert_eq!(skipped(&old), vec![2, 3]);
    // Triangle 2 is no longer a copy of 0; 3 still is of 1.
    let new = [
        tri([0, 1, 2]),
        tri([1, 2, 3]),
        tri([2, 1, 0]),
        tri([1, 2, 3]),
    ];
    assert_eq!(skipped(&new), vec![3]);
    // A shorter list: nothing past its end.
    assert_eq!(skipped(&new[..3]), Vec::<usize>::new());
    // The same indices in another order are another triangle.
    assert!(find_repeats(&[tri([0, 1, 2]), tri([1, 2, 0])]).is_empty());
}

/// Without a depth buffer (a convex mesh, painter's order) a copy still
/// paints: it is drawn, not skipped.
#[test]
fn copies_on_a_convex_mesh_are_drawn() {
    let cube = reference_scene(true).objects[0].mesh.clone();
    assert!(cube.convex);
    let mut twice = cube.clone();
    twice.triangles.extend_from_within(..);
    let settings = Settings::default();
    let (_, once) = pixels_and_stats(&scene_of(cube), &settings);
    let (_, both) = pixels_and_stats(&scene_of(twice), &settings);
    assert_eq!(once.counters.depth_tests, 0);
    assert_eq!(
        both.counters.triangles_drawn,
        2 * once.counters.triangles_drawn
    );
    assert_eq!(both.counters.pixels_shaded, 2 * once.counters.pixels_shaded);
}

/// An `n` × `n` grid of quads facing the camera, gently waved in depth.
fn grid(n: usize) -> Mesh {
    let mut text = String::new();
    for y in 0..=n {
        for x in 0..=n {
            let (u, v) = (x as f32 / n as f32, y as f32 / n as f32);
            text += &format!(
                "v {} {} {}\n",
                u * 2.0 - 1.0,
                v * 2.0 - 1.0,
                0.1 * (u * 9.0).sin()
            );
        }
    }
    let at = |x: usize, y: usize| y * (n + 1) + x + 1;
    for y in 0..n {
        for x in 0..n {
            let (a, b, c, d) = (at(x, y), at(x + 1, y), at(x + 1, y + 1), at(x, y + 1));
            text += &format!("f {a} {b} {c}\nf {a} {c} {d}\n");
        }
    }
    obj::parse("grid.obj", text).expect("a valid OBJ")
}

/// A frame whose cancel hook says stop after `allowed` questions.
fn cancelled_after(allowed: usize) -> (relief_pipeline::render::CancelHook, Arc<AtomicUsize>) {
    let asked = Arc::new(AtomicUsize::new(0));
    let count = asked.clone();
    let hook: relief_pipeline::render::CancelHook =
        Arc::new(move || count.fetch_add(1, Ordering::SeqCst) >= allowed);
    (hook, asked)
}

/// The hook is asked before each band: told to stop after three answers,
/// the frame draws three bands whole and no more, and says it was abandoned.
#[test]
fn a_cancelled_frame_draws_no_band_after_the_stop() {
    let scene = reference_scene(true);
    let settings = Settings::default();
    let mut fb = Framebuffer::new(640, 480);
    let mut renderer = Renderer::new();
    let whole = renderer.render(&scene, &settings, &mut fb);
    assert!(!whole.abandoned);
    assert_eq!(whole.bands_drawn, whole.bands);
    let (hook, _) = cancelled_after(3);
    renderer.set_cancel(Some(hook));
    let cut = renderer.render(&scene, &settings, &mut fb);
    // One thread draws the frame as one band: nothing to stop.
    assert_eq!(cut.abandoned, whole.bands > 3);
    assert_eq!(cut.bands_drawn, whole.bands.min(3));
    assert_eq!(cut.bands, whole.bands);
    if whole.bands > 3 {
        assert!(cut.counters.pixels_shaded < whole.counters.pixels_shaded);
    }
    renderer.set_cancel(None);
    let again = renderer.render(&scene, &settings, &mut fb);
    assert!(!again.abandoned);
    assert_eq!(again.counters, whole.counters);
}

/// Within a band the hook is asked every 1024 triangles: a frame of 3,200
/// triangles drawn by one thread (one band) stops at the second question.
#[test]
fn a_cancelled_band_stops_between_triangles() {
    let mesh = grid(40);
    assert_eq!(mesh.triangles.len(), 3200);
    let scene = scene_of(mesh);
    let settings = Settings {
        rotation: Vec3::ZERO,
        ..Settings::default()
    };
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("a pool");
    one.install(|| {
        let mut fb = Framebuffer::new(320, 200);
        let mut renderer = Renderer::new();
        let whole = renderer.render(&scene, &settings, &mut fb);
        assert_eq!((whole.bands_drawn, whole.bands), (1, 1));
        assert!(
            whole.counters.triangles_drawn > 2048,
            "{:?}",
            whole.counters
        );
        let (hook, asked) = cancelled_after(1);
        renderer.set_cancel(Some(hook));
        let cut = renderer.render(&scene, &settings, &mut fb);
        assert!(cut.abandoned);
        assert_eq!(asked.load(Ordering::SeqCst), 2);
        assert_eq!(cut.bands_drawn, 0);
        assert!(cut.counters.pixels_shaded > 0);
        assert!(cut.counters.pixels_shaded < whole.counters.pixels_shaded);
    });
}

/// The progress a long frame shows counts every triangle a band goes
/// through: all of them once a frame is whole, the 1,024 before the stop
/// of a frame abandoned at its second question.
#[test]
fn a_frame_counts_its_progress_to_the_end_or_to_its_stop() {
    use relief_pipeline::render::{FrameProgress, FrameStep};
    let scene = scene_of(grid(40));
    let settings = Settings {
        rotation: Vec3::ZERO,
        ..Settings::default()
    };
    let progress = Arc::new(FrameProgress::new());
    assert_eq!(progress.now(), FrameStep::Preparing);
    let mut fb = Framebuffer::new(320, 200);
    let mut renderer = Renderer::new();
    renderer.set_progress(Some(progress.clone()));
    // Several threads and bands: every band counts all its visits.
    let whole = renderer.render(&scene, &settings, &mut fb);
    let FrameStep::Drawing { done, total } = progress.now() else {
        panic!("the bands ran");
    };
    assert_eq!(done, total);
    assert_eq!(
        total % whole.bands as u64,
        0,
        "each band visits every triangle"
    );
    let per_band = total / whole.bands as u64;
    let tris = whole.counters.triangles_drawn;
    assert!(
        per_band == tris || per_band == 2 * tris,
        "once, or twice depth first: {per_band} for {tris} triangles"
    );
    // One thread, one band, stopped at the hook's second question.
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("a pool");
    one.install(|| {
        let (hook, _) = cancelled_after(1);
        renderer.set_cancel(Some(hook));
        let cut = renderer.render(&scene, &settings, &mut fb);
        assert!(cut.abandoned);
        let FrameStep::Drawing { done, total } = progress.now() else {
            panic!("the band started");
        };
        assert_eq!(done, 1024);
        assert!(total > done);
    });
}

/// `layers` square quads over the same pixels, each at its own depth but
/// every fourth at the depth of the one before with the other diagonal
/// (two different triangles tie at each of those pixels), front last.
fn stacked_quads(layers: usize) -> Mesh {
    let mut text = String::new();
    let mut depth = -0.5f32;
    for k in 0..layers {
        if k % 4 != 3 {
            depth += 1.0 / layers as f32;
        }
        for (x, y) in [(-0.8, -0.8), (0.8, -0.8), (0.8, 0.8), (-0.8, 0.8)] {
            text += &format!("v {x} {y} {depth}\nvt {} {}\n", x + 0.8, y + 0.8);
        }
        let v = 4 * k as u32 + 1;
        if k % 4 == 3 {
            text += &format!("f {v}/{v} {}/{} {}/{}\n", v + 1, v + 1, v + 3, v + 3);
            text += &format!(
                "f {}/{} {}/{} {}/{}\n",
                v + 1,
                v + 1,
                v + 2,
                v + 2,
                v + 3,
                v + 3
            );
        } else {
            text += &format!("f {v}/{v} {}/{} {}/{}\n", v + 1, v + 1, v + 2, v + 2);
            text += &format!("f {v}/{v} {}/{} {}/{}\n", v + 2, v + 2, v + 3, v + 3);
        }
    }
    obj::parse("stacked.obj", text).expect("a valid OBJ")
}

/// A frame's colours and depths.
type Drawn = (Vec<[u8; 3]>, Vec<f32>);

/// Draws the frame's triangles one pass as the depth test decides, and
/// again depth first (every triangle's depth, then only each pixel's
/// owner shaded): the same colours and the same depths, bit for bit.
fn one_pass_and_depth_first(
    scene: &Scene,
    settings: &Settings,
    w: usize,
    h: usize,
) -> (Drawn, Drawn, Counters) {
    let plan = Plan::new(scene, settings);
    let mut renderer = Renderer::new();
    let (tris, shaders) = renderer.screen_triangles(scene, settings, w, h);
    let mut map = ShadowMap::new();
    if let Some(light) = plan.shadow_light {
        let at = plan.lights[light].position;
        map.render(scene, plan.rotation, at, &plan.shadow_casters, w, h);
    }
    let ctx = ShadeCtx {
        plan: &plan,
        texture: &scene.material.texture,
        shadow: plan.shadow_light.map(|light| Shadow { light, map: &map }),
        packets: true,
    };
    let mut one = (vec![scene.background; w * h], vec![f32::INFINITY; w * h]);
    let mut first = one.clone();
    let mut owner = vec![u32::MAX; w * h];
    let mut counters = Counters::default();
    let mut band = Band {
        y0: 0,
        width: w,
        color: &mut one.0,
        depth: Some(&mut one.1),
        pending: Pending::off(),
    };
    for tri in tris {
        draw_triangle(
            tri,
            &shaders[tri.shader as usize],
            &ctx,
            &mut band,
            &mut counters,
        );
    }
    let mut owned = OwnedBand {
        band: Band {
            y0: 0,
            width: w,
            color: &mut first.0,
            depth: Some(&mut first.1),
            pending: Pending::off(),
        },
        owner: &mut owner,
    };
    counters = Counters::default();
    for tri in tris {
        depth_prepass(tri, &mut owned, &mut counters);
    }
    for tri in tris {
        draw_owned_triangle(
            tri,
            &shaders[tri.shader as usize],
            &ctx,
            &mut owned,
            &mut counters,
        );
    }
    (one, first, counters)
}

/// Depth before shading changes no pixel and no depth, ties between
/// different triangles included (the first at the nearest depth keeps the
/// pixel, as in one pass), on every kind of kernel and on clipped
/// triangles; and each pixel is shaded at most once.
#[test]
fn depth_first_gives_the_pixels_and_depths_of_one_pass() {
    let (w, h) = (48, 40);
    let mut scenes = vec![("stacked", scene_of(stacked_quads(24)))];
    let mut near = scene_of(stacked_quads(12));
    // Close enough that the near plane cuts the nearest quads.
    near.camera.eye *= 0.25;
    scenes.push(("clipped", near));
    scenes.push(("cube", reference_scene(true)));
    for (name, scene) in &scenes {
        for shading in [Shading::Flat, Shading::Gouraud, Shading::Phong] {
            for (specular, rotation) in [(false, Vec3::ZERO), (true, Vec3::new(20.0, -30.0, 5.0))] {
                let settings = Settings {
                    shading,
                    specular,
                    rotation,
                    ..Settings::default()
                };
                let (one, first, counters) = one_pass_and_depth_first(scene, &settings, w, h);
                let what = format!("{name} {shading:?} specular {specular}");
                assert!(one.0 == first.0, "{what}: colours");
                let bits = |d: &[f32]| d.iter().map(|z| z.to_bits()).collect::<Vec<_>>();
                assert!(bits(&one.1) == bits(&first.1), "{what}: depths");
                assert!(counters.pixels_shaded <= (w * h) as u64, "{what}");
            }
        }
    }
}

/// The renderer draws a stack of distinct layers depth first by itself:
/// the picture of one pass, and each pixel shaded at most once (a single
/// pass would shade about one pixel per layer in front of those drawn).
#[test]
fn overdraw_does_not_multiply_shading() {
    let (w, h) = (64, 40);
    let scene = scene_of(stacked_quads(32));
    let settings = Settings::default();
    let (one, _, _) = one_pass_and_depth_first(&scene, &settings, w, h);
    let (fb, stats) = render(&scene, &settings, w, h);
    assert!(fb.pixels() == one.0.as_slice());
    assert!(stats.counters.pixels_shaded > 0);
    assert!(stats.counters.pixels_shaded <= (w * h) as u64);
}
