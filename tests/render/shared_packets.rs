//! Small triangles' last pixels shaded together (`raster::pending`): the
//! frame is the very frame each triangle shading its own pixels gives, bit
//! for bit and counter for counter, on dense spheres (pixels of one or two
//! a triangle) without a depth buffer (one convex sphere), with one (a
//! dented sphere, which also shades itself through its shadow map), drawn
//! depth first (spheres stacked towards the eye), with two materials side
//! by side, and with quads drawn over pixels still waiting, on one thread
//! and on three: glTF metallic-roughness spheres, and the same spheres as
//! a PLY, which the Phong kernel draws.

use glam::Vec3;
use relief_core::framebuffer::Framebuffer;
use relief_core::settings::Settings;
use relief_core::stats::FrameStats;
use relief_pipeline::render::Renderer;
use relief_scene::Scene;

use crate::glb_writer::Bin;

/// A UV sphere of `rings` × `segments` about `centre`, its radius dented
/// by `dent` (1 + dent·sin 7θ·sin 9φ), every vertex shared (one at each
/// pole, the seam closed: a closed surface, so found convex undented):
/// positions, normals, texture coordinates and colours appended to `mesh`.
fn sphere(
    mesh: &mut Mesh,
    (centre, colour): (Vec3, [f32; 3]),
    dent: f32,
    (rings, segments): (u16, u16),
) {
    let base = (mesh.positions.len() / 3) as u16;
    let mut vertex = |theta: f32, phi: f32| {
        let n = Vec3::new(
            theta.sin() * phi.cos(),
            theta.cos(),
            theta.sin() * phi.sin(),
        );
        let r = 1.0 + dent * (7.0 * theta).sin() * (9.0 * phi).sin();
        let p = centre + n * r;
        mesh.positions.extend([p.x, p.y, p.z]);
        mesh.normals.extend([n.x, n.y, n.z]);
        mesh.uvs
            .extend([phi / std::f32::consts::TAU, theta / std::f32::consts::PI]);
        mesh.colours.extend(colour);
    };
    vertex(0.0, 0.0);
    for i in 1..rings {
        let theta = std::f32::consts::PI * f32::from(i) / f32::from(rings);
        for j in 0..segments {
            vertex(
                theta,
                std::f32::consts::TAU * f32::from(j) / f32::from(segments),
            );
        }
    }
    vertex(std::f32::consts::PI, 0.0);
    // Ring i (1..rings) vertex j; the poles before and after them.
    let at = |i: u16, j: u16| base + 1 + (i - 1) * segments + j % segments;
    let (top, bottom) = (base, base + 1 + (rings - 1) * segments);
    for j in 0..segments {
        // Counter-clockwise seen from outside.
        mesh.indices.extend([top, at(1, j + 1), at(1, j)]);
        mesh.indices
            .extend([bottom, at(rings - 1, j), at(rings - 1, j + 1)]);
        for i in 1..rings - 1 {
            let (a, b) = (at(i, j), at(i + 1, j));
            let (a1, b1) = (at(i, j + 1), at(i + 1, j + 1));
            mesh.indices.extend([a, a1, b, a1, b1, b]);
        }
    }
}

/// Two quads over the left and right halves of the unit sphere, in
/// front of it (z = 1.5, facing +Z, blue), drawn after the first and the
/// second third of `mesh`'s triangles: each covers, with packets shaded at
/// once, the sphere's pixels still waiting to be shaded then.
fn add_quads(mesh: &mut Mesh) {
    let far: Vec<u16> = std::mem::take(&mut mesh.indices);
    let third = far.len() / 9 * 3;
    let mut quad = |x0: f32, x1: f32| {
        let base = (mesh.positions.len() / 3) as u16;
        for (x, y) in [(x0, -1.2), (x1, -1.2), (x1, 1.2), (x0, 1.2)] {
            mesh.positions.extend([x, y, 1.5]);
            mesh.normals.extend([0.0, 0.0, 1.0]);
            mesh.uvs.extend([x, y]);
            mesh.colours.extend([0.2, 0.4, 1.0]);
        }
        [base, base + 1, base + 2, base, base + 2, base + 3]
    };
    let (left, right) = (quad(-1.2, 0.0), quad(0.0, 1.2));
    mesh.indices = [
        &far[..third],
        &left,
        &far[third..2 * third],
        &right,
        &far[2 * third..],
    ]
    .concat();
}

#[derive(Default)]
struct Mesh {
    positions: Vec<f32>,
    normals: Vec<f32>,
    uvs: Vec<f32>,
    colours: Vec<f32>,
    indices: Vec<u16>,
}

/// A PNG of `w` × `h` whose texels vary (so neighbouring pixels read
/// different values).
fn varying_png(w: u32, h: u32, f: impl Fn(u32, u32) -> [u8; 4]) -> Vec<u8> {
    let img = image::RgbaImage::from_fn(w, h, |x, y| image::Rgba(f(x, y)));
    relief_texture::picture::encode(&img.into(), image::ImageFormat::Png).unwrap()
}

/// A GLB of the spheres of `parts` (each its own primitive and material:
/// a textured metal-roughness material with a normal map, material `k`
/// tinted by k), with `add_quads` in the first when `quads`.
fn spheres_glb(parts: &[Vec<(Vec3, f32, u16)>], quads: bool) -> Vec<u8> {
    let mut bin = Bin::default();
    let mut prims = Vec::new();
    for (k, spheres) in parts.iter().enumerate() {
        let mut mesh = Mesh::default();
        for &(centre, dent, rings) in spheres {
            sphere(&mut mesh, (centre, [1.0; 3]), dent, (rings, 2 * rings));
        }
        if quads {
            add_quads(&mut mesh);
        }
        let p = bin.positions(&mesh.positions);
        let n = bin.floats(&mesh.normals, "VEC3");
        let t = bin.floats(&mesh.uvs, "VEC2");
        let c = bin.floats(&mesh.colours, "VEC3");
        let i = bin.shorts(&mesh.indices, "SCALAR");
        prims.push(format!(
            r#"{{"attributes":{{"POSITION":{p},"NORMAL":{n},"TEXCOORD_0":{t},"COLOR_0":{c}}},"indices":{i},"material":{k}}}"#
        ));
    }
    let images = [
        varying_png(32, 16, |x, y| [(x * 8) as u8, (y * 16) as u8, 160, 255]),
        varying_png(16, 16, |x, y| [0, (x * 16) as u8, (y * 16) as u8, 255]),
        varying_png(16, 16, |x, y| {
            [128 + (x % 3) as u8 * 30, 128 + (y % 5) as u8 * 20, 230, 255]
        }),
    ];
    let mut image_json = Vec::new();
    for png in &images {
        image_json.push(format!(
            r#"{{"bufferView":{},"mimeType":"image/png"}}"#,
            bin.view(png)
        ));
    }
    let materials: Vec<String> = (0..parts.len())
        .map(|k| {
            format!(
                r#"{{"pbrMetallicRoughness":{{"baseColorFactor":[1,{},0.8,1],"baseColorTexture":{{"index":0}},"metallicFactor":0.7,"roughnessFactor":0.6,"metallicRoughnessTexture":{{"index":1}}}},"normalTexture":{{"index":2}}}}"#,
                1.0 - 0.4 * k as f32
            )
        })
        .collect();
    let nodes: Vec<String> = (0..parts.len())
        .map(|k| format!(r#"{{"mesh":{k}}}"#))
        .collect();
    let meshes: Vec<String> = prims
        .iter()
        .map(|p| format!(r#"{{"primitives":[{p}]}}"#))
        .collect();
    let roots: Vec<String> = (0..parts.len()).map(|k| k.to_string()).collect();
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[{}]}}],"nodes":[{}],"meshes":[{}],"materials":[{}],"images":[{}],"textures":[{{"source":0}},{{"source":1}},{{"source":2}}]"#,
        roots.join(","),
        nodes.join(","),
        meshes.join(","),
        materials.join(","),
        image_json.join(",")
    );
    bin.glb(&json)
}

/// An ASCII PLY of the spheres of `spheres` (positions, normals, texture
/// coordinates, colours varying by vertex), with `add_quads` when `quads`:
/// a file without a material, drawn by the Phong kernel.
fn spheres_ply(spheres: &[(Vec3, f32, u16)], quads: bool) -> String {
    let mut mesh = Mesh::default();
    for (k, &(centre, dent, rings)) in spheres.iter().enumerate() {
        let colour = [0.9, 0.5 + 0.1 * k as f32, 0.3];
        sphere(&mut mesh, (centre, colour), dent, (rings, 2 * rings));
    }
    if quads {
        add_quads(&mut mesh);
    }
    let count = mesh.positions.len() / 3;
    let mut ply = format!(
        "ply\nformat ascii 1.0\nelement vertex {count}\nproperty float x\nproperty float y\n\
         property float z\nproperty float nx\nproperty float ny\nproperty float nz\n\
         property float s\nproperty float t\nproperty float red\nproperty float green\n\
         property float blue\nelement face {}\nproperty list uchar int vertex_indices\n\
         end_header\n",
        mesh.indices.len() / 3
    );
    for i in 0..count {
        let p = &mesh.positions[3 * i..3 * i + 3];
        let n = &mesh.normals[3 * i..3 * i + 3];
        let t = &mesh.uvs[2 * i..2 * i + 2];
        // Each vertex a little its own colour, so neighbours differ.
        let c = &mesh.colours[3 * i..3 * i + 3];
        let shade = 0.8 + 0.2 * ((i * 7 % 11) as f32 / 10.0);
        ply += &format!(
            "{} {} {} {} {} {} {} {} {} {} {}\n",
            p[0],
            p[1],
            p[2],
            n[0],
            n[1],
            n[2],
            t[0],
            t[1],
            c[0] * shade,
            c[1] * shade,
            c[2]
        );
    }
    for f in mesh.indices.chunks(3) {
        ply += &format!("3 {} {} {}\n", f[0], f[1], f[2]);
    }
    ply
}

fn scene(test: &str, parts: &[Vec<(Vec3, f32, u16)>], quads: bool) -> Scene {
    let dir = crate::common::scratch::scratch_dir(&format!("shared-packets-{test}"));
    let path = dir.join("spheres.glb");
    std::fs::write(&path, spheres_glb(parts, quads)).unwrap();
    crate::render::pbr::load(path)
}

/// The scene of `spheres_ply` in the model view, with the scene's
/// texture (chosen: the user named it).
fn phong_scene(test: &str, spheres: &[(Vec3, f32, u16)], quads: bool) -> Scene {
    let dir = crate::common::scratch::scratch_dir(&format!("shared-packets-{test}"));
    let path = dir.join("spheres.ply");
    std::fs::write(&path, spheres_ply(spheres, quads)).unwrap();
    crate::render::pbr::load(path)
}

/// The frame with small triangles' pixels shaded together or not, on a
/// pool of `threads`.
fn frame(
    scene: &Scene,
    shared: bool,
    (w, h): (usize, usize),
    (threads, settings): (usize, &Settings),
) -> (Framebuffer, FrameStats) {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| {
        let mut renderer = Renderer::new();
        renderer.set_shared_packets(shared);
        let mut fb = Framebuffer::new(w, h);
        let stats = renderer.render(scene, settings, &mut fb);
        (fb, stats)
    })
}

fn same_either_way(test: &str, parts: &[Vec<(Vec3, f32, u16)>]) {
    same_either_way_in(test, parts, false);
}

/// `same_either_way`, with quads in front of the first material's
/// spheres when `quads` (`add_quads`), seen head on.
fn same_either_way_in(test: &str, parts: &[Vec<(Vec3, f32, u16)>], quads: bool) {
    let scene = scene(test, parts, quads);
    same_frames(test, &scene, quads, &view(quads, Settings::default()));
}

/// `settings`, seen head on when `quads` (for `add_quads`).
fn view(quads: bool, settings: Settings) -> Settings {
    match quads {
        true => Settings {
            rotation: Vec3::new(-relief_scene::model_view::ELEVATION_DEGREES, 0.0, 0.0),
            ..settings
        },
        false => settings,
    }
}

/// The frames and counters of `scene` under `settings` are the same with
/// small triangles' pixels shaded together or not, at two sizes on one
/// thread and three; the triangles are small (unless `quads` cover many
/// pixels).
fn same_frames(test: &str, scene: &Scene, quads: bool, settings: &Settings) {
    for (size, threads) in [((160, 120), 1), ((200, 150), 3)] {
        let (a, sa) = frame(scene, true, size, (threads, settings));
        let (b, sb) = frame(scene, false, size, (threads, settings));
        let differ = a
            .pixels()
            .iter()
            .zip(b.pixels())
            .filter(|(x, y)| x != y)
            .count();
        assert_eq!(
            differ, 0,
            "{test}: {differ} pixels differ at {size:?}, {threads} threads"
        );
        assert_eq!(
            sa.counters, sb.counters,
            "{test} at {size:?}, {threads} threads"
        );
        // The case the queue is for: a few pixels a triangle (the quads
        // cover many).
        let c = sa.counters;
        assert!(c.pixels_shaded > 1000, "{test}: {c:?}");
        assert!(
            quads || c.pixels_shaded < 4 * c.triangles_drawn,
            "{test}: {c:?}"
        );
    }
}

#[test]
fn a_dense_convex_sphere_is_drawn_the_same() {
    same_either_way("convex", &[vec![(Vec3::ZERO, 0.0, 80)]]);
}

#[test]
fn a_dense_dented_sphere_is_drawn_the_same_behind_its_depth_buffer() {
    same_either_way("dented", &[vec![(Vec3::ZERO, 0.08, 80)]]);
}

#[test]
fn stacked_spheres_drawn_depth_first_are_drawn_the_same() {
    // Five layers over one disc: an overdraw far above the pre-pass's 2.
    let stack: Vec<(Vec3, f32, u16)> = (0..5)
        .map(|k| (Vec3::new(0.02 * k as f32, 0.0, -0.1 * k as f32), 0.0, 80))
        .collect();
    same_either_way("stacked", &[stack]);
}

#[test]
fn two_materials_overlapping_are_drawn_the_same() {
    same_either_way(
        "two-materials",
        &[
            vec![(Vec3::new(-0.6, 0.0, 0.0), 0.0, 80)],
            vec![(Vec3::new(0.6, 0.1, 0.3), 0.05, 80)],
        ],
    );
}

/// A dense sphere and two quads in front of it drawn in the middle of
/// its triangles (`add_quads`): the quads' packets, shaded at once, cover
/// the sphere's pixels that wait to be shaded, and the depth buffer keeps
/// the quads' colour.
#[test]
fn a_near_quad_drawn_over_waiting_pixels_keeps_its_colour() {
    same_either_way_in("quads", &[vec![(Vec3::ZERO, 0.0, 80)]], true);
}

/// The Phong kernel's pixels (a PLY, no material of its own) under the
/// settings of each of its kernels that share packets: the scene's
/// texture or none, highlights or none, Blinn's bump off (its kernel
/// keeps its pixels).
fn phong_same_either_way(test: &str, spheres: &[(Vec3, f32, u16)], quads: bool) {
    let scene = phong_scene(test, spheres, quads);
    for (texture, specular) in [(true, true), (false, false), (true, false), (false, true)] {
        let settings = Settings {
            texture,
            specular,
            bump: false,
            ..Settings::default()
        };
        let test = format!("{test}, texture {texture}, specular {specular}");
        same_frames(&test, &scene, quads, &view(quads, settings));
    }
}

#[test]
fn phong_pixels_of_a_dense_convex_sphere_are_drawn_the_same() {
    phong_same_either_way("phong-convex", &[(Vec3::ZERO, 0.0, 80)], false);
}

#[test]
fn phong_pixels_of_a_dented_sphere_are_drawn_the_same_behind_its_depth_buffer() {
    phong_same_either_way("phong-dented", &[(Vec3::ZERO, 0.08, 80)], false);
}

#[test]
fn phong_pixels_of_stacked_spheres_drawn_depth_first_are_drawn_the_same() {
    let stack: Vec<(Vec3, f32, u16)> = (0..5)
        .map(|k| (Vec3::new(0.02 * k as f32, 0.0, -0.1 * k as f32), 0.0, 80))
        .collect();
    phong_same_either_way("phong-stacked", &stack, false);
}

#[test]
fn a_near_quad_drawn_over_waiting_phong_pixels_keeps_its_colour() {
    phong_same_either_way("phong-quads", &[(Vec3::ZERO, 0.0, 80)], true);
}
