//! The Pareto front of (time, quality): the configurations nothing else beats
//! on both counts at once.

/// Indices (ascending) of the points that no other point dominates, where
/// point `(time, quality)` dominates another when it is no slower and no worse
/// and strictly better in one of the two. Equal points are all kept. NaN
/// values never dominate and are never on the front.
pub fn front(points: &[(f64, f64)]) -> Vec<usize> {
    let valid = |p: &(f64, f64)| !p.0.is_nan() && !p.1.is_nan();
    (0..points.len())
        .filter(|&i| {
            let a = points[i];
            valid(&a)
                && !points
                    .iter()
                    .any(|b| valid(b) && b.0 <= a.0 && b.1 >= a.1 && (b.0 < a.0 || b.1 > a.1))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dominated_points_are_dropped() {
        // (time, PSNR)
        let points = [
            (1.0, 30.0),          // front: fastest
            (2.0, 29.0),          // slower and worse than 0
            (3.0, 40.0),          // front
            (3.0, 35.0),          // same time as 2, worse
            (9.0, f64::INFINITY), // front: exact
            (2.0, 30.0),          // slower than 0, same quality
            (f64::NAN, 50.0),
        ];
        assert_eq!(front(&points), vec![0, 2, 4]);
    }

    #[test]
    fn ties_stay_together() {
        assert_eq!(front(&[(1.0, 2.0), (1.0, 2.0)]), vec![0, 1]);
        assert!(front(&[]).is_empty());
    }
}
