//! The renderer's hard cases (docs/hard-cases.md), one named test each, plus a
//! property test over orientations and every mode combination.

use crate::common;

use std::sync::Arc;

use common::*;
use glam::{Mat4, Vec2, Vec3};
use proptest::prelude::*;
use relief_core::framebuffer::Framebuffer;
use relief_core::settings::{AntiAlias, Filter, HeightDerivative, Normals, Settings, Shading};
use relief_pipeline::render::Renderer;
use relief_scene::Scene;
use relief_scene::{Camera, Face, Light, Mesh, Object, Vertex};
use relief_texture::{Level, Texture};

fn front(settings: Settings) -> Settings {
    Settings {
        rotation: Vec3::ZERO,
        ..settings
    }
}

fn with_camera(mut scene: Scene, eye: Vec3, target: Vec3) -> Scene {
    scene.camera = Camera {
        eye,
        target,
        ..Camera::default()
    };
    scene
}

/// A scene holding one object made of the given triangles.
fn mesh_scene(vertices: Vec<Vertex>, triangles: Vec<[u32; 3]>) -> Scene {
    let mut scene = reference_scene(true);
    let faces: Vec<Face> = triangles
        .into_iter()
        .map(|indices| {
            let p = indices.map(|i| vertices[i as usize].position);
            let n = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or(Vec3::Z);
            Face {
                indices,
                face_normal: n,
                face_tangent_u: Vec3::X,
                face_tangent_v: Vec3::Y,
                facet_center: (p[0] + p[1] + p[2]) / 3.0,
                facet_color: Vec3::ONE,
                textured: true,
            }
        })
        .collect();
    scene.objects = vec![Object {
        mesh: Mesh::new(vertices, &faces, true, false),
        transform: Mat4::IDENTITY,
        rotates: true,
    }];
    scene
}

fn vertex(p: Vec3, n: Vec3) -> Vertex {
    Vertex {
        position: p,
        normal: n,
        uv: Vec2::new(p.x * 0.5 + 0.5, p.y * 0.5 + 0.5),
        color: Vec3::ONE,
        tangent_u: Vec3::X,
        tangent_v: Vec3::Y,
    }
}

fn clean(stats: &relief_core::stats::FrameStats) {
    assert_eq!(
        stats.counters.nonfinite, 0,
        "a NaN or infinite colour was shaded"
    );
}

#[test]
fn triangles_crossing_the_near_plane_are_clipped_not_dropped() {
    // The eye 0.2 above the +Z face, looking almost along it: the near plane
    // cuts the face, part of which lies behind the eye.
    let scene = with_camera(
        reference_scene(false),
        Vec3::new(0.0, 0.0, 1.2),
        Vec3::new(5.0, 0.0, 0.45),
    );
    let (fb, stats) = render(&scene, &front(Settings::default()), 160, 120);
    clean(&stats);
    assert!(stats.counters.triangles_clipped > 0);
    // The camera's right is about +Z, so the face (below the eye in z)
    // fills the left of the view, in perspective; the right stays empty.
    let left = (0..120).all(|y| fb.get(0, y) != scene.background);
    let right = (0..120).all(|y| fb.get(159, y) == scene.background);
    assert!(left && right);
}

#[test]
fn geometry_behind_the_camera_draws_nothing() {
    let scene = with_camera(
        reference_scene(false),
        Vec3::new(0.0, 0.0, 5.0),
        Vec3::new(0.0, 0.0, 10.0),
    );
    let (fb, stats) = render(&scene, &Settings::default(), 160, 120);
    clean(&stats);
    assert_eq!(covered(&scene, &fb), 0);
    assert_eq!(stats.counters.pixels_shaded, 0);
}

#[test]
fn camera_inside_the_cube_sees_only_back_faces_and_draws_nothing() {
    // Faces are culled from inside (the cube is closed and seen from outside only).
    let scene = with_camera(
        reference_scene(false),
        Vec3::new(0.2, -0.1, 0.5),
        Vec3::new(0.0, 0.0, -1.0),
    );
    for shading in [Shading::Flat, Shading::Gouraud, Shading::Phong] {
        let (fb, stats) = render(
            &scene,
            &Settings {
                shading,
                ..Settings::default()
            },
            64,
            48,
        );
        clean(&stats);
        assert_eq!(covered(&scene, &fb), 0);
    }
}

#[test]
fn zero_area_and_collinear_triangles_draw_nothing() {
    let n = Vec3::Z;
    let v = vec![
        vertex(Vec3::new(-1.0, -1.0, 0.0), n),
        vertex(Vec3::new(1.0, 1.0, 0.0), n),
        vertex(Vec3::new(0.0, 0.0, 0.0), n),
        vertex(Vec3::new(0.5, 0.5, 0.0), n),
    ];
    // Repeated vertex, and three collinear points.
    let scene = mesh_scene(v, vec![[0, 0, 1], [0, 1, 2], [0, 2, 3]]);
    let (fb, stats) = render(&scene, &front(Settings::default()), 64, 48);
    clean(&stats);
    assert_eq!(covered(&scene, &fb), 0);
}

#[test]
fn slivers_draw_at_most_a_line_of_pixels() {
    let n = Vec3::Z;
    let v = vec![
        vertex(Vec3::new(-1.5, -1.0, 0.0), n),
        vertex(Vec3::new(1.5, 1.0, 0.0), n),
        vertex(Vec3::new(1.5, 1.0001, 0.0), n),
    ];
    let scene = mesh_scene(v, vec![[0, 1, 2]]);
    let (fb, stats) = render(&scene, &front(Settings::default()), 160, 120);
    clean(&stats);
    assert!(covered(&scene, &fb) <= 4);
}

#[test]
fn huge_coordinates_are_clipped_without_overflow() {
    let n = Vec3::Z;
    let huge = |s: f32| {
        vec![
            vertex(Vec3::new(-s, -s, 0.0), n),
            vertex(Vec3::new(s, -s, 0.0), n),
            vertex(Vec3::new(0.0, s, 0.0), n),
            vertex(Vec3::new(f32::NAN, 0.0, 0.0), n),
            vertex(Vec3::new(f32::INFINITY, 1.0, 0.0), n),
        ]
    };
    let tris = vec![[0, 1, 2], [0, 3, 4], [2, 4, 1]];
    // A triangle a million units wide covers the whole view exactly; the
    // NaN and infinite ones draw nothing.
    let scene = mesh_scene(huge(1e6), tris.clone());
    let (fb, stats) = render(&scene, &front(Settings::default()), 64, 48);
    clean(&stats);
    assert_eq!(covered(&scene, &fb), 64 * 48);
    // At 1e30 clip-space positions keep no precision at all (f32 spacing
    // there is ~1e23): the result must still be finite and in bounds.
    let scene = mesh_scene(huge(1e30), tris);
    for shading in [Shading::Flat, Shading::Gouraud, Shading::Phong] {
        let (_, stats) = render(
            &scene,
            &front(Settings {
                shading,
                ..Settings::default()
            }),
            64,
            48,
        );
        clean(&stats);
    }
}

#[test]
fn normals_that_interpolate_to_zero_fall_back_to_the_facet() {
    // Opposite vertex normals cancel in the middle of the triangle.
    let v = vec![
        vertex(Vec3::new(-1.0, -1.0, 0.0), Vec3::X),
        vertex(Vec3::new(1.0, -1.0, 0.0), Vec3::NEG_X),
        vertex(Vec3::new(0.0, 1.0, 0.0), Vec3::ZERO),
    ];
    let scene = mesh_scene(v, vec![[0, 1, 2]]);
    for shading in [Shading::Gouraud, Shading::Phong] {
        let (fb, stats) = render(
            &scene,
            &front(Settings {
                shading,
                ..Settings::default()
            }),
            64,
            48,
        );
        clean(&stats);
        assert!(covered(&scene, &fb) > 100);
    }
}

#[test]
fn light_at_the_shaded_point_and_grazing_light_stay_finite() {
    let mut scene = reference_scene(false);
    // A light exactly on the front face's centre, one grazing the face.
    scene
        .lights
        .push(Light::new(Vec3::new(0.0, 0.0, 1.0), Vec3::ONE));
    scene
        .lights
        .push(Light::new(Vec3::new(50.0, 0.0, 1.0), Vec3::ONE));
    for shading in [Shading::Flat, Shading::Gouraud, Shading::Phong] {
        let (_, stats) = render(
            &scene,
            &front(Settings {
                shading,
                ..Settings::default()
            }),
            80,
            60,
        );
        clean(&stats);
    }
}

#[test]
fn many_lights_saturate_to_white_without_overflow() {
    let mut scene = reference_scene(false);
    for i in 0..64 {
        scene.lights.push(Light::new(
            Vec3::new(i as f32 - 32.0, 10.0, 20.0),
            Vec3::ONE,
        ));
    }
    let settings = front(Settings {
        colors: false,
        texture: false,
        ..Settings::default()
    });
    let (fb, stats) = render(&scene, &settings, 80, 60);
    clean(&stats);
    assert_eq!(fb.get(40, 30), [255, 255, 255]);
}

#[test]
fn bump_strength_zero_equals_bump_off_and_huge_strength_stays_finite() {
    let scene = reference_scene(true);
    let off = render(
        &scene,
        &Settings {
            bump: false,
            ..Settings::default()
        },
        160,
        120,
    )
    .0;
    let zero = render(
        &scene,
        &Settings {
            bump_strength: 0.0,
            ..Settings::default()
        },
        160,
        120,
    )
    .0;
    assert_eq!(off, zero);
    for k in [1e6f32, f32::MAX] {
        let (fb, stats) = render(
            &scene,
            &Settings {
                bump_strength: k,
                ..Settings::default()
            },
            160,
            120,
        );
        clean(&stats);
        assert_eq!(covered(&scene, &fb), covered(&scene, &off));
    }
}

#[test]
fn angles_of_a_billion_degrees_nan_and_infinity_are_stable() {
    let scene = reference_scene(false);
    let at = |r: Vec3| {
        render(
            &scene,
            &Settings {
                rotation: r,
                ..Settings::default()
            },
            80,
            60,
        )
        .0
    };
    // 1e9 is exact in f32 and 1e9 mod 360 = 280.
    assert_eq!(at(Vec3::new(1e9, 0.0, 0.0)), at(Vec3::new(280.0, 0.0, 0.0)));
    assert_eq!(
        at(Vec3::new(f32::NAN, 35.0, 0.0)),
        at(Vec3::new(0.0, 35.0, 0.0))
    );
    assert_eq!(
        at(Vec3::new(25.0, f32::INFINITY, f32::NEG_INFINITY)),
        at(Vec3::new(25.0, 0.0, 0.0))
    );
    assert_eq!(
        at(Vec3::new(-90.0, 0.0, 0.0)),
        at(Vec3::new(270.0, 0.0, 0.0))
    );
}

#[test]
fn degenerate_and_extreme_framebuffer_sizes() {
    let scene = reference_scene(false);
    let settings = Settings::default();
    let mut renderer = Renderer::new();
    for (w, h) in [(0, 0), (0, 10), (10, 0), (1, 1), (1, 300), (300, 1), (2, 3)] {
        let mut fb = Framebuffer::new(w, h);
        let stats = renderer.render(&scene, &settings, &mut fb);
        clean(&stats);
        assert_eq!(fb.pixels().len(), w * h);
    }
    // 1×1 looks at the cube's middle: covered.
    let (fb, _) = render(&scene, &settings, 1, 1);
    assert_ne!(fb.get(0, 0), scene.background);
    // Very large: the cube's coverage scales with the area (within 1%).
    let (big, stats) = render(&scene, &Settings::default(), 3200, 2400);
    clean(&stats);
    let ratio = covered(&scene, &big) as f64 / (11_741.0 * 100.0);
    assert!((ratio - 1.0).abs() < 0.01, "{ratio}");
}

/// Renders `scene` at `w`×`h` on 1, 2, 3 and 8 threads, checks every
/// frame and its counters against one thread's, and returns its stats.
fn same_on_any_threads(
    scene: &Scene,
    settings: &Settings,
    w: usize,
    h: usize,
) -> relief_core::stats::FrameStats {
    let frames: Vec<_> = [1, 2, 3, 8]
        .iter()
        .map(|&n| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .unwrap();
            pool.install(|| render(scene, settings, w, h))
        })
        .collect();
    let (first, stats) = &frames[0];
    for (fb, other) in &frames[1..] {
        assert_eq!(fb, first);
        assert_eq!(other.counters, stats.counters);
    }
    *stats
}

#[test]
fn the_same_bits_for_any_number_of_threads() {
    let scene = reference_scene(true);
    for settings in [
        Settings::default(),
        Settings {
            shading: Shading::Gouraud,
            ..Settings::default()
        },
        Settings {
            shading: Shading::Flat,
            texture: false,
            ..Settings::default()
        },
        // Bands of samples, cut at the same rows.
        Settings {
            aa: AntiAlias::Msaa4,
            ..Settings::default()
        },
    ] {
        same_on_any_threads(&scene, &settings, 640, 480);
    }
}

/// A closed UV sphere of 128 × 64 cells (16,384 triangles, about half of
/// them facing the camera): enough that the triangle stage cuts it into
/// chunks on two threads and more (`render::triangles`). Joined, they must
/// give the one-thread frame, bit for bit, in every shading.
#[test]
fn a_big_mesh_gives_the_same_bits_for_any_number_of_threads() {
    use std::f32::consts::PI;
    let (segments, rings) = (128u32, 64u32);
    let mut vertices = Vec::new();
    for j in 0..=rings {
        let theta = PI * j as f32 / rings as f32;
        for i in 0..=segments {
            let phi = 2.0 * PI * i as f32 / segments as f32;
            let n = Vec3::new(
                theta.sin() * phi.cos(),
                theta.cos(),
                theta.sin() * phi.sin(),
            );
            vertices.push(vertex(n * 1.2, n));
        }
    }
    let mut triangles = Vec::new();
    for j in 0..rings {
        for i in 0..segments {
            let a = j * (segments + 1) + i;
            let c = a + segments + 1;
            triangles.push([a, a + 1, c]);
            triangles.push([a + 1, c + 1, c]);
        }
    }
    let mut scene = mesh_scene(vertices, triangles);
    scene.objects[0].mesh.closed = true;
    for settings in [
        Settings::default(),
        Settings {
            shading: Shading::Gouraud,
            ..Settings::default()
        },
        Settings {
            shading: Shading::Flat,
            ..Settings::default()
        },
    ] {
        let stats = same_on_any_threads(&scene, &settings, 320, 240);
        // Thousands of the sphere's triangles are drawn.
        assert!(stats.counters.triangles_drawn > 3_000, "{stats:?}");
    }
}

#[test]
fn resizing_a_reused_renderer_gives_the_same_frame_as_a_fresh_one() {
    let scene = reference_scene(true);
    let settings = Settings::default();
    let mut renderer = Renderer::new();
    let mut fb = Framebuffer::new(640, 480);
    renderer.render(&scene, &settings, &mut fb);
    fb.resize(200, 150);
    renderer.render(&scene, &settings, &mut fb);
    assert_eq!(fb, render(&scene, &settings, 200, 150).0);
}

/// One texel high, non-power-of-two and 1×1 textures render everywhere.
#[test]
fn tiny_and_odd_textures_render() {
    for (w, h) in [(1, 1), (3, 1), (1, 5), (7, 13)] {
        let texels = (0..w * h)
            .map(|i| [0.5, 0.4, 0.3, (i % 3) as f32 / 2.0])
            .collect();
        let tex = Texture::new(
            "odd",
            Level {
                wrap: Default::default(),
                width: w,
                height: h,
                texels,
            },
        );
        let scene = Scene::cube(Arc::new(tex), true);
        for height_derivative in [HeightDerivative::Texel, HeightDerivative::Filtered] {
            for filter in [Filter::Nearest, Filter::Bilinear] {
                let s = Settings {
                    height_derivative,
                    filter,
                    ..Settings::default()
                };
                let (fb, stats) = render(&scene, &s, 80, 60);
                clean(&stats);
                assert!(covered(&scene, &fb) > 500);
            }
        }
    }
}

fn any_settings() -> impl Strategy<Value = Settings> {
    (
        0..3usize,
        any::<bool>(),
        any::<bool>(),
        any::<bool>(),
        any::<bool>(),
        prop_oneof![Just(0.0f32), Just(0.006), 0.0f32..10.0, Just(1e9)],
        (any::<bool>(), any::<bool>()),
        (any::<bool>(), any::<bool>()),
    )
        .prop_map(
            |(shading, face, texture, colors, bump, k, (nearest, texel), (lights, att))| Settings {
                shading: [Shading::Flat, Shading::Gouraud, Shading::Phong][shading],
                normals: if face { Normals::Face } else { Normals::Vertex },
                texture,
                colors,
                bump,
                bump_strength: k,
                filter: if nearest {
                    Filter::Nearest
                } else {
                    Filter::Bilinear
                },
                height_derivative: if texel {
                    HeightDerivative::Texel
                } else {
                    HeightDerivative::Filtered
                },
                lights,
                attenuation: att,
                ..Settings::default()
            },
        )
}

fn any_angle() -> impl Strategy<Value = f32> {
    prop_oneof![
        8 => -720.0f32..720.0,
        1 => prop_oneof![Just(1e9f32), Just(-1e12), Just(f32::NAN), Just(f32::INFINITY), Just(f32::MAX)],
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]

    #[test]
    fn no_nan_and_a_sane_coverage_for_any_orientation_and_modes(
        settings in any_settings(),
        rx in any_angle(), ry in any_angle(), rz in any_angle(),
        all_faces in any::<bool>(),
    ) {
        let scene = reference_scene(all_faces);
        let settings = Settings { rotation: Vec3::new(rx, ry, rz), ..settings };
        let (_, stats) = render(&scene, &settings, 64, 48);
        prop_assert_eq!(stats.counters.nonfinite, 0);
        // The cube at 5 units always covers between ~6% and ~25% of the view.
        let c = coverage(&scene, &settings, 64, 48);
        prop_assert!((150..800).contains(&c), "covered {}", c);
        prop_assert_eq!(stats.counters.pixels_shaded as usize, c);
    }
}

/// A coordinate for the facing pass: mostly ordinary, sometimes zero,
/// tiny, huge, infinite or NaN.
fn any_coordinate() -> impl Strategy<Value = f32> {
    prop_oneof![
        6 => -4.0f32..4.0,
        1 => prop_oneof![
            Just(0.0f32),
            Just(-0.0),
            Just(1e-30),
            Just(-3e-39),
            Just(1e30),
            Just(-f32::MAX),
            Just(f32::INFINITY),
            Just(f32::NAN),
        ],
    ]
}

fn any_point() -> impl Strategy<Value = Vec3> {
    (any_coordinate(), any_coordinate(), any_coordinate()).prop_map(|(x, y, z)| Vec3::new(x, y, z))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// The four-lane facing pass gives the bits of the one-triangle code
    /// for every triangle: degenerate, huge, NaN, a corner past the
    /// vertices, a facet from the side table, from any start.
    #[test]
    fn the_facing_pass_in_lanes_gives_the_bits_of_one_triangle_at_a_time(
        points in prop::collection::vec(any_point(), 1..12),
        corners in prop::collection::vec(([0u32..13, 0u32..13, 0u32..13], 0u8..8, any_point()), 0..40),
        rows in [any_point(), any_point(), any_point()],
        eye in any_point(),
        closed in any::<bool>(),
        start in 0usize..5,
    ) {
        use relief_scene::Facet;
        use relief_scene::facing::Facing;
        use std::sync::atomic::{AtomicU8, Ordering};
        let vertices: Vec<Vertex> = points.iter().map(|&p| vertex(p, Vec3::Z)).collect();
        // Mostly triangles whose facet is their own (computed from the
        // corners), some with a facet of their own in the side table.
        let faces: Vec<Face> = corners
            .iter()
            .map(|&(indices, kind, normal)| {
                let own = indices
                    .iter()
                    .all(|&i| (i as usize) < vertices.len())
                    .then(|| Facet::of_triangle(indices.map(|i| &vertices[i as usize])))
                    .filter(|_| kind > 0);
                let facet = own.unwrap_or(Facet {
                    normal,
                    tangent_u: Vec3::X,
                    tangent_v: Vec3::Y,
                    center: Vec3::ZERO,
                    color: Vec3::ONE,
                });
                Face {
                    indices,
                    face_normal: facet.normal,
                    face_tangent_u: facet.tangent_u,
                    face_tangent_v: facet.tangent_v,
                    facet_center: facet.center,
                    facet_color: facet.color,
                    textured: true,
                }
            })
            .collect();
        let mesh = Mesh::new(vertices, &faces, false, closed);
        let positions: Vec<Vec3> = points.iter().map(|&p| p * 2.0 + Vec3::X).collect();
        let seen: Vec<AtomicU8> = points.iter().map(|_| AtomicU8::new(0)).collect();
        let facing = Facing {
            mesh: &mesh,
            positions: &positions,
            normals: glam::Mat3::from_cols(rows[0], rows[1], rows[2]),
            eye,
            seen: &seen,
            quick: None,
        };
        let start = start.min(faces.len());
        let n = faces.len() - start;
        let (mut facets, mut sides) = (vec![Vec3::splat(7.0); n], vec![9i8; n]);
        facing.run(start, &mut facets, &mut sides);
        for (k, (f, s)) in facets.iter().zip(&sides).enumerate() {
            let (f1, s1) = facing.one(start + k);
            // Rust leaves the sign and payload of a NaN result unspecified
            // (the lanes and the scalar code may order a product's
            // operands differently), so a NaN only has to be a NaN.
            let bits = |v: Vec3| v.to_array().map(|c| if c.is_nan() { u32::MAX } else { c.to_bits() });
            prop_assert_eq!(bits(*f), bits(f1), "facet {}", start + k);
            prop_assert_eq!(*s, s1, "side {}", start + k);
        }
        // Seen: exactly the corners of the triangles run with a side.
        for (v, mark) in seen.iter().enumerate() {
            let corner = faces[start..]
                .iter()
                .zip(&sides)
                .any(|(f, &s)| s != 0 && f.indices.contains(&(v as u32)));
            prop_assert_eq!(mark.load(Ordering::Relaxed), u8::from(corner), "vertex {}", v);
        }
    }
}

/// A model matrix: a rotation, a scale per axis (sometimes far from 1 or
/// mirroring), sometimes a shear, and a translation.
fn any_model() -> impl Strategy<Value = Mat4> {
    (
        (-180.0f32..180.0, -180.0f32..180.0, -180.0f32..180.0),
        prop_oneof![
            3 => Just(Vec3::ONE),
            2 => (0.01f32..100.0).prop_map(Vec3::splat),
            2 => (-3.0f32..3.0, 0.1f32..3.0, 0.001f32..1000.0).prop_map(|(x, y, z)| Vec3::new(x, y, z)),
            1 => Just(Vec3::new(1.0, 1.0, 0.0)),
        ],
        prop_oneof![3 => Just(0.0f32), 1 => -2.0f32..2.0],
        (-50.0f32..50.0, -50.0f32..50.0, -50.0f32..50.0),
    )
        .prop_map(|(angles, scale, shear, t)| {
            let shear = Mat4::from_cols_array(&[
                1.0, shear, 0.0, 0.0, //
                0.0, 1.0, 0.0, 0.0, //
                0.0, 0.0, 1.0, 0.0, //
                0.0, 0.0, 0.0, 1.0,
            ]);
            Mat4::from_translation(Vec3::from(t))
                * relief_scene::rotation_matrix(Vec3::from(angles))
                * shear
                * Mat4::from_scale(scale)
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// The sides made without facets, decided in model space where that is
    /// sure, are those of the one-triangle code for every triangle, under
    /// any model matrix and eye: random, degenerate, huge and NaN corners,
    /// and triangles built to lie within a hair of edge-on to the eye
    /// (where the two formulas' roundings could disagree).
    #[test]
    fn the_sides_alone_are_those_of_one_triangle_at_a_time(
        points in prop::collection::vec(any_point(), 3..12),
        corners in prop::collection::vec([0u32..14, 0u32..14, 0u32..14], 0..40),
        edge_on in prop::collection::vec((0usize..12, 0usize..12, -2.0f32..2.0, -2.0f32..2.0, -6i32..0), 0..24),
        model in any_model(),
        eye in prop_oneof![3 => (-20.0f32..20.0, -20.0f32..20.0, -20.0f32..20.0).prop_map(Vec3::from), 1 => any_point()],
        closed in any::<bool>(),
        start in 0usize..5,
    ) {
        use relief_scene::facing::{Facing, Quick};
        use relief_scene::{Triangle, normal_matrix};
        use std::sync::atomic::{AtomicU8, Ordering};
        let mut points = points;
        let mut triangles: Vec<Triangle> = corners.iter().map(|&c| Triangle::new(c, true)).collect();
        // Edge-on triangles: a third corner in the plane of two others and
        // the model-space eye, moved off it by 10^k of the edge's length.
        let eye_model = model.inverse().transform_point3(eye);
        for &(i, j, s, t, k) in &edge_on {
            let (a, b) = (points[i % points.len()], points[j % points.len()]);
            let normal = (b - a).cross(eye_model - a).normalize_or_zero();
            let c = a + (b - a) * s + (eye_model - a) * t
                + normal * (10f32.powi(k) * (b - a).length());
            points.push(c);
            let n = points.len() as u32 - 1;
            triangles.push(Triangle::new([(i % points.len()) as u32, (j % points.len()) as u32, n], true));
        }
        let vertices: Vec<Vertex> = points.iter().map(|&p| vertex(p, Vec3::Z)).collect();
        let mesh = Mesh::of_triangles(vertices, triangles, false, closed);
        let positions: Vec<Vec3> = points.iter().map(|&p| model.transform_point3(p)).collect();
        let normals = normal_matrix(model);
        let quick = Quick::new(model, normals, eye);
        // A model whose linear part is not too far from a rotation, seen
        // from a finite eye, always has the quick test.
        let linear = glam::DMat3::from_mat4(model.as_dmat4());
        let frobenius = |m: glam::DMat3| (m.x_axis.length_squared() + m.y_axis.length_squared() + m.z_axis.length_squared()).sqrt();
        let condition = frobenius(linear) * frobenius(linear.inverse());
        if condition < 1e3 && eye.is_finite() && eye.abs().max_element() < 1e6 {
            prop_assert!(quick.is_some());
        }
        let marks = || -> Vec<AtomicU8> { points.iter().map(|_| AtomicU8::new(0)).collect() };
        let (seen, seen_one) = (marks(), marks());
        let facing = Facing { mesh: &mesh, positions: &positions, normals, eye, seen: &seen, quick };
        let start = start.min(mesh.triangles.len());
        let n = mesh.triangles.len() - start;
        let mut sides = vec![9i8; n];
        facing.run_sides(start, &mut sides);
        let exact = Facing { seen: &seen_one, ..facing };
        let mut facets = vec![Vec3::ZERO; n];
        let mut sides_one = vec![9i8; n];
        exact.run(start, &mut facets, &mut sides_one);
        for (k, s) in sides.iter().enumerate() {
            prop_assert_eq!(*s, exact.one(start + k).1, "side {}", start + k);
        }
        prop_assert_eq!(&sides, &sides_one);
        for (v, (a, b)) in seen.iter().zip(&seen_one).enumerate() {
            prop_assert_eq!(a.load(Ordering::Relaxed), b.load(Ordering::Relaxed), "vertex {}", v);
        }
    }
}
