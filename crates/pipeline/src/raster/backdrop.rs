//! What a band is cleared to before its triangles are drawn: the plain
//! background colour, or a picture of the environment behind the model
//! (`--backdrop`, key `B`; made by `render::backdrop`).

use super::fill::fill;
use relief_core::framebuffer::Rgb;

/// The frame's backdrop.
#[derive(Clone, Debug, PartialEq)]
pub enum Backdrop {
    /// The background colour everywhere.
    Plain(Rgb),
    /// One colour per pixel of the frame, row by row.
    Picture(Vec<Rgb>),
}

impl Backdrop {
    /// Fills `color`: pixels of the frame from row `y0`, the frame `width`
    /// pixels wide.
    pub fn fill(&self, color: &mut [Rgb], y0: usize, width: usize) {
        match self {
            Backdrop::Plain(c) => fill(color, *c),
            Backdrop::Picture(p) => {
                let start = y0 * width;
                match p.get(start..start + color.len()) {
                    Some(rows) => color.copy_from_slice(rows),
                    None => fill(color, [0; 3]),
                }
            }
        }
    }

    /// One colour standing for the backdrop where a single one is needed.
    pub fn plain(&self) -> Rgb {
        match self {
            Backdrop::Plain(c) => *c,
            Backdrop::Picture(p) => p.first().copied().unwrap_or([0; 3]),
        }
    }
}
