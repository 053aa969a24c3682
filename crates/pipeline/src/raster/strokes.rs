//! A model's points and lines (`scene::strokes`) over the filled picture:
//! points as small squares, lines stepped by DDA as the lines display
//! steps them (`wire`), every pixel tested against the depth the
//! triangles left (and writing its own, so the nearer of two strokes
//! wins). Unlit: a stroke has no surface to light; its colour is the
//! material's base colour × the vertex colour (white with colours off).
//!
//! Depth is NDC z (z/w) as the triangles store it; along a projected
//! segment it is affine in the screen position, so it is interpolated
//! linearly between the clipped ends. A stroke on a surface passes
//! (`z <= stored`).

use glam::{DVec2, Mat4, Vec3, Vec4};

use super::wire::{clip_depth, clip_viewport};
use crate::shade::lighting::finish;
use relief_core::framebuffer::Rgb;
use relief_core::stats::Counters;
use relief_scene::strokes::Strokes;

/// Pixels with their depths: `width × height` of each, row-major.
pub struct DepthCanvas<'a> {
    width: usize,
    height: usize,
    pixels: &'a mut [Rgb],
    depth: &'a mut [f32],
}

impl<'a> DepthCanvas<'a> {
    /// `pixels` and `depth` hold exactly `width × height` each (else the
    /// canvas is empty and draws nothing).
    pub fn new(width: usize, height: usize, pixels: &'a mut [Rgb], depth: &'a mut [f32]) -> Self {
        let fits = width
            .checked_mul(height)
            .is_some_and(|n| n == pixels.len() && n == depth.len());
        let (width, height) = if fits { (width, height) } else { (0, 0) };
        DepthCanvas {
            width,
            height,
            pixels,
            depth,
        }
    }

    /// A `size × size` square around (x, y) (as the wire brush places it),
    /// each pixel written where `z` is not behind what it holds.
    fn brush(&mut self, x: i64, y: i64, size: usize, z: f32, color: Rgb) -> u64 {
        let half = (size / 2) as i64;
        let mut written = 0;
        for yy in (y - half).max(0)..(y - half + size as i64).min(self.height as i64) {
            for xx in (x - half).max(0)..(x - half + size as i64).min(self.width as i64) {
                let at = yy as usize * self.width + xx as usize;
                if z <= self.depth[at] {
                    self.depth[at] = z;
                    self.pixels[at] = color;
                    written += 1;
                }
            }
        }
        written
    }

    /// Clip space to screen pixels (y down), as triangle setup places them.
    fn to_screen(&self, p: Vec4) -> DVec2 {
        let inv_w = 1.0 / p.w as f64;
        DVec2::new(
            (p.x as f64 * inv_w + 1.0) * 0.5 * self.width as f64,
            (1.0 - p.y as f64 * inv_w) * 0.5 * self.height as f64,
        )
    }
}

/// Draws `strokes` placed by `model` and seen through `view_proj`:
/// points `point` pixels wide, lines `line` pixels thick. Returns the
/// counters (pixels written).
pub fn draw_strokes(
    strokes: &Strokes,
    model: Mat4,
    view_proj: Mat4,
    colors: bool,
    (point, line): (usize, usize),
    canvas: &mut DepthCanvas,
) -> Counters {
    let mut counters = Counters::default();
    if strokes.is_empty() || canvas.width == 0 || canvas.height == 0 {
        return counters;
    }
    let m = view_proj * model;
    let clip: Vec<Vec4> = strokes
        .vertices
        .iter()
        .map(|v| m * v.position.extend(1.0))
        .collect();
    let color = |i: usize| {
        if colors {
            strokes.vertices[i].color
        } else {
            Vec3::ONE
        }
    };
    for &i in &strokes.points {
        let Some(&p) = clip.get(i as usize) else {
            continue;
        };
        if !(p.is_finite() && p.w > 0.0 && p.z >= -p.w && p.z <= p.w) {
            continue;
        }
        let s = canvas.to_screen(p);
        if !(s.x >= 0.0 && s.y >= 0.0 && s.x < canvas.width as f64 && s.y < canvas.height as f64) {
            continue;
        }
        let c = finish(color(i as usize), &mut counters);
        counters.pixels_shaded += canvas.brush(s.x as i64, s.y as i64, point, p.z / p.w, c);
    }
    for &[a, b] in &strokes.lines {
        let (Some(&pa), Some(&pb)) = (clip.get(a as usize), clip.get(b as usize)) else {
            continue;
        };
        let ends = ((pa, color(a as usize)), (pb, color(b as usize)));
        segment(ends, line, canvas, &mut counters);
    }
    counters
}

/// One segment, clipped to the depth range and the viewport, its colour
/// and depth interpolated from end to end.
fn segment(
    ((a, ca), (b, cb)): ((Vec4, Vec3), (Vec4, Vec3)),
    size: usize,
    canvas: &mut DepthCanvas,
    counters: &mut Counters,
) {
    if !a.is_finite() || !b.is_finite() {
        return;
    }
    let Some((t0, t1)) = clip_depth(a, b) else {
        return;
    };
    let (pa, pb) = (a + (b - a) * t0, a + (b - a) * t1);
    let (c0, c1) = (ca + (cb - ca) * t0, ca + (cb - ca) * t1);
    let (z0, z1) = (pa.z / pa.w, pb.z / pb.w);
    let (sa, sb) = (canvas.to_screen(pa), canvas.to_screen(pb));
    if !sa.is_finite() || !sb.is_finite() {
        return;
    }
    let Some((u0, u1)) = clip_viewport(sa, sb, canvas.width as f64, canvas.height as f64) else {
        return;
    };
    let (s0, s1) = (sa + (sb - sa) * u0, sa + (sb - sa) * u1);
    let lerp_z = |u: f64| z0 + (z1 - z0) * u as f32;
    let (k0, k1) = (c0 + (c1 - c0) * u0 as f32, c0 + (c1 - c0) * u1 as f32);
    let (w0, w1) = (lerp_z(u0), lerp_z(u1));
    let d = s1 - s0;
    let n = d.x.abs().max(d.y.abs()).ceil().max(1.0) as i64;
    for i in 0..=n {
        let t = i as f64 / n as f64;
        let p = s0 + d * t;
        let color = finish(k0 + (k1 - k0) * t as f32, counters);
        let z = w0 + (w1 - w0) * t as f32;
        counters.pixels_shaded +=
            canvas.brush(p.x.floor() as i64, p.y.floor() as i64, size, z, color);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use relief_scene::strokes::{StrokeMode, StrokeVertex};

    fn strokes(points: &[(Vec3, Vec3)], mode: StrokeMode) -> Strokes {
        let v: Vec<StrokeVertex> = points
            .iter()
            .map(|&(position, color)| StrokeVertex { position, color })
            .collect();
        let corners: Vec<u32> = (0..v.len() as u32).collect();
        let mut s = Strokes::default();
        s.add(&v, &corners, mode);
        s
    }

    /// With the identity as view and projection, clip = NDC: on a 10 × 6
    /// canvas, x = −1 + (2k + 1)/10 is the centre of column k and
    /// y = 1 − (2r + 1)/6 the centre of row r.
    fn centre(col: usize, row: usize, z: f32) -> Vec3 {
        Vec3::new(
            -1.0 + (2 * col + 1) as f32 / 10.0,
            1.0 - (2 * row + 1) as f32 / 6.0,
            z,
        )
    }

    #[test]
    fn a_point_lights_its_pixel_only_where_nothing_is_nearer() {
        let mut px = vec![[0u8; 3]; 60];
        let mut depth = vec![f32::INFINITY; 60];
        // Pixel (7, 4) holds a surface at depth 0.2.
        depth[4 * 10 + 7] = 0.2;
        let red = Vec3::X;
        let s = strokes(
            &[
                (centre(2, 1, 0.5), red),
                (centre(7, 4, 0.5), red),
                (centre(8, 4, 0.1), red),
            ],
            StrokeMode::Points,
        );
        let mut canvas = DepthCanvas::new(10, 6, &mut px, &mut depth);
        let c = draw_strokes(
            &s,
            Mat4::IDENTITY,
            Mat4::IDENTITY,
            true,
            (1, 1),
            &mut canvas,
        );
        assert_eq!(c.pixels_shaded, 2);
        for y in 0..6 {
            for x in 0..10 {
                let lit = (x, y) == (2, 1) || (x, y) == (8, 4);
                assert_eq!(
                    px[y * 10 + x],
                    if lit { [255, 0, 0] } else { [0; 3] },
                    "({x}, {y})"
                );
            }
        }
        assert_eq!(depth[10 + 2], 0.5);
        // Colours off: white.
        let mut px = vec![[0u8; 3]; 60];
        let mut depth = vec![f32::INFINITY; 60];
        let mut canvas = DepthCanvas::new(10, 6, &mut px, &mut depth);
        draw_strokes(
            &s,
            Mat4::IDENTITY,
            Mat4::IDENTITY,
            false,
            (1, 1),
            &mut canvas,
        );
        assert_eq!(px[10 + 2], [255; 3]);
    }

    #[test]
    fn a_line_covers_the_pixels_between_its_ends_in_front_of_the_surface() {
        let mut px = vec![[0u8; 3]; 60];
        // Columns 5 and up hold a surface at depth 0 (nearer than the
        // line's 0.5 at every step), the others nothing.
        let mut depth: Vec<f32> = (0..60)
            .map(|i| if i % 10 >= 5 { 0.0 } else { f32::INFINITY })
            .collect();
        // From the centre of (1, 2) to that of (8, 2): a horizontal line.
        let s = strokes(
            &[(centre(1, 2, 0.5), Vec3::Y), (centre(8, 2, 0.5), Vec3::Y)],
            StrokeMode::Lines,
        );
        let mut canvas = DepthCanvas::new(10, 6, &mut px, &mut depth);
        draw_strokes(
            &s,
            Mat4::IDENTITY,
            Mat4::IDENTITY,
            true,
            (1, 1),
            &mut canvas,
        );
        for y in 0..6 {
            for x in 0..10 {
                let lit = y == 2 && (1..5).contains(&x);
                assert_eq!(px[y * 10 + x] == [0, 255, 0], lit, "({x}, {y})");
            }
        }
    }

    #[test]
    fn a_diagonal_line_steps_one_pixel_per_column() {
        let mut px = vec![[0u8; 3]; 60];
        let mut depth = vec![f32::INFINITY; 60];
        // From (0, 0) to (5, 5): the pixels (k, k).
        let s = strokes(
            &[
                (centre(0, 0, 0.0), Vec3::ONE),
                (centre(5, 5, 0.0), Vec3::ONE),
            ],
            StrokeMode::LineStrip,
        );
        let mut canvas = DepthCanvas::new(10, 6, &mut px, &mut depth);
        draw_strokes(
            &s,
            Mat4::IDENTITY,
            Mat4::IDENTITY,
            true,
            (1, 1),
            &mut canvas,
        );
        for y in 0..6 {
            for x in 0..10 {
                assert_eq!(px[y * 10 + x] == [255; 3], x == y, "({x}, {y})");
            }
        }
    }
}
