//! The plot: PSNR against median frame time (log scale), one numbered point
//! per configuration, the Pareto front joined and highlighted, a legend of the
//! numbers. Drawn straight into an `image` buffer with the hand-made font.

use image::{Rgb, RgbImage};

use super::font;
use super::report::Report;

const WIDTH: u32 = 1520;
const HEIGHT: u32 = 800;
/// The plotting area.
const LEFT: i64 = 100;
const RIGHT: i64 = 900;
const TOP: i64 = 70;
const BOTTOM: i64 = 720;
const LEGEND_X: i64 = 940;

const BACKGROUND: Rgb<u8> = Rgb([255, 255, 255]);
const INK: Rgb<u8> = Rgb([30, 30, 30]);
const GRID: Rgb<u8> = Rgb([225, 225, 225]);
const POINT: Rgb<u8> = Rgb([90, 110, 150]);
const FRONT: Rgb<u8> = Rgb([220, 90, 20]);

struct Canvas(RgbImage);

impl Canvas {
    fn put(&mut self, x: i64, y: i64, c: Rgb<u8>) {
        if x >= 0 && y >= 0 && x < self.0.width() as i64 && y < self.0.height() as i64 {
            self.0.put_pixel(x as u32, y as u32, c);
        }
    }

    /// A line `width` pixels thick, stepped along its longer axis.
    fn line(&mut self, (x0, y0): (f64, f64), (x1, y1): (f64, f64), width: i64, c: Rgb<u8>) {
        let steps = (x1 - x0).abs().max((y1 - y0).abs()).ceil().max(1.0) as i64;
        for i in 0..=steps {
            let t = i as f64 / steps as f64;
            let (x, y) = (x0 + (x1 - x0) * t, y0 + (y1 - y0) * t);
            for dy in 0..width {
                for dx in 0..width {
                    self.put(
                        x.round() as i64 + dx - width / 2,
                        y.round() as i64 + dy - width / 2,
                        c,
                    );
                }
            }
        }
    }

    fn disc(&mut self, cx: f64, cy: f64, r: f64, c: Rgb<u8>) {
        let (x0, x1) = ((cx - r).floor() as i64, (cx + r).ceil() as i64);
        let (y0, y1) = ((cy - r).floor() as i64, (cy + r).ceil() as i64);
        for y in y0..=y1 {
            for x in x0..=x1 {
                let (dx, dy) = (x as f64 - cx, y as f64 - cy);
                if dx * dx + dy * dy <= r * r {
                    self.put(x, y, c);
                }
            }
        }
    }

    fn text(&mut self, text: &str, x: i64, y: i64, scale: usize, c: Rgb<u8>) {
        font::draw(text, x, y, scale, |px, py| self.put(px, py, c));
    }
}

/// Tick label of a power of ten in milliseconds (0.01, 0.1, 1, 10, …).
fn decade_label(exp: i32) -> String {
    if exp >= 0 {
        format!("{}", 10u64.pow(exp as u32))
    } else {
        format!("{:.*}", (-exp) as usize, 10f64.powi(exp))
    }
}

/// Draws the plot of `report`; `title` goes on top.
pub fn draw(report: &Report, title: &str) -> RgbImage {
    let mut c = Canvas(RgbImage::from_pixel(WIDTH, HEIGHT, BACKGROUND));
    let points = Points::of(report);
    let axes = Axes::new(&points.times, &points.psnrs);
    draw_time_grid(&mut c, &axes);
    draw_db_grid(&mut c, &axes);
    draw_frame(&mut c, title);
    draw_front_line(&mut c, &axes, &points);
    draw_numbers(&mut c, &axes, &points);
    draw_discs(&mut c, &axes, &points);
    draw_legend(&mut c, report, &points.front);
    c.0
}

/// The rows as plotted: time in milliseconds, PSNR, and whether on the front.
struct Points {
    /// Floored at 0.1 µs so that the log scale has a place for a zero time.
    times: Vec<f64>,
    psnrs: Vec<f64>,
    front: Vec<bool>,
}

impl Points {
    fn of(report: &Report) -> Points {
        let front = report.front();
        let times = report
            .rows
            .iter()
            .map(|r| (r.median.as_secs_f64() * 1e3).max(1e-4))
            .collect();
        let psnrs = report.rows.iter().map(|r| r.psnr).collect();
        Points {
            times,
            psnrs,
            front,
        }
    }

    /// The rows on the front (`on`) or off it, in table order, without the
    /// NaN PSNRs that have no place on the plot.
    fn drawn(&self, on: bool) -> impl Iterator<Item = usize> + '_ {
        (0..self.times.len()).filter(move |&i| self.front[i] == on && !self.psnrs[i].is_nan())
    }
}

/// The two scales: whole decades of milliseconds across, PSNR up.
struct Axes {
    /// First and last decade (powers of ten) of the X axis.
    x_lo: i32,
    x_hi: i32,
    /// PSNR at the bottom and at the highest finite grid line.
    y_lo: f64,
    y_hi: f64,
    /// PSNR at the top: `y_hi`, or a band above it where exact matches sit.
    y_top: f64,
    has_inf: bool,
    /// dB between grid lines.
    step: f64,
}

impl Axes {
    fn new(times: &[f64], psnrs: &[f64]) -> Axes {
        let (x_lo, x_hi) = decades(times);
        let (y_lo, y_hi) = db_bounds(psnrs);
        // An exact match sits on a band above, marked INF.
        let has_inf = psnrs.iter().any(|p| p.is_infinite());
        let y_top = if has_inf { y_hi + 5.0 } else { y_hi };
        let y_lo = y_lo.min(y_hi);
        let step = if y_top - y_lo > 60.0 { 10.0 } else { 5.0 };
        Axes {
            x_lo,
            x_hi,
            y_lo,
            y_hi,
            y_top,
            has_inf,
            step,
        }
    }

    fn x_of(&self, ms: f64) -> f64 {
        LEFT as f64
            + (ms.log10() - self.x_lo as f64) / (self.x_hi - self.x_lo) as f64
                * (RIGHT - LEFT) as f64
    }

    fn y_of(&self, db: f64) -> f64 {
        let db = if db.is_infinite() { self.y_top } else { db };
        BOTTOM as f64 - (db - self.y_lo) / (self.y_top - self.y_lo) * (BOTTOM - TOP) as f64
    }
}

/// The decades of milliseconds the times span: at least one, -1..1 when
/// there is no time to go by.
fn decades(times: &[f64]) -> (i32, i32) {
    let lmin = times.iter().copied().fold(f64::INFINITY, f64::min).log10();
    let lmax = times
        .iter()
        .copied()
        .fold(f64::NEG_INFINITY, f64::max)
        .log10();
    let (mut x_lo, mut x_hi) = (lmin.floor() as i32, lmax.ceil() as i32);
    if !lmin.is_finite() {
        (x_lo, x_hi) = (-1, 1);
    }
    if x_hi <= x_lo {
        x_hi = x_lo + 1;
    }
    (x_lo, x_hi)
}

/// The finite PSNRs rounded out to steps of 5 dB, at least one step apart
/// (0..50 when none is finite).
fn db_bounds(psnrs: &[f64]) -> (f64, f64) {
    let finite: Vec<f64> = psnrs.iter().copied().filter(|p| p.is_finite()).collect();
    let fmin = finite.iter().copied().fold(f64::INFINITY, f64::min);
    let fmax = finite.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let (y_lo, mut y_hi) = if finite.is_empty() {
        (0.0, 50.0)
    } else {
        ((fmin / 5.0).floor() * 5.0, (fmax / 5.0).ceil() * 5.0)
    };
    if y_hi - y_lo < 5.0 {
        y_hi = y_lo + 5.0;
    }
    (y_lo, y_hi)
}

/// A vertical grid line and label per decade, with ticks at 2× to 9×.
fn draw_time_grid(c: &mut Canvas, axes: &Axes) {
    let (x_lo, x_hi) = (axes.x_lo, axes.x_hi);
    for e in x_lo..=x_hi {
        let x = axes.x_of(10f64.powi(e));
        c.line((x, TOP as f64), (x, BOTTOM as f64), 1, GRID);
        let label = decade_label(e);
        let w = font::text_width(&label, 2) as i64;
        c.text(&label, x as i64 - w / 2, BOTTOM + 10, 2, INK);
        if e < x_hi {
            for m in 2..10 {
                let v = m as f64 * 10f64.powi(e);
                let x = axes.x_of(v);
                c.line((x, BOTTOM as f64 - 6.0), (x, BOTTOM as f64), 1, INK);
                // With few decades, label 2× and 5× too.
                if x_hi - x_lo <= 2 && (m == 2 || m == 5) {
                    let label = format!("{}", m as f64 * 10f64.powi(e));
                    let w = font::text_width(&label, 2) as i64;
                    c.text(&label, x as i64 - w / 2, BOTTOM + 10, 2, POINT);
                }
            }
        }
    }
}

/// A horizontal grid line and label per step of dB, and the INF band.
fn draw_db_grid(c: &mut Canvas, axes: &Axes) {
    let mut db = axes.y_lo;
    while db <= axes.y_hi + 1e-9 {
        let y = axes.y_of(db);
        c.line((LEFT as f64, y), (RIGHT as f64, y), 1, GRID);
        let label = format!("{db:.0}");
        let w = font::text_width(&label, 2) as i64;
        c.text(&label, LEFT - 12 - w, y as i64 - 7, 2, INK);
        db += axes.step;
    }
    if axes.has_inf {
        let y = axes.y_of(f64::INFINITY);
        c.line((LEFT as f64, y), (RIGHT as f64, y), 1, GRID);
        c.text(
            "INF",
            LEFT - 12 - font::text_width("INF", 2) as i64,
            y as i64 - 7,
            2,
            INK,
        );
    }
}

/// The two axes, the plot's title and the axes' titles.
fn draw_frame(c: &mut Canvas, title: &str) {
    c.line(
        (LEFT as f64, TOP as f64),
        (LEFT as f64, BOTTOM as f64),
        2,
        INK,
    );
    c.line(
        (LEFT as f64, BOTTOM as f64),
        (RIGHT as f64, BOTTOM as f64),
        2,
        INK,
    );
    c.text(title, LEFT, 16, 2, INK);
    c.text("PSNR (DB), HIGHER IS BETTER", LEFT - 60, TOP - 30, 2, INK);
    let x_title = "MEDIAN TIME PER FRAME (MS, LOG SCALE), LEFT IS FASTER";
    let w = font::text_width(x_title, 2) as i64;
    c.text(x_title, (LEFT + RIGHT) / 2 - w / 2, BOTTOM + 40, 2, INK);
}

/// The front, joined in order of time.
fn draw_front_line(c: &mut Canvas, axes: &Axes, p: &Points) {
    let (times, psnrs) = (&p.times, &p.psnrs);
    let mut on: Vec<usize> = (0..times.len()).filter(|&i| p.front[i]).collect();
    on.sort_by(|&a, &b| times[a].total_cmp(&times[b]));
    for pair in on.windows(2) {
        let (a, b) = (pair[0], pair[1]);
        c.line(
            (axes.x_of(times[a]), axes.y_of(psnrs[a])),
            (axes.x_of(times[b]), axes.y_of(psnrs[b])),
            2,
            FRONT,
        );
    }
}

/// Each point's number as in the table, the front's first so that they get
/// the best spots, each placed where it overlaps no number already drawn.
fn draw_numbers(c: &mut Canvas, axes: &Axes, p: &Points) {
    let mut placed: Vec<(i64, i64, i64, i64)> = Vec::new();
    for pass in [true, false] {
        for i in p.drawn(pass) {
            let (x, y) = (axes.x_of(p.times[i]) as i64, axes.y_of(p.psnrs[i]) as i64);
            let label = (i + 1).to_string();
            let (w, h) = (font::text_width(&label, 2) as i64, 2 * font::GLYPH_H as i64);
            let (lx, ly) = label_spot((x, y), (w, h), &placed);
            placed.push((lx, ly, w, h));
            let color = if pass { FRONT } else { POINT };
            c.text(&label, lx, ly, 2, color);
        }
    }
}

/// Where a `w × h` label of the point at (x, y) goes: the first of the
/// candidate spots around it clear (by 2 pixels) of every `placed`
/// rectangle, or the first spot if none is.
fn label_spot(
    (x, y): (i64, i64),
    (w, h): (i64, i64),
    placed: &[(i64, i64, i64, i64)],
) -> (i64, i64) {
    let spots = [
        (x + 8, y - 16),
        (x + 8, y + 4),
        (x - 8 - w, y - 16),
        (x - 8 - w, y + 4),
        (x - w / 2, y - 24),
        (x - w / 2, y + 10),
        (x + 8, y - 32),
        (x + 8, y + 20),
        (x - 8 - w, y - 32),
        (x - 8 - w, y + 20),
    ];
    let free = |&(lx, ly): &(i64, i64)| {
        placed.iter().all(|&(px, py, pw, ph)| {
            lx + w + 2 <= px || px + pw + 2 <= lx || ly + h + 2 <= py || py + ph + 2 <= ly
        })
    };
    spots.iter().copied().find(|s| free(s)).unwrap_or(spots[0])
}

/// The points: others first, the front on top, larger.
fn draw_discs(c: &mut Canvas, axes: &Axes, p: &Points) {
    for pass in [false, true] {
        for i in p.drawn(pass) {
            let (x, y) = (axes.x_of(p.times[i]), axes.y_of(p.psnrs[i]));
            let color = if pass { FRONT } else { POINT };
            c.disc(x, y, if pass { 6.0 } else { 4.5 }, color);
        }
    }
}

/// The numbered configuration names, as many as fit below the heading.
fn draw_legend(c: &mut Canvas, report: &Report, front: &[bool]) {
    c.text(
        "CONFIGURATIONS (* PARETO FRONT)",
        LEGEND_X,
        TOP - 30,
        2,
        INK,
    );
    let line_height = 20;
    let max_lines = ((HEIGHT as i64 - TOP) / line_height) as usize;
    for (i, row) in report.rows.iter().enumerate().take(max_lines) {
        let color = if front[i] { FRONT } else { INK };
        let mark = if front[i] { "*" } else { " " };
        let text = format!("{:>2}{mark} {}", i + 1, row.config.name);
        c.text(&text, LEGEND_X, TOP + i as i64 * line_height, 2, color);
    }
}

/// Draws the plot and writes it as a PNG.
pub fn save(report: &Report, title: &str, path: &std::path::Path) -> anyhow::Result<()> {
    use anyhow::Context;
    relief_core::framebuffer::write_png(&draw(report, title), path)
        .with_context(|| format!("cannot write {}", relief_core::sanitize::display_path(path)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decade_labels() {
        assert_eq!(decade_label(-2), "0.01");
        assert_eq!(decade_label(-1), "0.1");
        assert_eq!(decade_label(0), "1");
        assert_eq!(decade_label(2), "100");
    }
}
