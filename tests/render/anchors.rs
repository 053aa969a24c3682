//! Agreement with another renderer: the reference scene as Mesa llvmpipe drew
//! it (see tests/data/anchors/README.md) against relief's frame of the same
//! scene. Coverage must be identical in every variant; Phong (per-pixel
//! light, texture, Blinn bump) must agree within 3 levels per channel.
//! Gouraud and flat compute a different (documented) quantity, so their
//! colours are held to what that difference allows.

use std::path::Path;
use std::sync::Arc;

use relief_bench::anchors;
use relief_pipeline::render::render_frame;
use relief_texture::load_texture;

const W: usize = 320;
const H: usize = 240;

fn data(name: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

/// The llvmpipe picture of `variant`, as RGB rows top first.
fn anchor(variant: &str) -> Vec<[u8; 3]> {
    let path = data(&format!("anchors/anchor_llvmpipe_{variant}_{W}x{H}.png"));
    let img = relief_texture::picture::open(&path)
        .expect("anchor picture")
        .to_rgb8();
    assert_eq!((img.width() as usize, img.height() as usize), (W, H));
    img.pixels().map(|p| p.0).collect()
}

/// relief's frame of `variant` and the scene's background.
fn relief_frame(variant: &str) -> (Vec<[u8; 3]>, [u8; 3]) {
    let texture = load_texture(&data("reference-brick.png")).expect("reference brick");
    let scene = anchors::scene(Arc::new(texture));
    let (fb, stats) = render_frame(&scene, &anchors::settings(variant), W, H);
    assert_eq!(stats.counters.nonfinite, 0);
    (fb.pixels().to_vec(), scene.background)
}

/// (pixels covered differently, largest channel difference where both cover).
fn compare(variant: &str) -> (usize, u8, usize) {
    let (ours, background) = relief_frame(variant);
    let theirs = anchor(variant);
    let mut coverage_mismatch = 0;
    let mut max = 0u8;
    let mut covered = 0;
    for (a, b) in ours.iter().zip(&theirs) {
        let (ca, cb) = (*a != background, *b != background);
        if ca != cb {
            coverage_mismatch += 1;
        } else if ca {
            covered += 1;
            for c in 0..3 {
                max = max.max(a[c].abs_diff(b[c]));
            }
        }
    }
    (coverage_mismatch, max, covered)
}

#[test]
fn phong_agrees_with_llvmpipe_within_3_levels() {
    let (mismatch, max, covered) = compare("phong");
    assert_eq!(covered, 11_741);
    assert_eq!(mismatch, 0, "pixels covered by one renderer only");
    assert!(max <= 3, "largest channel difference {max}");
}

#[test]
fn gouraud_covers_the_same_pixels_and_stays_close() {
    // relief interpolates the albedo and the light apart and multiplies them;
    // llvmpipe interpolates their product. They differ inside a triangle by
    // at most a few levels on this scene.
    let (mismatch, max, _) = compare("gouraud");
    assert_eq!(mismatch, 0);
    assert!(max <= 8, "largest channel difference {max}");
}

#[test]
fn flat_covers_the_same_pixels() {
    // relief's flat gives one colour per facet (the facet's mean vertex
    // colour, lit at its centre); llvmpipe's keeps interpolating the vertex
    // colour. Only coverage is comparable.
    let (mismatch, _, covered) = compare("flat");
    assert_eq!(covered, 11_741);
    assert_eq!(mismatch, 0);
}

/// The three-way comparison (`relief bench --anchors`) finds the three
/// pictures, and both renderers cover the same 11,741 pixels in each.
#[test]
fn the_three_way_comparison_finds_every_variant() {
    let texture = load_texture(&data("reference-brick.png")).expect("reference brick");
    let rows = anchors::three_way(Arc::new(texture), 1);
    let variants: Vec<&str> = rows.iter().map(|r| r.variant).collect();
    assert_eq!(variants, anchors::VARIANTS);
    assert!(rows.iter().all(|r| r.covered == 11_741));
    // The same pair as `phong_agrees_with_llvmpipe_within_3_levels`.
    assert!(rows[2].relief_llvmpipe.max <= 3);
}

// --- The model-file view (`relief bench --anchors --model`), which
// docs/tools/llvmpipe_mesh.py draws with llvmpipe: the same fit, camera,
// lights, vertex colours and Lambert terms, checked here against the
// analytic sphere they describe.

use relief_bench::mesh_anchor;
use relief_core::framebuffer::Framebuffer;
use relief_pipeline::render::Renderer;

/// A UV sphere of radius 3 away from the origin (the fit must move and
/// scale it to radius 1.5 at the origin), written as the harness writes it,
/// rendered in the anchor view at 320×240 without shadows.
fn sphere_frame(name: &str) -> (Framebuffer, relief_scene::Scene) {
    let dir = crate::common::scratch::scratch_dir("mesh-anchor");
    let path = dir.join(format!("{name}.ply"));
    let centre = glam::Vec3::new(1.0, -2.0, 0.5);
    std::fs::write(&path, mesh_anchor::uv_sphere_ply(64, 128, 3.0, centre)).unwrap();
    let scene = mesh_anchor::scene(&path).expect("the sphere loads");
    let _ = std::fs::remove_file(&path);
    assert_eq!(scene.objects.len(), 1);
    assert_eq!(scene.objects[0].mesh.triangles.len(), 2 * 128 * 63);
    assert!(scene.objects[0].mesh.closed, "back faces are culled");
    let (w, h) = mesh_anchor::COMPARE_SIZE;
    let mut fb = Framebuffer::new(w, h);
    let mut renderer = Renderer::new();
    renderer.set_shadows(false);
    let stats = renderer.render(&scene, &mesh_anchor::settings(), &mut fb);
    assert_eq!(stats.counters.shadow_texels, 0);
    (fb, scene)
}

/// The silhouette of a sphere of radius r seen from distance d is a circle
/// of angular radius asin(r/d); with a vertical field of view of 60° its
/// radius on the picture is tan(asin(r/d)) / tan(30°) half-heights.
#[test]
fn the_model_view_covers_the_analytic_silhouette() {
    let (fb, scene) = sphere_frame("silhouette");
    let (w, h) = mesh_anchor::COMPARE_SIZE;
    let alpha = (1.5f64 / 5.0).asin();
    let radius_px = alpha.tan() / 30f64.to_radians().tan() * h as f64 / 2.0;
    let expected = std::f64::consts::PI * radius_px * radius_px; // 13,424 pixels
    let covered = mesh_anchor::covered(&fb, scene.background) as f64;
    // The polygon (128 segments, 64 rings) is inscribed: at most 0.1 % smaller.
    assert!(
        (covered / expected - 1.0).abs() < 0.005,
        "covered {covered}, analytic {expected:.0}"
    );
    // Centred: the covered pixels' centroid is the picture's centre.
    let (mut sx, mut sy) = (0.0, 0.0);
    for (i, p) in fb.pixels().iter().enumerate() {
        if *p != scene.background {
            sx += (i % w) as f64 + 0.5;
            sy += (i / w) as f64 + 0.5;
        }
    }
    assert!((sx / covered - w as f64 / 2.0).abs() < 0.25);
    assert!((sy / covered - h as f64 / 2.0).abs() < 0.25);
}

/// The colour the harness computes, by hand: the ray through a pixel
/// centre meets the sphere of radius 1.5 at P (world); the model point is
/// P turned back by the rotation 25°, 35°, 0° (X, then Y, then Z); its
/// colour 0.4 + 0.3·(q/1.5 + 1); the light ambient 0.1 + Σ c·max(0, N·L)
/// over the four reference lights, N = P/1.5.
#[test]
fn the_model_view_shades_as_the_harness_computes() {
    let (fb, _) = sphere_frame("shading");
    let (w, h) = mesh_anchor::COMPARE_SIZE;
    let rotation = relief_scene::rotation_matrix(glam::Vec3::new(25.0, 35.0, 0.0)).as_dmat4();
    let lights = [
        ([3.0, 4.0, 6.0], [1.0, 1.0, 1.0]),
        ([-8.0, 1.0, 3.0], [0.3, 0.0, 0.0]),
        ([8.0, -2.0, 3.0], [0.0, 0.3, 0.0]),
        ([0.0, -8.0, 2.0], [0.0, 0.0, 0.3]),
    ];
    let tan = 30f64.to_radians().tan();
    let aspect = w as f64 / h as f64;
    let mut checked = 0;
    for (px, py) in [(160, 120), (130, 90), (200, 150), (110, 140), (175, 70)] {
        let x = ((px as f64 + 0.5) / w as f64 * 2.0 - 1.0) * tan * aspect;
        let y = (1.0 - (py as f64 + 0.5) / h as f64 * 2.0) * tan;
        let eye = glam::DVec3::new(0.0, 0.0, 5.0);
        let dir = glam::DVec3::new(x, y, -1.0).normalize();
        // |eye + t·dir| = 1.5, nearest t.
        let b = eye.dot(dir);
        let t = -b - (b * b - (eye.length_squared() - 2.25)).sqrt();
        let p = eye + t * dir;
        let n = p / 1.5;
        let q = rotation.inverse().transform_point3(p);
        let mut expected = [0u8; 3];
        for c in 0..3 {
            let mut light = 0.1;
            for (pos, col) in lights {
                let l = (glam::DVec3::from(pos) - p).normalize();
                light += col[c] * n.dot(l).max(0.0);
            }
            let colour = 0.4 + 0.3 * (q[c] / 1.5 + 1.0);
            expected[c] = ((colour * light).clamp(0.0, 1.0) * 255.0).round() as u8;
        }
        let got = fb.pixels()[py * w + px];
        for c in 0..3 {
            assert!(
                got[c].abs_diff(expected[c]) <= 2,
                "pixel ({px}, {py}): {got:?}, by hand {expected:?}"
            );
        }
        checked += 1;
    }
    assert_eq!(checked, 5);
}
