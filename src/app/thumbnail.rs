//! A texture's preview for the texture panel: its size and a few pixels of
//! its colour, each the mean of the texels it covers.

use relief_core::framebuffer::Framebuffer;
use relief_texture::Texture;
use relief_texture::decode::resample;

/// Pixels across a thumbnail (one terminal column each).
pub const THUMB_WIDTH: usize = 4;
/// Pixels down a thumbnail (two per terminal row).
pub const THUMB_HEIGHT: usize = 4;

/// What the panel shows of one texture besides its name.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Preview {
    /// The texture's size in texels.
    pub width: usize,
    pub height: usize,
    /// [`THUMB_WIDTH`] × [`THUMB_HEIGHT`] pixels of its colour.
    pub thumb: Framebuffer,
}

impl Preview {
    pub fn of(texture: &Texture) -> Preview {
        Preview {
            width: texture.width(),
            height: texture.height(),
            thumb: thumbnail(texture, THUMB_WIDTH, THUMB_HEIGHT),
        }
    }
}

/// The colour of `texture` shrunk to `width × height` pixels: each channel
/// resampled like a height map is (box means when shrinking), the height
/// left out.
pub fn thumbnail(texture: &Texture, width: usize, height: usize) -> Framebuffer {
    let base = texture.base();
    let size = (base.width, base.height);
    let channel = |c: usize| {
        let plane: Vec<f32> = base.texels.iter().map(|t| t[c]).collect();
        resample::grid(&plane, size, (width, height))
    };
    let (r, g, b) = (channel(0), channel(1), channel(2));
    let mut fb = Framebuffer::new(width, height);
    let byte = |x: f32| (x.clamp(0.0, 1.0) * 255.0).round() as u8;
    for (i, px) in fb.pixels_mut().iter_mut().enumerate() {
        *px = [byte(r[i]), byte(g[i]), byte(b[i])];
    }
    fb
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quadrants_of_one_colour_give_their_colour() {
        // 8×8: red top-left, green top-right, blue bottom-left, white bottom-right.
        let mut rgba = Vec::new();
        for y in 0..8 {
            for x in 0..8 {
                let c = match (x < 4, y < 4) {
                    (true, true) => [255, 0, 0],
                    (false, true) => [0, 255, 0],
                    (true, false) => [0, 0, 255],
                    (false, false) => [255, 255, 255],
                };
                rgba.extend_from_slice(&[c[0], c[1], c[2], 128]);
            }
        }
        let tex = Texture::from_rgba8("q", 8, 8, &rgba);
        let fb = thumbnail(&tex, 2, 2);
        assert_eq!(fb.get(0, 0), [255, 0, 0]);
        assert_eq!(fb.get(1, 0), [0, 255, 0]);
        assert_eq!(fb.get(0, 1), [0, 0, 255]);
        assert_eq!(fb.get(1, 1), [255, 255, 255]);
        let p = Preview::of(&tex);
        assert_eq!((p.width, p.height), (8, 8));
        assert_eq!(
            (p.thumb.width(), p.thumb.height()),
            (THUMB_WIDTH, THUMB_HEIGHT)
        );
    }
}
