//! Shadow mapping in two passes (docs/shadows.md): the depth of the casters seen
//! from the strong light, then a lookup per shaded point that darkens that
//! light's contribution only.
//!
//! - Which light: the strongest enabled one (the reference scene's white light).
//! - When: only if something can cast onto something else (the plan's
//!   `shadow_light`, from `scene::casters`):
//!   never for a lone convex object, nor for a flat object with the light
//!   and everything else on its front side (a floor lit from above).
//! - The map: a perspective view from the light toward the casters, fitted
//!   to their bounding sphere, so its texels are spent on them; a point
//!   outside that cone, or nearer the light than its near plane, cannot be
//!   behind a caster and is lit. It stores the distance along the light's
//!   axis (w), interpolated as 1/w so it is exact on every triangle.
//! - Closed casters are drawn by their faces turned away from the light
//!   (second-depth shadow mapping): the lit side is never compared against
//!   itself, so it cannot self-shadow ("acne"). Open casters draw both sides.
//!   A point on a face turned away from the light is in shadow without a
//!   lookup (its smoothed normal may light it; its own surface blocks).
//! - A caster with an alpha mask (glTF MASK, MTL `d`/`map_d`) writes only
//!   the texels whose point the mask keeps, as the main pass draws it.
//! - A dense caster (`lod`) is drawn by a simplified stand-in within
//!   about half a texel, when the renderer is told to use them.
//! - The lookup compares with a slope-scaled bias (one texel plus twice
//!   tan θ texels, θ between the surface and the light) over a 3×3
//!   percentage-closer filter: 9 depth compares, soft one-texel edges.

mod depth;
mod lod;
pub use depth::{CHECK_EVERY, Unwatched, Watch};
pub use lod::{CasterLod, MIN_TRIANGLES as LOD_MIN_TRIANGLES, StandInReady};

use glam::{Mat3, Mat4, Vec3};

use relief_core::stats::Counters;
use relief_scene::Scene;
use relief_scene::casters::{Caster, enclose};
use relief_scene::world::World;

/// Smallest and largest shadow map side, in texels.
pub const MIN_SIZE: usize = 256;
pub const MAX_SIZE: usize = 2048;
// The fill's set-up triangles keep their rows and columns in u16.
const _: () = assert!(MAX_SIZE <= u16::MAX as usize);

/// Texels per framebuffer pixel along the frame's longer side.
const SIZE_PER_PIXEL: f32 = 1.5;

/// The depth of the casters seen from one light, reused from frame to frame.
#[derive(Clone, Debug, Default)]
pub struct ShadowMap {
    size: usize,
    /// Distance along the light's axis of the nearest caster, per texel
    /// (row 0 at the top); infinity where no caster is.
    depth: Vec<f32>,
    /// Which object (index in `Scene::objects`) that nearest caster is.
    owner: Vec<u32>,
    /// Per object: whether it may shade itself (not convex).
    self_shadowing: Vec<bool>,
    view_proj: Mat4,
    light: Vec3,
    near: f32,
    /// Width of one texel at unit distance along the axis.
    texel_per_depth: f32,
    /// Width of a texel where they are finest: on the casters' near side.
    finest_texel: f32,
    /// Whether dense casters are drawn by their stand-ins, the stand-ins
    /// made, and how many triangles those drawn in the last pass had.
    caster_lod: CasterLod,
    lods: lod::LodCache,
    stand_in_triangles: usize,
    /// Whether the last pass drew a closed caster as it is (reading its
    /// facets), or drew none yet.
    read_facets: bool,
    /// Scratch of the pass, kept for the next frame: the casters'
    /// triangles set up and sorted into bands, and the vertices projected.
    setups: depth::Setups,
    projected: Vec<[f32; 3]>,
}

/// The shadow of one of the plan's lights, as the shaders see it.
#[derive(Clone, Copy, Debug)]
pub struct Shadow<'a> {
    /// Index of the shadowed light in `Plan::lights`.
    pub light: usize,
    pub map: &'a ShadowMap,
}

impl Shadow<'_> {
    /// The factor of light `index` at point `p` of object `object` with
    /// geometric normal `normal`: 1 for the other lights; for the shadowed
    /// one, the lit fraction (one lookup).
    #[inline]
    pub fn factor(
        &self,
        index: usize,
        p: Vec3,
        normal: Vec3,
        object: u32,
        counters: &mut Counters,
    ) -> f32 {
        if index != self.light {
            return 1.0;
        }
        counters.shadow_lookups += 1;
        self.map.visibility(p, normal, object)
    }
}

impl ShadowMap {
    pub fn new() -> Self {
        ShadowMap::default()
    }

    /// The map's side in texels for a frame of `width × height` pixels.
    pub fn size_for(width: usize, height: usize) -> usize {
        ((width.max(height) as f32 * SIZE_PER_PIXEL) as usize).clamp(MIN_SIZE, MAX_SIZE)
    }

    pub fn size(&self) -> usize {
        self.size
    }

    /// Whether the pass draws dense casters by their stand-ins
    /// (`shadow::lod`); off by default.
    pub fn set_caster_lod(&mut self, mode: CasterLod) {
        self.caster_lod = mode;
    }

    /// What to call when a stand-in made in the background is there.
    pub fn set_stand_in_ready(&mut self, ready: Option<StandInReady>) {
        self.lods.ready = ready;
    }

    /// Whether the last pass read facets: it drew a closed caster as it is
    /// (true before the first pass).
    pub fn read_facets(&self) -> bool {
        self.read_facets || self.size == 0
    }

    /// The triangles of the stand-ins the last pass drew (0: every caster
    /// was drawn as it is).
    pub fn stand_in_triangles(&self) -> usize {
        self.stand_in_triangles
    }

    /// Per texel (row 0 at the top): the distance along the light's axis of
    /// the nearest caster (infinity where none is), and which object that is.
    pub fn texels(&self) -> (&[f32], &[u32]) {
        (&self.depth, &self.owner)
    }

    /// Pass 1: the depth of `casters` (the plan's, found for this light)
    /// seen from `light`, the user's rotation being `rotation`, for a frame
    /// of `width × height`. Returns the counters (texels written).
    pub fn render(
        &mut self,
        scene: &Scene,
        rotation: Mat4,
        light: Vec3,
        casters: &[Caster],
        width: usize,
        height: usize,
    ) -> Counters {
        let world = World::of(scene, rotation);
        let watch = &Unwatched;
        self.render_placed(scene, &world, light, casters, width, height, &[], watch)
    }

    /// [`ShadowMap::render`] of the scene placed as `world` (the frame's
    /// world-space vertices), skipping the repeated triangles of each object
    /// (`scene::repeats`: the pairs of object `i` are `repeats[i]`, none
    /// past the end), which cannot change a texel, telling `watch` how far
    /// it has come and stopping (the map incomplete) as soon as it says so,
    /// asked every few thousand triangles. The map is filled in bands of
    /// rows on the current thread pool; the texels are the same whatever
    /// the bands (docs/shadows.md).
    #[allow(clippy::too_many_arguments)]
    pub fn render_placed(
        &mut self,
        scene: &Scene,
        world: &World,
        light: Vec3,
        casters: &[Caster],
        width: usize,
        height: usize,
        repeats: &[&[(u32, u32)]],
        watch: &dyn Watch,
    ) -> Counters {
        let mut counters = Counters::default();
        let size = Self::size_for(width, height);
        self.size = size;
        self.light = light;
        self.depth.clear();
        self.depth.resize(size * size, f32::INFINITY);
        self.owner.clear();
        self.owner.resize(size * size, u32::MAX);
        self.self_shadowing.clear();
        self.self_shadowing
            .extend(scene.objects.iter().map(|o| !o.mesh.convex));
        if !self.aim(light, casters) {
            self.view_proj = Mat4::ZERO;
            return counters;
        }
        let mut target = depth::Target {
            size,
            depth: &mut self.depth,
            owner: &mut self.owner,
            view_proj: self.view_proj,
            light: self.light,
            near: self.near,
        };
        let threads = rayon::current_num_threads();
        self.setups.start(depth::Bands::for_map(size, threads));
        self.stand_in_triangles = 0;
        self.read_facets = false;
        let mut masks = vec![None; scene.objects.len()];
        let mut whole = true;
        for caster in casters {
            let i = caster.object;
            let mesh = &scene.objects[i].mesh;
            // A texel its alpha mask cuts out casts nothing.
            let cutout = scene.own_terms(i).and_then(|t| t.cutout.as_ref());
            masks[i] = cutout.map(|c| (c, mesh));
            let placed = world.object(i);
            let stand_in = if cutout.is_some() || deformed(scene, i) {
                None
            } else {
                let error = lod::ERROR_TEXELS * self.finest_texel / stretch(placed.linear);
                self.lods.get(i, mesh, error, self.caster_lod)
            };
            let (setups, projected) = (&mut self.setups, &mut self.projected);
            whole = match &stand_in {
                Some(lod) => {
                    self.stand_in_triangles += lod.triangles.len();
                    let (closed, object) = (mesh.closed, i as u32);
                    depth::set_up_lod(
                        &target, lod, closed, placed, object, watch, setups, projected,
                    )
                }
                None => {
                    self.read_facets |= mesh.closed;
                    let repeats = repeats.get(i).copied().unwrap_or(&[]);
                    depth::set_up_mesh(
                        &target, mesh, placed, i as u32, repeats, watch, setups, projected,
                    )
                }
            };
            if !whole {
                break;
            }
        }
        if whole {
            counters.shadow_texels += depth::fill_all(&mut target, &self.setups, &masks, watch);
        }
        counters
    }

    /// Points the map's view from `light` at the casters' bounding sphere,
    /// just wide enough; `false` when there is nothing to aim at or the
    /// light is inside the sphere.
    fn aim(&mut self, light: Vec3, casters: &[Caster]) -> bool {
        let Some((centre, radius)) = enclose(casters) else {
            return false;
        };
        let distance = light.distance(centre);
        if distance.is_nan() || distance <= radius * 1.01 {
            return false;
        }
        let to_centre = (centre - light) / distance;
        let up = if to_centre.cross(Vec3::Y).length_squared() > 1e-6 {
            Vec3::Y
        } else {
            Vec3::X
        };
        // A small margin so silhouettes do not touch the border.
        let half_angle = ((radius / distance).min(1.0).asin() * 1.05).min(80f32.to_radians());
        self.near = (distance - radius) * 0.9;
        let far = distance + radius;
        let proj = Mat4::perspective_rh_gl(2.0 * half_angle, 1.0, self.near, far);
        self.view_proj = proj * Mat4::look_at_rh(light, centre, up);
        self.texel_per_depth = 2.0 * half_angle.tan() / self.size as f32;
        self.finest_texel = self.texel_per_depth * (distance - radius);
        true
    }
    /// Pass 2: the lit fraction (0..1) of the point `p` of object `object`
    /// whose geometric normal is `normal` (turned to the side seen), for
    /// the light the map was drawn from. A point whose geometric normal
    /// turns away from the light is in shadow (0): smoothed vertex normals
    /// can light it, but a ray from it to the light enters its own surface.
    /// Otherwise a convex object's own texels never shade it: it cannot
    /// cast onto itself.
    pub fn visibility(&self, p: Vec3, normal: Vec3, object: u32) -> f32 {
        let size = self.size;
        if size == 0 {
            return 1.0;
        }
        // A surface whose own normal turns away from the light is behind
        // itself: in shadow, whatever its smoothed normal says (the map
        // holds such faces, so it would compare a point with its own depth).
        if normal.dot(self.light - p) < 0.0 {
            return 0.0;
        }
        let clip = self.view_proj * p.extend(1.0);
        let w = clip.w;
        if !w.is_finite() || w <= self.near {
            return 1.0;
        }
        let (nx, ny) = (clip.x / w, clip.y / w);
        if nx.is_nan() || ny.is_nan() || nx.abs() > 1.0 || ny.abs() > 1.0 {
            return 1.0;
        }
        let tx = ((nx * 0.5 + 0.5) * size as f32) as i64;
        let ty = ((0.5 - ny * 0.5) * size as f32) as i64;
        // Slope-scaled bias: one texel, plus the depth change across two
        // texels of a surface at angle θ to the light.
        let to_light = (self.light - p).normalize_or_zero();
        let cos = normal.normalize_or_zero().dot(to_light).abs().max(0.1);
        let tan = (1.0 - cos * cos).max(0.0).sqrt() / cos;
        let bias = w * self.texel_per_depth * (1.0 + 2.0 * tan);
        let limit = w - bias;
        let own_texels_count = self
            .self_shadowing
            .get(object as usize)
            .copied()
            .unwrap_or(true);
        let mut lit = 0u32;
        for dy in -1..=1 {
            for dx in -1..=1 {
                let (x, y) = (tx + dx, ty + dy);
                let inside = x >= 0 && y >= 0 && (x as usize) < size && (y as usize) < size;
                let at = if inside {
                    y as usize * size + x as usize
                } else {
                    0
                };
                let blocked = inside
                    && self.depth[at] < limit
                    && (own_texels_count || self.owner[at] != object);
                lit += u32::from(!blocked);
            }
        }
        lit as f32 / 9.0
    }
}

/// Whether object `i` of `scene` is deformed by an animation (a skin or
/// morph targets): a stand-in made from one pose would stray from another.
fn deformed(scene: &Scene, i: usize) -> bool {
    let part = scene.motion.as_ref().and_then(|m| m.rig.parts.get(i));
    part.is_some_and(|p| p.skin.is_some() || !p.targets.is_empty())
}

/// How far `linear` can stretch a length, at most: its scale when it is a
/// rotation and one scale (a model's placing, as a rule), else the bound
/// its entries give (the Frobenius norm).
fn stretch(linear: Mat3) -> f32 {
    let gram = linear.transpose() * linear;
    let scale2 = gram.x_axis.x.max(gram.y_axis.y).max(gram.z_axis.z);
    let off = gram - Mat3::from_diagonal(glam::Vec3::splat(scale2));
    let similar = off.to_cols_array().iter().all(|v| v.abs() <= 1e-4 * scale2);
    if similar {
        scale2.sqrt()
    } else {
        (gram.x_axis.x + gram.y_axis.y + gram.z_axis.z).sqrt()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A placing's stretch is its scale when it turns and scales evenly,
    /// and never less than its largest stretch otherwise.
    #[test]
    fn a_placing_stretches_lengths_at_most_by_its_stretch() {
        let turn = Mat3::from_rotation_y(0.7) * Mat3::from_rotation_x(-1.2);
        assert!((stretch(turn * 2.5) - 2.5).abs() < 1e-5);
        let uneven = turn * Mat3::from_diagonal(Vec3::new(1.0, 3.0, 0.5));
        let largest = [Vec3::X, Vec3::Y, Vec3::Z, Vec3::ONE.normalize()]
            .iter()
            .map(|v| (uneven * *v).length())
            .fold(0.0, f32::max);
        assert!(
            largest >= 2.99 && stretch(uneven) >= largest,
            "{}",
            stretch(uneven)
        );
        let shear = Mat3::from_cols(Vec3::X, Vec3::new(2.0, 1.0, 0.0), Vec3::Z);
        let sheared = (shear * Vec3::new(1.0, 1.0, 0.0).normalize()).length();
        assert!(stretch(shear) >= sheared, "{} < {sheared}", stretch(shear));
    }
}
