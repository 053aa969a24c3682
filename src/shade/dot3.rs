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
use super::kernels::{PixelShader, ShadeCtx};
use super::lighting::ATTENUATION_QUADRATIC;
use super::tangent::{Frame, Surface, lerp3};
use crate::framebuffer::Rgb;
use crate::plan::ActiveLight;
use crate::stats::Counters;
use crate::texture::NormalMap;
use crate::texture::filter::{Footprint, read_normal, sample};

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

/// The dot3 kernel: with or without the colour texture, light vector per
/// pixel or interpolated from the vertices.
pub struct Dot3Kernel<'a, const TEX: bool, const PER_PIXEL: bool> {
    pub tri: &'a PhongTri,
    pub map: &'a NormalMap,
    /// The light vectors at the vertices (empty when per pixel).
    pub vertex_lights: Option<VertexLights>,
}

impl<'a, const TEX: bool, const PER_PIXEL: bool> Dot3Kernel<'a, TEX, PER_PIXEL> {
    pub fn new(tri: &'a PhongTri, map: &'a NormalMap, ctx: &ShadeCtx) -> Self {
        Dot3Kernel {
            tri,
            map,
            vertex_lights: (!PER_PIXEL).then(|| VertexLights::new(tri, &ctx.plan.lights)),
        }
    }

    /// How much of light `i` reaches `p` past the shadow map (1 without one).
    #[inline]
    fn seen(&self, ctx: &ShadeCtx, i: usize, p: Vec3, counters: &mut Counters) -> f32 {
        ctx.shadow.map_or(1.0, |sh| {
            sh.factor(i, p, self.tri.face_normal, self.tri.object, counters)
        })
    }
}

impl<const TEX: bool, const PER_PIXEL: bool> PixelShader for Dot3Kernel<'_, TEX, PER_PIXEL> {
    const SAMPLES_TEXTURE: bool = true;
    #[inline]
    fn shade(&self, ctx: &ShadeCtx, b: Vec3, fp: Footprint, counters: &mut Counters) -> Rgb {
        let plan = ctx.plan;
        let tri = self.tri;
        counters.pixels_shaded += 1;
        counters.bump_evals += 1;
        counters.texture_samples += 1;
        let (p, albedo, uv) = (
            lerp3(b, &tri.position),
            lerp3(b, &tri.color),
            super::tangent::lerp2(b, &tri.uv),
        );
        let mut albedo = albedo;
        if TEX {
            counters.texture_samples += 1;
            let t = sample(ctx.texture, plan.filter, uv, fp);
            albedo *= Vec3::new(t[0], t[1], t[2]);
        }
        let normal = Vec3::from(read_normal(
            self.map,
            plan.height_derivative,
            plan.filter,
            uv,
            fp,
        ));
        counters.light_evals += plan.lights.len() as u64;
        let mut sum = plan.ambient;
        if PER_PIXEL {
            let frame = Surface::at(tri, b).frame();
            for (i, light) in plan.lights.iter().enumerate() {
                let d = light.position - p;
                let len2 = d.length_squared();
                if len2 > 0.0 && len2.is_finite() {
                    // The frame is orthonormal: dividing by the world length
                    // gives the unit tangent-space light vector.
                    let l = frame.to_tangent(d) / len2.sqrt();
                    let mut k = normal.dot(l);
                    if k > 0.0 {
                        if plan.attenuation {
                            k /= 1.0 + ATTENUATION_QUADRATIC * len2;
                        }
                        sum += light.color * (k.min(1.0) * self.seen(ctx, i, p, counters));
                    }
                }
            }
        } else if let Some(vertex_lights) = &self.vertex_lights {
            for (j, light) in plan.lights.iter().enumerate() {
                let v = vertex_lights.light(j);
                let l = v[0] * b.x + v[1] * b.y + v[2] * b.z;
                let mut k = normal.dot(l);
                if k > 0.0 {
                    if plan.attenuation {
                        k /= 1.0 + ATTENUATION_QUADRATIC * (light.position - p).length_squared();
                    }
                    sum += light.color * (k.min(1.0) * self.seen(ctx, j, p, counters));
                }
            }
        }
        super::lighting::finish(albedo * sum, counters)
    }
    fn uvs(&self) -> Option<&[Vec2; 3]> {
        Some(&self.tri.uv)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
