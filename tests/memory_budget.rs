//! Tiny files that ask for huge memory stay under relief's memory budget:
//! each case runs the binary and reads its peak resident memory.

mod hostile;

use std::path::Path;

use relief::budget::BUDGET_BYTES;

fn mib(bytes: u64) -> u64 {
    bytes >> 20
}

/// Peak a 4096×4096 picture may reach now that texels are stored at their
/// source's precision (it was 520 to 800 MiB with f32 texels).
const PRECISION_PEAK: u64 = 300 << 20;

/// Runs the case, prints its peak, checks it against the budget; returns
/// the exit code and stderr.
fn case(name: &str, args: &[&str]) -> (Option<i32>, String) {
    let (code, err, _) = case_peak(name, args);
    (code, err)
}

/// [`case`] with the peak.
fn case_peak(name: &str, args: &[&str]) -> (Option<i32>, String, u64) {
    let (code, err, peak) = hostile::relief_peak(args);
    println!(
        "{name}: peak {} MiB (budget {} MiB), exit {code:?}: {}",
        mib(peak),
        mib(BUDGET_BYTES),
        err.trim()
    );
    assert!(peak < BUDGET_BYTES, "{name}: {} MiB", mib(peak));
    assert!(code.is_some(), "{name}: killed by a signal: {err}");
    (code, err, peak)
}

fn write_png(path: &Path, w: u32, h: u32) {
    let img = image::RgbaImage::from_fn(w, h, |x, y| {
        image::Rgba([(x % 256) as u8, (y % 256) as u8, 128, ((x ^ y) % 256) as u8])
    });
    img.save(path).unwrap();
}

#[test]
fn bad_inputs_stay_under_the_budget() {
    let dir = hostile::scratch("budget");
    let p = |n: &str| dir.join(n).to_str().unwrap().to_owned();
    let out = p("out.png");

    // A 1×16384 height map onto a 16384×1 picture.
    std::fs::write(p("tall.png"), hostile::grey_png(1, 16_384, 90)).unwrap();
    std::fs::write(p("wide.png"), hostile::grey_png(16_384, 1, 200)).unwrap();
    let (code, err) = case(
        "height map 1x16384 onto 16384x1",
        &[
            "render",
            "--out",
            &out,
            "--height-map",
            &p("tall.png"),
            &p("wide.png"),
        ],
    );
    assert_eq!(code, Some(0), "{err}");

    // A 4096×4096 PNG (small on disk), dot3 and anisotropic filtering.
    write_png(Path::new(&p("big.png")), 4096, 4096);
    let (code, err, peak) = case_peak(
        "4096x4096 PNG, dot3 + anisotropic",
        &[
            "render",
            "--out",
            &out,
            "--technique",
            "dot3",
            "--filter",
            "anisotropic",
            "--all-faces",
            &p("big.png"),
        ],
    );
    assert_eq!(code, Some(0), "{err}");
    assert!(peak <= PRECISION_PEAK, "{} MiB", mib(peak));

    // The same picture as a normal map, a 16-bit picture and a one-colour
    // WebP of a few hundred bytes as a specular map.
    let (code, err, peak) = case_peak(
        "4096x4096 PNG as --normal-map",
        &[
            "render",
            "--out",
            &out,
            "--technique",
            "dot3",
            "--normal-map",
            &p("big.png"),
        ],
    );
    assert_eq!(code, Some(0), "{err}");
    assert!(peak <= PRECISION_PEAK, "{} MiB", mib(peak));
    image::ImageBuffer::<image::Rgb<u16>, _>::from_fn(4096, 4096, |x, y| {
        image::Rgb([(x * 16) as u16, (y * 16) as u16, 4321])
    })
    .save(p("big16.png"))
    .unwrap();
    let (code, err, peak) = case_peak(
        "4096x4096 16-bit PNG",
        &["render", "--out", &out, &p("big16.png")],
    );
    assert_eq!(code, Some(0), "{err}");
    assert!(peak <= PRECISION_PEAK, "{} MiB", mib(peak));
    let grey = image::RgbImage::from_pixel(4096, 4096, image::Rgb([128, 128, 128]));
    let webp = std::fs::File::create(p("spec.webp")).unwrap();
    image::codecs::webp::WebPEncoder::new_lossless(webp)
        .encode(grey.as_raw(), 4096, 4096, image::ExtendedColorType::Rgb8)
        .unwrap();
    let (code, err, peak) = case_peak(
        "4096x4096 WebP as --specular-map",
        &["render", "--out", &out, "--specular-map", &p("spec.webp")],
    );
    assert_eq!(code, Some(0), "{err}");
    assert!(peak <= PRECISION_PEAK, "{} MiB", mib(peak));

    // A float picture of the same size.
    let hdr = std::fs::File::create(p("big.hdr")).unwrap();
    let pixels = vec![image::Rgb([0.5f32, 0.25, 1.0]); 4096 * 4096];
    image::codecs::hdr::HdrEncoder::new(std::io::BufWriter::new(hdr))
        .encode(&pixels, 4096, 4096)
        .unwrap();
    drop(pixels);
    let (code, err) = case(
        "4096x4096 HDR, dot3 + anisotropic",
        &[
            "render",
            "--out",
            &out,
            "--technique",
            "dot3",
            "--filter",
            "anisotropic",
            &p("big.hdr"),
        ],
    );
    assert!(code == Some(0) || err.contains("memory budget"), "{err}");

    // The largest frame, as text and as a picture.
    for extra in [&["--ansi"][..], &["--out", &out]] {
        let mut args = vec!["render", "--width", "16384", "--height", "16384"];
        args.extend_from_slice(extra);
        let (code, err) = case(&format!("16384x16384 {}", extra[0]), &args);
        assert!(code == Some(0) || err.contains("memory budget"), "{err}");
    }

    // A polygon of 999,999 corners, and one corner repeated 999,999 times:
    // refused on their line before any triangle is made.
    let mut poly = String::new();
    for i in 0..999_999 {
        let a = i as f32 * 1e-5;
        poly += &format!("v {} {} 0\n", a.cos(), a.sin());
    }
    let corners: Vec<String> = (1..=999_999).map(|i| i.to_string()).collect();
    let repeated = format!("{poly}f {}\n", "1 ".repeat(999_999));
    poly += &format!("f {}\n", corners.join(" "));
    std::fs::write(p("polygon.obj"), poly).unwrap();
    std::fs::write(p("repeated.obj"), repeated).unwrap();
    for model in ["polygon.obj", "repeated.obj"] {
        let (code, err) = case(
            &format!("OBJ {model}"),
            &["render", "--out", &out, "--model", &p(model)],
        );
        assert_eq!(code, Some(1), "{err}");
        assert!(
            err.contains("line 1000000: a face of 999999 corners"),
            "{err}"
        );
    }
    let _ = std::fs::remove_dir_all(dir);
}
