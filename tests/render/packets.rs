//! Packet shading gives the very bits of the one-pixel loop: every triangle
//! of a frame drawn through the renderer's own dispatch twice, eight pixels
//! at a time where the kernel can, and with packets off (`ShadeCtx::packets`).

use crate::common;

use std::sync::Arc;

use clap::ValueEnum;
use glam::{Vec2, Vec3};
use proptest::prelude::*;
use relief_core::framebuffer::Rgb;
use relief_core::settings::Settings;
use relief_core::settings::{Filter, HeightDerivative, LightVector, Normals, Shading, Technique};
use relief_core::stats::Counters;
use relief_pipeline::plan::Plan;
use relief_pipeline::raster::Band;
use relief_pipeline::raster::pending::Pending;
use relief_pipeline::render::{Renderer, draw_triangle};
use relief_pipeline::shade::ShadeCtx;
use relief_pipeline::shadow::{Shadow, ShadowMap};
use relief_scene::Scene;
use relief_scene::{Built, ModelChoice, SceneKind, build_scene};
use relief_texture::Texture;

/// Draws every triangle of the frame twice, with and without packets, and
/// returns both pictures, their counters, and how many triangles used packets.
fn both(
    scene: &Scene,
    settings: &Settings,
    w: usize,
    h: usize,
) -> (Vec<Rgb>, Vec<Rgb>, Counters, Counters, usize) {
    both_planned(scene, &Plan::new(scene, settings), settings, w, h)
}

/// `both` under a given plan of the scene (a model material's, say).
fn both_planned(
    scene: &Scene,
    plan: &Plan,
    settings: &Settings,
    w: usize,
    h: usize,
) -> (Vec<Rgb>, Vec<Rgb>, Counters, Counters, usize) {
    let plan = plan.clone();
    let mut renderer = Renderer::new();
    let (tris, shaders) = renderer.screen_triangles(scene, settings, w, h);
    // The plan's shadow map, when it asks for one (the shadow scene).
    let mut map = ShadowMap::new();
    if let Some(light) = plan.shadow_light {
        let at = plan.lights[light].position;
        map.render(scene, plan.rotation, at, &plan.shadow_casters, w, h);
    }
    let ctx = |packets| ShadeCtx {
        plan: &plan,
        texture: &scene.material.texture,
        shadow: plan.shadow_light.map(|light| Shadow { light, map: &map }),
        packets,
    };
    let (with, without) = (ctx(true), ctx(false));
    let mut a = vec![[0u8; 3]; w * h];
    let mut b = vec![[0u8; 3]; w * h];
    let (mut ca, mut cb) = (Counters::default(), Counters::default());
    let mut packed = 0;
    for tri in tris {
        let band = |color| Band {
            y0: 0,
            width: w,
            color,
            depth: None,
            pending: Pending::off(),
        };
        let shader = &shaders[tri.shader as usize];
        let before = ca.packet_pixels;
        draw_triangle(tri, shader, &with, &mut band(&mut a), &mut ca);
        draw_triangle(tri, shader, &without, &mut band(&mut b), &mut cb);
        packed += usize::from(ca.packet_pixels > before);
    }
    // The one-pixel loop shades no packet; every other count is the same.
    assert_eq!(cb.packet_pixels, 0);
    cb.packet_pixels = ca.packet_pixels;
    (a, b, ca, cb, packed)
}

/// Whether a bumped triangle of `plan` is drawn with a technique's hook
/// (emboss, dot3 with its map, parallax, POM) rather than Blinn's kernel.
fn hooked(plan: &Plan) -> bool {
    match plan.technique {
        Technique::Blinn => false,
        Technique::Dot3 => plan.normal_map.is_some(),
        _ => true,
    }
}

fn check(settings: Settings, w: usize, h: usize) {
    check_in(&common::reference_scene(true), settings, w, h);
}

fn check_in(scene: &Scene, settings: Settings, w: usize, h: usize) {
    let (a, b, ca, cb, packed) = both(scene, &settings, w, h);
    assert!(packed > 0, "no triangle used packets: {settings:?}");
    let differ = a.iter().zip(&b).filter(|(x, y)| x != y).count();
    assert_eq!(differ, 0, "{differ} pixels differ: {settings:?}");
    assert_eq!(ca, cb, "counters differ: {settings:?}");
}

#[test]
fn every_packet_kernel_matches_the_one_pixel_loop() {
    for shading in [Shading::Flat, Shading::Gouraud, Shading::Phong] {
        for normals in [Normals::Face, Normals::Vertex] {
            for (texture, bump) in [(true, true), (true, false), (false, true), (false, false)] {
                for attenuation in [false, true] {
                    check(
                        Settings {
                            shading,
                            normals,
                            texture,
                            bump,
                            attenuation,
                            ..Settings::default()
                        },
                        160,
                        120,
                    );
                }
            }
        }
    }
    // Every filter and height derivative: the mip filters read per lane
    // with the lane's footprint, like the one-pixel kernels.
    for shading in [Shading::Flat, Shading::Gouraud, Shading::Phong] {
        for &filter in Filter::value_variants() {
            for height_derivative in [HeightDerivative::Texel, HeightDerivative::Filtered] {
                for (texture, bump) in [(true, true), (true, false), (false, true)] {
                    check(
                        Settings {
                            shading,
                            filter,
                            height_derivative,
                            texture,
                            bump,
                            // Turned far over: minified, so the mip chain is read.
                            rotation: Vec3::new(70.0, 35.0, 10.0),
                            ..Settings::default()
                        },
                        48,
                        36,
                    );
                }
            }
        }
    }
    check(
        Settings {
            texture: false,
            filter: Filter::Nearest,
            height_derivative: HeightDerivative::Filtered,
            technique: Technique::Blinn,
            ..Settings::default()
        },
        97,
        61,
    );
}

/// The highlight kernels (flat, Gouraud, Phong with and without texture,
/// bump and a specular map), as the one-pixel loop draws them.
#[test]
fn specular_kernels_match_the_one_pixel_loop() {
    let plain = common::reference_scene(true);
    let mut mapped = common::reference_scene(true);
    // A grey map varying over texels, with odd sizes so lanes wrap.
    let rgba: Vec<u8> = (0..13 * 7 * 4).map(|i| (i * 37 % 256) as u8).collect();
    let grey = relief_texture::specular_map::grey(&Texture::from_rgba8("gloss", 13, 7, &rgba));
    mapped.material.specular_map = Some(Arc::new(grey));
    for scene in [&plain, &mapped] {
        for shading in [Shading::Flat, Shading::Gouraud, Shading::Phong] {
            for normals in [Normals::Face, Normals::Vertex] {
                for (texture, bump) in [(true, true), (true, false), (false, true), (false, false)]
                {
                    for (attenuation, shininess) in [(false, 32.0), (true, 1.0), (false, 500.0)] {
                        let s = Settings {
                            shading,
                            normals,
                            texture,
                            bump,
                            attenuation,
                            specular: true,
                            shininess,
                            ..Settings::default()
                        };
                        check_in(scene, s, 80, 60);
                        let (_, stats) = relief_pipeline::render::render_frame(scene, &s, 80, 60);
                        assert!(stats.counters.specular_evals > 0, "{s:?}");
                    }
                }
            }
        }
        // The mip filters read per lane beside the highlight.
        for &filter in Filter::value_variants() {
            let s = Settings {
                filter,
                specular: true,
                rotation: Vec3::new(70.0, 35.0, 10.0),
                ..Settings::default()
            };
            check_in(scene, s, 48, 36);
        }
    }
}

/// Textures too small for the unwrapped fast path (under 4 texels on an
/// axis) and odd sizes, where lanes wrap at either border.
#[test]
fn small_and_odd_textures_match_the_one_pixel_loop() {
    for (w, h) in [(1, 1), (2, 3), (3, 5), (4, 4), (5, 7), (17, 4)] {
        let rgba: Vec<u8> = (0..w * h * 4).map(|i| (i * 89 % 251) as u8).collect();
        let texture = Texture::from_rgba8("odd", w, h, &rgba);
        let scene = Scene::cube(Arc::new(texture), true);
        for shading in [Shading::Gouraud, Shading::Phong] {
            let settings = Settings {
                shading,
                ..Settings::default()
            };
            let (a, b, ca, cb, packed) = both(&scene, &settings, 120, 90);
            assert!(packed > 0);
            assert!(a == b, "{w}x{h} {shading:?}");
            assert_eq!(ca, cb);
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]
    #[test]
    fn any_orientation_size_and_strength_matches(
        rx in -720.0f32..720.0, ry in -720.0f32..720.0, rz in -720.0f32..720.0,
        w in 1usize..200, h in 1usize..150, k in 0.0f32..0.2, vertex in any::<bool>(),
        specular in any::<bool>(), shininess in 0.5f32..300.0,
    ) {
        let settings = Settings {
            specular,
            shininess,
            rotation: Vec3::new(rx, ry, rz),
            bump_strength: k,
            normals: if vertex { Normals::Vertex } else { Normals::Face },
            ..Settings::default()
        };
        let scene = common::reference_scene(true);
        let (a, b, ca, cb, _) = both(&scene, &settings, w, h);
        prop_assert!(a == b);
        prop_assert_eq!(ca, cb);
    }
}

/// Environment mapping (Phong with and without texture, bump and
/// highlights; the built-in sky and a small loaded-size picture), as the
/// one-pixel loop draws it.
#[test]
fn environment_kernels_match_the_one_pixel_loop() {
    use relief_texture::environment::Environment;
    let sky = common::reference_scene(true);
    let mut small = common::reference_scene(true);
    // Odd sizes, so the seam and the pole rows are read by some lanes.
    small.material.environment = Some(Arc::new(Environment::from_fn("odd", 7, 5, |d| {
        Vec3::splat(0.5) + 0.5 * d
    })));
    for scene in [&sky, &small] {
        for normals in [Normals::Face, Normals::Vertex] {
            for (texture, bump) in [(true, true), (true, false), (false, true), (false, false)] {
                for (specular, reflectivity, rotation) in [
                    (false, 0.35, Vec3::new(25.0, 35.0, 0.0)),
                    (true, 1.0, Vec3::new(70.0, -20.0, 10.0)),
                ] {
                    let s = Settings {
                        normals,
                        texture,
                        bump,
                        specular,
                        environment: true,
                        reflectivity,
                        rotation,
                        ..Settings::default()
                    };
                    check_in(scene, s, 80, 60);
                    let (_, stats) = relief_pipeline::render::render_frame(scene, &s, 80, 60);
                    assert!(stats.counters.env_lookups > 0, "{s:?}");
                }
            }
        }
    }
}

/// Phong and Blinn under a shadow map (the cube over its floor): each lane
/// asks the map once per light that reaches it, as the one-pixel loop does.
#[test]
fn shadowed_kernels_match_the_one_pixel_loop() {
    let texture = Arc::new(relief_texture::decode::procedural::brick());
    let Built::Scene(scene) =
        build_scene(SceneKind::Shadow, &ModelChoice::Cube, texture, false).unwrap()
    else {
        panic!("a 3D scene")
    };
    for normals in [Normals::Face, Normals::Vertex] {
        for (texture, bump) in [(true, true), (true, false), (false, true), (false, false)] {
            for (specular, attenuation, environment) in [
                (false, false, false),
                (true, true, false),
                (true, false, true),
            ] {
                let s = Settings {
                    normals,
                    texture,
                    bump,
                    specular,
                    attenuation,
                    environment,
                    rotation: Vec3::new(20.0, 30.0, 0.0),
                    ..Settings::default()
                };
                assert!(Plan::new(&scene, &s).shadow_light.is_some(), "{s:?}");
                check_in(&scene, s, 96, 72);
                let (_, stats) = relief_pipeline::render::render_frame(&scene, &s, 96, 72);
                assert!(stats.counters.shadow_lookups > 0, "{s:?}");
            }
        }
    }
}

/// A model material's terms (emission with and without a map, ambient
/// occlusion, a tinted highlight with its own exponent, the sampler's
/// filter, an alpha mask) on every Phong kernel, as the one-pixel loop
/// draws them.
#[test]
fn material_terms_match_the_one_pixel_loop() {
    use relief_scene::terms::{Cutout, MaterialTerms};
    let scene = common::reference_scene(true);
    // Odd sizes, so lanes wrap at the borders of both maps.
    let map = |w: usize, h: usize, k: usize| {
        let rgba: Vec<u8> = (0..w * h * 4).map(|i| (i * k % 253) as u8).collect();
        Arc::new(Texture::from_rgba8("terms", w, h, &rgba).base().clone())
    };
    let glowing = MaterialTerms {
        emissive: Vec3::new(0.3, 0.1, 0.05),
        emissive_map: Some(map(5, 3, 71)),
        occlusion: Some((map(7, 9, 43), 0.8)),
        specular_color: Vec3::new(0.9, 0.4, 0.2),
        shininess: Some(12.0),
        filter: Some(Filter::Trilinear),
        ..Default::default()
    };
    let plain_glow = MaterialTerms {
        emissive: Vec3::new(0.05, 0.2, 0.1),
        specular_color: Vec3::new(0.5, 1.0, 0.5),
        ..Default::default()
    };
    let masked = MaterialTerms {
        emissive: Vec3::new(0.1, 0.0, 0.2),
        cutout: Some(Cutout {
            factor: 0.9,
            map: Some(map(11, 6, 97)),
            cutoff: 0.5,
            blend: false,
            transmission: None,
            tint: Vec3::ONE,
        }),
        ..Default::default()
    };
    for terms in [glowing, plain_glow, masked].map(Arc::new) {
        for normals in [Normals::Face, Normals::Vertex] {
            for (texture, bump) in [(true, true), (true, false), (false, true), (false, false)] {
                for (specular, environment, rotation) in [
                    (false, false, Vec3::new(25.0, 35.0, 0.0)),
                    (true, false, Vec3::new(70.0, -20.0, 10.0)),
                    (true, true, Vec3::new(-30.0, 50.0, 5.0)),
                ] {
                    let s = Settings {
                        normals,
                        texture,
                        bump,
                        specular,
                        environment,
                        rotation,
                        ..Settings::default()
                    };
                    let plan = Plan::new(&scene, &s).with_terms(&terms);
                    assert!(plan.terms.is_some(), "{s:?}");
                    let (a, b, ca, cb, packed) = both_planned(&scene, &plan, &s, 80, 60);
                    assert!(packed > 0, "no triangle used packets: {s:?}");
                    assert!(a == b, "{s:?}");
                    assert_eq!(ca, cb, "{s:?}");
                    // The terms show: the picture is not the plain plan's.
                    let (plain, ..) = both(&scene, &s, 80, 60);
                    assert!(a != plain, "{s:?}");
                }
            }
        }
    }
}

/// Maps on their own texture coordinates (`scene::map_uv`): the emissive
/// and normal maps on a second set, moved and turned, the occlusion and
/// specular maps on the first set scaled, all under trilinear filtering
/// (so the carried footprints choose levels), on the Phong and dot3
/// kernels, as the one-pixel loop draws them.
#[test]
fn map_coordinates_match_the_one_pixel_loop() {
    use glam::Affine2;
    use relief_scene::map_uv::{MapUv, MapUvs};
    use relief_scene::terms::MaterialTerms;
    let mut scene = common::reference_scene(true);
    // A second set that is no affine image of the first: every face's
    // Jacobian differs.
    for object in &mut scene.objects {
        let mesh = std::mem::take(&mut object.mesh);
        let uv2 = (mesh.vertices.iter().enumerate())
            .map(|(i, v)| Vec2::new(1.7 * v.uv.y + 0.1 * i as f32, 0.6 * v.uv.x - 0.3))
            .collect();
        object.mesh = mesh.with_uv2(uv2);
    }
    let map = |w: usize, h: usize, k: usize| {
        let rgba: Vec<u8> = (0..w * h * 4).map(|i| (i * k % 253) as u8).collect();
        Arc::new(Texture::from_rgba8("terms", w, h, &rgba).base().clone())
    };
    // A specular map, so the highlight reads one.
    scene.material.specular_map = Some(map(9, 5, 29));
    let turned = |angle: f32, scale: f32, x: f32| {
        Some(Affine2::from_scale_angle_translation(
            Vec2::new(scale, 2.0 - scale),
            angle,
            Vec2::new(x, -x),
        ))
    };
    let terms = Arc::new(MaterialTerms {
        emissive: Vec3::new(0.3, 0.1, 0.05),
        emissive_map: Some(map(5, 3, 71)),
        occlusion: Some((map(7, 9, 43), 0.8)),
        filter: Some(Filter::Trilinear),
        uvs: MapUvs {
            normal: MapUv {
                second: true,
                transform: turned(0.7, 1.3, 0.2),
            },
            specular: MapUv {
                second: false,
                transform: turned(0.0, 3.0, 0.0),
            },
            occlusion: MapUv {
                second: false,
                transform: turned(-0.4, 0.5, 0.1),
            },
            emissive: MapUv {
                second: true,
                transform: None,
            },
            ..MapUvs::default()
        },
        ..Default::default()
    });
    let unmoved = MaterialTerms {
        uvs: MapUvs::default(),
        ..(*terms).clone()
    };
    for (technique, light_vector) in [
        (Technique::Blinn, LightVector::Pixel),
        (Technique::Dot3, LightVector::Pixel),
        (Technique::Dot3, LightVector::Vertex),
    ] {
        for normals in [Normals::Face, Normals::Vertex] {
            for specular in [false, true] {
                let s = Settings {
                    technique,
                    light_vector,
                    normals,
                    specular,
                    rotation: Vec3::new(60.0, 35.0, 0.0),
                    ..Settings::default()
                };
                let plan = Plan::new(&scene, &s).with_terms(&terms);
                let (a, b, ca, cb, packed) = both_planned(&scene, &plan, &s, 80, 60);
                assert!(packed > 0, "no triangle used packets: {s:?}");
                assert!(a == b, "{s:?}");
                assert_eq!(ca, cb, "{s:?}");
                // The coordinates show: the picture is not the one of the
                // same maps on the vertices' UVs.
                let plain = Plan::new(&scene, &s).with_terms(&Arc::new(unmoved.clone()));
                let (c, ..) = both_planned(&scene, &plain, &s, 80, 60);
                assert!(a != c, "{s:?}");
            }
        }
    }
}

/// Emboss, dot3 (light vector per pixel and per vertex), parallax and POM
/// on eight lanes give the one-pixel loop's bits and counts: with and
/// without texture and highlights, face and vertex normals, every filter
/// and height derivative (minified, so the mip chains are read), under a
/// shadow map and with the environment.
#[test]
fn technique_kernels_match_the_one_pixel_loop() {
    let techniques = [
        (Technique::Emboss, LightVector::Pixel),
        (Technique::Dot3, LightVector::Pixel),
        (Technique::Dot3, LightVector::Vertex),
        (Technique::Parallax, LightVector::Pixel),
        (Technique::Pom, LightVector::Pixel),
    ];
    let cube = common::reference_scene(true);
    for (technique, light_vector) in techniques {
        for normals in [Normals::Face, Normals::Vertex] {
            for texture in [true, false] {
                for (specular, attenuation, environment) in [
                    (false, false, false),
                    (true, true, false),
                    (true, false, true),
                ] {
                    let s = Settings {
                        technique,
                        light_vector,
                        normals,
                        texture,
                        specular,
                        attenuation,
                        environment,
                        rotation: Vec3::new(25.0, 35.0, 0.0),
                        ..Settings::default()
                    };
                    assert!(hooked(&Plan::new(&cube, &s)), "{s:?}");
                    check_in(&cube, s, 96, 72);
                    let (_, stats) = relief_pipeline::render::render_frame(&cube, &s, 96, 72);
                    assert!(stats.counters.bump_evals > 0, "{s:?}");
                }
            }
        }
        for &filter in Filter::value_variants() {
            for height_derivative in [HeightDerivative::Texel, HeightDerivative::Filtered] {
                let s = Settings {
                    technique,
                    light_vector,
                    filter,
                    height_derivative,
                    rotation: Vec3::new(70.0, 35.0, 10.0),
                    ..Settings::default()
                };
                check_in(&cube, s, 64, 48);
            }
        }
    }
    // Under the shadow scene's map.
    let texture = Arc::new(relief_texture::decode::procedural::brick());
    let Built::Scene(shadowed) =
        build_scene(SceneKind::Shadow, &ModelChoice::Cube, texture, false).unwrap()
    else {
        panic!("a 3D scene")
    };
    for (technique, light_vector) in techniques {
        for specular in [false, true] {
            let s = Settings {
                technique,
                light_vector,
                specular,
                rotation: Vec3::new(20.0, 30.0, 0.0),
                ..Settings::default()
            };
            assert!(Plan::new(&shadowed, &s).shadow_light.is_some(), "{s:?}");
            check_in(&shadowed, s, 96, 72);
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(16))]
    #[test]
    fn any_technique_orientation_and_strength_matches(
        rx in -720.0f32..720.0, ry in -720.0f32..720.0, rz in -720.0f32..720.0,
        w in 1usize..160, h in 1usize..120, k in 0.0f32..0.2, vertex in any::<bool>(),
        specular in any::<bool>(), t in 0usize..5,
    ) {
        let (technique, light_vector) = [
            (Technique::Emboss, LightVector::Pixel),
            (Technique::Dot3, LightVector::Pixel),
            (Technique::Dot3, LightVector::Vertex),
            (Technique::Parallax, LightVector::Pixel),
            (Technique::Pom, LightVector::Pixel),
        ][t];
        let settings = Settings {
            technique,
            light_vector,
            specular,
            rotation: Vec3::new(rx, ry, rz),
            bump_strength: k,
            normals: if vertex { Normals::Face } else { Normals::Vertex },
            ..Settings::default()
        };
        let scene = common::reference_scene(true);
        let (a, b, ca, cb, _) = both(&scene, &settings, w, h);
        prop_assert!(a == b);
        prop_assert_eq!(ca, cb);
    }
}

/// The physically based kernel with every layer map (docs/shading.md,
/// "Metallic-roughness"): `KHR_materials_specular`'s strength and colour,
/// `KHR_materials_clearcoat`'s intensity and roughness (one picture read
/// once) and its normal map, `KHR_materials_sheen`'s colour and roughness
/// maps, one of them scaled by a texture transform,
/// under the lights and the built-in studio, turned so the view direction
/// differs across each packet: eight lanes give the one-pixel loop's bits
/// and counts, with normal maps on and off.
#[test]
fn the_physical_kernel_with_layer_maps_matches_the_one_pixel_loop() {
    use super::layers::halves_png;
    use super::pbr::{model, solid_png};
    let material = r#"[{"pbrMetallicRoughness":{"baseColorFactor":[0.6,0.3,0.2,1],"metallicFactor":0,"roughnessFactor":0.6},"extensions":{"KHR_materials_specular":{"specularFactor":0.8,"specularColorFactor":[1,0.5,2],"specularTexture":{"index":0},"specularColorTexture":{"index":1,"extensions":{"KHR_texture_transform":{"scale":[2,3],"rotation":0.4}}}},"KHR_materials_clearcoat":{"clearcoatFactor":0.9,"clearcoatRoughnessFactor":0.5,"clearcoatTexture":{"index":2},"clearcoatRoughnessTexture":{"index":2},"clearcoatNormalTexture":{"index":3,"scale":0.7}},"KHR_materials_sheen":{"sheenColorFactor":[0.8,0.6,0.9],"sheenRoughnessFactor":0.7,"sheenColorTexture":{"index":1},"sheenRoughnessTexture":{"index":0}}}}]"#;
    let images = [
        halves_png([0, 0, 0, 40], [0, 0, 0, 250]),
        halves_png([255, 128, 0, 255], [30, 200, 90, 255]),
        halves_png([255, 60, 0, 255], [90, 255, 0, 255]),
        solid_png([170, 150, 240, 255]),
    ];
    let scene = model("packets-layers", 1, material, &images);
    let terms = scene
        .own_terms(0)
        .expect("the quad's material terms")
        .clone();
    let pbr = terms.pbr.as_ref().unwrap();
    let coat = pbr.clearcoat.as_ref().unwrap();
    assert!(
        pbr.specular_maps
            .as_ref()
            .is_some_and(|m| m.strength.is_some() && m.colour.is_some())
    );
    let (Some((a, _)), Some((b, _))) = (&coat.factor_map, &coat.roughness_map) else {
        panic!("the clearcoat maps");
    };
    assert!(Arc::ptr_eq(a, b), "one picture for both");
    assert!(coat.normal.is_some());
    let sheen = pbr.sheen.as_ref().unwrap();
    assert!(sheen.colour_map.is_some() && sheen.roughness_map.is_some());
    for bump in [true, false] {
        let s = Settings {
            bump,
            rotation: Vec3::new(-30.0, 40.0, 10.0),
            ..Settings::default()
        };
        let plan = Plan::new(&scene, &s).with_terms(&terms);
        assert!(plan.physical.is_some() && plan.terms.is_some());
        let (a, b, ca, cb, packed) = both_planned(&scene, &plan, &s, 96, 72);
        assert!(packed > 0, "no triangle used packets: {s:?}");
        let differ = a.iter().zip(&b).filter(|(x, y)| x != y).count();
        assert_eq!(differ, 0, "{differ} pixels differ: {s:?}");
        assert_eq!(ca, cb, "{s:?}");
    }
}

/// Small triangles: the built-in sphere drawn a few pixels wide, whose
/// rows are shorter than a packet, so the ends of several rows are shaded
/// in one packet (and a lone pixel by the one-pixel kernel); every
/// shading, with and without texture and bump, and the sphere shaded
/// physically with a normal map: the one-pixel loop's bits and counts.
#[test]
fn small_triangles_shaded_together_match_the_one_pixel_loop() {
    use relief_scene::terms::{MaterialTerms, PbrMaterial};
    use relief_texture::sample::normal_map::normal_map_scale;
    let Built::Scene(sphere) = build_scene(
        SceneKind::Cube,
        &ModelChoice::Sphere,
        Arc::new(relief_texture::decode::procedural::brick()),
        false,
    )
    .unwrap() else {
        panic!("a 3D scene")
    };
    for (w, h) in [(40, 30), (96, 72)] {
        for shading in [Shading::Flat, Shading::Gouraud, Shading::Phong] {
            for (texture, bump) in [(true, true), (false, false)] {
                let s = Settings {
                    shading,
                    texture,
                    bump,
                    ..Settings::default()
                };
                check_in(&sphere, s, w, h);
            }
        }
    }
    let mut physical = (*sphere).clone().into_model_view();
    let normal = physical
        .material
        .texture
        .normal_map(normal_map_scale(2.0))
        .0;
    let terms = Arc::new(MaterialTerms {
        pbr: Some(PbrMaterial {
            metallic: 0.5,
            roughness: 0.4,
            normal: Some(normal),
            ..PbrMaterial::gltf_default()
        }),
        ..MaterialTerms::default()
    });
    physical.object_terms = vec![Some(terms.clone())];
    let s = Settings::default();
    let plan = Plan::new(&physical, &s).with_terms(&terms);
    assert!(plan.physical.is_some());
    for (w, h) in [(40, 30), (96, 72)] {
        let (a, b, ca, cb, packed) = both_planned(&physical, &plan, &s, w, h);
        assert!(packed > 0);
        assert_eq!(a.iter().zip(&b).filter(|(x, y)| x != y).count(), 0);
        assert_eq!(ca, cb);
    }
}
