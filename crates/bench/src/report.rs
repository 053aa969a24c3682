//! The table of a run as aligned text, Markdown and CSV.

use std::fmt::Write as _;
use std::time::Duration;

use super::config::value_name;
use super::figures::{db, kb, ms};
use super::pareto;
use super::runner::Row;

/// A finished run: what was measured (header lines) and the rows.
#[derive(Clone, Debug)]
pub struct Report {
    pub header: Vec<String>,
    pub rows: Vec<Row>,
}

impl Report {
    /// Which rows are on the Pareto front of (median time, PSNR).
    pub fn front(&self) -> Vec<bool> {
        let points: Vec<(f64, f64)> = self
            .rows
            .iter()
            .map(|r| (r.median.as_secs_f64(), r.psnr))
            .collect();
        let mut on = vec![false; points.len()];
        for i in pareto::front(&points) {
            on[i] = true;
        }
        on
    }
}

const HEADINGS: [&str; 16] = [
    "#",
    "configuration",
    "threads",
    "ms/frame",
    "p10–p90 ms",
    "Mpx/s",
    "PSNR dB",
    "max err",
    "SSIM",
    "truth",
    "truth dB",
    "self PSNR",
    "self max",
    "KB 24-bit",
    "KB 256",
    "front",
];

/// The columns of text (left-aligned); the others are numbers.
const TEXT_COLUMNS: [usize; 2] = [1, 9];

/// The cells of one row, in `HEADINGS` order.
fn cells(index: usize, row: &Row, on_front: bool) -> Vec<String> {
    vec![
        (index + 1).to_string(),
        row.config.name.clone(),
        row.threads.to_string(),
        ms(row.median),
        format!("{}–{}", ms(row.p10), ms(row.p90)),
        format!("{:.1}", row.pixels_per_second() / 1e6),
        db(row.psnr),
        row.max_error.to_string(),
        format!("{:.4}", row.ssim),
        row.truth.clone(),
        db(row.truth_psnr),
        db(row.self_psnr),
        row.self_max_error.to_string(),
        kb(row.bytes_truecolor),
        kb(row.bytes_256),
        if on_front { "*".into() } else { String::new() },
    ]
}

fn all_cells(report: &Report) -> Vec<Vec<String>> {
    let front = report.front();
    report
        .rows
        .iter()
        .enumerate()
        .map(|(i, r)| cells(i, r, front[i]))
        .collect()
}

/// Header lines, then a table with columns aligned (text left, numbers right).
pub fn text(report: &Report) -> String {
    let rows = all_cells(report);
    let mut widths: Vec<usize> = HEADINGS.iter().map(|h| h.chars().count()).collect();
    for row in &rows {
        for (w, c) in widths.iter_mut().zip(row) {
            *w = (*w).max(c.chars().count());
        }
    }
    let mut out = String::new();
    for line in &report.header {
        let _ = writeln!(out, "{line}");
    }
    out.push('\n');
    let line = |cells: &[String]| -> String {
        let mut s = String::new();
        for (i, (c, w)) in cells.iter().zip(&widths).enumerate() {
            let pad = w - c.chars().count();
            if i > 0 {
                s.push_str("  ");
            }
            if TEXT_COLUMNS.contains(&i) {
                s.push_str(c);
                s.push_str(&" ".repeat(pad));
            } else {
                s.push_str(&" ".repeat(pad));
                s.push_str(c);
            }
        }
        s.trim_end().to_string()
    };
    let headings: Vec<String> = HEADINGS.iter().map(|h| h.to_string()).collect();
    let _ = writeln!(out, "{}", line(&headings));
    for row in &rows {
        let _ = writeln!(out, "{}", line(row));
    }
    for note in one_pixel_notes(report) {
        let _ = writeln!(out, "{note}");
    }
    out
}

/// Footnotes naming the rows shaded one pixel at a time, grouped by reason
/// (the others shade eight pixels of a row at once).
pub fn one_pixel_notes(report: &Report) -> Vec<String> {
    let mut reasons: Vec<(&str, Vec<String>)> = Vec::new();
    for (i, row) in report.rows.iter().enumerate() {
        if let Some(reason) = row.one_pixel {
            match reasons.iter_mut().find(|(r, _)| *r == reason) {
                Some((_, rows)) => rows.push((i + 1).to_string()),
                None => reasons.push((reason, vec![(i + 1).to_string()])),
            }
        }
    }
    if reasons.is_empty() {
        return Vec::new();
    }
    let mut notes = vec![
        String::new(),
        "Shaded one pixel at a time (every other row shades eight pixels of a row at once):"
            .to_string(),
    ];
    for (reason, rows) in reasons {
        let label = if rows.len() == 1 { "row" } else { "rows" };
        notes.push(format!("- {label} {}: {reason}", rows.join(", ")));
    }
    notes
}

/// Header lines as a paragraph, then a Markdown table (numbers right-aligned).
pub fn markdown(report: &Report) -> String {
    let mut out = String::new();
    for line in &report.header {
        let _ = writeln!(out, "{line}  ");
    }
    out.push('\n');
    let _ = writeln!(out, "| {} |", HEADINGS.join(" | "));
    let align: Vec<&str> = (0..HEADINGS.len())
        .map(|i| {
            if TEXT_COLUMNS.contains(&i) {
                ":--"
            } else {
                "--:"
            }
        })
        .collect();
    let _ = writeln!(out, "|{}|", align.join("|"));
    for row in all_cells(report) {
        let escaped: Vec<String> = row.iter().map(|c| c.replace('|', "\\|")).collect();
        let _ = writeln!(out, "| {} |", escaped.join(" | "));
    }
    for note in one_pixel_notes(report) {
        let _ = writeln!(out, "{note}");
    }
    out
}

/// One CSV field, quoted when it holds a comma, quote or line break.
fn field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// Every row with its full settings and unrounded figures.
pub fn csv(report: &Report) -> String {
    let mut out = String::from(
        "index,configuration,threads,shading,normals,texture,filter,bump,technique,\
         height_derivative,light_vector,aa,specular,tone_map,scene,frames,median_ms,p10_ms,p90_ms,\
         pixels_per_frame,pixels_per_second,psnr_db,max_error,ssim,truth,truth_psnr_db,self_psnr_db,self_max_error,bytes_truecolor,bytes_256,plan_ms,raster_ms,pareto\n",
    );
    let front = report.front();
    for (i, r) in report.rows.iter().enumerate() {
        let s = &r.config.settings;
        let msf = |d: Duration| format!("{:.6}", d.as_secs_f64() * 1e3);
        let fields = [
            (i + 1).to_string(),
            field(&r.config.name),
            r.threads.to_string(),
            value_name(s.shading),
            value_name(s.normals),
            s.texture.to_string(),
            value_name(s.filter),
            s.bump.to_string(),
            value_name(s.technique),
            value_name(s.height_derivative),
            value_name(s.light_vector),
            value_name(s.aa),
            s.specular.to_string(),
            value_name(s.tone_map),
            r.config.variant.label().to_string(),
            r.frames.to_string(),
            msf(r.median),
            msf(r.p10),
            msf(r.p90),
            format!("{:.1}", r.pixels_per_frame),
            format!("{:.0}", r.pixels_per_second()),
            if r.psnr.is_infinite() {
                "inf".into()
            } else {
                format!("{:.4}", r.psnr)
            },
            r.max_error.to_string(),
            format!("{:.6}", r.ssim),
            field(&r.truth),
            if r.truth_psnr.is_infinite() {
                "inf".into()
            } else {
                format!("{:.4}", r.truth_psnr)
            },
            if r.self_psnr.is_infinite() {
                "inf".into()
            } else {
                format!("{:.4}", r.self_psnr)
            },
            r.self_max_error.to_string(),
            format!("{:.0}", r.bytes_truecolor),
            format!("{:.0}", r.bytes_256),
            msf(r.plan_time),
            msf(r.raster_time),
            front[i].to_string(),
        ];
        let _ = writeln!(out, "{}", fields.join(","));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config;

    fn row(name: &str, median_ms: f64, psnr: f64) -> Row {
        let d = Duration::from_secs_f64(median_ms / 1e3);
        Row {
            config: config::Config {
                name: name.into(),
                ..config::quick()[0].clone()
            },
            threads: 2,
            frames: 10,
            median: d,
            p10: d,
            p90: d,
            pixels_per_frame: 1000.0,
            psnr,
            max_error: 9,
            self_psnr: psnr,
            self_max_error: 9,
            truth: "Blinn".into(),
            truth_psnr: 60.0,
            ssim: 0.99,
            bytes_truecolor: 41_234.0,
            bytes_256: 20_000.0,
            plan_time: Duration::ZERO,
            one_pixel: None,
            raster_time: d,
        }
    }

    fn report() -> Report {
        Report {
            header: vec!["relief bench".into()],
            rows: vec![
                row("fast, rough", 0.5, 30.0),
                row("slow", 5.0, 25.0),
                row("exact", 50.0, f64::INFINITY),
            ],
        }
    }

    #[test]
    fn rows_shaded_one_pixel_at_a_time_are_noted_by_reason() {
        let mut r = report();
        assert!(one_pixel_notes(&r).is_empty());
        assert!(!markdown(&r).contains("one pixel at a time"));
        r.rows[0].one_pixel = Some("mip filters");
        r.rows[2].one_pixel = Some("mip filters");
        r.rows[1].one_pixel = Some("MSAA");
        let notes = one_pixel_notes(&r);
        assert!(notes.contains(&"- rows 1, 3: mip filters".to_string()));
        assert!(notes.contains(&"- row 2: MSAA".to_string()));
        assert!(text(&r).contains("- rows 1, 3: mip filters"));
        assert!(markdown(&r).contains("- row 2: MSAA"));
    }

    /// The reasons follow the plan: the reference setting shades in packets,
    /// each setting that leaves them says why.
    #[test]
    fn one_pixel_reasons_follow_the_settings() {
        use clap::ValueEnum;
        use relief_core::settings::{AntiAlias, Filter, Settings, Technique};
        use relief_pipeline::plan::Plan;
        use relief_pipeline::shade::kernels::one_pixel_reason;
        let scene = relief_scene::Scene::cube(
            std::sync::Arc::new(relief_texture::decode::procedural::brick()),
            true,
        );
        let reason = |s: Settings| one_pixel_reason(&Plan::new(&scene, &s));
        assert_eq!(reason(Settings::default()), None);
        for &filter in Filter::value_variants() {
            let s = Settings {
                filter,
                ..Settings::default()
            };
            assert_eq!(reason(s), None, "{s:?}");
        }
        // Every technique shades eight pixels at a time.
        for &technique in Technique::value_variants() {
            let s = Settings {
                technique,
                ..Settings::default()
            };
            assert_eq!(reason(s), None, "{s:?}");
        }
        let msaa = Settings {
            aa: AntiAlias::Msaa4,
            ..Settings::default()
        };
        assert!(reason(msaa).is_some());
        assert_eq!(
            reason(Settings {
                aa: AntiAlias::Ssaa2,
                ..Settings::default()
            }),
            None
        );
    }

    #[test]
    fn formats() {
        assert_eq!(ms(Duration::from_micros(41)), "0.0410");
        assert_eq!(ms(Duration::from_micros(412)), "0.412");
        assert_eq!(ms(Duration::from_micros(41_234)), "41.2");
        assert_eq!(db(f64::INFINITY), "inf");
        assert_eq!(db(31.256), "31.26");
        assert_eq!(kb(41_260.0), "41.3");
        assert_eq!(field("a,b"), "\"a,b\"");
        assert_eq!(field("say \"x\""), "\"say \"\"x\"\"\"");
    }

    #[test]
    fn tables_have_a_line_per_row_and_mark_the_front() {
        let r = report();
        assert_eq!(r.front(), vec![true, false, true]);
        let t = text(&r);
        assert!(t.starts_with("relief bench\n"));
        let lines: Vec<&str> = t.lines().collect();
        assert_eq!(lines.len(), 1 + 1 + 1 + 3);
        assert!(lines[3].contains("fast, rough") && lines[3].ends_with('*'));
        assert!(lines[5].contains("inf"));
        // Columns line up: every table line has the same width up to the front column.
        let md = markdown(&r);
        let table: Vec<&str> = md.lines().filter(|l| l.starts_with('|')).collect();
        assert_eq!(table.len(), 2 + 3);
        assert!(
            table
                .iter()
                .all(|l| l.matches('|').count() == HEADINGS.len() + 1)
        );
    }

    #[test]
    fn csv_has_a_header_and_a_record_per_row() {
        let c = csv(&report());
        let lines: Vec<&str> = c.lines().collect();
        assert_eq!(lines.len(), 4);
        let columns = lines[0].split(',').count();
        assert_eq!(columns, 33);
        assert!(lines[1].starts_with("1,\"fast, rough\",2,phong,vertex,true,bilinear,true,blinn,"));
        assert!(lines[3].contains(",inf,"));
        assert!(lines[1].ends_with(",true") && lines[2].ends_with(",false"));
    }
}
