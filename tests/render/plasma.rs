//! The 2D plasma bump effect (docs/plasma.md), on the raw framebuffer.

use relief_core::framebuffer::Framebuffer;
use relief_plasma::{Plasma, PlasmaNormal};

const MODES: [PlasmaNormal; 2] = [PlasmaNormal::Table, PlasmaNormal::Exact];

fn render(p: &Plasma, light: (f32, f32), mode: PlasmaNormal, w: usize, h: usize) -> Framebuffer {
    let mut fb = Framebuffer::new(w, h);
    p.render(light, mode, &mut fb);
    fb
}

/// Brightness-weighted centre of the brightest pixels (those within 2% of the maximum).
fn bright_centre(fb: &Framebuffer) -> (f32, f32) {
    let max = fb.pixels().iter().map(|p| p[0]).max().unwrap() as f32;
    let (mut sx, mut sy, mut sw) = (0.0, 0.0, 0.0);
    for y in 0..fb.height() {
        for x in 0..fb.width() {
            let v = fb.get(x, y)[0] as f32;
            if v >= 0.98 * max {
                sx += x as f32 * v;
                sy += y as f32 * v;
                sw += v;
            }
        }
    }
    (sx / sw, sy / sw)
}

#[test]
fn the_brightest_spot_follows_the_light() {
    let p = Plasma::new(0);
    for mode in MODES {
        for light in [(160.0, 100.0), (60.0, 40.0), (250.0, 150.0), (100.0, 170.0)] {
            let fb = render(&p, light, mode, 320, 200);
            let (cx, cy) = bright_centre(&fb);
            // The surface's slopes shift the highlight (by up to the largest
            // height difference, about 19): the spot stays around the light.
            let d = ((cx - light.0).powi(2) + (cy - light.1).powi(2)).sqrt();
            assert!(d < 14.0, "{mode:?} light {light:?}: spot at ({cx}, {cy})");
            // Far from the light it is darker than at the light.
            let at = fb.get(light.0 as usize, light.1 as usize)[0];
            let corner_x = if light.0 < 160.0 { 319 } else { 0 };
            let corner_y = if light.1 < 100.0 { 199 } else { 0 };
            assert!(fb.get(corner_x, corner_y)[0] < at / 2, "{mode:?} {light:?}");
        }
    }
}

#[test]
fn the_table_mode_is_the_articles_loop() {
    // The article's Pascal, transcribed: table, plasma, inner loop (borders
    // are left out there; relief clamps its neighbours instead).
    let mut norm = vec![[0u8; 255]; 255];
    for y in -127i32..=127 {
        for x in -127i32..=127 {
            let i = ((1.0 - (x as f64 / 128.0).powi(2) - (y as f64 / 128.0).powi(2)) * 255.0)
                .trunc() as i32;
            norm[(y + 127) as usize][(x + 127) as usize] = i.max(0) as u8;
        }
    }
    let mut buf1 = vec![[0i32; 320]; 200];
    for (y, row) in buf1.iter_mut().enumerate() {
        for (x, v) in row.iter_mut().enumerate() {
            let (x, y) = (x as f64, y as f64);
            *v = ((x / 10.0).cos() + (y / 10.0).sin() + (x / 20.0).sin() + (y / 20.0).cos())
                .mul_add(63.0, 0.0)
                .trunc()
                .abs() as i32;
        }
    }
    let p = Plasma::new(0);
    for (lx, ly) in [(160, 100), (17, 180), (300, 5)] {
        let fb = render(&p, (lx as f32, ly as f32), PlasmaNormal::Table, 320, 200);
        for y in 1..199 {
            for x in 1..319 {
                let i = (buf1[y][x + 1] - buf1[y][x - 1] + lx - x as i32).clamp(-127, 127);
                let j = (buf1[y + 1][x] - buf1[y - 1][x] + ly - y as i32).clamp(-127, 127);
                let want = norm[(j + 127) as usize][(i + 127) as usize];
                assert_eq!(fb.get(x, y), [want; 3], "pixel ({x}, {y})");
            }
        }
    }
}

#[test]
fn table_and_exact_agree_near_the_light_and_part_away_from_it() {
    let p = Plasma::new(0);
    let light = (160.0, 100.0);
    let table = render(&p, light, PlasmaNormal::Table, 320, 200);
    let exact = render(&p, light, PlasmaNormal::Exact, 320, 200);
    let (mut near_max, mut far_sum, mut far_n) = (0i32, 0i64, 0i64);
    let mut near_sum = 0i64;
    let mut near_n = 0i64;
    for y in 0..200 {
        for x in 0..320 {
            let (a, b) = (table.get(x, y)[0] as i32, exact.get(x, y)[0] as i32);
            let r = ((x as f32 - light.0).powi(2) + (y as f32 - light.1).powi(2)).sqrt();
            if r < 24.0 {
                near_max = near_max.max((a - b).abs());
                near_sum += (a - b).abs() as i64;
                near_n += 1;
            } else if r > 128.0 {
                far_sum += (b - a) as i64;
                far_n += 1;
            }
        }
    }
    // Near the light all angles are small and the table's Z² is the
    // expansion of the exact cos²: a level apart (truncation, slopes).
    let near_mean = near_sum as f64 / near_n as f64;
    assert!(
        near_max <= 3 && near_mean < 1.5,
        "near: max {near_max}, mean {near_mean}"
    );
    // Beyond 128 pixels the table is black (its circle ends there) while the
    // exact light still reaches: the difference the setting shows.
    let far_mean = far_sum as f64 / far_n as f64;
    assert!(
        (60.0..140.0).contains(&far_mean),
        "far: exact − table = {far_mean}"
    );
}

#[test]
fn any_size_and_any_light_render_without_trouble() {
    let p = Plasma::new(3);
    let lights = [
        (0.0, 0.0),
        (-1e30, 5.0),
        (f32::NAN, f32::INFINITY),
        (f32::NEG_INFINITY, f32::MAX),
        (0.5, 0.5),
    ];
    for (w, h) in [
        (0, 0),
        (0, 7),
        (7, 0),
        (1, 1),
        (1, 9),
        (9, 1),
        (2, 2),
        (33, 17),
    ] {
        for mode in MODES {
            for light in lights {
                let mut fb = Framebuffer::new(w, h);
                fb.fill([1, 2, 3]);
                let counters = p.render(light, mode, &mut fb);
                assert_eq!(counters.pixels_shaded, (w * h) as u64);
                assert_eq!(counters.shadow_texels + counters.texture_samples, 0);
                // Every pixel written, grey.
                assert!(
                    fb.pixels()
                        .iter()
                        .all(|px| px[0] == px[1] && px[1] == px[2])
                );
                let again = render(&p, light, mode, w, h);
                assert_eq!(fb, again, "deterministic");
            }
        }
    }
    // A 1×1 frame lit from its own pixel is flat there: full brightness.
    for mode in MODES {
        assert_eq!(render(&p, (0.0, 0.0), mode, 1, 1).get(0, 0), [255; 3]);
    }
}

#[test]
fn the_light_moves_the_picture_and_the_modes_switch() {
    let p = Plasma::new(0);
    let a = render(&p, (100.0, 100.0), PlasmaNormal::Table, 64, 48);
    let b = render(&p, (10.0, 10.0), PlasmaNormal::Table, 64, 48);
    let c = render(&p, (100.0, 100.0), PlasmaNormal::Exact, 64, 48);
    assert_ne!(a, b);
    assert_ne!(a, c);
    assert_eq!(PlasmaNormal::Table.toggle(), PlasmaNormal::Exact);
    assert_ne!(PlasmaNormal::Table.label(), PlasmaNormal::Exact.label());
}
