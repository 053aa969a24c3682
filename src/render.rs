//! The frame: plan → transform → cull/clip/setup → bands of rows rasterized
//! and shaded (in parallel when the frame is big enough to gain).

use std::time::Instant;

use glam::{Mat3, Mat4, Vec2, Vec3, Vec4};
use rayon::prelude::*;

use crate::framebuffer::{Framebuffer, Rgb};
use crate::plan::Plan;
use crate::raster::aa::{
    MSAA_REACH, MSAA_SAMPLES, MsaaBand, RasterTarget, resolve_box, resolve_msaa, ssaa_factor,
};
use crate::raster::frames::{DepthView, draw_tangent_frames};
use crate::raster::setup::ONE;
use crate::raster::wire::{Canvas, WireTri, draw_lines, draw_points, point_size};
use crate::raster::{Band, ClipVertex, Clipped, ScreenTri, clip_triangle, setup_reaching};
use crate::scene::{Scene, normal_matrix};
use crate::settings::{AntiAlias, Display, LightVector, Settings, Shading, Technique};
use crate::shade::dot3::Dot3Kernel;
use crate::shade::emboss::EmbossKernel;
use crate::shade::kernels::{FlatHighlightKernel, GouraudKernel, PhongKernel};
use crate::shade::lighting::{diffuse, finish, light_with};
use crate::shade::parallax::ParallaxKernel;
use crate::shade::specular::{gloss, view_dir};
use crate::shade::{GouraudTri, PhongTri, ShadeCtx, TexturedFlatTri, TriShader};
use crate::shadow::{Shadow, ShadowMap};
use crate::stats::{Counters, FrameStats};

/// Bands of equal estimated work per thread: one would leave a thread idle
/// whenever the estimate is off; a few let the first to finish take another.
const CHUNKS_PER_THREAD: usize = 8;

/// Below this much estimated work (covered pixels weighted by kernel cost,
/// plus the clear) one thread is faster than splitting the frame.
const PARALLEL_MIN_WORK: f64 = 16_384.0;

/// Work units of a row that one triangle spans, besides its pixels: finding
/// the covered span.
const ROW_SETUP_WORK: f64 = 4.0;

/// A vertex after the model transform, in world space.
#[derive(Clone, Copy, Debug)]
struct WorldVertex {
    position: Vec3,
    normal: Vec3,
    uv: Vec2,
    color: Vec3,
    tangent_u: Vec3,
    tangent_v: Vec3,
}

/// Reusable buffers: one `Renderer` per view keeps allocations across frames.
#[derive(Default)]
pub struct Renderer {
    world: Vec<WorldVertex>,
    clip: Vec<Vec4>,
    shaders: Vec<TriShader>,
    tris: Vec<ScreenTri>,
    depth: Vec<f32>,
    polygon: Vec<ClipVertex>,
    /// Visible triangles of the points and lines displays.
    wire: Vec<WireTri>,
    /// The supersampled frame, kept between frames.
    supersampled: Option<Framebuffer>,
    /// Multisampled colours and depths, kept between frames.
    msaa_color: Vec<[Rgb; MSAA_SAMPLES]>,
    msaa_depth: Vec<[f32; MSAA_SAMPLES]>,
    /// The shadow map, kept between frames.
    shadow: ShadowMap,
}

impl Renderer {
    pub fn new() -> Self {
        Renderer::default()
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
        let normal_maps_before = scene.material.texture.normal_map_builds();
        let plan = Plan::new(scene, settings);
        let mips_before = scene.material.texture.mips_built();
        let normal_mips_built =
            |plan: &Plan| plan.normal_map.as_ref().is_some_and(|m| m.mips_built());
        let normal_mips_before = normal_mips_built(&plan);
        // Supersampling draws k times larger, then box-filters down.
        let k = ssaa_factor(plan.aa, width, height);
        // Taken out of `self` for the frame so the shaders can borrow it.
        let mut shadow_map = std::mem::take(&mut self.shadow);
        let (shadow, mut counters) =
            shadow_pass(&mut shadow_map, scene, &plan, width * k, height * k);
        counters += self.prepare(scene, &plan, shadow, width * k, height * k);
        counters.normal_map_builds +=
            scene.material.texture.normal_map_builds() - normal_maps_before;
        stats.plan_time = start.elapsed();

        let raster_start = Instant::now();
        if k > 1 {
            let mut big = self
                .supersampled
                .take()
                .unwrap_or_else(|| Framebuffer::new(0, 0));
            big.resize(width * k, height * k);
            counters += self.rasterize(scene, &plan, shadow, &mut big, k);
            counters += self.tangent_frames(scene, &plan, &mut big, k);
            resolve_box(&big, k, fb);
            self.supersampled = Some(big);
        } else {
            counters += self.rasterize(scene, &plan, shadow, fb, 1);
            counters += self.tangent_frames(scene, &plan, fb, 1);
        }
        self.shadow = shadow_map;
        if !mips_before && scene.material.texture.mips_built() {
            counters.mip_builds += 1;
        }
        if !normal_mips_before && normal_mips_built(&plan) {
            counters.mip_builds += 1;
        }
        stats.raster_time = raster_start.elapsed();
        stats.counters = counters;
        stats
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
        let plan = Plan::new(scene, settings);
        let mut shadow_map = std::mem::take(&mut self.shadow);
        let (shadow, _) = shadow_pass(&mut shadow_map, scene, &plan, width, height);
        self.prepare(scene, &plan, shadow, width, height);
        self.shadow = shadow_map;
        (&self.tris, &self.shaders)
    }

    /// Transforms vertices, culls, clips, sets triangles up and builds their
    /// shaders. Returns the counters of the work done here (per-vertex and
    /// per-facet lighting).
    fn prepare(
        &mut self,
        scene: &Scene,
        plan: &Plan,
        shadow: Option<Shadow>,
        width: usize,
        height: usize,
    ) -> Counters {
        let mut counters = Counters::default();
        self.wire.clear();
        self.shaders.clear();
        self.tris.clear();
        let aspect = width as f32 / height as f32;
        let view_proj = scene.camera.projection(aspect) * scene.camera.view();
        let eye = scene.camera.eye;
        let user_rotation = plan.rotation;
        // Multisampling covers samples off the pixel centres: a sliver
        // between two rows of centres still has samples inside.
        let reach = if plan.aa == AntiAlias::Msaa4 {
            MSAA_REACH
        } else {
            0
        };
        for (object_index, object) in scene.objects.iter().enumerate() {
            let model = object.model_matrix(user_rotation);
            let linear = Mat3::from_mat4(model);
            let normal_matrix = normal_matrix(model);
            self.world.clear();
            self.clip.clear();
            for v in &object.mesh.vertices {
                let position = model.transform_point3(v.position);
                self.world.push(WorldVertex {
                    position,
                    normal: (normal_matrix * v.normal).normalize_or_zero(),
                    uv: v.uv,
                    color: v.color,
                    tangent_u: linear * v.tangent_u,
                    tangent_v: linear * v.tangent_v,
                });
                self.clip.push(view_proj * position.extend(1.0));
            }
            for tri in &object.mesh.triangles {
                let idx = tri.indices.map(|i| i as usize);
                if idx.iter().any(|&i| i >= self.world.len()) {
                    continue;
                }
                let face_normal = (normal_matrix * tri.face_normal).normalize_or_zero();
                let p0 = self.world[idx[0]].position;
                let facing = face_normal.dot(eye - p0);
                if !facing.is_finite() || facing == 0.0 || (facing < 0.0 && object.mesh.closed) {
                    continue;
                }
                // An open surface seen from behind is lit on the side we see.
                let side = if facing < 0.0 { -1.0 } else { 1.0 };
                if plan.display != Display::Fill {
                    counters.light_evals += 3 * plan.lights.len() as u64;
                    self.wire.push(wire_triangle(
                        plan,
                        idx.map(|i| &self.world[i]),
                        idx.map(|i| self.clip[i]),
                        face_normal * side,
                        side,
                    ));
                    continue;
                }
                let shader_index = self.shaders.len() as u32;
                let first_tri = self.tris.len();
                let clip = idx.map(|i| self.clip[i]);
                match clip_triangle(clip, &mut self.polygon) {
                    Clipped::Outside => {}
                    Clipped::Inside => {
                        let v = [0, 1, 2].map(|k| ClipVertex {
                            pos: clip[k],
                            bary: Vec3::AXES[k],
                        });
                        self.tris
                            .extend(setup_reaching(v, width, height, shader_index, reach));
                    }
                    Clipped::Polygon => {
                        counters.triangles_clipped += 1;
                        for k in 1..self.polygon.len() - 1 {
                            let v = [self.polygon[0], self.polygon[k], self.polygon[k + 1]];
                            self.tris
                                .extend(setup_reaching(v, width, height, shader_index, reach));
                        }
                    }
                }
                if self.tris.len() == first_tri {
                    continue;
                }
                let verts = idx.map(|i| self.world[i]);
                let shader = build_shader(
                    plan,
                    &verts,
                    tri,
                    face_normal * side,
                    side,
                    &model,
                    &linear,
                    shadow,
                    object_index as u32,
                    &mut counters,
                );
                self.shaders.push(shader);
            }
        }
        counters.triangles_drawn = self.tris.len() as u64;
        counters
    }

    /// Clears and draws the frame: bands of pixels (or of samples, with
    /// multisampling), or the wireframe. `brush` is the supersampling factor,
    /// which widens lines and points so they keep their size.
    fn rasterize(
        &mut self,
        scene: &Scene,
        plan: &Plan,
        shadow: Option<Shadow>,
        fb: &mut Framebuffer,
        brush: usize,
    ) -> Counters {
        let width = fb.width();
        let height = fb.height();
        let background = scene.background;
        if plan.display != Display::Fill {
            let mut counters = Counters::default();
            fb.fill(background);
            let mut canvas = Canvas::new(width, height, fb.pixels_mut());
            if plan.display == Display::Points {
                let size = point_size(width / brush, height / brush) * brush;
                draw_points(&self.wire, size, &mut canvas, &mut counters);
            } else {
                draw_lines(&self.wire, brush, &mut canvas, &mut counters);
            }
            return counters;
        }
        let ctx = ShadeCtx {
            plan,
            texture: &scene.material.texture,
            shadow,
        };
        let work = RowWork::new(&self.tris, &self.shaders, width, height);
        let threads = rayon::current_num_threads();
        let parallel = work.total() >= PARALLEL_MIN_WORK && threads > 1;
        let bounds = if parallel {
            work.split(threads * CHUNKS_PER_THREAD)
        } else {
            vec![0, height]
        };

        let tris = &self.tris;
        let shaders = &self.shaders;
        if plan.aa == AntiAlias::Msaa4 {
            self.msaa_color.clear();
            self.msaa_color
                .resize(width * height, [background; MSAA_SAMPLES]);
            let mut bands: Vec<MsaaBand> = if plan.depth {
                self.msaa_depth.clear();
                self.msaa_depth
                    .resize(width * height, [f32::INFINITY; MSAA_SAMPLES]);
                split_rows(&mut self.msaa_color, width, &bounds)
                    .zip(split_rows(&mut self.msaa_depth, width, &bounds))
                    .map(|((y0, samples), (_, depth))| MsaaBand {
                        y0,
                        width,
                        samples,
                        depth: Some(depth),
                    })
                    .collect()
            } else {
                split_rows(&mut self.msaa_color, width, &bounds)
                    .map(|(y0, samples)| MsaaBand {
                        y0,
                        width,
                        samples,
                        depth: None,
                    })
                    .collect()
            };
            let total = draw_bands(&mut bands, parallel, tris, shaders, &ctx, background);
            drop(bands);
            resolve_msaa(&self.msaa_color, fb.pixels_mut());
            return total;
        }
        let mut bands: Vec<Band> = if plan.depth {
            self.depth.clear();
            self.depth.resize(width * height, f32::INFINITY);
            split_rows(fb.pixels_mut(), width, &bounds)
                .zip(split_rows(&mut self.depth, width, &bounds))
                .map(|((y0, color), (_, depth))| Band {
                    y0,
                    width,
                    color,
                    depth: Some(depth),
                })
                .collect()
        } else {
            split_rows(fb.pixels_mut(), width, &bounds)
                .map(|(y0, color)| Band {
                    y0,
                    width,
                    color,
                    depth: None,
                })
                .collect()
        };
        draw_bands(&mut bands, parallel, tris, shaders, &ctx, background)
    }
}

impl Renderer {
    /// The tangent frames over the drawn frame (src/raster/frames.rs), their
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
        draw_tangent_frames(scene, plan, depth, fb, brush)
    }
}

/// The estimated work of each row: a triangle's covered area spread evenly
/// over its rows (a flat colour counts a quarter: its rows are fills), a
/// setup cost per row it spans, and the clear.
struct RowWork {
    /// `before[y]`: the work of rows 0..y (`height + 1` entries).
    before: Vec<f64>,
}

impl RowWork {
    fn new(tris: &[ScreenTri], shaders: &[TriShader], width: usize, height: usize) -> Self {
        // Per-row increments, summed once at the end.
        let mut delta = vec![0.0f64; height + 1];
        let px_per_unit = 1.0 / (2 * ONE * ONE) as f64;
        for t in tris {
            let weight = match shaders[t.shader as usize] {
                TriShader::Solid(_) => 0.25,
                _ => 1.0,
            };
            let rows = (t.y1 - t.y0 + 1) as f64;
            let per_row = t.area as f64 * px_per_unit * weight / rows + ROW_SETUP_WORK;
            delta[t.y0 as usize] += per_row;
            delta[t.y1 as usize + 1] -= per_row;
        }
        let clear = width as f64 / 16.0;
        let mut before = Vec::with_capacity(height + 1);
        let (mut sum, mut rate) = (0.0, 0.0);
        before.push(0.0);
        for d in &delta[..height] {
            rate += d;
            sum += rate.max(0.0) + clear;
            before.push(sum);
        }
        RowWork { before }
    }

    fn total(&self) -> f64 {
        *self.before.last().unwrap_or(&0.0)
    }

    /// Row bounds of at most `parts` bands of about equal work, from 0 to
    /// the height.
    fn split(&self, parts: usize) -> Vec<usize> {
        let height = self.before.len() - 1;
        let total = self.total();
        let mut bounds = vec![0];
        let mut y = 0;
        for k in 1..parts {
            let goal = total * k as f64 / parts as f64;
            while y < height && self.before[y] < goal {
                y += 1;
            }
            if y > *bounds.last().unwrap_or(&0) && y < height {
                bounds.push(y);
            }
        }
        bounds.push(height);
        bounds
    }
}

/// Cuts a frame-sized buffer into the bands between consecutive row
/// `bounds`, each with its first row.
fn split_rows<'a, T>(
    mut buf: &'a mut [T],
    width: usize,
    bounds: &'a [usize],
) -> impl Iterator<Item = (usize, &'a mut [T])> + 'a {
    bounds.windows(2).map(move |b| {
        let (band, rest) = std::mem::take(&mut buf).split_at_mut((b[1] - b[0]) * width);
        buf = rest;
        (b[0], band)
    })
}

/// Clears each band and draws every triangle into it, in parallel or not
/// (the same result either way: bands never share a pixel).
fn draw_bands<T: RasterTarget + Send>(
    bands: &mut [T],
    parallel: bool,
    tris: &[ScreenTri],
    shaders: &[TriShader],
    ctx: &ShadeCtx,
    background: Rgb,
) -> Counters {
    let draw = |band: &mut T| -> Counters {
        band.clear(background);
        let mut counters = Counters::default();
        for tri in tris {
            draw_into(tri, &shaders[tri.shader as usize], ctx, band, &mut counters);
        }
        counters
    };
    let per_band: Vec<Counters> = if parallel {
        // One band per task, so an idle thread can take any band left.
        bands.par_iter_mut().with_max_len(1).map(draw).collect()
    } else {
        bands.iter_mut().map(draw).collect()
    };
    let mut total = Counters::default();
    for c in per_band {
        total += c;
    }
    total
}

/// Runs the pixel loop monomorphised for the triangle's kernel.
pub fn draw_triangle(
    tri: &ScreenTri,
    shader: &TriShader,
    ctx: &ShadeCtx,
    band: &mut Band,
    counters: &mut Counters,
) {
    draw_into(tri, shader, ctx, band, counters)
}

/// The kernel dispatch, for any raster target (plain or multisampled).
pub fn draw_into<T: RasterTarget>(
    tri: &ScreenTri,
    shader: &TriShader,
    ctx: &ShadeCtx,
    target: &mut T,
    counters: &mut Counters,
) {
    match shader {
        TriShader::Solid(color) => target.raster(tri, color, ctx, counters),
        TriShader::FlatTextured(s) if ctx.plan.specular.is_some() => {
            target.raster(tri, &FlatHighlightKernel(s), ctx, counters)
        }
        TriShader::FlatTextured(s) => target.raster(tri, s, ctx, counters),
        TriShader::Gouraud(s) => match (s.textured, ctx.plan.specular.is_some()) {
            (true, true) => target.raster(tri, &GouraudKernel::<true, true>(s), ctx, counters),
            (true, false) => target.raster(tri, &GouraudKernel::<true, false>(s), ctx, counters),
            (false, true) => target.raster(tri, &GouraudKernel::<false, true>(s), ctx, counters),
            (false, false) => target.raster(tri, &GouraudKernel::<false, false>(s), ctx, counters),
        },
        TriShader::Phong(s) => match (s.textured, s.bumped) {
            (_, true) if ctx.plan.technique != Technique::Blinn => {
                draw_technique(tri, s, ctx, target, counters)
            }
            (true, true) => phong::<T, true, true>(tri, s, ctx, target, counters),
            (true, false) => phong::<T, true, false>(tri, s, ctx, target, counters),
            (false, true) => phong::<T, false, true>(tri, s, ctx, target, counters),
            (false, false) => phong::<T, false, false>(tri, s, ctx, target, counters),
        },
    }
}

/// A Phong triangle, with highlights when the plan has them (chosen here,
/// once per triangle, so the kernel without them does no specular work).
fn phong<T: RasterTarget, const TEX: bool, const BUMP: bool>(
    tri: &ScreenTri,
    s: &PhongTri,
    ctx: &ShadeCtx,
    target: &mut T,
    counters: &mut Counters,
) {
    if ctx.plan.specular.is_some() {
        target.raster(tri, &PhongKernel::<TEX, BUMP, true>(s), ctx, counters)
    } else {
        target.raster(tri, &PhongKernel::<TEX, BUMP, false>(s), ctx, counters)
    }
}

/// A bumped Phong triangle drawn with the plan's technique (one kernel per
/// technique and variant, chosen here once per triangle).
fn draw_technique<T: RasterTarget>(
    tri: &ScreenTri,
    s: &PhongTri,
    ctx: &ShadeCtx,
    target: &mut T,
    counters: &mut Counters,
) {
    let plan = ctx.plan;
    let eye = plan.eye;
    match (plan.technique, s.textured) {
        (Technique::Emboss, true) => {
            target.raster(tri, &EmbossKernel::<true>::new(s, ctx), ctx, counters)
        }
        (Technique::Emboss, false) => {
            target.raster(tri, &EmbossKernel::<false>::new(s, ctx), ctx, counters)
        }
        (Technique::Dot3, textured) => {
            let Some(map) = plan.normal_map.as_deref() else {
                // The plan builds the map whenever dot3 runs; without one, Blinn.
                return if textured {
                    phong::<T, true, true>(tri, s, ctx, target, counters)
                } else {
                    phong::<T, false, true>(tri, s, ctx, target, counters)
                };
            };
            match (textured, plan.light_vector) {
                (true, LightVector::Pixel) => {
                    let k = Dot3Kernel::<true, true>::new(s, map, ctx);
                    target.raster(tri, &k, ctx, counters)
                }
                (true, LightVector::Vertex) => {
                    let k = Dot3Kernel::<true, false>::new(s, map, ctx);
                    target.raster(tri, &k, ctx, counters)
                }
                (false, LightVector::Pixel) => {
                    let k = Dot3Kernel::<false, true>::new(s, map, ctx);
                    target.raster(tri, &k, ctx, counters)
                }
                (false, LightVector::Vertex) => {
                    let k = Dot3Kernel::<false, false>::new(s, map, ctx);
                    target.raster(tri, &k, ctx, counters)
                }
            }
        }
        (Technique::Parallax, true) => {
            let k = ParallaxKernel::<true, false> { tri: s, eye };
            target.raster(tri, &k, ctx, counters)
        }
        (Technique::Parallax, false) => {
            let k = ParallaxKernel::<false, false> { tri: s, eye };
            target.raster(tri, &k, ctx, counters)
        }
        (Technique::Pom, true) => {
            let k = ParallaxKernel::<true, true> { tri: s, eye };
            target.raster(tri, &k, ctx, counters)
        }
        (Technique::Pom, false) => {
            let k = ParallaxKernel::<false, true> { tri: s, eye };
            target.raster(tri, &k, ctx, counters)
        }
        (Technique::Blinn, true) => phong::<T, true, true>(tri, s, ctx, target, counters),
        (Technique::Blinn, false) => phong::<T, false, true>(tri, s, ctx, target, counters),
    }
}

/// A triangle of the points and lines displays: clip-space corners and the
/// light at each vertex (Gouraud's, whatever the shading mode).
fn wire_triangle(
    plan: &Plan,
    verts: [&WorldVertex; 3],
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
fn build_shader(
    plan: &Plan,
    verts: &[WorldVertex; 3],
    tri: &crate::scene::Triangle,
    face_normal: Vec3,
    side: f32,
    model: &Mat4,
    linear: &Mat3,
    shadow: Option<Shadow>,
    object: u32,
    counters: &mut Counters,
) -> TriShader {
    let textured = tri.textured && plan.texture;
    let bumped = tri.textured && plan.bump;
    let glossy = tri.textured && plan.specular.as_ref().is_some_and(|s| s.map.is_some());
    let uv = verts.map(|v| v.uv);
    let white = Vec3::ONE;
    let color = if plan.colors {
        verts.map(|v| v.color)
    } else {
        [white; 3]
    };
    let lights = plan.lights.len() as u64;
    match plan.shading {
        Shading::Flat => {
            counters.light_evals += lights;
            let center = model.transform_point3(tri.facet_center);
            let albedo = if plan.colors { tri.facet_color } else { white };
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
            let gloss_uv = (uv[0] + uv[1] + uv[2]) / 3.0;
            let highlight = highlight * glossiness(plan, glossy, gloss_uv);
            let lit = albedo * light;
            if textured {
                TriShader::FlatTextured(TexturedFlatTri { lit, uv, highlight })
            } else if plan.specular.is_some() {
                TriShader::Solid(finish(lit + highlight, counters))
            } else {
                TriShader::Solid(finish(lit, counters))
            }
        }
        Shading::Gouraud => {
            counters.light_evals += 3 * lights;
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
                let tu = *linear * tri.face_tangent_u;
                let tv = *linear * tri.face_tangent_v;
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
    mut visibility: impl FnMut(usize, &mut Counters) -> f32,
    counters: &mut Counters,
) -> (Vec3, Vec3) {
    let (ambient, attenuation) = (plan.ambient, plan.attenuation);
    match &plan.specular {
        Some(spec) => {
            counters.specular_evals += plan.lights.len() as u64;
            let view = view_dir(plan.eye, p);
            light_with::<true>(
                &plan.lights,
                ambient,
                p,
                n,
                attenuation,
                view,
                spec.shininess,
                |i| visibility(i, counters),
            )
        }
        None => light_with::<false>(
            &plan.lights,
            ambient,
            p,
            n,
            attenuation,
            Vec3::ZERO,
            0.0,
            |i| visibility(i, counters),
        ),
    }
}

/// The specular map's value at `uv` for a `glossy` triangle, else 1.
fn glossiness(plan: &Plan, glossy: bool, uv: Vec2) -> f32 {
    match plan.specular.as_ref().and_then(|s| s.map.as_deref()) {
        Some(map) if glossy => gloss(map, uv),
        _ => 1.0,
    }
}

/// Pass 1 of the shadows, when the plan asks for it: the map of the plan's
/// shadow light, and what drawing it cost.
fn shadow_pass<'a>(
    map: &'a mut ShadowMap,
    scene: &Scene,
    plan: &Plan,
    width: usize,
    height: usize,
) -> (Option<Shadow<'a>>, Counters) {
    let Some(light) = plan.shadow_light else {
        return (None, Counters::default());
    };
    let counters = map.render(
        scene,
        plan.rotation,
        plan.lights[light].position,
        &plan.shadow_casters,
        width,
        height,
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
