//! Metallic-roughness shading in the model view (docs/shading.md,
//! "Metallic-roughness"): GLB files written here (quads and their
//! materials), rendered, and pixels checked against values worked out by
//! hand from the specification's formulas.

use std::path::PathBuf;
use std::sync::Arc;

use glam::Vec3;
use relief_core::framebuffer::Framebuffer;
use relief_core::settings::Settings;
use relief_core::settings::ToneMap;
use relief_pipeline::render::Renderer;
use relief_scene::model_view::view_axes;
use relief_scene::{Built, Light, ModelChoice, Scene, SceneKind, build_scene};
use relief_texture::decode::procedural;

/// A GLB of quads side by side in z = 0 facing +Z, quad i spanning x from
/// 2i to 2i + 2 and y from −1 to 1, with material i; `materials` and
/// `images` (PNG files; texture i reads image i) as JSON and bytes.
pub fn quads_glb(count: usize, materials: &str, images: &[Vec<u8>]) -> Vec<u8> {
    let mut bin: Vec<u8> = Vec::new();
    let mut views = Vec::new();
    let mut accessors = Vec::new();
    let mut prims = Vec::new();
    let mut add =
        |bin: &mut Vec<u8>, bytes: &[u8], count: usize, ty: &str, ct: u32, extra: &str| {
            while !bin.len().is_multiple_of(4) {
                bin.push(0);
            }
            views.push(format!(
                r#"{{"buffer":0,"byteOffset":{},"byteLength":{}}}"#,
                bin.len(),
                bytes.len()
            ));
            bin.extend_from_slice(bytes);
            accessors.push(format!(
                r#"{{"bufferView":{},"componentType":{ct},"count":{count},"type":"{ty}"{extra}}}"#,
                views.len() - 1
            ));
            accessors.len() - 1
        };
    let floats = |v: &[f32]| v.iter().flat_map(|f| f.to_le_bytes()).collect::<Vec<u8>>();
    for i in 0..count {
        let x0 = 2.0 * i as f32;
        let x1 = x0 + 2.0;
        let pos = [x0, 1.0, 0.0, x0, -1.0, 0.0, x1, -1.0, 0.0, x1, 1.0, 0.0];
        let minmax = format!(r#","min":[{x0},-1,0],"max":[{x1},1,0]"#);
        let p = add(&mut bin, &floats(&pos), 4, "VEC3", 5126, &minmax);
        let n = add(
            &mut bin,
            &floats(&[0.0, 0.0, 1.0].repeat(4)),
            4,
            "VEC3",
            5126,
            "",
        );
        let uv = [0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0, 0.0];
        let t = add(&mut bin, &floats(&uv), 4, "VEC2", 5126, "");
        // A second set, mirrored left to right, for the maps that read it.
        let mirrored = [1.0, 0.0, 1.0, 1.0, 0.0, 1.0, 0.0, 0.0];
        let t1 = add(&mut bin, &floats(&mirrored), 4, "VEC2", 5126, "");
        let idx: Vec<u8> = [0u16, 1, 2, 0, 2, 3]
            .iter()
            .flat_map(|i| i.to_le_bytes())
            .collect();
        let k = add(&mut bin, &idx, 6, "SCALAR", 5123, "");
        prims.push(format!(
            r#"{{"attributes":{{"POSITION":{p},"NORMAL":{n},"TEXCOORD_0":{t},"TEXCOORD_1":{t1}}},"indices":{k},"material":{i}}}"#
        ));
    }
    let mut image_json = Vec::new();
    for png in images {
        let v = {
            while !bin.len().is_multiple_of(4) {
                bin.push(0);
            }
            views.push(format!(
                r#"{{"buffer":0,"byteOffset":{},"byteLength":{}}}"#,
                bin.len(),
                png.len()
            ));
            bin.extend_from_slice(png);
            views.len() - 1
        };
        image_json.push(format!(r#"{{"bufferView":{v},"mimeType":"image/png"}}"#));
    }
    let nodes: Vec<String> = (0..count).map(|i| format!(r#"{{"mesh":{i}}}"#)).collect();
    let meshes: Vec<String> = prims
        .iter()
        .map(|p| format!(r#"{{"primitives":[{p}]}}"#))
        .collect();
    let roots: Vec<String> = (0..count).map(|i| i.to_string()).collect();
    let mut json = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[{}]}}],"nodes":[{}],"meshes":[{}],"materials":{materials},"accessors":[{}],"bufferViews":[{}],"buffers":[{{"byteLength":{}}}]"#,
        roots.join(","),
        nodes.join(","),
        meshes.join(","),
        accessors.join(","),
        views.join(","),
        bin.len()
    );
    if !images.is_empty() {
        let textures: Vec<String> = (0..images.len())
            .map(|i| format!(r#"{{"source":{i}}}"#))
            .collect();
        json += &format!(
            r#","images":[{}],"textures":[{}]"#,
            image_json.join(","),
            textures.join(",")
        );
    }
    json.push('}');
    while !json.len().is_multiple_of(4) {
        json.push(' ');
    }
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    let mut out = Vec::new();
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&((12 + 8 + json.len() + 8 + bin.len()) as u32).to_le_bytes());
    out.extend_from_slice(&(json.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(json.as_bytes());
    out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(&bin);
    out
}

/// A PNG of one colour.
pub fn solid_png(rgba: [u8; 4]) -> Vec<u8> {
    let img = image::RgbaImage::from_pixel(4, 4, image::Rgba(rgba));
    relief_texture::picture::encode(&img.into(), image::ImageFormat::Png).unwrap()
}

pub fn write(test: &str, bytes: &[u8]) -> PathBuf {
    let dir = crate::common::scratch::scratch_dir(&format!("pbr-{test}"));
    let path = dir.join("model.glb");
    std::fs::write(&path, bytes).unwrap();
    path
}

pub fn model(test: &str, count: usize, materials: &str, images: &[Vec<u8>]) -> Scene {
    load(write(test, &quads_glb(count, materials, images)))
}

/// The scene of model file `path`, in the model view.
pub fn load(path: PathBuf) -> Scene {
    match build_scene(
        SceneKind::Cube,
        &ModelChoice::File(path),
        Arc::new(procedural::brick()),
        false,
    ) {
        Ok(Built::Scene(scene)) => *scene,
        Ok(Built::Plasma(_)) => unreachable!(),
        Err(e) => panic!("{e}"),
    }
}

/// The quads turned to face the model view's camera, which looks down
/// from above: their normal is then the view's back axis.
pub fn facing() -> Settings {
    Settings {
        rotation: Vec3::new(-relief_scene::model_view::ELEVATION_DEGREES, 0.0, 0.0),
        tone_map: ToneMap::None,
        ..Settings::default()
    }
}

/// One light of `colour` far along the view's back axis (straight on), no ambient.
pub fn head_on(scene: &mut Scene, colour: f32) {
    let [_, _, back] = view_axes();
    scene.lights = vec![Light::new(back * 1e4, Vec3::splat(colour))];
    scene.ambient = Vec3::ZERO;
}

pub fn draw(scene: &Scene, settings: &Settings, w: usize, h: usize) -> Framebuffer {
    let mut fb = Framebuffer::new(w, h);
    Renderer::new().render(scene, settings, &mut fb);
    fb
}

pub fn centre(fb: &Framebuffer) -> [u8; 3] {
    fb.pixels()[fb.height() / 2 * fb.width() + fb.width() / 2]
}

/// The 8-bit sRGB value of linear light `x` (the exact curve).
pub fn srgb8(x: f32) -> u8 {
    let e = if x <= 0.003_130_8 {
        12.92 * x
    } else {
        1.055 * x.powf(1.0 / 2.4) - 0.055
    };
    (e.clamp(0.0, 1.0) * 255.0 + 0.5) as u8
}

pub fn near(got: [u8; 3], want: [u8; 3], tolerance: i32) -> bool {
    (0..3).all(|k| (got[k] as i32 - want[k] as i32).abs() <= tolerance)
}

pub fn material(base: [f32; 3], metallic: f32, roughness: f32) -> String {
    format!(
        r#"{{"pbrMetallicRoughness":{{"baseColorFactor":[{},{},{},1],"metallicFactor":{metallic},"roughnessFactor":{roughness}}}}}"#,
        base[0], base[1], base[2]
    )
}

/// Seen and lit head on, N·L = N·V = N·H = V·H = 1: F = F0, D = 1/(π·α²),
/// V = 1/4, so f·π = (1 − F0)(1 − m)·base + F0/(4α²). A white dielectric
/// of roughness 1 (α = 1) under a light of 0.5 gives 0.5·(0.96 + 0.01);
/// a metal of roughness 1 and base (1, 0.5, 0.25) under 2 gives
/// 2·base/4 = base/2.
#[test]
fn a_face_lit_head_on_gives_the_specifications_value() {
    let mut scene = model(
        "head-on",
        1,
        &format!("[{}]", material([1.0; 3], 0.0, 1.0)),
        &[],
    );
    head_on(&mut scene, 0.5);
    let fb = draw(&scene, &facing(), 120, 90);
    let want = srgb8(0.5 * 0.97);
    assert!(
        near(centre(&fb), [want; 3], 1),
        "dielectric: {:?}, want {want}",
        centre(&fb)
    );

    let base = [1.0, 0.5, 0.25];
    let mut scene = model(
        "head-on-metal",
        1,
        &format!("[{}]", material(base, 1.0, 1.0)),
        &[],
    );
    head_on(&mut scene, 2.0);
    let fb = draw(&scene, &facing(), 120, 90);
    let want = base.map(|b| srgb8(b / 2.0));
    assert!(
        near(centre(&fb), want, 1),
        "metal: {:?}, want {want:?}",
        centre(&fb)
    );
}

/// A smooth dielectric's highlight seen head on: 0.96 + 0.04/(4α²) with
/// roughness 0.5 (α² = 1/16): 0.96 + 0.16 = 1.12, times the light's 0.5.
/// `roughnessFactor` acts without a texture.
#[test]
fn roughness_factor_alone_sharpens_the_highlight() {
    let mut scene = model(
        "rough",
        1,
        &format!("[{}]", material([1.0; 3], 0.0, 0.5)),
        &[],
    );
    head_on(&mut scene, 0.5);
    let fb = draw(&scene, &facing(), 120, 90);
    let want = srgb8(0.5 * 1.12);
    assert!(
        near(centre(&fb), [want; 3], 1),
        "{:?}, want {want}",
        centre(&fb)
    );
}

/// The metallic-roughness map's blue (metallic) and green (roughness)
/// multiply the factors: a map of blue 255, green 255 under factors 1, 1
/// draws what factors 1, 1 draw alone; under a metallic factor of 1 a map
/// of blue 0 makes the quad a dielectric. (Each quad alone, seen head on
/// at the picture's centre: the view direction changes across a picture.)
#[test]
fn the_metallic_roughness_map_scales_the_factors() {
    let base = [1.0, 0.5, 0.25];
    let mapped = r#"[{"pbrMetallicRoughness":{"baseColorFactor":[1,0.5,0.25,1],"metallicFactor":1,"roughnessFactor":1,"metallicRoughnessTexture":{"index":0}}}]"#;
    let centre_of = |test: &str, materials: &str, images: &[Vec<u8>]| {
        let mut scene = model(test, 1, materials, images);
        head_on(&mut scene, 1.0);
        centre(&draw(&scene, &facing(), 120, 90))
    };
    let metal_map = centre_of("mr-metal", mapped, &[solid_png([0, 255, 255, 255])]);
    let dielectric_map = centre_of("mr-dielectric", mapped, &[solid_png([0, 255, 0, 255])]);
    let metal = centre_of(
        "mr-f-metal",
        &format!("[{}]", material(base, 1.0, 1.0)),
        &[],
    );
    let dielectric = centre_of("mr-f-diel", &format!("[{}]", material(base, 0.0, 1.0)), &[]);
    assert!(near(metal_map, metal, 1), "{metal_map:?} vs {metal:?}");
    assert!(
        near(dielectric_map, dielectric, 1),
        "{dielectric_map:?} vs {dielectric:?}"
    );
    // Head on under a unit light: a metal of roughness 1 gives base/4.
    assert!(near(metal, base.map(|b| srgb8(b / 4.0)), 1), "{metal:?}");
    assert!(!near(metal, dielectric, 20), "{metal:?} vs {dielectric:?}");
}

/// Leftmost and rightmost drawn pixels of a row.
pub fn extent(fb: &Framebuffer, background: [u8; 3], row: usize) -> (usize, usize) {
    let w = fb.width();
    let drawn: Vec<usize> = (0..w)
        .filter(|&x| fb.pixels()[row * w + x] != background)
        .collect();
    (drawn[0], *drawn.last().unwrap())
}

/// Spheres would show it best; quads under the neutral rig already do: a
/// metal and a dielectric of the same colour and roughness are far apart.
#[test]
fn metal_and_dielectric_look_different_under_the_rig() {
    let base = [0.8, 0.6, 0.2];
    for roughness in [0.2, 0.6] {
        let materials = format!(
            "[{},{}]",
            material(base, 0.0, roughness),
            material(base, 1.0, roughness)
        );
        let scene = model("metal-vs", 2, &materials, &[]);
        let settings = Settings {
            rotation: Vec3::ZERO,
            ..Settings::default()
        };
        let fb = draw(&scene, &settings, 200, 100);
        let row = fb.height() / 2;
        let (l, r) = extent(&fb, scene.background, row);
        let mean = |from: usize, to: usize| {
            let px = &fb.pixels()[row * fb.width() + from..row * fb.width() + to];
            let sum = px.iter().fold([0u32; 3], |a, p| {
                [a[0] + p[0] as u32, a[1] + p[1] as u32, a[2] + p[2] as u32]
            });
            sum.map(|s| s as f32 / px.len() as f32)
        };
        let mid = (l + r) / 2;
        let (a, b) = (mean(l + 2, mid - 2), mean(mid + 2, r - 2));
        let diff: f32 = (0..3).map(|k| (a[k] - b[k]).abs()).sum();
        assert!(
            diff > 30.0,
            "roughness {roughness}: dielectric {a:?}, metal {b:?}"
        );
    }
}

/// The base colour texture is sRGB: a texel of 188 (0.5 in linear light,
/// 0.5029 exactly) draws what a factor of 0.5029 draws.
#[test]
fn the_base_colour_texture_is_decoded_to_linear() {
    let textured = r#"{"pbrMetallicRoughness":{"baseColorTexture":{"index":0},"metallicFactor":0,"roughnessFactor":1}}"#;
    let linear = ((188.0 / 255.0 + 0.055) / 1.055f32).powf(2.4);
    let materials = format!("[{textured}]");
    let mut a = model(
        "srgb-tex",
        1,
        &materials,
        &[solid_png([188, 188, 188, 255])],
    );
    let mut b = model(
        "srgb-factor",
        1,
        &format!("[{}]", material([linear; 3], 0.0, 1.0)),
        &[],
    );
    head_on(&mut a, 1.0);
    head_on(&mut b, 1.0);
    let (fa, fb) = (draw(&a, &facing(), 120, 90), draw(&b, &facing(), 120, 90));
    assert!(
        near(centre(&fa), centre(&fb), 1),
        "{:?} vs {:?}",
        centre(&fa),
        centre(&fb)
    );
    let want = srgb8(linear * 0.97);
    assert!(
        near(centre(&fb), [want; 3], 1),
        "{:?}, want {want}",
        centre(&fb)
    );
}

/// A normal map tilting every normal shows in the model view without any
/// key (its N·L changes), and `b` (bump off) takes it away.
#[test]
fn a_normal_map_shows_by_default_and_bump_off_removes_it() {
    // (0.6, 0, 0.8) encoded: r = 0.8, g = 0.5, b = 0.9.
    let tilted = solid_png([204, 128, 230, 255]);
    let with_map = r#"{"pbrMetallicRoughness":{"metallicFactor":0,"roughnessFactor":1},"normalTexture":{"index":0}}"#;
    let mut mapped = model("nmap", 1, &format!("[{with_map}]"), &[tilted]);
    let mut plain = model(
        "nmap-plain",
        1,
        &format!("[{}]", material([1.0; 3], 0.0, 1.0)),
        &[],
    );
    head_on(&mut mapped, 0.5);
    head_on(&mut plain, 0.5);
    let on = draw(&mapped, &facing(), 120, 90);
    let flat = draw(&plain, &facing(), 120, 90);
    // N·L = 0.8: the diffuse part falls from 0.96 to about 0.8·0.96.
    assert!(
        centre(&on)[0] + 10 < centre(&flat)[0],
        "{:?} vs {:?}",
        centre(&on),
        centre(&flat)
    );
    let off = Settings {
        bump: false,
        ..facing()
    };
    assert_eq!(draw(&mapped, &off, 120, 90).pixels(), flat.pixels());
}

/// An OBJ quad (z = 0, facing +Z, 2 × 2) with the MTL `mtl`.
fn obj_model(test: &str, mtl: &str) -> Scene {
    let dir = crate::common::scratch::scratch_dir(&format!("pbr-{test}"));
    std::fs::write(dir.join("quad.mtl"), format!("newmtl m\n{mtl}\n")).unwrap();
    let obj = "mtllib quad.mtl\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nvn 0 0 1\nusemtl m\nf 1//1 2//1 3//1\nf 1//1 3//1 4//1\n";
    let path = dir.join("quad.obj");
    std::fs::write(&path, obj).unwrap();
    match build_scene(
        SceneKind::Cube,
        &ModelChoice::File(path),
        Arc::new(procedural::brick()),
        false,
    ) {
        Ok(Built::Scene(scene)) => *scene,
        Ok(Built::Plasma(_)) => unreachable!(),
        Err(e) => panic!("{e}"),
    }
}

/// MTL's PBR extension gives what glTF's factors give: `Pm 1`, `Pr 1` and
/// `Kd 1 0.5 0.25` seen head on under a light of 2 is base/2; a plain
/// Phong material's `Ns 250` is roughness 0.5 (Ns = 1000·(1 − r)²): a
/// white dielectric under 0.5 gives 0.5·(0.96 + 0.04/(4·0.0625)).
#[test]
fn an_mtl_material_is_read_as_metallic_roughness() {
    let mut metal = obj_model("mtl-metal", "Kd 1 0.5 0.25\nPm 1\nPr 1");
    head_on(&mut metal, 2.0);
    let want = [1.0, 0.5, 0.25].map(|b: f32| srgb8(b / 2.0));
    let got = centre(&draw(&metal, &facing(), 120, 90));
    assert!(near(got, want, 1), "{got:?}, want {want:?}");
    let mut phong = obj_model("mtl-phong", "Kd 1 1 1\nKs 1 1 1\nNs 250");
    head_on(&mut phong, 0.5);
    let want = srgb8(0.5 * 1.12);
    let got = centre(&draw(&phong, &facing(), 120, 90));
    assert!(near(got, [want; 3], 1), "{got:?}, want {want}");
}

/// Tone maps: none clamps, PBR Neutral keeps a mid grey (less its 0.04
/// offset) and rolls off white, ACES darkens a mid grey; exposure scales
/// the light before them.
#[test]
fn the_tone_map_and_exposure_flags_change_the_picture_as_their_curves_say() {
    let mut scene = model(
        "tone",
        1,
        &format!("[{}]", material([1.0; 3], 0.0, 1.0)),
        &[],
    );
    head_on(&mut scene, 0.5);
    let with = |tone_map, exposure| {
        let s = Settings {
            tone_map,
            exposure,
            ..facing()
        };
        centre(&draw(&scene, &s, 120, 90))[0]
    };
    let x = 0.5 * 0.97;
    assert!((with(ToneMap::None, 1.0) as i32 - srgb8(x) as i32).abs() <= 1);
    assert!((with(ToneMap::PbrNeutral, 1.0) as i32 - srgb8(x - 0.04) as i32).abs() <= 1);
    let aces = x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14);
    assert!((with(ToneMap::Aces, 1.0) as i32 - srgb8(aces) as i32).abs() <= 1);
    assert!((with(ToneMap::None, 2.0) as i32 - srgb8(2.0 * x) as i32).abs() <= 1);
}

/// `KHR_materials_unlit`: the base colour alone, whatever the light: the
/// linear factor (0.5, 0.25, 1) encoded to sRGB, under a light of 3 and
/// under none.
#[test]
fn an_unlit_material_shows_its_base_colour_under_any_light() {
    let base = [0.5, 0.25, 1.0];
    let unlit = format!(
        r#"[{{"pbrMetallicRoughness":{{"baseColorFactor":[{},{},{},1]}},"extensions":{{"KHR_materials_unlit":{{}}}}}}]"#,
        base[0], base[1], base[2]
    );
    let want = base.map(srgb8);
    for light in [3.0, 0.0] {
        let mut scene = model("unlit", 1, &unlit, &[]);
        head_on(&mut scene, light);
        let got = centre(&draw(&scene, &facing(), 120, 90));
        assert!(near(got, want, 1), "light {light}: {got:?}, want {want:?}");
    }
}

/// `KHR_materials_transmission` as thin see-through: transmission t lets
/// t·(1 − 0.04) of the background through, tinted by the base colour
/// factor, so the face is its own colour (drawn with t = 0) at opacity
/// a = 1 − 0.96·t over the background times the factor (both in display
/// values): a·face + (1 − a)·tint·background.
#[test]
fn a_transmitting_material_shows_the_background_through_it_tinted() {
    let with = |t: f32| {
        format!(
            r#"[{{"pbrMetallicRoughness":{{"baseColorFactor":[1,0.5,0.25,1],"metallicFactor":0,"roughnessFactor":1}},"extensions":{{"KHR_materials_transmission":{{"transmissionFactor":{t}}}}}}}]"#
        )
    };
    // A light grey background, so that the tint shows.
    let background = [200, 200, 200];
    let picture = |t: f32| {
        let mut scene = model("transmission", 1, &with(t), &[]);
        head_on(&mut scene, 1.0);
        scene.background = background;
        centre(&draw(&scene, &facing(), 120, 90))
    };
    let solid = picture(0.0);
    assert_ne!(solid, background);
    let tint = [1.0, 0.5, 0.25].map(|c| f32::from(srgb8(c)) / 255.0);
    for t in [0.5f32, 1.0] {
        let a = 1.0 - 0.96 * t;
        let want: [u8; 3] = std::array::from_fn(|k| {
            (f32::from(solid[k]) * a + f32::from(background[k]) * tint[k] * (1.0 - a)).round() as u8
        });
        let got = picture(t);
        assert!(near(got, want, 1), "t {t}: {got:?}, want {want:?}");
    }
}

/// `transmissionTexture`: the factor times the map's red. A map black on
/// its left half and white on its right lets nothing through on the left
/// (the face's own colour, as with t = 0) and 96 % on the right (as with
/// no texture), in the same picture; read through the quad's second
/// coordinate set, mirrored, the other way round (the colour texture, white,
/// keeps the first set in the vertices).
#[test]
fn a_transmission_texture_chooses_where_the_material_lets_light_through() {
    let img = image::RgbaImage::from_fn(4, 4, |x, _| {
        let red = if x < 2 { 0 } else { 255 };
        image::Rgba([red, 0, 0, 255])
    });
    let png = relief_texture::picture::encode(&img.into(), image::ImageFormat::Png).unwrap();
    let images = [png, solid_png([255; 4])];
    let with = |t: f32, map: &str| {
        format!(
            r#"[{{"pbrMetallicRoughness":{{"baseColorFactor":[1,0.5,0.25,1],"baseColorTexture":{{"index":1}},"metallicFactor":0,"roughnessFactor":1}},"extensions":{{"KHR_materials_transmission":{{"transmissionFactor":{t}{map}}}}}}}]"#
        )
    };
    let picture = |test: &str, materials: String| {
        let mut scene = model(test, 1, &materials, &images);
        head_on(&mut scene, 1.0);
        (draw(&scene, &facing(), 120, 90), scene.background)
    };
    let (solid, background) = picture("transmission-solid", with(0.0, ""));
    let (clear, _) = picture("transmission-clear", with(1.0, ""));
    let map = r#","transmissionTexture":{"index":0}"#;
    let (mapped, _) = picture("transmission-map", with(1.0, map));
    let second = r#","transmissionTexture":{"index":0,"texCoord":1}"#;
    let (mirrored, _) = picture("transmission-map-1", with(1.0, second));
    // The quad's columns on the middle row, and a column a quarter and
    // three quarters across (u ≈ 0.25 and 0.75: texels 0–1 and 2–3).
    let row = solid.height() / 2;
    let covered: Vec<usize> = (0..solid.width())
        .filter(|&x| solid.get(x, row) != background)
        .collect();
    assert!(covered.len() > 20, "{covered:?}");
    let (first, last) = (covered[0], covered[covered.len() - 1]);
    let left = first + (last - first) / 4;
    let right = first + 3 * (last - first) / 4;
    assert_ne!(solid.get(left, row), clear.get(left, row));
    assert_eq!(
        mapped.get(left, row),
        solid.get(left, row),
        "opaque on the left"
    );
    assert_eq!(
        mapped.get(right, row),
        clear.get(right, row),
        "clear on the right"
    );
    assert_eq!(
        mirrored.get(left, row),
        clear.get(left, row),
        "set 1: clear on the left"
    );
    assert_eq!(
        mirrored.get(right, row),
        solid.get(right, row),
        "set 1: opaque on the right"
    );
}

/// The GLB `glb` with `from` replaced by `to` in its JSON chunk.
fn edit_json(glb: &[u8], from: &str, to: &str) -> Vec<u8> {
    let len = u32::from_le_bytes(glb[12..16].try_into().unwrap()) as usize;
    let json = std::str::from_utf8(&glb[20..20 + len]).unwrap();
    assert!(json.contains(from), "{from} not in the file");
    let mut json = json.trim_end().replace(from, to);
    while !json.len().is_multiple_of(4) {
        json.push(' ');
    }
    let bin = &glb[20 + len..];
    let mut out = Vec::new();
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&((20 + json.len() + bin.len()) as u32).to_le_bytes());
    out.extend_from_slice(&(json.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(json.as_bytes());
    out.extend_from_slice(bin);
    out
}

/// `EXT_texture_webp`: a texture given only as WebP (no `source`) draws as
/// its PNG twin does.
#[test]
fn a_webp_only_texture_draws_as_its_png_twin() {
    let rgba = [200, 120, 40, 255];
    let img = image::RgbaImage::from_pixel(4, 4, image::Rgba(rgba));
    let webp = relief_texture::picture::encode(&img.into(), image::ImageFormat::WebP).unwrap();
    let materials =
        r#"[{"pbrMetallicRoughness":{"baseColorTexture":{"index":0},"metallicFactor":0}}]"#;
    let draw_file = |test: &str, glb: &[u8]| {
        let path = write(test, glb);
        let built = build_scene(
            SceneKind::Cube,
            &ModelChoice::File(path),
            Arc::new(procedural::brick()),
            false,
        );
        let mut scene = match built {
            Ok(Built::Scene(scene)) => *scene,
            Ok(Built::Plasma(_)) => unreachable!(),
            Err(e) => panic!("{test}: {e}"),
        };
        head_on(&mut scene, 1.0);
        draw(&scene, &facing(), 120, 90)
    };
    let png = draw_file("webp-twin", &quads_glb(1, materials, &[solid_png(rgba)]));
    let only_webp = edit_json(
        &quads_glb(1, materials, &[webp]),
        r#""textures":[{"source":0}]"#,
        r#""extensionsUsed":["EXT_texture_webp"],"extensionsRequired":["EXT_texture_webp"],"textures":[{"extensions":{"EXT_texture_webp":{"source":0}}}]"#,
    );
    let only_webp = edit_json(&only_webp, "image/png", "image/webp");
    let webp = draw_file("webp-only", &only_webp);
    assert_ne!(
        centre(&png),
        centre(&draw_file("webp-twin", &quads_glb(1, "[{}]", &[])))
    );
    assert_eq!(png.pixels(), webp.pixels());
}
