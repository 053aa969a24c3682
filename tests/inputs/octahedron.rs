//! The octahedron of the Draco and meshopt tests, shared with the tools that
//! write its streams (`tools/draco-octahedron`, `tools/meshopt-streams`).

/// An octahedron: six points on the axes, eight faces wound outwards.
pub const POINTS: [[f32; 3]; 6] = [
    [1.0, 0.0, 0.0],
    [-1.0, 0.0, 0.0],
    [0.0, 1.0, 0.0],
    [0.0, -1.0, 0.0],
    [0.0, 0.0, 1.0],
    [0.0, 0.0, -1.0],
];
pub const FACES: [[u32; 3]; 8] = [
    [0, 2, 4],
    [2, 1, 4],
    [1, 3, 4],
    [3, 0, 4],
    [2, 0, 5],
    [1, 2, 5],
    [3, 1, 5],
    [0, 3, 5],
];

/// Each point's texture coordinate: (x + 1)/2, (y + 1)/2.
pub fn uv(p: [f32; 3]) -> [f32; 2] {
    [(p[0] + 1.0) / 2.0, (p[1] + 1.0) / 2.0]
}
