//! The plain colour image every stage writes into and every test reads.

/// 8-bit RGB, the framebuffer's pixel.
pub type Rgb = [u8; 3];

/// `width × height` RGB pixels, top row first.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Framebuffer {
    width: usize,
    height: usize,
    pixels: Vec<Rgb>,
}

impl Framebuffer {
    /// A framebuffer filled with black. Zero sizes are allowed (nothing is drawn).
    pub fn new(width: usize, height: usize) -> Self {
        Framebuffer {
            width,
            height,
            pixels: vec![[0; 3]; width * height],
        }
    }

    pub fn width(&self) -> usize {
        self.width
    }

    pub fn height(&self) -> usize {
        self.height
    }

    /// Changes the size, keeping the allocation when it is big enough.
    pub fn resize(&mut self, width: usize, height: usize) {
        self.width = width;
        self.height = height;
        self.pixels.resize(width * height, [0; 3]);
    }

    pub fn fill(&mut self, color: Rgb) {
        self.pixels.fill(color);
    }

    /// The pixel at column `x`, row `y` (row 0 at the top).
    pub fn get(&self, x: usize, y: usize) -> Rgb {
        self.pixels[y * self.width + x]
    }

    pub fn set(&mut self, x: usize, y: usize, color: Rgb) {
        self.pixels[y * self.width + x] = color;
    }

    pub fn pixels(&self) -> &[Rgb] {
        &self.pixels
    }

    pub fn pixels_mut(&mut self) -> &mut [Rgb] {
        &mut self.pixels
    }

    /// One row of pixels.
    pub fn row(&self, y: usize) -> &[Rgb] {
        &self.pixels[y * self.width..(y + 1) * self.width]
    }

    /// Copies into an `image` buffer, for PNG output.
    pub fn to_image(&self) -> image::RgbImage {
        let raw: Vec<u8> = self.pixels.iter().flatten().copied().collect();
        image::RgbImage::from_raw(self.width as u32, self.height as u32, raw)
            .expect("buffer length matches the size")
    }

    /// Writes a PNG.
    pub fn save_png(&self, path: &std::path::Path) -> anyhow::Result<()> {
        use anyhow::Context;
        if self.width == 0 || self.height == 0 {
            anyhow::bail!("cannot write an empty {}x{} image", self.width, self.height);
        }
        write_png(&self.to_image(), path)
            .with_context(|| format!("cannot write {}", crate::sanitize::display_path(path)))
    }
}

/// Writes `picture` as a PNG file. The PNG encoder is named, not chosen
/// from the file name: a format chosen at run time would compile every
/// encoder `image` has into the caller.
pub fn write_png(picture: &image::RgbImage, path: &std::path::Path) -> image::ImageResult<()> {
    use image::ImageEncoder;
    let mut file = std::io::BufWriter::new(std::fs::File::create(path)?);
    image::codecs::png::PngEncoder::new(&mut file).write_image(
        picture.as_raw(),
        picture.width(),
        picture.height(),
        image::ExtendedColorType::Rgb8,
    )?;
    std::io::Write::flush(&mut file)?;
    Ok(())
}
