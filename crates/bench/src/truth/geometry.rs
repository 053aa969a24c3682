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
}

/// The scene's triangles in world space and the camera's frame.
pub struct World {
    tris: Vec<Tri>,
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
        for object in &scene.objects {
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
                });
            }
        }
        let cam = &scene.camera;
        let eye = cam.eye.as_dvec3();
        let forward = (cam.target.as_dvec3() - eye).normalize();
        let right = forward.cross(cam.up.as_dvec3()).normalize();
        let up = right.cross(forward);
        let tan = (cam.fov_y_degrees as f64)
            .to_radians()
            .mul_add(0.5, 0.0)
            .tan();
        let aspect = width as f64 / height as f64;
        World {
            tris,
            eye,
            right: right * tan * aspect,
            up: up * tan,
            forward,
            width: width as f64,
            height: height as f64,
        }
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

    /// The nearest triangle the ray meets in front of the eye.
    pub fn hit(&self, ray: &Ray) -> Option<Hit> {
        let mut best: Option<(f64, usize, f64, f64)> = None;
        for i in 0..self.tris.len() {
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
        })
    }
}
