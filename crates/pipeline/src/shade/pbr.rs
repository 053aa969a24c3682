//! The metallic-roughness kernel (docs/shading.md, "Metallic-roughness"):
//! a model's glTF material in the model view, per pixel, in linear light.
//!
//! Base colour = vertex colour × factor (linear) × the colour texture
//! decoded from sRGB; metallic and roughness = their factors × the map's
//! blue and green; the normal map's normal in the pixel's tangent frame;
//! a dielectric's F0 and F90 from `KHR_materials_specular`'s factors and
//! maps, a clearcoat's intensity, roughness and normal from
//! `KHR_materials_clearcoat`'s, a sheen's colour and roughness from
//! `KHR_materials_sheen`'s (each map read only by a material that has it).
//! Each light adds (1 − F)(1 − metallic)·base + π·F·D·V, times its colour
//! and N·L (a light of colour 1 gives a white Lambert surface facing it 1);
//! the environment adds its image-based light (by default spherical
//! harmonics for the diffuse part, prefiltered levels and the split-sum
//! table for the specular part, `texture::ibl`; `--ibl-diffuse integrated`
//! reads an exact irradiance map instead, `--ibl-specular sampled` samples
//! the lobe, `shade::sampled`) with the occlusion map on it; a sheen
//! scales all that by 1 − max(colour)·E(N·V) and adds its own lobe
//! (`shade::sheen`) per light and from the environment; emission is
//! added; a clearcoat goes over everything; then exposure, the tone map and
//! the sRGB encoding, once.
//!
//! One source for one pixel and eight (`shade::lanes`); texels and shadow
//! lookups are read lane by lane where the packet read does not apply.

use std::sync::Arc;

use glam::{Vec2, Vec3};
use wide::f32x8;

use super::PhongTri;
use super::brdf::{
    self, MIN_ROUGHNESS, distribution, fresnel, saturate, srgb_to_linear, visibility,
};
use super::core::colour;
use super::lanes::{Lanes, Vector};
use super::lighting::{ATTENUATION_QUADRATIC, finish, physical_falloff};
use super::map_uv::{Coords, carry, footprint_map};
use super::packet::{self, LANES, V3};
use super::sampled::sample_lobe;
use super::shader::{PendingKey, PixelShader, ShadeCtx, pending_key};
use super::sheen::{self, MIN_SHEEN_ROUGHNESS, charlie, neubelt};
use super::specular::view_dir;
use super::split_sum::lut;
use super::tangent::{Surface, Tris};
use crate::plan::Physical;
use relief_core::framebuffer::Rgb;
use relief_core::settings::{IblDiffuse, IblSpecular};
use relief_core::stats::Counters;
use relief_scene::light::Falloff;
use relief_scene::map_uv::MapUv;
use relief_scene::terms::{Clearcoat, DIELECTRIC_F0, MaterialTerms, PbrMaterial, Sheen};
use relief_texture::environment::Environment;
use relief_texture::ibl::Ibl;
use relief_texture::ibl::prefilter::{OctMap, oct_uv};
use relief_texture::ibl::radiance::RadianceLevels;
use relief_texture::sample::filter::{normal_reads_base, read_normal};
use relief_texture::sample::mip::Footprint;
use relief_texture::{Level, NormalMap};

/// A metallic-roughness triangle: with or without its colour texture
/// (`TEX`) and normal map (`NMAP`).
pub struct PbrKernel<'a, const TEX: bool, const NMAP: bool> {
    pub tri: &'a PhongTri,
    pub terms: &'a MaterialTerms,
    pub pbr: &'a PbrMaterial,
    pub physical: &'a Physical,
    /// The environment's light, when the plan has an environment.
    pub light: Option<EnvLight<'a>>,
}

/// What the kernel reads of the environment, as `--ibl-diffuse` and
/// `--ibl-specular` choose: chosen once per triangle, so a pixel's only
/// cost of the choice is one predictable branch per part.
#[derive(Clone, Copy)]
pub struct EnvLight<'a> {
    pub diffuse: DiffuseLight<'a>,
    pub specular: SpecularLight<'a>,
}

/// The environment's diffuse light.
#[derive(Clone, Copy)]
pub enum DiffuseLight<'a> {
    /// Nine spherical-harmonic coefficients (`irradiance`).
    Sh(&'a [Vec3; 9]),
    /// The exact irradiance map (`texture::ibl::irradiance`), read
    /// bilinearly.
    Integrated(&'a OctMap),
}

/// The environment's specular light.
#[derive(Clone, Copy)]
pub enum SpecularLight<'a> {
    /// Prefiltered levels and the split-sum table.
    Prefiltered(&'a Ibl),
    /// The lobe sampled per pixel (`shade::sampled`).
    Sampled(&'a RadianceLevels),
}

impl<'a> EnvLight<'a> {
    /// The parts of `environment`'s light the settings ask for (each made
    /// on its first use and kept with the environment).
    pub fn of(environment: &'a Environment, physical: &Physical) -> EnvLight<'a> {
        EnvLight {
            diffuse: match physical.ibl_diffuse {
                IblDiffuse::Sh => DiffuseLight::Sh(&environment.light().sh),
                IblDiffuse::Integrated => DiffuseLight::Integrated(environment.irradiance_map()),
            },
            specular: match physical.ibl_specular {
                IblSpecular::Prefiltered => SpecularLight::Prefiltered(environment.light()),
                IblSpecular::Sampled => SpecularLight::Sampled(environment.radiance_levels()),
            },
        }
    }
}

/// What the light loop reads at the pixels.
struct At<V: Vector> {
    p: V,
    n: V,
    view: V,
    nv: V::L,
    /// Lambert's colour: (1 − metallic)·base.
    diffuse: V,
    /// Reflectance head on and at grazing angles (Schlick's F0 and F90).
    f0: V,
    f90: V::L,
    alpha2: V::L,
    /// The clearcoat layer, when the material has one.
    coat: Option<Coat<V>>,
    /// The sheen layer, when the material has one.
    sheen: Option<SheenAt<V>>,
}

/// A sheen layer at the pixels: its colour and roughness (factors times
/// maps), on the material's normal (mapped or not).
struct SheenAt<V: Vector> {
    colour: V,
    /// The Charlie distribution's α: the sheen roughness squared.
    alpha: V::L,
    /// The lobe's directional albedo E(N·V, roughness).
    albedo: V::L,
    /// Where the lobe gathers the environment's light from:
    /// normalize(a·N + g·(V − N·(N·V))), from the table.
    along_n: V::L,
    along_view: V::L,
    /// What the material below keeps: 1 − max(colour)·E(N·V).
    keeps: V::L,
}

/// A clearcoat layer at the pixels: on the surface's own normal (not the
/// normal map's) or its own normal map's, with its own roughness and
/// intensity (their factors times their maps).
struct Coat<V: Vector> {
    n: V,
    nv: V::L,
    roughness: V::L,
    alpha2: V::L,
    factor: V::L,
}

impl<V: Vector> Coat<V> {
    /// A layer of intensity `factor` and roughness `roughness` (both in
    /// 0..=1) on the normal `n`, seen along `view`.
    #[inline(always)]
    fn new(n: V, view: V, factor: V::L, roughness: V::L) -> Self {
        let nv = brdf::max(n.dot(view), V::L::splat(1e-4)).min(V::L::ONE);
        let roughness = brdf::max(roughness, V::L::splat(MIN_ROUGHNESS));
        let alpha = roughness * roughness;
        Coat {
            n,
            nv,
            roughness,
            alpha2: alpha * alpha,
            factor,
        }
    }

    /// What the layer lets through of the light below it: 1 − factor·F(N·V).
    #[inline(always)]
    fn passes(&self) -> V::L {
        let f = V::L::splat(DIELECTRIC_F0);
        V::L::ONE - self.factor * (f + (V::L::ONE - f) * brdf::schlick_weight(self.nv))
    }

    /// The layer's own reflection of a light in direction `l`, half vector
    /// `h`: π·F·D·V with F0 0.04, times N·L on its own normal.
    #[inline(always)]
    fn reflects(&self, l: V, h: V, vh: V::L) -> V::L {
        let nl = saturate(self.n.dot(l));
        let nh = saturate(self.n.dot(h));
        let f = V::L::splat(DIELECTRIC_F0);
        let f = f + (V::L::ONE - f) * brdf::schlick_weight(vh);
        f * distribution(self.alpha2, nh)
            * visibility(self.alpha2, nl, self.nv)
            * V::L::splat(std::f32::consts::PI)
            * nl
    }
}

impl<const TEX: bool, const NMAP: bool> PbrKernel<'_, TEX, NMAP> {
    /// The colour of the pixels at barycentrics `b`, encoded for display
    /// (before quantising).
    #[inline(always)]
    fn shade_lanes<V: Vector>(
        &self,
        ctx: &ShadeCtx,
        b: [V::L; 3],
        fp: &[Footprint],
        live: u32,
        counters: &mut Counters,
    ) -> V {
        let s = Surface::<V>::at(self.tri, &b);
        self.shade_surface(ctx, (Tris::One(self.tri), s), b, (fp, live), counters)
    }

    /// The colour of the pixels of surface `s` on triangles `tris`, at
    /// barycentrics `b`, encoded for display (before quantising).
    #[inline(always)]
    fn shade_surface<V: Vector>(
        &self,
        ctx: &ShadeCtx,
        (tris, s): (Tris, Surface<V>),
        b: [V::L; 3],
        (fp, live): (&[Footprint], u32),
        counters: &mut Counters,
    ) -> V {
        let (tri, terms, pbr) = (self.tri, self.terms, self.pbr);
        let count = live.count_ones() as u64;
        counters.pixels_shaded += count;
        let at = Coords {
            uv: (s.u, s.v),
            b: &b,
            uv2: &tri.uv2,
        };
        let mut base = s.albedo;
        if TEX {
            counters.texture_samples += count;
            base = base * srgb_to_linear(colour::<V>(ctx, s.u, s.v, fp, live));
        }
        if terms.unlit {
            return brdf::display(base, self.physical.exposure, self.physical.tone_map);
        }
        let (metallic, roughness) = self.metallic_roughness::<V::L>(at);
        let metallic = saturate(metallic);
        let roughness = brdf::max(saturate(roughness), V::L::splat(MIN_ROUGHNESS));
        let n = if NMAP {
            self.mapped_normal(ctx, (tris, &s), at, (fp, live), counters)
        } else {
            s.n
        };
        let view = view_dir(ctx.plan.eye, s.p);
        // A normal turned away from the eye (interpolated or mapped) is lit
        // as if grazing, not from behind.
        let nv = brdf::max(n.dot(view), V::L::splat(1e-4)).min(V::L::ONE);
        let (dielectric, weight) = self.dielectric::<V>(at);
        let alpha = roughness * roughness;
        let px = At {
            p: s.p,
            n,
            view,
            nv,
            diffuse: base * (V::L::ONE - metallic),
            f0: dielectric + (base - dielectric) * metallic,
            f90: weight + (V::L::ONE - weight) * metallic,
            alpha2: alpha * alpha,
            coat: pbr
                .clearcoat
                .as_ref()
                .map(|c| self.coat(c, ctx, (tris, &s, view), at, (fp, live), counters)),
            sheen: pbr.sheen.as_ref().map(|sh| self.sheen(sh, nv, at)),
        };
        let (direct, coat_direct, sheen_direct) = self.lights(ctx, &px, (tris, live), counters);
        let lit = direct + self.ambient(&px, roughness, at, live);
        // A sheen keeps 1 − max(colour)·E(N·V) of the material below it (for
        // the lights and the environment alike) and adds its own lobe.
        let lit = match &px.sheen {
            Some(sh) => lit * sh.keeps + sheen_direct + self.sheen_ambient(sh, &px, at, live),
            None => lit,
        };
        let lit = lit + emission(terms, at);
        // A clearcoat lets 1 − c·F through of all that is below it (the
        // emission too) and adds its own reflection, times c.
        let lit = match &px.coat {
            Some(c) => {
                lit * c.passes() + (coat_direct + self.coat_ambient(c, view, live)) * c.factor
            }
            None => lit,
        };
        brdf::display(lit, self.physical.exposure, self.physical.tone_map)
    }

    /// Metallic and roughness at the pixels: their factors times the
    /// map's channels, before clamping.
    #[inline(always)]
    fn metallic_roughness<L: Lanes>(&self, at: Coords<L>) -> (L, L) {
        let pbr = self.pbr;
        let (mut metallic, mut roughness) = (L::splat(pbr.metallic), L::splat(pbr.roughness));
        if pbr.roughness_map.is_none() && pbr.metallic_map.is_none() {
            return (metallic, roughness);
        }
        let (u, v) = at.of(&self.terms.uvs.specular);
        match (&pbr.roughness_map, &pbr.metallic_map) {
            // glTF's one map: one read for both.
            (Some((a, r)), Some((b, m))) if std::sync::Arc::ptr_eq(a, b) => {
                let t = L::bilinear(a, u, v);
                roughness = roughness * t[*r];
                metallic = metallic * t[*m];
            }
            (r, m) => {
                if let Some((map, c)) = r {
                    roughness = roughness * L::bilinear(map, u, v)[*c];
                }
                if let Some((map, c)) = m {
                    metallic = metallic * L::bilinear(map, u, v)[*c];
                }
            }
        }
        (metallic, roughness)
    }

    /// A dielectric's reflectance head on (weight included) and at grazing
    /// angles: `KHR_materials_specular`'s F0 = min(f0·colour, 1)·w and F90
    /// = w, the colour and the weight w times their maps where the
    /// material has them.
    #[inline(always)]
    fn dielectric<V: Vector>(&self, at: Coords<V::L>) -> (V, V::L) {
        let pbr = self.pbr;
        let weight = V::L::splat(pbr.specular_weight);
        let Some(maps) = &pbr.specular_maps else {
            return (V::uniform(pbr.dielectric_f0), weight);
        };
        let uvs = &self.terms.uvs;
        let colour = factor_times_srgb::<V>(
            maps.f0_colour,
            maps.colour.as_deref(),
            &uvs.specular_colour,
            at,
        );
        let one = V::L::ONE;
        let colour = V::new(
            colour.x().min(one),
            colour.y().min(one),
            colour.z().min(one),
        );
        let weight = match &maps.strength {
            Some(map) => {
                let (u, v) = at.of(&uvs.specular_strength);
                weight * V::L::bilinear(map, u, v)[0]
            }
            None => weight,
        };
        (colour * weight, weight)
    }

    /// The clearcoat layer at the pixels of surface `s` seen along `view`:
    /// its factor and roughness times their maps (one read when one picture
    /// holds both), on its own normal map when it has one and normal maps
    /// are on, else on the surface's normal.
    #[inline(always)]
    fn coat<V: Vector>(
        &self,
        c: &Clearcoat,
        ctx: &ShadeCtx,
        (tris, s, view): (Tris, &Surface<V>, V),
        at: Coords<V::L>,
        (fp, live): (&[Footprint], u32),
        counters: &mut Counters,
    ) -> Coat<V> {
        let uvs = &self.terms.uvs;
        let (mut factor, mut roughness) = (V::L::splat(c.factor), V::L::splat(c.roughness));
        match (&c.factor_map, &c.roughness_map) {
            (Some((a, k)), Some((b, r))) if Arc::ptr_eq(a, b) && uvs.coat == uvs.coat_roughness => {
                let (u, v) = at.of(&uvs.coat);
                let t = V::L::bilinear(a, u, v);
                factor = factor * t[*k];
                roughness = roughness * t[*r];
            }
            (f, r) => {
                if let Some((map, k)) = f {
                    let (u, v) = at.of(&uvs.coat);
                    factor = factor * V::L::bilinear(map, u, v)[*k];
                }
                if let Some((map, k)) = r {
                    let (u, v) = at.of(&uvs.coat_roughness);
                    roughness = roughness * V::L::bilinear(map, u, v)[*k];
                }
            }
        }
        let n = match c.normal.as_deref() {
            Some(map) if self.tri.bumped => {
                let read = (map, &uvs.coat_normal);
                self.normal_from(read, ctx, (tris, s), at, (fp, live), counters)
            }
            _ => s.n,
        };
        Coat::new(n, view, saturate(factor), saturate(roughness))
    }

    /// The sheen layer at the pixels seen at N·V = `nv`: its colour (factor
    /// × the colour map decoded from sRGB) and roughness (factor × the
    /// roughness map, held ≥ the minimum), the lobe's albedo and mean
    /// direction from the table, read lane by lane.
    #[inline(always)]
    fn sheen<V: Vector>(&self, sh: &Sheen, nv: V::L, at: Coords<V::L>) -> SheenAt<V> {
        let uvs = &self.terms.uvs;
        let colour =
            factor_times_srgb::<V>(sh.colour, sh.colour_map.as_deref(), &uvs.sheen_colour, at);
        let mut roughness = V::L::splat(sh.roughness);
        if let Some(map) = &sh.roughness_map {
            let (u, v) = at.of(&uvs.sheen_roughness);
            roughness = roughness * V::L::bilinear(map, u, v)[0];
        }
        let roughness = brdf::max(saturate(roughness), V::L::splat(MIN_SHEEN_ROUGHNESS));
        let table = sheen::table();
        let [albedo, along_n, along_view] = table.read(nv, roughness);
        let peak = brdf::max(brdf::max(colour.x(), colour.y()), colour.z());
        SheenAt {
            colour,
            alpha: roughness * roughness,
            albedo,
            along_n,
            along_view,
            keeps: V::L::ONE - peak * albedo,
        }
    }

    /// The environment's light on the sheen: its colour × E(N·V) × the
    /// irradiance about the direction the lobe gathers from (N leaning
    /// towards the eye; exact for a uniform environment, docs/shading.md,
    /// "Sheen"), read as the diffuse part reads it (the spherical
    /// harmonics, or the integrated map), times the occlusion map.
    #[inline(always)]
    fn sheen_ambient<V: Vector>(
        &self,
        sh: &SheenAt<V>,
        px: &At<V>,
        at: Coords<V::L>,
        live: u32,
    ) -> V {
        let Some(env) = self.light else {
            return V::uniform(Vec3::ZERO);
        };
        let (c, s) = self.physical.turn;
        // The view's part across the normal (from the true N·V: a normal
        // turned from the eye, whose N·V is held at 1e-4, leans no lower).
        let side = px.view - px.n * px.n.dot(px.view);
        let gather = (px.n * sh.along_n + side * sh.along_view).normalize_or(px.n);
        let gather = turned(gather, c, s);
        let irradiance = match env.diffuse {
            DiffuseLight::Sh(coefficients) => irradiance(coefficients, gather),
            DiffuseLight::Integrated(map) => {
                V::gather(live, |i| map.read_seamless(oct_uv(gather.lane(i))))
            }
        };
        let mut light = sh.colour * sh.albedo * irradiance;
        if let Some((map, strength)) = &self.terms.occlusion {
            let (u, v) = at.of(&self.terms.uvs.occlusion);
            let occ = V::L::bilinear(map, u, v)[0];
            light = light * (V::L::ONE + V::L::splat(*strength) * (occ - V::L::ONE));
        }
        light
    }

    /// The normal map's normal at the pixels, in their tangent frame.
    #[inline(always)]
    fn mapped_normal<V: Vector>(
        &self,
        ctx: &ShadeCtx,
        (tris, s): (Tris, &Surface<V>),
        at: Coords<V::L>,
        (fp, live): (&[Footprint], u32),
        counters: &mut Counters,
    ) -> V {
        let Some(map) = self.pbr.normal.as_deref() else {
            return s.n;
        };
        let read = (map, &self.terms.uvs.normal);
        self.normal_from(read, ctx, (tris, s), at, (fp, live), counters)
    }

    /// Normal map `map`, read at its coordinates `m`, at the pixels, in
    /// their tangent frame.
    #[inline(always)]
    fn normal_from<V: Vector>(
        &self,
        (map, m): (&NormalMap, &MapUv),
        ctx: &ShadeCtx,
        (tris, s): (Tris, &Surface<V>),
        at: Coords<V::L>,
        (fp, live): (&[Footprint], u32),
        counters: &mut Counters,
    ) -> V {
        counters.bump_evals += live.count_ones() as u64;
        let plan = ctx.plan;
        let (u, v) = at.of(m);
        let t = if normal_reads_base(plan.height_derivative, plan.filter) {
            let [x, y, z] = V::L::normal_bilinear(map, u, v, live);
            V::new(x, y, z)
        } else {
            let to_of = |t: &PhongTri| footprint_map(m, &t.uv, &t.uv2);
            let one = match tris {
                Tris::One(t) => to_of(t),
                Tris::Each(_) => None,
            };
            V::gather(live, |i| {
                let to = match tris {
                    Tris::One(_) => one,
                    Tris::Each(t) => to_of(t[i]),
                };
                let uv = Vec2::new(u.lane(i), v.lane(i));
                let f = carry(fp.get(i).copied().unwrap_or_default(), to);
                Vec3::from(read_normal(map, plan.height_derivative, plan.filter, uv, f))
            })
        };
        let f = s.frame();
        (f.t * t.x() + f.b * t.y() + f.n * t.z()).normalize_or(s.n)
    }

    /// Σ over the lights of colour × N·L × ((1 − F)·diffuse + π·F·D·V),
    /// each scaled by its attenuation and shadow; and the same sums of the
    /// clearcoat layer's own reflection and of the sheen's lobe
    /// colour·π·D·V (Charlie, Neubelt) (zero without the layer).
    #[inline(always)]
    fn lights<V: Vector>(
        &self,
        ctx: &ShadeCtx,
        px: &At<V>,
        (tris, live): (Tris, u32),
        counters: &mut Counters,
    ) -> (V, V, V) {
        let plan = ctx.plan;
        let zero = V::L::ZERO;
        let mut sum = V::uniform(Vec3::ZERO);
        let mut coat_sum = V::uniform(Vec3::ZERO);
        let mut sheen_sum = V::uniform(Vec3::ZERO);
        counters.light_evals += live.count_ones() as u64 * plan.lights.len() as u64;
        for (i, light) in plan.lights.iter().enumerate() {
            let d = V::uniform(light.position) - px.p;
            let len2 = d.dot(d);
            let l = d * (V::L::ONE / len2.sqrt());
            let nl = px.n.dot(l);
            let inf = V::L::splat(f32::INFINITY);
            let reached = V::L::both(nl.gt(zero), || V::L::both(len2.gt(zero), || len2.lt(inf)));
            if V::L::skips(reached) || V::L::none(reached) {
                continue;
            }
            let h = (l + px.view).normalize_or(px.n);
            let nh = saturate(px.n.dot(h));
            let vh = saturate(px.view.dot(h));
            let nl = saturate(nl);
            let f = fresnel(px.f0, px.f90, vh);
            let specular = distribution(px.alpha2, nh)
                * visibility(px.alpha2, nl, px.nv)
                * V::L::splat(std::f32::consts::PI);
            let one = V::uniform(Vec3::ONE);
            let brdf = (one - f) * px.diffuse + f * specular;
            let mut k = nl;
            // The layer's reflection takes the same falloff and shadow.
            let mut kc = px.coat.as_ref().map(|c| c.reflects(l, h, vh));
            match light.falloff {
                Falloff::Setting if plan.attenuation => {
                    let q = V::L::ONE + V::L::splat(ATTENUATION_QUADRATIC) * len2;
                    k = k / q;
                    kc = kc.map(|kc| kc / q);
                }
                Falloff::Setting | Falloff::None => {}
                falloff @ Falloff::InverseSquare { .. } => {
                    let f = physical_falloff(falloff, d, len2);
                    k = k * f;
                    kc = kc.map(|kc| kc * f);
                }
            }
            if let Some(sh) = ctx.shadow
                && sh.light == i
            {
                let lanes = V::L::bits(reached) & live;
                let [seen] = V::L::gather(lanes, 1.0, |lane| {
                    let p = px.p.lane(lane);
                    let t = tris.lane(lane);
                    [sh.factor(i, p, t.face_normal, t.object, counters)]
                });
                k = k * seen;
                kc = kc.map(|kc| kc * seen);
            }
            let add = brdf * V::uniform(light.color) * k;
            sum = sum + V::select(reached, add, V::uniform(Vec3::ZERO));
            if let Some(sh) = &px.sheen {
                // The fibres' lobe, with the base's N·L, falloff and shadow.
                let lobe = charlie(sh.alpha, V::L::ONE - nh * nh)
                    * neubelt(nl, px.nv)
                    * V::L::splat(std::f32::consts::PI);
                let add = sh.colour * V::uniform(light.color) * (lobe * k);
                sheen_sum = sheen_sum + V::select(reached, add, V::uniform(Vec3::ZERO));
            }
            if let Some(kc) = kc {
                let add = V::uniform(light.color) * kc;
                coat_sum = coat_sum + V::select(reached, add, V::uniform(Vec3::ZERO));
            }
        }
        (sum, coat_sum, sheen_sum)
    }

    /// The environment's light: irradiance(N)·diffuse·(1 − S) +
    /// prefiltered(R, roughness)·S with S = F0·A + F90·B from the split-sum
    /// table, times the occlusion map; or, as the settings ask, the exact
    /// irradiance map's E(N)/π for the SH's, and the lobe sampled
    /// (`shade::sampled`: its reflected radiance and its own S) for the
    /// prefiltered levels and the table. No environment: no light from
    /// everywhere.
    #[inline(always)]
    fn ambient<V: Vector>(&self, px: &At<V>, roughness: V::L, at: Coords<V::L>, live: u32) -> V {
        let Some(env) = self.light else {
            return V::uniform(Vec3::ZERO);
        };
        let (c, s) = self.physical.turn;
        let n = turned(px.n, c, s);
        let one = V::uniform(Vec3::ONE);
        let (specular, reflected) = match env.specular {
            SpecularLight::Prefiltered(ibl) => {
                let r = turned(px.n * (px.nv + px.nv) - px.view, c, s);
                let [a, b] = lut().read(px.nv, roughness);
                let prefiltered = prefiltered(ibl, r, roughness, live);
                let specular = px.f0 * a + one * (px.f90 * b);
                (specular, specular * prefiltered)
            }
            SpecularLight::Sampled(levels) => {
                let view = turned(px.view, c, s);
                sample_lobe(levels, n, view, px.nv, px.f0, px.f90, roughness, live)
            }
        };
        let irradiance = match env.diffuse {
            DiffuseLight::Sh(coefficients) => irradiance(coefficients, n),
            DiffuseLight::Integrated(map) => {
                V::gather(live, |i| map.read_seamless(oct_uv(n.lane(i))))
            }
        };
        let diffuse = px.diffuse * (one - specular) * irradiance;
        let mut light = diffuse + reflected;
        if let Some((map, strength)) = &self.terms.occlusion {
            let (u, v) = at.of(&self.terms.uvs.occlusion);
            let occ = V::L::bilinear(map, u, v)[0];
            light = light * (V::L::ONE + V::L::splat(*strength) * (occ - V::L::ONE));
        }
        light
    }

    /// The environment's light on the clearcoat layer: prefiltered(R,
    /// roughness)·(0.04·A + B), on the layer's own normal; or its lobe
    /// sampled with F0 = 0.04, as the settings ask.
    #[inline(always)]
    fn coat_ambient<V: Vector>(&self, c: &Coat<V>, view: V, live: u32) -> V {
        let Some(env) = self.light else {
            return V::uniform(Vec3::ZERO);
        };
        let (cos, sin) = self.physical.turn;
        match env.specular {
            SpecularLight::Prefiltered(ibl) => {
                let r = turned(c.n * (c.nv + c.nv) - view, cos, sin);
                let [a, b] = lut().read(c.nv, c.roughness);
                let prefiltered = prefiltered(ibl, r, c.roughness, live);
                prefiltered * (V::L::splat(DIELECTRIC_F0) * a + b)
            }
            SpecularLight::Sampled(levels) => {
                let n = turned(c.n, cos, sin);
                let view = turned(view, cos, sin);
                let f0 = V::uniform(Vec3::splat(DIELECTRIC_F0));
                sample_lobe(levels, n, view, c.nv, f0, V::L::ONE, c.roughness, live).1
            }
        }
    }
}

/// The prefiltered levels' radiance about the lanes' reflected directions
/// `r` (normalised here; a zero or non-finite one reads +Y) for their
/// roughness, in the lanes of `live`.
#[inline(always)]
fn prefiltered<V: Vector>(ibl: &Ibl, r: V, roughness: V::L, live: u32) -> V {
    let r = r.normalize_or(V::uniform(Vec3::Y));
    let r = [r.x().to_x8(), r.y().to_x8(), r.z().to_x8()];
    let [x, y, z] = ibl.specular_lanes(r, roughness.to_x8(), live);
    V::new(V::L::from_x8(x), V::L::from_x8(y), V::L::from_x8(z))
}

/// The irradiance over π at unit normals `n` from the nine SH
/// coefficients `c` (`texture::ibl::sh`'s basis, per lane): nine
/// multiply-adds per channel; never below 0 (the truncated series can ring
/// below 0 opposite a bright light).
#[inline(always)]
pub fn irradiance<V: Vector>(c: &[Vec3; 9], n: V) -> V {
    let (x, y, z) = (n.x(), n.y(), n.z());
    let k = V::L::splat;
    let basis = [
        k(0.282_094_8),
        k(0.488_602_5) * y,
        k(0.488_602_5) * z,
        k(0.488_602_5) * x,
        k(1.092_548_4) * x * y,
        k(1.092_548_4) * y * z,
        k(0.315_391_57) * (k(3.0) * z * z - V::L::ONE),
        k(1.092_548_4) * x * z,
        k(0.546_274_2) * (x * x - y * y),
    ];
    let mut sum = V::uniform(Vec3::ZERO);
    for (ci, bi) in c.iter().zip(basis) {
        sum = sum + V::uniform(*ci) * bi;
    }
    let zero = V::L::ZERO;
    let pos = |x: V::L| V::L::select(x.gt(zero), x, zero);
    V::new(pos(sum.x()), pos(sum.y()), pos(sum.z()))
}

/// Direction `d` in the environment's frame when the environment is
/// turned by the angle of cosine `c` and sine `s` about +Y (so the
/// environment turns with positive angles from +Z toward +X).
#[inline(always)]
pub fn turned<V: Vector>(d: V, c: f32, s: f32) -> V {
    let (c, s) = (V::L::splat(c), V::L::splat(s));
    V::new(c * d.x() - s * d.z(), d.y(), s * d.x() + c * d.z())
}

/// The light given off: the emissive factor (linear) times the emissive
/// map decoded from sRGB.
#[inline(always)]
fn emission<V: Vector>(terms: &MaterialTerms, at: Coords<V::L>) -> V {
    if terms.emissive == Vec3::ZERO {
        return V::uniform(Vec3::ZERO);
    }
    factor_times_srgb(
        terms.emissive,
        terms.emissive_map.as_deref(),
        &terms.uvs.emissive,
        at,
    )
}

/// A colour factor (linear) times its map, if any, read bilinearly at its
/// coordinates `m` and decoded from sRGB: the emissive, specular and sheen
/// colours alike.
#[inline(always)]
fn factor_times_srgb<V: Vector>(
    factor: Vec3,
    map: Option<&Level>,
    m: &MapUv,
    at: Coords<V::L>,
) -> V {
    match map {
        Some(map) => {
            let (u, v) = at.of(m);
            let [r, g, b] = V::L::bilinear(map, u, v);
            V::uniform(factor) * srgb_to_linear(V::new(r, g, b))
        }
        None => V::uniform(factor),
    }
}

impl<'a, const TEX: bool, const NMAP: bool> PbrKernel<'a, TEX, NMAP> {
    /// The same triangle and material in another variant.
    pub fn variant<const T: bool, const N: bool>(&self) -> PbrKernel<'a, T, N> {
        PbrKernel {
            tri: self.tri,
            terms: self.terms,
            pbr: self.pbr,
            physical: self.physical,
            light: self.light,
        }
    }

    /// The kind of kernel whose pixels may be shaded together in the
    /// band's queue: the context (the material), the variant and whether
    /// the triangle's normal maps apply.
    fn kind(ctx: &ShadeCtx, bumped: bool) -> PendingKey {
        let variant = u32::from(TEX) | u32::from(NMAP) << 1 | u32::from(bumped) << 2;
        pending_key(ctx, variant)
    }

    /// Eight pixels of different triangles of this kernel's kind, one per
    /// lane (`tris`), at their barycentrics `b`: bit for bit what each
    /// triangle's own kernel shades there (the kernel's triangle is one of
    /// them: what it holds beyond the pixels' own is the same for all).
    pub fn shade_each(
        &self,
        ctx: &ShadeCtx,
        (tris, b): (&[&PhongTri; LANES], [f32x8; 3]),
        fp: &[Footprint; LANES],
        live: u32,
        counters: &mut Counters,
    ) -> [Rgb; LANES] {
        let s = Surface::each(tris, &b, true);
        let c: V3 = self.shade_surface(ctx, (Tris::Each(tris), s), b, (fp, live), counters);
        packet::finish(c, live, counters)
    }
}

impl<const TEX: bool, const NMAP: bool> PixelShader for PbrKernel<'_, TEX, NMAP> {
    const SAMPLES_TEXTURE: bool = true;
    #[inline]
    fn shade(&self, ctx: &ShadeCtx, b: Vec3, fp: Footprint, counters: &mut Counters) -> Rgb {
        let c: Vec3 = self.shade_lanes(ctx, [b.x, b.y, b.z], &[fp], 1, counters);
        finish(c, counters)
    }
    fn uvs(&self) -> Option<&[Vec2; 3]> {
        Some(&self.tri.uv)
    }
    fn second_uvs(&self) -> Option<&[Vec2; 3]> {
        Some(&self.tri.uv2)
    }
    #[inline]
    fn shade8(
        &self,
        ctx: &ShadeCtx,
        b: [f32x8; 3],
        fp: &[Footprint; LANES],
        live: u32,
        counters: &mut Counters,
    ) -> [Rgb; LANES] {
        let c: V3 = self.shade_lanes(ctx, b, fp, live, counters);
        packet::finish(c, live, counters)
    }
    /// A material whose maps read only the vertices' first set: then a
    /// pixel's shading needs of its triangle only what `shade_each` takes
    /// per lane.
    fn defers(&self, ctx: &ShadeCtx) -> Option<PendingKey> {
        (!self.terms.uvs.reads_second_set()).then(|| Self::kind(ctx, self.tri.bumped))
    }
}
