//! A square table over N·V (columns) and roughness (rows), both 0..=1 with
//! entry i at i/(size − 1), so that 0 and 1 are exact entries; N values per
//! entry, read bilinearly: the split sum's (A, B) (`split_sum`) and the
//! sheen's lobe (`sheen`).

use glam::Vec4;
use rayon::prelude::*;
use wide::f32x8;

use super::lanes::Lanes;

pub struct Table<const N: usize> {
    size: usize,
    /// Roughness rows, N·V columns; each entry's N values padded to four,
    /// so that a read blends one entry's values at once.
    entries: Vec<Vec4>,
}

impl<const N: usize> Table<N> {
    /// A `size`² table (size ≥ 2) whose entry at roughness row `r` and N·V
    /// column `c` is `f(r, c)`, the entries computed in parallel (each is an
    /// integral of its own, made once per process).
    pub fn from_fn(size: usize, f: impl Fn(usize, usize) -> [f32; N] + Sync) -> Table<N> {
        assert!(size >= 2, "a table needs two entries per side");
        assert!(N <= 4, "an entry holds at most four values");
        let entries = (0..size * size)
            .into_par_iter()
            .map(|i| {
                let values = f(i / size, i % size);
                Vec4::from_array(std::array::from_fn(|k| {
                    values.get(k).copied().unwrap_or(0.0)
                }))
            })
            .collect();
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
        let (xi, yi, fx, fy) = (xi.to_array(), yi.to_array(), fx.to_array(), fy.to_array());
        // Per lane, the four entries around it blended, all values at once:
        // t = a + (b − a)·f along N·V, then along roughness.
        let mut values = [[0.0f32; 8]; N];
        for lane in 0..L::WIDTH {
            let (x0, y0) = (xi[lane] as usize, yi[lane] as usize);
            let (x1, y1) = ((x0 + 1).min(n - 1), (y0 + 1).min(n - 1));
            let at = |r: usize, c: usize| self.entries[r * n + c];
            let (a, b, c, d) = (at(y0, x0), at(y0, x1), at(y1, x0), at(y1, x1));
            let top = a + (b - a) * fx[lane];
            let bottom = c + (d - c) * fx[lane];
            let t = top + (bottom - top) * fy[lane];
            for (k, v) in values.iter_mut().enumerate() {
                v[lane] = t[k];
            }
        }
        values.map(|v| L::from_x8(f32x8::from(v)))
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
