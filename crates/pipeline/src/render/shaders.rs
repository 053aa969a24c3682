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
        let albedo = if plan.colors {
            v.color
        } else {
            plan.uncoloured
        };
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
    let uv = verts.map(|v| v.uv);
    // The specular map's coordinates, when a model's map reads its own.
    let gloss_uv = match plan.terms.as_deref().map(|t| t.uvs.specular) {
        Some(m) if !m.is_vertex_uv() => [0, 1, 2].map(|k| m.at(uv[k], uv2[k])),
        _ => uv,
    };
    let corners = Corners {
        plan,
        verts,
        face_normal,
        side,
        shadow,
        object,
        textured: tri.textured && plan.texture,
        glossy: tri.textured && plan.specular.as_ref().is_some_and(|s| s.map.is_some()),
        uv,
        gloss_uv,
        color: if plan.colors {
            verts.map(|v| v.color)
        } else {
            [plan.uncoloured; 3]
        },
    };
    match plan.shading {
        Shading::Flat => flat_shader(&corners, mesh.facet(t), model, counters),
        Shading::Gouraud => gouraud_shader(&corners, counters),
        Shading::Phong => {
            let bumped = tri.textured && plan.bump;
            phong_shader(&corners, (mesh, t, linear), bumped, uv2)
        }
    }
}

/// What every shading mode reads of a triangle's corners.
struct Corners<'a> {
    plan: &'a Plan,
    verts: &'a [WorldVertex; 3],
    face_normal: Vec3,
    /// 1, or −1 for a back face seen (its normals turned to the eye).
    side: f32,
    shadow: Option<Shadow<'a>>,
    object: u32,
    textured: bool,
    glossy: bool,
    uv: [Vec2; 3],
    gloss_uv: [Vec2; 3],
    /// The vertex colours, or the material's own colour (`Plan::uncoloured`).
    color: [Vec3; 3],
}

/// Flat: one light for the facet, at its centre; a textured triangle
/// reads its texture per pixel, an alpha-masked one its UVs.
fn flat_shader(
    c: &Corners,
    facet: relief_scene::Facet,
    model: &Mat4,
    counters: &mut Counters,
) -> TriShader {
    let (plan, face_normal) = (c.plan, c.face_normal);
    let center = model.transform_point3(facet.center);
    let albedo = if plan.colors {
        facet.color
    } else {
        plan.uncoloured
    };
    let (light, highlight) = lights_at(
        plan,
        center,
        face_normal,
        |i, k: &mut Counters| {
            c.shadow
                .map_or(1.0, |s| s.factor(i, center, face_normal, c.object, k))
        },
        counters,
    );
    // One highlight per facet, the specular map read at its centre.
    let gloss_uv = (c.gloss_uv[0] + c.gloss_uv[1] + c.gloss_uv[2]) / 3.0;
    let highlight = highlight * glossiness(plan, c.glossy, gloss_uv);
    let lit = albedo * light;
    let cut = plan.terms.as_ref().is_some_and(|t| t.cutout.is_some());
    let uv = c.uv;
    if c.textured {
        TriShader::FlatTextured(TexturedFlatTri { lit, uv, highlight })
    } else if cut {
        // One colour, but the alpha mask needs the UVs: Gouraud
        // with the same light at the three corners.
        TriShader::Gouraud(GouraudTri {
            light: [lit; 3],
            highlight: [highlight; 3],
            color: [Vec3::ONE; 3],
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

/// Gouraud: the light at each corner, interpolated.
fn gouraud_shader(c: &Corners, counters: &mut Counters) -> TriShader {
    let (plan, face_normal) = (c.plan, c.face_normal);
    let lit = c.verts.map(|v| {
        let n = if plan.face_normals {
            face_normal
        } else {
            v.normal * c.side
        };
        lights_at(
            plan,
            v.position,
            n,
            |i, k: &mut Counters| {
                c.shadow
                    .map_or(1.0, |s| s.factor(i, v.position, face_normal, c.object, k))
            },
            counters,
        )
    });
    TriShader::Gouraud(GouraudTri {
        light: lit.map(|l| l.0),
        highlight: lit.map(|l| l.1),
        color: c.color,
        uv: c.uv,
        gloss_uv: c.gloss_uv,
        textured: c.textured,
        glossy: c.glossy,
    })
}

/// Phong: positions, normals and tangent axes at the corners, lit per
/// pixel.
fn phong_shader(
    c: &Corners,
    (mesh, t, linear): (&relief_scene::Mesh, usize, &Mat3),
    bumped: bool,
    uv2: [Vec2; 3],
) -> TriShader {
    let (plan, verts, face_normal) = (c.plan, c.verts, c.face_normal);
    let smooth = !plan.face_normals;
    let normal = if smooth {
        verts.map(|v| v.normal * c.side)
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
        color: c.color,
        uv: c.uv,
        uv2,
        tangent_u,
        tangent_v,
        uniform_tangents,
        textured: c.textured,
        bumped,
        glossy: c.glossy,
        object: c.object,
    })
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
