//! Keyframe curves (glTF 2.0 §3.11, "Animations"): a sampler's key times
//! and values, read at any time with STEP, LINEAR or CUBICSPLINE
//! interpolation. Rotations are unit quaternions: LINEAR takes the short
//! way round by spherical interpolation, and every result is normalised.

use glam::Quat;

/// How values between two keys are found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Interpolation {
    /// The earlier key's value until the next key.
    Step,
    /// A straight line (a spherical one for rotations).
    Linear,
    /// A cubic Hermite spline through the keys, with the in- and
    /// out-tangents the file gives per key.
    CubicSpline,
}

/// One curve: `times` increasing, and per key `width` values (three
/// groups of `width` for a cubic spline: in-tangent, value, out-tangent).
#[derive(Clone, Debug, PartialEq)]
pub struct Sampler {
    pub times: Vec<f32>,
    pub values: Vec<f32>,
    pub width: usize,
    pub interpolation: Interpolation,
}

impl Sampler {
    /// The last key's time (0 without keys).
    pub fn end(&self) -> f32 {
        self.times.last().copied().unwrap_or(0.0)
    }

    /// Values per key in `values` (3 × `width` for a cubic spline).
    fn stride(&self) -> usize {
        match self.interpolation {
            Interpolation::CubicSpline => 3 * self.width,
            _ => self.width,
        }
    }

    /// Key `k`'s value (for a cubic spline, the middle group).
    fn value(&self, k: usize) -> &[f32] {
        let start = k * self.stride()
            + match self.interpolation {
                Interpolation::CubicSpline => self.width,
                _ => 0,
            };
        &self.values[start..start + self.width]
    }

    /// Key `k`'s in-tangent (`group` 0) or out-tangent (`group` 2) of a
    /// cubic spline.
    fn tangent(&self, k: usize, group: usize) -> &[f32] {
        let start = k * self.stride() + group * self.width;
        &self.values[start..start + self.width]
    }

    /// The curve at `time` into `out` (`width` values); before the first
    /// key the first value, after the last the last. `rotation`: the
    /// values are quaternions (x, y, z, w).
    pub fn sample(&self, time: f32, rotation: bool, out: &mut [f32]) {
        let n = self.times.len();
        if n == 0 {
            return;
        }
        let after = self.times.partition_point(|&t| t <= time);
        if after == 0 || n == 1 {
            out.copy_from_slice(self.value(0));
        } else if after == n {
            out.copy_from_slice(self.value(n - 1));
        } else {
            let k = after - 1;
            let (t0, t1) = (self.times[k], self.times[k + 1]);
            let span = t1 - t0;
            let s = if span > 0.0 { (time - t0) / span } else { 0.0 };
            self.between(k, s, span, rotation, out);
        }
        if rotation {
            normalise_quaternions(out);
        }
    }

    /// The value a share `s` of the way from key `k` to key `k + 1`,
    /// `span` seconds apart.
    fn between(&self, k: usize, s: f32, span: f32, rotation: bool, out: &mut [f32]) {
        match self.interpolation {
            Interpolation::Step => out.copy_from_slice(self.value(k)),
            Interpolation::Linear if rotation => {
                for (q, (a, b)) in out.chunks_exact_mut(4).zip(
                    self.value(k)
                        .chunks_exact(4)
                        .zip(self.value(k + 1).chunks_exact(4)),
                ) {
                    q.copy_from_slice(&slerp(quat(a), quat(b), s).to_array());
                }
            }
            Interpolation::Linear => {
                let (a, b) = (self.value(k), self.value(k + 1));
                for (o, (a, b)) in out.iter_mut().zip(a.iter().zip(b)) {
                    *o = a + (b - a) * s;
                }
            }
            Interpolation::CubicSpline => {
                let (s2, s3) = (s * s, s * s * s);
                let h00 = 2.0 * s3 - 3.0 * s2 + 1.0;
                let h10 = s3 - 2.0 * s2 + s;
                let h01 = -2.0 * s3 + 3.0 * s2;
                let h11 = s3 - s2;
                let (v0, b0) = (self.value(k), self.tangent(k, 2));
                let (v1, a1) = (self.value(k + 1), self.tangent(k + 1, 0));
                for (i, o) in out.iter_mut().enumerate() {
                    *o = h00 * v0[i] + h10 * span * b0[i] + h01 * v1[i] + h11 * span * a1[i];
                }
            }
        }
    }
}

fn quat(v: &[f32]) -> Quat {
    Quat::from_xyzw(v[0], v[1], v[2], v[3])
}

/// Spherical interpolation the short way round (the two quaternions q
/// and −q are the same rotation).
fn slerp(a: Quat, b: Quat, s: f32) -> Quat {
    let b = if a.dot(b) < 0.0 { -b } else { b };
    a.slerp(b, s)
}

/// Each group of four made a unit quaternion (the identity when zero).
fn normalise_quaternions(out: &mut [f32]) {
    for q in out.chunks_exact_mut(4) {
        q.copy_from_slice(&unit(quat(q)).to_array());
    }
}

/// `q` made unit length (the identity when it has none).
pub fn unit(q: Quat) -> Quat {
    let length = q.length();
    if length > 0.0 && length.is_finite() {
        q / length
    } else {
        Quat::IDENTITY
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn curve(times: &[f32], values: &[f32], width: usize, interpolation: Interpolation) -> Sampler {
        Sampler {
            times: times.to_vec(),
            values: values.to_vec(),
            width,
            interpolation,
        }
    }

    fn at(s: &Sampler, t: f32) -> Vec<f32> {
        let mut out = vec![0.0; s.width];
        s.sample(t, false, &mut out);
        out
    }

    #[test]
    fn step_holds_each_key_until_the_next() {
        let s = curve(&[0.0, 1.0, 2.0], &[5.0, 7.0, 9.0], 1, Interpolation::Step);
        assert_eq!(at(&s, -1.0), [5.0]);
        assert_eq!(at(&s, 0.99), [5.0]);
        assert_eq!(at(&s, 1.0), [7.0]);
        assert_eq!(at(&s, 1.5), [7.0]);
        assert_eq!(at(&s, 3.0), [9.0]);
    }

    #[test]
    fn linear_is_a_straight_line_between_keys() {
        let s = curve(
            &[0.0, 2.0],
            &[1.0, 10.0, 3.0, 20.0],
            2,
            Interpolation::Linear,
        );
        assert_eq!(at(&s, 0.5), [1.5, 12.5]);
        assert_eq!(at(&s, 2.5), [3.0, 20.0]);
    }

    #[test]
    fn a_cubic_spline_passes_its_keys_and_follows_its_tangents() {
        // Keys 0 at t = 0 and 1 at t = 2, out-tangent of the first 3 and
        // in-tangent of the second −1 (per second): with s = ½ the Hermite
        // weights are ½, ⅛·2, ½, −⅛·2, so 0·½ + 3·¼ + 1·½ + (−1)·(−¼) = 1.5.
        let values = [9.0, 0.0, 3.0, -1.0, 1.0, 9.0];
        let s = curve(&[0.0, 2.0], &values, 1, Interpolation::CubicSpline);
        assert_eq!(at(&s, 0.0), [0.0]);
        assert_eq!(at(&s, 2.0), [1.0]);
        assert!((at(&s, 1.0)[0] - 1.5).abs() < 1e-6, "{:?}", at(&s, 1.0));
    }

    #[test]
    fn rotations_turn_the_short_way_at_constant_speed() {
        // From the identity to 90° about Y, given as its negative: halfway
        // is 45° about Y, not the long way round.
        let h = std::f32::consts::FRAC_PI_4;
        let q90 = -Quat::from_rotation_y(2.0 * h);
        let values = [[0.0, 0.0, 0.0, 1.0], q90.to_array()].concat();
        let s = curve(&[0.0, 1.0], &values, 4, Interpolation::Linear);
        let mut out = [0.0; 4];
        s.sample(0.5, true, &mut out);
        let q = Quat::from_array(out);
        assert!(q.angle_between(Quat::from_rotation_y(h)) < 1e-5, "{q}");
        s.sample(0.25, true, &mut out);
        let q = Quat::from_array(out);
        assert!(
            q.angle_between(Quat::from_rotation_y(h / 2.0)) < 1e-5,
            "{q}"
        );
    }
}
