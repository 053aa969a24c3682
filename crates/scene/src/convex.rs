//! Whether a closed triangle surface bounds a convex body, found when a
//! model is built, in time linear in its edges. A convex mesh drawn alone
//! needs no depth buffer and casts no shadow on itself, so no shadow map.
//!
//! The surface is given by its triangles over welded points (one id per
//! distinct position, counter-clockwise seen from outside). It is judged
//! convex when all of these hold:
//!
//! 1. every directed edge `a → b` occurs once and `b → a` once (a closed,
//!    consistently wound surface);
//! 2. every triangle faces away from `c`, the mean of the corners (the
//!    triple product of its corners taken from `c` is positive);
//! 3. the solid angles of the triangles seen from `c` sum to 4π (within
//!    π; their exact sum is 4π times an integer);
//! 4. at every edge the far corner of the neighbouring triangle lies
//!    behind (or within `CREASE` × the radius in front of) the triangle's
//!    plane: every edge folds outwards.
//!
//! Why that is convexity: projecting the surface from `c` onto the unit
//! sphere maps each triangle, by 2., one to one and keeping orientation
//! onto a spherical triangle; the sum in 3. is 4π times the number of
//! times the projection covers the sphere, so by 3. it covers it once:
//! the surface is one embedded sphere, star-shaped about `c` (two pieces,
//! or a surface winding twice about a vertex — a bipyramid over a
//! pentagram, whose every edge folds outwards — would cover it twice). It
//! bounds a solid that is locally convex along every edge by 4., and at
//! every vertex, whose cone's cross-section is a simple spherical polygon
//! turning the same way at every corner; a connected closed set that is
//! locally convex everywhere is convex (Tietze's theorem). Conversely a
//! closed convex surface with a centre inside passes 1.–4. With the
//! tolerance, a surface passes when it is convex up to creases shallower
//! than `CREASE` of its radius (a finely tessellated sphere whose
//! coordinates were rounded to six decimals), far below a pixel.

use glam::DVec3;
use rayon::prelude::*;

/// How far, relative to the surface's radius about its centre, a
/// neighbouring corner may lie in front of a triangle's plane.
pub const CREASE: f64 = 1e-5;

/// Triangles summed per block: sums are made per block, then the blocks in
/// order, so the result does not depend on the thread count.
const BLOCK: usize = 4096;

/// The scratch memory of [`is_convex`] for `triangles` triangles over
/// `points` point ids, in bytes.
pub fn scratch_bytes(triangles: usize, points: usize) -> u64 {
    let edges = 3 * triangles as u64;
    // The bucket starts and their fill counters, and (target, edge) per edge.
    8 * (points as u64 + 1) + edges * 8
}

/// Whether the closed surface of `triangles` triangles, whose corners
/// `corners(t)` are point ids below `points` at positions `place(t)`,
/// bounds a convex body (see the module's comment).
pub fn is_convex(
    triangles: usize,
    points: usize,
    corners: &(dyn Fn(usize) -> [u32; 3] + Sync),
    place: &(dyn Fn(usize) -> [glam::Vec3; 3] + Sync),
) -> bool {
    if triangles < 4 || points < 4 {
        return false;
    }
    let surface = Surface {
        triangles,
        points,
        corners,
        place,
    };
    if !surface.ids_in_range() {
        return false;
    }
    let Some(centre) = surface.centre() else {
        return false;
    };
    let Some(radius) = surface.radius(centre) else {
        return false;
    };
    // 2. and 3.: every triangle faces away from the centre, and together
    // they cover the sphere of directions once.
    if !surface.faces_away_from(centre) {
        return false;
    }
    let solid = surface.solid_angle_sum(centre);
    if (solid - 4.0 * std::f64::consts::PI).abs() >= std::f64::consts::PI {
        return false;
    }
    // 1. and 4. over the edges, bucketed by their source point.
    let buckets = surface.edges_by_source();
    let tolerance = CREASE * radius;
    (0..3 * triangles)
        .into_par_iter()
        .all(|e| surface.edge_closes_and_folds_outwards(&buckets, e, tolerance))
}

/// The surface [`is_convex`] is given. Edge `e` is the one from corner
/// `e % 3` to the next of triangle `e / 3`.
struct Surface<'a> {
    triangles: usize,
    points: usize,
    corners: &'a (dyn Fn(usize) -> [u32; 3] + Sync),
    place: &'a (dyn Fn(usize) -> [glam::Vec3; 3] + Sync),
}

impl Surface<'_> {
    /// Triangle `t`'s corners' positions, in double precision.
    #[inline]
    fn corner_points(&self, t: usize) -> [DVec3; 3] {
        (self.place)(t).map(|p| p.as_dvec3())
    }

    /// Edge `e`'s source and target point ids.
    #[inline]
    fn edge(&self, e: usize) -> (u32, u32) {
        let c = (self.corners)(e / 3);
        (c[e % 3], c[(e + 1) % 3])
    }

    /// Whether every corner's id is below the point count.
    fn ids_in_range(&self) -> bool {
        (0..self.triangles).into_par_iter().all(|t| {
            (self.corners)(t)
                .iter()
                .all(|&i| (i as usize) < self.points)
        })
    }

    /// The centre: the mean of the corners, summed in fixed blocks; none
    /// when not finite.
    fn centre(&self) -> Option<DVec3> {
        let sum = ordered_sum(self.triangles, &|t| {
            let [a, b, d] = self.corner_points(t);
            a + b + d
        });
        let centre = sum / (3 * self.triangles) as f64;
        centre.is_finite().then_some(centre)
    }

    /// The greatest distance of a corner from `centre`; none when it is
    /// zero or not finite.
    fn radius(&self, centre: DVec3) -> Option<f64> {
        let radius = (0..self.triangles)
            .into_par_iter()
            .map(|t| {
                self.corner_points(t)
                    .iter()
                    .map(|p| p.distance(centre))
                    .fold(0.0, f64::max)
            })
            .reduce(|| 0.0, f64::max);
        (radius > 0.0 && radius.is_finite()).then_some(radius)
    }

    /// Whether every triangle's triple product from `centre` is positive
    /// (2.).
    fn faces_away_from(&self, centre: DVec3) -> bool {
        (0..self.triangles).into_par_iter().all(|t| {
            let [a, b, d] = self.corner_points(t).map(|p| p - centre);
            a.dot(b.cross(d)) > 0.0
        })
    }

    /// The triangles' solid angles seen from `centre`, summed in fixed
    /// blocks (for 3.).
    fn solid_angle_sum(&self, centre: DVec3) -> f64 {
        let solid = ordered_sum(self.triangles, &|t| {
            let [a, b, d] = self.corner_points(t).map(|p| p - centre);
            DVec3::splat(solid_angle(a, b, d))
        });
        solid.x
    }

    /// The edges bucketed by their source point (a counting sort, linear
    /// in the edges) and, in each bucket, ordered by target.
    fn edges_by_source(&self) -> EdgeBuckets {
        let start = self.bucket_starts();
        let mut sorted = self.edges_in_buckets(&start);
        sort_buckets(&start, &mut sorted, self.points);
        EdgeBuckets { start, sorted }
    }

    /// Where each source point's bucket starts (and, last, the edge count).
    fn bucket_starts(&self) -> Vec<u32> {
        let mut start = vec![0u32; self.points + 1];
        for e in 0..3 * self.triangles {
            start[self.edge(e).0 as usize + 1] += 1;
        }
        for i in 0..self.points {
            start[i + 1] += start[i];
        }
        start
    }

    /// Per source, (target, edge) in order of edge: the buckets unsorted.
    fn edges_in_buckets(&self, start: &[u32]) -> Vec<(u32, u32)> {
        let edges = 3 * self.triangles;
        let mut sorted = vec![(0u32, 0u32); edges];
        let mut fill = start.to_vec();
        for e in 0..edges {
            let (source, target) = self.edge(e);
            sorted[fill[source as usize] as usize] = (target, e as u32);
            fill[source as usize] += 1;
        }
        sorted
    }

    /// Whether edge `e` passes 1. and 4.: it occurs once, its reverse
    /// once, and the reverse's triangle's far corner lies behind (or within
    /// `tolerance` in front of) the plane of `e`'s triangle.
    #[inline]
    fn edge_closes_and_folds_outwards(
        &self,
        buckets: &EdgeBuckets,
        e: usize,
        tolerance: f64,
    ) -> bool {
        let (a, b) = self.edge(e);
        let own = buckets.bucket(a);
        let at_own = own.partition_point(|&(t, _)| t < b);
        // 1. this edge once, its reverse once.
        if own.get(at_own + 1).is_some_and(|&(t, _)| t == b) {
            return false;
        }
        let back = buckets.bucket(b);
        let at_back = back.partition_point(|&(t, _)| t < a);
        let Some(&(_, reverse)) = back.get(at_back).filter(|&&(t, _)| t == a) else {
            return false;
        };
        if back.get(at_back + 1).is_some_and(|&(t, _)| t == a) {
            return false;
        }
        // 4. the neighbour's far corner behind this triangle's plane.
        let [p, q, r] = self.corner_points(e / 3);
        let normal = (q - p).cross(r - p);
        let far = self.corner_points(reverse as usize / 3)[(reverse as usize + 2) % 3];
        normal.dot(far - p) <= tolerance * normal.length()
    }
}

/// The edges as (target, edge), per source point in order of target, then
/// of edge.
struct EdgeBuckets {
    /// Where each source's bucket starts in `sorted`, and the edge count.
    start: Vec<u32>,
    sorted: Vec<(u32, u32)>,
}

impl EdgeBuckets {
    /// The edges from `source`.
    #[inline]
    fn bucket(&self, source: u32) -> &[(u32, u32)] {
        let s = source as usize;
        &self.sorted[self.start[s] as usize..self.start[s + 1] as usize]
    }
}

/// Sorts each of the buckets of `points` sources that `start` marks in
/// `sorted`. The buckets are short (a point's edges): sorted in place, in
/// blocks of points on the threads.
fn sort_buckets(start: &[u32], sorted: &mut [(u32, u32)], points: usize) {
    let mut blocks = Vec::with_capacity(points.div_ceil(BLOCK));
    let mut rest = sorted;
    for first in (0..points).step_by(BLOCK) {
        let last = (first + BLOCK).min(points);
        let (block, tail) = rest.split_at_mut((start[last] - start[first]) as usize);
        blocks.push((first, block));
        rest = tail;
    }
    blocks.into_par_iter().for_each(|(first, block)| {
        let base = start[first] as usize;
        for s in first..(first + BLOCK).min(points) {
            block[start[s] as usize - base..start[s + 1] as usize - base].sort_unstable();
        }
    });
}

/// The solid angle of the triangle `a b d` seen from the origin, positive
/// when it is counter-clockwise seen from there (Van Oosterom and
/// Strackee's formula).
fn solid_angle(a: DVec3, b: DVec3, d: DVec3) -> f64 {
    let (la, lb, ld) = (a.length(), b.length(), d.length());
    let det = a.dot(b.cross(d));
    let div = la * lb * ld + a.dot(b) * ld + a.dot(d) * lb + b.dot(d) * la;
    2.0 * det.atan2(div)
}

/// `f(0) + … + f(n − 1)` summed per block of [`BLOCK`] and then the blocks
/// in order: the same bits on any number of threads.
fn ordered_sum(n: usize, f: &(dyn Fn(usize) -> DVec3 + Sync)) -> DVec3 {
    let blocks: Vec<DVec3> = (0..n.div_ceil(BLOCK))
        .into_par_iter()
        .map(|b| (b * BLOCK..n.min((b + 1) * BLOCK)).map(f).sum())
        .collect();
    blocks.into_iter().sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;
    use proptest::prelude::*;

    fn convex(points: &[Vec3], triangles: &[[u32; 3]]) -> bool {
        is_convex(triangles.len(), points.len(), &|t| triangles[t], &|t| {
            triangles[t].map(|i| points[i as usize])
        })
    }

    /// A sphere of `rings` × `segments` cells with the radius `radius(i)`
    /// at point `i`: two poles, then the rings; counter-clockwise seen from
    /// outside.
    fn sphere(
        rings: usize,
        segments: usize,
        radius: &dyn Fn(usize) -> f32,
    ) -> (Vec<Vec3>, Vec<[u32; 3]>) {
        let mut points = vec![Vec3::Y * radius(0), -Vec3::Y * radius(1)];
        for i in 1..rings {
            let theta = std::f32::consts::PI * i as f32 / rings as f32;
            for j in 0..segments {
                let phi = std::f32::consts::TAU * j as f32 / segments as f32;
                let dir = Vec3::new(
                    theta.sin() * phi.cos(),
                    theta.cos(),
                    -theta.sin() * phi.sin(),
                );
                points.push(dir * radius(points.len()));
            }
        }
        let at = |i: usize, j: usize| (2 + (i - 1) * segments + j % segments) as u32;
        let mut triangles = Vec::new();
        for j in 0..segments {
            triangles.push([0, at(1, j), at(1, j + 1)]);
            triangles.push([1, at(rings - 1, j + 1), at(rings - 1, j)]);
        }
        for i in 1..rings - 1 {
            for j in 0..segments {
                let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
                triangles.push([a, b, c]);
                triangles.push([a, c, d]);
            }
        }
        (points, triangles)
    }

    /// The brute-force answer: every point on or behind every triangle's
    /// plane (by `margin` × the radius), `None` when some point is within
    /// the margin of the tolerance's edge (too close to call).
    fn brute_force(points: &[Vec3], triangles: &[[u32; 3]]) -> Option<bool> {
        let p = |i: u32| points[i as usize].as_dvec3();
        let centre = points.iter().map(|p| p.as_dvec3()).sum::<DVec3>() / points.len() as f64;
        let radius = points
            .iter()
            .map(|q| q.as_dvec3().distance(centre))
            .fold(0.0, f64::max);
        let mut worst = f64::NEG_INFINITY;
        for t in triangles {
            let normal = (p(t[1]) - p(t[0])).cross(p(t[2]) - p(t[0])).normalize();
            for q in points {
                worst = worst.max(normal.dot(q.as_dvec3() - p(t[0])) / radius);
            }
        }
        // Any fold between the tolerance and a hundred times it is not called.
        if worst > CREASE && worst < 100.0 * CREASE {
            return None;
        }
        Some(worst <= CREASE)
    }

    #[test]
    fn a_sphere_and_a_cube_are_convex() {
        let (points, triangles) = sphere(8, 12, &|_| 1.0);
        assert!(convex(&points, &triangles));
        // The cube with each face cut in two along a diagonal: coplanar
        // neighbours are convex too.
        let points: Vec<Vec3> = (0..8)
            .map(|i| Vec3::new((i & 1) as f32, (i >> 1 & 1) as f32, (i >> 2) as f32) * 2.0 - 1.0)
            .collect();
        let quads = [
            [0, 2, 3, 1],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 4, 6, 2],
            [1, 3, 7, 5],
        ];
        let triangles: Vec<[u32; 3]> = quads
            .iter()
            .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
            .collect();
        assert_eq!(brute_force(&points, &triangles), Some(true));
        assert!(convex(&points, &triangles));
        // Inside out: every triangle faces the centre.
        let flipped: Vec<[u32; 3]> = triangles.iter().map(|t| [t[0], t[2], t[1]]).collect();
        assert!(!convex(&points, &flipped));
        // One triangle missing: not closed.
        assert!(!convex(&points, &triangles[1..]));
        // Twice over: every edge twice.
        let twice = [triangles.clone(), triangles].concat();
        assert!(!convex(&points, &twice));
    }

    /// A bipyramid over a pentagram: closed, every triangle faces away from
    /// the centre and every edge folds outwards, but it winds twice about
    /// its apexes (solid angles summing to 8π) and is not convex.
    #[test]
    fn a_pentagram_bipyramid_is_not_convex() {
        let mut points = vec![Vec3::Y, -Vec3::Y];
        for k in 0..5 {
            let phi = std::f32::consts::TAU * k as f32 / 5.0;
            points.push(Vec3::new(phi.cos(), 0.0, -phi.sin()) * 0.3);
        }
        // Around the star: every second point of the pentagon.
        let star = |k: usize| (2 + (2 * k) % 5) as u32;
        let mut triangles = Vec::new();
        for k in 0..5 {
            triangles.push([0, star(k), star(k + 1)]);
            triangles.push([1, star(k + 1), star(k)]);
        }
        assert_eq!(brute_force(&points, &triangles), Some(false));
        let centre = DVec3::ZERO;
        let total: f64 = triangles
            .iter()
            .map(|t| {
                let [a, b, d] = t.map(|i| points[i as usize].as_dvec3() - centre);
                assert!(a.dot(b.cross(d)) > 0.0, "faces away from the centre");
                solid_angle(a, b, d)
            })
            .sum();
        assert!((total - 8.0 * std::f64::consts::PI).abs() < 1e-9, "{total}");
        assert!(!convex(&points, &triangles));
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(300))]
        /// Spheres with a radius per point (star-shaped: round, with one
        /// point moved in or out, or dented all over) are judged as the
        /// brute-force test judges them.
        #[test]
        fn agrees_with_the_brute_force_test(
            rings in 2usize..7,
            segments in 3usize..9,
            mode in 0u8..3,
            moved in 0usize..64,
            dents in proptest::collection::vec(-0.3f32..0.3, 64),
            dented in proptest::collection::vec(any::<bool>(), 64),
            scale in 0.01f32..100.0,
        ) {
            let radius = |i: usize| {
                let dent = match mode {
                    0 => 0.0,
                    1 if i == moved % (2 + (rings - 1) * segments) => dents[0],
                    1 => 0.0,
                    _ if dented[i % 64] => dents[i % 64].abs(),
                    _ => 0.0,
                };
                scale * (1.0 - dent)
            };
            let (points, triangles) = sphere(rings, segments, &radius);
            if let Some(expected) = brute_force(&points, &triangles) {
                prop_assert_eq!(convex(&points, &triangles), expected);
            }
        }
    }
}
