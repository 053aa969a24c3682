//! glTF 2.0 models (`--model file.gltf` or `file.glb`, docs/models.md).
//!
//! The JSON is parsed and validated by the `gltf` crate; relief reads the
//! bytes itself (`data`), so every length and offset the file claims is
//! checked, and the memory budget asked, before it is used. Then:
//! - the default scene (else the first) is walked from its root nodes, each
//!   node's matrix or TRS applied after its parent's; every triangle
//!   primitive of every mesh instance becomes one object, in world space,
//!   and the points and lines primitives the scene's strokes;
//! - the whole model is centred on its bounding box and scaled so its
//!   farthest point is `FIT_RADIUS` from the centre, as OBJ models are;
//! - each glTF material becomes one relief material (`material`), shared
//!   by the objects that use it.

mod data;
mod material;
mod sampling;
mod tangent;

use std::path::Path;
use std::sync::Arc;

use ::gltf::accessor::Accessor;
use ::gltf::mesh::Mode;
use glam::{Mat3, Mat4, Vec2, Vec3, Vec4};

use super::mesh::{Face, Mesh, Vertex};
use super::obj::{MODEL_BYTES_PER_TRIANGLE, ObjError, fit_of, fitted};
use super::strokes::{StrokeMode, StrokeVertex, Strokes};
use super::tangents::{accumulate, face_frame};
use super::{Material, Object, Scene};
use crate::sanitize::display_path;
use crate::texture::Texture;

use data::Problem;
use material::Materials;

/// Extensions a file may require that relief draws; any other required
/// one is refused.
const SUPPORTED_REQUIRED: &[&str] = &["KHR_materials_emissive_strength", "KHR_texture_transform"];

/// Deepest node hierarchy walked (a file with a cycle would never end).
const MAX_DEPTH: usize = 64;

/// Whether `path` names a glTF file (by its extension).
pub fn is_gltf(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("gltf") || e.eq_ignore_ascii_case("glb"))
}

/// One drawable part of a model: a primitive of a mesh instance.
pub struct Part {
    pub mesh: Mesh,
    pub material: Arc<Material>,
    /// Emission, occlusion, the sampler's filter (shared like the material).
    pub terms: Option<Arc<crate::scene::terms::MaterialTerms>>,
}

/// A loaded model: its parts in world space, fitted to the unit view.
pub struct Model {
    pub parts: Vec<Part>,
    /// Its points and lines primitives, fitted with the parts.
    pub strokes: Strokes,
}

impl Scene {
    /// A glTF model at the origin, turning, in the reference lighting and
    /// camera; each part with its own material. `texture` stays the
    /// scene's material (what the built-in models and `t` use).
    pub fn gltf(model: Model, texture: Arc<Texture>) -> Scene {
        let mut scene = Scene::model(Mesh::default(), texture);
        scene.objects.clear();
        for part in model.parts {
            scene.objects.push(Object {
                mesh: part.mesh,
                transform: Mat4::IDENTITY,
                rotates: true,
            });
            scene.object_materials.push(Some(part.material));
            scene.object_terms.push(part.terms);
        }
        scene.strokes = model.strokes;
        scene
    }
}

/// Loads a `.gltf` or `.glb` file. A problem is one line naming the file
/// and the place (a JSON path or a byte offset).
pub fn load(path: &Path) -> Result<Model, ObjError> {
    let name = display_path(path);
    let fail = |reason: Problem| ObjError::Parse {
        name: name.clone(),
        reason,
    };
    let (bytes, _held) = data::read_file(path, &format!("model {name}")).map_err(&fail)?;
    let dir = path.parent().unwrap_or(Path::new("."));
    crate::contain::contain(|| load_bytes(&name, &bytes, dir))
        .unwrap_or_else(|cause| Err(format!("the reader failed on it ({cause})")))
        .map_err(fail)
}

/// Loads a model from the file's bytes; `dir` holds its external files.
pub fn load_bytes(name: &str, bytes: &[u8], dir: &Path) -> Result<Model, Problem> {
    let container = data::container(bytes)?;
    let parsed = ::gltf::Gltf::from_slice_without_validation(container.json).map_err(json_error)?;
    for ext in parsed.document.extensions_required() {
        if !SUPPORTED_REQUIRED.contains(&ext) {
            return Err(format!(
                "extensionsRequired: '{}' is not supported",
                crate::sanitize::clean(ext)
            ));
        }
    }
    let document = ::gltf::Document::from_json(parsed.document.into_json()).map_err(json_error)?;
    let mut buffers = Vec::new();
    let mut held = Vec::new();
    for b in document.buffers() {
        let what = format!("model {name}, buffers[{}]", b.index());
        let (bytes, h) = data::buffer(b.source(), b.length(), container.bin, dir, &what)
            .map_err(|p| format!("buffers[{}]: {p}", b.index()))?;
        buffers.push(bytes);
        held.extend(h);
    }
    let instances = instances(&document)?;
    // The budget for what is built, before building it.
    let mut triangles = 0u64;
    for (mesh, _) in &instances {
        for prim in mesh.primitives() {
            let corners = prim
                .indices()
                .or_else(|| prim.get(&::gltf::Semantic::Positions))
                .map_or(0, |a| a.count() as u64);
            triangles += corners;
        }
    }
    let need = triangles.saturating_mul(MODEL_BYTES_PER_TRIANGLE);
    held.push(crate::budget::reserve(&format!("model {name}"), need).map_err(|e| e.to_string())?);

    let mut materials = Materials::new(name, &document, &buffers, dir);
    let mut prims = Vec::new();
    for (mesh, world) in &instances {
        for prim in mesh.primitives() {
            let place = format!("meshes[{}].primitives[{}]", mesh.index(), prim.index());
            prims.push(read_primitive(&prim, *world, &buffers, &place)?);
        }
    }
    if prims
        .iter()
        .all(|p| p.tris.is_empty() && p.strokes.is_none())
    {
        return Err("it has no triangles, lines or points to draw".into());
    }
    fit(&mut prims)?;
    let mut parts = Vec::with_capacity(prims.len());
    let mut strokes = Strokes::default();
    for prim in prims {
        if let Some(s) = &prim.strokes {
            let colors = prim.colors.as_deref();
            let vertices: Vec<StrokeVertex> = prim
                .positions
                .iter()
                .enumerate()
                .map(|(i, &position)| StrokeVertex {
                    position,
                    color: (colors.map_or(Vec3::ONE, |c| c[i]) * s.factor)
                        .clamp(Vec3::ZERO, Vec3::ONE),
                })
                .collect();
            strokes.add(&vertices, &s.corners, s.mode);
            continue;
        }
        let look = materials.get(prim.material)?;
        let mesh = build_mesh(prim, &look);
        if !mesh.triangles.is_empty() {
            parts.push(Part {
                mesh,
                material: look.material.clone(),
                terms: look.terms.clone(),
            });
        }
    }
    if parts.is_empty() && strokes.is_empty() {
        return Err("it has no triangle with an area".into());
    }
    Ok(Model { parts, strokes })
}

/// The parser's complaint, without its internals: the JSON line and
/// column, or the JSON path of the first invalid value.
fn json_error(e: ::gltf::Error) -> Problem {
    match e {
        ::gltf::Error::Deserialize(e) => format!(
            "the JSON is not glTF 2.0 (line {}, column {})",
            e.line(),
            e.column()
        ),
        ::gltf::Error::Validation(list) => match list.first() {
            Some((path, kind)) => {
                let what = match kind {
                    ::gltf::json::validation::Error::IndexOutOfBounds => "an index out of range",
                    ::gltf::json::validation::Error::Invalid => "an invalid value",
                    ::gltf::json::validation::Error::Missing => "a required value is missing",
                    ::gltf::json::validation::Error::Oversize => "a size past the limits",
                    ::gltf::json::validation::Error::Unsupported => "not supported",
                };
                format!("{}: {what}", crate::sanitize::clean(&path.to_string()))
            }
            None => "the JSON is not valid glTF 2.0".into(),
        },
        ::gltf::Error::Binary(_) => "the GLB container is not valid".into(),
        _ => "the file is not valid glTF 2.0".into(),
    }
}

/// Every mesh instance of the scene drawn, with its world matrix.
fn instances(document: &::gltf::Document) -> Result<Vec<(::gltf::Mesh<'_>, Mat4)>, Problem> {
    let mut out = Vec::new();
    let roots: Vec<::gltf::Node> = match document
        .default_scene()
        .or_else(|| document.scenes().next())
    {
        Some(scene) => scene.nodes().collect(),
        None => {
            // No scene: every mesh once, where it is.
            return Ok(document.meshes().map(|m| (m, Mat4::IDENTITY)).collect());
        }
    };
    let mut stack: Vec<(::gltf::Node, Mat4, usize)> =
        roots.into_iter().map(|n| (n, Mat4::IDENTITY, 0)).collect();
    while let Some((node, parent, depth)) = stack.pop() {
        if depth > MAX_DEPTH {
            return Err(format!(
                "nodes[{}]: the node hierarchy is deeper than {MAX_DEPTH} (a cycle?)",
                node.index()
            ));
        }
        let local = Mat4::from_cols_array_2d(&node.transform().matrix());
        let world = parent * local;
        if !world.is_finite() {
            return Err(format!(
                "nodes[{}]: its transform is not finite",
                node.index()
            ));
        }
        if let Some(mesh) = node.mesh() {
            out.push((mesh, world));
        }
        for child in node.children() {
            stack.push((child, world, depth + 1));
        }
    }
    // Depth-first from the end: back to the file's order.
    out.reverse();
    Ok(out)
}

/// One primitive in world space, as triangles.
struct Prim {
    positions: Vec<Vec3>,
    normals: Option<Vec<Vec3>>,
    /// ∂P/∂u and ∂P/∂v directions from the file's TANGENT.
    axes: Option<Vec<(Vec3, Vec3)>>,
    uvs: Option<Vec<Vec2>>,
    colors: Option<Vec<Vec3>>,
    tris: Vec<[u32; 3]>,
    material: Option<usize>,
    /// A points or lines primitive (no triangles).
    strokes: Option<PrimStrokes>,
}

/// What a points or lines primitive draws.
struct PrimStrokes {
    mode: StrokeMode,
    corners: Vec<u32>,
    /// The material's base colour factor (RGB), times the vertex colours.
    factor: Vec3,
}

/// Checks that an accessor's elements lie inside its view and the view
/// inside its buffer.
fn check_accessor(acc: &Accessor, buffers: &[Vec<u8>], role: &str) -> Result<(), Problem> {
    let path = format!("accessors[{}] ({role})", acc.index());
    if acc.sparse().is_some() {
        return Err(format!("{path}: sparse accessors are not read"));
    }
    let Some(view) = acc.view() else {
        return Err(format!("{path}: it has no bufferView"));
    };
    let have = buffers.get(view.buffer().index()).map_or(0, |b| b.len()) as u64;
    let (start, length) = (view.offset() as u64, view.length() as u64);
    if start.saturating_add(length) > have {
        return Err(format!(
            "bufferViews[{}]: bytes {start}..{} are past the end of buffers[{}] ({have} bytes)",
            view.index(),
            start.saturating_add(length),
            view.buffer().index()
        ));
    }
    let size = acc.size() as u64;
    let stride = view.stride().map_or(size, |s| s as u64);
    let count = acc.count() as u64;
    if count == 0 {
        return Ok(());
    }
    let end = (count - 1)
        .saturating_mul(stride)
        .saturating_add(acc.offset() as u64)
        .saturating_add(size);
    if end > length {
        return Err(format!(
            "{path}: {count} elements reach byte {end} of bufferViews[{}], which has {length}",
            view.index()
        ));
    }
    Ok(())
}

fn read_primitive(
    prim: &::gltf::Primitive,
    world: Mat4,
    buffers: &[Vec<u8>],
    place: &str,
) -> Result<Prim, Problem> {
    let mode = prim.mode();
    let stroke = match mode {
        Mode::Points => Some(StrokeMode::Points),
        Mode::Lines => Some(StrokeMode::Lines),
        Mode::LineLoop => Some(StrokeMode::LineLoop),
        Mode::LineStrip => Some(StrokeMode::LineStrip),
        _ => None,
    };
    for (semantic, acc) in prim.attributes() {
        check_accessor(&acc, buffers, &format!("{semantic:?} of {place}"))?;
    }
    if let Some(acc) = prim.indices() {
        check_accessor(&acc, buffers, &format!("indices of {place}"))?;
    }
    let reader = prim.reader(|b| buffers.get(b.index()).map(Vec::as_slice));
    let unreadable = |what: &str| format!("{place}: its {what} cannot be read");
    let positions: Vec<Vec3> = reader
        .read_positions()
        .ok_or_else(|| unreadable("POSITION"))?
        .map(Vec3::from)
        .collect();
    if let Some(k) = positions.iter().position(|p| !p.is_finite()) {
        return Err(format!("{place}: POSITION {k} is not a finite number"));
    }
    let n = positions.len();
    let same_count = |what: &str, len: usize| {
        if len == n {
            Ok(())
        } else {
            Err(format!("{place}: {len} {what} for {n} positions"))
        }
    };
    let normals: Option<Vec<Vec3>> = reader.read_normals().map(|r| r.map(Vec3::from).collect());
    if let Some(v) = &normals {
        same_count("NORMAL", v.len())?;
    }
    let material = prim.material();
    let reading = sampling::Reading::of(&material);
    let uvs: Option<Vec<Vec2>> = reader
        .read_tex_coords(reading.set)
        .map(|r| r.into_f32().map(|uv| reading.uv(Vec2::from(uv))).collect());
    if let Some(v) = &uvs {
        same_count("TEXCOORD", v.len())?;
    }
    let colors: Option<Vec<Vec3>> = reader
        .read_colors(0)
        .map(|r| r.into_rgb_f32().map(Vec3::from).collect());
    if let Some(v) = &colors {
        same_count("COLOR_0", v.len())?;
    }
    let tangents: Option<Vec<Vec4>> = reader.read_tangents().map(|r| r.map(Vec4::from).collect());
    if let Some(v) = &tangents {
        same_count("TANGENT", v.len())?;
    }
    let corners: Vec<u32> = match reader.read_indices() {
        Some(r) => r.into_u32().collect(),
        None => (0..n as u32).collect(),
    };
    if let Some((k, i)) = corners.iter().enumerate().find(|(_, i)| **i as usize >= n) {
        return Err(format!("{place}: index {k} is {i}, past the {n} vertices"));
    }
    if let Some(mode) = stroke {
        let [r, g, b, _] = material.pbr_metallic_roughness().base_color_factor();
        return Ok(Prim {
            positions: positions
                .iter()
                .map(|p| world.transform_point3(*p))
                .collect(),
            normals: None,
            axes: None,
            uvs: None,
            colors,
            tris: Vec::new(),
            material: material.index(),
            strokes: Some(PrimStrokes {
                mode,
                corners,
                factor: Vec3::new(r, g, b),
            }),
        });
    }
    let mut tris = triangles(mode, &corners);
    // A mirroring transform turns counter-clockwise faces clockwise.
    let linear = Mat3::from_mat4(world);
    if linear.determinant() < 0.0 {
        for t in &mut tris {
            t.swap(1, 2);
        }
    }
    let normal_matrix = super::normal_matrix(world);
    let axes = match (&tangents, &normals) {
        (Some(t), Some(nrm)) => Some(
            t.iter()
                .zip(nrm)
                .map(|(t, n)| {
                    let (tu, tv) = tangent::axes(t.truncate(), t.w, *n);
                    (linear * tu, linear * tv)
                })
                .collect(),
        ),
        _ => None,
    };
    Ok(Prim {
        positions: positions
            .iter()
            .map(|p| world.transform_point3(*p))
            .collect(),
        normals: normals.map(|v| {
            v.iter()
                .map(|n| (normal_matrix * *n).normalize_or_zero())
                .collect()
        }),
        axes,
        uvs,
        colors,
        tris,
        material: material.index(),
        strokes: None,
    })
}

/// The triangles of a list, strip or fan of corner indices.
fn triangles(mode: Mode, c: &[u32]) -> Vec<[u32; 3]> {
    match mode {
        Mode::TriangleStrip => (0..c.len().saturating_sub(2))
            .map(|i| {
                if i % 2 == 0 {
                    [c[i], c[i + 1], c[i + 2]]
                } else {
                    [c[i + 1], c[i], c[i + 2]]
                }
            })
            .collect(),
        Mode::TriangleFan => (1..c.len().saturating_sub(1))
            .map(|i| [c[0], c[i], c[i + 1]])
            .collect(),
        _ => c.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect(),
    }
}

/// Centres the model and scales it so its farthest point is `FIT_RADIUS`
/// away (in f64, as OBJ models are fitted).
fn fit(prims: &mut [Prim]) -> Result<(), Problem> {
    // Only the points the triangles and strokes use count.
    let fit = fit_of(|| {
        prims.iter().flat_map(|p| {
            let strokes = p.strokes.iter().flat_map(|s| &s.corners);
            p.tris
                .iter()
                .flatten()
                .chain(strokes)
                .map(move |&i| p.positions[i as usize])
        })
    })
    .ok_or("all its points coincide")?;
    for p in prims.iter_mut() {
        for q in &mut p.positions {
            *q = fitted(*q, fit);
        }
    }
    Ok(())
}

/// A primitive as a relief mesh: vertices as the file has them (split per
/// corner where normals or tangents must be made per face), triangles with
/// an area, tangent frames from the file, MikkTSpace or relief's own.
fn build_mesh(mut prim: Prim, look: &material::Look) -> Mesh {
    // No normals: flat ones, so each corner is its own vertex (glTF 2.0 §3.7.2.1).
    let flat = prim.normals.is_none();
    let mikk = look.normal_mapped && prim.axes.is_none() && prim.uvs.is_some();
    if flat || mikk {
        prim = split_corners(prim);
    }
    if flat {
        let mut normals = vec![Vec3::Z; prim.positions.len()];
        for t in &prim.tris {
            let p = t.map(|i| prim.positions[i as usize]);
            let n = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
            for &i in t {
                normals[i as usize] = n;
            }
        }
        prim.normals = Some(normals);
    }
    let normals = prim.normals.take().unwrap_or_default();
    if mikk && let Some(uvs) = &prim.uvs {
        prim.axes = tangent::mikktspace(&prim.positions, &normals, uvs);
    }
    let factor = look.base_color;
    let vertices: Vec<Vertex> = (0..prim.positions.len())
        .map(|i| {
            let color = prim.colors.as_ref().map_or(Vec3::ONE, |c| c[i]);
            Vertex {
                position: prim.positions[i],
                normal: normals[i].try_normalize().unwrap_or(Vec3::Z),
                uv: prim.uvs.as_ref().map_or(Vec2::ZERO, |u| u[i]),
                color: (color * factor).clamp(Vec3::ZERO, Vec3::ONE),
                tangent_u: Vec3::ZERO,
                tangent_v: Vec3::ZERO,
            }
        })
        .collect();
    let textured = prim.uvs.is_some();
    let faces: Vec<Face> = prim
        .tris
        .iter()
        .filter_map(|&indices| {
            let v = indices.map(|i| vertices[i as usize]);
            let p = v.map(|v| v.position);
            let face_normal = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
            if face_normal == Vec3::ZERO {
                return None;
            }
            let frame = face_frame(p, v.map(|v| v.uv), face_normal);
            Some(Face {
                indices,
                face_normal,
                face_tangent_u: frame.tangent_u,
                face_tangent_v: frame.tangent_v,
                facet_center: p.iter().sum::<Vec3>() / 3.0,
                facet_color: v.iter().map(|v| v.color).sum::<Vec3>() / 3.0,
                textured,
            })
        })
        .collect();
    let mut mesh = Mesh::new(vertices, &faces, false, !look.double_sided);
    drop(faces);
    accumulate(&mut mesh);
    if let Some(axes) = &prim.axes {
        // The file's (or MikkTSpace's) directions, relief's lengths.
        for (v, (pu, pv)) in mesh.vertices.iter_mut().zip(axes) {
            let (lu, lv) = (v.tangent_u.length(), v.tangent_v.length());
            if let (Some(u), Some(w)) = (pu.try_normalize(), pv.try_normalize()) {
                v.tangent_u = u * lu;
                v.tangent_v = w * lv;
            }
        }
    }
    mesh
}

/// The primitive with one vertex per triangle corner.
fn split_corners(prim: Prim) -> Prim {
    let order: Vec<usize> = prim.tris.iter().flatten().map(|&i| i as usize).collect();
    fn pick<T: Copy>(v: &Option<Vec<T>>, order: &[usize]) -> Option<Vec<T>> {
        v.as_ref().map(|v| order.iter().map(|&i| v[i]).collect())
    }
    Prim {
        positions: order.iter().map(|&i| prim.positions[i]).collect(),
        normals: pick(&prim.normals, &order),
        axes: pick(&prim.axes, &order),
        uvs: pick(&prim.uvs, &order),
        colors: pick(&prim.colors, &order),
        tris: (0..prim.tris.len() as u32)
            .map(|t| [3 * t, 3 * t + 1, 3 * t + 2])
            .collect(),
        material: prim.material,
        strokes: None,
    }
}
