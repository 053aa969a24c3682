//! The model view (docs/models.md, "The model view"): what a model file
//! is shown with, as a glTF viewer shows it. The camera frames the model's
//! points so they fill `FILL` of the picture in the start view, from a
//! front three-quarter view (the camera `ELEVATION_DEGREES` above, the
//! model turned by `START_ROTATION`), and a neutral rig of white lights
//! replaces the reference cube's coloured ones. The reference cube scene
//! keeps its own camera and lights.

use glam::{Mat4, Vec2, Vec3};

use super::camera::{Camera, REFERENCE_DISTANCE};
use super::contents::ModelView;
use super::light::Light;
use super::{Scene, rotation_matrix};
use relief_core::settings::UpAxis;

/// Share of the picture's limiting side the framed model spans (each
/// side keeps (1 − FILL)/2 of margin).
pub const FILL: f32 = 0.9;
/// How far above the model's horizon the camera looks down, in degrees.
pub const ELEVATION_DEGREES: f32 = 20.0;
/// The start rotation of a model file (degrees about X, Y, Z): its front
/// (+Z) turned 35° to the viewer's left, so its own left side (+X) shows too.
pub const START_ROTATION: Vec3 = Vec3::new(0.0, -35.0, 0.0);
/// The soft light from everywhere that stands in for an environment.
pub const AMBIENT: Vec3 = Vec3::splat(0.22);

/// The neutral rig, in world space about the model's centre: a white key
/// light above, left and in front; a weaker fill from the right; a rim
/// light from behind and above, which outlines the silhouette.
pub fn neutral_lights() -> Vec<Light> {
    vec![
        Light::new(Vec3::new(-4.0, 6.0, 7.0), Vec3::splat(0.85)),
        Light::new(Vec3::new(7.0, 1.0, 4.0), Vec3::splat(0.3)),
        Light::new(Vec3::new(1.0, 5.0, -8.0), Vec3::splat(0.25)),
    ]
}

impl Scene {
    /// This scene shown in the model view: the file's own lights, else the
    /// neutral rig, and the framing camera (a model file's scene; the
    /// built-in models keep the reference scene's).
    pub fn into_model_view(mut self) -> Scene {
        self.lights = if self.file_lights.is_empty() {
            neutral_lights()
        } else {
            self.file_lights.clone()
        };
        self.ambient = AMBIENT;
        self.model_view = Some(ModelView::new());
        self
    }

    /// What this scene's parts have that the keys act on.
    pub fn features(&self) -> ModelFeatures {
        let normal_maps = self.has_normal_maps();
        let colour_texture = self.shows_a_texture();
        ModelFeatures {
            vertex_colours: self.shows_vertex_colours(),
            varied_normals: self.normals_vary(),
            normal_maps,
            colour_texture,
            pictures: colour_texture || normal_maps || self.reads_other_maps(),
            texture_coordinates: self.has_texture_coordinates(),
        }
    }

    /// Whether some part's vertex colours differ from what it is drawn
    /// with when colours are off (its material's colour factor, else
    /// white): what the colours switch (`c`) shows on a model file. A part
    /// whose file gave none is drawn the same either way.
    fn shows_vertex_colours(&self) -> bool {
        self.objects.iter().enumerate().any(|(i, o)| {
            let plain = self.own_terms(i).map_or(Vec3::ONE, |t| t.colour_factor);
            !o.mesh.colours_invented && o.mesh.vertices.iter().any(|v| v.color != plain)
        })
    }

    /// Whether some triangle has texture coordinates (is textured): what
    /// the tangent frames (`F`) are drawn from.
    pub fn has_texture_coordinates(&self) -> bool {
        self.objects
            .iter()
            .any(|o| o.mesh.triangles.iter().any(|t| t.textured))
    }

    /// Whether some textured part shows a picture: a material of its own
    /// whose colour texture is more than one texel (a glTF material without
    /// a map has a white texel), or no material of its own (it takes the
    /// file's or the user's texture). What `t` switches.
    fn shows_a_texture(&self) -> bool {
        (0..self.objects.len()).any(|i| {
            let textured = self.objects[i].mesh.triangles.iter().any(|t| t.textured);
            let picture = self.own_material(i).is_none_or(|m| {
                let base = m.texture.base();
                base.width * base.height > 1
            });
            textured && picture
        })
    }

    /// Whether some part's material reads a map besides its colour texture
    /// and normal map (metallic-roughness, emissive, occlusion, the
    /// extensions'): with those, what the filter (`f`) reads.
    fn reads_other_maps(&self) -> bool {
        self.object_terms.iter().flatten().any(|t| {
            !t.map_names.is_empty()
                || t.pbr
                    .as_ref()
                    .is_some_and(|p| p.roughness_map.is_some() || p.metallic_map.is_some())
        })
    }

    /// Whether some part's physical material has a normal map (its own, or
    /// its clearcoat's): what the bump switch (`b`) turns off there.
    fn has_normal_maps(&self) -> bool {
        self.object_terms.iter().flatten().any(|t| {
            t.pbr.as_ref().is_some_and(|p| {
                p.normal.is_some() || p.clearcoat.as_ref().is_some_and(|c| c.normal.is_some())
            })
        })
    }

    /// Whether more than one corner in a hundred has a normal other than
    /// its facet's: what the normals switch (`n`, vertex / face) shows. A
    /// flat model (every corner split with its facet's normal) looks the
    /// same either way, though a few slivers' stored normals may differ.
    fn normals_vary(&self) -> bool {
        let corners: usize = self
            .objects
            .iter()
            .map(|o| 3 * o.mesh.triangles.len())
            .sum();
        let mut differ = 0;
        for mesh in self.objects.iter().map(|o| &o.mesh) {
            for (t, tri) in mesh.triangles.iter().enumerate() {
                let face = mesh.face_normal(t);
                for &i in &tri.indices {
                    let n = mesh.vertices.get(i as usize).map_or(face, |v| v.normal);
                    differ += usize::from(n.dot(face) < 0.9999);
                }
                if differ * 100 > corners {
                    return true;
                }
            }
        }
        false
    }

    /// Whether the model view shades every object physically (each has a
    /// metallic-roughness or unlit material): the Phong-only settings (bump
    /// technique, Blinn highlight, environment reflection) change nothing.
    pub fn all_physical(&self) -> bool {
        let physical = |i: usize| {
            let terms = self.object_terms.get(i).and_then(|t| t.as_deref());
            terms.is_some_and(|t| t.pbr.is_some() || t.unlit)
        };
        self.model_view.is_some()
            && !self.objects.is_empty()
            && (0..self.objects.len()).all(physical)
    }

    /// Which of this model file's parts can show a texture (`None` for
    /// the reference scenes, which always can).
    pub fn texture_reach(&self) -> Option<TextureReach> {
        let view = self.model_view?;
        let textured = |i: usize| self.objects[i].mesh.triangles.iter().any(|t| t.textured);
        let own = (0..self.objects.len()).any(|i| self.own_material(i).is_some() && textured(i));
        let bare = (0..self.objects.len()).any(|i| self.own_material(i).is_none() && textured(i));
        Some(if bare && !own && !view.file_texture {
            TextureReach::WhenChosen
        } else {
            TextureReach::Own
        })
    }

    /// This scene in the reference camera and lights, its materials drawn
    /// as the reference scenes draw them (the llvmpipe comparison's view).
    pub fn into_reference_view(mut self) -> Scene {
        if self.model_view.take().is_some() {
            self.lights = super::light::reference_lights();
            self.ambient = super::light::AMBIENT;
        }
        self
    }
}

/// The colour of a model file's part that gives none (an STL, a PLY of
/// positions, an OBJ without MTL) in the model view: a light grey, as
/// Blender's default material (0.8), so the neutral rig's light (up to
/// about 1.3 where key, fill and ambient meet) leaves its shading visible
/// instead of clipping a quarter of it to white.
pub const PLAIN_ALBEDO: f32 = 0.8;

/// What a model file's parts have that some keys act on (`c`, `n`, `t`,
/// `f`, `F`, `b`, `h`): without it, those keys are refused, since they
/// would change nothing (`Scene::features`). All there by default, as in
/// the reference scenes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ModelFeatures {
    /// Vertex colours other than the material's own colour
    /// (`Scene::shows_vertex_colours`).
    pub vertex_colours: bool,
    /// Corner normals other than their facets' (`Scene::normals_vary`).
    pub varied_normals: bool,
    /// A physical material's normal map (`Scene::has_normal_maps`).
    pub normal_maps: bool,
    /// A colour texture shown (`Scene::shows_a_texture`).
    pub colour_texture: bool,
    /// Some picture read, any map (a colour texture, a normal map, or
    /// `Scene::reads_other_maps`).
    pub pictures: bool,
    /// Texture coordinates (`Scene::has_texture_coordinates`).
    pub texture_coordinates: bool,
}

impl Default for ModelFeatures {
    fn default() -> Self {
        ModelFeatures {
            vertex_colours: true,
            varied_normals: true,
            normal_maps: true,
            colour_texture: true,
            pictures: true,
            texture_coordinates: true,
        }
    }
}

/// Which parts of a model file can show a texture (`Scene::texture_reach`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TextureReach {
    /// Parts with a material of their own (whose texture may be the
    /// file's map, or white: a glTF material without one), or parts that
    /// take the file's own map.
    Own,
    /// Only parts without a material of their own, which take a texture
    /// once the user chooses one (`ModelView::dresses_bare_parts`).
    WhenChosen,
}

/// The camera axes of the model view: right, up, and back toward the eye
/// (unit, orthogonal), for a camera `ELEVATION_DEGREES` above the horizon.
pub fn view_axes() -> [Vec3; 3] {
    let e = ELEVATION_DEGREES.to_radians();
    let back = Vec3::new(0.0, e.sin(), e.cos());
    let right = Vec3::X;
    [right, back.cross(right), back]
}

/// Where the framing camera stands, in the view axes: the point it looks
/// at is `centre` along right and up, and the eye `distance` back from it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fit {
    pub centre: Vec2,
    pub distance: f32,
}

/// The fit of `points` (world space) for tangents of the half field of
/// view `tan_x`, `tan_y` already shrunk to the share to fill: the camera,
/// looking along −back, that sees every point within them, as close as
/// it can be and with equal margins on either side of the limiting axis.
///
/// A point (x, y, z) in view axes is inside the horizontal half-angle of
/// an eye at (cx, ·, d) when |x − cx| ≤ tan_x·(d − z), i.e. when
/// d ≥ z + (x − cx)/tan_x and d ≥ z − (x − cx)/tan_x. With
/// A = max(z + x/tan_x) and B = max(z − x/tan_x) over the points, the
/// smallest d is (A + B)/2 at cx = tan_x·(A − B)/2, where the two outer
/// points lie on the two edges; the same holds vertically. `None` when
/// there is no finite point.
pub fn fit(points: impl Iterator<Item = Vec3>, tan_x: f32, tan_y: f32) -> Option<Fit> {
    let [right, up, back] = view_axes();
    let (sx, sy) = (1.0 / tan_x as f64, 1.0 / tan_y as f64);
    let mut m = [f64::NEG_INFINITY; 5];
    for p in points.filter(|p| p.is_finite()) {
        let (x, y, z) = (p.dot(right) as f64, p.dot(up) as f64, p.dot(back) as f64);
        m[0] = m[0].max(z + x * sx);
        m[1] = m[1].max(z - x * sx);
        m[2] = m[2].max(z + y * sy);
        m[3] = m[3].max(z - y * sy);
        m[4] = m[4].max(z);
    }
    if !m.iter().all(|v| v.is_finite()) {
        return None;
    }
    let (dx, dy) = ((m[0] + m[1]) / 2.0, (m[2] + m[3]) / 2.0);
    // The eye keeps clear of the nearest point (a flat model seen edge on
    // has no extent to frame).
    let distance = dx.max(dy).max(m[4] + MIN_CLEARANCE as f64);
    let centre = Vec2::new(
        ((m[0] - m[1]) / 2.0 / sx) as f32,
        ((m[2] - m[3]) / 2.0 / sy) as f32,
    );
    Some(Fit {
        centre,
        distance: distance as f32,
    })
}

/// Closest the framing camera comes to the model's nearest point.
const MIN_CLEARANCE: f32 = 0.5;

/// The fit of `scene`'s objects turned by `pose` (degrees, with the
/// model's `up` axis) for a picture of `aspect` (width over height) and a
/// vertical field of view of `fov_degrees`.
pub fn fit_scene(
    scene: &Scene,
    pose: Vec3,
    up: UpAxis,
    fov_degrees: f32,
    aspect: f32,
) -> Option<Fit> {
    let rotation = view_rotation(pose, up);
    let tan_y = (fov_degrees.to_radians() / 2.0).tan() * FILL;
    let tan_x = tan_y * aspect;
    if !(tan_x.is_finite() && tan_y.is_finite() && tan_x > 0.0 && tan_y > 0.0) {
        return None;
    }
    let objects = scene.objects.iter().flat_map(|o| {
        let model = o.model_matrix(rotation);
        o.mesh
            .vertices
            .iter()
            .map(move |v| model.transform_point3(v.position))
    });
    let strokes = scene
        .strokes
        .vertices
        .iter()
        .map(|v| rotation.transform_point3(v.position));
    fit(objects.chain(strokes), tan_x, tan_y)
}

/// The user's rotation `degrees` of a model whose `up` axis is given: a
/// Z-up model is first turned so +Z is up.
pub fn view_rotation(degrees: Vec3, up: UpAxis) -> Mat4 {
    match up {
        UpAxis::Y => rotation_matrix(degrees),
        UpAxis::Z => rotation_matrix(degrees) * Mat4::from_rotation_x(-std::f32::consts::FRAC_PI_2),
    }
}

/// The framing camera, with the user's zoom and pan of `user` (the
/// reference camera moved by `Camera::at_distance` and `Camera::panned`):
/// its distance scales the fit's as it scales the reference one, its pan
/// moves the point looked at along the view's right and up.
pub fn framed_camera(user: &Camera, fit: Fit) -> Camera {
    let [right, up, back] = view_axes();
    let zoom = (user.eye - user.target).length() / REFERENCE_DISTANCE;
    let zoom = if zoom.is_finite() && zoom > 0.0 {
        zoom
    } else {
        1.0
    };
    let centre = fit.centre + Vec2::new(user.target.x, user.target.y);
    let target = right * centre.x + up * centre.y;
    Camera {
        eye: target + back * (fit.distance * zoom),
        target,
        up: Vec3::Y,
        ..*user
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_point_pair_is_fitted_to_the_edges() {
        // Two points 2 apart across at depth 0: seen with tan 0.5, the eye
        // stands 2 back, centred between them.
        let [right, _, _] = view_axes();
        let pts = [right * 3.0, right * 5.0];
        let f = fit(pts.into_iter(), 0.5, 0.5).unwrap();
        assert!((f.centre.x - 4.0).abs() < 1e-5, "{f:?}");
        assert!((f.distance - 2.0).abs() < 1e-5, "{f:?}");
    }

    #[test]
    fn no_finite_point_has_no_fit() {
        assert_eq!(fit([Vec3::NAN].into_iter(), 0.5, 0.5), None);
        assert_eq!(fit(std::iter::empty(), 0.5, 0.5), None);
    }

    #[test]
    fn the_view_axes_are_orthonormal_and_look_down() {
        let [r, u, b] = view_axes();
        assert!(r.dot(u).abs() < 1e-6 && u.dot(b).abs() < 1e-6 && r.dot(b).abs() < 1e-6);
        assert!(b.y > 0.0, "the eye is above the horizon");
        assert!((r.cross(u) - b).length() < 1e-6, "right-handed");
    }
}
