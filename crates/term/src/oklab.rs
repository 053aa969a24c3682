//! OKLab (Björn Ottosson, 2020): a colour space where straight-line distance
//! follows perceived difference far better than distance in sRGB.

use relief_core::framebuffer::Rgb;

/// A colour in OKLab: lightness `l` in 0..=1, `a` green→red, `b` blue→yellow.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lab {
    pub l: f32,
    pub a: f32,
    pub b: f32,
}

/// An sRGB channel (0..=1) to linear light.
#[inline]
pub fn to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// Linear light (0..=1) to an sRGB channel.
#[inline]
pub fn from_linear(c: f32) -> f32 {
    if c <= 0.003_130_8 {
        c * 12.92
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

/// An 8-bit sRGB colour as linear-light RGB.
#[inline]
pub fn linear_rgb(rgb: Rgb) -> [f32; 3] {
    rgb.map(|c| to_linear(c as f32 / 255.0))
}

/// Linear-light RGB to OKLab.
#[inline]
pub fn lab_from_linear([r, g, b]: [f32; 3]) -> Lab {
    let l = 0.412_221_46 * r + 0.536_332_55 * g + 0.051_445_995 * b;
    let m = 0.211_903_5 * r + 0.680_699_5 * g + 0.107_396_96 * b;
    let s = 0.088_302_46 * r + 0.281_718_85 * g + 0.629_978_7 * b;
    let (l, m, s) = (l.cbrt(), m.cbrt(), s.cbrt());
    Lab {
        l: 0.210_454_26 * l + 0.793_617_8 * m - 0.004_072_047 * s,
        a: 1.977_998_5 * l - 2.428_592_2 * m + 0.450_593_7 * s,
        b: 0.025_904_037 * l + 0.782_771_77 * m - 0.808_675_77 * s,
    }
}

/// An 8-bit sRGB colour in OKLab.
#[inline]
pub fn lab(rgb: Rgb) -> Lab {
    lab_from_linear(linear_rgb(rgb))
}

impl Lab {
    /// Chroma: distance from the grey axis.
    #[inline]
    pub fn chroma(self) -> f32 {
        self.a.hypot(self.b)
    }

    /// Plain Euclidean distance (the error measure of the tests and tables).
    #[inline]
    pub fn distance(self, other: Lab) -> f32 {
        let (dl, da, db) = (self.l - other.l, self.a - other.a, self.b - other.b);
        (dl * dl + da * da + db * db).sqrt()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn white_black_and_grey_sit_on_the_axis() {
        let w = lab([255, 255, 255]);
        assert!((w.l - 1.0).abs() < 1e-3 && w.chroma() < 1e-3, "{w:?}");
        let k = lab([0, 0, 0]);
        assert!(k.l.abs() < 1e-6 && k.chroma() < 1e-6);
        let g = lab([119, 119, 119]);
        assert!(g.chroma() < 1e-3 && (g.l - 0.57).abs() < 0.01, "{g:?}");
    }

    #[test]
    fn known_values_match_the_published_ones() {
        // Ottosson's table: pure sRGB red is L 0.628, a 0.225, b 0.126.
        let r = lab([255, 0, 0]);
        assert!((r.l - 0.628).abs() < 2e-3, "{r:?}");
        assert!(
            (r.a - 0.225).abs() < 2e-3 && (r.b - 0.126).abs() < 2e-3,
            "{r:?}"
        );
    }

    #[test]
    fn linear_round_trip() {
        for c in [0u8, 1, 10, 50, 128, 200, 255] {
            let v = c as f32 / 255.0;
            assert!((from_linear(to_linear(v)) - v).abs() < 1e-5);
        }
    }
}
