//! Clipping in homogeneous clip space (before the division by w), so
//! triangles crossing the near plane or lying behind the camera are cut or
//! dropped before anything divides by a w near 0.

use glam::{Vec3, Vec4};

/// A clipped vertex: its clip-space position and its barycentric
/// coordinates in the source triangle (so every varying can be rebuilt).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClipVertex {
    pub pos: Vec4,
    pub bary: Vec3,
}

/// How far outside the viewport x and y may reach before a triangle is cut
/// (a guard band): rarely cut, and screen coordinates stay small enough for
/// exact fixed-point edge functions.
const GUARD: f32 = 4.0;

/// Plane distances, each ≥ 0 inside: near (z ≥ −w), far (z ≤ w), and the guard band.
#[inline]
fn distances(p: Vec4) -> [f32; 6] {
    [
        p.w + p.z,
        p.w - p.z,
        GUARD * p.w + p.x,
        GUARD * p.w - p.x,
        GUARD * p.w + p.y,
        GUARD * p.w - p.y,
    ]
}

/// What clipping made of a triangle.
#[derive(Debug, PartialEq)]
pub enum Clipped {
    /// Entirely inside: use the three vertices as they are.
    Inside,
    /// Entirely outside (or not finite): draw nothing.
    Outside,
    /// Cut: the convex polygon left is in the output buffer.
    Polygon,
}

/// The outcode bit of a vertex that is not finite.
const NOT_FINITE: u8 = 1 << 6;

/// A vertex's outcode: bit k set when it is outside plane k of
/// [`distances`], and [`NOT_FINITE`]. Computed once per vertex and frame,
/// it decides most triangles without [`clip_triangle`].
#[inline]
pub fn outcode(p: Vec4) -> u8 {
    if !p.is_finite() {
        return NOT_FINITE;
    }
    distances(p)
        .iter()
        .enumerate()
        .fold(0, |code, (k, d)| code | (u8::from(*d < 0.0) << k))
}

/// What [`clip_triangle`] makes of a triangle whose vertices have
/// `codes`, when the codes alone decide it: `None` when it must be cut.
#[inline]
pub fn clip_by_codes(codes: [u8; 3]) -> Option<Clipped> {
    let any = codes[0] | codes[1] | codes[2];
    if any & NOT_FINITE != 0 || codes[0] & codes[1] & codes[2] != 0 {
        Some(Clipped::Outside)
    } else if any == 0 {
        Some(Clipped::Inside)
    } else {
        None
    }
}

/// Clips a triangle against the near and far planes and the guard band.
/// On `Clipped::Polygon`, `out` holds the polygon (3 to 9 vertices).
pub fn clip_triangle(v: [Vec4; 3], out: &mut Vec<ClipVertex>) -> Clipped {
    if !v.iter().all(|p| p.is_finite()) {
        return Clipped::Outside;
    }
    let d = v.map(distances);
    let mut any_out = false;
    for plane in 0..6 {
        let outside = d.iter().filter(|dist| dist[plane] < 0.0).count();
        if outside == 3 {
            return Clipped::Outside;
        }
        any_out |= outside > 0;
    }
    if !any_out {
        return Clipped::Inside;
    }
    out.clear();
    out.extend([
        ClipVertex {
            pos: v[0],
            bary: Vec3::X,
        },
        ClipVertex {
            pos: v[1],
            bary: Vec3::Y,
        },
        ClipVertex {
            pos: v[2],
            bary: Vec3::Z,
        },
    ]);
    let mut next = Vec::with_capacity(9);
    for plane in 0..6 {
        next.clear();
        for i in 0..out.len() {
            let a = out[i];
            let b = out[(i + 1) % out.len()];
            let da = distances(a.pos)[plane];
            let db = distances(b.pos)[plane];
            if da >= 0.0 {
                next.push(a);
            }
            if (da >= 0.0) != (db >= 0.0) {
                // The crossing point, interpolated linearly in clip space,
                // where linear interpolation of every attribute is exact.
                let t = da / (da - db);
                next.push(ClipVertex {
                    pos: a.pos + (b.pos - a.pos) * t,
                    bary: a.bary + (b.bary - a.bary) * t,
                });
            }
        }
        std::mem::swap(out, &mut next);
        if out.len() < 3 {
            return Clipped::Outside;
        }
    }
    Clipped::Polygon
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inside_triangle_is_untouched() {
        let mut out = Vec::new();
        let v = [
            Vec4::new(0.0, 0.0, 0.0, 1.0),
            Vec4::new(0.5, 0.0, 0.0, 1.0),
            Vec4::new(0.0, 0.5, 0.0, 1.0),
        ];
        assert_eq!(clip_triangle(v, &mut out), Clipped::Inside);
    }

    #[test]
    fn behind_the_camera_is_dropped() {
        let mut out = Vec::new();
        let v = [
            Vec4::new(0.0, 0.0, -2.0, -1.0),
            Vec4::new(0.5, 0.0, -2.0, -1.0),
            Vec4::new(0.0, 0.5, -2.0, -1.0),
        ];
        assert_eq!(clip_triangle(v, &mut out), Clipped::Outside);
    }

    #[test]
    fn crossing_the_near_plane_keeps_w_positive_and_barycentrics_valid() {
        let mut out = Vec::new();
        let v = [
            Vec4::new(0.0, 0.0, 0.5, 1.0),
            Vec4::new(0.5, 0.0, -3.0, -1.0),
            Vec4::new(0.0, 0.5, 0.5, 1.0),
        ];
        assert_eq!(clip_triangle(v, &mut out), Clipped::Polygon);
        assert_eq!(out.len(), 4);
        for cv in &out {
            assert!(cv.pos.w + cv.pos.z >= -1e-6);
            assert!(cv.pos.w > 0.0);
            assert!((cv.bary.element_sum() - 1.0).abs() < 1e-6);
            assert!(cv.bary.min_element() >= -1e-6);
        }
    }

    /// Whenever the outcodes decide, they decide as `clip_triangle` does;
    /// when they do not, it cuts the triangle.
    #[test]
    fn outcodes_agree_with_clipping() {
        let mut seed = 0x9e37_79b9_u64;
        let mut next = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed % 2001) as f32 / 100.0 - 10.0
        };
        let mut out = Vec::new();
        let (mut decided, mut cut) = (0, 0);
        for n in 0..20_000 {
            let mut v = [0; 3].map(|_| Vec4::new(next(), next(), next(), next().abs() * 0.4));
            if n % 97 == 0 {
                v[n % 3].y = f32::NAN;
            }
            let codes = v.map(outcode);
            match clip_by_codes(codes) {
                Some(c) => {
                    decided += 1;
                    assert_eq!(clip_triangle(v, &mut out), c, "{v:?}");
                }
                None => {
                    cut += 1;
                    assert_ne!(clip_triangle(v, &mut out), Clipped::Inside, "{v:?}");
                }
            }
        }
        assert!(decided > 1000 && cut > 1000, "{decided} {cut}");
    }

    #[test]
    fn nan_input_is_dropped() {
        let mut out = Vec::new();
        let v = [Vec4::NAN, Vec4::ONE, Vec4::ONE];
        assert_eq!(clip_triangle(v, &mut out), Clipped::Outside);
    }
}
