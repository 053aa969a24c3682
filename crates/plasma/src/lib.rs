//! The 2D bump effect of docs/plasma.md ([001], Plouf, PrograZine #10): a plasma height
//! field lit by a light that follows the mouse pointer.
//!
//! Per pixel the article takes the height differences to the right/left and
//! below/above, adds the offset to the light (Lx − X, Ly − Y), and looks the
//! result up in a table of Z² = 1 − (dX/128)² − (dY/128)², clamped at 0.
//! That Z² is the small-slope expansion of cos²θ, θ the angle between the
//! surface's true normal n = (−∂xH, −∂yH, 1) and the direction to a light
//! 128 pixels above the picture, l = (Lx − X, Ly − Y, 128), with the
//! heights' differences read per 128 as the article does. The `Exact`
//! mode computes that cos² per pixel with both vectors normalised: the two
//! agree near the light and part where the angles grow (the table's spot
//! ends in a hard circle 128 pixels wide, the exact light fades slowly).

mod height;
mod table;

pub use height::HeightField;
pub use table::ZTable;

use clap::ValueEnum;
use glam::Vec3;
use rayon::prelude::*;

use relief_core::framebuffer::Framebuffer;
use relief_core::stats::Counters;

/// How the plasma's normal is lit (a setting: key in the app, `--plasma-normal`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, ValueEnum)]
pub enum PlasmaNormal {
    /// The article's 255×255 Z² lookup table on integer slopes clamped to ±127.
    #[default]
    Table,
    /// The exact per-pixel normal and light direction, cos² in floating point.
    Exact,
}

impl PlasmaNormal {
    pub fn toggle(self) -> Self {
        match self {
            PlasmaNormal::Table => PlasmaNormal::Exact,
            PlasmaNormal::Exact => PlasmaNormal::Table,
        }
    }
    pub fn label(self) -> &'static str {
        match self {
            PlasmaNormal::Table => "Z² table",
            PlasmaNormal::Exact => "exact normal",
        }
    }
}

/// The article's slope scale: differences are read per 128 (its table divides by 128).
pub const SLOPE_SCALE: f32 = 128.0;
/// Light positions are clamped to this many pixels from the origin, so
/// nothing overflows for any input (NaN counts as 0).
const LIGHT_LIMIT: f32 = 1.0e6;

/// The plasma effect: a height field and the Z² table.
#[derive(Clone, Debug)]
pub struct Plasma {
    heights: HeightField,
    table: ZTable,
}

impl Plasma {
    /// Seed 0 is the article's picture; other seeds shift the pattern.
    pub fn new(seed: u32) -> Self {
        Plasma {
            heights: HeightField::new(seed),
            table: ZTable::new(),
        }
    }

    pub fn heights(&self) -> &HeightField {
        &self.heights
    }

    /// Draws the effect over the whole framebuffer, lit by a light at pixel
    /// `light` ((0, 0) is the top-left pixel, y down; it may lie outside).
    pub fn render(
        &self,
        light: (f32, f32),
        normal: PlasmaNormal,
        fb: &mut Framebuffer,
    ) -> Counters {
        let (w, h) = (fb.width(), fb.height());
        if w == 0 || h == 0 {
            return Counters::default();
        }
        let light = (sanitize(light.0), sanitize(light.1));
        // The article works on whole pixels.
        let light_px = (light.0.round() as i64, light.1.round() as i64);
        let alt = self.heights.sample(w, h);
        let at = |x: usize, y: usize| alt[y * w + x] as i32;
        fb.pixels_mut()
            .par_chunks_mut(w)
            .enumerate()
            .for_each(|(y, row)| {
                let (up, down) = (y.saturating_sub(1), (y + 1).min(h - 1));
                for (x, px) in row.iter_mut().enumerate() {
                    let (left, right) = (x.saturating_sub(1), (x + 1).min(w - 1));
                    // The article's height differences (borders clamped).
                    let dx = at(right, y) - at(left, y);
                    let dy = at(x, down) - at(x, up);
                    let value = match normal {
                        PlasmaNormal::Table => self.table_value(dx, dy, light_px, x, y),
                        PlasmaNormal::Exact => exact_value(dx, dy, light, x, y),
                    };
                    *px = [value; 3];
                }
            });
        let n = (w * h) as u64;
        Counters {
            pixels_shaded: n,
            light_evals: n,
            ..Counters::default()
        }
    }

    /// The article's inner loop: integer slope plus light offset, clamped to
    /// ±127, looked up in the table.
    fn table_value(&self, dx: i32, dy: i32, light: (i64, i64), x: usize, y: usize) -> u8 {
        let lx = light.0 - x as i64;
        let ly = light.1 - y as i64;
        let i = (dx as i64 + lx).clamp(-127, 127) as i32;
        let j = (dy as i64 + ly).clamp(-127, 127) as i32;
        self.table.get(i, j)
    }
}

/// cos² of the angle between the true normal and the direction to the light.
fn exact_value(dx: i32, dy: i32, light: (f32, f32), x: usize, y: usize) -> u8 {
    let n = Vec3::new(-dx as f32, -dy as f32, SLOPE_SCALE).normalize();
    let l = Vec3::new(light.0 - x as f32, light.1 - y as f32, SLOPE_SCALE).normalize();
    let c = n.dot(l).max(0.0);
    let v = (c * c * 255.0).round();
    // NaN cannot occur (both vectors have z = 128), but never let one through.
    if v.is_finite() {
        v.clamp(0.0, 255.0) as u8
    } else {
        0
    }
}

fn sanitize(c: f32) -> f32 {
    if c.is_nan() {
        0.0
    } else {
        c.clamp(-LIGHT_LIMIT, LIGHT_LIMIT)
    }
}
