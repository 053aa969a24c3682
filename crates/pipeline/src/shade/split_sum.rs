//! The split-sum lookup table (Karis, "Real Shading in Unreal Engine 4",
//! 2013): for N·V and roughness, the scale A and bias B such that the
//! specular light a uniform white environment sends back is F0·A + B,
//! with this kernel's BRDF (GGX D, Smith height-correlated V, Schlick F).
//! Integrated once by sampling the visible normals over `SAMPLES`
//! Hammersley points per entry.

use std::f32::consts::PI;

use glam::Vec3;

use super::brdf::visibility;
use super::table::Table;

/// Entries along N·V and along roughness; entry i is at i/(SIZE − 1), so
/// N·V = 1 and roughness 0 are exact entries.
pub const SIZE: usize = 32;
/// Samples per entry.
const SAMPLES: u32 = 1024;

/// A and B per entry ([`Table::read`] gives `[A, B]`).
pub type Lut = Table<2>;

/// The i-th of n Hammersley points: (i + ½)/n and the bit-reversed i.
pub fn hammersley(i: u32, n: u32) -> (f32, f32) {
    let reversed = i.reverse_bits() as f32 * (1.0 / 4_294_967_296.0);
    ((i as f32 + 0.5) / n as f32, reversed)
}

/// (A, B) at N·V = `nv` and `roughness`: the mean over microfacet normals
/// H drawn from GGX's distribution of visible normals (Heitz, "Sampling the
/// GGX Distribution of Visible Normals", 2018) of G2/G1(V), the BRDF times
/// N·L over that density with F taken out, split by Schlick's weight
/// (1 − V·H)⁵. Each sample's weight is at most 1 (G2 ≤ G1), so A + B ≤ 1.
pub fn split_sum(nv: f32, roughness: f32) -> (f32, f32) {
    split_sum_over(&disc_points(), nv, roughness)
}

/// [`split_sum`] over the samples' points on the unit disc, made once for
/// the whole table.
fn split_sum_over(points: &[DiscPoint], nv: f32, roughness: f32) -> (f32, f32) {
    let nv = nv.clamp(1e-3, 1.0);
    let v = Vec3::new((1.0 - nv * nv).sqrt(), 0.0, nv);
    let alpha = roughness * roughness;
    let alpha2 = alpha * alpha;
    let g1_v = 2.0 * nv / (nv + (alpha2 + (1.0 - alpha2) * nv * nv).sqrt());
    let (mut a, mut b) = (0.0f64, 0.0f64);
    for point in points {
        let h = visible_normal(v, alpha, point);
        let vh = v.dot(h);
        let l = h * (2.0 * vh) - v;
        let nl = l.z;
        if nl <= 0.0 || vh <= 0.0 {
            continue;
        }
        let g2 = visibility(alpha2, nl, nv) * 4.0 * nl * nv;
        let w = (g2 / g1_v).min(1.0);
        let fc = (1.0 - vh).powi(5);
        a += ((1.0 - fc) * w) as f64;
        b += (fc * w) as f64;
    }
    let n = SAMPLES as f64;
    ((a / n) as f32, (b / n) as f32)
}

/// A Hammersley point (u1, u2) on the unit disc: radius √u1 and angle 2π·u2.
struct DiscPoint {
    p1: f32,
    p2: f32,
}

/// The `SAMPLES` Hammersley points on the disc: the same for every entry,
/// so their square roots and sines are computed once.
fn disc_points() -> Vec<DiscPoint> {
    (0..SAMPLES)
        .map(|i| {
            let (u1, u2) = hammersley(i, SAMPLES);
            let r = u1.sqrt();
            let phi = 2.0 * PI * u2;
            DiscPoint {
                p1: r * phi.cos(),
                p2: r * phi.sin(),
            }
        })
        .collect()
}

/// A microfacet normal seen from `v` (unit, +Z the normal) for GGX of
/// roughness α = `alpha`, from a point on the unit disc (Heitz 2018): the
/// view stretched to α = 1, the point lifted onto the projected
/// hemisphere, and back.
fn visible_normal(v: Vec3, alpha: f32, &DiscPoint { p1, p2 }: &DiscPoint) -> Vec3 {
    let vh = Vec3::new(alpha * v.x, alpha * v.y, v.z).normalize();
    let len2 = vh.x * vh.x + vh.y * vh.y;
    let t1 = if len2 > 0.0 {
        Vec3::new(-vh.y, vh.x, 0.0) / len2.sqrt()
    } else {
        Vec3::X
    };
    let t2 = vh.cross(t1);
    let s = 0.5 * (1.0 + vh.z);
    let p2 = (1.0 - s) * (1.0 - p1 * p1).max(0.0).sqrt() + s * p2;
    let nh = t1 * p1 + t2 * p2 + vh * (1.0 - p1 * p1 - p2 * p2).max(0.0).sqrt();
    Vec3::new(alpha * nh.x, alpha * nh.y, nh.z.max(0.0)).normalize_or(Vec3::Z)
}

/// The table of [`split_sum`] at every entry.
pub fn build() -> Lut {
    let step = 1.0 / (SIZE - 1) as f32;
    let points = disc_points();
    Table::from_fn(SIZE, |r, c| {
        let (a, b) = split_sum_over(&points, c as f32 * step, r as f32 * step);
        [a, b]
    })
}

/// The table, computed on first use and shared.
pub fn lut() -> &'static Lut {
    static LUT: std::sync::OnceLock<Lut> = std::sync::OnceLock::new();
    LUT.get_or_init(build)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A mirror head on reflects everything it receives: A + B = 1 at N·V = 1
    /// and roughness 0 (the sampled H is N, V = 1/4, weight 1, F weight 0).
    #[test]
    fn the_table_is_one_for_a_mirror_head_on_and_never_above_one() {
        let (a, b) = split_sum(1.0, 0.0);
        assert!((a - 1.0).abs() < 1e-6 && b.abs() < 1e-6, "{a} {b}");
        let lut = build();
        let [a, b] = lut.read(1.0, 0.0);
        assert!((a + b - 1.0).abs() < 1e-6, "{a} {b}");
        let mut worst = 0.0f32;
        for r in 0..SIZE {
            for c in 0..SIZE {
                let step = 1.0 / (SIZE - 1) as f32;
                let [a, b] = lut.read(c as f32 * step, r as f32 * step);
                assert!(a >= 0.0 && b >= 0.0, "{c} {r}: {a} {b}");
                worst = worst.max(a + b);
            }
        }
        assert!(worst <= 1.0 + 1e-6, "{worst}");
        // Roughness 1 (α = 1): D = 1/π and V = ½/(N·L + N·V), so head on
        // A + B = ∫ N·L/(2π(N·L + 1)) dω = ∫₀¹ μ/(μ + 1) dμ = 1 − ln 2.
        let [a, b] = lut.read(1.0, 1.0);
        assert!((a + b - (1.0 - 2f32.ln())).abs() < 0.005, "{a} {b}");
        // Grazing, Fresnel's share grows: B above A for a mirror.
        let [a, b] = lut.read(0.0, 0.0);
        assert!(b > a, "{a} {b}");
    }
}
