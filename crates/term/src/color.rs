//! Colour depth: which one the terminal takes, and how a 24-bit pixel maps onto it.

use ratatui::style::Color;

use super::palette::ANSI16;
use super::palette::Palette;
use relief_core::framebuffer::Rgb;

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

    /// The palette this depth maps onto (`None` for 24-bit).
    pub fn palette(self) -> Option<&'static Palette> {
        match self {
            ColorDepth::Truecolor => None,
            ColorDepth::Palette256 => Some(Palette::xterm256()),
            ColorDepth::Palette16 => Some(Palette::ansi16()),
        }
    }

    /// A mapper for pictures drawn over `background`.
    pub fn quantizer(self, background: Rgb) -> Quantizer {
        let palette = self.palette();
        Quantizer {
            palette,
            background: palette.map(|p| p.pick(background).best),
            pad: Some(background),
        }
    }

    /// The terminal colour for pixel `rgb` at pixel position (`x`, `y`),
    /// with no background to keep clear of; the position only matters with
    /// dithering. The view uses [`Quantizer`], which also knows the background.
    pub fn map(self, rgb: Rgb, dither: bool, x: usize, y: usize) -> Color {
        Quantizer {
            palette: self.palette(),
            background: None,
            pad: None,
        }
        .pick(rgb, dither, x, y)
    }
}

/// Maps 24-bit pixels to the terminal's colours for one picture.
///
/// A pixel that is not the background never takes the background's palette
/// entry (it takes its next best instead), so a dim surface or an edge
/// against the background stays visible.
#[derive(Clone, Copy)]
pub struct Quantizer {
    palette: Option<&'static Palette>,
    /// Position of the background's entry.
    background: Option<u8>,
    pad: Option<Rgb>,
}

impl Quantizer {
    /// The colour for `rgb` at pixel (`x`, `y`); `dither` allows the ordered
    /// dither pick (the caller allows it only off flat areas, and the
    /// palette table only where mixing lowers the error).
    #[inline]
    pub fn pick(&self, rgb: Rgb, dither: bool, x: usize, y: usize) -> Color {
        let Some(palette) = self.palette else {
            return Color::Rgb(rgb[0], rgb[1], rgb[2]);
        };
        let p = palette.pick(rgb);
        let mut pos = p.best;
        // The background itself is never dithered, even at an edge.
        if dither && BAYER4[y & 3][x & 3] < p.share && Some(rgb) != self.pad {
            pos = p.partner;
        }
        if Some(pos) == self.background && Some(rgb) != self.pad {
            pos = if p.best != pos { p.best } else { p.second };
        }
        palette.entries[pos as usize].color
    }
}

/// What a terminal colour shows (xterm's default values), for pictures of
/// what the terminal would display. `Reset` shows as `default`.
pub fn shown_rgb(color: Color, default: Rgb) -> Rgb {
    match color {
        Color::Rgb(r, g, b) => [r, g, b],
        Color::Indexed(i) if i >= 16 => {
            let p = Palette::xterm256();
            p.entries[i as usize - 16].rgb
        }
        Color::Indexed(i) => ANSI16[i as usize].0,
        Color::Reset => default,
        named => ANSI16
            .iter()
            .find(|(_, c)| *c == named)
            .map_or(default, |(rgb, _)| *rgb),
    }
}

/// The xterm-256 index perceptually nearest to `rgb` (see [`Palette`]).
pub fn nearest_256(rgb: Rgb) -> u8 {
    match Palette::xterm256().entries[Palette::xterm256().nearest(rgb)].color {
        Color::Indexed(i) => i,
        _ => unreachable!("the 256-colour palette holds indexed colours"),
    }
}

/// Position in [`ANSI16`] of the colour perceptually nearest to `rgb`.
pub fn nearest_16(rgb: Rgb) -> usize {
    Palette::ansi16().nearest(rgb)
}

/// 4×4 Bayer matrix, values 0..16.
const BAYER4: [[u8; 4]; 4] = [[0, 8, 2, 10], [12, 4, 14, 6], [3, 11, 1, 9], [15, 7, 13, 5]];
