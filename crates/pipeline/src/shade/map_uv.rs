//! A material map's texture coordinate and footprint at the pixels
//! (`scene::map_uv`, docs/models.md): the set it reads (the pixels' `uv`,
//! as the technique left it, or the second set interpolated), then its
//! affine transform. Written once over the lane type, so one pixel and
//! eight read the same coordinates.

use glam::Mat2;

use glam::Vec2;

use super::interpolate::lerp2;
use super::lanes::Lanes;
use relief_scene::map_uv::{MapUv, second_set_jacobian};
use relief_texture::sample::mip::Footprint;

/// Map `m`'s coordinate at the pixels of barycentrics `b` on a triangle
/// whose second set is `uv2` at its vertices, where the (vertex-set)
/// coordinate is `uv`.
#[inline(always)]
pub fn map_coords<L: Lanes>(m: &MapUv, uv2: &[Vec2; 3], b: &[L; 3], uv: (L, L)) -> (L, L) {
    let (u, v) = if m.second { lerp2(b, uv2) } else { uv };
    match &m.transform {
        None => (u, v),
        Some(t) => {
            let (a, o) = (t.matrix2, t.translation);
            (
                L::splat(a.x_axis.x) * u + L::splat(a.y_axis.x) * v + L::splat(o.x),
                L::splat(a.x_axis.y) * u + L::splat(a.y_axis.y) * v + L::splat(o.y),
            )
        }
    }
}

/// Where a pixel's (or eight pixels') maps read: the colour's coordinate
/// `uv`, the barycentrics `b` and the triangle's second set `uv2`.
#[derive(Clone, Copy, Debug)]
pub struct Coords<'a, L> {
    pub uv: (L, L),
    pub b: &'a [L; 3],
    pub uv2: &'a [Vec2; 3],
}

impl<L: Lanes> Coords<'_, L> {
    /// Map `m`'s coordinate there.
    #[inline(always)]
    pub fn of(&self, m: &MapUv) -> (L, L) {
        map_coords(m, self.uv2, self.b, self.uv)
    }
}

/// How footprints measured in the vertices' `uv` become footprints in map
/// `m`'s coordinate on a triangle whose sets are `uv` and `uv2` at its
/// vertices: the map's transform's linear part, after the step from `uv`
/// to the second set when it reads that one. `None` when the triangle's
/// `uv` has no area (no footprint can be carried: the map is then read at
/// its base level).
pub fn footprint_map(m: &MapUv, uv: &[Vec2; 3], uv2: &[Vec2; 3]) -> Option<Mat2> {
    let second = if m.second {
        second_set_jacobian(uv, uv2)?
    } else {
        Mat2::IDENTITY
    };
    Some(m.linear() * second)
}

/// A footprint carried by `to` (from `footprint_map`).
#[inline]
pub fn carry(fp: Footprint, to: Option<Mat2>) -> Footprint {
    match to {
        Some(m) => Footprint {
            dx: m * fp.dx,
            dy: m * fp.dy,
        },
        None => Footprint::default(),
    }
}

#[cfg(test)]
mod tests {
    use glam::Affine2;

    use super::*;

    const UV: [Vec2; 3] = [Vec2::ZERO, Vec2::X, Vec2::Y];
    /// The first set shifted by (0.5, 0.25), twice as big.
    const UV2: [Vec2; 3] = [
        Vec2::new(0.5, 0.25),
        Vec2::new(2.5, 0.25),
        Vec2::new(0.5, 2.25),
    ];

    #[test]
    fn one_pixel_and_eight_read_the_same_second_set_coordinates() {
        let m = MapUv {
            second: true,
            transform: Some(Affine2::from_scale_angle_translation(
                Vec2::new(2.0, 1.0),
                0.3,
                Vec2::new(0.1, -0.2),
            )),
        };
        let b = [0.2f32, 0.3, 0.5];
        let (u, v) = map_coords(&m, &UV2, &b, (0.0, 0.0));
        // At b the second set is (0.5 + 2·0.3, 0.25 + 2·0.5) = (1.1, 1.25).
        let want = m.transform.unwrap().transform_point2(Vec2::new(1.1, 1.25));
        assert!((Vec2::new(u, v) - want).length() < 1e-5, "{u} {v} {want}");
        let b8 = b.map(wide::f32x8::splat);
        let zero = wide::f32x8::splat(0.0);
        let (u8, v8) = map_coords(&m, &UV2, &b8, (zero, zero));
        for i in 0..8 {
            assert_eq!((u8.lane(i), v8.lane(i)), (u, v));
        }
    }

    #[test]
    fn footprints_follow_the_set_and_the_transform() {
        let fp = Footprint {
            dx: Vec2::new(0.01, 0.0),
            dy: Vec2::new(0.0, 0.02),
        };
        // The second set is twice as big: twice the footprint; a scale of
        // (3, 1) on top triples its u part.
        let m = MapUv {
            second: true,
            transform: Some(Affine2::from_scale(Vec2::new(3.0, 1.0))),
        };
        let got = carry(fp, footprint_map(&m, &UV, &UV2));
        assert!((got.dx - Vec2::new(0.06, 0.0)).length() < 1e-7, "{got:?}");
        assert!((got.dy - Vec2::new(0.0, 0.04)).length() < 1e-7, "{got:?}");
        assert_eq!(carry(fp, footprint_map(&MapUv::default(), &UV, &UV2)), fp);
    }
}
