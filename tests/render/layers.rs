//! The textures of glTF's material layers in the model view
//! (docs/shading.md, "Metallic-roughness"): `KHR_materials_specular`'s
//! strength and colour maps, `KHR_materials_clearcoat`'s intensity,
//! roughness and normal maps. Quads written as GLB files (`pbr`'s
//! helpers), seen and lit head on, pixels checked against values worked
//! out by hand from the specifications' formulas.
//!
//! Head on (N·L = N·V = N·H = V·H = 1) with roughness 1 (α = 1) GGX is
//! D = 1/π and the visibility V = 1/4, so a light of colour C reflects
//! C·F0/4 of a dielectric's F0. Off the picture's centre the eye is a few
//! degrees off the normal: V = ½/(N·L + N·V) rises by under 1 %, which
//! the 8-bit tolerance covers.

use relief_core::framebuffer::Framebuffer;
use relief_scene::Scene;

use super::pbr::{centre, draw, extent, facing, head_on, model, near, solid_png, srgb8};

/// An 8 × 8 PNG whose left four columns are `left` and right four `right`:
/// read bilinearly, u from 1/16 to 7/16 reads `left` alone and 9/16 to
/// 15/16 `right` alone.
pub fn halves_png(left: [u8; 4], right: [u8; 4]) -> Vec<u8> {
    let img = image::RgbaImage::from_fn(8, 8, |x, _| image::Rgba(if x < 4 { left } else { right }));
    relief_texture::picture::encode(&img.into(), image::ImageFormat::Png).unwrap()
}

/// The scene of one quad of material `material` (JSON) reading `images`,
/// lit head on by one light of `light`, no environment.
fn quad(test: &str, material: &str, images: &[Vec<u8>], light: f32) -> Scene {
    let mut scene = model(test, 1, &format!("[{material}]"), images);
    head_on(&mut scene, light);
    scene
}

/// The pixels of the centre row at u = ¼ and u = ¾ of the quad (the
/// middles of `halves_png`'s halves), and the picture.
fn quarters(scene: &Scene) -> ([u8; 3], [u8; 3], Framebuffer) {
    let fb = draw(scene, &facing(), 120, 90);
    let row = fb.height() / 2;
    let background = fb.pixels()[0];
    let (x0, x1) = extent(&fb, background, row);
    let at = |u: f32| fb.pixels()[row * fb.width() + x0 + ((x1 - x0) as f32 * u) as usize];
    (at(0.25), at(0.75), fb)
}

/// A black dielectric of roughness 1 (nothing but its reflection shows).
fn black(extensions: &str) -> String {
    format!(
        r#"{{"pbrMetallicRoughness":{{"baseColorFactor":[0,0,0,1],"metallicFactor":0,"roughnessFactor":1}},"extensions":{{{extensions}}}}}"#
    )
}

/// `specularTexture`'s alpha multiplies `specularFactor`: where it is 0
/// the black dielectric reflects nothing (F0 = F90 = 0), where it is 1 the
/// factor's 0.5: F0 = 0.04·0.5, and head on under a light of 2 that is
/// 2·0.02/4 = 0.01. The map's colour channels are not read.
#[test]
fn the_specular_texture_alpha_weights_the_dielectric_reflection() {
    let ext = r#""KHR_materials_specular":{"specularFactor":0.5,"specularTexture":{"index":0}}"#;
    let map = halves_png([255, 255, 255, 0], [0, 0, 0, 255]);
    let (left, right, _) = quarters(&quad("spec-strength", &black(ext), &[map], 2.0));
    assert_eq!(left, [0, 0, 0], "no reflection where the map is 0");
    let want = srgb8(0.01);
    assert!(near(right, [want; 3], 1), "{right:?}, want {want}");
    // The factor alone (no map) draws the right half's value everywhere.
    let factor = r#""KHR_materials_specular":{"specularFactor":0.5}"#;
    let (l, r, _) = quarters(&quad("spec-factor", &black(factor), &[], 2.0));
    assert!(
        near(l, right, 1) && near(r, right, 1),
        "{l:?} {r:?} {right:?}"
    );
    // A picture without alpha is opaque: its alpha reads 1.
    let rgb = {
        let img = image::RgbImage::from_pixel(4, 4, image::Rgb([0, 0, 0]));
        relief_texture::picture::encode(&img.into(), image::ImageFormat::Png).unwrap()
    };
    let opaque = centre(&draw(
        &quad("spec-rgb", &black(ext), &[rgb], 2.0),
        &facing(),
        120,
        90,
    ));
    assert!(near(opaque, [want; 3], 1), "{opaque:?}, want {want}");
}

/// `specularColorTexture` (sRGB) multiplies `specularColorFactor` before
/// the clamp to 1: F0 = min(0.04·(50, 50, 50)·(c(128), c(255), 0), 1) with
/// c(128) = 0.2168 (the kernel's cubic sRGB decode; exactly 0.2158),
/// so F0 = (0.4336, 1, 0), and head on under a light of 2 the quad is
/// F0/2 = (0.2168, 0.5, 0). Clamping the factor first would give
/// (0.1084, 0.5, 0). With a factor of 1 the map tints 0.04 by
/// (1, c(188) = 0.5024, 0): (0.02, 0.01005, 0).
#[test]
fn the_specular_colour_texture_tints_f0() {
    let decode = |x: f32| x * (x * (0.305_306 * x + 0.682_171) + 0.012_523);
    let ext = |factor: f32| {
        format!(
            r#""KHR_materials_specular":{{"specularColorFactor":[{factor},{factor},{factor}],"specularColorTexture":{{"index":0}}}}"#
        )
    };
    let draw_centre = |test: &str, factor: f32, rgba: [u8; 4]| {
        let scene = quad(test, &black(&ext(factor)), &[solid_png(rgba)], 2.0);
        centre(&draw(&scene, &facing(), 120, 90))
    };
    let got = draw_centre("spec-colour-clamp", 50.0, [128, 255, 0, 255]);
    let red = (0.04 * 50.0 * decode(128.0 / 255.0)).min(1.0);
    let want = [srgb8(red / 2.0), srgb8(0.5), 0];
    assert!((red - 0.4336).abs() < 2e-4, "{red}");
    assert!(near(got, want, 1), "{got:?}, want {want:?}");
    let got = draw_centre("spec-colour", 1.0, [255, 188, 0, 255]);
    let want = [srgb8(0.02), srgb8(0.04 * decode(188.0 / 255.0) / 2.0), 0];
    assert!(near(got, want, 1), "{got:?}, want {want:?}");
}

/// `clearcoatTexture`'s red multiplies `clearcoatFactor`: over a black
/// dielectric that reflects nothing (specular 0) the layer alone shows,
/// 2·0.04/4 = 0.02 head on under a light of 2 where the map is 1, and
/// nothing where it is 0.
#[test]
fn a_clearcoat_map_of_zero_removes_the_layer() {
    let ext = r#""KHR_materials_specular":{"specularFactor":0},"KHR_materials_clearcoat":{"clearcoatFactor":1,"clearcoatRoughnessFactor":1,"clearcoatTexture":{"index":0}}"#;
    let map = halves_png([0, 255, 255, 255], [255, 0, 0, 255]);
    let (left, right, _) = quarters(&quad("coat-map", &black(ext), &[map], 2.0));
    assert_eq!(left, [0, 0, 0], "no layer where the map is 0");
    let want = srgb8(0.02);
    assert!(near(right, [want; 3], 1), "{right:?}, want {want}");
}

/// `clearcoatRoughnessTexture`'s green multiplies
/// `clearcoatRoughnessFactor`: a factor of 1 and green 128 make the layer
/// 128/255 rough, α² = (128/255)⁴ = 0.06349, and head on its reflection of
/// a light of 2 is 2·0.04·D·V·π = 0.02/α² = 0.3150 (D = 1/(π·α²), V =
/// 1/4), against 0.02 at roughness 1. The highlight narrows: at roughness
/// 1 it is flat across the quad (D = 1/π whatever N·H), at 0.5 it falls
/// off from the centre. The red channel (0 here) is not read.
#[test]
fn the_clearcoat_roughness_map_narrows_the_layers_highlight() {
    let coat = |map: &str| {
        format!(
            r#""KHR_materials_specular":{{"specularFactor":0}},"KHR_materials_clearcoat":{{"clearcoatFactor":1,"clearcoatRoughnessFactor":1{map}}}"#
        )
    };
    let mapped = coat(r#","clearcoatRoughnessTexture":{"index":0}"#);
    let map = solid_png([0, 128, 255, 255]);
    let (_, smooth_right, smooth) = quarters(&quad("coat-rough", &black(&mapped), &[map], 2.0));
    let (_, rough_right, rough) = quarters(&quad("coat-rough-1", &black(&coat("")), &[], 2.0));
    let alpha2 = (128.0f32 / 255.0).powi(4);
    let want = srgb8(0.02 / alpha2);
    assert!((0.02 / alpha2 - 0.3150).abs() < 1e-3);
    assert!(
        near(centre(&smooth), [want; 3], 1),
        "{:?}, want {want}",
        centre(&smooth)
    );
    let want = srgb8(0.02);
    assert!(near(centre(&rough), [want; 3], 1), "{:?}", centre(&rough));
    // Three quarters across: the rough layer as at the centre, the smooth
    // one well below its centre.
    assert!(near(rough_right, centre(&rough), 1), "{rough_right:?}");
    assert!(
        (smooth_right[0] as i32) < centre(&smooth)[0] as i32 - 20,
        "{smooth_right:?} against {:?}",
        centre(&smooth)
    );
}

/// GGX D for α² at N·H.
fn ggx(alpha2: f64, nh: f64) -> f64 {
    let d = nh * nh * (alpha2 - 1.0) + 1.0;
    alpha2 / (std::f64::consts::PI * d * d)
}

/// Smith's height-correlated visibility for α².
fn smith(alpha2: f64, nl: f64, nv: f64) -> f64 {
    let a = nl * (nv * nv * (1.0 - alpha2) + alpha2).sqrt();
    let b = nv * (nl * nl * (1.0 - alpha2) + alpha2).sqrt();
    0.5 / (a + b)
}

/// `clearcoatNormalTexture` tilts the layer's normal, not the base's.
/// The map's bytes (204, 128, 230) are n = 2·rgb − 1 = (0.6, 0.0039,
/// 0.8039), whose unit vector leans 36.7° off the surface: N_c·V = N_c·L =
/// N_c·H = c = 0.8014 at the centre, seen and lit head on. Over a white
/// dielectric with no reflection of its own (specular 0), roughness 1,
/// under a light of 0.5: the base's Lambert term stays 0.5 (its normal is
/// the surface's), the layer lets 1 − (0.04 + 0.96·(1 − c)⁵) through and
/// adds 0.5·0.04·D(c)·V(c, c)·π·c at roughness 0.3 (α² = 0.0081): 0.4802
/// in all. Without the map the layer's highlight sits there: 0.48 +
/// 0.5·0.04/(4·0.0081) = 1.097, white.
#[test]
fn the_clearcoat_normal_map_tilts_the_layer_alone() {
    let white = |ext: &str| {
        format!(
            r#"{{"pbrMetallicRoughness":{{"baseColorFactor":[1,1,1,1],"metallicFactor":0,"roughnessFactor":1}},"extensions":{{"KHR_materials_specular":{{"specularFactor":0}},"KHR_materials_clearcoat":{{"clearcoatFactor":1,"clearcoatRoughnessFactor":0.3{ext}}}}}}}"#
        )
    };
    let mapped = white(r#","clearcoatNormalTexture":{"index":0}"#);
    let tilted = solid_png([204, 128, 230, 255]);
    let got = centre(&draw(
        &quad("coat-normal", &mapped, &[tilted], 0.5),
        &facing(),
        120,
        90,
    ));
    let n = [204.0, 128.0, 230.0].map(|b: f64| 2.0 * b / 255.0 - 1.0);
    let c = n[2] / (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    let alpha2 = 0.3f64.powi(4);
    let passes = 1.0 - (0.04 + 0.96 * (1.0 - c).powi(5));
    let layer = 0.5 * 0.04 * ggx(alpha2, c) * smith(alpha2, c, c) * std::f64::consts::PI * c;
    let linear = 0.5 * passes + layer;
    assert!((linear - 0.4802).abs() < 1e-3, "{linear}");
    let want = srgb8(linear as f32);
    assert!(near(got, [want; 3], 1), "{got:?}, want {want}");
    let plain = centre(&draw(
        &quad("coat-normal-plain", &white(""), &[], 0.5),
        &facing(),
        120,
        90,
    ));
    assert_eq!(plain, [255; 3]);
}

/// A slight tilt of the layer's normal (bytes (134, 128, 255): 2.9° toward
/// the map's +u) moves its highlight along the centre row, off the centre
/// where the untilted layer has it, while `b` (normal maps off) puts it
/// back. Over a black base with no reflection of its own, under a light of
/// 0.5, roughness 0.3.
#[test]
fn the_clearcoat_normal_map_moves_the_layers_highlight() {
    let coat = |ext: &str| {
        black(&format!(
            r#""KHR_materials_specular":{{"specularFactor":0}},"KHR_materials_clearcoat":{{"clearcoatFactor":1,"clearcoatRoughnessFactor":0.3{ext}}}"#
        ))
    };
    let brightest = |fb: &Framebuffer| {
        let row = fb.height() / 2;
        let w = fb.width();
        (0..w).max_by_key(|&x| fb.pixels()[row * w + x][0]).unwrap() as i32
    };
    let tilted = quad(
        "coat-tilt",
        &coat(r#","clearcoatNormalTexture":{"index":0}"#),
        &[solid_png([134, 128, 255, 255])],
        0.5,
    );
    let plain = quad("coat-tilt-plain", &coat(""), &[], 0.5);
    let on = brightest(&draw(&tilted, &facing(), 120, 90));
    let flat = brightest(&draw(&plain, &facing(), 120, 90));
    assert!((flat - 60).abs() <= 1, "untilted highlight at {flat}");
    assert!(
        (on - flat).abs() >= 4,
        "tilted highlight at {on}, untilted {flat}"
    );
    let off = relief_core::settings::Settings {
        bump: false,
        ..facing()
    };
    assert_eq!(
        draw(&tilted, &off, 120, 90).pixels(),
        draw(&plain, &off, 120, 90).pixels()
    );
}

// KHR_materials_sheen: the Charlie lobe D = (2 + k)·sin^k θh / (2π), k =
// 1/α = 1/sheenRoughness², with the visibility 1/(4(N·L + N·V − N·L·N·V)),
// over the material scaled by 1 − max(colour)·E(N·V).

/// The scene of one 2 × 2 quad of material `material` (JSON, with
/// `images` as data URIs read by textures in order) turned `degrees` about
/// the vertical from facing +Z: its normal is (sin θ, 0, cos θ), which the
/// model view's facing turn (`facing`) takes to sin θ·right + cos θ·back.
/// Seen at the picture's centre, V = L = back (the light far along it):
/// N·V = N·L = N·H = cos θ. Lit by one light of `light`, no environment.
fn tilted(test: &str, degrees: f32, material: &str, images: &[Vec<u8>], light: f32) -> Scene {
    use base64::Engine;
    use relief_scene::{Built, ModelChoice, SceneKind, build_scene};
    let (s, c) = degrees.to_radians().sin_cos();
    let t = glam::Vec3::new(c, 0.0, -s);
    let pos: Vec<f32> = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
        .iter()
        .flat_map(|&(x, y)| (t * x + glam::Vec3::Y * y).to_array())
        .collect();
    let mut bin = crate::glb_writer::Bin::default();
    let position = bin.positions(&pos);
    let normal = bin.floats(&[s, 0.0, c].repeat(4), "VEC3");
    let uv = bin.floats(&[0.0, 1.0, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0], "VEC2");
    let indices = bin.shorts(&[0, 1, 2, 0, 2, 3], "SCALAR");
    let mut json = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0}}],"meshes":[{{"primitives":[{{"attributes":{{"POSITION":{position},"NORMAL":{normal},"TEXCOORD_0":{uv}}},"indices":{indices},"material":0}}]}}],"materials":[{material}]"#
    );
    if !images.is_empty() {
        let b64 = |png: &Vec<u8>| base64::engine::general_purpose::STANDARD.encode(png);
        let uris: Vec<String> = images
            .iter()
            .map(|png| format!(r#"{{"uri":"data:image/png;base64,{}"}}"#, b64(png)))
            .collect();
        let textures: Vec<String> = (0..images.len())
            .map(|i| format!(r#"{{"source":{i}}}"#))
            .collect();
        json += &format!(
            r#","images":[{}],"textures":[{}]"#,
            uris.join(","),
            textures.join(",")
        );
    }
    let path = super::pbr::write(test, &bin.glb(&json));
    let texture = std::sync::Arc::new(relief_texture::decode::procedural::brick());
    let Ok(Built::Scene(mut scene)) =
        build_scene(SceneKind::Cube, &ModelChoice::File(path), texture, false)
    else {
        panic!("not a scene");
    };
    head_on(&mut scene, light);
    *scene
}

/// A black dielectric that reflects nothing itself (specular 0) under a
/// sheen of `sheen` (the extension's JSON members).
fn black_sheen(sheen: &str) -> String {
    black(&format!(
        r#""KHR_materials_specular":{{"specularFactor":0}},"KHR_materials_sheen":{{{sheen}}}"#
    ))
}

/// The sheen lobe seen and lit from the same direction at θ from the
/// normal, under a light of 1: N·L·π·D·V = (2 + k)·sin^k θ / (8(2 − cos θ)).
fn retro_lobe(degrees: f32, k: f32) -> f32 {
    let (s, c) = degrees.to_radians().sin_cos();
    (2.0 + k) * s.powf(k) / (8.0 * (2.0 - c))
}

/// Grazing: seen and lit along the same direction 60° and 80° off the
/// normal, over a black base, the quad is the sheen lobe alone: at sheen
/// roughness 1 (k = 1) 3·sin θ/(8(2 − cos θ)) = 0.2165 at 60° and 0.2022
/// at 80°; at roughness ½ (k = 4) 6·sin⁴θ/(8(2 − cos θ)) = 0.2813 and
/// 0.3863. Head on (below) the lobe is 0: D vanishes at N·H = 1.
#[test]
fn the_sheen_lobe_at_grazing_angles_is_the_charlie_lobe() {
    assert!((retro_lobe(60.0, 1.0) - 0.216_51).abs() < 1e-4);
    assert!((retro_lobe(80.0, 1.0) - 0.202_21).abs() < 1e-4);
    assert!((retro_lobe(60.0, 4.0) - 0.281_25).abs() < 1e-4);
    assert!((retro_lobe(80.0, 4.0) - 0.386_27).abs() < 1e-4);
    for (roughness, k) in [(1.0, 1.0), (0.5, 4.0)] {
        let sheen = format!(r#""sheenColorFactor":[1,1,1],"sheenRoughnessFactor":{roughness}"#);
        for degrees in [60.0, 80.0] {
            let scene = tilted("sheen-grazing", degrees, &black_sheen(&sheen), &[], 1.0);
            let got = centre(&draw(&scene, &facing(), 120, 90));
            let want = srgb8(retro_lobe(degrees, k));
            assert!(
                near(got, [want; 3], 1),
                "{roughness} at {degrees}°: {got:?}, want {want}"
            );
        }
    }
    // The colour scales the lobe per channel.
    let sheen = r#""sheenColorFactor":[1,0.5,0.25],"sheenRoughnessFactor":1"#;
    let scene = tilted("sheen-colour", 80.0, &black_sheen(sheen), &[], 1.0);
    let got = centre(&draw(&scene, &facing(), 120, 90));
    let want = [1.0, 0.5, 0.25].map(|c| srgb8(c * retro_lobe(80.0, 1.0)));
    assert!(near(got, want, 1), "{got:?}, want {want:?}");
}

/// Head on the lobe is 0 (sin θh = 0), and the material below keeps
/// 1 − max(colour)·E(1): E at N·V = 1 is 2^(−(k+2)/2)·2/(k + 4) by hand
/// (`shade::sheen`'s tests), 0.141421 at roughness 1. A white Lambert base
/// (specular 0) under a light of ½ gives ½·(1 − 0.141421) = 0.42929 with a
/// white sheen, ½·(1 − 0.5·0.141421) = 0.46464 with a grey one of 0.5.
#[test]
fn head_on_the_sheen_only_darkens_the_base_by_its_albedo() {
    let white = |sheen: &str| {
        format!(
            r#"{{"pbrMetallicRoughness":{{"baseColorFactor":[1,1,1,1],"metallicFactor":0,"roughnessFactor":1}},"extensions":{{"KHR_materials_specular":{{"specularFactor":0}},"KHR_materials_sheen":{{{sheen}}}}}}}"#
        )
    };
    let e1 = 2f32.powf(-1.5) * 2.0 / 5.0;
    for (colour, want) in [(1.0, 0.5 * (1.0 - e1)), (0.5, 0.5 * (1.0 - 0.5 * e1))] {
        let sheen =
            format!(r#""sheenColorFactor":[{colour},{colour},{colour}],"sheenRoughnessFactor":1"#);
        let got = centre(&draw(
            &quad("sheen-head-on", &white(&sheen), &[], 0.5),
            &facing(),
            120,
            90,
        ));
        assert!(
            near(got, [srgb8(want); 3], 1),
            "{colour}: {got:?}, want {want}"
        );
    }
    assert!((0.5 * (1.0 - e1) - 0.429_29).abs() < 1e-5);
}

/// A sheen whose colour is black is no sheen (the extension's default):
/// the picture is the one without the extension, bit for bit, under the
/// model view's lights and the studio.
#[test]
fn a_black_sheen_changes_nothing() {
    let base = r#""pbrMetallicRoughness":{"baseColorFactor":[0.7,0.4,0.2,1],"metallicFactor":0.3,"roughnessFactor":0.5}"#;
    let plain = model("sheen-none", 1, &format!("[{{{base}}}]"), &[]);
    let black = model(
        "sheen-black",
        1,
        &format!(
            r#"[{{{base},"extensions":{{"KHR_materials_sheen":{{"sheenColorFactor":[0,0,0],"sheenRoughnessFactor":0.5}}}}}}]"#
        ),
        &[],
    );
    let settings = relief_core::settings::Settings {
        rotation: glam::Vec3::new(-30.0, 40.0, 0.0),
        ..relief_core::settings::Settings::default()
    };
    assert!(
        black
            .own_terms(0)
            .unwrap()
            .pbr
            .as_ref()
            .unwrap()
            .sheen
            .is_none()
    );
    assert_eq!(
        draw(&plain, &settings, 96, 72).pixels(),
        draw(&black, &settings, 96, 72).pixels()
    );
}

/// `sheenColorTexture` (sRGB) multiplies the colour and
/// `sheenRoughnessTexture`'s alpha the roughness: at 80° a colour map of
/// (255, 128, 0) makes the roughness-1 lobe 0.2022·(1, c(128) = 0.2168,
/// 0), c the kernel's sRGB decode; a roughness map of alpha 128 under a
/// factor of 1 makes the roughness 128/255, k = (255/128)² = 3.969, and
/// the lobe (2 + k)·sin^k 80°/(8(2 − cos 80°)) = 0.3845.
#[test]
fn the_sheen_maps_scale_the_colour_and_the_roughness() {
    let decode = |x: f32| x * (x * (0.305_306 * x + 0.682_171) + 0.012_523);
    let sheen =
        r#""sheenColorFactor":[1,1,1],"sheenRoughnessFactor":1,"sheenColorTexture":{"index":0}"#;
    let map = solid_png([255, 128, 0, 255]);
    let got = centre(&draw(
        &tilted("sheen-map", 80.0, &black_sheen(sheen), &[map], 1.0),
        &facing(),
        120,
        90,
    ));
    let lobe = retro_lobe(80.0, 1.0);
    let want = [srgb8(lobe), srgb8(lobe * decode(128.0 / 255.0)), 0];
    assert!(near(got, want, 1), "{got:?}, want {want:?}");
    let sheen = r#""sheenColorFactor":[1,1,1],"sheenRoughnessFactor":1,"sheenRoughnessTexture":{"index":0}"#;
    let map = solid_png([0, 0, 0, 128]);
    let got = centre(&draw(
        &tilted("sheen-rough-map", 80.0, &black_sheen(sheen), &[map], 1.0),
        &facing(),
        120,
        90,
    ));
    let k = (255.0f32 / 128.0).powi(2);
    assert!(
        (retro_lobe(80.0, k) - 0.3845).abs() < 1e-4,
        "{}",
        retro_lobe(80.0, k)
    );
    let want = srgb8(retro_lobe(80.0, k));
    assert!(near(got, [want; 3], 1), "{got:?}, want {want}");
}

/// The white furnace: under a uniform environment of radiance 1 and no
/// light, a white dielectric under a white sheen sends back at most 1,
/// whatever the base's and the sheen's roughness and the angle it is seen
/// at, with the irradiance from the spherical harmonics or the integrated
/// map (exposure ½ keeps the result below the clamp, so an excess would
/// show): the sheen takes max(colour)·E(N·V) of the base and gives back
/// colour·E(N·V) × the irradiance, which is 1 here.
#[test]
fn a_sheen_in_a_white_furnace_reflects_at_most_its_input() {
    use relief_core::settings::IblDiffuse;
    use relief_texture::environment::Environment;
    for roughness in [0.3, 1.0] {
        for sheen_roughness in [0.0, 0.3, 0.6, 1.0] {
            let material = format!(
                r#"[{{"pbrMetallicRoughness":{{"baseColorFactor":[1,1,1,1],"metallicFactor":0,"roughnessFactor":{roughness}}},"extensions":{{"KHR_materials_sheen":{{"sheenColorFactor":[1,1,1],"sheenRoughnessFactor":{sheen_roughness}}}}}}}]"#
            );
            let mut scene = model("sheen-furnace", 1, &material, &[]);
            scene.lights.clear();
            scene.material.environment = Some(std::sync::Arc::new(Environment::from_fn(
                "white",
                64,
                32,
                |_| glam::Vec3::ONE,
            )));
            for (turn, diffuse) in [0.0, 30.0, 50.0, 70.0, 80.0]
                .into_iter()
                .flat_map(|t| [(t, IblDiffuse::Sh), (t, IblDiffuse::Integrated)])
            {
                let mut settings = facing();
                settings.rotation.y = turn;
                settings.exposure = 0.5;
                settings.ibl_diffuse = diffuse;
                let got = centre(&draw(&scene, &settings, 120, 90));
                let most = srgb8(0.5) as i32 + 1;
                assert!(
                    got.iter().all(|&c| c as i32 <= most),
                    "{roughness} {sheen_roughness} {turn} {diffuse:?}: {got:?}"
                );
            }
        }
    }
}
