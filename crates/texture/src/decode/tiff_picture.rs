//! What both TIFF readers ([`super::tiff_samples`], [`super::tiff_strips`])
//! give back: the decoded picture, or why a picture they recognise is
//! refused.

/// A decoded picture: size, RGBA samples in 0..1 row by row, and whether
/// the alpha is real.
pub struct Picture {
    pub width: usize,
    pub height: usize,
    pub rgba: Vec<[f32; 4]>,
    pub has_alpha: bool,
}

/// Why a picture a reader recognises is not drawn, in plain words.
#[derive(Debug, PartialEq)]
pub enum Refusal {
    /// Valid, but a variant relief does not decode.
    Unsupported(String),
    /// Damaged: the data contradicts the tags.
    Corrupt(String),
}

impl Picture {
    /// Samples in 0..1, `per_pixel` to a pixel (grey or RGB first, then
    /// alpha if there is one more), as RGBA; `white_is_zero` turns grey over.
    pub fn from_samples(
        width: usize,
        height: usize,
        samples: &[f32],
        per_pixel: usize,
        channels: usize,
        white_is_zero: bool,
    ) -> Picture {
        let has_alpha = per_pixel > channels;
        let rgba = samples
            .chunks_exact(per_pixel)
            .map(|p| {
                let a = if has_alpha { p[channels] } else { 1.0 };
                if channels == 1 {
                    let g = if white_is_zero { 1.0 - p[0] } else { p[0] };
                    [g, g, g, a]
                } else {
                    [p[0], p[1], p[2], a]
                }
            })
            .collect();
        Picture {
            width,
            height,
            rgba,
            has_alpha,
        }
    }
}
