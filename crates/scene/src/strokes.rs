//! Points and lines a model draws as such (glTF primitives of mode POINTS,
//! LINES, LINE_LOOP and LINE_STRIP; docs/models.md): not triangles, so
//! they live beside the objects, and the renderer draws them over the
//! filled picture, depth-tested against it (`raster::strokes`).

use glam::Vec3;

/// One end of a line, or a point: where it is (model space, fitted like
/// the model's triangles) and its colour (the material's base colour ×
/// the vertex colour).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StrokeVertex {
    pub position: Vec3,
    pub color: Vec3,
}

/// A model's points and lines. They follow the user's rotation, as the
/// model's objects do.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Strokes {
    pub vertices: Vec<StrokeVertex>,
    /// Vertices drawn as small squares.
    pub points: Vec<u32>,
    /// Segments between two vertices.
    pub lines: Vec<[u32; 2]>,
}

impl Strokes {
    /// Nothing to draw.
    pub fn is_empty(&self) -> bool {
        self.points.is_empty() && self.lines.is_empty()
    }

    /// Adds a primitive's vertices, and its points or the segments of its
    /// lines, from its corner indices (into `vertices`) and mode.
    pub fn add(&mut self, vertices: &[StrokeVertex], corners: &[u32], mode: StrokeMode) {
        let base = self.vertices.len() as u32;
        self.vertices.extend_from_slice(vertices);
        let at = |i: u32| base + i;
        match mode {
            StrokeMode::Points => self.points.extend(corners.iter().map(|&i| at(i))),
            StrokeMode::Lines => self
                .lines
                .extend(corners.chunks_exact(2).map(|s| [at(s[0]), at(s[1])])),
            StrokeMode::LineStrip | StrokeMode::LineLoop => {
                self.lines
                    .extend(corners.windows(2).map(|s| [at(s[0]), at(s[1])]));
                // A loop closes from its last corner to its first.
                if mode == StrokeMode::LineLoop
                    && corners.len() > 2
                    && let (Some(&first), Some(&last)) = (corners.first(), corners.last())
                {
                    self.lines.push([at(last), at(first)]);
                }
            }
        }
    }
}

/// How a primitive's corners make strokes (glTF's four modes).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StrokeMode {
    Points,
    /// Pairs of corners.
    Lines,
    /// Each corner to the next.
    LineStrip,
    /// Each corner to the next, and the last to the first.
    LineLoop,
}

#[cfg(test)]
mod tests {
    use super::*;

    fn verts(n: usize) -> Vec<StrokeVertex> {
        (0..n)
            .map(|i| StrokeVertex {
                position: Vec3::X * i as f32,
                color: Vec3::ONE,
            })
            .collect()
    }

    #[test]
    fn each_mode_makes_the_segments_the_specification_lists() {
        let c = [0, 1, 2, 3];
        let mut s = Strokes::default();
        s.add(&verts(4), &c, StrokeMode::Lines);
        assert_eq!(s.lines, [[0, 1], [2, 3]]);
        let mut s = Strokes::default();
        s.add(&verts(4), &c, StrokeMode::LineStrip);
        assert_eq!(s.lines, [[0, 1], [1, 2], [2, 3]]);
        let mut s = Strokes::default();
        s.add(&verts(4), &c, StrokeMode::LineLoop);
        assert_eq!(s.lines, [[0, 1], [1, 2], [2, 3], [3, 0]]);
        // A second primitive's indices follow the first's vertices.
        s.add(&verts(2), &[0, 1], StrokeMode::Points);
        assert_eq!(s.points, [4, 5]);
        assert!(!s.is_empty());
        assert!(Strokes::default().is_empty());
    }
}
