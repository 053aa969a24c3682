//! Blinn's perturbed normal (docs/bump-blinn.md), and Blinn's technique
//! for the shading core: the height gradient tilts the normal.

use glam::Vec3;

use super::PhongTri;
use super::core::{Hook, HookAt, Pixels, gradient};
use super::lanes::{Lanes, Vector};
use super::shader::ShadeCtx;
use relief_core::settings::{Filter, HeightDerivative};
use relief_core::stats::Counters;

/// Blinn bump mapping when `BUMP`, plain Phong otherwise (the surface's own
/// normal and texture coordinate).
pub struct Blinn<const BUMP: bool> {
    /// The triangle's axes when every pixel has the same ones (see
    /// [`Blinn::for_triangle`]).
    flat: Option<Axes<Vec3>>,
}

impl<const BUMP: bool> Blinn<BUMP> {
    /// Blinn's hook for `tri` under the strength `k`. A facet drawn with its
    /// face normal and one pair of texture axes (a cube face) has the same
    /// N × ∂P/∂v, N × ∂P/∂u and orientation at every pixel: they are made
    /// here once, with the very operations each pixel would repeat.
    pub fn for_triangle(tri: &PhongTri, k: f32) -> Self {
        let flat = (BUMP && !tri.smooth && tri.uniform_tangents)
            .then(|| Axes::new(tri.face_normal, tri.tangent_u[0], tri.tangent_v[0], k));
        Blinn { flat }
    }
}

impl<const BUMP: bool> Hook for Blinn<BUMP> {
    type Pixel<V: Vector> = ();
    #[inline(always)]
    fn at<V: Vector>(
        &self,
        ctx: &ShadeCtx,
        px: &Pixels<V>,
        colour: bool,
        counters: &mut Counters,
    ) -> (HookAt<V>, ()) {
        let s = &px.s;
        let mut at = HookAt {
            u: s.u,
            v: s.v,
            n: s.n,
            texel: None,
        };
        if BUMP {
            let plan = ctx.plan;
            counters.bump_evals += px.count();
            // Bilinear colour and filtered heights read the same texels: one
            // neighbourhood serves both (the default, and the common case).
            let fused = colour
                && plan.filter == Filter::Bilinear
                && plan.height_derivative == HeightDerivative::Filtered;
            let (fu, fv) = if fused {
                let ([r, g, b], fu, fv) =
                    V::L::bilinear_with_gradient(ctx.texture.base(), s.u, s.v);
                at.texel = Some(V::new(r, g, b));
                (fu, fv)
            } else {
                gradient(ctx, s.u, s.v, px.fp, px.live)
            };
            let axes = match &self.flat {
                Some(a) => a.lanes(),
                None => Axes::new(s.n, s.pu, s.pv, plan.bump_strength),
            };
            at.n = axes.perturb(s.n, fu, fv);
        }
        (at, ())
    }
}

/// N' = N + k·(F_u·(N × Pv) − F_v·(N × Pu)), normalised. `n` is unit length;
/// (fu, fv) are the height derivatives per unit of texture coordinate and
/// (pu, pv) = ∂P/∂u, ∂P/∂v. The formula assumes Pu × Pv points along N; on
/// mirrored UVs it points the other way and the perturbation changes sign
/// with it, so raised stays raised. A perturbation that cancels the normal
/// (or any non-finite input) falls back to the unperturbed normal.
/// Written once for one normal or eight (`shade::lanes`).
#[inline(always)]
pub fn blinn<V: Vector>(n: V, pu: V, pv: V, fu: V::L, fv: V::L, k: f32) -> V {
    Axes::new(n, pu, pv, k).perturb(n, fu, fv)
}

/// The part of Blinn's formula the heights do not change: N × Pv, N × Pu
/// and k with the sign of the UVs' orientation.
#[derive(Clone, Copy, Debug)]
pub struct Axes<V: Vector> {
    n_pv: V,
    n_pu: V,
    k: V::L,
}

impl<V: Vector> Axes<V> {
    #[inline(always)]
    pub fn new(n: V, pu: V, pv: V, k: f32) -> Self {
        let flip = pu.cross(pv).dot(n).lt(V::L::ZERO);
        Axes {
            n_pv: n.cross(pv),
            n_pu: n.cross(pu),
            k: V::L::select(flip, V::L::splat(-k), V::L::splat(k)),
        }
    }

    /// The unit normal `n` tilted by the height slopes (fu, fv).
    #[inline(always)]
    pub fn perturb(&self, n: V, fu: V::L, fv: V::L) -> V {
        let perturbed = n + (self.n_pv * fu - self.n_pu * fv) * self.k;
        let len2 = perturbed.dot(perturbed);
        let inf = V::L::splat(f32::INFINITY);
        let ok = V::L::both(len2.gt(V::L::splat(1e-20)), || len2.lt(inf));
        V::select(ok, perturbed / len2.sqrt(), n)
    }
}

impl Axes<Vec3> {
    /// The same axes in every lane of `V`.
    #[inline(always)]
    fn lanes<V: Vector>(&self) -> Axes<V> {
        Axes {
            n_pv: V::uniform(self.n_pv),
            n_pu: V::uniform(self.n_pu),
            k: V::L::splat(self.k),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    // +Z face of the reference cube: U = +X, V = +Y, Pu = 2U, Pv = 2V.
    const PU: Vec3 = Vec3::new(2.0, 0.0, 0.0);
    const PV: Vec3 = Vec3::new(0.0, 2.0, 0.0);

    #[test]
    fn zero_slope_or_zero_strength_keeps_the_normal() {
        assert_eq!(blinn(Vec3::Z, PU, PV, 0.0, 0.0, 0.006), Vec3::Z);
        assert_eq!(blinn(Vec3::Z, PU, PV, 50.0, -20.0, 0.0), Vec3::Z);
    }

    #[test]
    fn height_rising_along_u_tilts_the_normal_toward_minus_u() {
        // F_u = 100 per unit of u, k = 0.005: N' = (0,0,1) + 0.005·100·(Z × 2Y) = (−1, 0, 1).
        let n = blinn(Vec3::Z, PU, PV, 100.0, 0.0, 0.005);
        let expected = Vec3::new(-1.0, 0.0, 1.0).normalize();
        assert!((n - expected).length() < 1e-6, "{n}");
    }

    #[test]
    fn height_rising_along_v_tilts_the_normal_toward_minus_v() {
        let n = blinn(Vec3::Z, PU, PV, 0.0, 100.0, 0.005);
        let expected = Vec3::new(0.0, -1.0, 1.0).normalize();
        assert!((n - expected).length() < 1e-6, "{n}");
    }

    #[test]
    fn mirrored_uvs_keep_raised_surfaces_raised() {
        // Mirror u: Pu = −2X. Height rising along u now rises toward −X, so
        // the normal must tilt toward +X (away from the slope), not −X.
        let n = blinn(Vec3::Z, -PU, PV, 100.0, 0.0, 0.005);
        assert!(n.x > 0.5, "{n}");
        let n = blinn(Vec3::Z, PU, -PV, 0.0, 100.0, 0.005);
        assert!(n.y > 0.5, "{n}");
    }

    #[test]
    fn huge_strength_stays_unit_and_finite() {
        let n = blinn(Vec3::Z, PU, PV, 1e30, 1e30, 1e30);
        assert!(n.is_finite());
        assert!((n.length() - 1.0).abs() < 1e-5);
    }

    #[test]
    fn a_facets_axes_made_once_give_every_pixels_normal() {
        use crate::shade::packet::V3;
        use wide::f32x8;
        let n = Vec3::new(0.3, -0.5, 0.8).normalize();
        let slopes = [
            (0.0, 0.0),
            (37.5, -12.25),
            (-0.001, 250.0),
            (1e30, 1e30),
            (f32::NAN, 1.0),
            (3.0, f32::INFINITY),
            (-80.0, -80.0),
            (0.5, -0.5),
        ];
        let (fu, fv) = (slopes.map(|s| s.0), slopes.map(|s| s.1));
        for (pu, pv) in [
            (PU, PV),
            (-PU, PV),
            (Vec3::new(1.5, 0.2, -0.1), Vec3::new(-0.3, 2.0, 0.4)),
        ] {
            for k in [0.006, -0.02, 0.0] {
                let once = Axes::new(n, pu, pv, k);
                let eight =
                    once.lanes::<V3>()
                        .perturb(V3::splat(n), f32x8::from(fu), f32x8::from(fv));
                let (x, y, z) = (eight.x.to_array(), eight.y.to_array(), eight.z.to_array());
                for i in 0..8 {
                    let each = blinn(n, pu, pv, fu[i], fv[i], k);
                    let one = once.lanes::<Vec3>().perturb(n, fu[i], fv[i]);
                    let bits = |v: Vec3| v.to_array().map(f32::to_bits);
                    assert_eq!(bits(one), bits(each), "{pu} {pv} {k} lane {i}");
                    assert_eq!(
                        bits(Vec3::new(x[i], y[i], z[i])),
                        bits(each),
                        "{pu} {pv} {k} lane {i}"
                    );
                }
            }
        }
    }
}
