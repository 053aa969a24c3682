//! Every key of the picture's options, pressed in many places: either the
//! picture changes, or the key says why it does not and changes nothing
//! (README: "A key that cannot act where you are says so").

use std::sync::Arc;

use relief::app::stage::Stage;
use relief::app::{Action, State, update};
use relief_core::framebuffer::Framebuffer;
use relief_core::settings::{AntiAlias, Display, Filter, Settings, Shading, Technique};
use relief_pipeline::render::Renderer;
use relief_scene::{ModelChoice, SceneKind};
use relief_term::ColorDepth;
use relief_texture::decode::procedural::brick;

fn picture(stage: &mut Stage, state: &State) -> Framebuffer {
    let mut fb = Framebuffer::new(160, 120);
    stage.render(&mut Renderer::new(), state, &mut fb);
    fb
}

/// The keys that neither change `state`'s picture nor say anything, as
/// "key (option)".
fn silent_keys(stage: &mut Stage, state: &State) -> Vec<String> {
    let mut silent = Vec::new();
    let before = picture(stage, state);
    for opt in relief_options::OPTIONS {
        for key in opt.keys {
            let mut s = state.clone();
            s.message = None;
            let press = key.press;
            update(&mut s, Action::Option { id: opt.id, press });
            if s.message.is_none() && picture(stage, &s) == before {
                silent.push(format!("{} ({:?})", key.keys[0], opt.id));
            }
        }
    }
    silent
}

fn with(state: &State, f: impl FnOnce(&mut Settings)) -> State {
    let mut s = state.clone();
    f(&mut s.settings);
    s
}

/// `b` outside Phong acts on the setting while the status line says
/// "Phong only" (README, key `b`).
const BUMP_OUTSIDE_PHONG: &str = "b (Bump)";

#[test]
fn every_option_key_changes_the_picture_or_says_why() {
    let mut stage = Stage::new(
        SceneKind::Cube,
        &ModelChoice::Cube,
        Arc::new(brick()),
        false,
    )
    .unwrap();
    let cube = State::new(Settings::default(), ColorDepth::Truecolor);
    let cases: Vec<(&str, State, Vec<&str>)> = vec![
        ("cube", cube.clone(), vec![]),
        ("bump off", with(&cube, |s| s.bump = false), vec![]),
        (
            "flat",
            with(&cube, |s| s.shading = Shading::Flat),
            vec![BUMP_OUTSIDE_PHONG],
        ),
        (
            "Gouraud",
            with(&cube, |s| s.shading = Shading::Gouraud),
            vec![BUMP_OUTSIDE_PHONG],
        ),
        ("lines", with(&cube, |s| s.display = Display::Lines), vec![]),
        (
            "points",
            with(&cube, |s| s.display = Display::Points),
            vec![],
        ),
        (
            "dot3",
            with(&cube, |s| s.technique = Technique::Dot3),
            vec![],
        ),
        ("specular", with(&cube, |s| s.specular = true), vec![]),
        ("lights off", with(&cube, |s| s.lights = false), vec![]),
        (
            "lights off, environment",
            with(&cube, |s| {
                s.lights = false;
                s.environment = true;
            }),
            vec![],
        ),
        ("texture off", with(&cube, |s| s.texture = false), vec![]),
        ("colours off", with(&cube, |s| s.colors = false), vec![]),
        ("MSAA", with(&cube, |s| s.aa = AntiAlias::Msaa4), vec![]),
        (
            "trilinear",
            with(&cube, |s| s.filter = Filter::Trilinear),
            vec![],
        ),
        (
            "emboss",
            with(&cube, |s| s.technique = Technique::Emboss),
            vec![],
        ),
        (
            "parallax",
            with(&cube, |s| s.technique = Technique::Parallax),
            vec![],
        ),
        ("POM", with(&cube, |s| s.technique = Technique::Pom), vec![]),
        (
            "bump strength 0",
            with(&cube, |s| s.bump_strength = 0.0),
            vec![],
        ),
    ];
    for (name, state, expected) in cases {
        assert_eq!(silent_keys(&mut stage, &state), expected, "{name}");
    }
    // The other scenes and built-in models.
    for (kind, model) in [
        (SceneKind::Shadow, ModelChoice::Cube),
        (SceneKind::Cube, ModelChoice::Sphere),
        (SceneKind::Cube, ModelChoice::Plane),
        (SceneKind::Cube, ModelChoice::Triangle),
    ] {
        stage.build(kind, &model).unwrap();
        let mut s = cube.clone();
        update(&mut s, Action::SceneBuilt(Ok((kind, model.clone()))));
        let silent = silent_keys(&mut stage, &s);
        assert!(silent.is_empty(), "{kind:?} {model:?}: {silent:?}");
    }
}

/// The same on a model file shaded physically: a glTF quad with a colour
/// texture and a normal map, no vertex colours.
#[test]
fn every_option_key_on_a_physical_model_changes_the_picture_or_says_why() {
    let checker = {
        let img = image::RgbaImage::from_fn(8, 8, |x, y| {
            image::Rgba(if (x + y) % 2 == 0 {
                [200, 60, 40, 255]
            } else {
                [40, 80, 200, 255]
            })
        });
        relief_texture::picture::encode(&img.into(), image::ImageFormat::Png).unwrap()
    };
    use crate::render::pbr;
    let tilted = pbr::solid_png([204, 128, 230, 255]);
    let m = r#"[{"pbrMetallicRoughness":{"baseColorTexture":{"index":0},"metallicFactor":0.3,"roughnessFactor":0.5},"normalTexture":{"index":1}}]"#;
    let path = pbr::write("sweep", &pbr::quads_glb(1, m, &[checker, tilted]));
    let model = ModelChoice::File(path);
    let mut stage = Stage::new(SceneKind::Cube, &model, Arc::new(brick()), false).unwrap();
    let mut s = State::new(Settings::default(), ColorDepth::Truecolor);
    update(&mut s, Action::SceneBuilt(Ok((SceneKind::Cube, model))));
    update(&mut s, Action::ModelNotes(stage.take_notes()));
    // Flat, without colours of its own: `n` and `c` are refused.
    assert!(s.physical && !s.features.vertex_colours && !s.features.varied_normals);
    // Its 8 × 8 texture is magnified, where bilinear and nearest-mip read
    // the same texels: that one step of `f` acts and shows nothing here.
    let magnified = "f (Filter)";
    let cases: Vec<(&str, State, Vec<&str>)> = vec![
        ("model", s.clone(), vec![magnified]),
        (
            "model, flat",
            with(&s, |s| s.shading = Shading::Flat),
            vec![BUMP_OUTSIDE_PHONG, magnified],
        ),
        // The studio still lights it: the normal map shows.
        (
            "model, lights off",
            with(&s, |s| s.lights = false),
            vec![magnified],
        ),
        (
            "model, lines",
            with(&s, |s| s.display = Display::Lines),
            vec![],
        ),
        // Its normal maps do not take the height map's strength.
        (
            "model, bump strength 0",
            with(&s, |s| s.bump_strength = 0.0),
            vec![magnified],
        ),
    ];
    for (name, state, expected) in cases {
        assert_eq!(silent_keys(&mut stage, &state), expected, "{name}");
    }
}

/// Model files without a material of their own (an OBJ box, a PLY
/// sphere): the texture keys wait for a texture, and say so.
#[test]
fn every_option_key_on_a_bare_model_changes_the_picture_or_says_why() {
    let dir = crate::common::scratch::scratch_dir("sweep-bare");
    let sphere = dir.join("sphere.ply");
    let ply = relief_bench::mesh_anchor::uv_sphere_ply(16, 32, 1.0, glam::Vec3::ZERO);
    std::fs::write(&sphere, ply).unwrap();
    let model = ModelChoice::File(sphere);
    let mut stage = Stage::new(SceneKind::Cube, &model, Arc::new(brick()), false).unwrap();
    let mut s = State::new(Settings::default(), ColorDepth::Truecolor);
    update(&mut s, Action::SceneBuilt(Ok((SceneKind::Cube, model))));
    update(&mut s, Action::ModelNotes(stage.take_notes()));
    assert!(!s.physical && s.features.varied_normals);
    for state in [
        s.clone(),
        with(&s, |s| s.filter = Filter::Trilinear),
        with(&s, |s| s.shading = Shading::Gouraud),
    ] {
        let silent = silent_keys(&mut stage, &state);
        assert!(silent.is_empty(), "{:?}: {silent:?}", state.settings);
    }
}

/// A flat model without texture coordinates (an OBJ tetrahedron whose
/// corners take their faces' normals, with a plain MTL colour): `n`, `F`
/// and the texture keys have nothing to show.
#[test]
fn every_option_key_on_a_flat_model_without_coordinates_changes_the_picture_or_says_why() {
    let dir = crate::common::scratch::scratch_dir("sweep-flat");
    let path = dir.join("tetra.obj");
    std::fs::write(dir.join("tetra.mtl"), "newmtl clay\nKd 0.8 0.5 0.3\n").unwrap();
    let mut obj = String::from("mtllib tetra.mtl\nusemtl clay\n");
    obj += "v 1 1 1\nv -1 -1 1\nv -1 1 -1\nv 1 -1 -1\n";
    // Each face's outward normal (a unit vector along the sum of its corners,
    // opposite the fourth), given to its three corners.
    for (k, [a, b, c]) in [[1, 3, 2], [1, 2, 4], [1, 4, 3], [2, 3, 4]]
        .into_iter()
        .enumerate()
    {
        let v = |i: usize| {
            [
                [1.0f32, 1.0, 1.0],
                [-1.0, -1.0, 1.0],
                [-1.0, 1.0, -1.0],
                [1.0, -1.0, -1.0],
            ][i - 1]
        };
        let n = glam::Vec3::from(v(a)) + glam::Vec3::from(v(b)) + glam::Vec3::from(v(c));
        let n = n.normalize();
        obj += &format!(
            "vn {} {} {}\nf {a}//{} {b}//{} {c}//{}\n",
            n.x,
            n.y,
            n.z,
            k + 1,
            k + 1,
            k + 1
        );
    }
    std::fs::write(&path, obj).unwrap();
    let model = ModelChoice::File(path);
    let mut stage = Stage::new(SceneKind::Cube, &model, Arc::new(brick()), false).unwrap();
    let mut s = State::new(Settings::default(), ColorDepth::Truecolor);
    update(&mut s, Action::SceneBuilt(Ok((SceneKind::Cube, model))));
    update(&mut s, Action::ModelNotes(stage.take_notes()));
    assert!(!s.features.varied_normals, "normals vary");
    assert!(!s.features.texture_coordinates, "texture coordinates");
    let gouraud = with(&s, |s| s.shading = Shading::Gouraud);
    assert!(silent_keys(&mut stage, &s).is_empty());
    assert_eq!(silent_keys(&mut stage, &gouraud), [BUMP_OUTSIDE_PHONG]);
}

/// A physically shaded model without normal maps: `b` and `h` have none
/// to act on, and say so.
#[test]
fn a_physical_model_without_normal_maps_refuses_the_bump_keys() {
    use crate::render::pbr;
    let m = format!("[{}]", pbr::material([0.8, 0.5, 0.3], 0.5, 0.4));
    let path = pbr::write("sweep-no-normals", &pbr::quads_glb(1, &m, &[]));
    let model = ModelChoice::File(path);
    let mut stage = Stage::new(SceneKind::Cube, &model, Arc::new(brick()), false).unwrap();
    let mut s = State::new(Settings::default(), ColorDepth::Truecolor);
    update(&mut s, Action::SceneBuilt(Ok((SceneKind::Cube, model))));
    update(&mut s, Action::ModelNotes(stage.take_notes()));
    assert!(s.physical && !s.features.normal_maps);
    for state in [s.clone(), with(&s, |s| s.filter = Filter::Trilinear)] {
        let silent = silent_keys(&mut stage, &state);
        assert!(silent.is_empty(), "{:?}: {silent:?}", state.settings);
    }
}
