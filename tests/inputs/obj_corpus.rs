//! OBJ files as real exporters write them (tests/data/obj): each loads, with
//! the triangles, UVs, normals and colours the file says.

use std::path::{Path, PathBuf};

use glam::{Vec2, Vec3};
use relief_scene::Mesh;
use relief_scene::obj;

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/obj")
        .join(name)
}

fn load(name: &str) -> Mesh {
    obj::load(&data(name)).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// The distinct values of `f` over the vertices, rounded to 1/1000.
fn distinct<const N: usize>(
    mesh: &Mesh,
    f: impl Fn(&relief_scene::Vertex) -> [f32; N],
) -> Vec<[i32; N]> {
    let mut out: Vec<[i32; N]> = mesh
        .vertices
        .iter()
        .map(|v| f(v).map(|x| (x * 1000.0).round() as i32))
        .collect();
    out.sort_unstable();
    out.dedup();
    out
}

#[test]
fn cube_with_a_material_library_loads_closed() {
    let mesh = load("cube_mtl.obj");
    assert_eq!(mesh.triangles.len(), 12);
    assert_eq!(mesh.vertices.len(), 24);
    assert!(mesh.closed);
    // The file's UVs are kept.
    assert!(mesh.vertices.iter().any(|v| v.uv == Vec2::new(0.875, 0.75)));
}

#[test]
fn empty_usemtl_is_ignored() {
    assert_eq!(load("empty_usemtl.obj").triangles.len(), 2);
}

#[test]
fn colours_on_some_vertices_leave_the_others_white() {
    let mesh = load("partial_colors.obj");
    assert_eq!(mesh.triangles.len(), 2);
    let colours = distinct(&mesh, |v| v.color.to_array());
    assert_eq!(
        colours,
        vec![[0, 0, 1000], [1000, 0, 0], [1000, 1000, 1000]]
    );
}

#[test]
fn a_byte_order_mark_is_skipped() {
    let mesh = load("bom.obj");
    assert_eq!(mesh.triangles.len(), 1);
}

#[test]
fn latin1_names_and_comments_are_read() {
    assert_eq!(load("latin1.obj").triangles.len(), 1);
}

#[test]
fn trailing_comments_are_cut() {
    let mesh = load("trailing_comments.obj");
    assert_eq!(mesh.triangles.len(), 1);
    assert_eq!(
        distinct(&mesh, |v| v.uv.to_array()),
        vec![[0, 0], [0, 1000], [1000, 0]]
    );
    assert!(mesh.vertices.iter().all(|v| v.normal == Vec3::Z));
}

#[test]
fn a_one_number_vt_has_v_zero() {
    let mesh = load("vt_one_number.obj");
    assert_eq!(
        distinct(&mesh, |v| v.uv.to_array()),
        vec![[250, 0], [500, 1000], [750, 0]]
    );
}

#[test]
fn quads_are_split_in_two() {
    let mesh = load("quad_mesh.obj");
    assert_eq!(mesh.triangles.len(), 12);
    assert_eq!(mesh.vertices.len(), 12);
    assert!(!mesh.closed);
}

#[test]
fn negative_indices_name_the_vertices_before() {
    let mesh = load("negative_indices.obj");
    assert_eq!(mesh.triangles.len(), 3);
    // The first triangle at z = 0, the quad at z = 1: two depths.
    assert_eq!(distinct(&mesh, |v| [v.position.z]).len(), 2);
}

#[test]
fn normals_without_uvs_are_normalised() {
    let mesh = load("normals_only.obj");
    assert_eq!(mesh.triangles.len(), 1);
    assert!(mesh.vertices.iter().all(|v| v.normal == Vec3::Z));
}

#[test]
fn uvs_without_normals_are_kept() {
    let mesh = load("uv_only.obj");
    assert_eq!(
        distinct(&mesh, |v| v.uv.to_array()),
        vec![[0, 0], [0, 1000], [1000, 0]]
    );
    assert!(mesh.vertices.iter().all(|v| v.normal == Vec3::Z));
}

#[test]
fn objects_groups_points_and_lines() {
    // Two one-sided triangles (front and back) and a quad; points and lines not drawn.
    assert_eq!(load("groups.obj").triangles.len(), 4);
}

#[test]
fn repeated_corners_are_dropped() {
    // 1 1 2 2 2 3 3 4 1 1 is the quad 1 2 3 4; 1 2 2 1 is a line.
    let mesh = load("repeats.obj");
    assert_eq!(mesh.triangles.len(), 2);
    assert_eq!(mesh.vertices.len(), 4);
}

#[test]
fn carriage_returns_alone_end_lines() {
    assert_eq!(load("old_mac.obj").triangles.len(), 1);
}

#[test]
fn errors_keep_their_line_whatever_the_encoding() {
    // After a BOM, Latin-1 bytes and CR-only lines, the bad index is on line 4.
    let text = b"\xef\xbb\xbfo caf\xe9\rv 0 0 0\r\nv 1 0 0 # \xe9\nf 1 2 3\n";
    let e = obj::parse("t.obj", text).unwrap_err().to_string();
    assert_eq!(
        e,
        "model t.obj, line 4: vertex index 3 is out of range (there are 2 so far)"
    );
    let e = obj::parse("t.obj", b"v 0 0 \xe9\n")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("line 1") && e.contains("not a finite number"),
        "{e}"
    );
}

#[test]
fn the_exported_cube_has_the_corners_of_the_hand_written_one() {
    // The hand-written cube in tests/data and the exported one give the same shape.
    let a = load("cube_mtl.obj");
    let b = obj::load(&data("../cube.obj")).unwrap();
    assert_eq!(a.triangles.len(), b.triangles.len());
    let corners = |m: &Mesh| distinct(m, |v| v.position.to_array());
    assert_eq!(corners(&a), corners(&b));
}
