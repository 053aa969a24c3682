//! Normal maps read from files (`--normal-map`, docs/bump-dot3.md): a file
//! holding the analytic normal of a known slope, written by hand in the
//! common "OpenGL" convention (red = right, green = up the picture), gives
//! the same map and the same dot3 frame as the map relief derives from a
//! height ramp of that slope; a flat file renders like no bump; a file that
//! is off costs nothing; bad files are refused; `N` switches through `update`.

use crate::techniques_scenes;

use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::{Vec2, Vec3};
use image::{ImageBuffer, Rgb};
use relief::app::{Action, State, update};
use relief_core::framebuffer::Framebuffer;
use relief_core::settings::Settings;
use relief_core::settings::{DEFAULT_BUMP_STRENGTH, Filter, Technique};
use relief_pipeline::render::Renderer;
use relief_pipeline::render::render_frame;
use relief_scene::Scene;
use relief_texture::normal_map_file::{FileNormalMap, load_normal_map, load_normal_map_from_bytes};
use relief_texture::sample::normal_map::normal_map_scale;
use relief_texture::{NormalMap, Texture};
use techniques_scenes::*;

/// Texels per side of the test maps.
const N: usize = 64;
/// Height rise per unit of texture coordinate along the ramp.
const SLOPE: f32 = 0.5;

/// A scratch file, removed when dropped.
struct Scratch(PathBuf);

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.0);
    }
}

fn scratch(name: &str) -> Scratch {
    Scratch(std::env::temp_dir().join(format!("relief-nmap-{}-{name}", std::process::id())))
}

/// Which texture axis the height rises along.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Axis {
    U,
    V,
}

/// A white texture whose height rises by `SLOPE` per unit of u (or v):
/// 0.25 + SLOPE·t at texel t's centre (it wraps back at the seam).
fn ramp(axis: Axis) -> Texture {
    texture_of(N, |x, y| {
        let t = if axis == Axis::U { x } else { y };
        [1.0, 1.0, 1.0, 0.25 + SLOPE * (t as f32 + 0.5) / N as f32]
    })
}

/// The ramp's normal as a normal-map file states it, in the picture's own
/// axes (right, up the picture, out), at relief's slope scale for bump
/// strength `k` (docs/bump-dot3.md): a height rising to the right faces
/// left; one rising *down* the picture (relief's +v: v = 0 is the top row)
/// faces *up* the picture, which is +green in that convention.
fn analytic_rgb(axis: Axis, k: f32) -> [f64; 3] {
    let s = (normal_map_scale(k) * SLOPE) as f64;
    let (right, up) = match axis {
        Axis::U => (-s, 0.0),
        Axis::V => (0.0, s),
    };
    let len = (right * right + up * up + 1.0).sqrt();
    [right / len, up / len, 1.0 / len].map(|c| (c + 1.0) / 2.0)
}

/// The analytic ramp as an 8-bit or 16-bit PNG file.
fn write_ramp_file(axis: Axis, k: f32, bits16: bool, name: &str) -> Scratch {
    let file = scratch(name);
    let rgb = analytic_rgb(axis, k);
    if bits16 {
        let px = Rgb(rgb.map(|c| (c * 65535.0).round() as u16));
        let picture = ImageBuffer::from_pixel(N as u32, N as u32, px);
        relief_texture::picture::save(&picture.into(), &file.0).unwrap();
    } else {
        let px = Rgb(rgb.map(|c| (c * 255.0).round() as u8));
        let picture = ImageBuffer::from_pixel(N as u32, N as u32, px);
        relief_texture::picture::save(&picture.into(), &file.0).unwrap();
    }
    file
}

/// Largest per-component difference between the two maps, away from the
/// ramp's wrap seam (the first and last texel along its axis).
fn map_difference(a: &NormalMap, b: &NormalMap, axis: Axis) -> f32 {
    let mut worst = 0.0f32;
    for y in 0..N {
        for x in 0..N {
            let t = if axis == Axis::U { x } else { y };
            if t == 0 || t == N - 1 {
                continue;
            }
            let (p, q) = (a.normals.at(y * N + x), b.normals.at(y * N + x));
            for c in 0..3 {
                worst = worst.max((p[c] - q[c]).abs());
            }
        }
    }
    worst
}

/// The strength the test files are written for: steep enough that 8 bits
/// resolve the tilt well (the reference strength tilts a gentle ramp by
/// less than one 8-bit step).
const K_FILE: f32 = DEFAULT_BUMP_STRENGTH * 40.0;

fn derived(axis: Axis, k: f32) -> Arc<NormalMap> {
    ramp(axis).normal_map(normal_map_scale(k)).0
}

#[test]
fn a_file_of_a_known_slope_matches_the_height_derived_map() {
    for axis in [Axis::U, Axis::V] {
        let derived = derived(axis, K_FILE);
        // The derived map tilts by the slope (not a flat map).
        let mid = derived.normals.at((N / 2) * N + N / 2);
        assert!(mid[0].abs().max(mid[1].abs()) > 0.2, "{axis:?}: {mid:?}");
        // Quantisation: half a step of the channel is 1/255 (1/65535) of
        // a component, a little more once renormalised.
        for (bits16, tolerance) in [(false, 0.006), (true, 5e-5)] {
            let file = write_ramp_file(axis, K_FILE, bits16, &format!("{axis:?}-{bits16}.png"));
            let loaded = load_normal_map(&file.0).unwrap();
            let diff = map_difference(&derived, loaded.given(), axis);
            eprintln!("{axis:?}, 16-bit {bits16}: largest difference {diff:.6}");
            assert!(diff <= tolerance, "{axis:?} 16-bit {bits16}: {diff}");
        }
    }
}

#[test]
fn bump_strength_scales_the_file_maps_slope_as_it_does_the_height_maps() {
    // The file is the ramp at K_FILE, read at the default strength: twice
    // the default doubles the slope, as twice K_FILE does for the height map.
    for axis in [Axis::U, Axis::V] {
        let file = write_ramp_file(axis, K_FILE, true, &format!("k-{axis:?}.png"));
        let loaded = load_normal_map(&file.0).unwrap();
        for factor in [0.5, 2.0] {
            let (tilted, built) = loaded.for_strength(DEFAULT_BUMP_STRENGTH * factor);
            assert!(built);
            let diff = map_difference(&derived(axis, K_FILE * factor), &tilted, axis);
            assert!(diff <= 1e-4, "{axis:?} ×{factor}: {diff}");
        }
        assert_eq!(loaded.builds(), 2);
    }
}

/// A quad facing the camera, texture coordinates 0.1..0.9 (the ramp's
/// wrap seam stays outside), lit from the upper left and in front.
fn ramp_quad(axis: Axis) -> Scene {
    let mesh = quad_mesh(1.0, 0.0, Vec2::splat(0.1), Vec2::splat(0.9), Vec3::ONE);
    scene_of(
        vec![fixed(mesh)],
        ramp(axis),
        white_light(Vec3::new(-3.0, 2.0, 4.0)),
        Vec3::splat(0.1),
    )
}

fn dot3(k: f32, file: bool) -> Settings {
    Settings {
        technique: Technique::Dot3,
        bump_strength: k,
        normal_map_file: file,
        ..Settings::default()
    }
}

#[test]
fn dot3_frames_with_the_file_map_match_the_height_derived_ones() {
    for axis in [Axis::U, Axis::V] {
        let mut scene = ramp_quad(axis);
        let (want, stats) = render_frame(&scene, &dot3(K_FILE, false), 160, 120);
        assert!(stats.counters.pixels_shaded > 1000, "{stats:?}");
        for bits16 in [false, true] {
            let file = write_ramp_file(axis, K_FILE, bits16, &format!("r-{axis:?}-{bits16}.png"));
            scene.material.normal_map = Some(Arc::new(load_normal_map(&file.0).unwrap()));
            // The file's map as written is read at the default strength.
            for filter in [Filter::Bilinear, Filter::Trilinear] {
                let s = Settings {
                    filter,
                    ..dot3(DEFAULT_BUMP_STRENGTH, true)
                };
                let (got, _) = render_frame(&scene, &s, 160, 120);
                let d = max_diff(&want, &got);
                eprintln!("{axis:?} 16-bit {bits16} {filter:?}: {d} levels");
                assert!(d <= 2, "{axis:?} 16-bit {bits16} {filter:?}: {d} levels");
            }
        }
        // The slope shows: the frame is not the unbumped one.
        let (flat, _) = render_frame(
            &scene,
            &Settings {
                bump: false,
                ..dot3(K_FILE, false)
            },
            160,
            120,
        );
        assert!(max_diff(&want, &flat) > 20, "{axis:?}");
    }
}

/// (128, 128, 255) everywhere: the 8-bit "flat" colour.
fn flat_file() -> FileNormalMap {
    let picture = ImageBuffer::from_pixel(8, 8, Rgb([128u8, 128, 255]));
    let bytes = relief_texture::picture::encode(&picture.into(), image::ImageFormat::Png).unwrap();
    load_normal_map_from_bytes("flat.png", &bytes).unwrap()
}

#[test]
fn a_flat_file_renders_like_no_bump() {
    // The brick's own heights are anything but flat: the file replaces them.
    let mut scene = Scene::cube(Arc::new(relief_texture::decode::procedural::brick()), false);
    scene.material.normal_map = Some(Arc::new(flat_file()));
    let plain = Settings {
        bump: false,
        ..Settings::default()
    };
    let (want, _) = render_frame(&scene, &plain, 120, 90);
    let (got, _) = render_frame(&scene, &dot3(DEFAULT_BUMP_STRENGTH, true), 120, 90);
    let d = max_diff(&want, &got);
    assert!(d <= 2, "{d} levels");
    let (derived, _) = render_frame(&scene, &dot3(DEFAULT_BUMP_STRENGTH, false), 120, 90);
    assert!(
        max_diff(&want, &derived) > 10,
        "the bricks show without the file"
    );
}

#[test]
fn a_file_map_that_is_off_costs_nothing() {
    // Each its own texture, so that neither shares the other's mip chain.
    let base = Scene::cube(Arc::new(relief_texture::decode::procedural::brick()), false);
    let mut with_file = Scene::cube(Arc::new(relief_texture::decode::procedural::brick()), false);
    let file = Arc::new(flat_file());
    with_file.material.normal_map = Some(file.clone());
    let mut fb_a = Framebuffer::new(120, 90);
    let mut fb_b = Framebuffer::new(120, 90);
    for technique in [Technique::Blinn, Technique::Dot3] {
        for k in [DEFAULT_BUMP_STRENGTH, 2.0 * DEFAULT_BUMP_STRENGTH] {
            let s = Settings {
                technique,
                bump_strength: k,
                filter: Filter::Trilinear,
                ..Settings::default()
            };
            let a = Renderer::new().render(&base, &s, &mut fb_a).counters;
            let b = Renderer::new().render(&with_file, &s, &mut fb_b).counters;
            assert_eq!(a, b, "{technique:?} {k}");
            assert_eq!(fb_a.pixels(), fb_b.pixels());
            // On, but another technique: the file is not read either.
            let on = Settings {
                normal_map_file: true,
                ..s
            };
            if technique != Technique::Dot3 {
                Renderer::new().render(&with_file, &on, &mut fb_b);
                assert_eq!(fb_a.pixels(), fb_b.pixels());
            }
        }
    }
    assert_eq!(file.builds(), 0);
    assert!(!file.given().mips_built());
}

#[test]
fn a_file_map_in_use_is_built_once_per_strength_and_its_chain_once() {
    let mut scene = ramp_quad(Axis::U);
    let file = write_ramp_file(Axis::U, K_FILE, false, "count.png");
    let map = Arc::new(load_normal_map(&file.0).unwrap());
    scene.material.normal_map = Some(map.clone());
    let plan = |s: &Settings| relief_pipeline::plan::Plan::new(&scene, s);
    assert!(plan(&dot3(DEFAULT_BUMP_STRENGTH, true)).normal_map_from_file);
    assert!(!plan(&dot3(DEFAULT_BUMP_STRENGTH, false)).normal_map_from_file);
    let mut fb = Framebuffer::new(96, 72);
    let mut renderer = Renderer::new();
    let mut run = |k: f32| renderer.render(&scene, &dot3(k, true), &mut fb).counters;
    let first = run(DEFAULT_BUMP_STRENGTH);
    assert_eq!(first.normal_map_builds, 0, "the height map's is not built");
    assert_eq!(map.builds(), 0, "the file's own map at the default");
    let tilted = run(2.0 * DEFAULT_BUMP_STRENGTH);
    assert_eq!(
        tilted.normal_map_builds, 1,
        "the frame counts the tilted copy"
    );
    let kept = run(2.0 * DEFAULT_BUMP_STRENGTH);
    assert_eq!(kept.normal_map_builds, 0);
    assert_eq!(map.builds(), 1, "tilted once for a new strength, then kept");
}

#[test]
fn bad_files_are_refused_with_one_line_naming_them() {
    let missing = load_normal_map(Path::new("no-such-normal-map.png")).unwrap_err();
    assert!(missing.to_string().contains("no-such-normal-map.png"));
    let garbage = load_normal_map_from_bytes("junk.png", b"\x89PNG not really").unwrap_err();
    let dir = load_normal_map(&std::env::temp_dir()).unwrap_err();
    let empty = load_normal_map_from_bytes("empty.png", b"").unwrap_err();
    for e in [missing, garbage, dir, empty] {
        let text = e.to_string();
        assert!(!text.contains('\n') && !text.is_empty(), "{text}");
    }
}

fn state_with_file(file: Option<&str>) -> State {
    let mut state = State::new(Settings::default(), relief_term::ColorDepth::Truecolor);
    state.normal_map_file = file.map(str::to_owned);
    state
}

#[test]
fn key_n_switches_between_the_file_and_the_derived_map() {
    let key = |c: char| {
        let s = state_with_file(Some("bumps.png"));
        relief::app::action_for_key(
            &s,
            &crossterm::event::KeyEvent::new(
                crossterm::event::KeyCode::Char(c),
                crossterm::event::KeyModifiers::SHIFT,
            ),
        )
    };
    assert_eq!(key('N'), Some(Action::ToggleNormalMapFile));

    let mut state = state_with_file(Some("bumps.png"));
    assert_eq!(update(&mut state, Action::ToggleNormalMapFile), None);
    assert!(state.settings.normal_map_file);
    assert_eq!(
        state.settings.technique,
        Technique::Dot3,
        "switched to dot3"
    );
    let message = state.message.clone().unwrap();
    assert!(
        message.contains("bumps.png") && message.contains("dot3"),
        "{message}"
    );
    assert!(relief::app::view::status_line(&state, 200).contains("map file"));

    update(&mut state, Action::ToggleNormalMapFile);
    assert!(!state.settings.normal_map_file);
    assert_eq!(state.settings.technique, Technique::Dot3, "stays");
    assert!(state.message.clone().unwrap().contains("derived"));
    assert!(!relief::app::view::status_line(&state, 200).contains("map file"));

    // Started with the file on (`--normal-map`) but another technique: `N`
    // shows the file instead of turning it off unseen.
    let mut started = state_with_file(Some("bumps.png"));
    started.settings.normal_map_file = true;
    update(&mut started, Action::ToggleNormalMapFile);
    assert!(started.settings.normal_map_file);
    assert_eq!(started.settings.technique, Technique::Dot3);

    // Without a file: nothing changes but the message, which says what to do.
    let mut bare = state_with_file(None);
    update(&mut bare, Action::ToggleNormalMapFile);
    assert_eq!(bare.settings, Settings::default());
    assert!(bare.message.unwrap().contains("--normal-map"));
}

/// The asset `assets/brick-normal.png`: the built-in brick's dot3 normal map
/// at the reference strength, as an 8-bit normal-map file. Written by
/// `RELIEF_WRITE_ASSETS=1 cargo test --release --test suite texture::normal_map_file::`;
/// otherwise checked against the map relief derives.
#[test]
fn the_brick_normal_asset_is_the_bricks_derived_map() {
    let brick = relief_texture::decode::procedural::brick();
    let derived = brick.normal_map(normal_map_scale(DEFAULT_BUMP_STRENGTH)).0;
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/brick-normal.png");
    if std::env::var_os("RELIEF_WRITE_ASSETS").is_some() {
        let rgb = relief_texture::normal_map_file::encode_rgb8(&derived);
        let picture =
            ImageBuffer::<Rgb<u8>, _>::from_raw(derived.width as u32, derived.height as u32, rgb)
                .unwrap();
        relief_texture::picture::save(&picture.into(), &path).unwrap();
    }
    let asset = load_normal_map(&path).unwrap();
    assert_eq!(
        (asset.width(), asset.height()),
        (derived.width, derived.height)
    );
    let worst = asset
        .given()
        .normals
        .iter()
        .zip(&derived.normals)
        .flat_map(|(a, b)| (0..3).map(move |c| (a[c] - b[c]).abs()))
        .fold(0.0f32, f32::max);
    assert!(worst <= 0.006, "{worst}");
}

fn relief_render(args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_relief"))
        .arg("render")
        .args(args)
        .output()
        .expect("the binary runs")
}

#[test]
fn relief_render_reads_the_file_and_refuses_a_bad_one_in_one_line() {
    let out = scratch("out.png");
    let out = out.0.to_str().unwrap();
    let asset = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/brick-normal.png");
    let small = ["--width", "64", "--height", "48", "--out", out];
    let ok = relief_render(&[&small[..], &["--technique", "dot3", "--normal-map", asset]].concat());
    assert!(
        ok.status.success(),
        "{}",
        String::from_utf8_lossy(&ok.stderr)
    );
    assert!(ok.stderr.is_empty());
    // Without dot3 the file cannot show: a note says so.
    let note = relief_render(&[&small[..], &["--normal-map", asset]].concat());
    assert!(note.status.success());
    assert!(String::from_utf8_lossy(&note.stderr).contains("--technique dot3"));
    let junk = scratch("junk.png");
    std::fs::write(&junk.0, b"not a picture").unwrap();
    for bad in [junk.0.to_str().unwrap(), "no-such-normal-map.png"] {
        let o =
            relief_render(&[&small[..], &["--technique", "dot3", "--normal-map", bad]].concat());
        assert!(!o.status.success(), "{bad}");
        let err = String::from_utf8_lossy(&o.stderr);
        let name = Path::new(bad).file_name().unwrap().to_str().unwrap();
        assert!(err.contains(name), "{err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{err}");
        assert!(!err.contains("panicked"));
    }
}
