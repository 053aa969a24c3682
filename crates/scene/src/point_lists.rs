//! The corners at each point, listed in corner order: what finds a
//! model's vertices and its computed normals (only corners at one point
//! can share either).

/// Corners grouped by point: those at point `p` are [`PointLists::at`]`(p)`,
/// in corner order.
pub(crate) struct PointLists {
    start: Vec<u32>,
    around: Vec<u32>,
}

impl PointLists {
    /// What [`PointLists::new`] allocates for `corners` corners at
    /// `points` points: a `u32` for each corner and two for each point.
    pub fn bytes(corners: u64, points: u64) -> u64 {
        points
            .saturating_add(1)
            .saturating_mul(2)
            .saturating_add(corners)
            .saturating_mul(std::mem::size_of::<u32>() as u64)
    }

    /// The lists of `corners` corners at `points` points, corner `i` being
    /// at `point(i)` (below `points`): a counting sort, which keeps each
    /// point's corners in corner order. It runs on one thread: cut into
    /// pieces counted and placed in parallel, it took longer (each piece's
    /// counts and the shared list are fresh memory, and the work is all
    /// memory traffic).
    pub fn new(corners: usize, points: usize, point: impl Fn(usize) -> usize) -> PointLists {
        let mut start = vec![0u32; points + 1];
        for i in 0..corners {
            start[point(i) + 1] += 1;
        }
        for p in 0..points {
            start[p + 1] += start[p];
        }
        let mut next = start.clone();
        let mut around = vec![0u32; corners];
        for i in 0..corners {
            let slot = &mut next[point(i)];
            around[*slot as usize] = i as u32;
            *slot += 1;
        }
        PointLists { start, around }
    }

    /// The corners at point `p`, in corner order.
    pub fn at(&self, p: usize) -> &[u32] {
        &self.around[self.start[p] as usize..self.start[p + 1] as usize]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_point_lists_its_corners_in_corner_order() {
        let mut seed = 99u64;
        let points = 1000;
        let of: Vec<usize> = (0..20_000)
            .map(|_| {
                seed = seed
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                // Some points crowded, some never used.
                let r = (seed >> 33) as usize;
                if r.is_multiple_of(7) {
                    3
                } else {
                    r % (points - 10)
                }
            })
            .collect();
        let mut expected = vec![Vec::new(); points];
        for (i, &p) in of.iter().enumerate() {
            expected[p].push(i as u32);
        }
        let lists = PointLists::new(of.len(), points, |i| of[i]);
        for (p, e) in expected.iter().enumerate() {
            assert_eq!(lists.at(p), &e[..], "point {p}");
        }
        // No corners, and no points.
        let empty = PointLists::new(0, 3, |_| 0);
        assert!((0..3).all(|p| empty.at(p).is_empty()));
        assert_eq!(PointLists::new(0, 0, |_| 0).start, vec![0]);
    }
}
