//! A triangle's shader as the rasterizer sees it: the per-triangle data of
//! each kernel family, what every kernel reads besides its triangle, and
//! the [`PixelShader`] trait the kernels (`shade::kernels`) implement.

use glam::{Vec2, Vec3};
use wide::f32x8;

use super::interpolate::lerp2_at;
use super::packet::LANES;
use crate::plan::Plan;
use crate::shadow::Shadow;
use relief_core::framebuffer::Rgb;
use relief_core::stats::Counters;
use relief_texture::Texture;
use relief_texture::sample::mip::Footprint;

/// What every kernel reads besides its triangle.
pub struct ShadeCtx<'a> {
    pub plan: &'a Plan,
    pub texture: &'a Texture,
    /// The shadow map of `plan.shadow_light`, when the plan asked for one.
    pub shadow: Option<Shadow<'a>>,
    /// Whether kernels that can shade eight pixels at a time do (false: every
    /// pixel through the one-pixel loop, which the packets must match bit
    /// for bit; tests compare the two through the renderer's own dispatch).
    pub packets: bool,
}

/// What pixels shaded together by one kernel share (`raster::pending`):
/// the shading context's address and the kernel's variant (each kernel's
/// `defers` gives it).
pub type PendingKey = (usize, u32);

/// The key of pixels shaded under `ctx` (the material) by a kernel's
/// `variant`.
pub fn pending_key(ctx: &ShadeCtx, variant: u32) -> PendingKey {
    (std::ptr::from_ref(ctx) as usize, variant)
}

/// The bit of a [`PendingKey`]'s variant that tells the Phong kernel's
/// pixels from the metallic-roughness kernel's.
pub const PHONG_KIND: u32 = 1 << 8;

/// One pixel's colour from the barycentric coordinates `b` of the pixel
/// centre in the *source* triangle (perspective-correct, summing to 1).
pub trait PixelShader {
    /// Whether the kernel reads the texture (and so may want a footprint).
    const SAMPLES_TEXTURE: bool;
    /// One pixel, from its perspective-correct barycentrics and texture
    /// footprint.
    fn shade(&self, ctx: &ShadeCtx, b: Vec3, fp: Footprint, counters: &mut Counters) -> Rgb;
    /// Eight pixels of a row at once, from their perspective-correct
    /// barycentrics and (when the plan wants them) texture footprints;
    /// `live` has a bit per covered lane (the others are computed and
    /// thrown away, and not counted). Bit for bit `shade` of each lane.
    fn shade8(
        &self,
        ctx: &ShadeCtx,
        b: [f32x8; 3],
        fp: &[Footprint; LANES],
        live: u32,
        counters: &mut Counters,
    ) -> [Rgb; LANES];
    /// Texture coordinates at the source triangle's vertices, for footprints
    /// and the alpha mask.
    fn uvs(&self) -> Option<&[Vec2; 3]> {
        None
    }
    /// Whether `shade8` shades this triangle under this plan (the others
    /// go one pixel at a time).
    fn packets(&self, _ctx: &ShadeCtx) -> bool {
        true
    }
    /// Whether this triangle's pixels may be cut out by an alpha mask
    /// (asked once per triangle; then `opacity` once per covered pixel,
    /// before its depth test): a kernel with texture coordinates under a
    /// masked material.
    fn cutout(&self, ctx: &ShadeCtx) -> bool {
        self.uvs().is_some() && cuts(ctx)
    }
    /// The material's opacity at barycentrics `b` of the source triangle
    /// (asked only when `cutout` said yes).
    fn opacity(&self, ctx: &ShadeCtx, b: Vec3) -> f32 {
        match self.uvs() {
            Some(uv) => opacity_at(ctx, b, uv, self.second_uvs()),
            None => 1.0,
        }
    }
    /// The corners' second texture coordinates, for a kernel that has
    /// them (a transmission map may read them).
    fn second_uvs(&self) -> Option<&[Vec2; 3]> {
        None
    }
    /// The one colour of every pixel, for a kernel that has one: its rows
    /// are filled, not shaded.
    fn solid(&self) -> Option<Rgb> {
        None
    }
    /// For a kernel that can shade eight pixels of different triangles of
    /// its kind at once: its kind, under which a triangle's last, partial
    /// packet waits in the band's queue (`raster::pending`) for other
    /// triangles' pixels.
    fn defers(&self, _ctx: &ShadeCtx) -> Option<PendingKey> {
        None
    }
    /// The most pixels of a triangle's last packet that wait in the queue
    /// (a longer one is shaded at once): a cheap kernel gains less from a
    /// shared packet than gathering each lane's triangle costs.
    const MOST_DEFERRED: usize = LANES;
}

/// Whether the plan's material has an alpha mask.
#[inline]
pub(crate) fn cuts(ctx: &ShadeCtx) -> bool {
    ctx.plan.terms.as_ref().is_some_and(|t| t.cutout.is_some())
}

/// The opacity of the plan's material at barycentrics `b` of a triangle
/// whose vertices have texture coordinates `uv` and, when given, second
/// ones `uv2` (1 without a cutout).
#[inline]
pub(crate) fn opacity_at(ctx: &ShadeCtx, b: Vec3, uv: &[Vec2; 3], uv2: Option<&[Vec2; 3]>) -> f32 {
    match ctx.plan.terms.as_ref().and_then(|t| t.cutout.as_ref()) {
        Some(c) => {
            let at = lerp2_at(b, uv);
            let second = match uv2 {
                Some(uv2) if c.reads_second_set() => lerp2_at(b, uv2),
                _ => at,
            };
            c.opacity(at, second)
        }
        None => 1.0,
    }
}

/// Per-triangle shading data, one variant per kernel family.
#[derive(Clone, Debug)]
pub enum TriShader {
    /// Flat without texture: the whole triangle is one colour.
    Solid(Rgb),
    FlatTextured(TexturedFlatTri),
    Gouraud(GouraudTri),
    Phong(PhongTri),
}

/// Flat lighting, textured: the facet's lit colour times the texel.
#[derive(Clone, Debug)]
pub struct TexturedFlatTri {
    pub lit: Vec3,
    pub uv: [Vec2; 3],
    /// The facet's highlight (zero when specular is off), added after the texel.
    pub highlight: Vec3,
}

/// Gouraud: light computed at the vertices, interpolated with the albedo.
#[derive(Clone, Debug)]
pub struct GouraudTri {
    pub light: [Vec3; 3],
    /// The highlights at the vertices (zero when specular is off), added
    /// after the albedo.
    pub highlight: [Vec3; 3],
    pub color: [Vec3; 3],
    pub uv: [Vec2; 3],
    /// Where the specular map is read at the vertices: `uv`, unless a
    /// model's map reads its own set or transform (`scene::map_uv`; both
    /// are affine, so interpolating them is exact).
    pub gloss_uv: [Vec2; 3],
    pub textured: bool,
    /// The plan's specular map scales the highlight (the triangle has UVs).
    pub glossy: bool,
}

/// Phong: normal, position and albedo interpolated; lighting per pixel.
#[derive(Clone, Debug)]
pub struct PhongTri {
    pub position: [Vec3; 3],
    /// Vertex normals, or three copies of the facet normal.
    pub normal: [Vec3; 3],
    /// The facet normal: used as is for face normals, and as the fallback
    /// when interpolated normals cancel out.
    pub face_normal: Vec3,
    pub smooth: bool,
    pub color: [Vec3; 3],
    pub uv: [Vec2; 3],
    /// The mesh's second texture coordinate set at the vertices (zero when
    /// it has none), for the maps that read it (`scene::map_uv`).
    pub uv2: [Vec2; 3],
    /// ∂P/∂u and ∂P/∂v at the vertices (equal on a flat cube face).
    pub tangent_u: [Vec3; 3],
    pub tangent_v: [Vec3; 3],
    /// The three vertex tangents are the same: skip interpolating them.
    pub uniform_tangents: bool,
    pub textured: bool,
    pub bumped: bool,
    /// The plan's specular map scales the highlight (the triangle has UVs).
    pub glossy: bool,
    /// Index of the object in the scene (whose own shadow a convex one ignores).
    pub object: u32,
}
