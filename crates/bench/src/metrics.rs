//! Error of a frame against the reference: PSNR, largest channel error, SSIM.
//!
//! All three compare 8-bit RGB images of the same size. They are written here
//! rather than taken from a crate because each is a few lines of well-known
//! arithmetic and the tests below pin them to hand-computed values.

use relief_core::framebuffer::Rgb;

/// Sum of squared channel differences and the number of channel values compared.
/// Accumulating these over several frames and taking the PSNR of the total
/// gives the PSNR of the frames seen as one image.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SquaredError {
    pub sum: f64,
    pub count: u64,
}

impl SquaredError {
    /// Adds the error of `image` against `reference` (same length).
    pub fn add(&mut self, image: &[Rgb], reference: &[Rgb]) {
        assert_eq!(image.len(), reference.len(), "images of different sizes");
        for (a, b) in image.iter().zip(reference) {
            for c in 0..3 {
                let d = a[c] as f64 - b[c] as f64;
                self.sum += d * d;
            }
        }
        self.count += 3 * image.len() as u64;
    }

    /// Mean squared error per channel value (0 when nothing was compared).
    pub fn mse(&self) -> f64 {
        if self.count == 0 {
            0.0
        } else {
            self.sum / self.count as f64
        }
    }

    /// Peak signal-to-noise ratio in dB for 8-bit channels: 10·log10(255² / MSE).
    /// Identical images give `f64::INFINITY`.
    pub fn psnr(&self) -> f64 {
        psnr_from_mse(self.mse())
    }
}

/// 10·log10(255² / mse); infinite for a zero error.
pub fn psnr_from_mse(mse: f64) -> f64 {
    if mse <= 0.0 {
        f64::INFINITY
    } else {
        10.0 * (255.0 * 255.0 / mse).log10()
    }
}

/// PSNR of one image against another, in dB (infinite when identical).
pub fn psnr(image: &[Rgb], reference: &[Rgb]) -> f64 {
    let mut e = SquaredError::default();
    e.add(image, reference);
    e.psnr()
}

/// The largest absolute difference of any channel of any pixel (0..=255).
pub fn max_channel_error(image: &[Rgb], reference: &[Rgb]) -> u8 {
    assert_eq!(image.len(), reference.len(), "images of different sizes");
    image
        .iter()
        .zip(reference)
        .flat_map(|(a, b)| (0..3).map(move |c| a[c].abs_diff(b[c])))
        .max()
        .unwrap_or(0)
}

/// Luma (Rec. 601 weights) in 0..255, the channel SSIM is computed on.
fn luma(p: Rgb) -> f64 {
    0.299 * p[0] as f64 + 0.587 * p[1] as f64 + 0.114 * p[2] as f64
}

/// Normalised 1-D Gaussian of σ = 1.5 over 11 taps: the window of Wang et al. (2004).
fn gaussian_window() -> [f64; 11] {
    let mut w = [0.0; 11];
    for (i, v) in w.iter_mut().enumerate() {
        let x = i as f64 - 5.0;
        *v = (-x * x / (2.0 * 1.5 * 1.5)).exp();
    }
    let sum: f64 = w.iter().sum();
    w.map(|v| v / sum)
}

/// Separable Gaussian blur with the edge pixel repeated outside the image.
fn blur(values: &[f64], width: usize, height: usize) -> Vec<f64> {
    let w = gaussian_window();
    let clamp = |i: isize, n: usize| i.clamp(0, n as isize - 1) as usize;
    let mut rows = vec![0.0; values.len()];
    for y in 0..height {
        for x in 0..width {
            rows[y * width + x] = (0..11)
                .map(|k| w[k] * values[y * width + clamp(x as isize + k as isize - 5, width)])
                .sum();
        }
    }
    let mut out = vec![0.0; values.len()];
    for y in 0..height {
        for x in 0..width {
            out[y * width + x] = (0..11)
                .map(|k| w[k] * rows[clamp(y as isize + k as isize - 5, height) * width + x])
                .sum();
        }
    }
    out
}

/// Mean structural similarity (SSIM) of the luma of two images: 1 for
/// identical images, lower as structure differs. Gaussian window σ = 1.5,
/// K1 = 0.01, K2 = 0.03, dynamic range 255, averaged over every pixel (the
/// window repeats edge pixels, so any size works).
pub fn ssim(image: &[Rgb], reference: &[Rgb], width: usize, height: usize) -> f64 {
    assert_eq!(image.len(), reference.len(), "images of different sizes");
    assert_eq!(
        image.len(),
        width * height,
        "size does not match the pixels"
    );
    if image.is_empty() {
        return 1.0;
    }
    let a: Vec<f64> = image.iter().map(|&p| luma(p)).collect();
    let b: Vec<f64> = reference.iter().map(|&p| luma(p)).collect();
    let product =
        |x: &[f64], y: &[f64]| -> Vec<f64> { x.iter().zip(y).map(|(p, q)| p * q).collect() };
    let mu_a = blur(&a, width, height);
    let mu_b = blur(&b, width, height);
    let aa = blur(&product(&a, &a), width, height);
    let bb = blur(&product(&b, &b), width, height);
    let ab = blur(&product(&a, &b), width, height);
    let c1 = (0.01f64 * 255.0).powi(2);
    let c2 = (0.03f64 * 255.0).powi(2);
    let total: f64 = (0..a.len())
        .map(|i| {
            let (ma, mb) = (mu_a[i], mu_b[i]);
            let var_a = aa[i] - ma * ma;
            let var_b = bb[i] - mb * mb;
            let cov = ab[i] - ma * mb;
            ((2.0 * ma * mb + c1) * (2.0 * cov + c2))
                / ((ma * ma + mb * mb + c1) * (var_a + var_b + c2))
        })
        .sum();
    total / a.len() as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(n: usize, f: impl Fn(usize) -> Rgb) -> Vec<Rgb> {
        (0..n).map(f).collect()
    }

    #[test]
    fn identical_images_have_infinite_psnr_and_no_error() {
        let a = image(64, |i| [i as u8, (3 * i) as u8, 200]);
        assert_eq!(psnr(&a, &a), f64::INFINITY);
        assert_eq!(max_channel_error(&a, &a), 0);
        assert!((ssim(&a, &a, 8, 8) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn psnr_of_a_known_difference() {
        // 4 pixels, 12 channel values; one channel off by 10 → MSE = 100 / 12.
        let a = vec![[10, 20, 30]; 4];
        let mut b = a.clone();
        b[2][1] = 30;
        let expected = 10.0 * (255.0f64 * 255.0 * 12.0 / 100.0).log10(); // 38.9226… dB
        assert!((psnr(&b, &a) - expected).abs() < 1e-9);
        assert!((expected - 38.9226).abs() < 1e-4);
        // Every channel off by 1 → MSE = 1 → 20·log10(255) = 48.1308 dB.
        let c: Vec<Rgb> = a.iter().map(|p| p.map(|v| v + 1)).collect();
        assert!((psnr(&c, &a) - 48.130_803_608).abs() < 1e-6);
    }

    #[test]
    fn squared_error_accumulates_frames_as_one_image() {
        let a = vec![[0u8; 3]; 2];
        let b = vec![[2u8, 0, 0]; 2]; // squared error 8 over 6 values
        let mut e = SquaredError::default();
        e.add(&a, &a);
        e.add(&b, &a);
        assert_eq!(e.count, 12);
        assert_eq!(e.sum, 8.0);
        assert!((e.psnr() - psnr_from_mse(8.0 / 12.0)).abs() < 1e-12);
        assert_eq!(SquaredError::default().psnr(), f64::INFINITY);
    }

    #[test]
    fn max_channel_error_takes_the_worst_channel_either_way() {
        let a = vec![[10, 200, 30], [0, 0, 0]];
        let b = vec![[12, 150, 30], [0, 0, 255]];
        assert_eq!(max_channel_error(&a, &b), 255);
        assert_eq!(max_channel_error(&b[..1], &a[..1]), 50);
    }

    #[test]
    fn ssim_falls_with_noise_and_is_symmetric() {
        let (w, h) = (32, 24);
        let a = image(w * h, |i| {
            let (x, y) = (i % w, i / w);
            let v = if (x / 4 + y / 4) % 2 == 0 { 40 } else { 220 };
            [v, v, v]
        });
        let noisy = image(w * h, |i| {
            let v = a[i][0] as i32 + if i % 3 == 0 { 30 } else { -30 };
            let v = v.clamp(0, 255) as u8;
            [v, v, v]
        });
        let s = ssim(&noisy, &a, w, h);
        assert!(s < 0.95 && s > 0.0, "ssim {s}");
        assert!((s - ssim(&a, &noisy, w, h)).abs() < 1e-12);
        // A uniform brightness shift keeps the structure: SSIM stays close to 1.
        let shifted: Vec<Rgb> = a.iter().map(|p| p.map(|v| v.saturating_add(4))).collect();
        assert!(ssim(&shifted, &a, w, h) > s);
    }
}
