//! Dot3 normal mapping (seeds 000 §1.3.2, 004): a normal map derived from the
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

use glam::{Vec2, Vec3};

use super::PhongTri;
use super::kernels::{PixelShader, ShadeCtx};
use super::lighting::ATTENUATION_QUADRATIC;
use super::tangent::{Frame, Surface, lerp3};
use crate::framebuffer::Rgb;
use crate::plan::ActiveLight;
use crate::stats::Counters;
use crate::texture::NormalMap;
use crate::texture::filter::{Footprint, sample};

/// |∂P/∂u| of the reference cube's faces: the normal map's slope scale is
/// Blinn's k times this, so both techniques show the same relief there.
pub const REFERENCE_TANGENT_LENGTH: f32 = 2.0;

/// The normal map's slope scale for bump strength `k`.
pub fn normal_map_scale(k: f32) -> f32 {
    k * REFERENCE_TANGENT_LENGTH
}

/// Per-vertex tangent-space light vectors of one triangle, appended to `out`
/// light by light: `out[3·j + i]` is light j at vertex i, unit length (zero
/// when the light sits on the vertex).
pub fn vertex_light_vectors(tri: &PhongTri, lights: &[ActiveLight], out: &mut Vec<Vec3>) {
    let frames: [Frame; 3] = [0, 1, 2].map(|i| {
        Frame::new(
            tri.normal[i].normalize_or(tri.face_normal),
            tri.tangent_u[i],
            tri.tangent_v[i],
        )
    });
    for light in lights {
        for (i, frame) in frames.iter().enumerate() {
            let l = frame.to_tangent(light.position - tri.position[i]);
            out.push(l.normalize_or_zero());
        }
    }
}

/// The dot3 kernel: with or without the colour texture, light vector per
/// pixel or interpolated from the vertices.
pub struct Dot3Kernel<'a, const TEX: bool, const PER_PIXEL: bool> {
    pub tri: &'a PhongTri,
    pub map: &'a NormalMap,
    /// This triangle's `vertex_light_vectors` (unused per pixel).
    pub vertex_lights: &'a [Vec3],
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
        let normal = Vec3::from(self.map.bilinear(uv.x, uv.y));
        counters.light_evals += plan.lights.len() as u64;
        let mut sum = plan.ambient;
        if PER_PIXEL {
            let frame = Surface::at(tri, b).frame();
            for light in &plan.lights {
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
                        sum += light.color * k.min(1.0);
                    }
                }
            }
        } else {
            for (j, light) in plan.lights.iter().enumerate() {
                let v = &self.vertex_lights[3 * j..3 * j + 3];
                let l = v[0] * b.x + v[1] * b.y + v[2] * b.z;
                let mut k = normal.dot(l);
                if k > 0.0 {
                    if plan.attenuation {
                        k /= 1.0 + ATTENUATION_QUADRATIC * (light.position - p).length_squared();
                    }
                    sum += light.color * k.min(1.0);
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
        }
    }

    #[test]
    fn vertex_vectors_are_unit_and_point_at_the_light() {
        let light = ActiveLight {
            position: Vec3::new(1.0, -1.0, 5.0),
            color: Vec3::ONE,
        };
        let mut out = Vec::new();
        vertex_light_vectors(&quad_tri(), &[light], &mut out);
        assert_eq!(out.len(), 3);
        assert_eq!(out[1], Vec3::Z, "vertex 1 is right under the light");
        for v in &out {
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
        let mut out = Vec::new();
        vertex_light_vectors(&quad_tri(), &[light], &mut out);
        assert_eq!(out[0], Vec3::ZERO);
        assert!(out.iter().all(|v| v.is_finite()));
    }
}
