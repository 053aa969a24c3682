//! The rasterizer against the bench's ray-cast truth (crates/bench/src/truth), one
//! technique at a time, at three orientations.
//!
//! A rasterizer without anti-aliasing shades each pixel at its centre, so
//! these tests compare it with the truth's ray through the same centre
//! (`truth::render_centres`): sampling error is then out of the comparison
//! and what remains is what the technique approximates, plus:
//! - rounding: relief rounds to 8 bits (≤ 0.5 level) and so does the
//!   comparison with the unrounded truth (≤ 0.5);
//! - f32 against f64: relative errors near 1e-6, far below a level;
//! - vertex snapping: the rasterizer places vertices on a 1/256-pixel grid,
//!   moving a pixel centre's texture coordinate by at most ~1/256 px. The
//!   texture here is the reference brick reduced to 16×16 texels (area
//!   means), magnified on a 160×120 frame (a face spans ~30 px, ~2 px a
//!   texel), so that shift is under 1/500 of a texel: with colour steps of
//!   at most 255 levels a texel, under 1 level.
//!
//! Together ≤ 2 levels wherever the technique is defined the same way on
//! both sides. Only pixels whose 3×3 neighbourhood is covered in both
//! pictures count (silhouettes are coverage, not shading); of those, a
//! pixel whose centre lies within the snap distance of an edge between two
//! faces may take the other face's texel: at most ~(edge length × 2/256)
//! ≈ 1 pixel a frame, so up to 4 such pixels are allowed.

use std::sync::Arc;

use glam::{DVec3, Vec3};
use relief_bench::truth::{self, View, geometry::World};
use relief_core::settings::{Filter, Settings, Technique};
use relief_pipeline::render::render_frame;
use relief_scene::Scene;
use relief_texture::{Level, Texture, load_texture};

const W: usize = 160;
const H: usize = 120;
/// Pixels near a face edge that may take the other face (see above).
const EDGE_PIXELS: usize = 4;

fn orientations() -> [Vec3; 3] {
    [
        Vec3::new(25.0, 35.0, 0.0),
        Vec3::new(-30.0, 120.0, 10.0),
        Vec3::new(60.0, -40.0, -20.0),
    ]
}

fn brick() -> Texture {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/reference-brick.png");
    load_texture(&path).expect("reference brick")
}

/// The reference brick reduced to `side × side` texels by area means.
fn small_brick(side: usize) -> Arc<Texture> {
    let full = brick();
    let base = full.base();
    let (bw, bh) = (base.width / side, base.height / side);
    let mut texels = Vec::with_capacity(side * side);
    for y in 0..side {
        for x in 0..side {
            let mut sum = [0.0f32; 4];
            for j in 0..bh {
                for i in 0..bw {
                    let t = base.texels.at((y * bh + j) * base.width + x * bw + i);
                    for c in 0..4 {
                        sum[c] += t[c];
                    }
                }
            }
            texels.push(sum.map(|s| s / (bw * bh) as f32));
        }
    }
    Arc::new(Texture::new(
        "brick 16",
        Level {
            wrap: Default::default(),
            width: side,
            height: side,
            texels: texels.into(),
        },
    ))
}

fn cube() -> Scene {
    Scene::cube(small_brick(16), true)
}

/// relief's frame and the truth's centre rays for `settings`.
fn both(scene: &Scene, settings: &Settings) -> (Vec<[u8; 3]>, Vec<Option<DVec3>>) {
    let (fb, stats) = render_frame(scene, settings, W, H);
    assert_eq!(stats.counters.nonfinite, 0);
    let truth = truth::render_centres(scene, &View::of(settings, scene), W, H);
    (fb.pixels().to_vec(), truth)
}

/// Pixels whose 3×3 neighbourhood is covered in both pictures.
fn interior(frame: &[[u8; 3]], truth: &[Option<DVec3>], background: [u8; 3]) -> Vec<usize> {
    let covered = |i: usize| frame[i] != background && truth[i].is_some();
    (0..W * H)
        .filter(|&i| {
            let (x, y) = (i % W, i / W);
            x > 0
                && y > 0
                && x + 1 < W
                && y + 1 < H
                && (0..9).all(|k| covered((y + k / 3 - 1) * W + x + k % 3 - 1))
        })
        .collect()
}

/// Largest channel difference in levels between a pixel and a truth colour.
fn diff(a: [u8; 3], t: DVec3) -> f64 {
    (0..3)
        .map(|c| (a[c] as f64 - t[c] * 255.0).abs())
        .fold(0.0, f64::max)
}

/// RMS in levels over `pixels`.
fn rms(frame: &[[u8; 3]], truth: &[Option<DVec3>], pixels: &[usize]) -> f64 {
    let sum: f64 = pixels
        .iter()
        .map(|&i| {
            let t = truth[i].unwrap() * 255.0;
            (0..3)
                .map(|c| (frame[i][c] as f64 - t[c]).powi(2))
                .sum::<f64>()
        })
        .sum();
    (sum / (3 * pixels.len().max(1)) as f64).sqrt()
}

/// Blinn, emboss, the Blinn-Phong highlight and the mirror reflection are
/// evaluated from the same definitions on both sides (bilinear reads of the
/// base level, central differences one texel apart, emboss's one-texel
/// shift toward the strongest light, (N·H)^s, the lat-long lookup of
/// R = 2(N·V)N − V): within the 2 levels derived above.
#[test]
fn techniques_defined_alike_match_the_truth_at_pixel_centres() {
    let scene = cube();
    let r = Settings::default();
    let cases = [
        ("Blinn", r),
        (
            "emboss",
            Settings {
                technique: Technique::Emboss,
                ..r
            },
        ),
        (
            "specular",
            Settings {
                specular: true,
                ..r
            },
        ),
        (
            "environment",
            Settings {
                environment: true,
                ..r
            },
        ),
    ];
    for (name, settings) in cases {
        for rotation in orientations() {
            let settings = Settings {
                rotation,
                ..settings
            };
            let (frame, truth) = both(&scene, &settings);
            let pixels = interior(&frame, &truth, scene.background);
            assert!(pixels.len() > 1500, "{name}: {} pixels", pixels.len());
            let off: Vec<(usize, f64)> = pixels
                .iter()
                .map(|&i| (i, diff(frame[i], truth[i].unwrap())))
                .filter(|&(_, d)| d > 2.0)
                .collect();
            let worst = off.iter().map(|o| o.1).fold(0.0, f64::max);
            eprintln!(
                "{name} at {rotation}: {} of {} pixels beyond 2 levels (worst {worst:.1}), RMS {:.3}",
                off.len(),
                pixels.len(),
                rms(&frame, &truth, &pixels)
            );
            assert!(off.len() <= EDGE_PIXELS, "{name} at {rotation}: {off:?}");
        }
    }
}

/// The derived normal map's unit normal at texel (i, j) (docs/bump-dot3.md):
/// normalise(−2k·F_u, −2k·F_v, 1), F_u and F_v central differences one texel
/// apart per unit of texture coordinate, repeating.
fn map_normal(level: &Level, i: i64, j: i64, k: f64) -> DVec3 {
    let (w, h) = (level.width as i64, level.height as i64);
    let f = |i: i64, j: i64| {
        level
            .texels
            .at((j.rem_euclid(h) * w + i.rem_euclid(w)) as usize)[3] as f64
    };
    let fu = (f(i + 1, j) - f(i - 1, j)) * w as f64 / 2.0;
    let fv = (f(i, j + 1) - f(i, j - 1)) * h as f64 / 2.0;
    DVec3::new(-2.0 * k * fu, -2.0 * k * fv, 1.0).normalize()
}

/// Dot3 reads the normal map bilinearly: a blend Σwᵢnᵢ of the four unit
/// normals nᵢ = mᵢ/|mᵢ| around the point, mᵢ = (−2k·F_u, −2k·F_v, 1) at the
/// texel centres. The truth's normal is normalise(Σwᵢmᵢ) (central
/// differences of bilinear heights are the bilinear blend of the
/// texel-centre differences). So the two are the same positive combination
/// of the mᵢ with weights wᵢ and wᵢ/|mᵢ|, which differ relatively by at
/// most ρ = max|mᵢ|/min|mᵢ| − 1: their directions differ by at most θ·ρ,
/// θ the largest angle between two of the nᵢ (all combinations lie in
/// their cone); and the blend's length is at least cos θ. So
/// |Δn| ≤ (1 − cos θ) + θ·ρ. Each light's clamped cosine moves by at most
/// |Δn|, so a channel by at most albedo (≤ 1) × Σ of that channel's light
/// colours (1.3 for the reference lights) × |Δn|; plus the 2 levels of the
/// comparison. Where the four normals agree (flat brick faces, even
/// slopes) this is the 2 levels of the techniques defined alike.
#[test]
fn dot3_stays_within_what_interpolating_normals_can_change() {
    let scene = cube();
    let base = scene.material.texture.base().clone();
    let k = Settings::default().bump_strength as f64;
    let light_sum = (0..3)
        .map(|c| scene.lights.iter().map(|l| l.color[c] as f64).sum::<f64>())
        .fold(0.0, f64::max);
    for rotation in orientations() {
        let settings = Settings {
            technique: Technique::Dot3,
            rotation,
            ..Settings::default()
        };
        let (frame, truth) = both(&scene, &settings);
        let world = World::new(&scene, rotation, W, H);
        let pixels = interior(&frame, &truth, scene.background);
        let mut off = Vec::new();
        let mut tight = 0;
        for &i in &pixels {
            let ray = world.ray((i % W) as f64 + 0.5, (i / W) as f64 + 0.5);
            let hit = world.hit(&ray).unwrap();
            let x = (hit.uv.x - hit.uv.x.floor()) * base.width as f64 - 0.5;
            let y = (hit.uv.y - hit.uv.y.floor()) * base.height as f64 - 0.5;
            let (i0, j0) = (x.floor() as i64, y.floor() as i64);
            let n =
                [(0, 0), (1, 0), (0, 1), (1, 1)].map(|(a, b)| map_normal(&base, i0 + a, j0 + b, k));
            let lengths = n.map(|m| 1.0 / m.z);
            let rho = lengths.iter().fold(0.0f64, |a, &b| a.max(b))
                / lengths.iter().fold(f64::INFINITY, |a, &b| a.min(b))
                - 1.0;
            let mut theta = 0.0f64;
            for a in 0..4 {
                for b in a + 1..4 {
                    theta = theta.max(n[a].dot(n[b]).clamp(-1.0, 1.0).acos());
                }
            }
            let bound = 2.0 + 255.0 * light_sum * ((1.0 - theta.cos()) + theta * rho);
            if bound < 4.0 {
                tight += 1;
            }
            let d = diff(frame[i], truth[i].unwrap());
            if d > bound {
                off.push((i, d, bound));
            }
        }
        eprintln!(
            "dot3 at {rotation}: {} of {} pixels beyond their bound ({tight} with a bound under 4), RMS {:.3}",
            off.len(),
            pixels.len(),
            rms(&frame, &truth, &pixels)
        );
        // Most pixels are held to a few levels, so a wrong normal would show.
        assert!(
            tight > pixels.len() / 2,
            "too few pixels test anything: {tight}"
        );
        assert!(off.len() <= EDGE_PIXELS, "dot3 at {rotation}: {off:?}");
    }
}

/// Parallax and POM approximate the same carved relief (the truth marches
/// it finely): moving the texture coordinate must bring the picture closer
/// to that relief than not moving it (Blinn at the undisplaced point), and
/// POM's march closer than parallax's single step. A strength of 0.03
/// (depth 0.12, several texels of travel at these angles) makes the
/// displacement large enough to measure.
#[test]
fn parallax_and_pom_approach_the_carved_relief() {
    let scene = cube();
    for rotation in orientations() {
        let at = |technique| Settings {
            technique,
            bump_strength: 0.03,
            rotation,
            ..Settings::default()
        };
        let truth = truth::render_centres(&scene, &View::of(&at(Technique::Pom), &scene), W, H);
        let frame = |t| render_frame(&scene, &at(t), W, H).0.pixels().to_vec();
        let (none, parallax, pom) = (
            frame(Technique::Blinn),
            frame(Technique::Parallax),
            frame(Technique::Pom),
        );
        let pixels = interior(&pom, &truth, scene.background);
        let e = [&none, &parallax, &pom].map(|f| rms(f, &truth, &pixels));
        eprintln!(
            "at {rotation}: RMS against the relief, undisplaced {:.2}, parallax {:.2}, POM {:.2}",
            e[0], e[1], e[2]
        );
        assert!(e[1] < e[0] && e[2] < e[1], "at {rotation}: {e:?}");
    }
}

/// Shadows: a small cube (side 0.6, not turning) between the strongest
/// light and the reference cube casts onto it, so the shadow pass runs. The
/// truth's shadow rays decide per point; the shadow map decides per map
/// texel with a slope bias and a 3×3 filter, so the two may differ along
/// the shadow's boundary (within 2 pixels of a pixel whose truth changes
/// when shadows are toggled) and agree within 2 levels elsewhere.
///
/// That includes points on faces turned away from the strongest light that
/// their smoothed vertex normals still light (N·L > 0 while the face's own
/// normal points away): the truth's ray toward the light crosses the cube
/// there, and the renderer puts such a point in shadow by its geometric
/// normal (the map, holding those faces, would compare it with its own
/// depth). Their count is printed (see docs/bench.md).
#[test]
fn shadows_agree_with_shadow_rays_away_from_their_edges() {
    let scene = with_caster();
    let light = scene.lights[0].position.as_dvec3();
    let mut shadowed_somewhere = false;
    for rotation in orientations() {
        let settings = Settings {
            rotation,
            ..Settings::default()
        };
        let (frame, truth) = both(&scene, &settings);
        let unshadowed = truth::render_centres(
            &scene,
            &View {
                rotation,
                setting: truth::Setting {
                    shadows: false,
                    ..truth::Setting::of(&settings, &scene)
                },
            },
            W,
            H,
        );
        let in_shadow = |i: usize| match (truth[i], unshadowed[i]) {
            (Some(a), Some(b)) => (a - b).abs().max_element() * 255.0 > 0.5,
            _ => false,
        };
        let near_edge = |i: usize| {
            let (x, y) = ((i % W) as i64, (i / W) as i64);
            let s = in_shadow(i);
            (-2..=2).any(|dy: i64| {
                (-2..=2).any(|dx: i64| {
                    let (a, b) = (x + dx, y + dy);
                    a >= 0
                        && b >= 0
                        && a < W as i64
                        && b < H as i64
                        && in_shadow(b as usize * W + a as usize) != s
                })
            })
        };
        let world = World::new(&scene, rotation, W, H);
        let turned_away = |i: usize| {
            let ray = world.ray((i % W) as f64 + 0.5, (i / W) as f64 + 0.5);
            world
                .hit(&ray)
                .is_some_and(|h| h.face_normal.dot(light - h.position) <= 0.0)
        };
        let pixels = interior(&frame, &truth, scene.background);
        let shadowed = pixels.iter().filter(|&&i| in_shadow(i)).count();
        shadowed_somewhere |= pixels.iter().any(|&i| in_shadow(i) && !turned_away(i));
        let away: Vec<usize> = pixels.iter().copied().filter(|&i| turned_away(i)).collect();
        let away_off = away
            .iter()
            .filter(|&&i| diff(frame[i], truth[i].unwrap()) > 2.0)
            .count();
        let off: Vec<(usize, f64)> = pixels
            .iter()
            .filter(|&&i| !near_edge(i))
            .map(|&i| (i, diff(frame[i], truth[i].unwrap())))
            .filter(|&(_, d)| d > 2.0)
            .collect();
        eprintln!(
            "shadows at {rotation}: {shadowed} shadowed pixels, {} beyond 2 levels away from the edge; \
             on faces turned away from the light {away_off} of {} beyond 2 levels; RMS {:.2}",
            off.len(),
            away.len(),
            rms(&frame, &truth, &pixels),
        );
        assert!(off.len() <= EDGE_PIXELS, "at {rotation}: {off:?}");
    }
    assert!(
        shadowed_somewhere,
        "no orientation shows a cast shadow: the test tests nothing"
    );
}

/// The reference cube (16-texel brick) and a small cube of side 0.6 at
/// (0.9, 1.2, 1.8), on the way from the white light at (3, 4, 6) to the
/// reference cube's front, fixed while the reference cube turns.
fn with_caster() -> Scene {
    let mut scene = cube();
    let mut small = scene.objects[0].clone();
    small.transform = glam::Mat4::from_translation(Vec3::new(0.9, 1.2, 1.8))
        * glam::Mat4::from_scale(Vec3::splat(0.3));
    small.rotates = false;
    scene.objects.push(small);
    scene
}

/// The footprint: where the reference brick (256 texels) is minified on a
/// small frame, trilinear and anisotropic filtering average the texels a
/// pixel covers, as the truth's rays do, and nearest-mip reads one level
/// without blending: against the truth (8×8 rays, its own error under 1
/// level RMS) both are closer than nearest-mip at every orientation.
#[test]
fn trilinear_and_anisotropic_are_closer_to_the_truth_than_nearest_mip() {
    let scene = Scene::cube(Arc::new(brick()), true);
    let (w, h) = (96, 72);
    for rotation in orientations() {
        let settings = |filter| Settings {
            filter,
            rotation,
            ..Settings::default()
        };
        let truth = truth::render(
            &scene,
            &View::of(&settings(Filter::Bilinear), &scene),
            w,
            h,
            8,
        );
        let psnr = |filter| {
            let (fb, _) = render_frame(&scene, &settings(filter), w, h);
            let mut e = relief_bench::metrics::SquaredError::default();
            e.add(fb.pixels(), truth.pixels());
            e.psnr()
        };
        let [nearest_mip, trilinear, anisotropic] =
            [Filter::NearestMip, Filter::Trilinear, Filter::Anisotropic].map(psnr);
        eprintln!(
            "at {rotation}: nearest-mip {nearest_mip:.2} dB, trilinear {trilinear:.2}, anisotropic {anisotropic:.2}"
        );
        assert!(
            trilinear > nearest_mip && anisotropic > nearest_mip,
            "at {rotation}"
        );
    }
}
