//! Diffuse light from an environment as an irradiance map
//! (`--ibl-diffuse integrated`, docs/shading.md, "Image-based light"): an
//! octahedral map (`prefilter`'s conventions) whose every texel holds the
//! cosine-weighted integral of the radiance over the hemisphere around its
//! centre's direction N, divided by π:
//!
//! ```text
//! E(N)/π = (1/π)·Σ L(ω)·max(0, N·ω)·dω
//! ```
//!
//! over every texel ω of the source (at most 512 × 256) with its solid
//! angle sin θ·Δθ·Δφ (`Source::row_solid_angles`): the quantity `sh`
//! approximates with nine coefficients, here summed exactly, so a uniform
//! radiance L gives L. The kernel reads the map bilinearly, across its
//! edges (`OctMap::read_seamless`).
//!
//! The sum is the direct one, made in O(rows) per texel instead of
//! O(texels): along a row (θ fixed) N·ω = N_y·cos θ + sin θ·(N_x·sin φ −
//! N_z·cos φ) is positive on one arc of φ around N's own azimuth, of
//! half-width acos(−N_y·cos θ / (ρ·sin θ)), ρ = |(N_x, N_z)|, so the row's
//! share is N_y·cos θ·ΣL + sin θ·(N_x·ΣL·sin φ − N_z·ΣL·cos φ) over the
//! columns whose centres lie on that arc, each Σ read from prefix sums.

use std::f64::consts::PI;

use glam::{DVec3, Vec3};

use super::prefilter::OctMap;
use super::source::Source;

/// Side of the map: 64² texels, about 3° apart. The octahedral
/// parameterisation bends along the equator and the axes of the map, so a
/// bilinear read errs to the first order in the texel's size near those
/// lines; at 64² the read stays within 0.005 of the exact integral on a
/// sky lit above only (radiance 0 or 1, the steepest irradiance such an
/// environment has) and the studio, against 0.01 at 32² (measured in the
/// tests). The build costs SIZE² × the source's rows.
pub const SIZE: usize = 64;

/// The irradiance map of `source`: `SIZE`² texels of E(N)/π.
pub fn integrate(source: &Source) -> OctMap {
    integrate_at(source, SIZE)
}

/// The irradiance map of `source` at `size`² texels.
pub fn integrate_at(source: &Source, size: usize) -> OctMap {
    let rows = Rows::of(source);
    OctMap::from_fn(size, |n| rows.integral(n))
}

/// Each row of the source: its polar angle's cosine and sine, its texels'
/// solid angle, and the prefix sums along it of L, L·cos φ and L·sin φ
/// (entry c sums the columns before c).
struct Rows {
    width: usize,
    rows: Vec<Row>,
}

struct Row {
    cos: f64,
    sin: f64,
    d_omega: f64,
    sums: Vec<[DVec3; 3]>,
}

impl Rows {
    fn of(source: &Source) -> Rows {
        let (w, h) = (source.width.max(1), source.height.max(1));
        let d_phi = 2.0 * PI / w as f64;
        let rows = source
            .row_solid_angles()
            .into_iter()
            .enumerate()
            .map(|(y, d_omega)| {
                let theta = (y as f64 + 0.5) / h as f64 * PI;
                let mut sums = Vec::with_capacity(w + 1);
                let mut s = [DVec3::ZERO; 3];
                sums.push(s);
                for x in 0..w {
                    let phi = (x as f64 + 0.5) * d_phi - PI;
                    let l = source.texels[y * w + x].as_dvec3();
                    s[0] += l;
                    s[1] += l * phi.cos();
                    s[2] += l * phi.sin();
                    sums.push(s);
                }
                Row {
                    cos: theta.cos(),
                    sin: theta.sin(),
                    d_omega: d_omega as f64,
                    sums,
                }
            })
            .collect();
        Rows { width: w, rows }
    }

    /// E(N)/π at unit `n`.
    fn integral(&self, n: Vec3) -> Vec3 {
        let n = n.as_dvec3();
        let w = self.width as f64;
        let rho = n.x.hypot(n.z);
        // N's azimuth: N_x·sin φ − N_z·cos φ = ρ·cos(φ − ψ).
        let psi = n.x.atan2(-n.z);
        let mut total = DVec3::ZERO;
        for row in &self.rows {
            let (k1, k2) = (n.y * row.cos, rho * row.sin);
            // Columns whose centre has N·ω > 0: all, none, or an arc.
            let [l, lc, ls] = if k1 >= k2 {
                row.span(0, self.width)
            } else if k1 <= -k2 {
                continue;
            } else {
                let half = (-k1 / k2).acos();
                // Centre φ_c = (c + ½)·Δφ − π inside (ψ − half, ψ + half).
                let to_column = |phi: f64| (phi + PI) * w / (2.0 * PI) - 0.5;
                let first = to_column(psi - half).ceil() as i64;
                let last = to_column(psi + half).floor() as i64;
                if last < first {
                    continue;
                }
                let count = ((last - first + 1) as usize).min(self.width);
                row.span(first.rem_euclid(self.width as i64) as usize, count)
            };
            total += (l * k1 + (ls * n.x - lc * n.z) * row.sin) * row.d_omega;
        }
        (total / PI).max(DVec3::ZERO).as_vec3()
    }
}

impl Row {
    /// The sums of L, L·cos φ and L·sin φ over `count` columns from
    /// `first`, wrapping past the last column.
    fn span(&self, first: usize, count: usize) -> [DVec3; 3] {
        let w = self.sums.len() - 1;
        let end = first + count;
        std::array::from_fn(|k| {
            if end <= w {
                self.sums[end][k] - self.sums[first][k]
            } else {
                self.sums[w][k] - self.sums[first][k] + self.sums[end - w][k]
            }
        })
    }
}
