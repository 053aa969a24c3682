//! How the bench writes its figures (milliseconds, decibels, kilobytes),
//! the same in the table, the runner's progress and the terminal rows.

use std::time::Duration;

/// Milliseconds with three significant digits (0.0412, 0.412, 4.12, 41.2, 412).
pub fn ms(d: Duration) -> String {
    let v = d.as_secs_f64() * 1e3;
    if v >= 100.0 {
        format!("{v:.0}")
    } else if v >= 10.0 {
        format!("{v:.1}")
    } else if v >= 1.0 {
        format!("{v:.2}")
    } else if v >= 0.1 {
        format!("{v:.3}")
    } else {
        format!("{v:.4}")
    }
}

/// PSNR in dB, `inf` for an exact match.
pub fn db(psnr: f64) -> String {
    if psnr.is_infinite() {
        "inf".into()
    } else {
        format!("{psnr:.2}")
    }
}

/// Kilobytes (1000 bytes) with one decimal.
pub fn kb(bytes: f64) -> String {
    format!("{:.1}", bytes / 1e3)
}
