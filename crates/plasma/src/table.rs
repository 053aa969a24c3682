//! The article's lookup table: Z²·255 for integer slopes in −127..127,
//! built exactly as its Pascal code does (truncated, negatives set to 0).

/// 255 × 255 bytes indexed by (dY, dX).
#[derive(Clone, Debug)]
pub struct ZTable {
    values: Box<[u8]>,
}

const SIDE: usize = 255;

impl ZTable {
    pub fn new() -> Self {
        let mut values = vec![0u8; SIDE * SIDE].into_boxed_slice();
        for y in -127i32..=127 {
            for x in -127i32..=127 {
                let (fx, fy) = (x as f64 / 128.0, y as f64 / 128.0);
                let i = ((1.0 - fx * fx - fy * fy) * 255.0).trunc();
                values[(y + 127) as usize * SIDE + (x + 127) as usize] = i.max(0.0) as u8;
            }
        }
        ZTable { values }
    }

    /// Z²·255 at slope (dx, dy); both are clamped to −127..127 first.
    pub fn get(&self, dx: i32, dy: i32) -> u8 {
        let (x, y) = (dx.clamp(-127, 127) + 127, dy.clamp(-127, 127) + 127);
        self.values[y as usize * SIDE + x as usize]
    }
}

impl Default for ZTable {
    fn default() -> Self {
        Self::new()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_the_pascal_table() {
        let t = ZTable::new();
        assert_eq!(t.get(0, 0), 255);
        // trunc((1 − (64/128)²)·255) = trunc(191.25)
        assert_eq!(t.get(64, 0), 191);
        assert_eq!(t.get(0, -64), 191);
        assert_eq!(t.get(127, 127), 0);
        assert_eq!(t.get(1000, 0), t.get(127, 0));
        assert_eq!(t.get(91, 90), 0);
    }
}
