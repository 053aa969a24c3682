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

mod accessor;
mod cameras;
mod convexity;
mod data;
mod draco;
mod fitted_nodes;
mod lights;
mod material;
pub mod meshopt;
mod opacity;
mod reading;
mod rig;
mod sampling;
mod skipped;
mod tangent;
mod validate;

use std::path::Path;
use std::sync::Arc;

use ::gltf::mesh::Mode;
use glam::{DVec3, Mat3, Mat4, Vec2, Vec3, Vec4};

use super::anim::{Influences, MorphTarget, Motion, PartRig, Rig};
use super::corners::{fit_of, fitted};
use super::face_frame::face_frame;
use super::mesh::{Face, Facet, Mesh, Triangle, Vertex, triangle_normal};
use super::model_error::ObjError;
use super::strokes::{StrokeMode, StrokeVertex, Strokes};
use super::tangents::{accumulate_keeping_directions, sum_bytes};
use super::{Material, Object, Scene};
use relief_core::budget::Reservation;
use relief_core::sanitize::display_path;
use relief_texture::Texture;

use data::Problem;
use material::Materials;
use reading::{MAX_DEPTH, bytes_of, check_accessor, hold};
use validate::Role;

/// Extensions a file may require that relief draws; any other required
/// one is refused.
const SUPPORTED_REQUIRED: &[&str] = skipped::READ;

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
    pub terms: Option<Arc<crate::terms::MaterialTerms>>,
}

/// A loaded model: its parts in world space, fitted to the unit view.
pub struct Model {
    pub parts: Vec<Part>,
    /// Its points and lines primitives, fitted with the parts.
    pub strokes: Strokes,
    /// What the file has that is not drawn (one line each, safe to print).
    pub warnings: Vec<String>,
    /// Its animation, when it has one (or skins, or morph weights set):
    /// the parts are posed at the start of its first clip.
    pub motion: Option<Motion>,
    /// Its cameras, perspective and orthographic, placed in the fitted
    /// model's space.
    pub cameras: Vec<crate::Camera>,
    /// Its own lights (KHR_lights_punctual), placed likewise.
    pub lights: Vec<crate::Light>,
}

impl Model {
    /// Its clips: each one's name and length in seconds.
    pub fn clips(&self) -> Vec<(String, f32)> {
        let clips = self.motion.iter().flat_map(|m| m.clips());
        clips.map(|c| (c.name.clone(), c.duration)).collect()
    }
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
        scene.motion = model.motion;
        scene.cameras = model.cameras;
        scene.file_lights = model.lights;
        scene
    }
}

/// Loads a `.gltf` or `.glb` file. A problem is one line naming the file
/// and the place (a JSON path or a byte offset).
pub fn load(path: &Path) -> Result<Model, ObjError> {
    let _keep = crate::load_memory::KeepFreed::new();
    let name = display_path(path);
    let fail = |reason: Problem| ObjError::Parse {
        name: name.clone(),
        reason,
    };
    let (bytes, _held) = data::read_file(path, &format!("model {name}")).map_err(&fail)?;
    let dir = path.parent().unwrap_or(Path::new("."));
    relief_core::contain::contain(|| load_bytes(&name, &bytes, dir))
        .unwrap_or_else(|cause| Err(format!("the reader failed on it ({cause})")))
        .map_err(fail)
}

/// Loads a model from the file's bytes; `dir` holds its external files.
pub fn load_bytes(name: &str, bytes: &[u8], dir: &Path) -> Result<Model, Problem> {
    let container = data::container(bytes)?;
    let parsed = ::gltf::Gltf::from_slice_without_validation(container.json).map_err(json_error)?;
    let mut root = parsed.document.into_json();
    validate::before_parse(&mut root, SUPPORTED_REQUIRED)?;
    let (mut buffers, mut held) = read_buffers(&root, container.bin, dir, name)?;
    if root.extensions_used.iter().any(|e| is_compression(e)) {
        held.push(decompress(&mut root, &mut buffers, name)?);
    }
    let document = ::gltf::Document::from_json(root).map_err(json_error)?;
    let instances = instances(&document)?;
    let quantized = document
        .extensions_used()
        .any(|e| e == "KHR_mesh_quantization");
    // An animated model's parts are read in their own space, posed later.
    let rigged = rig::wanted(&document);
    // What is built is reserved step by step, before it is allocated.
    let mut model =
        relief_core::budget::reserve(&format!("model {name}"), 0).map_err(|e| e.to_string())?;
    let mut materials = Materials::new(name, &document, &buffers, dir);
    let mut prims = read_primitives(
        &document,
        &instances,
        &buffers,
        (rigged, quantized),
        (name, &mut model),
    )?;
    if prims
        .iter()
        .all(|p| p.tris.is_empty() && p.strokes.is_none())
    {
        return Err("it has no triangles, lines or points to draw".into());
    }
    let mut fitted_by = None;
    if !rigged {
        fitted_by = Some(fit(&mut prims)?);
    }
    let (mut parts, mut strokes, posings) = build_parts(prims, &mut materials, (name, &mut model))?;
    if parts.is_empty() && strokes.is_empty() {
        return Err("it has no triangle with an area".into());
    }
    let mut motion = None;
    if rigged {
        let posed = (&mut parts[..], &mut strokes);
        let (m, f) = pose_rig(&document, &buffers, posings, posed, (name, &mut model))?;
        (motion, fitted_by) = (Some(m), Some(f));
    }
    let cameras = fitted_by.map_or_else(Vec::new, |f| cameras::cameras(&document, f));
    let lights = fitted_by.map_or_else(Vec::new, |f| lights::lights(&document, f));
    let warnings = skipped::note(name, &document).into_iter().collect();
    Ok(Model {
        parts,
        strokes,
        warnings,
        motion,
        cameras,
        lights,
    })
}

/// Every primitive of every instance, in order; a posed one with its morph
/// targets and joint influences.
fn read_primitives(
    document: &::gltf::Document,
    instances: &[Instance],
    buffers: &[Vec<u8>],
    (rigged, quantized): (bool, bool),
    (name, model): (&str, &mut Reservation),
) -> Result<Vec<Prim>, Problem> {
    let mut prims = Vec::new();
    for inst in instances {
        for prim in inst.mesh.primitives() {
            let place = format!("meshes[{}].primitives[{}]", inst.mesh.index(), prim.index());
            let placing = Placing::of(
                inst,
                rigged && stroke_mode(prim.mode()).is_none(),
                quantized,
            );
            let mut read = read_primitive(
                (document, &prim),
                placing,
                buffers,
                &place,
                (name, &mut *model),
            )?;
            if placing.posed {
                let joints = inst
                    .skin
                    .and_then(|s| document.skins().nth(s))
                    .map(|s| s.joints().count());
                let n = read.vertices.len();
                let (targets, influences) = rig::part_data(
                    &prim,
                    (n, joints, quantized),
                    buffers,
                    &place,
                    (name, &mut *model),
                )?;
                read.posing = Some(Posing {
                    node: inst.node,
                    skin: inst.skin,
                    targets,
                    influences,
                });
            }
            prims.push(read);
        }
    }
    Ok(prims)
}

/// Whether extension `e` compresses a file's data.
fn is_compression(e: &str) -> bool {
    e == draco::NAME || meshopt::NAMES.contains(&e)
}

/// Every buffer's bytes (a meshopt fallback buffer's none) and what they
/// hold of the memory budget.
fn read_buffers(
    root: &::gltf::json::Root,
    bin: Option<&[u8]>,
    dir: &Path,
    name: &str,
) -> Result<(Vec<Vec<u8>>, Vec<Reservation>), Problem> {
    let (mut buffers, mut held) = (Vec::new(), Vec::new());
    for (k, b) in root.buffers.iter().enumerate() {
        if meshopt::is_fallback(b) {
            buffers.push(Vec::new());
            continue;
        }
        let what = format!("model {name}, buffers[{k}]");
        let source = match &b.uri {
            Some(uri) => ::gltf::buffer::Source::Uri(uri),
            None => ::gltf::buffer::Source::Bin,
        };
        let (bytes, h) = data::buffer(source, b.byte_length.0 as usize, bin, dir, &what)
            .map_err(|p| format!("buffers[{k}]: {p}"))?;
        buffers.push(bytes);
        held.extend(h);
    }
    Ok((buffers, held))
}

/// Decodes `root`'s compressed bufferViews (meshopt) and primitives
/// (Draco) into new buffers appended to `buffers`; what the decoded bytes
/// hold of the memory budget.
fn decompress(
    root: &mut ::gltf::json::Root,
    buffers: &mut Vec<Vec<u8>>,
    name: &str,
) -> Result<Reservation, Problem> {
    let mut held =
        relief_core::budget::reserve(&format!("model {name}"), 0).map_err(|e| e.to_string())?;
    meshopt::unpack(root, buffers, (name, &mut held))?;
    draco::unpack(root, buffers, (name, &mut held))?;
    Ok(held)
}

/// The parts (triangles, with their materials) and strokes of `prims`,
/// and how each part is posed when the model is animated.
fn build_parts(
    prims: Vec<Prim>,
    materials: &mut Materials,
    (name, held): (&str, &mut Reservation),
) -> Result<(Vec<Part>, Strokes, Vec<PartRig>), Problem> {
    let mut parts = Vec::with_capacity(prims.len());
    let mut strokes = Strokes::default();
    let mut posings = Vec::new();
    for mut prim in prims {
        if let Some(s) = &prim.strokes {
            let vertices: Vec<StrokeVertex> = prim
                .vertices
                .iter()
                .map(|v| StrokeVertex {
                    position: v.position,
                    color: (v.color * s.factor).clamp(Vec3::ZERO, Vec3::ONE),
                })
                .collect();
            strokes.add(&vertices, &s.corners, s.mode);
            continue;
        }
        let look = materials.get(prim.material)?;
        let posing = prim.posing.take();
        let deforms = posing
            .as_ref()
            .is_some_and(|p| p.skin.is_some() || !p.targets.is_empty());
        let flat = !prim.has_normals;
        let (mesh, source) = build_mesh(prim, &look, deforms, (name, &mut *held))?;
        if mesh.triangles.is_empty() {
            continue;
        }
        if let Some(p) = posing {
            hold(
                held,
                name,
                "the rest pose",
                bytes_of::<Vertex>(mesh.vertices.len() as u64),
            )?;
            posings.push(PartRig {
                node: p.node,
                skin: p.skin,
                rest: mesh.vertices.clone(),
                source,
                targets: p.targets,
                influences: p.influences,
                flat,
            });
        }
        parts.push(Part {
            mesh,
            material: look.material.clone(),
            terms: look.terms.clone(),
        });
    }
    Ok((parts, strokes, posings))
}

/// The animated model's rig, its parts posed at the start of its first
/// clip and fitted, with its strokes, to the unit view there.
fn pose_rig(
    document: &::gltf::Document,
    buffers: &[Vec<u8>],
    parts_rigs: Vec<PartRig>,
    (parts, strokes): (&mut [Part], &mut Strokes),
    (name, held): (&str, &mut Reservation),
) -> Result<(Motion, (DVec3, f64)), Problem> {
    let (nodes, order) = rig::nodes(document);
    let skins = rig::skins(document, buffers, (name, &mut *held))?;
    let clips = rig::clips(document, buffers, (name, held))?;
    let mut motion = Motion::new(Rig {
        nodes,
        order,
        clips,
        skins,
        parts: parts_rigs,
        fit: Mat4::IDENTITY,
    });
    let first = (!motion.clips().is_empty()).then_some(0);
    let mut objects: Vec<Object> = parts
        .iter_mut()
        .map(|p| Object {
            mesh: std::mem::take(&mut p.mesh),
            transform: Mat4::IDENTITY,
            rotates: true,
        })
        .collect();
    motion.show(&mut objects, first, 0.0);
    let points = || {
        let meshes = objects
            .iter()
            .flat_map(|o| o.mesh.vertices.iter().map(|v| v.position));
        meshes.chain(strokes.vertices.iter().map(|v| v.position))
    };
    let (centre, scale) = fit_of(points).ok_or("all its points coincide")?;
    let fit =
        Mat4::from_scale(Vec3::splat(scale as f32)) * Mat4::from_translation(-centre.as_vec3());
    for v in &mut strokes.vertices {
        v.position = fitted(v.position, (centre, scale));
    }
    motion = Motion::new(Rig {
        fit,
        ..Arc::unwrap_or_clone(motion.rig)
    });
    motion.show(&mut objects, first, 0.0);
    for (part, object) in parts.iter_mut().zip(objects) {
        part.mesh = object.mesh;
    }
    Ok((motion, (centre, scale)))
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
                format!(
                    "{}: {what}",
                    relief_core::sanitize::clean(&path.to_string())
                )
            }
            None => "the JSON is not valid glTF 2.0".into(),
        },
        ::gltf::Error::Binary(_) => "the GLB container is not valid".into(),
        _ => "the file is not valid glTF 2.0".into(),
    }
}

/// One mesh placed in the scene drawn.
struct Instance<'a> {
    mesh: ::gltf::Mesh<'a>,
    world: Mat4,
    /// Its node (none when the file has no scene: every mesh once).
    node: Option<usize>,
    skin: Option<usize>,
}

/// Every mesh instance of the scene drawn, with its world matrix.
fn instances(document: &::gltf::Document) -> Result<Vec<Instance<'_>>, Problem> {
    let mut out = Vec::new();
    let roots: Vec<::gltf::Node> = match document
        .default_scene()
        .or_else(|| document.scenes().next())
    {
        Some(scene) => scene.nodes().collect(),
        None => {
            // No scene: every mesh once, where it is.
            let once = |mesh| Instance {
                mesh,
                world: Mat4::IDENTITY,
                node: None,
                skin: None,
            };
            return Ok(document.meshes().map(once).collect());
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
            out.push(Instance {
                mesh,
                world,
                node: Some(node.index()),
                skin: node.skin().map(|s| s.index()),
            });
        }
        for child in node.children() {
            stack.push((child, world, depth + 1));
        }
    }
    // Depth-first from the end: back to the file's order.
    out.reverse();
    Ok(out)
}

/// One primitive in world space, read straight into its mesh's arrays.
struct Prim {
    /// Until the mesh is built: the file's colour (white without one), its
    /// normal in world space as read (zero without one), and in the tangent
    /// fields the file's ∂P/∂u and ∂P/∂v directions (zero without them).
    vertices: Vec<Vertex>,
    has_normals: bool,
    has_uvs: bool,
    /// The second texture coordinate set (`Mesh::uv2`), one per vertex,
    /// when a map of the material reads one; empty otherwise.
    uv2: Vec<Vec2>,
    /// The file's TANGENT is in the vertices' tangent fields.
    has_axes: bool,
    /// Triangles with their indices only (the facet data comes with the mesh).
    tris: Vec<Triangle>,
    material: Option<usize>,
    /// A points or lines primitive (no triangles).
    strokes: Option<PrimStrokes>,
    /// Keep `source` as vertices are split (the model is animated).
    track: bool,
    /// The file's vertex each vertex comes from, when `track` and they
    /// were split (empty: the same index).
    source: Vec<u32>,
    /// How it moves, when the model is animated.
    posing: Option<Posing>,
}

/// How an animated model's primitive moves: its node, skin, morph
/// targets and joint weights.
struct Posing {
    node: Option<usize>,
    skin: Option<usize>,
    targets: Vec<MorphTarget>,
    influences: Influences,
}

/// Where a primitive is read to: into `world`, its triangles turned as a
/// `mirrored` placement needs; `posed`: in its own space, to be posed
/// frame by frame.
#[derive(Clone, Copy)]
struct Placing {
    world: Mat4,
    mirrored: bool,
    quantized: bool,
    posed: bool,
}

impl Placing {
    fn of(inst: &Instance, posed: bool, quantized: bool) -> Placing {
        // A skinned mesh's node does not place it (glTF 2.0 §3.7.3.3).
        let mirrored = inst.skin.is_none() && Mat3::from_mat4(inst.world).determinant() < 0.0;
        Placing {
            world: if posed { Mat4::IDENTITY } else { inst.world },
            mirrored,
            quantized,
            posed,
        }
    }
}

/// What a points or lines primitive draws (none: triangles).
fn stroke_mode(mode: Mode) -> Option<StrokeMode> {
    match mode {
        Mode::Points => Some(StrokeMode::Points),
        Mode::Lines => Some(StrokeMode::Lines),
        Mode::LineLoop => Some(StrokeMode::LineLoop),
        Mode::LineStrip => Some(StrokeMode::LineStrip),
        _ => None,
    }
}

/// A vertex before anything is read into it.
const BLANK: Vertex = Vertex {
    position: Vec3::ZERO,
    normal: Vec3::ZERO,
    uv: Vec2::ZERO,
    color: Vec3::ONE,
    tangent_u: Vec3::ZERO,
    tangent_v: Vec3::ZERO,
};

/// A triangle with its corners only.
fn corners_only(indices: [u32; 3]) -> Triangle {
    Triangle::new(indices, false)
}

/// What a points or lines primitive draws.
struct PrimStrokes {
    mode: StrokeMode,
    corners: Vec<u32>,
    /// The material's base colour factor (RGB), times the vertex colours.
    factor: Vec3,
}

/// Reads one primitive into its place (`placing`): every accessor checked
/// and every array reserved before it is read.
fn read_primitive(
    (document, prim): (&::gltf::Document, &::gltf::Primitive),
    placing: Placing,
    buffers: &[Vec<u8>],
    place: &str,
    (name, held): (&str, &mut Reservation),
) -> Result<Prim, Problem> {
    check_accessors(prim, buffers, placing.quantized, place)?;
    let stroke = stroke_mode(prim.mode());
    let material = prim.material();
    let sets = sampling::Sets::of(document, &material);
    let mut vertices = read_positions(prim, buffers, placing.world, place, (name, held))?;
    let n = vertices.len();
    check_counts(prim, &sets, n, place)?;
    let given = read_attributes(
        prim,
        buffers,
        (&sets.first, stroke),
        placing.world,
        &mut vertices,
    );
    let uv2 = read_second_set(prim, buffers, (&sets, stroke), n, (name, held))?;
    let index_count = prim.indices().map_or(n, |a| a.count());
    let corners: Box<dyn Iterator<Item = (usize, u32)>> = match prim.indices() {
        Some(a) => Box::new(accessor::indices(&a, buffers).enumerate()),
        None => Box::new((0..n as u32).enumerate()),
    };
    if let Some(mode) = stroke {
        hold(
            held,
            name,
            "the strokes",
            bytes_of::<u32>(index_count as u64),
        )?;
        let corners = corners
            .map(|(k, i)| checked_index(k, i, n, place))
            .collect::<Result<Vec<u32>, _>>()?;
        return Ok(stroke_prim(vertices, &material, mode, corners));
    }
    let tris = read_triangles(
        corners,
        (prim.mode(), placing.mirrored),
        (index_count, n, place),
        (name, held),
    )?;
    Ok(Prim {
        vertices,
        has_normals: given.normals,
        has_uvs: given.uvs,
        uv2,
        has_axes: given.axes,
        tris,
        material: material.index(),
        strokes: None,
        track: placing.posed,
        source: Vec::new(),
        posing: None,
    })
}

/// Checks every attribute's and the indices' accessor against the
/// buffers, before anything is read through them.
fn check_accessors(
    prim: &::gltf::Primitive,
    buffers: &[Vec<u8>],
    quantized: bool,
    place: &str,
) -> Result<(), Problem> {
    for (semantic, acc) in prim.attributes() {
        check_accessor(
            &acc,
            buffers,
            (Role::Attribute(&semantic), quantized),
            place,
        )?;
    }
    if let Some(acc) = prim.indices() {
        check_accessor(&acc, buffers, (Role::Indices, quantized), place)?;
    }
    Ok(())
}

/// One attribute's elements as floats: positions, normals, tangents and
/// texture coordinates of any component type (KHR_mesh_quantization),
/// sparse or not.
fn floats<'a>(
    prim: &::gltf::Primitive<'a>,
    buffers: &'a [Vec<u8>],
    semantic: ::gltf::Semantic,
) -> Option<impl Iterator<Item = [f32; 4]> + use<'a>> {
    prim.get(&semantic).map(|a| accessor::floats(&a, buffers))
}

/// The primitive's vertices with their positions placed by `world` (the
/// rest blank), refused when a position is not a finite number.
fn read_positions(
    prim: &::gltf::Primitive,
    buffers: &[Vec<u8>],
    world: Mat4,
    place: &str,
    (name, held): (&str, &mut Reservation),
) -> Result<Vec<Vertex>, Problem> {
    use ::gltf::Semantic;
    let positions = floats(prim, buffers, Semantic::Positions)
        .ok_or_else(|| format!("{place}: its POSITION cannot be read"))?;
    let n = prim.get(&Semantic::Positions).map_or(0, |a| a.count());
    hold(held, name, "the vertices", bytes_of::<Vertex>(n as u64))?;
    let mut vertices = vec![BLANK; n];
    for (k, (v, p)) in vertices.iter_mut().zip(positions).enumerate() {
        let p = Vec4::from(p).truncate();
        if !p.is_finite() {
            return Err(format!("{place}: POSITION {k} is not a finite number"));
        }
        v.position = world.transform_point3(p);
    }
    Ok(vertices)
}

/// Checks that every attribute read has one element per position, so
/// that each can be zipped with the vertices.
fn check_counts(
    prim: &::gltf::Primitive,
    sets: &sampling::Sets,
    n: usize,
    place: &str,
) -> Result<(), Problem> {
    use ::gltf::Semantic;
    let count = |semantic: Semantic| prim.get(&semantic).map(|a| a.count());
    let second_set = sets
        .second
        .map(|r| (Semantic::TexCoords(r.set), "TEXCOORD"));
    for (semantic, what) in [
        (Semantic::Normals, "NORMAL"),
        (Semantic::TexCoords(sets.first.set), "TEXCOORD"),
        (Semantic::Colors(0), "COLOR_0"),
        (Semantic::Tangents, "TANGENT"),
    ]
    .into_iter()
    .chain(second_set)
    {
        if let Some(len) = count(semantic)
            && len != n
        {
            return Err(format!("{place}: {len} {what} for {n} positions"));
        }
    }
    Ok(())
}

/// Which of the optional attributes a primitive's vertices were given.
struct Given {
    normals: bool,
    uvs: bool,
    /// The file's tangents, as texture axes (triangles with normals only).
    axes: bool,
}

/// Reads the normals, the first texture coordinates (through `reading`),
/// the colours and the tangents into `vertices`, then turns the normals
/// into world space.
fn read_attributes(
    prim: &::gltf::Primitive,
    buffers: &[Vec<u8>],
    (reading, stroke): (&sampling::Reading, Option<StrokeMode>),
    world: Mat4,
    vertices: &mut [Vertex],
) -> Given {
    use ::gltf::Semantic;
    let normals = floats(prim, buffers, Semantic::Normals);
    let has_normals = normals.is_some();
    for (v, nrm) in vertices.iter_mut().zip(normals.into_iter().flatten()) {
        v.normal = Vec4::from(nrm).truncate();
    }
    let uvs = floats(prim, buffers, Semantic::TexCoords(reading.set));
    let has_uvs = uvs.is_some();
    for (v, uv) in vertices.iter_mut().zip(uvs.into_iter().flatten()) {
        v.uv = reading.uv(Vec2::new(uv[0], uv[1]));
    }
    let reader = prim.reader(|b| buffers.get(b.index()).map(Vec::as_slice));
    if let Some(colors) = reader.read_colors(0) {
        for (v, c) in vertices.iter_mut().zip(colors.into_rgb_f32()) {
            v.color = Vec3::from(c);
        }
    }
    let linear = Mat3::from_mat4(world);
    // The file's tangents, with its own normals, as texture axes (taken
    // against the normals as read, before they are placed).
    let tangents = floats(prim, buffers, Semantic::Tangents).filter(|_| has_normals);
    let has_axes = tangents.is_some() && stroke.is_none();
    if has_axes {
        for (v, t) in vertices.iter_mut().zip(tangents.into_iter().flatten()) {
            let t = Vec4::from(t);
            let (tu, tv) = tangent::axes(t.truncate(), t.w, v.normal);
            (v.tangent_u, v.tangent_v) = (linear * tu, linear * tv);
        }
    }
    let normal_matrix = super::normal_matrix(world);
    if has_normals {
        for v in vertices.iter_mut() {
            v.normal = (normal_matrix * v.normal).normalize_or_zero();
        }
    }
    Given {
        normals: has_normals,
        uvs: has_uvs,
        axes: has_axes,
    }
}

/// The second texture coordinate set, read only when a map reads it (and
/// the primitive draws triangles): one array of exactly one per vertex,
/// or empty.
fn read_second_set(
    prim: &::gltf::Primitive,
    buffers: &[Vec<u8>],
    (sets, stroke): (&sampling::Sets, Option<StrokeMode>),
    n: usize,
    (name, held): (&str, &mut Reservation),
) -> Result<Vec<Vec2>, Problem> {
    let second = sets.second.filter(|_| stroke.is_none()).and_then(|r| {
        Some((
            r,
            floats(prim, buffers, ::gltf::Semantic::TexCoords(r.set))?,
        ))
    });
    let Some((r, coords)) = second else {
        return Ok(Vec::new());
    };
    hold(
        held,
        name,
        "the second texture coordinates",
        bytes_of::<Vec2>(n as u64),
    )?;
    let mut uv2 = Vec::with_capacity(n);
    uv2.extend(coords.map(|uv| r.uv(Vec2::new(uv[0], uv[1]))));
    Ok(uv2)
}

/// Index `i` (the `k`th) when it names one of the `n` vertices.
fn checked_index(k: usize, i: u32, n: usize, place: &str) -> Result<u32, Problem> {
    if (i as usize) < n {
        Ok(i)
    } else {
        Err(format!("{place}: index {k} is {i}, past the {n} vertices"))
    }
}

/// A points or lines primitive: its vertices drawn through `corners` in
/// the material's base colour.
fn stroke_prim(
    vertices: Vec<Vertex>,
    material: &::gltf::Material,
    mode: StrokeMode,
    corners: Vec<u32>,
) -> Prim {
    let [r, g, b, _] = material.pbr_metallic_roughness().base_color_factor();
    Prim {
        vertices,
        has_normals: false,
        has_uvs: false,
        uv2: Vec::new(),
        has_axes: false,
        tris: Vec::new(),
        material: material.index(),
        strokes: Some(PrimStrokes {
            mode,
            corners,
            factor: Vec3::new(r, g, b),
        }),
        track: false,
        source: Vec::new(),
        posing: None,
    }
}

/// The triangles of a list, strip or fan of `index_count` corners over
/// `n` vertices, each index checked, turned when the placement mirrors.
fn read_triangles(
    corners: impl Iterator<Item = (usize, u32)>,
    (mode, mirrored): (Mode, bool),
    (index_count, n, place): (usize, usize, &str),
    (name, held): (&str, &mut Reservation),
) -> Result<Vec<Triangle>, Problem> {
    let count = match mode {
        Mode::TriangleStrip | Mode::TriangleFan => index_count.saturating_sub(2),
        _ => index_count / 3,
    };
    hold(
        held,
        name,
        "the triangles",
        bytes_of::<Triangle>(count as u64),
    )?;
    let mut tris = Vec::with_capacity(count);
    let mut walk = CornerWalk::default();
    for (at, i) in corners {
        let i = checked_index(at, i, n, place)?;
        if let Some(mut t) = walk.next(mode, at, i) {
            // A mirroring transform turns counter-clockwise faces clockwise.
            if mirrored {
                t.swap(1, 2);
            }
            tris.push(corners_only(t));
        }
    }
    Ok(tris)
}

/// The corners of a list, strip or fan, taken as they come: what is kept
/// of the corners before.
#[derive(Default)]
struct CornerWalk {
    first: Option<u32>,
    previous: Option<u32>,
    last: [u32; 2],
}

impl CornerWalk {
    /// The triangle corner `i` (the `at`th) completes, if any.
    fn next(&mut self, mode: Mode, at: usize, i: u32) -> Option<[u32; 3]> {
        let last = self.last;
        match mode {
            Mode::TriangleStrip => {
                let t = (at >= 2).then(|| {
                    if at.is_multiple_of(2) {
                        [last[0], last[1], i]
                    } else {
                        [last[1], last[0], i]
                    }
                });
                self.last = [last[1], i];
                t
            }
            Mode::TriangleFan => {
                let t = match (self.first, self.previous) {
                    (Some(f), Some(p)) => Some([f, p, i]),
                    _ => None,
                };
                self.first = self.first.or(Some(i));
                self.previous = (at >= 1).then_some(i);
                t
            }
            _ => {
                let t = (at % 3 == 2).then_some([last[0], last[1], i]);
                self.last = [last[1], i];
                t
            }
        }
    }
}

/// Centres the model and scales it so its farthest point is `FIT_RADIUS`
/// away (in f64, as OBJ models are fitted).
fn fit(prims: &mut [Prim]) -> Result<(DVec3, f64), Problem> {
    // Only the points the triangles and strokes use count.
    let fit = fit_of(|| {
        prims.iter().flat_map(|p| {
            let strokes = p.strokes.iter().flat_map(|s| &s.corners);
            p.tris
                .iter()
                .flat_map(|t| &t.indices)
                .chain(strokes)
                .map(move |&i| p.vertices[i as usize].position)
        })
    })
    .ok_or("all its points coincide")?;
    for p in prims.iter_mut() {
        for v in &mut p.vertices {
            v.position = fitted(v.position, fit);
        }
    }
    Ok(fit)
}

/// A primitive as a relief mesh: vertices as the file has them (split per
/// corner where normals or tangents must be made per face), triangles with
/// an area, tangent frames from the file, MikkTSpace or relief's own.
/// `held` grows by what is allocated, before it is. With the mesh, the
/// file's vertex each of its vertices comes from when tracked and split
/// (`Prim::source`). A culled primitive that does not `deform` is tested
/// for convexity.
fn build_mesh(
    mut prim: Prim,
    look: &material::Look,
    deforms: bool,
    (name, held): (&str, &mut Reservation),
) -> Result<(Mesh, Vec<u32>), Problem> {
    // No normals: flat ones, so each corner is its own vertex (glTF 2.0 §3.7.2.1).
    let flat = !prim.has_normals;
    // The normal map's tangents are those of its own coordinates (glTF 2.0
    // §3.7.2.1), which may be another set or transform than the colour's
    // (the clearcoat's normal map's when the material has only that one).
    let normal_uv = look.tangent_uv;
    let has_normal_set = if normal_uv.second {
        !prim.uv2.is_empty()
    } else {
        prim.has_uvs
    };
    let mikk = look.normal_mapped && !prim.has_axes && has_normal_set;
    if flat || mikk {
        split_corners(&mut prim, (name, held))?;
    }
    let tangent_uvs = if look.normal_mapped && has_normal_set && !normal_uv.is_vertex_uv() {
        Some(normal_map_uvs(&prim, normal_uv, (name, held))?)
    } else {
        None
    };
    if flat {
        set_flat_normals(&mut prim);
    }
    let mut has_axes = prim.has_axes;
    if mikk {
        // What MikkTSpace allocates, per corner, at most.
        let work = bytes_of::<[f32; 40]>(prim.vertices.len() as u64);
        hold(held, name, "the tangents", work)?;
        has_axes = tangent::mikktspace(&mut prim.vertices, tangent_uvs.as_deref());
        held.shrink(work);
    }
    let factor = look.base_color;
    for v in &mut prim.vertices {
        v.normal = v.normal.try_normalize().unwrap_or(Vec3::Z);
        v.color = (v.color * factor).clamp(Vec3::ZERO, Vec3::ONE);
    }
    let textured = prim.has_uvs;
    let vertices = &prim.vertices;
    // Each triangle is its own facet, computed from its corners when drawn
    // (`Facet::of_triangle`): only those with an area stay.
    prim.tris.retain_mut(|tri| {
        let p = tri.indices.map(|i| vertices[i as usize].position);
        tri.textured = textured;
        triangle_normal(p) != Vec3::ZERO
    });
    if !has_axes {
        for v in &mut prim.vertices {
            (v.tangent_u, v.tangent_v) = (Vec3::ZERO, Vec3::ZERO);
        }
    }
    let closed = !look.double_sided;
    let shape = (closed, deforms);
    let convex = convexity::convex_part(&prim.vertices, &prim.tris, shape, (name, held));
    let mut mesh = match &tangent_uvs {
        Some(uvs) => facets_on(
            prim.vertices,
            &prim.tris,
            uvs,
            (convex, closed),
            (name, held),
        )?,
        None => Mesh::of_triangles(prim.vertices, prim.tris, convex, closed),
    }
    .with_uv2(prim.uv2);
    let sums = sum_bytes(mesh.vertices.len() as u64, mesh.triangles.len() as u64);
    hold(held, name, "the tangent sums", sums)?;
    // The file's (or MikkTSpace's) directions where there are, relief's lengths.
    accumulate_keeping_directions(&mut mesh, tangent_uvs.as_deref());
    held.shrink(sums);
    if let Some(uvs) = tangent_uvs {
        held.shrink(bytes_of::<Vec2>(uvs.capacity() as u64));
    }
    Ok((mesh, prim.source))
}

/// The normal map's coordinates, one per vertex, when they are not the
/// vertices' UVs (another set, or transformed).
fn normal_map_uvs(
    prim: &Prim,
    normal_uv: crate::map_uv::MapUv,
    (name, held): (&str, &mut Reservation),
) -> Result<Vec<Vec2>, Problem> {
    hold(
        held,
        name,
        "the normal map's coordinates",
        bytes_of::<Vec2>(prim.vertices.len() as u64),
    )?;
    let uv2 = |i: usize| prim.uv2.get(i).copied().unwrap_or_default();
    let mut uvs = Vec::with_capacity(prim.vertices.len());
    uvs.extend((prim.vertices.iter().enumerate()).map(|(i, v)| normal_uv.at(v.uv, uv2(i))));
    Ok(uvs)
}

/// Each corner takes its triangle's normal (the corners are split first).
fn set_flat_normals(prim: &mut Prim) {
    for t in &prim.tris {
        let p = t.indices.map(|i| prim.vertices[i as usize].position);
        let n = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
        for &i in &t.indices {
            prim.vertices[i as usize].normal = n;
        }
    }
}

/// The mesh of `tris` over `vertices` whose facets' texture axes are those
/// of the normal map's coordinates `uvs` (one per vertex): the facets that
/// differ from their corners' own go to the mesh's side table.
fn facets_on(
    vertices: Vec<Vertex>,
    tris: &[Triangle],
    uvs: &[Vec2],
    (convex, closed): (bool, bool),
    (name, held): (&str, &mut Reservation),
) -> Result<Mesh, Problem> {
    let count = tris.len() as u64;
    let faces_bytes = bytes_of::<Face>(count);
    let side = bytes_of::<Facet>(count);
    hold(held, name, "the facets", faces_bytes.saturating_add(side))?;
    let mut faces = Vec::with_capacity(tris.len());
    faces.extend(tris.iter().map(|t| {
        let facet = Facet::of_triangle(t.indices.map(|i| &vertices[i as usize]));
        let p = t.indices.map(|i| vertices[i as usize].position);
        let frame = face_frame(p, t.indices.map(|i| uvs[i as usize]), facet.normal);
        Face {
            indices: t.indices,
            face_normal: facet.normal,
            face_tangent_u: frame.tangent_u,
            face_tangent_v: frame.tangent_v,
            facet_center: facet.center,
            facet_color: facet.color,
            textured: t.textured,
        }
    }));
    let mesh = Mesh::new(vertices, &faces, convex, closed);
    held.shrink(faces_bytes.saturating_add(side) - mesh.side_bytes() as u64);
    Ok(mesh)
}

/// The primitive with one vertex per triangle corner.
fn split_corners(prim: &mut Prim, (name, held): (&str, &mut Reservation)) -> Result<(), Problem> {
    let corners = 3 * prim.tris.len();
    hold(
        held,
        name,
        "the corners",
        bytes_of::<Vertex>(corners as u64),
    )?;
    let vertices: Vec<Vertex> = prim
        .tris
        .iter()
        .flat_map(|t| t.indices)
        .map(|i| prim.vertices[i as usize])
        .collect();
    let old = bytes_of::<Vertex>(prim.vertices.capacity() as u64);
    prim.vertices = vertices;
    held.shrink(old);
    if prim.track {
        hold(held, name, "the corners", bytes_of::<u32>(corners as u64))?;
        let from = |i: u32| prim.source.get(i as usize).copied().unwrap_or(i);
        prim.source = prim.tris.iter().flat_map(|t| t.indices).map(from).collect();
    }
    if !prim.uv2.is_empty() {
        hold(held, name, "the corners", bytes_of::<Vec2>(corners as u64))?;
        let mut uv2 = Vec::with_capacity(corners);
        uv2.extend((prim.tris.iter().flat_map(|t| t.indices)).map(|i| prim.uv2[i as usize]));
        let old = bytes_of::<Vec2>(prim.uv2.capacity() as u64);
        prim.uv2 = uv2;
        held.shrink(old);
    }
    for (t, tri) in prim.tris.iter_mut().enumerate() {
        let t = 3 * t as u32;
        tri.indices = [t, t + 1, t + 2];
    }
    Ok(())
}
