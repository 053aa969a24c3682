//! The points and lines display modes ([000] §3.2.3, docs/sources.md): each visible
//! triangle's vertices as dots, or its edges as lines.
//!
//! "Visible" means what fill draws before depth: back faces of closed meshes
//! are culled, so a cube shows its front edges only; there is no depth test,
//! so on a non-convex model an edge behind another front face still shows.
//! Lines and points take the lit vertex colour (lighting at the vertex, as
//! Gouraud does; no texture), interpolated along a line. Lines are clipped to
//! the near and far planes in clip space and to the viewport in screen space,
//! then stepped by DDA; every write is bounds-checked, so nothing lands
//! outside the framebuffer whatever the input.

use glam::{DVec2, Vec3, Vec4};

use crate::shade::lighting::finish;
use relief_core::framebuffer::Rgb;
use relief_core::stats::Counters;

/// A triangle of the wireframe: clip-space corners and lit vertex colours.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WireTri {
    pub clip: [Vec4; 3],
    pub color: [Vec3; 3],
}

/// Pixels a frame of this size gives a point (square side): 2 from 480
/// rows up, else 1.
pub fn point_size(width: usize, height: usize) -> usize {
    if width.min(height) >= 480 { 2 } else { 1 }
}

/// A pixel target: `width × height` pixels, row-major.
pub struct Canvas<'a> {
    width: usize,
    height: usize,
    pixels: &'a mut [Rgb],
}

impl<'a> Canvas<'a> {
    /// `pixels` holds exactly `width × height` pixels (or the canvas is empty).
    pub fn new(width: usize, height: usize, pixels: &'a mut [Rgb]) -> Self {
        if width.checked_mul(height) == Some(pixels.len()) {
            Canvas {
                width,
                height,
                pixels,
            }
        } else {
            Canvas {
                width: 0,
                height: 0,
                pixels,
            }
        }
    }
}

impl Canvas<'_> {
    /// Paints a `size × size` square whose top-left is (x, y) minus half the
    /// size, clipped to the canvas. Returns the pixels written.
    #[inline]
    fn brush(&mut self, x: i64, y: i64, size: usize, color: Rgb) -> u64 {
        let half = (size / 2) as i64;
        let mut written = 0;
        for yy in y - half..y - half + size as i64 {
            if yy < 0 || yy >= self.height as i64 {
                continue;
            }
            for xx in x - half..x - half + size as i64 {
                if xx < 0 || xx >= self.width as i64 {
                    continue;
                }
                // In bounds by the two tests above: an index past the end
                // would be a bug, and panics rather than hiding.
                self.pixels[yy as usize * self.width + xx as usize] = color;
                written += 1;
            }
        }
        written
    }

    /// Clip-space point to screen (pixels, y down), like triangle setup.
    #[inline]
    fn to_screen(&self, p: Vec4) -> DVec2 {
        let inv_w = 1.0 / p.w as f64;
        DVec2::new(
            (p.x as f64 * inv_w + 1.0) * 0.5 * self.width as f64,
            (1.0 - p.y as f64 * inv_w) * 0.5 * self.height as f64,
        )
    }
}

/// Inside near (z ≥ −w) and far (z ≤ w), with w > 0.
#[inline]
fn in_depth_range(p: Vec4) -> bool {
    p.w > 0.0 && p.z >= -p.w && p.z <= p.w
}

/// Draws each vertex of each triangle as a `size`-pixel square.
pub fn draw_points(tris: &[WireTri], size: usize, canvas: &mut Canvas, counters: &mut Counters) {
    for tri in tris {
        for (p, c) in tri.clip.iter().zip(&tri.color) {
            if !p.is_finite() || !in_depth_range(*p) {
                continue;
            }
            let s = canvas.to_screen(*p);
            if !(s.x >= 0.0
                && s.y >= 0.0
                && s.x < canvas.width as f64
                && s.y < canvas.height as f64)
            {
                continue;
            }
            let color = finish(*c, counters);
            counters.pixels_shaded += canvas.brush(s.x as i64, s.y as i64, size, color);
        }
    }
}

/// Draws the three edges of each triangle, `size` pixels thick.
pub fn draw_lines(tris: &[WireTri], size: usize, canvas: &mut Canvas, counters: &mut Counters) {
    for tri in tris {
        for i in 0..3 {
            let j = (i + 1) % 3;
            draw_line(
                (tri.clip[i], tri.color[i]),
                (tri.clip[j], tri.color[j]),
                size,
                canvas,
                counters,
            );
        }
    }
}

/// Clips the segment a→b in clip space to −w ≤ z ≤ w (parameters along it).
pub(crate) fn clip_depth(a: Vec4, b: Vec4) -> Option<(f32, f32)> {
    let mut t0 = 0.0f32;
    let mut t1 = 1.0f32;
    // Distances to the near and far planes, each ≥ 0 inside; also w ≥ a tiny
    // positive margin so the projection never divides by ~0.
    let planes = |p: Vec4| [p.w + p.z, p.w - p.z, p.w - 1e-6];
    let (da, db) = (planes(a), planes(b));
    for k in 0..3 {
        let (fa, fb) = (da[k], db[k]);
        if fa < 0.0 && fb < 0.0 {
            return None;
        }
        if fa < 0.0 {
            t0 = t0.max(fa / (fa - fb));
        } else if fb < 0.0 {
            t1 = t1.min(fa / (fa - fb));
        }
    }
    (t0 <= t1).then_some((t0, t1))
}

/// Liang–Barsky: the part of segment a→b inside [0, w) × [0, h).
pub(crate) fn clip_viewport(a: DVec2, b: DVec2, w: f64, h: f64) -> Option<(f64, f64)> {
    let d = b - a;
    let mut t0 = 0.0f64;
    let mut t1 = 1.0f64;
    // Keep endpoints a hair inside the far edges so floor() stays < size.
    let (wmax, hmax) = (w - 1e-9 * w.max(1.0), h - 1e-9 * h.max(1.0));
    for (p, q) in [
        (-d.x, a.x),
        (d.x, wmax - a.x),
        (-d.y, a.y),
        (d.y, hmax - a.y),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                t0 = t0.max(r);
            } else {
                t1 = t1.min(r);
            }
        }
    }
    (t0 <= t1 && t0.is_finite() && t1.is_finite()).then_some((t0, t1))
}

/// One line with colours interpolated from end to end.
pub fn draw_line(
    (a, ca): (Vec4, Vec3),
    (b, cb): (Vec4, Vec3),
    size: usize,
    canvas: &mut Canvas,
    counters: &mut Counters,
) {
    if !a.is_finite() || !b.is_finite() || canvas.width == 0 || canvas.height == 0 {
        return;
    }
    let Some((t0, t1)) = clip_depth(a, b) else {
        return;
    };
    let (pa, pb) = (a + (b - a) * t0, a + (b - a) * t1);
    let (c0, c1) = (ca + (cb - ca) * t0, ca + (cb - ca) * t1);
    let (sa, sb) = (canvas.to_screen(pa), canvas.to_screen(pb));
    if !sa.is_finite() || !sb.is_finite() {
        return;
    }
    let Some((u0, u1)) = clip_viewport(sa, sb, canvas.width as f64, canvas.height as f64) else {
        return;
    };
    let (s0, s1) = (sa + (sb - sa) * u0, sa + (sb - sa) * u1);
    let (k0, k1) = (c0 + (c1 - c0) * u0 as f32, c0 + (c1 - c0) * u1 as f32);
    // DDA: one pixel per step along the major axis.
    let d = s1 - s0;
    let n = d.x.abs().max(d.y.abs()).ceil().max(1.0) as i64;
    for i in 0..=n {
        let t = i as f64 / n as f64;
        let p = s0 + d * t;
        let color = finish(k0 + (k1 - k0) * t as f32, counters);
        counters.pixels_shaded += canvas.brush(p.x.floor() as i64, p.y.floor() as i64, size, color);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_horizontal_line_lights_one_row_inside_the_viewport() {
        let mut px = vec![[0u8; 3]; 10 * 6];
        let mut canvas = Canvas::new(10, 6, &mut px);
        let mut c = Counters::default();
        // From far left to far right at y = 0 (screen row 3), w = 1.
        draw_line(
            (Vec4::new(-5.0, 0.0, 0.0, 1.0), Vec3::ONE),
            (Vec4::new(5.0, 0.0, 0.0, 1.0), Vec3::ONE),
            1,
            &mut canvas,
            &mut c,
        );
        for y in 0..6 {
            for x in 0..10 {
                let lit = px[y * 10 + x] == [255; 3];
                assert_eq!(lit, y == 3, "({x}, {y})");
            }
        }
    }

    #[test]
    fn lines_behind_the_camera_draw_nothing() {
        let mut px = vec![[0u8; 3]; 16];
        let mut canvas = Canvas::new(4, 4, &mut px);
        let mut c = Counters::default();
        draw_line(
            (Vec4::new(0.0, 0.0, -3.0, -1.0), Vec3::ONE),
            (Vec4::new(0.5, 0.2, -2.0, -0.5), Vec3::ONE),
            1,
            &mut canvas,
            &mut c,
        );
        assert_eq!(c.pixels_shaded, 0);
    }

    #[test]
    fn point_size_grows_on_large_frames() {
        assert_eq!(point_size(320, 240), 1);
        assert_eq!(point_size(640, 480), 2);
    }
}
