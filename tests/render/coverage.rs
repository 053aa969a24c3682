//! Fill-rule conformance: pixels on shared edges are covered exactly once,
//! counted by rasterizing each triangle alone and adding the masks (the
//! additive-blending method of the GL conformance suites).

use crate::common;

use common::*;
use glam::{Vec3, Vec4};
use proptest::prelude::*;
use relief_core::settings::Settings;
use relief_core::stats::Counters;
use relief_pipeline::plan::Plan;
use relief_pipeline::raster::pending::Pending;
use relief_pipeline::raster::{Band, ClipVertex, ScreenTri, raster_triangle, setup};
use relief_pipeline::render::Renderer;
use relief_pipeline::render::draw_triangle;
use relief_pipeline::shade::{ShadeCtx, TriShader};

const MARK: [u8; 3] = [255, 255, 255];

/// Adds the coverage of one triangle to `counts`.
fn add_coverage(tri: &ScreenTri, ctx: &ShadeCtx, w: usize, h: usize, counts: &mut [u32]) {
    let mut color = vec![[0u8; 3]; w * h];
    let mut band = Band {
        y0: 0,
        width: w,
        color: &mut color,
        depth: None,
        pending: Pending::off(),
    };
    raster_triangle(tri, &MARK, ctx, &mut band, &mut Counters::default());
    for (c, p) in counts.iter_mut().zip(&color) {
        *c += (*p == MARK) as u32;
    }
}

/// A screen-space vertex (pixels, y down) as a clip-space vertex with w = 1.
fn at(x: f64, y: f64, w: usize, h: usize) -> ClipVertex {
    ClipVertex {
        pos: Vec4::new(
            (x / w as f64 * 2.0 - 1.0) as f32,
            (1.0 - y / h as f64 * 2.0) as f32,
            0.0,
            1.0,
        ),
        bary: Vec3::X,
    }
}

fn counting_ctx<R>(f: impl FnOnce(&ShadeCtx) -> R) -> R {
    let scene = reference_scene(false);
    let plan = Plan::new(&scene, &Settings::default());
    let ctx = ShadeCtx {
        plan: &plan,
        texture: &scene.material.texture,
        shadow: None,
        packets: true,
    };
    f(&ctx)
}

#[test]
fn cube_triangles_cover_each_pixel_once() {
    let scene = reference_scene(true);
    let (w, h) = (320, 240);
    let mut renderer = Renderer::new();
    let (tris, _) = renderer.screen_triangles(&scene, &Settings::default(), w, h);
    let tris = tris.to_vec();
    assert_eq!(tris.len(), 6, "three visible faces, two triangles each");
    let mut counts = vec![0u32; w * h];
    counting_ctx(|ctx| {
        for tri in &tris {
            add_coverage(tri, ctx, w, h, &mut counts);
        }
    });
    assert!(counts.iter().all(|&c| c <= 1), "a pixel was drawn twice");
    let union = counts.iter().filter(|&&c| c == 1).count();
    assert_eq!(union, 11_741);
}

#[test]
fn every_cube_triangle_is_drawn_through_the_shader_dispatch() {
    // The same coverage through the renderer's own dispatch (one kernel per triangle kind).
    let scene = reference_scene(true);
    let settings = Settings::default();
    let (w, h) = (320, 240);
    let plan = Plan::new(&scene, &settings);
    let mut renderer = Renderer::new();
    let (tris, shaders) = renderer.screen_triangles(&scene, &settings, w, h);
    let ctx = ShadeCtx {
        plan: &plan,
        texture: &scene.material.texture,
        shadow: None,
        packets: true,
    };
    let mut color = vec![scene.background; w * h];
    let mut band = Band {
        y0: 0,
        width: w,
        color: &mut color,
        depth: None,
        pending: Pending::off(),
    };
    let mut counters = Counters::default();
    for tri in tris {
        let shader: &TriShader = &shaders[tri.shader as usize];
        draw_triangle(tri, shader, &ctx, &mut band, &mut counters);
    }
    assert_eq!(counters.pixels_shaded, 11_741);
    let (fb, _) = render(&scene, &settings, w, h);
    assert_eq!(fb.pixels(), &color[..]);
}

/// A grid of quads over the whole viewport, inner vertices jittered on the
/// 1/16-pixel grid, each quad split along a random diagonal: every pixel of
/// the viewport must be covered exactly once.
fn tiled_viewport_counts(
    w: usize,
    h: usize,
    n: usize,
    jitter: &[(i32, i32)],
    diag: &[bool],
) -> Vec<u32> {
    let mut pts = vec![(0.0f64, 0.0f64); (n + 1) * (n + 1)];
    for j in 0..=n {
        for i in 0..=n {
            let mut x = i as f64 * w as f64 / n as f64;
            let mut y = j as f64 * h as f64 / n as f64;
            if i > 0 && i < n && j > 0 && j < n {
                let (dx, dy) = jitter[j * (n + 1) + i];
                x += dx as f64 / 16.0;
                y += dy as f64 / 16.0;
            }
            // Snap to the 1/16 grid, so pixel centres fall exactly on edges.
            pts[j * (n + 1) + i] = ((x * 16.0).round() / 16.0, (y * 16.0).round() / 16.0);
        }
    }
    let mut counts = vec![0u32; w * h];
    counting_ctx(|ctx| {
        for j in 0..n {
            for i in 0..n {
                let q = |a: usize, b: usize| pts[b * (n + 1) + a];
                let p = |a: usize, b: usize| {
                    let (x, y) = q(a, b);
                    at(x, y, w, h)
                };
                // A jittered quad may be non-convex: then only one diagonal
                // splits it into two triangles that do not fold over.
                let orient = |u: (f64, f64), v: (f64, f64), z: (f64, f64)| {
                    (v.0 - u.0) * (z.1 - u.1) - (v.1 - u.1) * (z.0 - u.0)
                };
                let (qa, qb, qc, qd) = (q(i, j), q(i + 1, j), q(i + 1, j + 1), q(i, j + 1));
                let first_ok = orient(qa, qb, qc) > 0.0 && orient(qa, qc, qd) > 0.0;
                let second_ok = orient(qa, qb, qd) > 0.0 && orient(qb, qc, qd) > 0.0;
                let use_first = if first_ok && second_ok {
                    diag[j * n + i]
                } else {
                    first_ok
                };
                let (a, b, c, d) = (p(i, j), p(i + 1, j), p(i + 1, j + 1), p(i, j + 1));
                let halves = if use_first {
                    [[a, b, c], [a, c, d]]
                } else {
                    [[a, b, d], [b, c, d]]
                };
                for tri in halves {
                    if let Some(t) = setup(tri, w, h, 0) {
                        add_coverage(&t, ctx, w, h, &mut counts);
                    }
                }
            }
        }
    });
    counts
}

#[test]
fn regular_grid_with_edges_through_pixel_centres_covers_once() {
    // 8×8 cells of 4 pixels: diagonals pass exactly through pixel centres.
    let n = 8;
    let counts = tiled_viewport_counts(
        32,
        32,
        n,
        &vec![(0, 0); (n + 1) * (n + 1)],
        &vec![true; n * n],
    );
    assert!(counts.iter().all(|&c| c == 1), "{counts:?}");
}

#[test]
fn triangles_meeting_at_a_pixel_centre_cover_it_once() {
    // A fan of 8 triangles around the pixel centre (8.5, 8.5): the centre
    // belongs to exactly one of them, and so does every other pixel.
    let (w, h) = (16, 16);
    let c = (8.5, 8.5);
    let ring = [
        (0.0, 0.0),
        (8.5, 0.0),
        (16.0, 0.0),
        (16.0, 8.5),
        (16.0, 16.0),
        (8.5, 16.0),
        (0.0, 16.0),
        (0.0, 8.5),
    ];
    let mut counts = vec![0u32; w * h];
    counting_ctx(|ctx| {
        for k in 0..ring.len() {
            let (a, b) = (ring[k], ring[(k + 1) % ring.len()]);
            let tri = [at(c.0, c.1, w, h), at(a.0, a.1, w, h), at(b.0, b.1, w, h)];
            let t = setup(tri, w, h, 0).expect("non-degenerate");
            add_coverage(&t, ctx, w, h, &mut counts);
        }
    });
    assert!(counts.iter().all(|&c| c == 1), "{counts:?}");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn jittered_meshes_cover_the_viewport_exactly_once(
        // Less than half the smallest cell (20/6 px), so the mesh never folds.
        jitter in proptest::collection::vec((-24i32..=24, -24i32..=24), 49),
        diag in proptest::collection::vec(any::<bool>(), 36),
        w in 20usize..48,
        h in 20usize..48,
    ) {
        let counts = tiled_viewport_counts(w, h, 6, &jitter, &diag);
        prop_assert!(counts.iter().all(|&c| c == 1));
    }

    #[test]
    fn two_triangles_sharing_an_edge_never_overlap(
        a in (0i32..256, 0i32..256), b in (0i32..256, 0i32..256),
        c in (0i32..256, 0i32..256), d in (0i32..256, 0i32..256),
    ) {
        // Vertices on the 1/16 grid of a 16×16 viewport; c and d on either
        // side of the shared edge ab (or the pair is skipped).
        let (w, h) = (16usize, 16usize);
        let p = |q: (i32, i32)| (q.0 as f64 / 16.0, q.1 as f64 / 16.0);
        let (pa, pb, pc, pd) = (p(a), p(b), p(c), p(d));
        let side = |q: (f64, f64)| (pb.0 - pa.0) * (q.1 - pa.1) - (pb.1 - pa.1) * (q.0 - pa.0);
        prop_assume!(side(pc) * side(pd) < 0.0);
        let mut counts = vec![0u32; w * h];
        counting_ctx(|ctx| {
            for tri in [[pa, pb, pc], [pb, pa, pd]] {
                let v = tri.map(|q| at(q.0, q.1, w, h));
                if let Some(t) = setup(v, w, h, 0) {
                    add_coverage(&t, ctx, w, h, &mut counts);
                }
            }
        });
        prop_assert!(counts.iter().all(|&c| c <= 1));
    }
}
