//! Colour depth: which one the terminal takes, and how a 24-bit pixel maps onto it.

use ratatui::style::Color;

use crate::framebuffer::Rgb;

/// How many colours the terminal is sent.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ColorDepth {
    /// 24-bit `38;2;r;g;b` colours.
    Truecolor,
    /// The xterm 256-colour palette: 6×6×6 cube plus a 24-step grey ramp.
    Palette256,
    /// The 16 ANSI colours.
    Palette16,
}

impl ColorDepth {
    pub fn label(self) -> &'static str {
        match self {
            ColorDepth::Truecolor => "24-bit",
            ColorDepth::Palette256 => "256 colours",
            ColorDepth::Palette16 => "16 colours",
        }
    }

    /// The depth a terminal announces through `COLORTERM` and `TERM`.
    ///
    /// `COLORTERM=truecolor|24bit` or a `*-direct` terminfo name mean 24-bit;
    /// the Linux console has 16 colours; anything else is assumed to take
    /// the xterm 256-colour palette (every terminal emulator in use does).
    pub fn detect(colorterm: Option<&str>, term: Option<&str>) -> ColorDepth {
        let colorterm = colorterm.unwrap_or("").trim().to_ascii_lowercase();
        let term = term.unwrap_or("").trim().to_ascii_lowercase();
        if colorterm == "truecolor" || colorterm == "24bit" || term.ends_with("-direct") {
            ColorDepth::Truecolor
        } else if term == "linux" || term == "vt100" || term == "ansi" {
            ColorDepth::Palette16
        } else {
            ColorDepth::Palette256
        }
    }

    /// The depth of the terminal this process runs in (from the environment).
    pub fn from_env() -> ColorDepth {
        let colorterm = std::env::var("COLORTERM").ok();
        let term = std::env::var("TERM").ok();
        ColorDepth::detect(colorterm.as_deref(), term.as_deref())
    }

    /// The terminal colour for pixel `rgb` at pixel position (`x`, `y`);
    /// the position only matters with ordered dithering.
    #[inline]
    pub fn map(self, rgb: Rgb, dither: bool, x: usize, y: usize) -> Color {
        match self {
            ColorDepth::Truecolor => Color::Rgb(rgb[0], rgb[1], rgb[2]),
            ColorDepth::Palette256 => {
                let rgb = if dither { dithered(rgb, x, y, 40) } else { rgb };
                Color::Indexed(nearest_256(rgb))
            }
            ColorDepth::Palette16 => {
                let rgb = if dither { dithered(rgb, x, y, 96) } else { rgb };
                ANSI16[nearest_16(rgb)].1
            }
        }
    }
}

/// The six channel levels of the xterm colour cube (indices 16..=231).
pub const CUBE_LEVELS: [u8; 6] = [0, 95, 135, 175, 215, 255];

/// Index of the nearest cube level to a channel value (thresholds halfway between levels).
#[inline]
fn cube_step(v: u8) -> usize {
    match v {
        0..=47 => 0,
        48..=114 => 1,
        115..=154 => 2,
        155..=194 => 3,
        195..=234 => 4,
        _ => 5,
    }
}

#[inline]
fn dist2(a: Rgb, b: Rgb) -> u32 {
    a.iter()
        .zip(b)
        .map(|(&p, q)| {
            let d = p as i32 - q as i32;
            (d * d) as u32
        })
        .sum()
}

/// The xterm-256 index nearest to `rgb`: the closest of the cube colour and
/// the grey-ramp colour (grey `232 + i` is `8 + 10·i`).
pub fn nearest_256(rgb: Rgb) -> u8 {
    let [r, g, b] = rgb.map(cube_step);
    let cube = [CUBE_LEVELS[r], CUBE_LEVELS[g], CUBE_LEVELS[b]];
    let cube_index = 16 + 36 * r + 6 * g + b;
    let mean = (rgb[0] as u32 + rgb[1] as u32 + rgb[2] as u32) / 3;
    let grey_step = (mean.saturating_sub(3) / 10).min(23);
    let grey_level = (8 + 10 * grey_step) as u8;
    let grey = [grey_level; 3];
    if dist2(rgb, grey) < dist2(rgb, cube) {
        232 + grey_step as u8
    } else {
        cube_index as u8
    }
}

/// The 16 ANSI colours with xterm's default RGB values.
pub const ANSI16: [(Rgb, Color); 16] = [
    ([0, 0, 0], Color::Black),
    ([205, 0, 0], Color::Red),
    ([0, 205, 0], Color::Green),
    ([205, 205, 0], Color::Yellow),
    ([0, 0, 238], Color::Blue),
    ([205, 0, 205], Color::Magenta),
    ([0, 205, 205], Color::Cyan),
    ([229, 229, 229], Color::Gray),
    ([127, 127, 127], Color::DarkGray),
    ([255, 0, 0], Color::LightRed),
    ([0, 255, 0], Color::LightGreen),
    ([255, 255, 0], Color::LightYellow),
    ([92, 92, 255], Color::LightBlue),
    ([255, 0, 255], Color::LightMagenta),
    ([0, 255, 255], Color::LightCyan),
    ([255, 255, 255], Color::White),
];

/// Position in [`ANSI16`] of the colour nearest to `rgb`.
pub fn nearest_16(rgb: Rgb) -> usize {
    let mut best = 0;
    let mut best_d = u32::MAX;
    for (i, (c, _)) in ANSI16.iter().enumerate() {
        let d = dist2(rgb, *c);
        if d < best_d {
            best = i;
            best_d = d;
        }
    }
    best
}

/// 4×4 Bayer matrix, values 0..16.
const BAYER4: [[u8; 4]; 4] = [[0, 8, 2, 10], [12, 4, 14, 6], [3, 11, 1, 9], [15, 7, 13, 5]];

/// `rgb` shifted by the ordered-dither offset of pixel (`x`, `y`), spread over
/// about one palette step (`step`).
#[inline]
fn dithered(rgb: Rgb, x: usize, y: usize, step: i32) -> Rgb {
    let t = BAYER4[y & 3][x & 3] as i32;
    // Offset in (-step/2, step/2).
    let offset = (2 * t + 1 - 16) * step / 32;
    rgb.map(|c| (c as i32 + offset).clamp(0, 255) as u8)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dither_offsets_stay_within_half_a_step() {
        for y in 0..4 {
            for x in 0..4 {
                let [r, _, _] = dithered([128, 128, 128], x, y, 40);
                assert!((108..=148).contains(&r), "{r}");
            }
        }
    }
}
