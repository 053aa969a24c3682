//! How the picture reaches the terminal: text cells of a symbol set, or
//! pixels through the kitty graphics protocol, sixel or iTerm2 images.

use std::io::{self, Write};

use super::color::ColorDepth;
use super::symbols::Symbols;
use super::{ansi, iterm, kitty, sixel};
use crate::framebuffer::{Framebuffer, Rgb};

/// `--format`, chafa's names.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, clap::ValueEnum)]
pub enum Format {
    /// What the terminal is found to speak (text symbols when unsure).
    #[default]
    Auto,
    /// Text cells of the `--symbols` set.
    Symbols,
    /// The kitty graphics protocol (kitty, WezTerm, Ghostty, Konsole).
    Kitty,
    /// Sixel (xterm -ti vt340, mlterm, foot, WezTerm, Windows Terminal).
    Sixels,
    /// iTerm2 inline images (iTerm2, WezTerm).
    Iterm,
}

impl Format {
    pub fn name(self) -> &'static str {
        match self {
            Format::Auto => "auto",
            Format::Symbols => "symbols",
            Format::Kitty => "kitty",
            Format::Sixels => "sixels",
            Format::Iterm => "iterm",
        }
    }

    /// True for the formats that send pixels.
    pub fn is_pixels(self) -> bool {
        matches!(self, Format::Kitty | Format::Sixels | Format::Iterm)
    }
}

/// The frame in `format` for a file or a pipe (`relief render --ansi`),
/// starting at the cursor and ending with a newline (LF only); pixel
/// formats show the frame at its own pixel size.
#[allow(clippy::too_many_arguments)]
pub fn write_frame(
    fb: &Framebuffer,
    format: Format,
    symbols: Symbols,
    depth: ColorDepth,
    dither: bool,
    pad: Rgb,
    out: &mut impl Write,
) -> io::Result<()> {
    match format {
        Format::Auto | Format::Symbols => {
            ansi::write_symbol_text(fb, symbols, depth, dither, pad, b"\n", out)
        }
        Format::Kitty => {
            kitty::write_image(fb, None, out)?;
            out.write_all(b"\n")
        }
        Format::Sixels => {
            sixel::write_image(fb, dither, out)?;
            out.write_all(b"\n")
        }
        Format::Iterm => {
            iterm::write_image(fb, None, out)?;
            out.write_all(b"\n")
        }
    }
}
