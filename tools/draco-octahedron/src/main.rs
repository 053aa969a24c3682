//! Writes to standard output the Draco stream of the tests' octahedron
//! (`tests/inputs/octahedron.rs`), read by tests/inputs/models_gltf_draco.rs
//! from tests/data/octahedron.drc.

use std::io::Write;

use draco_core::{
    DataType, EncoderBuffer, EncoderOptions, FaceIndex, GeometryAttributeType, MeshEncoder,
    PointAttribute,
};

#[path = "../../../tests/inputs/octahedron.rs"]
mod octahedron;
use octahedron::{FACES, POINTS, uv};

fn main() -> std::io::Result<()> {
    std::io::stdout().write_all(&octahedron_stream())
}

/// A Draco attribute of `values` (`width` floats a point).
fn attribute(kind: GeometryAttributeType, width: u8, values: &[f32]) -> PointAttribute {
    let mut a = PointAttribute::new();
    let n = values.len() / width as usize;
    a.init(kind, width, DataType::Float32, false, n);
    for (i, v) in values.iter().enumerate() {
        a.buffer_mut().write(i * 4, &v.to_le_bytes());
    }
    a
}

/// The octahedron as one Draco stream: POSITION (id 0), NORMAL (id 1,
/// the point's own direction), TEXCOORD_0 (id 2), default options.
fn octahedron_stream() -> Vec<u8> {
    let mut mesh = draco_core::Mesh::new();
    let flat: Vec<f32> = POINTS.iter().flatten().copied().collect();
    let uvs: Vec<f32> = POINTS.iter().flat_map(|&p| uv(p)).collect();
    mesh.add_attribute(attribute(GeometryAttributeType::Position, 3, &flat));
    mesh.add_attribute(attribute(GeometryAttributeType::Normal, 3, &flat));
    mesh.add_attribute(attribute(GeometryAttributeType::TexCoord, 2, &uvs));
    mesh.set_num_faces(FACES.len());
    for (k, f) in FACES.iter().enumerate() {
        mesh.set_face(FaceIndex(k as u32), f.map(Into::into));
    }
    let mut encoder = MeshEncoder::new();
    encoder.set_mesh(mesh);
    let mut out = EncoderBuffer::new();
    encoder.encode(&EncoderOptions::new(), &mut out).unwrap();
    out.data().to_vec()
}
