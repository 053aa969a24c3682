//! The plasma height field of the article:
//! Alt(X, Y) = |trunc((cos(X/10) + sin(Y/10) + sin(X/20) + cos(Y/20)) · 63)|,
//! one byte per pixel (0..252), in pixel units at any frame size.

/// The height field, shifted by a seed (seed 0 is the article's picture).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct HeightField {
    offset: (i64, i64),
}

impl HeightField {
    pub fn new(seed: u32) -> Self {
        if seed == 0 {
            return HeightField { offset: (0, 0) };
        }
        // Any shift shows another part of the same pattern; a hash spreads seeds.
        let mut h = seed.wrapping_mul(0x9e37_79b9);
        h ^= h >> 15;
        h = h.wrapping_mul(0x85eb_ca6b);
        h ^= h >> 13;
        HeightField {
            offset: ((h & 0xfff) as i64, ((h >> 12) & 0xfff) as i64),
        }
    }

    fn column_term(&self, x: i64) -> f64 {
        let x = (x + self.offset.0) as f64;
        (x / 10.0).cos() + (x / 20.0).sin()
    }

    fn row_term(&self, y: i64) -> f64 {
        let y = (y + self.offset.1) as f64;
        (y / 10.0).sin() + (y / 20.0).cos()
    }

    fn combine(column: f64, row: f64) -> u8 {
        // The sum is at most 4, so the value is at most 252: a byte, as in the article.
        ((column + row) * 63.0).trunc().abs() as u8
    }

    /// The height at pixel (x, y).
    pub fn at(&self, x: i64, y: i64) -> u8 {
        Self::combine(self.column_term(x), self.row_term(y))
    }

    /// All heights of a `width × height` picture, row by row. The formula
    /// separates into a column term and a row term, so only w + h sines are taken.
    pub fn sample(&self, width: usize, height: usize) -> Vec<u8> {
        let columns: Vec<f64> = (0..width as i64).map(|x| self.column_term(x)).collect();
        let mut out = Vec::with_capacity(width * height);
        for y in 0..height as i64 {
            let row = self.row_term(y);
            out.extend(columns.iter().map(|&c| Self::combine(c, row)));
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn seed_zero_is_the_article_formula() {
        let f = HeightField::new(0);
        // (cos 0 + sin 0 + sin 0 + cos 0)·63 = 126.
        assert_eq!(f.at(0, 0), 126);
        for (x, y) in [(5, 7), (100, 3), (319, 199), (37, 150)] {
            let (xf, yf) = (x as f64, y as f64);
            let want =
                ((xf / 10.0).cos() + (yf / 10.0).sin() + (xf / 20.0).sin() + (yf / 20.0).cos())
                    * 63.0;
            assert_eq!(f.at(x, y), want.trunc().abs() as u8);
        }
        let grid = f.sample(7, 3);
        assert_eq!(grid.len(), 21);
        assert_eq!(grid[2 * 7 + 5], f.at(5, 2));
    }

    #[test]
    fn seeds_shift_the_pattern() {
        let a = HeightField::new(0).sample(32, 32);
        let b = HeightField::new(7).sample(32, 32);
        assert_ne!(a, b);
        assert_eq!(HeightField::new(7), HeightField::new(7));
    }
}
