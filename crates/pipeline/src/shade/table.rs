//! A square table over N·V (columns) and roughness (rows), both 0..=1 with
//! entry i at i/(size − 1), so that 0 and 1 are exact entries; N values per
//! entry, read bilinearly: the split sum's (A, B) (`split_sum`) and the
//! sheen's lobe (`sheen`).

use wide::f32x8;

use super::lanes::Lanes;

pub struct Table<const N: usize> {
    size: usize,
    /// Roughness rows, N·V columns.
    entries: Vec<[f32; N]>,
}

impl<const N: usize> Table<N> {
    /// A `size`² table (size ≥ 2) whose entry at roughness row `r` and N·V
    /// column `c` is `f(r, c)`.
    pub fn from_fn(size: usize, mut f: impl FnMut(usize, usize) -> [f32; N]) -> Table<N> {
        assert!(size >= 2, "a table needs two entries per side");
        let mut entries = Vec::with_capacity(size * size);
        for r in 0..size {
            for c in 0..size {
                entries.push(f(r, c));
            }
        }
        Table { size, entries }
    }

    /// The values at `nv` and `roughness` (each clamped to 0..=1, a NaN to
    /// 0), bilinear between entries: per lane, t = a + (b − a)·f along N·V,
    /// then along roughness.
    #[inline(always)]
    pub fn read<L: Lanes>(&self, nv: L, roughness: L) -> [L; N] {
        let n = self.size;
        let last = f32x8::splat((n - 1) as f32);
        let x = (nv.to_x8() * last).max(f32x8::ZERO).min(last);
        let y = (roughness.to_x8() * last).max(f32x8::ZERO).min(last);
        let (xi, yi) = (x.trunc_int(), y.trunc_int());
        let (fx, fy) = (x - f32x8::from_i32x8(xi), y - f32x8::from_i32x8(yi));
        let (xi, yi) = (xi.to_array(), yi.to_array());
        // The four entries around each lane, value by value.
        let mut corners = [[[0.0f32; 8]; N]; 4];
        for lane in 0..L::WIDTH {
            let (x0, y0) = (xi[lane] as usize, yi[lane] as usize);
            let (x1, y1) = ((x0 + 1).min(n - 1), (y0 + 1).min(n - 1));
            let around = [(y0, x0), (y0, x1), (y1, x0), (y1, x1)];
            for (corner, (r, c)) in around.into_iter().enumerate() {
                let entry = self.entries[r * n + c];
                for k in 0..N {
                    corners[corner][k][lane] = entry[k];
                }
            }
        }
        std::array::from_fn(|k| {
            let at = |corner: usize| f32x8::from(corners[corner][k]);
            let (a, b, c, d) = (at(0), at(1), at(2), at(3));
            let top = a + (b - a) * fx;
            let bottom = c + (d - c) * fx;
            L::from_x8(top + (bottom - top) * fy)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Entry (r, c) holds (c, 10·r): the read is exact at entries,
    /// linear between them, clamped outside 0..=1 (a NaN to 0).
    #[test]
    fn reads_are_exact_at_entries_and_linear_between() {
        let table = Table::from_fn(5, |r, c| [c as f32, 10.0 * r as f32]);
        assert_eq!(table.read(0.5f32, 0.25f32), [2.0, 10.0]);
        assert_eq!(table.read(0.125f32, 0.375f32), [0.5, 15.0]);
        assert_eq!(table.read(-3.0f32, 7.0f32), [0.0, 40.0]);
        assert_eq!(table.read(f32::NAN, 1.0f32), [0.0, 40.0]);
    }

    /// Eight lanes give each lane the bits of a one-lane read.
    #[test]
    fn eight_lanes_read_as_eight_points() {
        let table = Table::from_fn(7, |r, c| [((r * 7 + c) as f32).sin(), (c as f32).sqrt()]);
        let nv = [0.0, 0.13, 0.5, 0.77, 1.0, 0.999, 0.31, 0.62];
        let roughness = [1.0, 0.2, 0.45, 0.0, 0.66, 0.05, 0.93, 0.5];
        let got = table.read(f32x8::from(nv), f32x8::from(roughness));
        for i in 0..8 {
            let want = table.read(nv[i], roughness[i]);
            let lane = [got[0].as_array()[i], got[1].as_array()[i]];
            assert_eq!(lane.map(f32::to_bits), want.map(f32::to_bits), "lane {i}");
        }
    }
}
