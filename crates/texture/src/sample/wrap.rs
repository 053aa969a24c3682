//! How a texture's coordinates outside 0..1 are read, per axis (glTF's
//! sampler wrap modes): repeat (every built-in texture), mirrored repeat
//! and clamp to edge. The addressing does it where a read turns a
//! coordinate into texel indices, so no map is laid out larger than it is.

/// One axis's wrap mode.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum WrapMode {
    #[default]
    Repeat,
    /// Every other period is the mirror image: u = 1.25 reads u = 0.75.
    MirroredRepeat,
    /// Past an edge, the edge texel: u = 7 reads u = 1, u = −3 reads 0.
    ClampToEdge,
}

/// The wrap modes of the S (u) and T (v) axes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Wrap {
    pub s: WrapMode,
    pub t: WrapMode,
}

impl Wrap {
    /// Both axes repeat: what relief's own textures do.
    pub const REPEAT: Wrap = Wrap {
        s: WrapMode::Repeat,
        t: WrapMode::Repeat,
    };

    pub fn new(s: WrapMode, t: WrapMode) -> Wrap {
        Wrap { s, t }
    }

    /// Whether both axes repeat (the reads' fast path).
    #[inline(always)]
    pub fn repeats(self) -> bool {
        self == Wrap::REPEAT
    }
}

impl WrapMode {
    /// A coordinate's position in texel units on an axis of `n` texels,
    /// within 0..=n. Repeat keeps the coordinate's fraction; mirrored
    /// repeat folds it into one period (2 − u for u in 1..2 of every period
    /// of 2); clamp keeps it within 0..=1. NaN reads 0.
    #[inline]
    pub fn position(self, t: f32, n: usize) -> f32 {
        let u = match self {
            WrapMode::ClampToEdge => t.clamp(0.0, 1.0),
            WrapMode::Repeat => {
                let f = if t.is_finite() {
                    t.rem_euclid(1.0)
                } else {
                    0.0
                };
                if f >= 1.0 { 0.0 } else { f }
            }
            WrapMode::MirroredRepeat => {
                // t mod 2 in [0, 2), then the second half mirrored.
                let m = if t.is_finite() {
                    t.rem_euclid(2.0)
                } else {
                    0.0
                };
                let m = if m >= 2.0 { 0.0 } else { m };
                if m > 1.0 { 2.0 - m } else { m }
            }
        };
        let u = if u.is_nan() { 0.0 } else { u };
        u * n as f32
    }

    /// Texel index `k` (any integer) of an axis of `n` texels read in this
    /// mode: repeated, mirrored (−1 is 0, n is n − 1) or clamped.
    #[inline]
    pub fn index(self, k: i64, n: usize) -> usize {
        let n = n as i64;
        let i = match self {
            WrapMode::Repeat => k.rem_euclid(n),
            WrapMode::ClampToEdge => k.clamp(0, n - 1),
            WrapMode::MirroredRepeat => {
                let m = k.rem_euclid(2 * n);
                if m >= n { 2 * n - 1 - m } else { m }
            }
        };
        i as usize
    }

    /// The texel containing coordinate `t` (nearest reads).
    #[inline]
    pub fn nearest(self, t: f32, n: usize) -> usize {
        (self.position(t, n) as usize).min(n - 1)
    }

    /// The bilinear neighbourhood's four indices i − 1 ..= i + 2 and the
    /// fraction between i and i + 1, for coordinate `t` on `n` texels.
    #[inline]
    pub fn around(self, t: f32, n: usize) -> ([usize; 4], f32) {
        let x = self.position(t, n) - 0.5;
        // x lies in [−0.5, n − 0.5]: its floor is −1 ..= n − 1.
        let i = if x < 0.0 {
            -1
        } else {
            (x as i64).min(n as i64 - 1)
        };
        let f = x - i as f32;
        ([i - 1, i, i + 1, i + 2].map(|k| self.index(k, n)), f)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The texel a nearest read of a 4-texel axis gives at u.
    fn texel(mode: WrapMode, u: f32) -> usize {
        mode.nearest(u, 4)
    }

    #[test]
    fn mirrored_repeat_reads_the_mirror_image() {
        let m = WrapMode::MirroredRepeat;
        // By hand: 1.26 is 2 − 1.26 = 0.74 (texel 2), 1.885 is 0.115
        // (texel 0), −0.24 is 0.24 (texel 0), 2.31 is 0.31 (texel 1),
        // −1.3 is 2 − 1.3 = 0.7 (texel 2), 0.31 itself (texel 1).
        for (u, want) in [
            (1.26, 2),
            (1.885, 0),
            (-0.24, 0),
            (2.31, 1),
            (-1.3, 2),
            (0.31, 1),
        ] {
            assert_eq!(texel(m, u), want, "u = {u}");
        }
        assert_eq!(
            [-2, -1, 4, 5, 8, 9].map(|k| m.index(k, 4)),
            [1, 0, 3, 2, 0, 1]
        );
    }

    #[test]
    fn clamp_to_edge_reads_the_edge_texels_at_any_distance() {
        let c = WrapMode::ClampToEdge;
        for (u, want) in [
            (1.2, 3),
            (1.6, 3),
            (7.0, 3),
            (-0.2, 0),
            (-0.7, 0),
            (-30.0, 0),
            (0.6, 2),
        ] {
            assert_eq!(texel(c, u), want, "u = {u}");
        }
        // Bilinear past the edges: both taps are the edge texel.
        let (taps, _) = c.around(-5.0, 4);
        assert_eq!(taps[1..3], [0, 0]);
        let (taps, _) = c.around(3.5, 4);
        assert_eq!(taps[1..3], [3, 3]);
    }

    #[test]
    fn one_axis_repeats_beside_a_clamped_one() {
        let r = WrapMode::Repeat;
        for (u, want) in [(1.26, 1), (-0.2, 3), (2.9, 3), (0.6, 2)] {
            assert_eq!(texel(r, u), want, "u = {u}");
        }
        // Bilinear across the seam reads the far edge, as repeat does.
        let (taps, f) = r.around(0.0, 4);
        assert_eq!((taps[1..3].to_vec(), f), (vec![3, 0], 0.5));
    }

    #[test]
    fn odd_numbers_read_something_inside() {
        for mode in [
            WrapMode::Repeat,
            WrapMode::MirroredRepeat,
            WrapMode::ClampToEdge,
        ] {
            for t in [
                f32::NAN,
                f32::INFINITY,
                -f32::INFINITY,
                1e30,
                -1e30,
                2.0,
                -2.0,
            ] {
                assert!(mode.nearest(t, 3) < 3, "{mode:?} {t}");
                let (taps, f) = mode.around(t, 3);
                assert!(taps.iter().all(|&k| k < 3) && (0.0..=1.0).contains(&f));
            }
        }
    }
}
