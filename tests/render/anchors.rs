//! Agreement with another renderer: the reference scene as Mesa llvmpipe drew
//! it (see tests/data/anchors/README.md) against relief's frame of the same
//! scene. Coverage must be identical in every variant; Phong (per-pixel
//! light, texture, Blinn bump) must agree within 3 levels per channel.
//! Gouraud and flat compute a different (documented) quantity, so their
//! colours are held to what that difference allows.

use std::path::Path;
use std::sync::Arc;

use relief::bench::anchors;
use relief::render::render_frame;
use relief::texture::load_texture;

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
    let img = image::open(&path).expect("anchor picture").to_rgb8();
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
