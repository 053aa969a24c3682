//! glTF's sheen layer (`KHR_materials_sheen`, docs/shading.md, "Sheen"):
//! the Charlie distribution of Conty and Kulla (2017),
//!
//! ```text
//! D = (2 + 1/α)·sin(θh)^(1/α) / (2π),   α = sheenRoughness²,
//! ```
//!
//! with Neubelt and Pettineo's visibility V = 1/(4(N·L + N·V − N·L·N·V))
//! (the extension's cheaper choice), and the lobe's directional albedo
//! E(N·V, sheenRoughness) = ∫ D·V·N·L dω(L), a 32 × 32 table integrated
//! once at first use and read bilinearly, held at most 1 (the layering's
//! bound; this visibility lets the lobe itself pass 1 at grazing angles
//! below a sheen roughness of about 0.3, as the extension warns).
//! Written over the lane type like the rest of the kernel: the power with
//! an exponent per lane is `f32::powf` lane by lane.

use std::f64::consts::PI;
use std::sync::OnceLock;

use super::brdf::MIN_ROUGHNESS;
use super::lanes::Lanes;
use super::table;

/// Entries per side of the albedo table (N·V and roughness from 0 to 1,
/// endpoints included).
const SIZE: usize = 32;

/// The smallest sheen roughness shaded (as the base's: at 0 the fibres'
/// distribution is a line at grazing angles, D infinite there).
pub const MIN_SHEEN_ROUGHNESS: f32 = MIN_ROUGHNESS;

/// The distribution at sin²θh = `sin2h` for the lanes' α = `alpha` (≥
/// [`MIN_SHEEN_ROUGHNESS`]²): (2 + 1/α)·(sin²θh)^(1/(2α)) / (2π); 0 where
/// sin²θh ≤ 0 (H on the normal).
#[inline(always)]
pub fn charlie<L: Lanes>(alpha: L, sin2h: L) -> L {
    let inv = L::ONE / alpha;
    (L::splat(2.0) + inv)
        * sin2h.pow_lanes(L::splat(0.5) * inv)
        * L::splat(1.0 / (2.0 * std::f32::consts::PI))
}

/// Neubelt and Pettineo's visibility 1/(4(N·L + N·V − N·L·N·V)), for N·L
/// and N·V in 0..=1 not both 0.
#[inline(always)]
pub fn neubelt<L: Lanes>(nl: L, nv: L) -> L {
    L::ONE / (L::splat(4.0) * (nl + nv - nl * nv))
}

/// What the sheen's table holds at each N·V and roughness: the lobe's
/// directional albedo E (capped at 1), and (a, g) such that
/// normalize(a·N + g·(V − N·(N·V))) is the direction the lobe gathers its
/// light from on average (tilted from N towards the eye, the more the
/// smoother the sheen), for the environment's share.
pub type Table = table::Table<3>;

/// The lobe seen at N·V = `nv` with sheen roughness `roughness` (held ≥
/// the minimum), in f64: its directional albedo E = ∫ D·V·N·L dω(L), and
/// the unit direction of its mean ∫ D·V·N·L·L dω(L) as (along N, along the
/// view's side of the tangent plane). Integrated over the half vector
/// (dω(L) = 4·V·H·dω(H)) on a θh grid that crowds towards 90°, where a
/// smooth sheen's distribution lives, by symmetry over half the azimuths.
pub fn lobe(nv: f64, roughness: f64) -> (f64, f64, f64) {
    const THETAS: usize = 192;
    const PHIS: usize = 48;
    let r = roughness.max(f64::from(MIN_SHEEN_ROUGHNESS));
    let k = 1.0 / (r * r);
    let norm = (2.0 + k) / (2.0 * PI);
    let nv = nv.clamp(1e-4, 1.0);
    let v = [(1.0 - nv * nv).sqrt(), 0.0, nv];
    let (mut e, mut mean_t, mut mean_n) = (0.0, 0.0, 0.0);
    let azimuths: [(f64, f64); PHIS] = std::array::from_fn(|j| {
        let phi = PI * (j as f64 + 0.5) / PHIS as f64;
        (phi.cos(), phi.sin())
    });
    for i in 0..THETAS {
        // θh = (π/2)(1 − (1 − t)²), t at the cells' middles.
        let t = (i as f64 + 0.5) / THETAS as f64;
        let theta = PI / 2.0 * (1.0 - (1.0 - t) * (1.0 - t));
        let d_theta = PI * (1.0 - t) / THETAS as f64;
        let (s, c) = theta.sin_cos();
        let d = norm * s.powf(k);
        if d == 0.0 {
            continue;
        }
        for &(cos_phi, sin_phi) in &azimuths {
            let h = [s * cos_phi, s * sin_phi, c];
            let vh = v[0] * h[0] + v[2] * h[2];
            let nl = 2.0 * vh * h[2] - v[2];
            if vh <= 0.0 || nl <= 0.0 {
                continue;
            }
            let vis = 1.0 / (4.0 * (nl + nv - nl * nv));
            // Both halves of the azimuths: × 2 (the mean's sideways part
            // cancels between them).
            let w = d * vis * nl * 4.0 * vh * s * d_theta * (2.0 * PI / PHIS as f64);
            e += w;
            mean_t += w * (2.0 * vh * h[0] - v[0]);
            mean_n += w * nl;
        }
    }
    let len = (mean_t * mean_t + mean_n * mean_n).sqrt();
    if len > 0.0 {
        (e, mean_n / len, mean_t / len)
    } else {
        (e, 1.0, 0.0)
    }
}

/// The lobe's directional albedo ([`lobe`]'s first value).
pub fn albedo(nv: f64, roughness: f64) -> f64 {
    lobe(nv, roughness).0
}

/// The table's entry at roughness row `row` and N·V column `col`.
fn entry(row: usize, col: usize) -> [f32; 3] {
    let last = (SIZE - 1) as f64;
    let nv = col as f64 / last;
    let (e, along_n, along_t) = lobe(nv, row as f64 / last);
    // The sideways part per unit of the view's own (V − N·N·V has length
    // sin θv): finite as the eye comes head on, where the lobe is
    // symmetric about N.
    let sin_v = (1.0 - nv.min(0.999) * nv.min(0.999)).sqrt();
    let along_t = if nv < 0.999 {
        along_t
    } else {
        lobe(0.999, row as f64 / last).2
    };
    [e.min(1.0) as f32, along_n as f32, (along_t / sin_v) as f32]
}

/// The table, integrated on first use (about 10 million steps, a few tens
/// of milliseconds) and kept.
pub fn table() -> &'static Table {
    static TABLE: OnceLock<Table> = OnceLock::new();
    TABLE.get_or_init(|| Table::from_fn(SIZE, entry))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Seen head on, V = N: L = 2(N·H)H − N, N·L = cos 2θh, dω(L) =
    /// 4·cos θh·dω(H), V = 1/4 whatever N·L, so with k = 1/α and s = sin θh
    /// E = (2 + k)·∫₀^{1/√2} s^(k+1)(1 − 2s²) ds = 2^(−(k+2)/2)·2/(k + 4):
    /// 2^(−3/2)·2/5 = 0.141421 at roughness 1 (k = 1), 2^(−3)·2/8 = 0.03125
    /// at roughness ½ (k = 4).
    #[test]
    fn the_albedo_head_on_is_the_closed_form() {
        let closed = |k: f64| 2f64.powf(-(k + 2.0) / 2.0) * 2.0 / (k + 4.0);
        for (roughness, k) in [(1.0, 1.0), (0.5, 4.0), (0.8, 1.0 / 0.64)] {
            let got = albedo(1.0, roughness);
            assert!(
                (got - closed(k)).abs() < 1e-4,
                "{roughness}: {got} against {}",
                closed(k)
            );
        }
        assert!((closed(1.0) - 0.141_421).abs() < 1e-6);
        let table = table();
        assert!((table.read(1.0, 1.0)[0] - 0.141_421).abs() < 1e-4);
        assert!((table.read(1.0, 0.5)[0] as f64 - closed(4.0)).abs() < 2e-3);
    }

    /// The distribution is normalised: ∫ D·cos θh dω(H) = 1 (by hand,
    /// (2 + k)·∫₀^{π/2} sin^(k+1)θ·cos θ dθ = (2 + k)/(k + 2)), here summed
    /// numerically through the lane function; and D vanishes head on.
    #[test]
    fn the_distribution_is_normalised() {
        for roughness in [0.1f32, 0.3, 0.6, 1.0] {
            let alpha = roughness * roughness;
            let n = 20_000;
            let mut sum = 0.0f64;
            for i in 0..n {
                let theta = (i as f64 + 0.5) / n as f64 * PI / 2.0;
                let (s, c) = theta.sin_cos();
                let d = charlie(alpha, (s * s) as f32) as f64;
                sum += d * c * s * (PI / 2.0 / n as f64) * 2.0 * PI;
            }
            assert!((sum - 1.0).abs() < 2e-3, "{roughness}: {sum}");
            assert_eq!(charlie(alpha, 0.0), 0.0);
        }
    }

    /// The environment's light on the sheen is taken as E(N·V) × the
    /// irradiance at N (over π): exact under a uniform environment, where
    /// both are E times the radiance. Under the built-in studio it is
    /// measured here against the lobe integrated over the studio itself
    /// (the same half-vector grid as the table, the studio's radiance at
    /// each L; the irradiance integrated alike, not through the spherical
    /// harmonics), for normals up, towards the key softbox, sideways and
    /// down, seen head on and at N·V = 0.5 and 0.2 from two sides, at sheen
    /// roughness 0.3, 0.6 and 1. The worst relative error, and the worst
    /// over the studio's brightest radiance (what a pixel shows), are the
    /// numbers docs/shading.md gives.
    #[test]
    fn the_environment_approximation_under_the_studio() {
        use glam::DVec3;
        use relief_texture::studio::studio;
        let radiance = |d: DVec3| f64::from(studio(d.as_vec3()).x);
        let frame = |n: DVec3| {
            let t = if n.y.abs() < 0.9 { DVec3::Y } else { DVec3::X };
            let t = (t - n * n.dot(t)).normalize();
            (t, n.cross(t))
        };
        // ∫ L·N·L dω / π over the hemisphere of n.
        let irradiance = |n: DVec3| {
            let (t, b) = frame(n);
            let (m, k) = (256, 512);
            let mut sum = 0.0;
            for i in 0..m {
                let th = (i as f64 + 0.5) / m as f64 * PI / 2.0;
                for j in 0..k {
                    let ph = (j as f64 + 0.5) / k as f64 * 2.0 * PI;
                    let l = n * th.cos() + (t * ph.cos() + b * ph.sin()) * th.sin();
                    sum += radiance(l)
                        * th.cos()
                        * th.sin()
                        * (PI / 2.0 / m as f64)
                        * (2.0 * PI / k as f64);
                }
            }
            sum / PI
        };
        // ∫ D·V·N·L·L(l) dω(l), over the half vector.
        let lobe = |n: DVec3, v: DVec3, roughness: f64| {
            let (t, b) = frame(n);
            let k = 1.0 / (roughness * roughness);
            let norm = (2.0 + k) / (2.0 * PI);
            let nv = n.dot(v);
            let (m, q) = (256, 256);
            let mut sum = 0.0;
            for i in 0..m {
                let u = (i as f64 + 0.5) / m as f64;
                let th = PI / 2.0 * (1.0 - (1.0 - u) * (1.0 - u));
                let d_th = PI * (1.0 - u) / m as f64;
                let d = norm * th.sin().powf(k);
                for j in 0..q {
                    let ph = (j as f64 + 0.5) / q as f64 * 2.0 * PI;
                    let h = n * th.cos() + (t * ph.cos() + b * ph.sin()) * th.sin();
                    let vh = v.dot(h);
                    let l = h * (2.0 * vh) - v;
                    let nl = n.dot(l);
                    if vh <= 0.0 || nl <= 0.0 {
                        continue;
                    }
                    let vis = 1.0 / (4.0 * (nl + nv - nl * nv));
                    sum += d
                        * vis
                        * nl
                        * 4.0
                        * vh
                        * radiance(l)
                        * th.sin()
                        * d_th
                        * (2.0 * PI / q as f64);
                }
            }
            sum
        };
        let key = DVec3::new(-0.5, 0.5, 0.7).normalize();
        let normals = [
            DVec3::Y,
            key,
            DVec3::X,
            DVec3::Z,
            DVec3::new(0.0, -0.6, 0.8),
        ];
        // The worst error over the studio's brightest radiance (2.2), of
        // the irradiance at N and at the table's direction; and the worst
        // relative error of the latter where the lobe gathers at least
        // 0.05 (a twentieth of a white furnace's 1).
        let (mut at_n, mut bent, mut bent_rel) = (0.0f64, 0.0f64, 0.0f64);
        for n in normals {
            let (t, _) = frame(n);
            let e_irr = irradiance(n);
            for nv in [1.0f64, 0.5, 0.2] {
                for side in [1.0, -1.0] {
                    let v = n * nv + t * (side * (1.0 - nv * nv).sqrt());
                    for roughness in [0.3, 0.6, 1.0] {
                        let truth = lobe(n, v, roughness);
                        let e = albedo(nv, roughness).min(1.0);
                        let plain = e * e_irr;
                        // What the kernel does (the spherical harmonics aside).
                        let [_, a, g] = table().read(nv as f32, roughness as f32);
                        let aside = v - n * nv;
                        let gather = (n * f64::from(a) + aside * f64::from(g)).normalize();
                        let got = e * irradiance(gather);
                        eprintln!(
                            "n {n:.2} N·V {nv} side {side} r {roughness}: lobe {truth:.4}, E·irradiance at N {plain:.4}, at the lean {got:.4} ({:+.0} %)",
                            100.0 * (got - truth) / truth
                        );
                        at_n = at_n.max((plain - truth).abs() / 2.2);
                        bent = bent.max((got - truth).abs() / 2.2);
                        if truth >= 0.05 {
                            bent_rel = bent_rel.max((got - truth).abs() / truth);
                        }
                    }
                }
            }
        }
        eprintln!("worst over 2.2: at N {at_n:.4}, at the lean {bent:.4}; relative {bent_rel:.3}");
        assert!(bent < 0.035 && bent < at_n / 2.0, "{bent} {at_n}");
        assert!(bent_rel < 1.0, "{bent_rel}");
    }

    /// The table is finite and within 0..=1, falls as the eye comes head
    /// on for a smooth sheen (it lives at grazing angles), and the lane
    /// functions give the one-lane bits on eight.
    #[test]
    fn the_table_is_bounded_and_the_lanes_agree() {
        let table = table();
        for row in 0..SIZE {
            for col in 0..SIZE {
                let [e, a, g] = entry(row, col);
                assert!(
                    e.is_finite() && (0.0..=1.0).contains(&e),
                    "{row} {col}: {e}"
                );
                assert!(a.is_finite() && g.is_finite() && (-1.0..=1.0).contains(&a));
            }
        }
        assert!(table.read(0.2, 0.3)[0] > table.read(0.9, 0.3)[0]);
        // Head on the lobe gathers along N; seen from aside it leans
        // towards the eye, the more the smoother the sheen.
        let [_, a, _] = table.read(1.0, 0.6);
        assert!((a - 1.0).abs() < 1e-3, "{a}");
        let lean = |r: f32| {
            let [_, a, g] = table.read(0.5, r);
            (g * 0.75f32.sqrt()).atan2(a).to_degrees()
        };
        assert!(lean(0.3) > lean(0.6) && lean(0.6) > lean(1.0) && lean(1.0) > 5.0);
        use wide::f32x8;
        let a = f32x8::from([0.01, 0.04, 0.09, 0.2, 0.36, 0.5, 0.81, 1.0]);
        let s = f32x8::from([0.0, 0.1, 0.5, 0.9, 0.99, 1.0, 0.3, 0.7]);
        let nl = f32x8::from([0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 1.0]);
        let d = charlie(a, s).to_array();
        let v = neubelt(nl, s).to_array();
        for i in 0..8 {
            let (ai, si, li) = (a.as_array()[i], s.as_array()[i], nl.as_array()[i]);
            assert_eq!(d[i].to_bits(), charlie(ai, si).to_bits());
            assert_eq!(v[i].to_bits(), neubelt(li, si).to_bits());
        }
    }
}
