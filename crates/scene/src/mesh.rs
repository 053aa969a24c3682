//! Triangle meshes with everything the shaders interpolate.

use glam::{Vec2, Vec3};

use super::face_frame::face_frame;

/// One vertex. Vertices are split wherever a face needs its own UVs or
/// tangents (a cube has 24), so hard edges stay hard.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Vertex {
    pub position: Vec3,
    /// Smooth normal (averaged over the faces that meet here), unit length.
    pub normal: Vec3,
    pub uv: Vec2,
    /// Per-vertex colour in 0..1.
    pub color: Vec3,
    /// ∂P/∂u and ∂P/∂v: the surface's texture axes scaled to model units
    /// (for a cube face of side 2: 2U and 2V).
    pub tangent_u: Vec3,
    pub tangent_v: Vec3,
}

/// What a mesh is built from: one triangle, counter-clockwise seen from
/// outside, with its facet data ([`Mesh::new`] keeps the facet data only
/// where it cannot be computed again from the corners).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Face {
    pub indices: [u32; 3],
    /// Normal of the facet (the polygon this triangle belongs to), unit length.
    pub face_normal: Vec3,
    /// ∂P/∂u, ∂P/∂v of the facet.
    pub face_tangent_u: Vec3,
    pub face_tangent_v: Vec3,
    /// Centre of the facet: flat shading lights the whole facet from here.
    pub facet_center: Vec3,
    /// Mean colour of the facet's vertices: flat shading paints it.
    pub facet_color: Vec3,
    /// Whether the material's texture and height map apply to this triangle.
    pub textured: bool,
}

/// The data of the facet (polygon) a triangle belongs to.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Facet {
    /// Unit normal (zero for a degenerate triangle).
    pub normal: Vec3,
    /// ∂P/∂u, ∂P/∂v.
    pub tangent_u: Vec3,
    pub tangent_v: Vec3,
    /// Centre: flat shading lights the whole facet from here.
    pub center: Vec3,
    /// Mean colour of the vertices: flat shading paints it.
    pub color: Vec3,
}

impl Facet {
    const ZERO: Facet = Facet {
        normal: Vec3::ZERO,
        tangent_u: Vec3::ZERO,
        tangent_v: Vec3::ZERO,
        center: Vec3::ZERO,
        color: Vec3::ZERO,
    };

    /// The facet of the triangle `v` alone, as every loader computes it:
    /// the normalised cross product of its edges, the tangents of its UVs
    /// (or a frame from the normal), the mean of its corners and colours.
    pub fn of_triangle(v: [&Vertex; 3]) -> Facet {
        let p = v.map(|v| v.position);
        let normal = triangle_normal(p);
        let frame = face_frame(p, v.map(|v| v.uv), normal);
        Facet {
            normal,
            tangent_u: frame.tangent_u,
            tangent_v: frame.tangent_v,
            center: p.iter().sum::<Vec3>() / 3.0,
            color: v.iter().map(|v| v.color).sum::<Vec3>() / 3.0,
        }
    }

    fn of_face(f: &Face) -> Facet {
        Facet {
            normal: f.face_normal,
            tangent_u: f.face_tangent_u,
            tangent_v: f.face_tangent_v,
            center: f.facet_center,
            color: f.facet_color,
        }
    }

    /// The facet's bits, field by field.
    pub(crate) fn bits(&self) -> [u32; 15] {
        let mut out = [0; 15];
        let fields = [
            self.normal,
            self.tangent_u,
            self.tangent_v,
            self.center,
            self.color,
        ];
        for (k, v) in fields.iter().enumerate() {
            out[3 * k..3 * k + 3].copy_from_slice(&v.to_array().map(f32::to_bits));
        }
        out
    }
}

/// The unit normal of the triangle `p` (zero when degenerate).
#[inline]
pub fn triangle_normal(p: [Vec3; 3]) -> Vec3 {
    (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero()
}

/// One triangle of a mesh, counter-clockwise seen from outside: 20 bytes.
/// Its facet data is computed from its corners ([`Facet::of_triangle`])
/// unless the mesh keeps it in its side table (a facet of more than three
/// corners, or data a loader set otherwise).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Triangle {
    pub indices: [u32; 3],
    /// Whether the material's texture and height map apply to this triangle.
    pub textured: bool,
    /// Index in [`Mesh`]'s side table, or [`COMPUTED`].
    facet: u32,
}

/// A triangle whose facet data is computed from its corners.
const COMPUTED: u32 = u32::MAX;

impl Triangle {
    /// A triangle whose facet is itself: its facet data is computed from
    /// its corners.
    pub fn new(indices: [u32; 3], textured: bool) -> Triangle {
        Triangle {
            indices,
            textured,
            facet: COMPUTED,
        }
    }
}

/// A mesh in model space.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    pub vertices: Vec<Vertex>,
    pub triangles: Vec<Triangle>,
    /// The facets that are not those of their triangle alone; consecutive
    /// triangles of one facet share an entry.
    facets: Vec<Facet>,
    /// A closed convex surface: with back-face culling no two visible
    /// triangles overlap, so no depth buffer is needed.
    pub convex: bool,
    /// A closed surface: back faces can never be seen from outside, so they are culled.
    pub closed: bool,
    /// A second texture coordinate per vertex, for a material whose maps
    /// read two sets (a glTF normal or emissive map on TEXCOORD_1 while
    /// the colour is on TEXCOORD_0; `scene::map_uv`); empty otherwise, so
    /// other meshes pay nothing for it ([`Mesh::with_uv2`]).
    uv2: Vec<Vec2>,
    /// A model file's part whose file gave none of its corners a colour:
    /// each is the reference scene's colour by position
    /// (`cube::corner_color`), which the model view does not show (it
    /// draws the part white, as a model viewer does).
    pub colours_invented: bool,
}

/// Below this many faces a mesh is built on one thread.
const PARALLEL_MIN: usize = 16_384;

impl Mesh {
    /// The mesh of `faces` over `vertices`, each face's facet data kept
    /// only when computing it from the corners would not give the same
    /// bits.
    pub fn new(vertices: Vec<Vertex>, faces: &[Face], convex: bool, closed: bool) -> Mesh {
        let mut mesh = Mesh {
            vertices,
            triangles: Vec::with_capacity(faces.len()),
            facets: Vec::new(),
            convex,
            closed,
            uv2: Vec::new(),
            colours_invented: false,
        };
        let kept = |f: &Face| {
            Some(Facet::of_face(f).bits())
                != mesh_facet_of(&mesh.vertices, f.indices).map(|g| g.bits())
        };
        let kept: Vec<bool> = if faces.len() < PARALLEL_MIN {
            faces.iter().map(kept).collect()
        } else {
            use rayon::prelude::*;
            faces.par_iter().map(kept).collect()
        };
        for (f, kept) in faces.iter().zip(kept) {
            let facet = if kept {
                let facet = Facet::of_face(f);
                if mesh.facets.last().map(Facet::bits) != Some(facet.bits()) {
                    mesh.facets.push(facet);
                }
                (mesh.facets.len() - 1) as u32
            } else {
                COMPUTED
            };
            mesh.triangles.push(Triangle {
                indices: f.indices,
                textured: f.textured,
                facet,
            });
        }
        mesh.facets.shrink_to_fit();
        mesh
    }

    /// The mesh of `triangles` over `vertices`, each triangle its own facet
    /// (made with [`Triangle::new`]): nothing goes to the side table, and
    /// nothing is allocated beyond the two arrays.
    pub fn of_triangles(
        vertices: Vec<Vertex>,
        triangles: Vec<Triangle>,
        convex: bool,
        closed: bool,
    ) -> Mesh {
        debug_assert!(triangles.iter().all(|t| t.facet == COMPUTED));
        Mesh {
            vertices,
            triangles,
            facets: Vec::new(),
            convex,
            closed,
            uv2: Vec::new(),
            colours_invented: false,
        }
    }

    /// The mesh with `uv2` as its second texture coordinate set, one per
    /// vertex (or none).
    pub fn with_uv2(mut self, uv2: Vec<Vec2>) -> Mesh {
        assert!(
            uv2.is_empty() || uv2.len() == self.vertices.len(),
            "a second texture coordinate set has one per vertex"
        );
        self.uv2 = uv2;
        self
    }

    /// The mesh of `triangles` (made with [`Triangle::new`]) over
    /// `vertices`, the triangles named in `side` (in increasing order)
    /// keeping the facet given there: what [`Mesh::new`] makes of the same
    /// faces when exactly those facets differ from their corners'.
    pub fn with_side_facets(
        vertices: Vec<Vertex>,
        mut triangles: Vec<Triangle>,
        side: &[(u32, Facet)],
        convex: bool,
        closed: bool,
    ) -> Mesh {
        let mut facets: Vec<Facet> = Vec::new();
        for (t, facet) in side {
            if facets.last().map(Facet::bits) != Some(facet.bits()) {
                facets.push(*facet);
            }
            triangles[*t as usize].facet = (facets.len() - 1) as u32;
        }
        facets.shrink_to_fit();
        Mesh {
            vertices,
            triangles,
            facets,
            convex,
            closed,
            uv2: Vec::new(),
            colours_invented: false,
        }
    }

    /// The second texture coordinate set: one per vertex, or empty.
    pub fn uv2(&self) -> &[Vec2] {
        &self.uv2
    }

    /// How many side-table entries [`Mesh::new`] would make at most (to
    /// reserve memory before building).
    pub fn side_facets(vertices: &[Vertex], faces: &[Face]) -> usize {
        use rayon::prelude::*;
        faces
            .par_iter()
            .filter(|f| {
                Some(Facet::of_face(f).bits())
                    != mesh_facet_of(vertices, f.indices).map(|g| g.bits())
            })
            .count()
    }

    /// The facet data of triangle `t` (all zero when a corner is past
    /// the vertices).
    #[inline]
    pub fn facet(&self, t: usize) -> Facet {
        let tri = &self.triangles[t];
        match tri.facet {
            COMPUTED => mesh_facet_of(&self.vertices, tri.indices).unwrap_or(Facet::ZERO),
            s => self.facets[s as usize],
        }
    }

    /// The unit normal of triangle `t`'s facet (the cheap part of
    /// [`Mesh::facet`]; zero when a corner is past the vertices).
    #[inline]
    pub fn face_normal(&self, t: usize) -> Vec3 {
        let tri = &self.triangles[t];
        match tri.facet {
            COMPUTED => match tri.indices.map(|i| self.vertices.get(i as usize)) {
                [Some(a), Some(b), Some(c)] => {
                    triangle_normal([a.position, b.position, c.position])
                }
                _ => Vec3::ZERO,
            },
            s => self.facets[s as usize].normal,
        }
    }

    /// Triangle `t`'s corners when its facet is computed from them and
    /// each is a vertex (its [`Mesh::face_normal`] is then the
    /// [`triangle_normal`] of their positions); `None` otherwise or past
    /// the last triangle.
    #[inline]
    pub fn computed_corners(&self, t: usize) -> Option<[u32; 3]> {
        let tri = self.triangles.get(t)?;
        let inside = tri
            .indices
            .iter()
            .all(|&i| (i as usize) < self.vertices.len());
        (tri.facet == COMPUTED && inside).then_some(tri.indices)
    }

    /// Triangle `t` with its facet data, as it was given to [`Mesh::new`].
    pub fn face(&self, t: usize) -> Face {
        let tri = &self.triangles[t];
        let f = self.facet(t);
        Face {
            indices: tri.indices,
            face_normal: f.normal,
            face_tangent_u: f.tangent_u,
            face_tangent_v: f.tangent_v,
            facet_center: f.center,
            facet_color: f.color,
            textured: tri.textured,
        }
    }

    /// Every triangle with its facet data.
    pub fn faces(&self) -> Vec<Face> {
        (0..self.triangles.len()).map(|t| self.face(t)).collect()
    }

    /// Appends triangle `t` of `other` with the corners `indices` (into
    /// this mesh's vertices, which must match `other`'s at those corners
    /// as far as the facet data goes): its facet data comes along.
    pub fn push_from(&mut self, other: &Mesh, t: usize, indices: [u32; 3]) {
        let tri = &other.triangles[t];
        let facet = match tri.facet {
            COMPUTED => COMPUTED,
            s => {
                let facet = other.facets[s as usize];
                if self.facets.last().map(Facet::bits) != Some(facet.bits()) {
                    self.facets.push(facet);
                }
                (self.facets.len() - 1) as u32
            }
        };
        self.triangles.push(Triangle {
            indices,
            textured: tri.textured,
            facet,
        });
    }

    /// Bytes held by the side table of facets.
    pub fn side_bytes(&self) -> usize {
        self.facets.capacity() * std::mem::size_of::<Facet>()
    }
}

/// The facet computed from the corners `indices` of `vertices`, or `None`
/// when an index is past the vertices.
fn mesh_facet_of(vertices: &[Vertex], indices: [u32; 3]) -> Option<Facet> {
    let v = indices.map(|i| vertices.get(i as usize));
    match v {
        [Some(a), Some(b), Some(c)] => Some(Facet::of_triangle([a, b, c])),
        _ => None,
    }
}
