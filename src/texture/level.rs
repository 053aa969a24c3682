//! One image level: storage, wrapping and the nearest / bilinear reads.

/// RGB + height, each in 0..1.
pub type Texel = [f32; 4];

/// A `width × height` grid of texels, bottom row first.
#[derive(Clone, Debug, PartialEq)]
pub struct Level {
    pub width: usize,
    pub height: usize,
    pub texels: Vec<Texel>,
}

/// Wraps an integer texel index into 0..n (repeat), for any i including negatives.
#[inline]
fn wrap(i: i64, n: usize) -> usize {
    i.rem_euclid(n as i64) as usize
}

/// Turns a texture coordinate into a texel-space position, robust to any
/// float: NaN and infinities map to 0 and huge values keep their fraction.
#[inline]
fn to_texel_space(t: f32, n: usize) -> f32 {
    if !t.is_finite() {
        return 0.0;
    }
    // Keep only the fraction first so that huge t does not lose every bit of
    // position once multiplied by n.
    (t - t.floor()) * n as f32
}

impl Level {
    /// A level with every texel equal to `texel`. Sizes of 0 become 1.
    pub fn solid(width: usize, height: usize, texel: Texel) -> Self {
        let (width, height) = (width.max(1), height.max(1));
        Level {
            width,
            height,
            texels: vec![texel; width * height],
        }
    }

    /// From 8-bit RGBA rows stored top row first (as images are).
    pub fn from_rgba8_top_down(width: usize, height: usize, rgba: &[u8]) -> Self {
        assert_eq!(rgba.len(), width * height * 4, "RGBA buffer size");
        assert!(width > 0 && height > 0, "a texture has at least one texel");
        let mut texels = Vec::with_capacity(width * height);
        for row in (0..height).rev() {
            for px in rgba[row * width * 4..(row + 1) * width * 4].chunks_exact(4) {
                texels.push([
                    px[0] as f32 / 255.0,
                    px[1] as f32 / 255.0,
                    px[2] as f32 / 255.0,
                    px[3] as f32 / 255.0,
                ]);
            }
        }
        Level {
            width,
            height,
            texels,
        }
    }

    /// The texel at integer coordinates, wrapped.
    #[inline]
    pub fn texel(&self, x: i64, y: i64) -> Texel {
        self.texels[wrap(y, self.height) * self.width + wrap(x, self.width)]
    }

    /// The texel that contains (u, v), wrapped.
    #[inline]
    pub fn nearest(&self, u: f32, v: f32) -> Texel {
        let x = (to_texel_space(u, self.width) as usize).min(self.width - 1);
        let y = (to_texel_space(v, self.height) as usize).min(self.height - 1);
        self.texels[y * self.width + x]
    }

    /// Bilinear interpolation between the four texel centres around (u, v),
    /// wrapping at the borders.
    #[inline]
    pub fn bilinear(&self, u: f32, v: f32) -> Texel {
        let x = to_texel_space(u, self.width) - 0.5;
        let y = to_texel_space(v, self.height) - 0.5;
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let (xi, yi) = (x0 as i64, y0 as i64);
        let xa = wrap(xi, self.width);
        let xb = wrap(xi + 1, self.width);
        let ra = wrap(yi, self.height) * self.width;
        let rb = wrap(yi + 1, self.height) * self.width;
        let (t00, t10) = (self.texels[ra + xa], self.texels[ra + xb]);
        let (t01, t11) = (self.texels[rb + xa], self.texels[rb + xb]);
        let mut out = [0.0; 4];
        for c in 0..4 {
            let top = t00[c] + (t10[c] - t00[c]) * fx;
            let bottom = t01[c] + (t11[c] - t01[c]) * fx;
            out[c] = top + (bottom - top) * fy;
        }
        out
    }

    /// Bilinear height alone (channel 3).
    #[inline]
    pub fn bilinear_height(&self, u: f32, v: f32) -> f32 {
        let x = to_texel_space(u, self.width) - 0.5;
        let y = to_texel_space(v, self.height) - 0.5;
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let (xi, yi) = (x0 as i64, y0 as i64);
        let xa = wrap(xi, self.width);
        let xb = wrap(xi + 1, self.width);
        let ra = wrap(yi, self.height) * self.width;
        let rb = wrap(yi + 1, self.height) * self.width;
        let h00 = self.texels[ra + xa][3];
        let h10 = self.texels[ra + xb][3];
        let h01 = self.texels[rb + xa][3];
        let h11 = self.texels[rb + xb][3];
        let top = h00 + (h10 - h00) * fx;
        let bottom = h01 + (h11 - h01) * fx;
        top + (bottom - top) * fy
    }

    /// ∂F/∂u and ∂F/∂v per unit of texture coordinate, exactly as the
    /// documented software renderer computes them: the texel under (u, v),
    /// its two neighbours clamped at the border (not wrapped), and
    /// (next − previous) / 2 · size.
    pub fn height_gradient_texel(&self, u: f32, v: f32) -> (f32, f32) {
        let (w, h) = (self.width, self.height);
        let x = (to_texel_space(u, w) as usize).min(w - 1);
        let y = (to_texel_space(v, h) as usize).min(h - 1);
        let at = |x: usize, y: usize| self.texels[y * w + x][3];
        let (xp, xn) = (x.saturating_sub(1), (x + 1).min(w - 1));
        let (yp, yn) = (y.saturating_sub(1), (y + 1).min(h - 1));
        let du = (at(xn, y) - at(xp, y)) * 0.5 * w as f32;
        let dv = (at(x, yn) - at(x, yp)) * 0.5 * h as f32;
        (du, dv)
    }

    /// ∂F/∂u and ∂F/∂v per unit of texture coordinate from bilinear heights
    /// one texel either side: (F(u+δ) − F(u−δ)) / 2δ with δ = one texel.
    /// Continuous in (u, v), so a magnified bump map shades smoothly.
    pub fn height_gradient_filtered(&self, u: f32, v: f32) -> (f32, f32) {
        let du = 1.0 / self.width as f32;
        let dv = 1.0 / self.height as f32;
        let fu = (self.bilinear_height(u + du, v) - self.bilinear_height(u - du, v))
            * 0.5
            * self.width as f32;
        let fv = (self.bilinear_height(u, v + dv) - self.bilinear_height(u, v - dv))
            * 0.5
            * self.height as f32;
        (fu, fv)
    }

    /// Halves the level (box filter, odd sizes handled by weighting the
    /// border texels), down to 1×1.
    pub fn build_chain(&self) -> Vec<Level> {
        let mut chain: Vec<Level> = Vec::new();
        let mut current = self;
        while current.width > 1 || current.height > 1 {
            let next = current.downsample();
            chain.push(next);
            current = chain.last().expect("just pushed");
        }
        chain
    }

    /// One level down: each output texel is the area-weighted mean of the
    /// input texels it covers, so odd sizes keep the average colour exactly.
    fn downsample(&self) -> Level {
        let (w, h) = (self.width, self.height);
        let nw = (w / 2).max(1);
        let nh = (h / 2).max(1);
        let sx = w as f32 / nw as f32;
        let sy = h as f32 / nh as f32;
        let mut texels = Vec::with_capacity(nw * nh);
        for oy in 0..nh {
            let (y0, y1) = (oy as f32 * sy, (oy + 1) as f32 * sy);
            for ox in 0..nw {
                let (x0, x1) = (ox as f32 * sx, (ox + 1) as f32 * sx);
                let mut acc = [0.0f32; 4];
                let mut total = 0.0;
                for iy in y0.floor() as usize..(y1.ceil() as usize).min(h) {
                    let wy = (y1.min(iy as f32 + 1.0) - y0.max(iy as f32)).max(0.0);
                    for ix in x0.floor() as usize..(x1.ceil() as usize).min(w) {
                        let wx = (x1.min(ix as f32 + 1.0) - x0.max(ix as f32)).max(0.0);
                        let weight = wx * wy;
                        let t = self.texels[iy * w + ix];
                        for c in 0..4 {
                            acc[c] += t[c] * weight;
                        }
                        total += weight;
                    }
                }
                texels.push(acc.map(|a| a / total));
            }
        }
        Level {
            width: nw,
            height: nh,
            texels,
        }
    }
}
