//! Dot3 normal mapping (docs/bump-dot3.md): a normal map derived from the
//! height map, dotted with the light vector expressed in tangent space.
//!
//! Two ways to get the tangent-space light vector, as the tutorial shows:
//! - per vertex (`LightVector::Vertex`): projected into each vertex's frame,
//!   normalised there, and interpolated across the triangle *without*
//!   renormalising — between vertices it is shorter than 1, so large
//!   triangles darken toward their middle (the tutorial's artefact);
//! - per pixel (`LightVector::Pixel`): recomputed and normalised at every
//!   pixel, which is what its normalisation cube map achieves.
//!
//! The normal map is built for the slope scale 2k (Blinn's k on a face two
//! units wide, the reference cube), so on the reference cube dot3 and Blinn
//! agree at texel centres; between texels dot3 interpolates normals where
//! Blinn interpolates heights.
//!
//! The normal map is read like the colour (`filter::read_normal`): on a
//! minified pixel, trilinear and anisotropic with the filtered derivative
//! read the footprint's level(s) of the map's mip chain, whose vectors are
//! averaged and left short, so N·L is the mean over the footprint and a far
//! or grazing surface stops shimmering. Magnified, or with nearest/bilinear
//! or the `texel` derivative, it is the base map, as documented.
//!
//! Like every kernel, each light is scaled by what the shadow map (when the
//! plan drew one) says reaches the point.

use glam::{Vec2, Vec3};

use super::PhongTri;
use super::core::{Hook, HookAt, Pixels};
use super::interpolate::lerp3;
use super::lanes::{Lanes, Vector};
use super::map_uv::{carry, footprint_map, map_coords};
use super::shader::ShadeCtx;
use super::tangent::Frame;
use crate::plan::ActiveLight;
use relief_core::stats::Counters;
use relief_texture::NormalMap;
use relief_texture::sample::filter::read_normal;

/// Lights whose per-vertex vectors are kept inline (more spill to the heap).
const INLINE_LIGHTS: usize = 8;

/// Per-vertex tangent-space light vectors of one triangle, light by light:
/// entry `3·j + i` is light j at vertex i, unit length (zero when the light
/// sits on the vertex). Computed once per triangle and band, on the stack
/// for up to eight lights.
pub struct VertexLights {
    inline: [Vec3; 3 * INLINE_LIGHTS],
    heap: Vec<Vec3>,
}

impl VertexLights {
    pub fn new(tri: &PhongTri, lights: &[ActiveLight]) -> Self {
        let frames: [Frame; 3] = [0, 1, 2].map(|i| {
            Frame::new(
                tri.normal[i].normalize_or(tri.face_normal),
                tri.tangent_u[i],
                tri.tangent_v[i],
            )
        });
        let vector = |j: usize, i: usize| {
            frames[i]
                .to_tangent(lights[j].position - tri.position[i])
                .normalize_or_zero()
        };
        let mut out = VertexLights {
            inline: [Vec3::ZERO; 3 * INLINE_LIGHTS],
            heap: Vec::new(),
        };
        if lights.len() <= INLINE_LIGHTS {
            for j in 0..lights.len() {
                for i in 0..3 {
                    out.inline[3 * j + i] = vector(j, i);
                }
            }
        } else {
            out.heap = (0..lights.len())
                .flat_map(|j| (0..3).map(move |i| (j, i)))
                .map(|(j, i)| vector(j, i))
                .collect();
        }
        out
    }

    /// The three vertex vectors of light `j`.
    #[inline]
    pub fn light(&self, j: usize) -> &[Vec3] {
        if self.heap.is_empty() {
            &self.inline[3 * j..3 * j + 3]
        } else {
            &self.heap[3 * j..3 * j + 3]
        }
    }
}

/// Dot3 for the shading core: the normal map's tangent-space normal dotted
/// with the light vector, per pixel or interpolated from the vertices.
pub struct Dot3<'a, const PER_PIXEL: bool> {
    pub map: &'a NormalMap,
    /// The tangent-space light vectors at the vertices (per-vertex mode).
    pub vertex_lights: Option<VertexLights>,
}

impl<'a, const PER_PIXEL: bool> Dot3<'a, PER_PIXEL> {
    pub fn new(tri: &PhongTri, map: &'a NormalMap, ctx: &ShadeCtx) -> Self {
        Dot3 {
            map,
            vertex_lights: (!PER_PIXEL).then(|| VertexLights::new(tri, &ctx.plan.lights)),
        }
    }
}

/// A dot3 pixel (or eight): the map's normal, in tangent space, and the
/// pixel's frame (per-pixel mode, or when the world normal is read).
pub struct Dot3Pixel<V: Vector> {
    normal: V,
    frame: Option<Frame<V>>,
}

impl<const PER_PIXEL: bool> Hook for Dot3<'_, PER_PIXEL> {
    type Pixel<V: Vector> = Dot3Pixel<V>;
    #[inline(always)]
    fn at<V: Vector>(
        &self,
        ctx: &ShadeCtx,
        px: &Pixels<V>,
        _colour: bool,
        counters: &mut Counters,
    ) -> (HookAt<V>, Dot3Pixel<V>) {
        let plan = ctx.plan;
        let s = &px.s;
        counters.bump_evals += px.count();
        counters.texture_samples += px.count();
        let (d, f) = (plan.height_derivative, plan.filter);
        let normal = match plan.terms.as_deref().map(|t| &t.uvs.normal) {
            // A model's normal map on its own set or transform.
            Some(m) if !m.is_vertex_uv() => {
                let (u, v) = map_coords(m, &px.tri.uv2, &px.b, (s.u, s.v));
                let to = footprint_map(m, &px.tri.uv, &px.tri.uv2);
                V::gather(px.live, |i| {
                    let uv = Vec2::new(u.lane(i), v.lane(i));
                    Vec3::from(read_normal(self.map, d, f, uv, carry(px.fp[i], to)))
                })
            }
            _ => V::gather(px.live, |i| {
                Vec3::from(read_normal(self.map, d, f, px.uv(i), px.fp[i]))
            }),
        };
        // The world normal serves the highlights and the reflection; per
        // vertex, the frame is built only when something reads it.
        let world_normal = plan.specular.is_some() || plan.environment.is_some();
        let frame = (PER_PIXEL || world_normal).then(|| s.frame());
        let n = frame.map_or(s.n, |f| {
            f.t * normal.x() + f.b * normal.y() + f.n * normal.z()
        });
        // The diffuse cosine keeps the filtered normal's length (the mean
        // N·L); the highlight and the mirror take its direction alone: a
        // minified map's short normal would dim (N·H)^s by about |N|^s,
        // further from the supersampled picture (docs/bump-dot3.md).
        let n = n.normalize_or(s.n);
        let at = HookAt {
            u: s.u,
            v: s.v,
            n,
            texel: None,
        };
        (at, Dot3Pixel { normal, frame })
    }

    #[inline(always)]
    fn cosine<V: Vector>(
        &self,
        _ctx: &ShadeCtx,
        px: &Pixels<V>,
        own: &Dot3Pixel<V>,
        _n: V,
        i: usize,
        d: V,
        _counters: &mut Counters,
    ) -> Option<V::L> {
        let l = if PER_PIXEL {
            let frame = own.frame.as_ref()?;
            frame.to_tangent(d) / d.dot(d).sqrt()
        } else {
            let vertex = self.vertex_lights.as_ref()?;
            let v = vertex.light(i);
            lerp3(&px.b, &[v[0], v[1], v[2]])
        };
        Some(own.normal.dot(l))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec2;

    fn quad_tri() -> PhongTri {
        PhongTri {
            position: [
                Vec3::new(-1.0, -1.0, 0.0),
                Vec3::new(1.0, -1.0, 0.0),
                Vec3::new(1.0, 1.0, 0.0),
            ],
            normal: [Vec3::Z; 3],
            face_normal: Vec3::Z,
            smooth: false,
            color: [Vec3::ONE; 3],
            uv: [Vec2::ZERO, Vec2::X, Vec2::ONE],
            uv2: [Vec2::ZERO; 3],
            tangent_u: [2.0 * Vec3::X; 3],
            tangent_v: [2.0 * Vec3::Y; 3],
            uniform_tangents: true,
            textured: true,
            bumped: true,
            glossy: false,
            object: 0,
        }
    }

    #[test]
    fn vertex_vectors_are_unit_and_point_at_the_light() {
        let light = ActiveLight {
            position: Vec3::new(1.0, -1.0, 5.0),
            color: Vec3::ONE,
            falloff: relief_scene::light::Falloff::Setting,
        };
        let vl = VertexLights::new(&quad_tri(), &[light]);
        let out = vl.light(0);
        assert_eq!(out[1], Vec3::Z, "vertex 1 is right under the light");
        for v in out {
            assert!((v.length() - 1.0).abs() < 1e-6);
        }
        // Interpolating two different unit vectors gives a shorter one: the artefact.
        assert!(((out[0] + out[2]) * 0.5).length() < 1.0);
    }

    #[test]
    fn a_light_on_a_vertex_gives_zero_not_nan() {
        let light = ActiveLight {
            position: Vec3::new(-1.0, -1.0, 0.0),
            color: Vec3::ONE,
            falloff: relief_scene::light::Falloff::Setting,
        };
        let vl = VertexLights::new(&quad_tri(), &[light]);
        assert_eq!(vl.light(0)[0], Vec3::ZERO);
        assert!(vl.light(0).iter().all(|v| v.is_finite()));
    }

    #[test]
    fn many_lights_spill_to_the_heap_with_the_same_vectors() {
        let lights: Vec<ActiveLight> = (0..11)
            .map(|i| ActiveLight {
                position: Vec3::new(i as f32, 2.0, 3.0),
                color: Vec3::ONE,
                falloff: relief_scene::light::Falloff::Setting,
            })
            .collect();
        let many = VertexLights::new(&quad_tri(), &lights);
        let few = VertexLights::new(&quad_tri(), &lights[..8]);
        for j in 0..8 {
            assert_eq!(many.light(j), few.light(j));
        }
        assert_eq!(many.light(10).len(), 3);
    }
}
