//! The frame: plan → transform → cull/clip/setup → bands of rows rasterized
//! and shaded (in parallel when the frame is big enough to gain).

use std::time::Instant;

use glam::{Mat3, Mat4, Vec2, Vec3, Vec4};
use rayon::prelude::*;

use crate::framebuffer::Framebuffer;
use crate::plan::Plan;
use crate::raster::{Band, ClipVertex, Clipped, ScreenTri, clip_triangle, raster_triangle, setup};
use crate::scene::{Scene, rotation_matrix};
use crate::settings::{Settings, Shading};
use crate::shade::kernels::{GouraudKernel, PhongKernel};
use crate::shade::lighting::{diffuse, finish};
use crate::shade::{GouraudTri, PhongTri, ShadeCtx, TexturedFlatTri, TriShader};
use crate::stats::{Counters, FrameStats};

/// Rows per band: small enough to balance two or more threads on a
/// 240-row frame, large enough that per-band overhead stays negligible.
const BAND_ROWS: usize = 16;

/// Below this much estimated work (covered bounding-box pixels, weighted by
/// kernel cost) one thread is faster than splitting the frame.
const PARALLEL_MIN_WORK: u64 = 16_384;

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
        let plan = Plan::new(scene, settings);
        let mips_before = scene.material.texture.mips_built();
        let mut counters = self.prepare(scene, settings, &plan, width, height);
        stats.plan_time = start.elapsed();

        let raster_start = Instant::now();
        counters += self.rasterize(scene, &plan, fb);
        if !mips_before && scene.material.texture.mips_built() {
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
        self.prepare(scene, settings, &plan, width, height);
        (&self.tris, &self.shaders)
    }

    /// Transforms vertices, culls, clips, sets triangles up and builds their
    /// shaders. Returns the counters of the work done here (per-vertex and
    /// per-facet lighting).
    fn prepare(
        &mut self,
        scene: &Scene,
        settings: &Settings,
        plan: &Plan,
        width: usize,
        height: usize,
    ) -> Counters {
        let mut counters = Counters::default();
        self.shaders.clear();
        self.tris.clear();
        let aspect = width as f32 / height as f32;
        let view_proj = scene.camera.projection(aspect) * scene.camera.view();
        let eye = scene.camera.eye;
        let user_rotation = rotation_matrix(settings.rotation);
        for object in &scene.objects {
            let model = if object.rotates {
                object.transform * user_rotation
            } else {
                object.transform
            };
            let linear = Mat3::from_mat4(model);
            let normal_matrix = linear.inverse().transpose();
            let normal_matrix = if normal_matrix.is_finite() {
                normal_matrix
            } else {
                linear
            };
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
                        self.tris.extend(setup(v, width, height, shader_index));
                    }
                    Clipped::Polygon => {
                        counters.triangles_clipped += 1;
                        for k in 1..self.polygon.len() - 1 {
                            let v = [self.polygon[0], self.polygon[k], self.polygon[k + 1]];
                            self.tris.extend(setup(v, width, height, shader_index));
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
                    &mut counters,
                );
                self.shaders.push(shader);
            }
        }
        counters.triangles_drawn = self.tris.len() as u64;
        counters
    }

    /// Clears and draws every band.
    fn rasterize(&mut self, scene: &Scene, plan: &Plan, fb: &mut Framebuffer) -> Counters {
        let width = fb.width();
        let height = fb.height();
        let background = scene.background;
        let ctx = ShadeCtx {
            plan,
            texture: &scene.material.texture,
        };
        let work: u64 = self
            .tris
            .iter()
            .map(|t| {
                let area = (t.x1 - t.x0 + 1) as u64 * (t.y1 - t.y0 + 1) as u64;
                match self.shaders[t.shader as usize] {
                    TriShader::Solid(_) => area / 4,
                    _ => area,
                }
            })
            .sum::<u64>()
            + (width * height / 16) as u64;
        let parallel = work >= PARALLEL_MIN_WORK && rayon::current_num_threads() > 1;

        let chunk = BAND_ROWS * width;
        let mut bands: Vec<Band> = if plan.depth {
            self.depth.clear();
            self.depth.resize(width * height, f32::INFINITY);
            fb.pixels_mut()
                .chunks_mut(chunk)
                .zip(self.depth.chunks_mut(chunk))
                .enumerate()
                .map(|(i, (color, depth))| Band {
                    y0: i * BAND_ROWS,
                    width,
                    color,
                    depth: Some(depth),
                })
                .collect()
        } else {
            fb.pixels_mut()
                .chunks_mut(chunk)
                .enumerate()
                .map(|(i, color)| Band {
                    y0: i * BAND_ROWS,
                    width,
                    color,
                    depth: None,
                })
                .collect()
        };
        let tris = &self.tris;
        let shaders = &self.shaders;
        let draw = |band: &mut Band| -> Counters {
            band.color.fill(background);
            let mut counters = Counters::default();
            for tri in tris {
                draw_triangle(
                    tri,
                    &shaders[tri.shader as usize],
                    &ctx,
                    band,
                    &mut counters,
                );
            }
            counters
        };
        let per_band: Vec<Counters> = if parallel {
            bands.par_iter_mut().map(draw).collect()
        } else {
            bands.iter_mut().map(draw).collect()
        };
        let mut total = Counters::default();
        for c in per_band {
            total += c;
        }
        total
    }
}

/// Runs the pixel loop monomorphised for the triangle's kernel.
pub fn draw_triangle(
    tri: &ScreenTri,
    shader: &TriShader,
    ctx: &ShadeCtx,
    band: &mut Band,
    counters: &mut Counters,
) {
    match shader {
        TriShader::Solid(color) => raster_triangle(tri, color, ctx, band, counters),
        TriShader::FlatTextured(s) => raster_triangle(tri, s, ctx, band, counters),
        TriShader::Gouraud(s) => {
            if s.textured {
                raster_triangle(tri, &GouraudKernel::<true>(s), ctx, band, counters)
            } else {
                raster_triangle(tri, &GouraudKernel::<false>(s), ctx, band, counters)
            }
        }
        TriShader::Phong(s) => match (s.textured, s.bumped) {
            (true, true) => {
                raster_triangle(tri, &PhongKernel::<true, true>(s), ctx, band, counters)
            }
            (true, false) => {
                raster_triangle(tri, &PhongKernel::<true, false>(s), ctx, band, counters)
            }
            (false, true) => {
                raster_triangle(tri, &PhongKernel::<false, true>(s), ctx, band, counters)
            }
            (false, false) => {
                raster_triangle(tri, &PhongKernel::<false, false>(s), ctx, band, counters)
            }
        },
    }
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
    counters: &mut Counters,
) -> TriShader {
    let textured = tri.textured && plan.texture;
    let bumped = tri.textured && plan.bump;
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
            let lit = albedo
                * diffuse(
                    &plan.lights,
                    plan.ambient,
                    center,
                    face_normal,
                    plan.attenuation,
                );
            if textured {
                TriShader::FlatTextured(TexturedFlatTri { lit, uv })
            } else {
                TriShader::Solid(finish(lit, counters))
            }
        }
        Shading::Gouraud => {
            counters.light_evals += 3 * lights;
            let light = verts.map(|v| {
                let n = if plan.face_normals {
                    face_normal
                } else {
                    v.normal * side
                };
                diffuse(&plan.lights, plan.ambient, v.position, n, plan.attenuation)
            });
            TriShader::Gouraud(GouraudTri {
                light,
                color,
                uv,
                textured,
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
            })
        }
    }
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
