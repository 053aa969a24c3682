//! The largest picture a load keeps: a small frame (a file manager's
//! preview of 80×24 cells) shows a 2048² map at a few dozen texels across,
//! so `relief render` decodes a model's maps and halves them, before any
//! texture is made of them, until they are no larger than the frame needs.
//! The mip levels a frame of that size samples are still there: only the
//! ones finer than it could use are never built.
//!
//! The cap is set around a load ([`with_max_side`]) on the thread that
//! loads, and read by the decoder ([`reduced`]); the interactive view sets
//! none and keeps every picture whole.

use std::cell::Cell;

use image::DynamicImage;

thread_local! {
    static MAX_SIDE: Cell<Option<u32>> = const { Cell::new(None) };
}

/// Texels per frame pixel kept, across the frame's larger side: a map
/// spread over the whole frame keeps four times the frame's detail; one
/// whose used part is a quarter of the picture still gets a texel a pixel.
const TEXELS_PER_PIXEL: u32 = 4;

/// No picture is reduced below this side (a few kB of texels).
const MIN_SIDE: u32 = 256;

/// The side a frame of `width × height` pixels needs its maps to have at
/// most: a power of two, at least [`MIN_SIDE`].
pub fn side_for_frame(width: usize, height: usize) -> u32 {
    let larger = width.max(height).min(1 << 20) as u32;
    (larger * TEXELS_PER_PIXEL)
        .next_power_of_two()
        .max(MIN_SIDE)
}

/// Runs `load` with pictures cut to at most `side` texels a side (`None`:
/// kept whole), on this thread; the cap before it is restored afterwards,
/// even when `load` panics.
pub fn with_max_side<T>(side: Option<u32>, load: impl FnOnce() -> T) -> T {
    struct Restore(Option<u32>);
    impl Drop for Restore {
        fn drop(&mut self) {
            MAX_SIDE.with(|cap| cap.set(self.0));
        }
    }
    let _restore = Restore(MAX_SIDE.with(|cap| cap.replace(side)));
    load()
}

/// The cap in force on this thread.
pub fn max_side() -> Option<u32> {
    MAX_SIDE.with(Cell::get)
}

/// How many times `width × height` is halved (each side rounded up) until
/// both are within `side`.
pub fn halvings(width: u32, height: u32, side: u32) -> u32 {
    let (mut w, mut h, mut k) = (width, height, 0);
    while w > side.max(1) || h > side.max(1) {
        (w, h, k) = (w.div_ceil(2), h.div_ceil(2), k + 1);
    }
    k
}

/// The size `width × height` is halved to (each side rounded up, never
/// below 1) until both are within `side`.
pub fn halved_within(width: u32, height: u32, side: u32) -> (u32, u32) {
    let f = 1u64 << halvings(width, height, side);
    let cut = |n: u32| u64::from(n).div_ceil(f) as u32;
    (cut(width), cut(height))
}

/// `image` halved until it fits the cap in force (each texel the mean of
/// the ones it covers; the colour type kept), or as it is.
pub fn reduced(image: DynamicImage) -> DynamicImage {
    let Some(side) = max_side() else {
        return image;
    };
    let shift = halvings(image.width(), image.height(), side);
    if shift == 0 {
        return image;
    }
    let (w, h) = halved_within(image.width(), image.height(), side);
    match image {
        DynamicImage::ImageRgb8(b) => DynamicImage::ImageRgb8(halved_buffer(&b, shift)),
        DynamicImage::ImageRgba8(b) => DynamicImage::ImageRgba8(halved_buffer(&b, shift)),
        DynamicImage::ImageLuma8(b) => DynamicImage::ImageLuma8(halved_buffer(&b, shift)),
        DynamicImage::ImageLumaA8(b) => DynamicImage::ImageLumaA8(halved_buffer(&b, shift)),
        // 16-bit and float pictures: the image crate's own averaging.
        other => other.thumbnail_exact(w, h),
    }
}

/// An 8-bit picture with each block of 2^`shift` × 2^`shift` texels (fewer
/// at the right and bottom edges) made one, the mean of its texels.
fn halved_buffer<P>(
    src: &image::ImageBuffer<P, Vec<u8>>,
    shift: u32,
) -> image::ImageBuffer<P, Vec<u8>>
where
    P: image::Pixel<Subpixel = u8>,
{
    let channels = usize::from(P::CHANNEL_COUNT);
    let (sw, sh) = (src.width() as usize, src.height() as usize);
    let f = 1usize << shift;
    let (dw, dh) = (sw.div_ceil(f), sh.div_ceil(f));
    let raw: &[u8] = src.as_raw();
    let mut out = Vec::with_capacity(dw * dh * channels);
    // Each column's sum over a block's rows first (one pass over the
    // bytes, in lanes; 2^24 rows of 255 fit in 32 bits), then the sums of
    // each block's columns.
    let mut columns = vec![0u32; sw * channels];
    for oy in 0..dh {
        columns.fill(0);
        let rows = oy * f..((oy + 1) * f).min(sh);
        let row_count = rows.len();
        for row in
            raw[rows.start * sw * channels..rows.end * sw * channels].chunks_exact(sw * channels)
        {
            for (sum, &v) in columns.iter_mut().zip(row) {
                *sum += u32::from(v);
            }
        }
        for (ox, run) in columns.chunks(f * channels).enumerate() {
            let n = ((((ox + 1) * f).min(sw) - ox * f) * row_count) as u64;
            for c in 0..channels {
                let sum: u64 = run
                    .iter()
                    .skip(c)
                    .step_by(channels)
                    .map(|&v| u64::from(v))
                    .sum();
                out.push(((sum + n / 2) / n) as u8);
            }
        }
    }
    image::ImageBuffer::from_raw(dw as u32, dh as u32, out).expect("the size it was made for")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_preview_needs_a_few_texels_a_pixel() {
        // 80×24 half-block cells are 80×48 pixels.
        assert_eq!(side_for_frame(80, 48), 512);
        assert_eq!(side_for_frame(480, 360), 2048);
        assert_eq!(side_for_frame(10, 5), MIN_SIDE);
        assert_eq!(halved_within(2048, 2048, 512), (512, 512));
        assert_eq!(halved_within(2048, 1000, 512), (512, 250));
        assert_eq!(halved_within(1500, 7, 512), (375, 2));
        assert_eq!(halved_within(300, 200, 512), (300, 200));
    }

    #[test]
    fn the_cap_holds_inside_the_load_only() {
        let picture = DynamicImage::ImageRgb8(image::RgbImage::from_pixel(
            1024,
            64,
            image::Rgb([200, 100, 50]),
        ));
        let small = with_max_side(Some(256), || {
            assert_eq!(max_side(), Some(256));
            reduced(picture.clone())
        });
        assert_eq!((small.width(), small.height()), (256, 16));
        assert_eq!(small.color(), image::ColorType::Rgb8);
        // A flat picture stays that colour.
        assert_eq!(small.to_rgb8().get_pixel(100, 8).0, [200, 100, 50]);
        assert_eq!(max_side(), None);
        assert_eq!(reduced(picture).width(), 1024);
        let caught = std::panic::catch_unwind(|| with_max_side(Some(8), || panic!("load")));
        assert!(caught.is_err());
        assert_eq!(max_side(), None, "restored after a panic");
    }

    #[test]
    fn each_texel_is_the_rounded_mean_of_its_block_edges_included() {
        // 5×3 grey texels halved twice: blocks of 4×4, the last column and
        // the rows cut short by the edges.
        let values = [
            [0u8, 10, 20, 30, 200],
            [40, 50, 60, 70, 100],
            [80, 90, 100, 111, 0],
        ];
        let grey =
            image::GrayImage::from_fn(5, 3, |x, y| image::Luma([values[y as usize][x as usize]]));
        let small = with_max_side(Some(2), || reduced(DynamicImage::ImageLuma8(grey)));
        let small = small.as_luma8().expect("still 8-bit grey");
        assert_eq!(small.dimensions(), (2, 1));
        // (0+10+20+30+40+50+60+70+80+90+100+111) / 12 = 55.08; (200+100+0) / 3 = 100.
        assert_eq!(small.as_raw(), &vec![55, 100]);
        // Colour channels are averaged each on its own, alpha too.
        let rgba = image::RgbaImage::from_fn(4, 4, |x, _| {
            image::Rgba([x as u8 * 50, 7, 255, 9 + x as u8])
        });
        let one = with_max_side(Some(1), || reduced(DynamicImage::ImageRgba8(rgba)));
        assert_eq!(one.as_rgba8().unwrap().as_raw(), &vec![75, 7, 255, 11]);
    }
}
