//! Key `s`: the picture on screen saved as a PNG, rendered again at a
//! size worth keeping and named by the UTC date and time.

use std::time::{SystemTime, UNIX_EPOCH};

use super::state::State;
use relief_core::framebuffer::Framebuffer;
use relief_core::stats::FrameStats;
use relief_scene::SceneKind;

/// The screenshot is at least this wide: the view's picture (a pixel per
/// column) is enlarged by a whole factor until it is.
pub const MIN_WIDTH: usize = 1280;
/// Most pixels a screenshot has (the factor stops below this).
pub const MAX_PIXELS: usize = 4096 * 4096;

/// The whole factor the view's `w × h` picture is rendered at for a
/// screenshot: the smallest that reaches [`MIN_WIDTH`], within
/// [`MAX_PIXELS`]; 1 for the plasma, a 2D effect drawn for the pixels of
/// the screen (its light is where the pointer is on them).
pub fn scale_for(scene: SceneKind, w: usize, h: usize) -> usize {
    if scene == SceneKind::Plasma || w == 0 || h == 0 {
        return 1;
    }
    let mut k = MIN_WIDTH.div_ceil(w).max(1);
    while k > 1 && (w * k) * (h * k) > MAX_PIXELS {
        k -= 1;
    }
    k
}

/// `relief-YYYY-MM-DDTHH-MM-SS.png` for `secs` seconds after the epoch
/// (UTC; `-` in the time: `:` is not allowed in every file system).
pub fn file_name(secs: u64) -> String {
    let days = (secs / 86_400) as i64;
    let rem = secs % 86_400;
    let (y, m, d) = civil_from_days(days);
    format!(
        "relief-{y:04}-{m:02}-{d:02}T{:02}-{:02}-{:02}.png",
        rem / 3600,
        rem / 60 % 60,
        rem % 60
    )
}

/// Year, month, day of the proleptic Gregorian calendar for a count of
/// days since 1970-01-01 (the well-known era arithmetic: 400-year eras of
/// 146 097 days, years starting in March so the leap day comes last).
fn civil_from_days(z: i64) -> (i64, u32, u32) {
    let z = z + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = (doy - (153 * mp + 2) / 5 + 1) as u32;
    let m = if mp < 10 { mp + 3 } else { mp - 9 } as u32;
    let y = yoe + era * 400 + i64::from(m <= 2);
    (y, m, d)
}

/// Renders the state's picture for a screenshot of the view's `w × h`
/// picture (see [`scale_for`]) and writes it in the current folder under
/// a new name (never over a file). The saved path and size, or the error.
pub fn save(
    state: &State,
    w: usize,
    h: usize,
    render: &mut impl FnMut(&State, &mut Framebuffer) -> FrameStats,
) -> Result<String, String> {
    let k = scale_for(state.scene, w, h);
    let (bw, bh) = (w * k, h * k);
    if bw == 0 || bh == 0 {
        return Err("no picture on this screen".into());
    }
    let _memory = relief_core::budget::reserve(
        &format!("a {bw}x{bh} screenshot"),
        relief_core::budget::frame_bytes_for(bw, bh, state.settings.aa),
    )
    .map_err(|e| e.to_string())?;
    let mut fb = Framebuffer::new(bw, bh);
    render(state, &mut fb);
    let secs = SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map(|d| d.as_secs())
        .unwrap_or(0);
    let base = file_name(secs);
    for n in 0..100 {
        let name = if n == 0 {
            base.clone()
        } else {
            base.replace(".png", &format!("-{n}.png"))
        };
        let path = std::path::Path::new(&name);
        if path.exists() {
            continue;
        }
        return fb
            .save_png(path)
            .map(|_| format!("{name} ({bw}x{bh})"))
            .map_err(|e| format!("{e:#}"));
    }
    Err("too many screenshots this second".into())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_utc_date_and_time() {
        assert_eq!(file_name(0), "relief-1970-01-01T00-00-00.png");
        // 2000-03-01 (after a leap day of a century divisible by 400):
        // 30 years × 365 + 7 leap days + 31 + 29 days.
        let days = 30 * 365 + 7 + 31 + 29;
        assert_eq!(file_name(days * 86_400), "relief-2000-03-01T00-00-00.png");
        // 2026-11-24 21:40:05: 56 years from 1970 with 14 leap days, then
        // January to October of 2026 (304 days) and 23 days.
        let days = 56 * 365 + 14 + 304 + 23;
        assert_eq!(
            file_name(days * 86_400 + 21 * 3600 + 40 * 60 + 5),
            "relief-2026-11-24T21-40-05.png"
        );
    }

    #[test]
    fn the_factor_reaches_the_width_within_the_pixels() {
        assert_eq!(scale_for(SceneKind::Cube, 160, 92), 8);
        assert_eq!(scale_for(SceneKind::Cube, 1280, 700), 1);
        assert_eq!(scale_for(SceneKind::Cube, 400, 200), 4);
        // 1000 columns: 2 reaches the width; a tall screen stays in the pixels.
        assert_eq!(scale_for(SceneKind::Cube, 1000, 3000), 2);
        assert_eq!(scale_for(SceneKind::Cube, 1000, 5000), 1);
        assert_eq!(scale_for(SceneKind::Plasma, 160, 92), 1);
    }
}
