//! Texture filtering against values worked out by hand, the mip chain,
//! wrapping, and robustness for any coordinate or footprint.

use std::sync::OnceLock;

use clap::ValueEnum;
use glam::Vec2;
use proptest::prelude::*;
use relief_core::settings::{Filter, HeightDerivative};
use relief_texture::decode::procedural;
use relief_texture::sample::filter::{height_gradient, sample};
use relief_texture::sample::mip::Footprint;
use relief_texture::sample::mip::{AnisoPlan, MAX_ANISOTROPY, lod};
use relief_texture::sample::sampler::Sampler;
use relief_texture::sample::texels::Texel;
use relief_texture::{Level, Texture};

/// Every filter, so a new one is checked here too.
fn filters() -> impl Iterator<Item = Filter> {
    Filter::value_variants().iter().copied()
}

fn close(a: [f32; 4], b: [f32; 4]) -> bool {
    a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-5)
}

/// A level from grey values (RGB = height = v), row v = 0 (the picture's top) first.
fn grey(width: usize, height: usize, values: &[f32]) -> Level {
    Level {
        wrap: Default::default(),
        width,
        height,
        texels: values.iter().map(|&v| [v, v, v, v]).collect(),
    }
}

/// An isotropic footprint of `texels` base texels per pixel.
fn footprint(tex: &Texture, texels: f32) -> Footprint {
    Footprint {
        dx: Vec2::new(texels / tex.width() as f32, 0.0),
        dy: Vec2::new(0.0, texels / tex.height() as f32),
    }
}

fn mean(level: &Level) -> [f32; 4] {
    let n = level.texels.len() as f64;
    let mut acc = [0.0f64; 4];
    for t in &level.texels {
        for c in 0..4 {
            acc[c] += t[c] as f64;
        }
    }
    acc.map(|a| (a / n) as f32)
}

#[test]
fn bilinear_at_centres_midpoints_and_across_the_wrap() {
    // 4×2, first row (v = 0) 0,1,2,3 ×0.1; second row 4..7 ×0.1.
    let l = grey(4, 2, &[0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7]);
    let u = |x: f32| (x + 0.5) / 4.0;
    let v = |y: f32| (y + 0.5) / 2.0;
    // Texel centres give the texel.
    for y in 0..2 {
        for x in 0..4 {
            let t = l.bilinear(u(x as f32), v(y as f32));
            assert!(close(t, l.texels.at(y * 4 + x)), "{x},{y}: {t:?}");
        }
    }
    // Midpoint between texels 1 and 2 of the first row: 0.15.
    assert!((l.bilinear(u(1.5), v(0.0))[0] - 0.15).abs() < 1e-6);
    // Centre of the 2×2 block 1,2 × rows 0,1: (0.1+0.2+0.5+0.6)/4 = 0.35.
    assert!((l.bilinear(u(1.5), v(0.5))[0] - 0.35).abs() < 1e-6);
    // u = 0 is the border between the last and the first texel: (0.3+0)/2.
    assert!((l.bilinear(0.0, v(0.0))[0] - 0.15).abs() < 1e-6);
    // v = 0 blends the first row with the last one (repeat): (0 + 0.4)/2.
    assert!((l.bilinear(u(0.0), 0.0)[0] - 0.2).abs() < 1e-6);
    // Corner (0, 0): all four corner texels, (0 + 0.3 + 0.4 + 0.7)/4.
    assert!((l.bilinear(0.0, 0.0)[0] - 0.35).abs() < 1e-6);
}

#[test]
fn wrapping_is_exact_at_0_1_negative_and_beyond() {
    let l = grey(4, 2, &[0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7]);
    for (u, v) in [(0.3, 0.2), (0.0, 0.0), (0.9, 0.7), (0.125, 0.75)] {
        for k in [-3.0f32, -1.0, 1.0, 2.0, 10.0] {
            assert_eq!(l.nearest(u + k, v), l.nearest(u, v), "nearest {u}+{k}");
            assert_eq!(l.nearest(u, v + k), l.nearest(u, v));
            assert!(
                close(l.bilinear(u + k, v + k), l.bilinear(u, v)),
                "bilinear {u}+{k}"
            );
        }
    }
    // u = 1.0 reads texel 0 (GL REPEAT), not one past the end.
    assert_eq!(l.nearest(1.0, 0.0), l.texels.at(0));
    assert_eq!(l.nearest(0.999_999_9, 0.0), l.texels.at(3));
    assert_eq!(l.nearest(-0.000_000_1, 0.0), l.texels.at(3));
    assert_eq!(l.nearest(-0.25, 0.0), l.texels.at(3));
    assert_eq!(l.nearest(0.0, 1.0), l.texels.at(0));
    assert_eq!(l.nearest(0.0, 0.999_999), l.texels.at(4));
    // Non-finite coordinates read as 0.
    for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
        assert_eq!(l.nearest(bad, 0.0), l.texels.at(0));
        assert!(close(l.bilinear(bad, bad), l.bilinear(0.0, 0.0)));
    }
}

#[test]
fn every_mip_level_keeps_the_average_colour() {
    for (w, h) in [(256, 256), (5, 3), (1, 7), (6, 1), (33, 17)] {
        let values: Vec<f32> = (0..w * h)
            .map(|i| ((i * 7919) % 101) as f32 / 100.0)
            .collect();
        let tex = Texture::new("t", grey(w, h, &values));
        let m0 = mean(tex.base());
        let mut size = (w, h);
        for (k, level) in tex.mip_levels().iter().enumerate() {
            size = ((size.0 / 2).max(1), (size.1 / 2).max(1));
            assert_eq!((level.width, level.height), size, "{w}x{h} level {}", k + 1);
            assert!(close(mean(level), m0), "{w}x{h} level {}", k + 1);
        }
        let last = tex.mip_levels().last().map_or(tex.base(), |l| l);
        assert_eq!((last.width, last.height), (1, 1));
    }
    // A 2×2 checker of 0 and 1 becomes one texel of 0.5.
    let tex = Texture::new("c", grey(2, 2, &[0.0, 1.0, 1.0, 0.0]));
    assert_eq!(tex.mip_levels()[0].texels, vec![[0.5; 4]]);
}

#[test]
fn level_of_detail_for_known_minifications() {
    let tex = procedural::brick();
    let t = tex.width() as f32;
    assert_eq!(lod(&tex, footprint(&tex, 1.0)), 0.0);
    assert_eq!(lod(&tex, footprint(&tex, 0.25)), 0.0);
    assert_eq!(lod(&tex, footprint(&tex, 4.0)), 2.0);
    assert!((lod(&tex, footprint(&tex, 3.0)) - 3f32.log2()).abs() < 1e-6);
    // The longer axis decides: 8 texels along u, 1 along v → level 3.
    let fp = Footprint {
        dx: Vec2::new(8.0 / t, 0.0),
        dy: Vec2::new(0.0, 1.0 / t),
    };
    assert_eq!(lod(&tex, fp), 3.0);
    // A diagonal footprint measures its length: (3, 4) texels → 5.
    let fp = Footprint {
        dx: Vec2::new(3.0 / t, 4.0 / t),
        dy: Vec2::ZERO,
    };
    assert!((lod(&tex, fp) - 5f32.log2()).abs() < 1e-6);
    // Non-square textures measure each axis in its own texels.
    let wide = Texture::new("w", grey(64, 4, &vec![0.5; 256]));
    let fp = Footprint {
        dx: Vec2::ZERO,
        dy: Vec2::new(0.0, 1.0),
    };
    assert_eq!(lod(&wide, fp), 2.0);
}

/// Trilinear colour at level of detail `lod`, through the one sampler.
fn trilinear(tex: &Texture, uv: Vec2, lod: f32) -> Texel {
    Sampler::at_lod(lod, || tex.mip_levels().len())
        .read(uv, |i, at| tex.level(i).bilinear(at.x, at.y))
}

#[test]
fn trilinear_at_an_integer_lod_is_bilinear_of_that_level() {
    let tex = procedural::brick();
    for k in 1..=8usize {
        for &(u, v) in &[(0.1f32, 0.2f32), (0.5, 0.5), (0.93, 0.07), (0.0, 0.0)] {
            let got = trilinear(&tex, Vec2::new(u, v), k as f32);
            assert_eq!(got, tex.level(k).bilinear(u, v), "level {k}");
            let via_sample = sample(
                &tex,
                Filter::Trilinear,
                Vec2::new(u, v),
                footprint(&tex, (1u32 << k) as f32),
            );
            assert!(close(via_sample, got), "level {k}");
        }
    }
    // Half-way between levels 1 and 2: the mean of both bilinear reads.
    let uv = Vec2::new(0.31, 0.77);
    let a = tex.level(1).bilinear(uv.x, uv.y);
    let b = tex.level(2).bilinear(uv.x, uv.y);
    let mid = trilinear(&tex, uv, 1.5);
    assert!(close(mid, std::array::from_fn(|c| (a[c] + b[c]) / 2.0)));
    // Beyond the last level: the 1×1 level, the texture's mean colour.
    let far = trilinear(&tex, uv, 40.0);
    assert!(close(far, mean(tex.base())));
    assert!(close(trilinear(&tex, uv, f32::INFINITY), far));
}

#[test]
fn no_chain_is_built_while_no_pixel_is_minified() {
    let tex = procedural::brick();
    let uv = Vec2::new(0.3, 0.6);
    for filter in filters() {
        for texels in [0.01, 0.5, 1.0] {
            let t = sample(&tex, filter, uv, footprint(&tex, texels));
            if filter != Filter::Nearest {
                assert_eq!(t, tex.base().bilinear(uv.x, uv.y), "{filter:?}");
            }
            let _ = height_gradient(
                &tex,
                HeightDerivative::Filtered,
                filter,
                uv,
                footprint(&tex, texels),
            );
        }
        // NaN footprints are treated as not minified.
        let nan = Footprint {
            dx: Vec2::NAN,
            dy: Vec2::NAN,
        };
        let _ = sample(&tex, filter, uv, nan);
    }
    // Anisotropic with a long but thin footprint (8 × 1 texels): taps on the base level.
    let t = tex.width() as f32;
    let thin = Footprint {
        dx: Vec2::new(8.0 / t, 0.0),
        dy: Vec2::new(0.0, 1.0 / t),
    };
    let plan = AnisoPlan::new(&tex, thin);
    assert_eq!((plan.taps, plan.lod), (8, 0.0));
    let _ = sample(&tex, Filter::Anisotropic, uv, thin);
    assert!(
        !tex.mips_built(),
        "a mip chain was built for magnified pixels"
    );
    // The first minified pixel builds it.
    let _ = sample(&tex, Filter::Trilinear, uv, footprint(&tex, 2.0));
    assert!(tex.mips_built());
}

#[test]
fn anisotropic_keeps_detail_across_a_long_footprint() {
    // Stripes one texel wide along u (columns 0,1,0,1…), constant along v.
    let w = 64;
    let values: Vec<f32> = (0..w * w).map(|i| (i % 2) as f32).collect();
    let tex = Texture::new("stripes", grey(w, w, &values));
    // Footprint 1 texel along u, 8 along v: the stripes should survive.
    let fp = Footprint {
        dx: Vec2::new(1.0 / w as f32, 0.0),
        dy: Vec2::new(0.0, 8.0 / w as f32),
    };
    let centre_of_white = Vec2::new(1.5 / w as f32, 0.5);
    let aniso = sample(&tex, Filter::Anisotropic, centre_of_white, fp);
    let tri = sample(&tex, Filter::Trilinear, centre_of_white, fp);
    assert!(
        (aniso[0] - 1.0).abs() < 1e-6,
        "anisotropic blurred: {aniso:?}"
    );
    assert!((tri[0] - 0.5).abs() < 1e-6, "trilinear at level 3: {tri:?}");
    // Along the stripes' varying axis the taps average them out.
    let across = Footprint {
        dx: Vec2::new(8.0 / w as f32, 0.0),
        dy: Vec2::new(0.0, 1.0 / w as f32),
    };
    assert!((sample(&tex, Filter::Anisotropic, centre_of_white, across)[0] - 0.5).abs() < 1e-6);
}

#[test]
fn anisotropy_is_capped_and_raises_the_lod_beyond_the_cap() {
    let tex = procedural::brick();
    let t = tex.width() as f32;
    let fp = |major: f32, minor: f32| Footprint {
        dx: Vec2::new(major / t, 0.0),
        dy: Vec2::new(0.0, minor / t),
    };
    let p = AnisoPlan::new(&tex, fp(64.0, 4.0));
    assert_eq!((p.taps, p.lod), (16, 2.0));
    let p = AnisoPlan::new(&tex, fp(128.0, 2.0)); // ratio 64 > 16: lod from 128/16
    assert_eq!((p.taps, p.lod), (MAX_ANISOTROPY, 3.0));
    let p = AnisoPlan::new(&tex, fp(6.0, 2.0));
    assert_eq!((p.taps, p.lod), (3, 1.0));
    let p = AnisoPlan::new(&tex, fp(4.0, 4.0));
    assert_eq!((p.taps, p.lod), (1, 2.0));
    // An isotropic footprint gives exactly trilinear.
    let uv = Vec2::new(0.4, 0.45);
    assert_eq!(
        sample(&tex, Filter::Anisotropic, uv, fp(4.0, 4.0)),
        sample(&tex, Filter::Trilinear, uv, fp(4.0, 4.0))
    );
}

#[test]
fn filtered_heights_follow_the_footprint() {
    // Heights: fine one-texel stripes along u on top of a gentle ramp in u
    // (0.25 over the whole width, away from the wrap at the borders).
    let w = 64;
    let values: Vec<f32> = (0..w * w)
        .map(|i| {
            let x = i % w;
            0.5 + 0.25 * (x as f32 / w as f32 - 0.5) + if x % 2 == 0 { 0.1 } else { -0.1 }
        })
        .collect();
    let tex = Texture::new("h", grey(w, w, &values));
    let uv = Vec2::new(0.5 + 0.5 / w as f32, 0.5);
    let mode = HeightDerivative::Filtered;
    let magnified = footprint(&tex, 0.5);
    let minified = footprint(&tex, 4.0);
    // Magnified: the base level, stripes and all (a steep slope here).
    let base = height_gradient(&tex, mode, Filter::Trilinear, uv, magnified);
    assert_eq!(base, tex.base().height_gradient_filtered(uv.x, uv.y));
    // Minified 4×: level 2, where the stripes have averaged out and only the
    // ramp's slope of 0.25 per unit of u is left.
    let (du, dv) = height_gradient(&tex, mode, Filter::Trilinear, uv, minified);
    assert!((du - 0.25).abs() < 1e-3 && dv.abs() < 1e-4, "({du}, {dv})");
    // Bilinear and nearest keep the base level whatever the footprint.
    assert_eq!(
        height_gradient(&tex, mode, Filter::Bilinear, uv, minified),
        base
    );
    // The documented per-texel derivative ignores filters and footprints.
    let texel = tex.base().height_gradient_texel(uv.x, uv.y);
    for filter in filters() {
        assert_eq!(
            height_gradient(&tex, HeightDerivative::Texel, filter, uv, minified),
            texel
        );
    }
}

#[test]
fn filtered_gradient_is_per_unit_of_texture_coordinate() {
    // A ramp h = x / w over the middle of the texture: slope 1 per unit u
    // on the base level and on the mip levels alike.
    let w = 32;
    let values: Vec<f32> = (0..w * 4)
        .map(|i| ((i % w) as f32 + 0.5) / w as f32)
        .collect();
    let tex = Texture::new("ramp", grey(w, 4, &values));
    let uv = Vec2::new(0.5, 0.5);
    let (du, _) = tex.base().height_gradient_filtered(uv.x, uv.y);
    assert!((du - 1.0).abs() < 1e-4, "{du}");
    let (du, _) = height_gradient(
        &tex,
        HeightDerivative::Filtered,
        Filter::Trilinear,
        uv,
        Footprint {
            dx: Vec2::new(2.0 / w as f32, 0.0),
            dy: Vec2::ZERO,
        },
    );
    assert!((du - 1.0).abs() < 1e-4, "{du}");
}

fn textures() -> &'static [Texture] {
    static T: OnceLock<Vec<Texture>> = OnceLock::new();
    T.get_or_init(|| {
        vec![
            procedural::brick(),
            Texture::new("one", grey(1, 1, &[0.7])),
            Texture::new(
                "odd",
                grey(
                    5,
                    3,
                    &[
                        0.0, 1.0, 0.2, 0.9, 0.4, 0.6, 1.0, 0.0, 0.3, 0.8, 0.1, 0.5, 0.7, 0.2, 1.0,
                    ],
                ),
            ),
        ]
    })
}

fn any_f32() -> impl Strategy<Value = f32> {
    prop_oneof![
        proptest::num::f32::ANY,
        -10.0f32..10.0,
        Just(0.0),
        Just(1.0),
        Just(-1.0),
        Just(f32::NAN),
        Just(f32::INFINITY),
        Just(f32::MAX),
        Just(f32::MIN_POSITIVE),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    #[test]
    fn any_coordinate_and_footprint_reads_in_range(
        u in any_f32(), v in any_f32(),
        a in any_f32(), b in any_f32(), c in any_f32(), d in any_f32(),
        which in 0usize..3,
    ) {
        let tex = &textures()[which];
        let uv = Vec2::new(u, v);
        let fp = Footprint { dx: Vec2::new(a, b), dy: Vec2::new(c, d) };
        for filter in filters() {
            let t = sample(tex, filter, uv, fp);
            prop_assert!(t.iter().all(|x| (0.0..=1.0).contains(x)), "{filter:?} {t:?}");
            for mode in [HeightDerivative::Texel, HeightDerivative::Filtered] {
                let (gu, gv) = height_gradient(tex, mode, filter, uv, fp);
                // A height step of at most 1 over one texel, either way.
                let bound = tex.width().max(tex.height()) as f32 + 1e-3;
                prop_assert!(gu.is_finite() && gv.is_finite(), "{filter:?} {mode:?}");
                prop_assert!(gu.abs() <= bound && gv.abs() <= bound, "{gu} {gv}");
            }
        }
    }
}

/// Nearest-mip reads exactly one level: at any level of detail its sample
/// is the hand-computed bilinear blend of the four texels of level
/// ⌈λ + ½⌉ − 1 around the point (the base up to λ = ½), and never a mix of two.
#[test]
fn nearest_mip_reads_one_level_bilinearly() {
    let tex = procedural::brick();
    let last = tex.level_count() - 1;
    // Bilinear by hand in f64: texel centres at (i + ½)/n, wrapped.
    let by_hand = |level: &Level, u: f64, v: f64| -> [f64; 4] {
        let (w, h) = (level.width as i64, level.height as i64);
        let x = u.rem_euclid(1.0) * w as f64 - 0.5;
        let y = v.rem_euclid(1.0) * h as f64 - 0.5;
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let at = |i: i64, j: i64| {
            level
                .texels
                .at((j.rem_euclid(h) * w + i.rem_euclid(w)) as usize)
        };
        let (i, j) = (x0 as i64, y0 as i64);
        std::array::from_fn(|c| {
            let t = |a: i64, b: i64| at(a, b)[c] as f64;
            (1.0 - fx) * (1.0 - fy) * t(i, j)
                + fx * (1.0 - fy) * t(i + 1, j)
                + (1.0 - fx) * fy * t(i, j + 1)
                + fx * fy * t(i + 1, j + 1)
        })
    };
    // (λ, the level it must read)
    let cases = [
        (0.3f32, 0usize),
        (0.45, 0),
        (0.55, 1),
        (1.2, 1),
        (1.45, 1),
        (1.7, 2),
        (3.0, 3),
        (40.0, last),
    ];
    for (lambda, want) in cases {
        // An isotropic footprint 2^λ texels across.
        let fp = footprint(&tex, 2f32.powf(lambda));
        for &(u, v) in &[(0.1f64, 0.2f64), (0.53, 0.47), (0.93, 0.07)] {
            let got = sample(&tex, Filter::NearestMip, Vec2::new(u as f32, v as f32), fp);
            let expect = by_hand(tex.level(want), u, v);
            for c in 0..4 {
                assert!(
                    (got[c] as f64 - expect[c]).abs() < 1e-5,
                    "λ {lambda}, level {want}, ({u}, {v}) channel {c}: {got:?} vs {expect:?}"
                );
            }
            // Not the neighbouring level's read (the brick differs between levels).
            if want < last {
                let other = by_hand(tex.level(want + 1), u, v);
                assert!((0..3).any(|c| (got[c] as f64 - other[c]).abs() > 1e-4));
            }
        }
    }
}
