//! Loaded textures through the renderer: every accepted file renders, with
//! every filter, and the mip chain is built only when a pixel is minified.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use clap::ValueEnum;
use glam::Vec3;
use relief_core::settings::Settings;
use relief_core::settings::{Filter, HeightDerivative};
use relief_pipeline::render::render_frame;
use relief_scene::Scene;
use relief_texture::{Texture, builtins, load_texture};

/// Every filter, so a new one is checked here too.
fn filters() -> impl Iterator<Item = Filter> {
    Filter::value_variants().iter().copied()
}

fn data(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(rel)
}

/// Renders `tex` on all six faces with `filter`; returns covered pixels.
fn render(tex: &Arc<Texture>, filter: Filter, w: usize, h: usize) -> usize {
    render_turned(tex, filter, w, h, Settings::default().rotation)
}

fn render_turned(tex: &Arc<Texture>, filter: Filter, w: usize, h: usize, rotation: Vec3) -> usize {
    let scene = Scene::cube(Arc::clone(tex), true);
    let settings = Settings {
        filter,
        rotation,
        ..Settings::default()
    };
    let (fb, stats) = render_frame(&scene, &settings, w, h);
    assert_eq!(stats.counters.nonfinite, 0, "{}", tex.name);
    fb.pixels()
        .iter()
        .filter(|&&p| p != scene.background)
        .count()
}

#[test]
fn every_accepted_file_renders_with_every_filter() {
    let mut files: Vec<PathBuf> = std::fs::read_dir(data("pngsuite"))
        .unwrap()
        .chain(std::fs::read_dir(data("formats")).unwrap())
        .map(|e| e.unwrap().path())
        .filter(|p| {
            let name = p.file_name().unwrap().to_string_lossy();
            !name.starts_with('x') && !name.starts_with("PngSuite.")
        })
        .collect();
    files.sort();
    files.push(data("reference-brick.png"));
    assert!(files.len() > 190);
    for path in &files {
        let tex = Arc::new(load_texture(path).unwrap());
        for filter in filters() {
            // 40×30 pixels: the cube covers a few hundred of them.
            assert!(render(&tex, filter, 40, 30) > 100, "{}", path.display());
        }
    }
    for b in builtins() {
        let tex = Arc::new(b.load().unwrap());
        assert!(render(&tex, Filter::Anisotropic, 40, 30) > 100);
    }
}

#[test]
fn the_chain_is_built_only_for_minified_textures() {
    // The front face seen straight on covers 104×104 pixels at 320×240: a
    // 96×96 picture is magnified everywhere. (In the default view the top
    // face is seen at a grazing angle, so even a 32×32 picture is minified
    // across it there.)
    let texels = vec![[0.5, 0.2, 0.1, 0.7]; 96 * 96];
    let small = Arc::new(Texture::new(
        "96",
        relief_texture::Level {
            wrap: Default::default(),
            width: 96,
            height: 96,
            texels: texels.into(),
        },
    ));
    for filter in filters() {
        assert_eq!(
            render_turned(&small, filter, 320, 240, Vec3::ZERO),
            104 * 104
        );
    }
    assert!(!small.mips_built());
    let big = Arc::new(Texture::new(
        "128",
        relief_texture::Level::solid(128, 128, [0.5, 0.2, 0.1, 0.7]),
    ));
    render_turned(&big, Filter::Trilinear, 320, 240, Vec3::ZERO);
    assert!(big.mips_built(), "128 texels over 104 pixels is minified");
    // The 256×256 brick in 40×30 pixels: minified, the chain is built once.
    let brick = Arc::new(builtins()[0].load().unwrap());
    render(&brick, Filter::Bilinear, 40, 30);
    assert!(!brick.mips_built(), "bilinear never reads the chain");
    render(&brick, Filter::Trilinear, 40, 30);
    assert!(brick.mips_built());
}

#[test]
fn filters_and_height_derivatives_change_a_minified_frame() {
    let brick = Arc::new(builtins()[0].load().unwrap());
    let scene = Scene::cube(Arc::clone(&brick), true);
    let frame = |filter, height_derivative| {
        let settings = Settings {
            filter,
            height_derivative,
            ..Settings::default()
        };
        render_frame(&scene, &settings, 64, 48).0
    };
    let bilinear = frame(Filter::Bilinear, HeightDerivative::Filtered);
    let trilinear = frame(Filter::Trilinear, HeightDerivative::Filtered);
    let texel = frame(Filter::Trilinear, HeightDerivative::Texel);
    assert_ne!(bilinear.pixels(), trilinear.pixels());
    assert_ne!(trilinear.pixels(), texel.pixels());
}

/// A face turned 40° away: its texture coordinates, read back from the
/// frame, match the exact ray–plane intersection on both of its triangles,
/// so the mapping is perspective-correct and continuous across the diagonal.
#[test]
fn texture_mapping_is_perspective_correct_across_both_triangles() {
    use relief_core::settings::Shading;
    // A grey ramp g = u / 2 (texel centres at (x + ½)/256), and a flat grey
    // of ½ under the same light: the ratio of the two frames is u.
    let ramp = (0..256).map(|x| [(x as f32 + 0.5) / 512.0; 4]).collect();
    let level = |texels| relief_texture::Level {
        wrap: Default::default(),
        width: 256,
        height: 1,
        texels,
    };
    let ramp = Scene::cube(Arc::new(Texture::new("ramp", level(ramp))), false);
    let flat = Scene::cube(
        Arc::new(Texture::new("flat", level(vec![[0.5; 4]; 256].into()))),
        false,
    );
    let angle = 40.0f32;
    let settings = Settings {
        shading: Shading::Flat,
        colors: false,
        bump: false,
        filter: Filter::Bilinear,
        rotation: Vec3::new(0.0, angle, 0.0),
        ..Settings::default()
    };
    let (w, h) = (320usize, 240usize);
    let (fb, _) = render_frame(&ramp, &settings, w, h);
    let (reference, _) = render_frame(&flat, &settings, w, h);
    let rot = glam::Mat3::from_rotation_y(angle.to_radians());
    let (normal, u_axis, v_axis) = (rot * Vec3::Z, rot * Vec3::X, rot * Vec3::Y);
    let eye = Vec3::new(0.0, 0.0, 5.0);
    let tan = (30.0f32).to_radians().tan();
    let aspect = w as f32 / h as f32;
    let (mut checked, mut worst) = (0, 0.0f32);
    let mut sides = [0, 0];
    for py in 0..h {
        for px in 0..w {
            let nx = (px as f32 + 0.5) / w as f32 * 2.0 - 1.0;
            let ny = 1.0 - (py as f32 + 0.5) / h as f32 * 2.0;
            let dir = Vec3::new(nx * tan * aspect, ny * tan, -1.0);
            let t = normal.dot(normal - eye) / normal.dot(dir);
            let local = eye + dir * t - normal;
            let (s, tt) = (
                (local.dot(u_axis) + 1.0) / 2.0,
                (local.dot(v_axis) + 1.0) / 2.0,
            );
            if !(0.05..0.95).contains(&s) || !(0.05..0.95).contains(&tt) {
                continue;
            }
            let g = reference.get(px, py)[1];
            assert!(
                g > 60,
                "{px},{py} is not on the face: {:?}",
                reference.get(px, py)
            );
            let u = fb.get(px, py)[1] as f32 / g as f32;
            worst = worst.max((u - s).abs());
            checked += 1;
            sides[(tt > s) as usize] += 1;
        }
    }
    assert!(
        checked > 3000 && sides[0] > 1000 && sides[1] > 1000,
        "{checked} {sides:?}"
    );
    // 8-bit colour resolves u to about 1/150 (measured worst 0.0055); an affine
    // mapping over a depth range of 1.38:1 would be off by up to about 0.08.
    assert!(worst < 0.02, "u off by {worst}");
}

/// One quad facing +Z with its texture coordinates shifted by `dv` in v.
fn quad(dv: f32) -> relief_scene::Mesh {
    let text = format!(
        "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\n\
         vt 0 {a}\nvt 1 {a}\nvt 1 {b}\nvt 0 {b}\n\
         f 1/1 2/2 3/3\nf 1/1 3/3 4/4\n",
        a = dv,
        b = 1.0 + dv,
    );
    relief_scene::obj::parse("quad.obj", text).unwrap()
}

/// The texture repeats, so adding a whole number to every v changes no
/// texel and no footprint: with the mip filters too, the picture must stay
/// the same within rounding. (The footprint once differentiated Σuv·q²·l /
/// Σq·l, which grows with v: 2062 of 2578 pixels moved by more than 2 with
/// nearest-mip, up to 54.)
#[test]
fn whole_number_uv_shifts_change_no_mip_filtered_pixel() {
    let brick = Arc::new(builtins()[0].load().unwrap());
    let noise: Vec<[f32; 4]> = (0..256 * 256u32)
        .map(|i| {
            let h = i.wrapping_mul(0x9e37_79b9).rotate_left(13) ^ i;
            let g = (h.wrapping_mul(0x85eb_ca6b) >> 24) as f32 / 255.0;
            [g, 1.0 - g, 0.5 * g, g]
        })
        .collect();
    let noise = Arc::new(Texture::new(
        "noise",
        relief_texture::Level {
            wrap: Default::default(),
            width: 256,
            height: 256,
            texels: noise.into(),
        },
    ));
    let (w, h) = (240, 180);
    for tex in [&brick, &noise] {
        for filter in [Filter::NearestMip, Filter::Trilinear, Filter::Anisotropic] {
            let settings = Settings {
                bump: false,
                filter,
                rotation: Vec3::new(-72.0, 0.0, 0.0),
                ..Settings::default()
            };
            let frame = |dv: f32| {
                let scene = Scene::model(quad(dv), Arc::clone(tex));
                render_frame(&scene, &settings, w, h).0
            };
            let (a, b) = (frame(0.0), frame(3.0));
            let (mut covered, mut moved, mut worst) = (0, 0, 0);
            for (p, q) in a.pixels().iter().zip(b.pixels()) {
                if *p == relief_scene::BACKGROUND {
                    continue;
                }
                covered += 1;
                let d = (0..3).map(|c| p[c].abs_diff(q[c])).max().unwrap();
                worst = worst.max(d);
                moved += (d > 2) as usize;
            }
            assert!(covered > 1200, "{covered}");
            // Rounding may flip a level or a texel at a handful of pixels.
            assert!(
                moved * 200 <= covered,
                "{} {filter:?}: {moved} of {covered} moved, worst {worst}",
                tex.name
            );
        }
    }
}
