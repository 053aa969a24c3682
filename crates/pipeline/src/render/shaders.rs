//! The per-triangle shading data: everything a visible triangle's pixels
//! need, in world space, and the lines and points displays' vertex light.

use glam::{Mat3, Mat4, Vec2, Vec3, Vec4};

use crate::plan::Plan;
use crate::raster::wire::WireTri;
use crate::shade::lighting::{LightSet, diffuse, finish, lambert, light_with};
use crate::shade::specular::{gloss, view_dir};
use crate::shade::{GouraudTri, PhongTri, TexturedFlatTri, TriShader};
use crate::shadow::Shadow;
use relief_core::settings::Shading;
use relief_core::stats::Counters;
use relief_scene::world::WorldVertex;

/// A triangle of the points and lines displays: clip-space corners and the
/// light at each vertex (Gouraud's, whatever the shading mode).
pub(super) fn wire_triangle(
    plan: &Plan,
    verts: [WorldVertex; 3],
    clip: [Vec4; 3],
    face_normal: Vec3,
    side: f32,
) -> WireTri {
    let color = verts.map(|v| {
        let n = if plan.face_normals {
            face_normal
        } else {
            v.normal * side
        };
        let albedo = if plan.colors { v.color } else { Vec3::ONE };
        albedo * diffuse(&plan.lights, plan.ambient, v.position, n, plan.attenuation)
    });
    WireTri { clip, color }
}

/// Everything a visible triangle's pixels need, in world space.
#[allow(clippy::too_many_arguments)]
pub(super) fn build_shader(
    plan: &Plan,
    verts: &[WorldVertex; 3],
    mesh: &relief_scene::Mesh,
    t: usize,
    face_normal: Vec3,
    side: f32,
    model: &Mat4,
    linear: &Mat3,
    shadow: Option<Shadow>,
    object: u32,
    uv2: [Vec2; 3],
    counters: &mut Counters,
) -> TriShader {
    let tri = &mesh.triangles[t];
    let textured = tri.textured && plan.texture;
    let bumped = tri.textured && plan.bump;
    let glossy = tri.textured && plan.specular.as_ref().is_some_and(|s| s.map.is_some());
    let uv = verts.map(|v| v.uv);
    // The specular map's coordinates, when a model's map reads its own.
    let gloss_uv = match plan.terms.as_deref().map(|t| t.uvs.specular) {
        Some(m) if !m.is_vertex_uv() => [0, 1, 2].map(|k| m.at(uv[k], uv2[k])),
        _ => uv,
    };
    let white = Vec3::ONE;
    let color = if plan.colors {
        verts.map(|v| v.color)
    } else {
        [white; 3]
    };
    match plan.shading {
        Shading::Flat => {
            let facet = mesh.facet(t);
            let center = model.transform_point3(facet.center);
            let albedo = if plan.colors { facet.color } else { white };
            let (light, highlight) = lights_at(
                plan,
                center,
                face_normal,
                |i, c: &mut Counters| {
                    shadow.map_or(1.0, |s| s.factor(i, center, face_normal, object, c))
                },
                counters,
            );
            // One highlight per facet, the specular map read at its centre.
            let gloss_uv = (gloss_uv[0] + gloss_uv[1] + gloss_uv[2]) / 3.0;
            let highlight = highlight * glossiness(plan, glossy, gloss_uv);
            let lit = albedo * light;
            let cut = plan.terms.as_ref().is_some_and(|t| t.cutout.is_some());
            if textured {
                TriShader::FlatTextured(TexturedFlatTri { lit, uv, highlight })
            } else if cut {
                // One colour, but the alpha mask needs the UVs: Gouraud
                // with the same light at the three corners.
                TriShader::Gouraud(GouraudTri {
                    light: [lit; 3],
                    highlight: [highlight; 3],
                    color: [white; 3],
                    uv,
                    gloss_uv: uv,
                    textured: false,
                    glossy: false,
                })
            } else if plan.specular.is_some() {
                TriShader::Solid(finish(lit + highlight, counters))
            } else {
                TriShader::Solid(finish(lit, counters))
            }
        }
        Shading::Gouraud => {
            let lit = verts.map(|v| {
                let n = if plan.face_normals {
                    face_normal
                } else {
                    v.normal * side
                };
                lights_at(
                    plan,
                    v.position,
                    n,
                    |i, c: &mut Counters| {
                        shadow.map_or(1.0, |s| s.factor(i, v.position, face_normal, object, c))
                    },
                    counters,
                )
            });
            TriShader::Gouraud(GouraudTri {
                light: lit.map(|l| l.0),
                highlight: lit.map(|l| l.1),
                color,
                uv,
                gloss_uv,
                textured,
                glossy,
            })
        }
        Shading::Phong => {
            let smooth = !plan.face_normals;
            let normal = if smooth {
                verts.map(|v| v.normal * side)
            } else {
                [face_normal; 3]
            };
            let (tangent_u, tangent_v, uniform_tangents) = if plan.face_normals {
                let facet = mesh.facet(t);
                let tu = *linear * facet.tangent_u;
                let tv = *linear * facet.tangent_v;
                ([tu; 3], [tv; 3], true)
            } else {
                let tu = verts.map(|v| v.tangent_u);
                let tv = verts.map(|v| v.tangent_v);
                let uniform = tu[0] == tu[1] && tu[1] == tu[2] && tv[0] == tv[1] && tv[1] == tv[2];
                (tu, tv, uniform)
            };
            TriShader::Phong(PhongTri {
                position: verts.map(|v| v.position),
                normal,
                face_normal,
                smooth,
                color,
                uv,
                uv2,
                tangent_u,
                tangent_v,
                uniform_tangents,
                textured,
                bumped,
                glossy,
                object,
            })
        }
    }
}

/// The diffuse light and (when the plan has them) the highlights at one
/// point of a flat or Gouraud triangle, each light's shadow asked once.
fn lights_at(
    plan: &Plan,
    p: Vec3,
    n: Vec3,
    visibility: impl FnMut(usize, &mut Counters) -> f32,
    counters: &mut Counters,
) -> (Vec3, Vec3) {
    let set = LightSet::of(plan);
    let cosine = |_, d, _: &mut Counters| lambert(n, d);
    if plan.specular.is_some() {
        let view = view_dir(plan.eye, p);
        light_with::<true>(&set, p, n, view, cosine, visibility, counters)
    } else {
        light_with::<false>(&set, p, n, Vec3::ZERO, cosine, visibility, counters)
    }
}

/// The specular map's value at `uv` for a `glossy` triangle, else 1.
fn glossiness(plan: &Plan, glossy: bool, uv: Vec2) -> f32 {
    match plan.specular.as_ref().and_then(|s| s.map.as_deref()) {
        Some(map) if glossy => gloss(map, uv.x, uv.y),
        _ => 1.0,
    }
}
