//! The scene placed in the world for one frame: each object's matrices, its
//! vertices and facet normals in world space, and which triangles face the
//! camera. Built once per frame and read by every pass that needs geometry
//! (the shadow pass, the main pass, the lines and points displays, the
//! tangent frames), so the model matrix and the cull are applied once.

use glam::{Mat3, Mat4, Vec2, Vec3};

use std::sync::atomic::{AtomicU8, Ordering};

use rayon::prelude::*;

use super::facing::{Facing, Quick};
use super::{Mesh, Object, Scene, normal_matrix};

/// A vertex after the model transform, in world space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WorldVertex {
    pub position: Vec3,
    /// The normal carried by the normal matrix, unit length (or zero).
    pub normal: Vec3,
    pub uv: Vec2,
    pub color: Vec3,
    /// ∂P/∂u and ∂P/∂v carried by the model's linear part.
    pub tangent_u: Vec3,
    pub tangent_v: Vec3,
}

/// One object placed for the frame.
#[derive(Debug, Default)]
pub struct Placed {
    pub model: Mat4,
    /// The model's linear part (carries tangents).
    pub linear: Mat3,
    /// The inverse transpose of `linear` (carries normals).
    pub normals: Mat3,
    /// World positions, one per mesh vertex.
    pub positions: Vec<Vec3>,
    /// Per triangle: its facet normal carried by `normals`, not normalized
    /// (the shadow pass's cull reads it so; [`Placed::facet_normal`] is
    /// its unit vector). Made only for a frame whose passes read every
    /// facet (the shadow pass); empty otherwise, when
    /// [`Placed::facet`] computes the few that the drawn triangles need.
    pub facets: Vec<Vec3>,
    /// Per triangle: the side the camera sees, 1 (front), −1 (the back of
    /// an open surface) or 0 (culled: a back face of a closed mesh, edge
    /// on, not finite, or with an index past the vertices).
    pub sides: Vec<i8>,
    /// Per vertex: 1 when it is a corner of a triangle the camera sees
    /// (side ≠ 0), else 0. A closed mesh seen from outside hides about
    /// half its vertices: the view projects only these
    /// ([`Placed::is_seen`]).
    seen: Vec<AtomicU8>,
}

impl Placed {
    /// Vertex `i` of `mesh` (the mesh this object was placed with) in world
    /// space, `i` below the vertex count. Its normal, colour, texture
    /// coordinates and tangents are carried here, on demand: a big mesh
    /// draws few of its vertices (most of its triangles are culled or cover
    /// no pixel centre), so they are not carried for every vertex each frame.
    /// Always inlined: called out of line from the triangle loop, its
    /// 68-byte result went through the stack and the loop stalled reading
    /// it back (the physical frame of a 100,000-triangle sphere at 320×192,
    /// one thread, 4.34 → 4.13 ms).
    #[inline(always)]
    pub fn vertex(&self, mesh: &Mesh, i: usize) -> WorldVertex {
        let v = &mesh.vertices[i];
        WorldVertex {
            position: self.positions[i],
            normal: (self.normals * v.normal).normalize_or_zero(),
            uv: v.uv,
            color: v.color,
            tangent_u: self.linear * v.tangent_u,
            tangent_v: self.linear * v.tangent_v,
        }
    }

    /// Whether vertex `i` is a corner of a triangle the camera sees (false
    /// past the vertices).
    #[inline]
    pub fn is_seen(&self, i: usize) -> bool {
        self.seen
            .get(i)
            .is_some_and(|s| s.load(Ordering::Relaxed) != 0)
    }

    /// Triangle `t`'s facet normal carried by the normal matrix, not
    /// normalized (`mesh` is the mesh this object was placed with): from
    /// `facets` when they were made, else computed as the facing pass
    /// computes it (the same bits).
    #[inline]
    pub fn facet(&self, mesh: &Mesh, t: usize) -> Vec3 {
        match self.facets.get(t) {
            Some(&f) => f,
            None => self.normals * mesh.face_normal(t),
        }
    }

    /// The unit facet normal of triangle `t` in world space (or zero).
    #[inline]
    pub fn facet_normal(&self, mesh: &Mesh, t: usize) -> Vec3 {
        self.facet(mesh, t).normalize_or_zero()
    }

    /// Places `object` with the user's `rotation`, its triangles culled for
    /// an eye at `eye`; every facet made too when `facets`.
    fn place(&mut self, object: &Object, rotation: Mat4, eye: Vec3, facets: bool) {
        let model = object.model_matrix(rotation);
        let linear = Mat3::from_mat4(model);
        let normals = normal_matrix(model);
        self.model = model;
        self.linear = linear;
        self.normals = normals;
        let (vertices, triangles) = (&object.mesh.vertices, &object.mesh.triangles);
        fill(&mut self.positions, vertices.len(), |i| {
            model.transform_point3(vertices[i].position)
        });
        // Cleared as memory (no other thread sees it here), then marked by
        // the facing pass from any thread.
        self.seen.resize_with(vertices.len(), AtomicU8::default);
        self.seen.iter_mut().for_each(|s| *s.get_mut() = 0);
        let facing = Facing {
            mesh: &object.mesh,
            seen: &self.seen,
            positions: &self.positions,
            normals,
            eye,
            quick: Quick::new(model, normals, eye),
        };
        if facets {
            // Each triangle's facet normal and the side the camera sees, in
            // one pass over the triangles.
            fill_pair_runs(
                &mut self.facets,
                &mut self.sides,
                triangles.len(),
                |start, facets, sides| facing.run(start, facets, sides),
            );
        } else {
            self.facets.clear();
            fill_runs(&mut self.sides, triangles.len(), |start, sides| {
                facing.run_sides(start, sides)
            });
        }
    }
}

/// Below this many elements a buffer is filled on one thread (the 5,000
/// vertices and 10,000 triangles of a sphere take about 75 µs to place:
/// a second thread pays).
const PARALLEL_MIN: usize = 2_048;
/// Elements per task of [`fill_pair`].
const PARALLEL_CHUNK: usize = 1_024;

/// Whether a buffer of `len` elements is filled on this thread alone: a
/// short one, or any on one thread (no tasks to cut).
fn serial(len: usize) -> bool {
    len < PARALLEL_MIN || rayon::current_num_threads() == 1
}

/// `out` = `f(0)`, `f(1)`, … `f(len − 1)`, in parallel for long buffers
/// (each element is computed alone: the result is the same).
pub fn fill<U: Send>(out: &mut Vec<U>, len: usize, f: impl Fn(usize) -> U + Sync + Send) {
    out.clear();
    if serial(len) {
        out.extend((0..len).map(f));
    } else {
        out.par_extend((0..len).into_par_iter().map(f));
    }
}

/// [`fill`] of two buffers at once: `a[i]`, `b[i]` = `f(i)`.
pub fn fill_pair<A: Send + Copy + Default, B: Send + Copy + Default>(
    a: &mut Vec<A>,
    b: &mut Vec<B>,
    len: usize,
    f: impl Fn(usize) -> (A, B) + Sync + Send,
) {
    fill_pair_runs(a, b, len, |start, a, b| {
        for (k, (a, b)) in a.iter_mut().zip(b.iter_mut()).enumerate() {
            (*a, *b) = f(start + k);
        }
    });
}

/// [`fill`] by runs: `run(start, out)` fills `out` with the elements from
/// `start` on, each element alone (the result does not depend on how the
/// buffer is cut).
pub fn fill_runs<A: Send + Copy + Default>(
    out: &mut Vec<A>,
    len: usize,
    run: impl Fn(usize, &mut [A]) + Sync + Send,
) {
    out.resize(len, A::default());
    if serial(len) {
        run(0, out);
    } else {
        out.par_chunks_mut(PARALLEL_CHUNK)
            .enumerate()
            .for_each(|(c, out)| run(c * PARALLEL_CHUNK, out));
    }
}

/// [`fill_pair`] by runs: `run(start, a, b)` fills `a`, `b` (equally
/// long) with the elements from `start` on, each element alone (the
/// result does not depend on how the buffers are cut).
pub fn fill_pair_runs<A: Send + Copy + Default, B: Send + Copy + Default>(
    a: &mut Vec<A>,
    b: &mut Vec<B>,
    len: usize,
    run: impl Fn(usize, &mut [A], &mut [B]) + Sync + Send,
) {
    // Every element is overwritten: only a longer buffer needs filling first.
    a.resize(len, A::default());
    b.resize(len, B::default());
    if serial(len) {
        run(0, a, b);
    } else {
        a.par_chunks_mut(PARALLEL_CHUNK)
            .zip(b.par_chunks_mut(PARALLEL_CHUNK))
            .enumerate()
            .for_each(|(c, (a, b))| run(c * PARALLEL_CHUNK, a, b));
    }
}

/// [`fill_pair_runs`] of three buffers at once.
pub fn fill_three_runs<A, B, C>(
    a: &mut Vec<A>,
    b: &mut Vec<B>,
    c: &mut Vec<C>,
    len: usize,
    run: impl Fn(usize, &mut [A], &mut [B], &mut [C]) + Sync + Send,
) where
    A: Send + Copy + Default,
    B: Send + Copy + Default,
    C: Send + Copy + Default,
{
    a.resize(len, A::default());
    b.resize(len, B::default());
    c.resize(len, C::default());
    if serial(len) {
        run(0, a, b, c);
    } else {
        a.par_chunks_mut(PARALLEL_CHUNK)
            .zip(b.par_chunks_mut(PARALLEL_CHUNK))
            .zip(c.par_chunks_mut(PARALLEL_CHUNK))
            .enumerate()
            .for_each(|(k, ((a, b), c))| run(k * PARALLEL_CHUNK, a, b, c));
    }
}

/// Every object of a scene placed for one frame; its buffers are kept from
/// frame to frame.
#[derive(Debug, Default)]
pub struct World {
    objects: Vec<Placed>,
}

impl World {
    pub fn new() -> Self {
        World::default()
    }

    /// Places every object of `scene` with the user's `rotation`, culled
    /// for the scene's camera, with every facet made.
    pub fn of(scene: &Scene, rotation: Mat4) -> Self {
        let mut world = World::new();
        world.place(scene, rotation, scene.camera.eye, true);
        world
    }

    /// Places every object of `scene` with the user's `rotation`, culled
    /// for an eye at `eye` (the frame's camera), reusing the buffers; every
    /// triangle's facet is made only when `facets` (a pass will read them all).
    pub fn place(&mut self, scene: &Scene, rotation: Mat4, eye: Vec3, facets: bool) {
        self.objects
            .resize_with(scene.objects.len(), Placed::default);
        for (placed, object) in self.objects.iter_mut().zip(&scene.objects) {
            placed.place(object, rotation, eye, facets);
        }
    }

    /// Object `i` as placed (index in `Scene::objects`).
    pub fn object(&self, i: usize) -> &Placed {
        &self.objects[i]
    }

    pub fn objects(&self) -> &[Placed] {
        &self.objects
    }
}
