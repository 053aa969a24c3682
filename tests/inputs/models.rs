//! Models: built-in meshes, OBJ loading (good and bad files), scene kinds.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::{Vec2, Vec3};
use relief_scene::corners;
use relief_scene::corners::FIT_RADIUS;
use relief_scene::model_error::ObjError;
use relief_scene::obj;
use relief_scene::{
    Built, Mesh, ModelChoice, SceneKind, build_scene, cube, plane, sphere, tangents, triangle,
};
use relief_texture::decode::procedural;

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

fn positions(mesh: &Mesh, tri: usize) -> [Vec3; 3] {
    mesh.triangles[tri]
        .indices
        .map(|i| mesh.vertices[i as usize].position)
}

/// Everything every mesh must satisfy: indices in range, finite data, unit
/// normals, triangles wound counter-clockwise around their facet normal,
/// tangents finite and non-zero, and in the tangent plane of the vertex
/// normal (except on the reference cube, whose corner normals are averaged
/// over three faces by design while its tangents are the face's).
fn check_mesh(name: &str, mesh: &Mesh) {
    let in_plane = name != "cube";
    assert!(!mesh.triangles.is_empty(), "{name}: no triangles");
    for (i, v) in mesh.vertices.iter().enumerate() {
        let all = [v.position, v.normal, v.color, v.tangent_u, v.tangent_v];
        assert!(
            all.iter().all(|x| x.is_finite()),
            "{name}: vertex {i} {v:?}"
        );
        assert!(v.uv.is_finite(), "{name}: vertex {i} uv");
        assert!(
            (v.normal.length() - 1.0).abs() < 1e-4,
            "{name}: vertex {i} normal"
        );
        assert!(v.color.min_element() >= 0.0 && v.color.max_element() <= 1.0);
        for t in [v.tangent_u, v.tangent_v] {
            assert!(t.length() > 1e-3, "{name}: vertex {i} has a null tangent");
            assert!(
                !in_plane || t.normalize().dot(v.normal).abs() < 1e-3,
                "{name}: vertex {i} tangent {t} leaves the tangent plane of {}",
                v.normal
            );
        }
        assert!(
            v.tangent_u
                .normalize()
                .cross(v.tangent_v.normalize())
                .length()
                > 0.1,
            "{name}: vertex {i} has parallel tangents"
        );
    }
    for (t, tri) in mesh.faces().iter().enumerate() {
        assert!(
            tri.indices
                .iter()
                .all(|&i| (i as usize) < mesh.vertices.len())
        );
        let [a, b, c] = positions(mesh, t);
        let geometric = (b - a).cross(c - a).normalize();
        assert!(
            geometric.dot(tri.face_normal) > 0.99,
            "{name}: triangle {t} is not counter-clockwise around its facet normal"
        );
        assert!((tri.face_normal.length() - 1.0).abs() < 1e-4);
        for x in [
            tri.face_tangent_u,
            tri.face_tangent_v,
            tri.facet_center,
            tri.facet_color,
        ] {
            assert!(x.is_finite(), "{name}: triangle {t}");
        }
    }
}

/// Counts of directed edges between positions: closed surfaces use each
/// edge once each way.
fn is_closed(mesh: &Mesh) -> bool {
    let key = |p: Vec3| (p + Vec3::ZERO).to_array().map(f32::to_bits);
    let mut edges: HashMap<_, u32> = HashMap::new();
    for t in 0..mesh.triangles.len() {
        let p = positions(mesh, t).map(key);
        for k in 0..3 {
            *edges.entry((p[k], p[(k + 1) % 3])).or_default() += 1;
        }
    }
    edges
        .iter()
        .all(|(&(a, b), &n)| n == 1 && edges.get(&(b, a)) == Some(&1))
}

#[test]
fn built_in_models_are_well_formed() {
    for (name, mesh, closed) in [
        ("triangle", triangle::triangle(), false),
        ("plane", plane::plane(), false),
        ("cube", cube::cube(true), true),
        ("sphere", sphere::sphere(), true),
    ] {
        check_mesh(name, &mesh);
        assert_eq!(mesh.closed, closed, "{name}");
        assert_eq!(is_closed(&mesh), closed, "{name}");
        assert!(mesh.convex, "{name}: a lone built-in never overlaps itself");
        assert!(mesh.triangles.iter().all(|t| t.textured), "{name}");
    }
}

#[test]
fn flat_models_carry_the_exact_texture_axes() {
    for (name, mesh) in [
        ("triangle", triangle::triangle()),
        ("plane", plane::plane()),
    ] {
        for t in 0..mesh.triangles.len() {
            let tri = mesh.face(t);
            let uv = tri.indices.map(|i| mesh.vertices[i as usize].uv);
            let (pu, pv) =
                relief_scene::face_frame::triangle_tangents(positions(&mesh, t), uv).unwrap();
            assert!((pu - 2.0 * Vec3::X).length() < 1e-5, "{name}: {pu}");
            assert!((pv - 2.0 * Vec3::Y).length() < 1e-5, "{name}: {pv}");
            assert_eq!((tri.face_tangent_u, tri.face_tangent_v), (pu, pv));
            for i in tri.indices {
                let v = mesh.vertices[i as usize];
                assert_eq!((v.tangent_u, v.tangent_v), (pu, pv));
                assert_eq!(v.normal, Vec3::Z);
            }
        }
    }
}

#[test]
fn plane_is_split_like_the_cube_faces() {
    let mesh = plane::plane();
    assert_eq!(mesh.vertices.len(), 4);
    let uv_of = |i: u32| mesh.vertices[i as usize].uv;
    // Both triangles share the (0,0)–(1,1) diagonal.
    for tri in &mesh.triangles {
        let uvs: Vec<Vec2> = tri.indices.iter().map(|&i| uv_of(i)).collect();
        assert!(uvs.contains(&Vec2::ZERO) && uvs.contains(&Vec2::ONE));
        assert!(
            tri.indices
                .iter()
                .all(|&i| mesh.vertices[i as usize].position.z == 0.0)
        );
    }
    let corners: Vec<Vec3> = mesh.vertices.iter().map(|v| v.position).collect();
    let max = corners
        .iter()
        .map(|p| p.abs().max_element())
        .fold(0.0, f32::max);
    assert_eq!(max, 1.0, "side 2");
}

#[test]
fn sphere_seam_is_clean() {
    let mesh = sphere::sphere();
    let du = 1.0 / sphere::SEGMENTS as f32;
    for t in 0..mesh.triangles.len() {
        let uv = mesh.triangles[t]
            .indices
            .map(|i| mesh.vertices[i as usize].uv);
        let (lo, hi) = (
            uv.iter().map(|p| p.x).fold(f32::MAX, f32::min),
            uv.iter().map(|p| p.x).fold(f32::MIN, f32::max),
        );
        // No triangle runs the texture backwards across the seam.
        assert!(hi - lo <= du + 1e-6, "triangle {t} spans u {lo}..{hi}");
        assert!((0.0..=1.0).contains(&lo) && hi <= 1.0);
    }
    // The seam column exists twice, at u = 0 and u = 1, at the same points.
    let at = |u: f32| -> Vec<Vec3> {
        let mut v: Vec<(u32, Vec3)> = mesh
            .vertices
            .iter()
            .filter(|v| v.uv.x == u && v.uv.y > 0.0 && v.uv.y < 1.0)
            .map(|v| ((v.uv.y * 1000.0) as u32, v.position))
            .collect();
        v.sort_by_key(|x| x.0);
        v.into_iter().map(|x| x.1).collect()
    };
    let (first, last) = (at(0.0), at(1.0));
    assert_eq!(first.len(), sphere::RINGS as usize - 1);
    assert_eq!(first, last);
}

#[test]
fn sphere_poles_have_one_vertex_per_triangle_and_a_frame() {
    let mesh = sphere::sphere();
    let mut uses: HashMap<u32, u32> = HashMap::new();
    for tri in &mesh.triangles {
        for &i in &tri.indices {
            if mesh.vertices[i as usize].position.y.abs() == 1.0 {
                *uses.entry(i).or_default() += 1;
            }
        }
    }
    assert_eq!(uses.len(), 2 * sphere::SEGMENTS as usize);
    assert!(uses.values().all(|&n| n == 1));
    for &i in uses.keys() {
        let v = mesh.vertices[i as usize];
        // u in the middle of its cell.
        let cell = v.uv.x * sphere::SEGMENTS as f32 - 0.5;
        assert!((cell - cell.round()).abs() < 1e-4, "pole u {}", v.uv.x);
        assert!(v.tangent_u.length() > 0.5 && v.tangent_v.length() > 3.0);
        // Right-handed with the outward normal, like the rest of the sphere.
        assert!(v.tangent_u.cross(v.tangent_v).normalize().dot(v.normal) > 0.999);
    }
}

#[test]
fn sphere_tangents_are_the_surface_derivatives() {
    let mesh = sphere::sphere();
    for v in mesh.vertices.iter().filter(|v| v.position.y.abs() < 1.0) {
        assert!((v.position.length() - 1.0).abs() < 1e-5);
        assert!((v.normal - v.position).length() < 1e-5);
        // |∂P/∂u| = 2π·cos(latitude), |∂P/∂v| = π.
        let cos_lat = (1.0 - v.position.y * v.position.y).sqrt();
        assert!((v.tangent_u.length() - std::f32::consts::TAU * cos_lat).abs() < 1e-4);
        assert!((v.tangent_v.length() - std::f32::consts::PI).abs() < 1e-4);
        assert!(v.tangent_u.cross(v.tangent_v).dot(v.normal) > 0.0);
        // ∂P/∂u points east: toward +X at the front.
        if v.uv.x == 0.5 {
            assert!(v.tangent_u.normalize().dot(Vec3::X) > 0.999);
        }
    }
    // Accumulating per face (docs/bump-dot3.md) finds the same directions.
    let mut acc = mesh.clone();
    tangents::accumulate(&mut acc);
    for (a, b) in mesh.vertices.iter().zip(&acc.vertices) {
        assert!(a.tangent_u.normalize().dot(b.tangent_u.normalize()) > 0.98);
        assert!(a.tangent_v.normalize().dot(b.tangent_v.normalize()) > 0.98);
    }
}

// ---- tangent frames --------------------------------------------------------

/// The plane with UVs given by `uv_of(position)` and its tangents cleared.
fn quad(uv_of: impl Fn(Vec3) -> Vec2) -> Mesh {
    let mut mesh = plane::plane();
    for v in &mut mesh.vertices {
        v.uv = uv_of(v.position);
        v.tangent_u = Vec3::ZERO;
        v.tangent_v = Vec3::ZERO;
    }
    mesh
}

#[test]
fn tangents_follow_the_uvs() {
    let mut mesh = quad(|p| Vec2::new(p.x + 1.0, p.y + 1.0) * 0.5);
    tangents::accumulate(&mut mesh);
    for v in &mesh.vertices {
        assert!((v.tangent_u - 2.0 * Vec3::X).length() < 1e-5);
        assert!((v.tangent_v - 2.0 * Vec3::Y).length() < 1e-5);
    }
}

#[test]
fn mirrored_uvs_keep_their_handedness() {
    // u runs right to left: ∂P/∂u points to −X and the frame is left-handed.
    let mut mesh = quad(|p| Vec2::new(1.0 - p.x, p.y + 1.0) * 0.5);
    tangents::accumulate(&mut mesh);
    for v in &mesh.vertices {
        assert!(
            (v.tangent_u - (-2.0) * Vec3::X).length() < 1e-5,
            "{}",
            v.tangent_u
        );
        assert!((v.tangent_v - 2.0 * Vec3::Y).length() < 1e-5);
        assert!(v.tangent_u.cross(v.tangent_v).dot(v.normal) < 0.0);
    }
    // What the shader must do with them: a height rising with u rises toward
    // −X here, so the bumped normal tilts toward +X. Blinn's perturbation
    // F_u·(N × Pv) − F_v·(N × Pu) is divided by the signed (Pu × Pv)·N: with
    // mirrored UVs that sign is negative, and only because both axes are
    // kept does the bump not invert.
    let v = mesh.vertices[0];
    let det = v.tangent_u.cross(v.tangent_v).dot(v.normal);
    let tilted = v.normal + 0.1 * v.normal.cross(v.tangent_v) / det;
    assert!(tilted.x > 0.0, "{tilted}");
}

#[test]
fn zero_uv_determinant_falls_back_to_a_frame_from_the_normal() {
    let constant = |_: Vec3| Vec2::splat(0.3);
    // Collinear UVs: every triangle has zero UV area.
    let collinear = |p: Vec3| Vec2::splat(p.x * 0.25 + p.y * 0.5);
    for uv_of in [&constant as &dyn Fn(Vec3) -> Vec2, &collinear] {
        let mut mesh = quad(uv_of);
        tangents::accumulate(&mut mesh);
        for v in &mesh.vertices {
            assert!(v.tangent_u.is_finite() && v.tangent_v.is_finite());
            assert!((v.tangent_u.length() - 1.0).abs() < 1e-5);
            assert!((v.tangent_u.cross(v.tangent_v) - v.normal).length() < 1e-5);
        }
        let frame = relief_scene::face_frame::face_frame(
            positions(&mesh, 0),
            mesh.triangles[0]
                .indices
                .map(|i| mesh.vertices[i as usize].uv),
            Vec3::Z,
        );
        assert!(!frame.from_uv);
    }
}

#[test]
fn a_vertex_between_mirrored_faces_still_gets_a_frame() {
    // Two quads side by side sharing the middle edge, the right one mirrored
    // in u, so ∂P/∂u cancels on the shared vertices.
    let mut mesh = plane::grid(1.0, 1.0, 2, |_| Vec3::ONE);
    for v in &mut mesh.vertices {
        let x = v.position.x;
        v.uv.x = 1.0 - x.abs();
        v.tangent_u = Vec3::ZERO;
        v.tangent_v = Vec3::ZERO;
    }
    tangents::accumulate(&mut mesh);
    for v in &mesh.vertices {
        assert!(v.tangent_u.is_finite() && v.tangent_u.length() > 0.1);
        assert!(v.tangent_u.dot(v.normal).abs() < 1e-5);
        assert!(v.tangent_v.normalize().dot(Vec3::Y) > 0.999);
        if v.position.x < -0.5 {
            assert!(v.tangent_u.x > 0.0);
        } else if v.position.x > 0.5 {
            assert!(v.tangent_u.x < 0.0);
        }
    }
}

// ---- OBJ files ---------------------------------------------------------------

fn fits_the_view(mesh: &Mesh) {
    let (mut lo, mut hi) = (Vec3::MAX, Vec3::MIN);
    let mut radius = 0.0f32;
    for v in &mesh.vertices {
        lo = lo.min(v.position);
        hi = hi.max(v.position);
        radius = radius.max(v.position.length());
    }
    assert!(((lo + hi) * 0.5).length() < 1e-5, "centred");
    assert!((radius - FIT_RADIUS).abs() < 1e-4, "radius {radius}");
}

#[test]
fn obj_cube_with_uvs_and_normals_keeps_its_24_vertices() {
    let mesh = obj::load(&data("cube.obj")).unwrap();
    check_mesh("cube.obj", &mesh);
    fits_the_view(&mesh);
    assert_eq!(mesh.triangles.len(), 12);
    assert_eq!(mesh.vertices.len(), 24);
    // A closed box, found convex when loaded.
    assert!(mesh.closed && mesh.convex);
    // Hard edges: every vertex normal is a face normal.
    for v in &mesh.vertices {
        assert_eq!(v.normal.abs().max_element(), 1.0, "{}", v.normal);
    }
    // Same texture axes as the reference cube, at the fitted scale.
    let scale = FIT_RADIUS / 3f32.sqrt();
    for (n, u, v) in cube::FACES {
        let tri = mesh
            .faces()
            .into_iter()
            .find(|t| t.face_normal == n)
            .unwrap();
        assert!((tri.face_tangent_u - 2.0 * scale * u).length() < 1e-4);
        assert!((tri.face_tangent_v - 2.0 * scale * v).length() < 1e-4);
    }
}

#[test]
fn computed_normals_keep_the_cube_hard_and_uvs_are_projected() {
    // The smoothed-cube pitfall: positions shared by three faces must not
    // get one averaged normal.
    let mesh = obj::load(&data("cube_positions_only.obj")).unwrap();
    check_mesh("cube_positions_only.obj", &mesh);
    fits_the_view(&mesh);
    assert_eq!(mesh.vertices.len(), 24);
    for tri in &mesh.faces() {
        for &i in &tri.indices {
            let v = mesh.vertices[i as usize];
            assert!((v.normal - tri.face_normal).length() < 1e-6);
            // Box projection: the cube's own axes, right-handed, 0..1 over a face.
            assert!(v.tangent_u.cross(v.tangent_v).dot(v.normal) > 0.0);
            assert!(v.uv.min_element() >= -1e-6 && v.uv.max_element() <= 1.0 + 1e-6);
        }
    }
    let reference = obj::load(&data("cube.obj")).unwrap();
    let mut a: Vec<[u32; 3]> = mesh
        .vertices
        .iter()
        .map(|v| {
            (v.position * 1e4)
                .round()
                .to_array()
                .map(|x| x as i32 as u32)
        })
        .collect();
    let mut b: Vec<[u32; 3]> = reference
        .vertices
        .iter()
        .map(|v| {
            (v.position * 1e4)
                .round()
                .to_array()
                .map(|x| x as i32 as u32)
        })
        .collect();
    a.sort();
    b.sort();
    assert_eq!(a, b, "offset and scale are normalised away");
}

/// A UV sphere written as OBJ text with positions only and shared vertices.
fn sphere_obj(segments: u32, rings: u32) -> String {
    let mut s = String::from("v 0 -1 0\n");
    for j in 1..rings {
        let lat = std::f32::consts::PI * (j as f32 / rings as f32 - 0.5);
        for i in 0..segments {
            let lon = std::f32::consts::TAU * i as f32 / segments as f32;
            s += &format!(
                "v {} {} {}\n",
                lat.cos() * lon.sin(),
                lat.sin(),
                lat.cos() * lon.cos()
            );
        }
    }
    s += "v 0 1 0\n";
    let ring = |i: u32, j: u32| 2 + (j - 1) * segments + i % segments;
    let top = 2 + (rings - 1) * segments;
    for i in 0..segments {
        s += &format!("f 1 {} {}\n", ring(i + 1, 1), ring(i, 1));
        s += &format!(
            "f {} {} {}\n",
            ring(i, rings - 1),
            ring(i + 1, rings - 1),
            top
        );
        for j in 1..rings - 1 {
            s += &format!(
                "f {} {} {} {}\n",
                ring(i, j),
                ring(i + 1, j),
                ring(i + 1, j + 1),
                ring(i, j + 1)
            );
        }
    }
    s
}

#[test]
fn computed_normals_are_smooth_on_curved_surfaces() {
    let mesh = obj::parse("sphere.obj", sphere_obj(24, 12)).unwrap();
    check_mesh("sphere.obj", &mesh);
    assert!(mesh.closed);
    for v in &mesh.vertices {
        // The smooth normal of a sphere is its position direction.
        assert!(
            v.normal.dot(v.position.normalize()) > 0.999,
            "{} at {}",
            v.normal,
            v.position
        );
    }
}

#[test]
fn a_point_with_a_vertex_per_face_keeps_them_apart() {
    // A flat disc of 100 faces round one centre: the centre has a UV of its
    // own in each face (100 vertices at one point, past the walk's limit),
    // the rim corners share one UV and the plane's normal (a vertex each).
    let n = 100;
    let mut text = String::from("v 0 0 0\n");
    for i in 0..n {
        let a = i as f32 / n as f32 * std::f32::consts::TAU;
        text += &format!("v {} {} 0\n", a.cos(), a.sin());
    }
    for i in 0..n {
        text += &format!("vt {} 0.5\n", i as f32 / n as f32);
    }
    text += "vt 0.5 1\nvn 0 0 1\n";
    for i in 0..n {
        let (a, b) = (i + 2, (i + 1) % n + 2);
        text += &format!("f 1/{}/1 {a}/{}/1 {b}/{}/1\n", i + 1, n + 1, n + 1);
    }
    let mesh = obj::parse("disc.obj", &text).unwrap();
    check_mesh("disc.obj", &mesh);
    assert_eq!(mesh.triangles.len(), n);
    assert_eq!(mesh.vertices.len(), 2 * n);
    // Each face's centre corner is its own vertex, with that face's UV.
    for (i, t) in mesh.triangles.iter().enumerate() {
        let centre = mesh.vertices[t.indices[0] as usize];
        assert_eq!(centre.uv.x, i as f32 / n as f32);
    }
}

#[test]
fn relative_indices_polygons_groups_colours_and_crlf() {
    let mesh = obj::load(&data("pyramid_relative.obj")).unwrap();
    check_mesh("pyramid_relative.obj", &mesh);
    fits_the_view(&mesh);
    assert_eq!(mesh.triangles.len(), 6);
    assert!(mesh.closed);
    let apex = mesh.vertices.iter().find(|v| v.position.y > 0.0).unwrap();
    assert_eq!(apex.color, Vec3::X, "the file's vertex colour");
}

#[test]
fn obj_models_load_through_the_model_choice() {
    let choice: ModelChoice = data("cube.obj").to_str().unwrap().parse().unwrap();
    assert_eq!(choice.label(), "cube.obj");
    let texture = Arc::new(procedural::brick());
    let Built::Scene(scene) = build_scene(SceneKind::Cube, &choice, texture, false).unwrap() else {
        panic!("a 3D scene")
    };
    assert_eq!(scene.objects.len(), 1);
    assert_eq!(scene.objects[0].mesh.triangles.len(), 12);
}

/// The error of a load that must fail (without printing a whole mesh if it did not).
fn failure(result: Result<Mesh, ObjError>) -> ObjError {
    match result {
        Ok(mesh) => panic!("loaded {} triangles", mesh.triangles.len()),
        Err(e) => e,
    }
}

fn error_of(name: &str) -> ObjError {
    failure(obj::load(&data(name)))
}

fn one_clean_line(e: &ObjError) -> String {
    let text = e.to_string();
    assert!(
        !text.contains('\n') && !text.chars().any(char::is_control),
        "{text:?}"
    );
    text
}

#[test]
fn bad_files_give_one_clear_line() {
    let e = error_of("bad_index.obj");
    assert!(matches!(e, ObjError::Line { line: 5, .. }), "{e:?}");
    assert!(one_clean_line(&e).contains("vertex index 4 is out of range"));

    let e = error_of("bad_number.obj");
    assert!(matches!(e, ObjError::Line { line: 2, .. }), "{e:?}");
    assert!(one_clean_line(&e).contains("'nan' is not a finite number"));
    assert!(one_clean_line(&e).contains("position"), "{e}");

    // A NaN in a vertex's colour is named as the colour.
    let e = failure(obj::parse(
        "colour.obj",
        "v 0 0 0 1 0 0\nv 1 0 0 0 nan 0\nv 0 1 0 0 0 1\nf 1 2 3\n",
    ));
    let text = one_clean_line(&e);
    assert!(text.contains("vertex colour: 'nan'"), "{text}");
    assert!(!text.contains("position"), "{text}");

    assert!(matches!(error_of("no_faces.obj"), ObjError::Empty { .. }));
    assert!(matches!(
        error_of("flat_line.obj"),
        ObjError::Degenerate { .. }
    ));
    // Two faces that repeat a corner: they are there, with no area.
    let e = failure(obj::parse(
        "repeats.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 1 2\nf 2 2 3\n",
    ));
    assert!(matches!(e, ObjError::Degenerate { .. }), "{e:?}");
    let e = error_of("missing.obj");
    assert!(matches!(e, ObjError::NotFound { .. }), "{e:?}");
    assert!(one_clean_line(&e).ends_with("missing.obj not found"), "{e}");
    assert!(matches!(
        obj::load(&data("")),
        Err(ObjError::NotAFile { .. })
    ));
}

#[test]
fn bad_text_is_refused_with_its_line() {
    let cases = [
        ("", "no faces"),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", "line 4"),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -4 1 2\n", "out of range"),
        (
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/2/3/4 2 3\n",
            "bad face corner",
        ),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x\n", "not a whole number"),
        (
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99999999999999999999999\n",
            "line 4",
        ),
        ("v 1e39 0 0\n", "not a finite number"),
        ("v 0 0\n", "needs 3 numbers"),
        ("v 0 0 0 0\n", "bad w"),
        ("v 0 0 0 1 1\n", "5 numbers"),
        ("vt 0 inf\n", "not a finite number"),
        ("vn 0 0\n", "needs 3 numbers"),
        (
            "v 0 0 0\nv 0 0 0\nv 0 0 0\nf 1 2 3\n",
            "no face with an area",
        ),
        ("v 0 0 0 1 1 1 1\n", "more than 6 numbers"),
        ("vt\n", "needs 1 numbers"),
        (
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3#\nf 1 2 4 # four\n",
            "line 5: vertex index 4",
        ),
        (
            "\u{feff}v 0 0 0\nv 1 0 0\nf 1 2 3\n",
            "line 3: vertex index 3",
        ),
        ("v 0 0 0\rv 1 0 0\rf 1 2 3\r", "line 3: vertex index 3"),
        (
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 1 1 2 2 2\n",
            "no face with an area",
        ),
        ("v 0 0 0\nf 1 1 1\nv 0 0 \u{1b}[31m\n", "'?[31m'"),
    ];
    for (text, expected) in cases {
        let e = failure(obj::parse("t.obj", text));
        let line = one_clean_line(&e);
        assert!(line.contains(expected), "{text:?} gave {line:?}");
        assert!(line.starts_with("model t.obj"), "{line}");
    }
    // Texture coordinate and normal indices out of range drop that attribute
    // for the face, with a warning, as tinyobjloader does.
    for (text, expected) in [
        (
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/1 2/1 3/1\n",
            "line 4: 1 line(s) with a texture coordinate index out of range",
        ),
        (
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1//2 2//2 3//2\n",
            "line 4: 1 line(s) with a normal index out of range",
        ),
    ] {
        let model = obj::parse_model("t.obj", text.as_bytes(), None).unwrap();
        assert_eq!(model.merged().triangles.len(), 1);
        assert!(model.warnings[0].contains(expected), "{:?}", model.warnings);
    }
}

fn temp_path(name: &str) -> PathBuf {
    std::env::temp_dir().join(format!("relief-models-{}-{name}", std::process::id()))
}

#[test]
fn huge_and_binary_files_are_refused() {
    // No fixed size limit: a file larger than the memory budget is refused
    // by the budget, before it is read (the file is sparse: nothing written).
    let path = temp_path("huge.obj");
    let file = std::fs::File::create(&path).unwrap();
    file.set_len(relief_core::budget::BUDGET_BYTES + 1).unwrap();
    drop(file);
    let e = failure(obj::load(&path));
    assert!(matches!(e, ObjError::Budget { .. }), "{e:?}");
    assert!(one_clean_line(&e).contains("memory budget"), "{e}");

    std::fs::write(&path, b"v 0 0 0\n\xff\xfe\x00 binary\n").unwrap();
    let e = failure(obj::load(&path));
    assert!(matches!(e, ObjError::NotText { at: 10, .. }), "{e:?}");
    std::fs::remove_file(&path).unwrap();

    // A name with control characters never reaches the message raw.
    let e = failure(obj::load(Path::new("/nonexistent/\u{1b}]0;pwned\u{7}.obj")));
    assert!(one_clean_line(&e).contains("?]0;pwned?.obj"));
}

#[test]
fn models_beyond_the_memory_budget_are_refused() {
    // A polygon is bounded on its own line, before anything is built from it.
    let mut text: String = "v 0 0 0\nv 1 0 0\nv 0 1 0\n# a huge polygon\nf".into();
    text += &" 1 2 3".repeat(corners::MAX_FACE_CORNERS / 3 + 1);
    let e = failure(obj::parse("big.obj", &text));
    assert!(matches!(e, ObjError::Line { line: 5, .. }), "{e:?}");
    assert!(one_clean_line(&e).contains("limit 65536"), "{e}");
    // More triangles than the budget holds at READ_BYTES_PER_TRIANGLE each
    // (fans of the same three corners, two bytes a triangle): refused by
    // the counting pass, before any corner is stored.
    let triangles =
        (relief_core::budget::BUDGET_BYTES / obj::read::READ_BYTES_PER_TRIANGLE) as usize + 1;
    let fan = corners::MAX_FACE_CORNERS / 3 * 3;
    let face = format!("f{}\n", " 1 2 3".repeat(fan / 3));
    text = "v 0 0 0\nv 1 0 0\nv 0 1 0\n".into();
    text += &face.repeat(triangles.div_ceil(fan - 2));
    let e = failure(obj::parse("big.obj", &text));
    assert!(matches!(e, ObjError::Budget { .. }), "{e:?}");
    assert!(one_clean_line(&e).contains("big.obj"), "{e}");
}

// ---- scenes ------------------------------------------------------------------

#[test]
fn every_scene_kind_and_model_builds() {
    let texture = Arc::new(procedural::brick());
    for model in [
        ModelChoice::Triangle,
        ModelChoice::Plane,
        ModelChoice::Cube,
        ModelChoice::Sphere,
    ] {
        let Built::Scene(scene) =
            build_scene(SceneKind::Cube, &model, texture.clone(), false).unwrap()
        else {
            panic!("a 3D scene")
        };
        assert_eq!(scene.objects.len(), 1);
        assert!(scene.objects[0].rotates);
        assert_eq!(scene.objects[0].mesh, model.mesh(false).unwrap());
        assert_eq!(model.label().parse::<ModelChoice>().unwrap(), model);
    }
    // The model cycle visits the four built-ins.
    let mut m = ModelChoice::Triangle;
    for _ in 0..4 {
        m = m.next();
    }
    assert_eq!(m, ModelChoice::Triangle);
    assert_eq!(SceneKind::Cube.next().next().next(), SceneKind::Cube);
    assert!(matches!(
        build_scene(
            SceneKind::Plasma,
            &ModelChoice::Cube,
            texture.clone(),
            false
        ),
        Ok(Built::Plasma(_))
    ));
    // A bad OBJ is an error, not a panic, in the scene that uses it only.
    let bad = ModelChoice::File(data("bad_index.obj"));
    assert!(build_scene(SceneKind::Cube, &bad, texture.clone(), false).is_err());
    assert!(build_scene(SceneKind::Shadow, &bad, texture, false).is_ok());
}

#[test]
fn shadow_scene_puts_a_still_floor_under_the_turning_cube() {
    let texture = Arc::new(procedural::brick());
    let Built::Scene(scene) =
        build_scene(SceneKind::Shadow, &ModelChoice::Cube, texture, true).unwrap()
    else {
        panic!("a 3D scene")
    };
    assert_eq!(scene.objects.len(), 2);
    let (cube, floor) = (&scene.objects[0], &scene.objects[1]);
    assert!(cube.rotates && !floor.rotates);
    assert_eq!(cube.mesh, cube::cube(true));
    let up = floor.transform.transform_vector3(Vec3::Z);
    assert!((up - Vec3::Y).length() < 1e-6, "the floor faces up");
    for v in &floor.mesh.vertices {
        let p = floor.transform.transform_point3(v.position);
        assert!((p.y - relief_scene::build::FLOOR_Y).abs() < 1e-5);
    }
    // The turning cube (radius √3) never reaches the floor.
    assert!(relief_scene::build::FLOOR_Y < -(3f32.sqrt()));
    // The shadow of the cube's centre, cast by the white light, is on the
    // floor and in view.
    let light = scene.lights[0].position;
    let t = (light.y - relief_scene::build::FLOOR_Y) / light.y;
    let shadow = light + t * (Vec3::ZERO - light);
    assert!(shadow.x.abs() < relief_scene::build::FLOOR_HALF);
    assert!(shadow.z.abs() < relief_scene::build::FLOOR_HALF);
    let clip = scene.camera.projection(4.0 / 3.0) * scene.camera.view() * shadow.extend(1.0);
    let ndc = clip.truncate() / clip.w;
    assert!(
        clip.w > 0.0 && ndc.x.abs() < 0.8 && ndc.y.abs() < 0.8,
        "{ndc}"
    );
}
