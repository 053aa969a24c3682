//! The frame: plan → transform → cull/clip/setup → bands of rows rasterized
//! and shaded (in parallel when the frame is big enough to gain).

mod abandon;
mod awake;
mod backdrop;
mod bands;
mod dispatch;
mod progress;
mod rasterize;
mod repeat_cache;
mod shaders;
mod strokes;
mod triangles;

use abandon::Abandon;
pub use abandon::CancelHook;
use bands::depth_first_pays;
pub use dispatch::{draw_owned_triangle, draw_triangle};
pub use progress::{FrameProgress, FrameStep};
use repeat_cache::RepeatCache;
use triangles::{ObjectView, TriChunk, join_chunks, run_chunks};

use std::sync::Arc;
use std::time::Instant;

use glam::{Vec3, Vec4};

use crate::plan::Plan;
use crate::raster::ScreenTri;
use crate::raster::aa::{MSAA_REACH, MSAA_SAMPLES, resolve_box};
use crate::raster::alpha::order_blended;
use crate::raster::clip::outcode;
use crate::raster::frames::{DepthView, draw_tangent_frames};
use crate::raster::setup::Projected;
use crate::raster::wire::WireTri;
use crate::shade::TriShader;
use crate::shadow::{CasterLod, Shadow, ShadowMap, StandInReady};
use relief_core::framebuffer::{Framebuffer, Rgb};
use relief_core::settings::ssaa_factor;
use relief_core::settings::{AntiAlias, Display, Settings};
use relief_core::stats::{Counters, FrameStats};
use relief_scene::terms::MaterialTerms;
use relief_scene::world::{World, fill_three_runs};
use relief_scene::{Scene, model_view};

/// Reusable buffers: one `Renderer` per view keeps allocations across frames.
#[derive(Default)]
pub struct Renderer {
    /// The scene placed for the frame, read by every pass.
    world: World,
    clip: Vec<Vec4>,
    /// Per vertex of the object being prepared: its clip outcode, and its
    /// screen position when inside every plane.
    codes: Vec<u8>,
    projected: Vec<Option<Projected>>,
    shaders: Vec<TriShader>,
    /// The material group (index in the frame's plans) of each shader,
    /// filled only when objects have materials of their own.
    shader_groups: Vec<u32>,
    tris: Vec<ScreenTri>,
    depth: Vec<f32>,
    /// Per pixel, the triangle a depth pre-pass found nearest (when the
    /// frame draws depth first).
    owner: Vec<u32>,
    /// The triangle stage's buffers, one per chunk of triangles.
    chunks: Vec<TriChunk>,
    /// Visible triangles of the points and lines displays.
    wire: Vec<WireTri>,
    /// The supersampled frame, kept between frames.
    supersampled: Option<Framebuffer>,
    /// Multisampled colours and depths, kept between frames.
    msaa_color: Vec<[Rgb; MSAA_SAMPLES]>,
    msaa_depth: Vec<[f32; MSAA_SAMPLES]>,
    /// The shadow map, kept between frames.
    shadow: ShadowMap,
    /// Width over height of a pixel where the frame is shown (`None`:
    /// square): the sub-cell symbol sets have tall pixels.
    pixel_aspect: Option<f32>,
    /// The repeated triangles of each object's mesh, which add nothing
    /// behind a depth buffer (`scene::repeats`).
    repeats: RepeatCache,
    /// Asked during each frame whether to abandon it.
    cancel: Option<CancelHook>,
    /// Told how far each frame has come.
    progress: Option<Arc<FrameProgress>>,
    /// No shadow pass even where the plan asks for one (`set_shadows`).
    no_shadows: bool,
    /// Every pixel shaded with its own triangle (`set_shared_packets`).
    no_shared_packets: bool,
    /// The model view's last framing, and what it was made for.
    fit: Option<(FrameKey, Option<model_view::Fit>)>,
    /// The environment drawn behind the model, kept between frames.
    backdrop: backdrop::BackdropCache,
}

/// What a model view's framing depends on.
#[derive(Clone, Copy, Debug, PartialEq)]
struct FrameKey {
    model: u64,
    pose: [u32; 3],
    up: relief_core::settings::UpAxis,
    fov: u32,
    aspect: u32,
}

impl Renderer {
    pub fn new() -> Self {
        Renderer::default()
    }

    /// Frames will be shown with pixels `aspect` times as wide as tall: the
    /// projection widens the view by it so shapes keep their proportions.
    pub fn set_pixel_aspect(&mut self, aspect: f32) {
        self.pixel_aspect = (aspect.is_finite() && aspect > 0.0 && aspect != 1.0).then_some(aspect);
    }

    /// From now on each frame asks `hook` as it goes and stops when it says
    /// so (`FrameStats::abandoned`); `None`: frames always finish.
    pub fn set_cancel(&mut self, hook: Option<CancelHook>) {
        self.cancel = hook;
    }

    /// From now on each frame counts its progress in `progress` (read by a
    /// view on another thread while a long frame runs).
    pub fn set_progress(&mut self, progress: Option<Arc<FrameProgress>>) {
        self.progress = progress;
    }

    /// `false`: frames draw no shadow map and light every point as if
    /// nothing stood between it and the lights, as a renderer without
    /// shadows does (`relief bench --anchors --model`, to draw what Mesa
    /// llvmpipe draws). On by default.
    pub fn set_shadows(&mut self, on: bool) {
        self.no_shadows = !on;
    }

    /// `false`: each triangle shades its own pixels, its last few in a
    /// packet of their own, instead of leaving them to be shaded with
    /// other small triangles' (`raster::pending`). The same pictures and
    /// counters either way (the tests compare the two); on by default.
    pub fn set_shared_packets(&mut self, on: bool) {
        self.no_shared_packets = !on;
    }

    /// Whether the shadow pass draws a dense caster (of
    /// `shadow::LOD_MIN_TRIANGLES` triangles or more, not cut out nor
    /// deformed) by a simplified stand-in (docs/shadows.md, "Dense
    /// casters"). Off by default: with [`CasterLod::Background`] what a
    /// frame draws depends on whether the stand-in was made in time.
    pub fn set_caster_lod(&mut self, mode: CasterLod) {
        self.shadow.set_caster_lod(mode);
    }

    /// What the thread that made a stand-in with [`CasterLod::Background`]
    /// calls once it is there (the view draws again), if anything.
    pub fn set_stand_in_ready(&mut self, ready: Option<StandInReady>) {
        self.shadow.set_stand_in_ready(ready);
    }

    /// The triangles of the stand-ins the last frame's shadow pass drew.
    pub fn stand_in_triangles(&self) -> usize {
        self.shadow.stand_in_triangles()
    }

    /// Draws `scene` into `fb` and says what it cost. Output is identical
    /// for any number of threads.
    pub fn render(
        &mut self,
        scene: &Scene,
        settings: &Settings,
        fb: &mut Framebuffer,
    ) -> FrameStats {
        let start = Instant::now();
        let mut stats = FrameStats::default();
        let (width, height) = (fb.width(), fb.height());
        if width == 0 || height == 0 {
            return stats;
        }
        let _awake = awake::Awake::start();
        // Normal maps built this frame: the height map's, and a file map's
        // copies for another strength.
        let normal_map_builds = |scene: &Scene| {
            scene.material.texture.normal_map_builds()
                + scene.material.normal_map.as_ref().map_or(0, |m| m.builds())
        };
        let cancel = self.cancel.clone();
        let progress = self.progress.clone();
        let abandon = Abandon::new(cancel.as_deref(), progress.as_deref());
        let normal_maps_before = normal_map_builds(scene);
        let base = self.plan_of(scene, settings, width, height);
        let plans = FramePlans::new(scene, settings, base);
        let plan = &plans.plans[0];
        let mips_before = scene.material.texture.mips_built();
        let normal_mips_built =
            |plan: &Plan| plan.normal_map.as_ref().is_some_and(|m| m.mips_built());
        let normal_mips_before = normal_mips_built(plan);
        // Supersampling draws k times larger, then box-filters down.
        let k = ssaa_factor(plan.aa, width, height);
        let facets = self.pass_reads_facets(plan);
        // Taken out of `self` for the frame so the shaders can borrow it.
        let mut shadow_map = std::mem::take(&mut self.shadow);
        self.repeats.update(scene);
        // Every facet is made only for the shadow pass, which reads them all.
        self.world.place(scene, plan.rotation, plan.eye, facets);
        let (shadow, mut counters) = shadow_pass(
            (!self.no_shadows).then_some(&mut shadow_map),
            scene,
            &self.world,
            plan,
            &self.repeats,
            &abandon,
            width * k,
            height * k,
        );
        counters += self.prepare(scene, &plans, shadow, width * k, height * k);
        counters.normal_map_builds += normal_map_builds(scene) - normal_maps_before;
        stats.plan_time = start.elapsed();

        let raster_start = Instant::now();
        counters += self.draw_scaled(scene, &plans, shadow, fb, k, &abandon, &mut stats);
        self.shadow = shadow_map;
        if !mips_before && scene.material.texture.mips_built() {
            counters.mip_builds += 1;
        }
        if !normal_mips_before && normal_mips_built(plan) {
            counters.mip_builds += 1;
        }
        stats.raster_time = raster_start.elapsed();
        stats.counters = counters;
        stats.abandoned = abandon.stopped();
        stats
    }

    /// Rasterizes the prepared triangles, then the strokes and tangent
    /// frames, into `fb`: directly, or `k` times larger and box-filtered
    /// down (supersampling).
    #[allow(clippy::too_many_arguments)]
    fn draw_scaled(
        &mut self,
        scene: &Scene,
        plans: &FramePlans,
        shadow: Option<Shadow>,
        fb: &mut Framebuffer,
        k: usize,
        abandon: &Abandon,
        stats: &mut FrameStats,
    ) -> Counters {
        if k <= 1 {
            return self.draw(scene, plans, shadow, fb, 1, abandon, stats);
        }
        let mut big = self
            .supersampled
            .take()
            .unwrap_or_else(|| Framebuffer::new(0, 0));
        big.resize(fb.width() * k, fb.height() * k);
        let counters = self.draw(scene, plans, shadow, &mut big, k, abandon, stats);
        resolve_box(&big, k, fb);
        self.supersampled = Some(big);
        counters
    }

    /// Rasterizes the prepared triangles, then the strokes and tangent
    /// frames, into `target` (`k` times the frame's size).
    #[allow(clippy::too_many_arguments)]
    fn draw(
        &mut self,
        scene: &Scene,
        plans: &FramePlans,
        shadow: Option<Shadow>,
        target: &mut Framebuffer,
        k: usize,
        abandon: &Abandon,
        stats: &mut FrameStats,
    ) -> Counters {
        let plan = &plans.plans[0];
        let (mut counters, bands) = self.rasterize(scene, plans, shadow, target, k, abandon);
        (stats.bands_drawn, stats.bands) = bands;
        counters += self.strokes(scene, plan, target, k);
        counters += self.tangent_frames(scene, plan, target, k);
        counters
    }

    /// The screen triangles of a frame (after culling, clipping and setup),
    /// with the plan and shaders they go with: for tests that rasterize
    /// triangles one by one.
    pub fn screen_triangles(
        &mut self,
        scene: &Scene,
        settings: &Settings,
        width: usize,
        height: usize,
    ) -> (&[ScreenTri], &[TriShader]) {
        let base = self.plan_of(scene, settings, width, height);
        let plans = FramePlans::new(scene, settings, base);
        let plan = &plans.plans[0];
        let facets = self.pass_reads_facets(plan);
        let mut shadow_map = std::mem::take(&mut self.shadow);
        self.repeats.update(scene);
        self.world.place(scene, plan.rotation, plan.eye, facets);
        let (shadow, _) = shadow_pass(
            (!self.no_shadows).then_some(&mut shadow_map),
            scene,
            &self.world,
            plan,
            &self.repeats,
            &Abandon::new(None, None),
            width,
            height,
        );
        self.prepare(scene, &plans, shadow, width, height);
        self.shadow = shadow_map;
        (&self.tris, &self.shaders)
    }

    /// The frame's plan, seen through the framing camera when the scene
    /// is in the model view (`scene::model_view`).
    fn plan_of(&mut self, scene: &Scene, settings: &Settings, width: usize, height: usize) -> Plan {
        let mut plan = Plan::new(scene, settings);
        let Some(view) = scene.model_view else {
            return plan;
        };
        // The file's own camera, where the author put it.
        if let Some(camera) = view.camera.and_then(|k| scene.cameras.get(k)) {
            plan.camera = *camera;
            plan.eye = camera.shading_eye();
            return plan;
        }
        let aspect = width as f32 / height as f32 * self.pixel_aspect.unwrap_or(1.0);
        let pose = view.pose.unwrap_or(settings.rotation);
        let key = FrameKey {
            model: view.id,
            pose: pose.to_array().map(f32::to_bits),
            up: settings.up,
            fov: settings.fov.to_bits(),
            aspect: aspect.to_bits(),
        };
        let fit = match &self.fit {
            Some((k, fit)) if *k == key => *fit,
            _ => {
                let fit = model_view::fit_scene(scene, pose, settings.up, settings.fov, aspect);
                self.fit = Some((key, fit));
                fit
            }
        };
        if let Some(fit) = fit {
            plan.camera = model_view::framed_camera(&scene.camera, fit);
            plan.camera.fov_y_degrees = settings.fov;
            plan.eye = plan.camera.eye;
        }
        plan
    }

    /// Whether the frame of `plan` draws a shadow map (the plan asks for
    /// one and the renderer is not told to skip it): its pass reads every
    /// facet.
    fn draws_shadow_map(&self, plan: &Plan) -> bool {
        plan.shadow_light.is_some() && !self.no_shadows
    }

    /// Whether the frame of `plan` should make every facet for its shadow
    /// pass: it draws a shadow map, and the last one drew a closed caster
    /// as it is (the stand-ins' facets are their corners'; a pass that
    /// finds a facet missing makes it).
    fn pass_reads_facets(&self, plan: &Plan) -> bool {
        self.draws_shadow_map(plan) && self.shadow.read_facets()
    }

    /// Projects the placed vertices (`self.world`, culled there), clips,
    /// sets triangles up and builds their shaders. Returns the counters of the work done here (per-vertex and
    /// per-facet lighting).
    fn prepare(
        &mut self,
        scene: &Scene,
        plans: &FramePlans,
        shadow: Option<Shadow>,
        width: usize,
        height: usize,
    ) -> Counters {
        let plan = &plans.plans[0];
        let mut counters = Counters::default();
        self.wire.clear();
        self.shaders.clear();
        self.shader_groups.clear();
        self.tris.clear();
        let aspect = width as f32 / height as f32 * self.pixel_aspect.unwrap_or(1.0);
        let view_proj = plan.camera.projection(aspect) * plan.camera.view();
        // Multisampling covers samples off the pixel centres: a sliver
        // between two rows of centres still has samples inside.
        let reach = if plan.aa == AntiAlias::Msaa4 {
            MSAA_REACH
        } else {
            0
        };
        for (object_index, object) in scene.objects.iter().enumerate() {
            let group = plans.of_object[object_index];
            let plan = &plans.plans[group];
            let placed = self.world.object(object_index);
            project_vertices(
                placed,
                view_proj,
                (width, height),
                (&mut self.clip, &mut self.codes, &mut self.projected),
            );
            let clip = &self.clip;
            // Behind a depth buffer a repeated triangle changes nothing.
            let skips_repeats = plan.display == Display::Fill && plan.depth;
            let view = ObjectView {
                plan,
                object,
                object_index: object_index as u32,
                placed,
                clip,
                codes: &self.codes,
                projected: &self.projected,
                repeats: if skips_repeats {
                    self.repeats.of(object_index)
                } else {
                    &[]
                },
                shadow,
                width,
                height,
                reach,
            };
            // Joined in triangle order, each chunk's shader indices moved
            // past the shaders before it.
            let chunks = run_chunks(&mut self.chunks, &view);
            for chunk in chunks.iter() {
                counters += chunk.counters;
            }
            let added = join_chunks(chunks, &mut self.tris, &mut self.shaders, &mut self.wire);
            if plans.plans.len() > 1 {
                self.shader_groups
                    .extend(std::iter::repeat_n(group as u32, added));
            }
        }
        self.order_blended(plans);
        counters.triangles_drawn = self.tris.len() as u64;
        counters
    }

    /// Translucent triangles after the opaque ones, far to near
    /// (`raster::alpha`); nothing moves in a frame without them.
    fn order_blended(&mut self, plans: &FramePlans) {
        let blends: Vec<bool> = plans
            .plans
            .iter()
            .map(|p| {
                let cutout = p.terms.as_ref().and_then(|t| t.cutout.as_ref());
                cutout.is_some_and(|c| c.blend)
            })
            .collect();
        if !blends.contains(&true) {
            return;
        }
        let groups = &self.shader_groups;
        let group = |t: &ScreenTri| groups.get(t.shader as usize).map_or(0, |&g| g as usize);
        order_blended(&mut self.tris, |t| blends[group(t)]);
    }

    /// Clears and draws the frame: bands of pixels (or of samples, with
    /// multisampling), or the wireframe. `brush` is the supersampling factor,
    /// which widens lines and points so they keep their size. Returns the
    /// counters, and the bands drawn whole and in all.
    fn rasterize(
        &mut self,
        scene: &Scene,
        plans: &FramePlans,
        shadow: Option<Shadow>,
        fb: &mut Framebuffer,
        brush: usize,
        abandon: &Abandon,
    ) -> (Counters, (usize, usize)) {
        let plan = &plans.plans[0];
        let background = scene.background;
        if plan.display != Display::Fill {
            let counters = rasterize::draw_wire(&self.wire, plan, background, fb, brush);
            return (counters, (1, 1));
        }
        let ctx = rasterize::material_ctxs(
            scene,
            (&plans.plans, &plans.textures),
            shadow,
            &self.shader_groups,
        );
        let (width, height) = (fb.width(), fb.height());
        let aspect = width as f32 / height as f32 * self.pixel_aspect.unwrap_or(1.0);
        let backdrop = self.backdrop.of(plan, background, (width, height, aspect));
        let (parallel, bounds) = rasterize::band_bounds(&self.tris, &self.shaders, width, height);
        let drawing = rasterize::Drawing {
            width,
            bounds: &bounds,
            parallel,
            tris: &self.tris,
            shaders: &self.shaders,
            ctx: &ctx,
            backdrop,
            abandon,
            shared_packets: !self.no_shared_packets,
        };
        if plan.aa == AntiAlias::Msaa4 {
            let depth = plan.depth.then_some(&mut self.msaa_depth);
            return rasterize::draw_msaa(&drawing, &mut self.msaa_color, depth, fb);
        }
        // Depth before shading, where overdraw would multiply the shading
        // (alpha masks excepted: their depth depends on the texture).
        let cutout = plans
            .plans
            .iter()
            .any(|p| p.terms.as_ref().is_some_and(|t| t.cutout.is_some()));
        if plan.depth && !cutout && depth_first_pays(&self.tris) {
            return rasterize::draw_depth_first(&drawing, &mut self.depth, &mut self.owner, fb);
        }
        let depth = plan.depth.then_some(&mut self.depth);
        rasterize::draw_single_pass(&drawing, depth, fb)
    }
}

impl Renderer {
    /// The tangent frames over the drawn frame (crates/pipeline/src/raster/frames.rs), their
    /// origins tested against the depth buffer this frame filled, if any.
    fn tangent_frames(
        &self,
        scene: &Scene,
        plan: &Plan,
        fb: &mut Framebuffer,
        brush: usize,
    ) -> Counters {
        if !plan.tangent_frames {
            return Counters::default();
        }
        let depth = match (plan.display, plan.depth, plan.aa) {
            (Display::Fill, true, AntiAlias::Msaa4) => DepthView::Samples(&self.msaa_depth),
            (Display::Fill, true, _) => DepthView::Pixels(&self.depth),
            _ => DepthView::None,
        };
        // The surfaces' projection: the pixels' shape widens the view.
        let aspect = fb.width() as f32 / fb.height() as f32 * self.pixel_aspect.unwrap_or(1.0);
        draw_tangent_frames(scene, &self.world, plan, depth, fb, (brush, aspect))
    }
}

/// The plans of one frame: the scene material's first, then one per
/// distinct own material of the objects (docs/models.md), with the
/// texture each draws and the plan of each object.
struct FramePlans<'s> {
    plans: Vec<Plan>,
    textures: Vec<&'s relief_texture::Texture>,
    of_object: Vec<usize>,
}

impl<'s> FramePlans<'s> {
    fn new(scene: &'s Scene, settings: &Settings, base: Plan) -> Self {
        let (materials, of_object) = scene.material_groups();
        let mut plans = vec![base];
        let mut textures = vec![&*scene.material.texture];
        for (k, material) in materials.into_iter().enumerate() {
            let any_textured = scene
                .objects
                .iter()
                .zip(&of_object)
                .filter(|(_, g)| **g == k + 1)
                .any(|(o, _)| o.mesh.triangles.iter().any(|t| t.textured));
            plans.push(plans[0].for_material(material, any_textured, settings));
            textures.push(&material.texture);
        }
        // Objects with extra terms: a plan per material group and terms.
        let mut of_object = of_object;
        let mut with_terms: Vec<(usize, *const MaterialTerms, usize)> = Vec::new();
        for (i, group) in of_object.iter_mut().enumerate() {
            let Some(terms) = scene.own_terms(i) else {
                continue;
            };
            let key = (*group, Arc::as_ptr(terms));
            *group = match with_terms.iter().find(|(g, t, _)| (*g, *t) == key) {
                Some(&(_, _, k)) => k,
                None => {
                    plans.push(plans[*group].with_terms(terms));
                    textures.push(textures[*group]);
                    with_terms.push((key.0, key.1, plans.len() - 1));
                    plans.len() - 1
                }
            };
        }
        let mut frame = FramePlans {
            plans,
            textures,
            of_object,
        };
        if scene.model_view.is_some() {
            frame.plain_invented_colours(scene);
        }
        frame
    }

    /// The model view draws a part whose colours the file did not give
    /// (`Mesh::colours_invented`) in a plain light grey, with colours on or
    /// off: such objects take their plan with the vertex colours off and
    /// `PLAIN_ALBEDO` as their colour.
    fn plain_invented_colours(&mut self, scene: &Scene) {
        let mut plain: Vec<(usize, usize)> = Vec::new();
        for (object, group) in scene.objects.iter().zip(self.of_object.iter_mut()) {
            if !object.mesh.colours_invented {
                continue;
            }
            *group = match plain.iter().find(|(g, _)| g == group) {
                Some(&(_, k)) => k,
                None => {
                    let plan = Plan {
                        colors: false,
                        uncoloured: Vec3::splat(relief_scene::model_view::PLAIN_ALBEDO),
                        ..self.plans[*group].clone()
                    };
                    self.plans.push(plan);
                    self.textures.push(self.textures[*group]);
                    plain.push((*group, self.plans.len() - 1));
                    self.plans.len() - 1
                }
            };
        }
    }
}

/// Pass 1 of the shadows, when the plan asks for it: the map of the plan's
/// shadow light, and what drawing it cost.
#[allow(clippy::too_many_arguments)]
fn shadow_pass<'a>(
    map: Option<&'a mut ShadowMap>,
    scene: &Scene,
    world: &World,
    plan: &Plan,
    repeats: &RepeatCache,
    abandon: &Abandon,
    width: usize,
    height: usize,
) -> (Option<Shadow<'a>>, Counters) {
    let (Some(light), Some(map)) = (plan.shadow_light, map) else {
        return (None, Counters::default());
    };
    let counters = map.render_placed(
        scene,
        world,
        plan.lights[light].position,
        &plan.shadow_casters,
        width,
        height,
        &repeats.all(),
        abandon,
    );
    (Some(Shadow { light, map }), counters)
}

/// Convenience for tests and tools: one frame of `scene` at `width × height`.
pub fn render_frame(
    scene: &Scene,
    settings: &Settings,
    width: usize,
    height: usize,
) -> (Framebuffer, FrameStats) {
    let mut fb = Framebuffer::new(width, height);
    let stats = Renderer::new().render(scene, settings, &mut fb);
    (fb, stats)
}

/// The view's projection of `placed`'s vertices, once per vertex: clip
/// position, outcode, and the screen position triangle setup reads. Each
/// vertex alone, in one sweep (in parallel for big meshes, the same
/// values), but for the vertices of no triangle the camera sees: the
/// triangle stage reads none of theirs.
fn project_vertices(
    placed: &relief_scene::world::Placed,
    view_proj: glam::Mat4,
    (width, height): (usize, usize),
    (clip, codes, projected): (&mut Vec<Vec4>, &mut Vec<u8>, &mut Vec<Option<Projected>>),
) {
    let positions = &placed.positions;
    let project =
        |start: usize, clip: &mut [Vec4], codes: &mut [u8], projected: &mut [Option<Projected>]| {
            let positions = &positions[start..start + clip.len()];
            let vertices = positions.iter().zip(clip).zip(codes).zip(projected);
            for (k, (((p, clip), code), projected)) in vertices.enumerate() {
                if !placed.is_seen(start + k) {
                    continue;
                }
                *clip = view_proj * p.extend(1.0);
                *code = outcode(*clip);
                *projected = (*code == 0)
                    .then(|| Projected::of(*clip, width, height))
                    .flatten();
            }
        };
    fill_three_runs(clip, codes, projected, positions.len(), project);
}
