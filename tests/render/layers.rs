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
