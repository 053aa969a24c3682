//! glTF `alphaMode: BLEND`: translucent surfaces composited over what is
//! behind them, far to near, whatever order the file gives them in.

use relief_core::framebuffer::Framebuffer;
use relief_core::settings::AntiAlias;
use relief_core::settings::Settings;
use relief_pipeline::render::Renderer;
use relief_scene::Scene;

use super::models_gltf::{Doc, Prim, encode, face_on, load_ok, quad, scene_of, write};

const W: usize = 160;
const H: usize = 120;
const MAGENTA: [u8; 3] = [255, 0, 255];

/// Three 2 × 2 quads facing the camera at z = −1, 0 and 1 (far to near),
/// each of its own material, written in the file in `order`; `alpha[k]`
/// and `mode[k]` are quad k's base colour alpha and alpha mode.
fn stack(order: [usize; 3], alpha: [f32; 3], mode: [&str; 3]) -> Scene {
    let colours = [[1.0, 0.2, 0.2], [0.2, 1.0, 0.2], [0.2, 0.2, 1.0]];
    let prims: Vec<Prim> = order
        .iter()
        .map(|&k| {
            let mut q = quad(-1.0, 1.0, -1.0, 1.0, 0.0, 1.0);
            for p in &mut q.pos {
                p[2] = k as f32 - 1.0;
            }
            q.material = Some(k);
            q
        })
        .collect();
    let mut doc = Doc::new(prims);
    let materials: Vec<String> = (0..3)
        .map(|k| {
            let [r, g, b] = colours[k];
            format!(
                r#"{{"pbrMetallicRoughness":{{"baseColorFactor":[{r},{g},{b},{}]}},"alphaMode":"{}"}}"#,
                alpha[k], mode[k]
            )
        })
        .collect();
    doc.materials = format!("[{}]", materials.join(","));
    let name = format!("stack-{order:?}-{alpha:?}-{mode:?}.glb").replace([' ', '[', ']', ','], "");
    scene_of(load_ok(&write("blend", &name, &encode(&doc))))
}

fn draw(scene: &Scene, aa: AntiAlias) -> Framebuffer {
    let settings = Settings { aa, ..face_on() };
    let mut fb = Framebuffer::new(W, H);
    let mut renderer = Renderer::new();
    // Translucent layers cast shadows where opaque enough: none here, so
    // each layer's colour alone is the colour it has in the stack.
    renderer.set_shadows(false);
    renderer.render(scene, &settings, &mut fb);
    fb
}

fn centre(fb: &Framebuffer) -> [u8; 3] {
    fb.get(W / 2, H / 2)
}

/// `src` over `dst` at opacity 1/2, rounded as an 8-bit target does.
fn half_over(dst: [u8; 3], src: [u8; 3]) -> [u8; 3] {
    std::array::from_fn(|i| ((f32::from(dst[i]) + f32::from(src[i])) / 2.0).round() as u8)
}

/// Each layer alone (opaque, the others wholly transparent) gives its lit
/// colour c_k; the three at alpha 1/2 give ((bg·½ + c₀·½)·½ + c₁·½)·½ + c₂·½
/// at the centre, for every order of the file and with multisampling.
#[test]
fn three_half_transparent_layers_compose_far_to_near_in_any_file_order() {
    for aa in [AntiAlias::Off, AntiAlias::Msaa4] {
        let alone = |k: usize| {
            let mut alpha = [0.0; 3];
            alpha[k] = 1.0;
            centre(&draw(&stack([0, 1, 2], alpha, ["BLEND"; 3]), aa))
        };
        let c = [alone(0), alone(1), alone(2)];
        for (k, colour) in c.iter().enumerate() {
            assert_ne!(*colour, MAGENTA, "layer {k} alone is drawn");
        }
        let want = half_over(half_over(half_over(MAGENTA, c[0]), c[1]), c[2]);
        for order in [
            [0, 1, 2],
            [2, 1, 0],
            [1, 0, 2],
            [1, 2, 0],
            [2, 0, 1],
            [0, 2, 1],
        ] {
            let fb = draw(&stack(order, [0.5; 3], ["BLEND"; 3]), aa);
            let got = centre(&fb);
            for i in 0..3 {
                assert!(
                    got[i].abs_diff(want[i]) <= 1,
                    "{aa:?}, file order {order:?}: {got:?}, want {want:?}"
                );
            }
        }
    }
}

/// An opaque layer hides the translucent one behind it and shows through
/// the one in front; a MASK layer at the same alpha is cut out whole.
#[test]
fn an_opaque_layer_hides_what_is_behind_it_and_mask_is_not_blend() {
    let aa = AntiAlias::Off;
    let alone = |k: usize| {
        let mut alpha = [0.0; 3];
        alpha[k] = 1.0;
        centre(&draw(&stack([0, 1, 2], alpha, ["BLEND"; 3]), aa))
    };
    let (middle, near) = (alone(1), alone(2));
    let modes = ["BLEND", "OPAQUE", "BLEND"];
    let fb = draw(&stack([2, 0, 1], [0.5, 1.0, 0.5], modes), aa);
    let want = half_over(middle, near);
    let got = centre(&fb);
    for i in 0..3 {
        assert!(got[i].abs_diff(want[i]) <= 1, "{got:?}, want {want:?}");
    }
    // MASK at alpha 0.4 (cutoff 0.5) draws nothing.
    let masked = draw(&stack([0, 1, 2], [0.4; 3], ["MASK"; 3]), aa);
    assert!(masked.pixels().iter().all(|&p| p == MAGENTA));
}
