//! The truth's camera rays and ray–triangle hits, in f64.

use glam::{DMat3, DMat4, DVec2, DVec3};

use relief_scene::Scene;

/// A ray from `origin` along `dir` (not necessarily unit).
pub struct Ray {
    pub origin: DVec3,
    pub dir: DVec3,
}

/// What a ray meets: the point and the vertex attributes interpolated with
/// the exact barycentrics of that point, in world space.
#[derive(Clone, Debug)]
pub struct Hit {
    pub t: f64,
    pub position: DVec3,
    pub normal: DVec3,
    pub color: DVec3,
    pub uv: DVec2,
    pub tangent_u: DVec3,
    pub tangent_v: DVec3,
    /// The unit normal of the triangle's plane, on its counter-clockwise side.
    pub face_normal: DVec3,
    pub textured: bool,
    /// The index of the scene object the triangle belongs to.
    pub object: usize,
}

/// One triangle placed in the world.
struct Tri {
    p: [DVec3; 3],
    n: [DVec3; 3],
    c: [DVec3; 3],
    uv: [DVec2; 3],
    tu: [DVec3; 3],
    tv: [DVec3; 3],
    textured: bool,
    object: usize,
}

/// The scene's triangles in world space and the camera's frame.
pub struct World {
    tris: Vec<Tri>,
    /// The triangles a camera ray through each tile of the picture may
    /// meet: those whose projection's bounds (one pixel wider) overlap it.
    tiles: Tiles,
    eye: DVec3,
    right: DVec3,
    up: DVec3,
    forward: DVec3,
    width: f64,
    height: f64,
}

/// The user's rotation in f64: about X first, then Y, then Z.
fn rotation(degrees: glam::Vec3) -> DMat4 {
    let r = |d: f32| {
        let d = d as f64;
        if d.is_finite() {
            d.rem_euclid(360.0).to_radians()
        } else {
            0.0
        }
    };
    DMat4::from_rotation_z(r(degrees.z))
        * DMat4::from_rotation_y(r(degrees.y))
        * DMat4::from_rotation_x(r(degrees.x))
}

impl World {
    pub fn new(scene: &Scene, degrees: glam::Vec3, width: usize, height: usize) -> Self {
        let user = rotation(degrees);
        let mut tris = Vec::new();
        for (index, object) in scene.objects.iter().enumerate() {
            let model = if object.rotates {
                object.transform.as_dmat4() * user
            } else {
                object.transform.as_dmat4()
            };
            let linear = DMat3::from_mat4(model);
            let normals = linear.inverse().transpose();
            let m = &object.mesh;
            for t in &m.triangles {
                let v = t.indices.map(|i| &m.vertices[i as usize]);
                tris.push(Tri {
                    p: v.map(|v| model.transform_point3(v.position.as_dvec3())),
                    n: v.map(|v| normals * v.normal.as_dvec3()),
                    c: v.map(|v| v.color.as_dvec3()),
                    uv: v.map(|v| v.uv.as_dvec2()),
                    tu: v.map(|v| linear * v.tangent_u.as_dvec3()),
                    tv: v.map(|v| linear * v.tangent_v.as_dvec3()),
                    textured: t.textured,
                    object: index,
                });
            }
        }
        let cam = &camera(scene, degrees, width, height);
        let eye = cam.eye.as_dvec3();
        let forward = (cam.target.as_dvec3() - eye).normalize();
        let right = forward.cross(cam.up.as_dvec3()).normalize();
        let up = right.cross(forward);
        let tan = (cam.fov_y_degrees as f64)
            .to_radians()
            .mul_add(0.5, 0.0)
            .tan();
        let aspect = width as f64 / height as f64;
        let mut world = World {
            tris,
            tiles: Tiles::default(),
            eye,
            right: right * tan * aspect,
            up: up * tan,
            forward,
            width: width as f64,
            height: height as f64,
        };
        world.tiles = Tiles::of(&world, width, height);
        world
    }

    /// The screen point (x, y) in pixels where `p` projects, if it lies in
    /// front of the eye.
    fn project(&self, p: DVec3) -> Option<(f64, f64)> {
        let d = p - self.eye;
        let depth = d.dot(self.forward);
        if depth <= 1e-9 {
            return None;
        }
        let nx = d.dot(self.right) / self.right.length_squared() / depth;
        let ny = d.dot(self.up) / self.up.length_squared() / depth;
        Some((
            (nx + 1.0) * self.width / 2.0,
            (1.0 - ny) * self.height / 2.0,
        ))
    }

    /// The ray through the screen point (x, y) in pixels, y down.
    pub fn ray(&self, x: f64, y: f64) -> Ray {
        let nx = 2.0 * x / self.width - 1.0;
        let ny = 1.0 - 2.0 * y / self.height;
        Ray {
            origin: self.eye,
            dir: self.forward + self.right * nx + self.up * ny,
        }
    }

    /// The camera's position.
    pub fn eye(&self) -> DVec3 {
        self.eye
    }

    /// Whether any triangle lies strictly between `from` and `to` (a shadow
    /// ray): hits within a millionth of the segment's ends do not count, so
    /// the triangle `from` lies on does not shadow itself.
    pub fn occluded(&self, from: DVec3, to: DVec3) -> bool {
        let ray = Ray {
            origin: from,
            dir: to - from,
        };
        (0..self.tris.len()).any(|i| {
            self.intersect(i, &ray)
                .is_some_and(|(d, ..)| d > 1e-6 && d < 1.0 - 1e-6)
        })
    }

    /// Möller–Trumbore: solve origin + d·dir = p0 + b1·e1 + b2·e2 for
    /// triangle `i`; (d, b1, b2) when the ray's line crosses it.
    fn intersect(&self, i: usize, ray: &Ray) -> Option<(f64, f64, f64)> {
        let t = &self.tris[i];
        let e1 = t.p[1] - t.p[0];
        let e2 = t.p[2] - t.p[0];
        let pv = ray.dir.cross(e2);
        let det = e1.dot(pv);
        if det.abs() < 1e-300 {
            return None;
        }
        let inv = 1.0 / det;
        let s = ray.origin - t.p[0];
        let b1 = s.dot(pv) * inv;
        if !(0.0..=1.0).contains(&b1) {
            return None;
        }
        let q = s.cross(e1);
        let b2 = ray.dir.dot(q) * inv;
        if b2 < 0.0 || b1 + b2 > 1.0 {
            return None;
        }
        Some((e2.dot(q) * inv, b1, b2))
    }

    /// The camera ray through the screen point (x, y) and the nearest
    /// triangle it meets, found among its tile's triangles.
    pub fn camera_hit(&self, x: f64, y: f64) -> (Ray, Option<Hit>) {
        let ray = self.ray(x, y);
        let hit = self.nearest(&ray, self.tiles.at(x, y));
        (ray, hit)
    }

    /// The nearest triangle the ray meets in front of the eye.
    pub fn hit(&self, ray: &Ray) -> Option<Hit> {
        self.nearest(ray, 0..self.tris.len())
    }

    /// The nearest of triangles `candidates` (in increasing order, so the
    /// first of equals wins as in a full search) the ray meets.
    fn nearest(&self, ray: &Ray, candidates: impl IntoIterator<Item = usize>) -> Option<Hit> {
        let mut best: Option<(f64, usize, f64, f64)> = None;
        for i in candidates {
            let Some((d, b1, b2)) = self.intersect(i, ray) else {
                continue;
            };
            if d > 0.0 && best.is_none_or(|(bd, ..)| d < bd) {
                best = Some((d, i, b1, b2));
            }
        }
        let (d, i, b1, b2) = best?;
        let t = &self.tris[i];
        let b = [1.0 - b1 - b2, b1, b2];
        let mix3 = |a: &[DVec3; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        Some(Hit {
            t: d,
            position: ray.origin + ray.dir * d,
            normal: mix3(&t.n),
            color: mix3(&t.c),
            uv: t.uv[0] * b[0] + t.uv[1] * b[1] + t.uv[2] * b[2],
            tangent_u: mix3(&t.tu),
            tangent_v: mix3(&t.tv),
            face_normal: (t.p[1] - t.p[0]).cross(t.p[2] - t.p[0]).normalize_or_zero(),
            textured: t.textured,
            object: t.object,
        })
    }
}

/// The camera the renderer sees `scene` through at rotation `degrees` in
/// a `width × height` picture: the scene's own, or in the model view the
/// camera that frames the model turned so (`scene::model_view`, the
/// scene's field of view).
fn camera(scene: &Scene, degrees: glam::Vec3, width: usize, height: usize) -> relief_scene::Camera {
    use relief_scene::model_view::{fit_scene, framed_camera};
    let Some(view) = scene.model_view else {
        return scene.camera;
    };
    let pose = view.pose.unwrap_or(degrees);
    let fov = scene.camera.fov_y_degrees;
    let aspect = width as f32 / height as f32;
    let up = relief_core::settings::UpAxis::Y;
    match fit_scene(scene, pose, up, fov, aspect) {
        Some(fit) => framed_camera(&scene.camera, fit),
        None => scene.camera,
    }
}

/// Side of a tile of `Tiles`, in pixels.
const TILE: usize = 8;

/// Per tile of the picture, the triangles whose projected bounds overlap
/// it; triangles reaching behind the eye are in every tile.
#[derive(Default)]
struct Tiles {
    columns: usize,
    lists: Vec<Vec<usize>>,
}

impl Tiles {
    fn of(world: &World, width: usize, height: usize) -> Tiles {
        let columns = width.div_ceil(TILE).max(1);
        let rows = height.div_ceil(TILE).max(1);
        let mut lists = vec![Vec::new(); columns * rows];
        for (i, t) in world.tris.iter().enumerate() {
            let projected: Option<Vec<(f64, f64)>> =
                t.p.iter().map(|&p| world.project(p)).collect();
            let (x0, y0, x1, y1) = match projected {
                Some(pts) => {
                    let fold = |f: fn(f64, f64) -> f64, init: f64, k: fn(&(f64, f64)) -> f64| {
                        pts.iter().map(k).fold(init, f)
                    };
                    (
                        fold(f64::min, f64::INFINITY, |p| p.0) - 1.0,
                        fold(f64::min, f64::INFINITY, |p| p.1) - 1.0,
                        fold(f64::max, f64::NEG_INFINITY, |p| p.0) + 1.0,
                        fold(f64::max, f64::NEG_INFINITY, |p| p.1) + 1.0,
                    )
                }
                None => (0.0, 0.0, width as f64, height as f64),
            };
            if !(x1 >= 0.0 && y1 >= 0.0 && x0 <= width as f64 && y0 <= height as f64) {
                continue;
            }
            let cell = |v: f64, n: usize| ((v.max(0.0) as usize) / TILE).min(n - 1);
            for row in cell(y0, rows)..=cell(y1, rows) {
                for column in cell(x0, columns)..=cell(x1, columns) {
                    lists[row * columns + column].push(i);
                }
            }
        }
        Tiles { columns, lists }
    }

    /// The triangles of the tile holding the screen point (x, y).
    fn at(&self, x: f64, y: f64) -> impl Iterator<Item = usize> + '_ {
        let cell = |v: f64| (v.max(0.0) as usize) / TILE;
        let rows = self.lists.len() / self.columns.max(1);
        let (c, r) = (cell(x), cell(y));
        let list = if c < self.columns && r < rows {
            &self.lists[r * self.columns + c][..]
        } else {
            &[][..]
        };
        list.iter().copied()
    }
}
