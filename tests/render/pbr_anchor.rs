//! The physically shaded model-file view (`relief bench --anchors --model
//! FILE --pbr`), which docs/tools/llvmpipe_mesh.py bench --pbr draws with
//! llvmpipe: the Phong view's coverage, and pixels of a sphere worked by
//! hand from the glTF BRDF under a uniform environment, where the
//! image-based light has a closed form but for the split sum's integrals
//! (summed here over the hemisphere).

use std::f64::consts::PI;
use std::sync::Arc;

use glam::{DVec3, Vec3};

use relief_bench::mesh_anchor;
use relief_bench::pbr_anchor::{self, Factors};
use relief_core::framebuffer::Framebuffer;
use relief_pipeline::render::Renderer;
use relief_scene::Scene;
use relief_texture::environment::Environment;

/// The radiance of the uniform environment.
const SKY: f32 = 0.5;

/// A UV sphere of radius 3 away from the origin (the fit moves and scales
/// it to radius 1.5 at the origin), loaded as `--model` loads it.
fn sphere_scene(name: &str) -> Scene {
    let dir = crate::common::scratch::scratch_dir("pbr-anchor");
    let path = dir.join(format!("{name}.ply"));
    let centre = Vec3::new(1.0, -2.0, 0.5);
    std::fs::write(&path, mesh_anchor::uv_sphere_ply(64, 128, 3.0, centre)).unwrap();
    let scene = mesh_anchor::scene(&path).expect("the sphere loads");
    let _ = std::fs::remove_file(&path);
    scene
}

/// `scene` at the comparison size, without shadows.
fn draw(scene: &Scene) -> Framebuffer {
    let (w, h) = mesh_anchor::COMPARE_SIZE;
    let mut fb = Framebuffer::new(w, h);
    let mut renderer = Renderer::new();
    renderer.set_shadows(false);
    renderer.render(scene, &mesh_anchor::settings(), &mut fb);
    fb
}

fn uniform() -> Arc<Environment> {
    Arc::new(Environment::from_fn("uniform", 64, 32, |_| {
        Vec3::splat(SKY)
    }))
}

/// The split sum's A and B at N·V = `nv` for α = 1 (roughness 1), where
/// D = 1/π and Vis = ½/(N·L + N·V): ∫ (1 − Fc)·D·Vis·N·L dω and
/// ∫ Fc·D·Vis·N·L dω, Fc = (1 − V·H)⁵, by the midpoint rule over θ and φ.
fn split_sum_rough(nv: f64) -> (f64, f64) {
    let v = DVec3::new((1.0 - nv * nv).sqrt(), 0.0, nv);
    let (nt, np) = (400, 800);
    let (mut a, mut b) = (0.0, 0.0);
    for i in 0..nt {
        let theta = (i as f64 + 0.5) / nt as f64 * PI / 2.0;
        for j in 0..np {
            let phi = (j as f64 + 0.5) / np as f64 * 2.0 * PI;
            let l = DVec3::new(
                theta.sin() * phi.cos(),
                theta.sin() * phi.sin(),
                theta.cos(),
            );
            let nl = l.z;
            let vh = v.dot((l + v).normalize());
            let f = 1.0 / PI * 0.5 / (nl + nv) * nl;
            let d_omega = theta.sin() * (PI / 2.0 / nt as f64) * (2.0 * PI / np as f64);
            let fc = (1.0 - vh).powi(5);
            a += (1.0 - fc) * f * d_omega;
            b += fc * f * d_omega;
        }
    }
    (a, b)
}

/// Khronos PBR Neutral of one colour.
fn neutral(c: DVec3) -> DVec3 {
    let low = c.min_element();
    let offset = if low < 0.08 {
        low - 6.25 * low * low
    } else {
        0.04
    };
    let c = c - DVec3::splat(offset);
    let peak = c.max_element();
    if peak < 0.76 {
        return c;
    }
    let d = 0.24;
    let new_peak = 1.0 - d * d / (peak + d - 0.76);
    let g = 1.0 - 1.0 / (0.15 * (peak - new_peak) + 1.0);
    c * (new_peak / peak) * (1.0 - g) + DVec3::splat(new_peak) * g
}

fn srgb_byte(x: f64) -> u8 {
    let x = x.clamp(0.0, 1.0);
    let e = if x <= 0.003_130_8 {
        12.92 * x
    } else {
        1.055 * x.powf(1.0 / 2.4) - 0.055
    };
    (e * 255.0).round() as u8
}

/// The colour of pixel (`px`, `py`) by hand: the ray through its centre
/// meets the sphere of radius 1.5 at P, N = P/1.5, V toward the eye; the
/// key light of colour 1 adds N·L·((1 − F)·(1 − m)·base + π·F·D·Vis), the
/// uniform environment c·((1 − m)·base·(1 − S) + S), S = F0·A + B.
fn by_hand(f: Factors, px: usize, py: usize) -> [u8; 3] {
    assert_eq!(
        f.roughness, 1.0,
        "the split sum is summed here for roughness 1"
    );
    let (w, h) = mesh_anchor::COMPARE_SIZE;
    let tan = 30f64.to_radians().tan();
    let x = ((px as f64 + 0.5) / w as f64 * 2.0 - 1.0) * tan * w as f64 / h as f64;
    let y = (1.0 - (py as f64 + 0.5) / h as f64 * 2.0) * tan;
    let eye = DVec3::new(0.0, 0.0, 5.0);
    let dir = DVec3::new(x, y, -1.0).normalize();
    let t = -eye.dot(dir) - (eye.dot(dir).powi(2) - (eye.length_squared() - 2.25)).sqrt();
    let p = eye + t * dir;
    let (n, v) = (p / 1.5, -dir);
    let nv = n.dot(v);
    let l = (pbr_anchor::KEY_LIGHT.as_dvec3() - p).normalize();
    let nl = n.dot(l).max(0.0);
    let hv = (l + v).normalize();
    let base = f.base.as_dvec3();
    let m = f.metallic as f64;
    let f0 = DVec3::splat(0.04).lerp(base, m);
    let fresnel = f0 + (DVec3::ONE - f0) * (1.0 - v.dot(hv)).powi(5);
    // α = 1: D = 1/π, Vis = ½/(N·L + N·V).
    let specular = fresnel * (PI * (1.0 / PI) * 0.5 / (nl + nv));
    let diffuse = base * (1.0 - m);
    let light = ((DVec3::ONE - fresnel) * diffuse + specular) * nl;
    let (a, b) = split_sum_rough(nv);
    let s = f0 * a + DVec3::splat(b);
    let sky = SKY as f64;
    let environment = sky * (diffuse * (DVec3::ONE - s) + s);
    let c = neutral(light + environment);
    [srgb_byte(c.x), srgb_byte(c.y), srgb_byte(c.z)]
}

/// The physical view covers what the Phong view covers (the same fit,
/// pose and camera), and shades five pixels as the formulas say, for a
/// metal and a dielectric, within 2 levels (relief's sRGB encoding is a
/// fit within 0.4 of a level, its split-sum table is interpolated, its
/// normals those of a 64 × 128 polygon).
#[test]
fn the_physical_view_shades_as_the_brdf_computes() {
    let scene = sphere_scene("pbr");
    let phong = draw(&scene);
    let (w, _) = mesh_anchor::COMPARE_SIZE;
    for base in [Vec3::new(1.0, 0.71, 0.29), Vec3::new(0.05, 0.2, 0.6)] {
        for metallic in [1.0, 0.0] {
            let f = Factors {
                base,
                metallic,
                roughness: 1.0,
            };
            let fb = draw(&pbr_anchor::physical(scene.clone(), f, uniform()));
            assert_eq!(
                mesh_anchor::covered(&fb, scene.background),
                mesh_anchor::covered(&phong, scene.background)
            );
            for (px, py) in [(160, 120), (130, 90), (200, 150), (110, 140), (175, 70)] {
                let (got, want) = (fb.pixels()[py * w + px], by_hand(f, px, py));
                for c in 0..3 {
                    assert!(
                        got[c].abs_diff(want[c]) <= 2,
                        "{f}: pixel ({px}, {py}) {got:?}, by hand {want:?}"
                    );
                }
            }
        }
    }
}
