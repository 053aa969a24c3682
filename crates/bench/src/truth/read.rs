//! The truth's readings of pictures: a texture's and an environment's
//! continuous forms, in f64.

use glam::DVec3;

use relief_texture::Level;

/// The texture's continuous form at (u, v): bilinear between texel
/// centres, repeating; texel (0, 0) is the first stored, v grows by rows.
pub fn bilinear(level: &Level, u: f64, v: f64) -> [f64; 4] {
    let (w, h) = (level.width as i64, level.height as i64);
    let x = (u - u.floor()) * w as f64 - 0.5;
    let y = (v - v.floor()) * h as f64 - 0.5;
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = (x - x0, y - y0);
    let at = |i: i64, j: i64| {
        level
            .texels
            .at((j.rem_euclid(h) * w + i.rem_euclid(w)) as usize)
    };
    let (i, j) = (x0 as i64, y0 as i64);
    let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i, j + 1), at(i + 1, j + 1));
    std::array::from_fn(|k| {
        let (a, b, c, d) = (a[k] as f64, b[k] as f64, c[k] as f64, d[k] as f64);
        (a * (1.0 - fx) + b * fx) * (1.0 - fy) + (c * (1.0 - fx) + d * fx) * fy
    })
}

/// The colour a latitude–longitude picture shows in direction `d`
/// (docs/environment.md): u = 1/2 + atan2(x, −z)/2π, v = acos(y/|d|)/π,
/// bilinear between texel centres, columns wrapping, rows clamped.
pub fn environment(level: &Level, d: DVec3) -> DVec3 {
    let len = d.length();
    let (u, v) = if len > 0.0 && len.is_finite() {
        (
            0.5 + d.x.atan2(-d.z) / std::f64::consts::TAU,
            (d.y / len).clamp(-1.0, 1.0).acos() / std::f64::consts::PI,
        )
    } else {
        (0.5, 0.5)
    };
    let (w, h) = (level.width as i64, level.height as i64);
    let x = u * w as f64 - 0.5;
    let y = (v * h as f64 - 0.5).clamp(0.0, (h - 1) as f64);
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = (x - x0, y - y0);
    let at = |i: i64, j: i64| {
        let t = level
            .texels
            .at((j.clamp(0, h - 1) * w + i.rem_euclid(w)) as usize);
        DVec3::new(t[0] as f64, t[1] as f64, t[2] as f64)
    };
    let (i, j) = (x0 as i64, y0 as i64);
    (at(i, j) * (1.0 - fx) + at(i + 1, j) * fx) * (1.0 - fy)
        + (at(i, j + 1) * (1.0 - fx) + at(i + 1, j + 1) * fx) * fy
}
