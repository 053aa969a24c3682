//! `relief bench --quick` end to end, through the library (the binary's code
//! path minus argument parsing), on a tiny frame so it stays fast.

use relief_bench::BenchArgs;

#[test]
fn quick_bench_writes_table_csv_and_plot() {
    let dir = crate::common::scratch::scratch_dir("bench-test");
    let csv = dir.join("bench.csv");
    let plot = dir.join("bench.png");
    let args = BenchArgs {
        size: Some((40, 30)),
        quick: true,
        csv: Some(csv.clone()),
        markdown: true,
        plot: Some(plot.clone()),
        threads: Some(2),
        anchors: false,
        model: None,
        picture: None,
        pbr: None,
        environment_map: None,
        modes: false,
        physical: false,
    };
    let (mut out, mut log) = (Vec::new(), Vec::new());
    let report = relief_bench::run(&args, &mut out, &mut log).unwrap();
    let out = String::from_utf8(out).unwrap();

    // One measured row per configuration of the quick list.
    let configs = relief_bench::config::quick();
    assert_eq!(report.rows.len(), configs.len());
    for (row, config) in report.rows.iter().zip(&configs) {
        assert_eq!(&row.config, config);
        assert!(
            row.frames >= 4,
            "{} timed {} frames",
            config.name,
            row.frames
        );
        assert!(row.p10 <= row.median && row.median <= row.p90);
        assert!(!row.psnr.is_nan() && row.psnr > 0.0);
        assert!(row.ssim > -1.0 && row.ssim <= 1.0 + 1e-9);
        assert!(row.pixels_per_frame > 0.0, "{} shaded nothing", config.name);
        // The turned cube changes cells, which costs more than the frame's
        // synchronized-output marks (16 bytes); 256 colours cost no more.
        assert!(
            row.bytes_truecolor > 20.0 && row.bytes_256 > 20.0,
            "{}",
            config.name
        );
        assert!(row.bytes_256 <= row.bytes_truecolor, "{}", config.name);
    }
    assert_eq!(report.rows[1].threads, 1);
    assert_eq!(report.rows[0].threads, 2);
    // Rendering is identical for any thread count, so the error is too.
    assert_eq!(report.rows[0].psnr, report.rows[1].psnr);
    assert_eq!(report.rows[0].max_error, report.rows[1].max_error);
    // The reference setting is closer to the reference than flat, untextured, bare.
    let flat = report
        .rows
        .iter()
        .find(|r| r.config.name.starts_with("flat"))
        .unwrap();
    assert!(report.rows[0].psnr > flat.psnr);

    // Markdown table: header row, alignment row, a row per configuration.
    let table: Vec<&str> = out.lines().filter(|l| l.starts_with('|')).collect();
    assert_eq!(table.len(), 2 + configs.len());
    assert!(out.contains("40x30"));
    assert!(out.contains("texture: "));

    let csv_text = std::fs::read_to_string(&csv).unwrap();
    assert_eq!(csv_text.lines().count(), 1 + configs.len());

    let image = relief_texture::picture::open(&plot).unwrap();
    assert!(image.width() > 400 && image.height() > 300);

    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn unwritable_outputs_are_errors_not_panics() {
    let args = BenchArgs {
        size: Some((16, 12)),
        quick: true,
        csv: Some(std::path::PathBuf::from(
            "/nonexistent-dir/relief/bench.csv",
        )),
        ..Default::default()
    };
    let err = relief_bench::run(&args, &mut Vec::new(), &mut Vec::new()).unwrap_err();
    assert!(format!("{err:#}").contains("bench.csv"));
}

#[test]
fn quick_anchors_bench_prints_every_variant_and_thread_count() {
    let args = BenchArgs {
        quick: true,
        anchors: true,
        threads: Some(2),
        ..Default::default()
    };
    let (mut out, mut log) = (Vec::new(), Vec::new());
    relief_bench::run(&args, &mut out, &mut log).unwrap();
    let out = String::from_utf8(out).unwrap();
    for variant in ["flat", "gouraud", "phong"] {
        for threads in [1, 2] {
            let key = format!("variant={variant:<7} size=64x48 threads={threads} ");
            assert!(out.contains(&key), "{key} missing in\n{out}");
        }
    }
}

/// A directory of this test's own (`tag`) holding `sphere.ply`, a UV
/// sphere of 8 rings and 16 segments: the directory and the file's path.
fn sphere_file(tag: &str) -> (std::path::PathBuf, std::path::PathBuf) {
    let dir = crate::common::scratch::scratch_dir(&format!("bench-{tag}"));
    let path = dir.join("sphere.ply");
    let ply = relief_bench::mesh_anchor::uv_sphere_ply(8, 16, 1.0, glam::Vec3::ZERO);
    std::fs::write(&path, ply).unwrap();
    (dir, path)
}

#[test]
fn quick_model_anchors_bench_times_the_file_on_each_thread_count() {
    let (dir, path) = sphere_file("model");
    let args = BenchArgs {
        quick: true,
        anchors: true,
        model: Some(path.clone()),
        picture: Some(dir.join("view.png")),
        threads: Some(2),
        ..Default::default()
    };
    let (mut out, mut log) = (Vec::new(), Vec::new());
    relief_bench::run(&args, &mut out, &mut log).unwrap();
    let picture = relief_texture::picture::open(dir.join("view.png")).unwrap();
    assert_eq!((picture.width(), picture.height()), (320, 240));
    let _ = std::fs::remove_dir_all(&dir);
    let out = String::from_utf8(out).unwrap();
    // 2 · 16 · 7 triangles, a closed surface.
    assert!(out.contains("224 triangles, closed"), "{out}");
    for threads in [1, 2] {
        let key = format!("variant=mesh    size=64x48 threads={threads} ");
        let line = out
            .lines()
            .find(|l| l.starts_with(&key))
            .unwrap_or_else(|| panic!("{key} missing in\n{out}"));
        assert!(!line.contains("covered_px=0 "), "{line}");
    }
}

/// `--pbr` times the same file shaded physically (rows `pbr`), with the
/// built-in studio when no environment map is given.
#[test]
fn quick_pbr_model_anchors_bench_times_the_physical_view() {
    let (dir, path) = sphere_file("pbr");
    let args = BenchArgs {
        quick: true,
        anchors: true,
        model: Some(path.clone()),
        pbr: Some(relief_bench::pbr_anchor::Look::Dielectric),
        threads: Some(1),
        ..Default::default()
    };
    let (mut out, mut log) = (Vec::new(), Vec::new());
    relief_bench::run(&args, &mut out, &mut log).unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    let out = String::from_utf8(out).unwrap();
    assert!(out.contains("metallic 0, roughness 0.5"), "{out}");
    assert!(out.contains("the built-in studio"), "{out}");
    let line = out
        .lines()
        .find(|l| l.starts_with("variant=pbr     size=64x48 threads=1 "))
        .unwrap_or_else(|| panic!("no pbr row in\n{out}"));
    assert!(!line.contains("covered_px=0 "), "{line}");
}

#[test]
fn pbr_needs_a_model_and_its_environment_map_needs_pbr() {
    use clap::Parser;
    let parse = |args: &[&str]| relief::cli::Cli::try_parse_from(args).is_ok();
    let model = ["relief", "bench", "--anchors", "--model", "x.ply"];
    assert!(!parse(&["relief", "bench", "--anchors", "--pbr"]));
    assert!(!parse(
        &[&model[..], &["--environment-map", "e.hdr"]].concat()
    ));
    assert!(parse(&[&model[..], &["--pbr"]].concat()));
    assert!(parse(
        &[&model[..], &["--pbr", "--environment-map", "e.hdr"]].concat()
    ));
    assert!(parse(&[&model[..], &["--pbr", "dielectric"]].concat()));
    assert!(!parse(&[&model[..], &["--pbr", "chrome"]].concat()));
}

#[test]
fn model_needs_anchors() {
    use clap::Parser;
    let parsed = relief::cli::Cli::try_parse_from(["relief", "bench", "--model", "x.ply"]);
    assert!(parsed.is_err());
    assert!(
        relief::cli::Cli::try_parse_from(["relief", "bench", "--anchors", "--model", "x.ply"])
            .is_ok()
    );
}

/// `relief bench --physical --quick`: the physical rows on a tiny frame,
/// each against the physical truth (the environment integrated by Monte
/// Carlo), which the renderer's metallic-roughness frame comes close to.
#[test]
fn quick_physical_bench_measures_against_the_physical_truth() {
    let args = BenchArgs {
        size: Some((40, 30)),
        quick: true,
        physical: true,
        threads: Some(2),
        ..Default::default()
    };
    let (mut out, mut log) = (Vec::new(), Vec::new());
    let report = relief_bench::run(&args, &mut out, &mut log).unwrap();
    let out = String::from_utf8(out).unwrap();
    let configs = relief_bench::physical::quick_rows();
    assert_eq!(report.rows.len(), configs.len());
    for (row, config) in report.rows.iter().zip(&configs) {
        assert_eq!(&row.config, config);
        assert!(
            row.truth.starts_with("physical, studio environment"),
            "{}",
            row.truth
        );
        assert!(
            row.psnr > 20.0 && row.psnr.is_finite(),
            "{}: {}",
            config.name,
            row.psnr
        );
        assert!(row.pixels_per_frame > 0.0, "{} shaded nothing", config.name);
    }
    assert!(out.contains("metallic-roughness sphere"), "{out}");
    assert!(out.contains("Monte Carlo"), "{out}");
}
