//! GLB files written byte by byte for the tests: the container, a
//! builder of accessors over one binary chunk, and a small skinned,
//! animated model. Shared by the test crates that write models
//! (`#[path]`-included).
#![allow(dead_code)]

use glam::{Mat4, Quat, Vec3};

/// The GLB container of `json` and the binary chunk `bin`, each padded
/// to four bytes.
pub fn glb(json: &str, bin: &[u8]) -> Vec<u8> {
    let mut json = json.as_bytes().to_vec();
    while !json.len().is_multiple_of(4) {
        json.push(b' ');
    }
    let mut bin = bin.to_vec();
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    let total = 12 + 8 + json.len() + 8 + bin.len();
    let mut out = Vec::new();
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(json.len() as u32).to_le_bytes());
    out.extend_from_slice(&0x4E4F534Au32.to_le_bytes());
    out.extend_from_slice(&json);
    out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
    out.extend_from_slice(&0x004E4942u32.to_le_bytes());
    out.extend_from_slice(&bin);
    out
}

/// A file's binary chunk, views and accessors, built up as data is added.
#[derive(Default)]
pub struct Bin {
    bytes: Vec<u8>,
    views: Vec<String>,
    accessors: Vec<String>,
}

impl Bin {
    /// An accessor of `values` floats as elements of `ty` (`SCALAR`,
    /// `VEC2`, `VEC3`, `VEC4`, `MAT4`); its index.
    pub fn floats(&mut self, values: &[f32], ty: &str) -> usize {
        let width = match ty {
            "SCALAR" => 1,
            "VEC2" => 2,
            "VEC3" => 3,
            "VEC4" => 4,
            "MAT4" => 16,
            _ => panic!("{ty}"),
        };
        let bytes = values.iter().flat_map(|f| f.to_le_bytes()).collect();
        self.add(bytes, values.len() / width, ty, 5126)
    }

    /// A POSITION accessor, with the bounds glTF asks of it; its index.
    pub fn positions(&mut self, values: &[f32]) -> usize {
        let at = self.floats(values, "VEC3");
        let bound = |pick: fn(f32, f32) -> f32| {
            let b: Vec<String> = (0..3)
                .map(|k| {
                    values
                        .iter()
                        .skip(k)
                        .step_by(3)
                        .copied()
                        .reduce(pick)
                        .unwrap()
                })
                .map(|v| format!("{v:?}"))
                .collect();
            b.join(",")
        };
        let (lo, hi) = (bound(f32::min), bound(f32::max));
        let last = self.accessors.last_mut().unwrap();
        last.pop();
        last.push_str(&format!(r#","min":[{lo}],"max":[{hi}]}}"#));
        at
    }

    /// An accessor of unsigned shorts as elements of `ty`; its index.
    pub fn shorts(&mut self, values: &[u16], ty: &str) -> usize {
        let width = if ty == "VEC4" { 4 } else { 1 };
        let bytes = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        self.add(bytes, values.len() / width, ty, 5123)
    }

    /// A buffer view of `bytes` (an image's, say); its index.
    pub fn view(&mut self, bytes: &[u8]) -> usize {
        while !self.bytes.len().is_multiple_of(4) {
            self.bytes.push(0);
        }
        self.views.push(format!(
            r#"{{"buffer":0,"byteOffset":{},"byteLength":{}}}"#,
            self.bytes.len(),
            bytes.len()
        ));
        self.bytes.extend_from_slice(bytes);
        self.views.len() - 1
    }

    fn add(&mut self, bytes: Vec<u8>, count: usize, ty: &str, component: u32) -> usize {
        self.view(&bytes);
        self.accessors.push(format!(
            r#"{{"bufferView":{},"componentType":{component},"count":{count},"type":"{ty}"}}"#,
            self.views.len() - 1
        ));
        self.accessors.len() - 1
    }

    /// The GLB of `json` (the document without its accessors, views and
    /// buffers, and without its closing brace) over this data.
    pub fn glb(&self, json: &str) -> Vec<u8> {
        let json = format!(
            r#"{json},"accessors":[{}],"bufferViews":[{}],"buffers":[{{"byteLength":{}}}]}}"#,
            self.accessors.join(","),
            self.views.join(","),
            self.bytes.len()
        );
        glb(&json, &self.bytes)
    }
}

/// A strip up +Y from 0 to 2, two vertices (x = ±0.1) at each of y = 0,
/// 1, 2, skinned to a root joint at the origin and a child joint at y = 1:
/// the bottom pair on the root, the middle pair half on each, the top pair
/// on the child. The clip turns the child about Z from 0° at 0 s to 90° at 1 s.
pub fn two_joint_strip() -> Vec<u8> {
    let mut bin = Bin::default();
    let ys = [0.0f32, 0.0, 1.0, 1.0, 2.0, 2.0];
    let xs = [-0.1f32, 0.1, -0.1, 0.1, -0.1, 0.1];
    let pos: Vec<f32> = xs.iter().zip(ys).flat_map(|(&x, y)| [x, y, 0.0]).collect();
    let position = bin.positions(&pos);
    let normal = bin.floats(&[0.0, 0.0, 1.0].repeat(6), "VEC3");
    let joints = bin.shorts(&[[0u16, 1, 0, 0]; 6].concat(), "VEC4");
    let w = |a: f32| [a, 1.0 - a, 0.0, 0.0];
    let weights = [w(1.0), w(1.0), w(0.5), w(0.5), w(0.0), w(0.0)].concat();
    let weights = bin.floats(&weights, "VEC4");
    let indices = bin.shorts(&[0, 1, 3, 0, 3, 2, 2, 3, 5, 2, 5, 4], "SCALAR");
    let child = Mat4::from_translation(Vec3::Y).inverse();
    let ibm = [Mat4::IDENTITY.to_cols_array(), child.to_cols_array()].concat();
    let ibm = bin.floats(&ibm, "MAT4");
    let times = bin.floats(&[0.0, 1.0], "SCALAR");
    let quarter = Quat::from_rotation_z(std::f32::consts::FRAC_PI_2).to_array();
    let turns = bin.floats(&[[0.0, 0.0, 0.0, 1.0], quarter].concat(), "VEC4");
    bin.glb(&format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0,2]}}],
        "nodes":[{{"children":[1]}},{{"translation":[0,1,0]}},{{"mesh":0,"skin":0}}],
        "skins":[{{"joints":[0,1],"inverseBindMatrices":{ibm}}}],
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":{position},"NORMAL":{normal},
            "JOINTS_0":{joints},"WEIGHTS_0":{weights}}},"indices":{indices}}}]}}],
        "animations":[{{"samplers":[{{"input":{times},"output":{turns}}}],
            "channels":[{{"sampler":0,"target":{{"node":1,"path":"rotation"}}}}]}}]"#
    ))
}
