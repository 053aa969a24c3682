//! The colour one ray sees, from the formulas of docs/ in f64: the
//! technique's normal or cosine, the diffuse and highlight terms, shadow
//! rays and the mirror reflection.

use glam::{DVec2, DVec3};

use super::geometry::{Hit, Ray, World};
use super::physical::{self, Directions};
use super::read::{bilinear, environment};
use super::setting::{Bump, Setting};
use relief_scene::Scene;
use relief_texture::Level;

/// What every ray of a frame shares.
pub struct Context<'a> {
    pub scene: &'a Scene,
    pub world: &'a World,
    pub setting: &'a Setting,
    pub base: &'a Level,
    pub specular_map: Option<&'a Level>,
    pub ambient: DVec3,
    /// Position and colour of each light that lights.
    pub lights: Vec<(DVec3, DVec3)>,
    /// The light emboss follows and whose shadows are drawn.
    pub strongest: Option<usize>,
}

impl<'a> Context<'a> {
    pub fn new(scene: &'a Scene, world: &'a World, setting: &'a Setting) -> Self {
        let lights: Vec<(DVec3, DVec3)> = if setting.lights {
            scene
                .lights
                .iter()
                .filter(|l| l.enabled && l.color.max_element() > 0.0)
                .filter(|l| l.position.is_finite() && l.color.is_finite())
                .map(|l| (l.position.as_dvec3(), l.color.as_dvec3()))
                .collect()
        } else {
            Vec::new()
        };
        // The brightest (largest colour sum), the first of equals.
        let mut strongest: Option<(usize, f64)> = None;
        for (i, (_, c)) in lights.iter().enumerate() {
            let power = c.x + c.y + c.z;
            if strongest.is_none_or(|(_, p)| power > p) {
                strongest = Some((i, power));
            }
        }
        Context {
            scene,
            world,
            setting,
            base: scene.material.texture.base(),
            specular_map: scene.material.specular_map.as_deref(),
            ambient: scene.ambient.as_dvec3(),
            lights,
            strongest: strongest.map(|(i, _)| i),
        }
    }
}

/// The height F (alpha) at (u, v), continuous.
fn height(level: &Level, uv: DVec2) -> f64 {
    bilinear(level, uv.x, uv.y)[3]
}

/// F_u, F_v per unit of texture coordinate: central differences one texel
/// apart on the continuous height (the derivative docs/bump-blinn.md names).
fn gradient(level: &Level, uv: DVec2) -> (f64, f64) {
    let (du, dv) = (1.0 / level.width as f64, 1.0 / level.height as f64);
    let f = |u: f64, v: f64| bilinear(level, u, v)[3];
    (
        (f(uv.x + du, uv.y) - f(uv.x - du, uv.y)) / (2.0 * du),
        (f(uv.x, uv.y + dv) - f(uv.x, uv.y - dv)) / (2.0 * dv),
    )
}

/// Blinn: N' = normalise(N + k (F_u (N × P_v) − F_v (N × P_u))); k changes
/// sign where (P_u × P_v)·N < 0 (a mirrored frame).
fn blinn(n: DVec3, pu: DVec3, pv: DVec3, (fu, fv): (f64, f64), k: f64) -> DVec3 {
    let k = if pu.cross(pv).dot(n) < 0.0 { -k } else { k };
    let p = n + k * (fu * n.cross(pv) - fv * n.cross(pu));
    if p.length_squared() > 1e-40 {
        p.normalize()
    } else {
        n
    }
}

/// The orthonormal tangent frame (T, B, N) at a point: T is P_u with its
/// normal part taken out, B is P_v with its normal and T parts taken out
/// (pointing along +v), N the unit normal.
fn frame(n: DVec3, pu: DVec3, pv: DVec3) -> (DVec3, DVec3) {
    let t = (pu - n * n.dot(pu)).normalize_or(n.any_orthonormal_vector());
    let b = pv - n * n.dot(pv) - t * t.dot(pv);
    let b = if b.length_squared() > 1e-30 {
        b.normalize()
    } else {
        n.cross(t)
    };
    (t, b)
}

/// Where the ray meets the height field carved below the triangle's plane
/// (docs/bump-parallax.md): height 1 is the plane, height 0 lies at depth
/// D = k·|P_u × P_v| along the face normal. Marched from the plane down in
/// steps of at most a quarter texel of travel and D/16 of depth, the
/// crossing then bisected to 1e-12 of D: the texture coordinate there.
pub(super) fn relief(base: &Level, ray: &Ray, hit: &Hit, k: f64) -> DVec2 {
    let (pu, pv, nf) = (hit.tangent_u, hit.tangent_v, hit.face_normal);
    let depth = k * pu.cross(pv).length();
    let dir = ray.dir.normalize();
    let c = -dir.dot(nf);
    if depth <= 0.0 || c <= 1e-12 {
        return hit.uv;
    }
    // Per unit of depth the ray moves `along` in the plane; as texture
    // coordinates, the least-squares solution of P_u·du + P_v·dv = along.
    let along = (dir + nf * c) / c;
    let (a, b, d) = (pu.dot(pu), pu.dot(pv), pv.dot(pv));
    let det = a * d - b * b;
    if det.abs() < 1e-300 {
        return hit.uv;
    }
    let (ru, rv) = (pu.dot(along), pv.dot(along));
    let per_depth = DVec2::new(d * ru - b * rv, a * rv - b * ru) / det;
    let uv_at = |z: f64| hit.uv + per_depth * z;
    // Above the relief while z < D·(1 − F): f < 0.
    let f = |z: f64| z - depth * (1.0 - height(base, uv_at(z)));
    if f(0.0) >= 0.0 {
        return hit.uv;
    }
    let texel = 1.0 / base.width.max(base.height) as f64;
    let speed = per_depth.length();
    let step = if speed > 0.0 {
        (depth / 16.0).min(0.25 * texel / speed)
    } else {
        depth / 16.0
    };
    let (mut lo, mut hi) = (0.0, depth);
    let mut z = 0.0;
    while z < depth {
        let next = (z + step).min(depth);
        if f(next) >= 0.0 {
            (lo, hi) = (z, next);
            break;
        }
        z = next;
    }
    while hi - lo > 1e-12 * depth {
        let mid = 0.5 * (lo + hi);
        if f(mid) >= 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    uv_at(hi)
}

/// The colour the ray sees at `hit`, before clamping: the physical
/// truth's for a model view's metallic-roughness materials (`physical`,
/// lit from the environment in `directions`), else the formulas of the
/// reference scenes.
pub fn shade(ctx: &Context, ray: &Ray, hit: &Hit, directions: &Directions) -> DVec3 {
    if let Some(p) = &ctx.setting.physical
        && let Some(terms) = ctx.scene.own_terms(hit.object)
        && let Some(pbr) = &terms.pbr
    {
        let material = ctx.scene.own_material(hit.object);
        let texture = material.map_or(&ctx.scene.material.texture, |m| &m.texture);
        let surface = physical::Surface {
            pbr,
            terms,
            texture: (ctx.setting.texture && hit.textured).then(|| texture.base()),
            lights: &ctx.lights,
            attenuation: ctx.setting.attenuation,
            eye: ctx.world.eye(),
        };
        let mut hit_colour = hit.clone();
        if !ctx.setting.colors {
            hit_colour.color = DVec3::ONE;
        }
        return physical::shade(p, &surface, &hit_colour, directions);
    }
    let surface = Surface::at(ctx, ray, hit);
    let albedo = albedo(ctx, hit, surface.uv);
    let (diffuse, highlight) = surface.lighting(ctx);
    let lit = albedo * diffuse + highlight;
    surface.reflected(ctx, lit)
}

/// What the lights meet at a hit: the point, its normals and texel.
struct Surface {
    p: DVec3,
    /// The interpolated (or face) normal, before any bump.
    smooth: DVec3,
    /// The normal the technique shades with (emboss keeps the smooth one and
    /// changes the strongest light's cosine instead).
    n: DVec3,
    pu: DVec3,
    pv: DVec3,
    /// Where the texture is read (moved by relief's march).
    uv: DVec2,
    /// Unit direction toward the eye.
    view: DVec3,
    bump: Bump,
    /// The bump strength k.
    k: f64,
    /// The highlight's scale from the specular map (1 without one).
    gloss: f64,
}

impl Surface {
    fn at(ctx: &Context, ray: &Ray, hit: &Hit) -> Surface {
        let s = ctx.setting;
        let smooth = if s.face_normals {
            hit.face_normal
        } else {
            hit.normal.normalize_or(hit.face_normal)
        };
        let k = s.bump_strength;
        let bump = if hit.textured { s.bump } else { Bump::None };
        let (pu, pv) = (hit.tangent_u, hit.tangent_v);
        let uv = match bump {
            Bump::Relief => relief(ctx.base, ray, hit, k),
            _ => hit.uv,
        };
        let n = shading_normal(ctx.base, hit, bump, smooth, uv, k);
        let p = hit.position;
        let view = (ctx.world.eye() - p).normalize_or_zero();
        Surface {
            p,
            smooth,
            n,
            pu,
            pv,
            uv,
            view,
            bump,
            k,
            gloss: gloss(ctx, hit, uv),
        }
    }

    /// The ambient plus each light's diffuse term, and the highlights.
    fn lighting(&self, ctx: &Context) -> (DVec3, DVec3) {
        let s = ctx.setting;
        let mut diffuse = ctx.ambient;
        let mut highlight = DVec3::ZERO;
        for (i, &(position, colour)) in ctx.lights.iter().enumerate() {
            let d = position - self.p;
            let len = d.length();
            if len == 0.0 || !len.is_finite() {
                continue;
            }
            let l = d / len;
            let cosine = self.cosine(ctx, i, l);
            if cosine <= 0.0 {
                continue;
            }
            let att = if s.attenuation {
                1.0 / (1.0 + 0.01 * len * len)
            } else {
                1.0
            };
            let seen = if self.shadowed(ctx, i, position) {
                0.0
            } else {
                1.0
            };
            diffuse += colour * cosine.min(1.0) * att * seen;
            if let Some(shininess) = s.shininess {
                let h = (l + self.view).normalize_or_zero();
                let power = self.n.dot(h).max(0.0).powf(shininess);
                highlight += colour * self.gloss * (power * att).min(1.0) * seen;
            }
        }
        (diffuse, highlight)
    }

    /// N·L for light `i` in unit direction `l`, with emboss's change when
    /// it is the strongest light and faces the point.
    fn cosine(&self, ctx: &Context, i: usize, l: DVec3) -> f64 {
        let cosine = self.n.dot(l);
        if self.bump == Bump::Emboss && Some(i) == ctx.strongest && cosine > 0.0 {
            let e = emboss(ctx.base, self.smooth, self.pu, self.pv, self.uv, l, self.k);
            (cosine + e).max(0.0)
        } else {
            cosine
        }
    }

    /// Whether light `i` at `position` is hidden: only the strongest
    /// light casts shadows, and only when they are drawn.
    fn shadowed(&self, ctx: &Context, i: usize, position: DVec3) -> bool {
        ctx.setting.shadows && Some(i) == ctx.strongest && ctx.world.occluded(self.p, position)
    }

    /// `lit` mixed with the environment's mirror reflection, if the
    /// setting has one.
    fn reflected(&self, ctx: &Context, lit: DVec3) -> DVec3 {
        let (n, view) = (self.n, self.view);
        match &ctx.setting.environment {
            Some((map, reflectivity)) => {
                let r = n * (2.0 * n.dot(view)) - view;
                lit * (1.0 - reflectivity) + environment(map.picture(), r) * *reflectivity
            }
            None => lit,
        }
    }
}

/// The normal `bump` shades with at `uv`, from the smooth normal `smooth`.
fn shading_normal(base: &Level, hit: &Hit, bump: Bump, smooth: DVec3, uv: DVec2, k: f64) -> DVec3 {
    let (pu, pv) = (hit.tangent_u, hit.tangent_v);
    match bump {
        Bump::None | Bump::Emboss => smooth,
        Bump::Blinn | Bump::Relief => blinn(smooth, pu, pv, gradient(base, uv), k),
        Bump::Dot3 => {
            // n = normalise(−2k·F_u, −2k·F_v, 1) in (T, B, N), taken out of
            // tangent space: its dot with L is n · L_t.
            let (fu, fv) = gradient(base, uv);
            let (t, b) = frame(smooth, pu, pv);
            let m = DVec3::new(-2.0 * k * fu, -2.0 * k * fv, 1.0).normalize();
            (t * m.x + b * m.y + smooth * m.z).normalize()
        }
    }
}

/// The vertex colour (or white), times the texture where the hit is textured.
fn albedo(ctx: &Context, hit: &Hit, uv: DVec2) -> DVec3 {
    let s = ctx.setting;
    let mut albedo = if s.colors { hit.color } else { DVec3::ONE };
    if s.texture && hit.textured {
        let t = bilinear(ctx.base, uv.x, uv.y);
        albedo *= DVec3::new(t[0], t[1], t[2]);
    }
    albedo
}

/// The specular map's mean channel at `uv`, or 1 without a map or texture.
fn gloss(ctx: &Context, hit: &Hit, uv: DVec2) -> f64 {
    match (ctx.specular_map, hit.textured) {
        (Some(map), true) => {
            let g = bilinear(map, uv.x, uv.y);
            (g[0] + g[1] + g[2]) / 3.0
        }
        _ => 1.0,
    }
}

/// Emboss's change to N·L for the unit light direction `l`
/// (docs/bump-emboss.md): e = F(uv) − F(uv + Δ), Δ one texel (of the larger
/// side) along the light's tangent part weighted like Blinn's cross
/// products, (|P_v|·L·T, |P_u|·L·B) / max(|P_u|, |P_v|), divided by that
/// texel and scaled by k·max(|P_u|, |P_v|): to first order
/// −k·(|P_v|·F_u·L·T + |P_u|·F_v·L·B), Blinn's change of N·L.
fn emboss(base: &Level, n: DVec3, pu: DVec3, pv: DVec3, uv: DVec2, l: DVec3, k: f64) -> f64 {
    let (t, b) = frame(n, pu, pv);
    let (lu, lv) = (pu.length(), pv.length());
    let m = lu.max(lv);
    if m <= 0.0 {
        return 0.0;
    }
    let texel = 1.0 / base.width.max(base.height) as f64;
    let toward = DVec2::new(lv * l.dot(t), lu * l.dot(b));
    let shifted = uv + toward * (texel / m);
    (height(base, uv) - height(base, shifted)) * k * m / texel
}
