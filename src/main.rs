//! `relief`: the interactive view, `relief render` and `relief bench`.

use std::io::Write;
use std::process::ExitCode;
use std::sync::Arc;

use anyhow::Context;
use clap::Parser;

use relief::cli::{Cli, Command, RenderArgs};
use relief::sanitize::clean;
use relief::scene::{Built, build_scene_noting};
use relief::texture::environment::Environment;
use relief::{Framebuffer, Renderer};

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => return parse_failure(&e),
    };
    let result = match cli.command {
        Some(Command::Render(args)) => render(&args),
        Some(Command::Assets { dir }) => write_assets(&dir),
        Some(Command::Bench(args)) => {
            relief::bench::run(&args, &mut std::io::stdout().lock(), &mut std::io::stderr())
                .map(|_| ())
        }
        None if cli.symbols_test => symbols_test(),
        None => relief::app::run(cli),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) => {
            eprintln!("relief: {}", clean(&format!("{err:#}")));
            ExitCode::FAILURE
        }
    }
}

/// The parser's message (usage errors, `--help`, `--version`) with the
/// user's arguments made safe to print, and the parser's exit code: it
/// quotes arguments as they were typed, escape sequences included.
fn parse_failure(e: &clap::Error) -> ExitCode {
    let text = relief::sanitize::clean_lines(&e.render().to_string());
    if e.use_stderr() {
        let _ = std::io::stderr().write_all(text.as_bytes());
    } else {
        let mut out = std::io::stdout().lock();
        let _ = out.write_all(text.as_bytes());
        let _ = out.flush();
    }
    ExitCode::from(e.exit_code().clamp(0, 255) as u8)
}

/// `relief --symbols-test`: every glyph of each set on a line of its own.
fn symbols_test() -> anyhow::Result<()> {
    let mut out = std::io::stdout().lock();
    for symbols in relief::term::Symbols::ALL {
        writeln!(out, "{}", relief::term::symbols::test_line(symbols))?;
    }
    Ok(())
}

/// `relief render`: one frame, to a PNG or to stdout as half-block text.
fn render(args: &RenderArgs) -> anyhow::Result<()> {
    for note in check_render_flags(args)? {
        eprintln!("relief: {}", clean(&note));
    }
    // A positional model file is the model; an image is the texture.
    let mut view = args.view.clone();
    let mut image = args.image.clone().into_iter().collect();
    relief::cli::models_from_positional(&mut image, &mut view.model);
    // Errors name the file and are already free of control characters.
    let texture = relief::texture::load::load_for_view(
        image.first().map(|p| p.as_path()),
        args.view.height_map.as_deref(),
    )?;
    let view = &view;
    let specular_map = match &view.specular_map {
        Some(path) => Some(Arc::new(relief::texture::specular_map::load_specular_map(
            path,
        )?)),
        None => None,
    };
    let normal_map = match &view.normal_map {
        Some(path) => Some(Arc::new(relief::texture::normal_map_file::load_normal_map(
            path,
        )?)),
        None => None,
    };
    let environment = Environment::load_optional(view.environment_map.as_deref())?;
    let (built, notes) =
        build_scene_noting(view.scene, &view.model, Arc::new(texture), view.all_faces)?;
    for warning in &notes.warnings {
        eprintln!("relief: warning: {}", clean(warning));
    }
    let mut settings = view.settings();
    if notes.points && settings.display == relief::settings::Display::Fill {
        eprintln!("relief: the model is a point cloud: drawn as points");
        settings.display = relief::settings::Display::Points;
    }
    let (width, height) = (args.width as usize, args.height as usize);
    // The frame's memory is reserved before any of it exists.
    let _frame = relief::budget::reserve(
        &format!("a {width}x{height} frame"),
        relief::budget::frame_bytes_for(width, height, settings.aa),
    )?;
    let mut fb = Framebuffer::new(width, height);
    match built {
        Built::Scene(mut scene) => {
            scene.camera = scene.camera.at_distance(view.distance);
            scene.camera.fov_y_degrees = settings.fov;
            // The flags' maps win over the model's own (MTL map_Ks, norm).
            if specular_map.is_some() {
                scene.material.specular_map = specular_map;
            }
            if normal_map.is_some() {
                scene.material.normal_map = normal_map;
            }
            scene.material.environment = environment;
            let mut renderer = Renderer::new();
            if args.ansi && !args.format.is_pixels() {
                // The text's pixels are as tall as its symbols make them.
                renderer.set_pixel_aspect(args.symbols.pixel_aspect());
            }
            renderer.render(&scene, &settings, &mut fb);
        }
        Built::Plasma(plasma) => {
            let centre = (fb.width() as f32 / 2.0, fb.height() as f32 / 2.0);
            let light = args.light.map_or(centre, |p| (p.x, p.y));
            plasma.render(light, view.plasma_normal, &mut fb);
        }
    }
    let depth = relief::app::color_depth(Some(args.color));
    let pad = relief::scene::BACKGROUND;
    if args.ansi {
        let mut out = std::io::BufWriter::new(std::io::stdout().lock());
        relief::term::format::write_frame(
            &fb,
            args.format,
            args.symbols,
            depth,
            args.dither,
            pad,
            &mut out,
        )?;
        out.flush()?;
        return Ok(());
    }
    let out = args.out.as_ref().context("--out FILE.png is required")?;
    let format = output_format(out)?;
    let out = &out_target(out)?;
    if depth == relief::term::ColorDepth::Truecolor && args.symbols == relief::term::Symbols::Half {
        write_picture(&fb, out, format)
    } else {
        // The picture a terminal with that depth shows: its cells first.
        let (w, h) = args.symbols.cells_for_pixels(fb.width(), fb.height());
        let _cells = relief::budget::reserve(
            &format!(
                "the {w}x{h} cells of a {}x{} frame",
                fb.width(),
                fb.height()
            ),
            (w * h * std::mem::size_of::<ratatui::buffer::Cell>()
                + fb.width() * fb.height() * relief::budget::FRAME_BYTES_PER_PIXEL as usize)
                as u64,
        )?;
        let cells = relief::term::ansi::symbol_cells(&fb, args.symbols, depth, args.dither, pad);
        let shown =
            relief::term::cells::shown_picture(&cells, args.symbols, fb.width(), fb.height(), pad);
        drop(cells);
        write_picture(&shown, out, format)
    }
}

/// Things `render` was asked for that it cannot do, said on stderr before
/// it does the rest; and what makes it stop before rendering.
fn check_render_flags(args: &RenderArgs) -> anyhow::Result<Vec<String>> {
    use relief::scene::{ModelChoice, SceneKind};
    let mut notes = Vec::new();
    let view = &args.view;
    let settings = view.settings();
    if view.scene != SceneKind::Cube && view.model != ModelChoice::Cube {
        notes.push(format!(
            "--model {} is ignored: only --scene cube draws a chosen model (the {} scene has its own)",
            clean(&view.model.to_string()),
            if view.scene == SceneKind::Plasma { "plasma" } else { "shadow" },
        ));
    }
    if view.normal_map.is_some() && !relief::plan::normal_map_file_shows(&settings, true) {
        notes.push(
            "--normal-map shows with --technique dot3 (the other techniques read the height map)"
                .into(),
        );
    }
    let (w, h) = (args.width as usize, args.height as usize);
    let k = relief::raster::aa::ssaa_factor(settings.aa, w, h);
    let wanted = match settings.aa {
        relief::settings::AntiAlias::Ssaa2 => 2,
        relief::settings::AntiAlias::Ssaa4 => 4,
        _ => 1,
    };
    if k < wanted {
        let now = if k == 1 {
            "off".to_string()
        } else {
            format!("{k}x{k}")
        };
        notes.push(format!(
            "--aa {wanted}x{wanted} falls back to {now} at {w}x{h}: the supersampled frame would exceed {} samples",
            relief::raster::aa::MAX_SUPERSAMPLES
        ));
    }
    if let Some(out) = &args.out {
        // Checked before rendering, so a refusal costs nothing.
        out_target(out)?;
    }
    Ok(notes)
}

/// Where `--out` writes.
#[derive(Debug)]
enum OutTarget {
    /// `--out -`: the picture goes to standard output.
    Stdout,
    /// This file: the one a symbolic link (or a chain of them) names, so
    /// the link stays and the file it points at is written.
    File(std::path::PathBuf),
}

/// Links followed before `--out` gives up (as the kernel's own limit).
const MAX_LINKS: usize = 40;

/// What `--out` names, checked: `-` is standard output (refused when it is
/// a terminal); a link is followed to its file; an existing file must be a
/// regular file the user may write (a read-only file is refused, not
/// replaced behind the user's back).
fn out_target(out: &std::path::Path) -> anyhow::Result<OutTarget> {
    use std::io::IsTerminal;
    let shown = relief::sanitize::display_path(out);
    if out.as_os_str() == "-" {
        if std::io::stdout().is_terminal() {
            anyhow::bail!(
                "--out - writes the picture to standard output, which is a terminal here: redirect it (--out - > frame.png) or use --ansi"
            );
        }
        return Ok(OutTarget::Stdout);
    }
    output_format(out)?;
    let mut target = out.to_path_buf();
    for _ in 0..=MAX_LINKS {
        let Ok(link) = std::fs::read_link(&target) else {
            break;
        };
        target = match target.parent() {
            Some(dir) if link.is_relative() => dir.join(link),
            _ => link,
        };
    }
    if std::fs::symlink_metadata(&target).is_ok_and(|m| m.file_type().is_symlink()) {
        anyhow::bail!("cannot write {shown}: too many levels of symbolic links");
    }
    // The target's own extension decides nothing: the user named `out`.
    if let Ok(meta) = std::fs::metadata(&target) {
        if !meta.is_file() {
            anyhow::bail!(
                "cannot write {shown}: not a regular file (only a new or regular file is replaced)"
            );
        }
        let mode = std::os::unix::fs::PermissionsExt::mode(&meta.permissions()) & 0o7777;
        if meta.permissions().readonly() {
            anyhow::bail!(
                "cannot write {shown}: the file is read-only (mode {mode:o}); make it writable (chmod u+w) or remove it to replace it"
            );
        }
        // Opened without truncating: only asks whether writing is allowed.
        if let Err(e) = std::fs::OpenOptions::new().write(true).open(&target) {
            anyhow::bail!(
                "cannot write {shown} (mode {mode:o}): {}",
                clean(&e.to_string())
            );
        }
    }
    Ok(OutTarget::File(target))
}

/// The picture format `--out`'s extension names (PNG when it has none).
fn output_format(out: &std::path::Path) -> anyhow::Result<image::ImageFormat> {
    use image::ImageFormat as F;
    let Some(ext) = out.extension() else {
        return Ok(F::Png);
    };
    match F::from_extension(ext) {
        Some(
            f @ (F::Png | F::Jpeg | F::Bmp | F::Tga | F::Tiff | F::Pnm | F::Qoi | F::Farbfeld),
        ) => Ok(f),
        _ => anyhow::bail!(
            "{}: unknown picture extension (use .png, .jpg, .bmp, .tga, .tif, .ppm, .qoi or .ff)",
            relief::sanitize::display_path(out)
        ),
    }
}

/// Writes the frame in `format` to standard output, or to a file through a
/// temporary file in the same directory renamed over it at the end: a
/// reader never sees half a picture, and nothing but a regular file is
/// ever opened for writing (a FIFO would block forever).
fn write_picture(
    fb: &Framebuffer,
    out: &OutTarget,
    format: image::ImageFormat,
) -> anyhow::Result<()> {
    if fb.width() == 0 || fb.height() == 0 {
        anyhow::bail!("cannot write an empty {}x{} image", fb.width(), fb.height());
    }
    let out = match out {
        OutTarget::File(path) => path,
        OutTarget::Stdout => {
            // Encoded whole first: the image encoders need a seekable
            // writer for some formats, and a pipe is not one.
            let mut bytes = std::io::Cursor::new(Vec::new());
            fb.to_image().write_to(&mut bytes, format)?;
            let mut stdout = std::io::stdout().lock();
            stdout
                .write_all(bytes.get_ref())
                .and_then(|()| stdout.flush())
                .context("cannot write the picture to standard output")?;
            return Ok(());
        }
    };
    let shown = relief::sanitize::display_path(out);
    // A file replaced keeps its permissions.
    let permissions = std::fs::metadata(out).ok().map(|m| m.permissions());
    let dir = match out.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => std::path::PathBuf::from("."),
    };
    let name = out.file_name().context("--out needs a file name")?;
    let mut temp_name = std::ffi::OsString::from(".");
    temp_name.push(name);
    temp_name.push(format!(".{}.tmp", std::process::id()));
    let temp = dir.join(temp_name);
    let written = (|| -> anyhow::Result<()> {
        let file = std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&temp)?;
        let mut writer = std::io::BufWriter::new(file);
        fb.to_image().write_to(&mut writer, format)?;
        writer.flush()?;
        if let Some(p) = permissions {
            std::fs::set_permissions(&temp, p)?;
        }
        std::fs::rename(&temp, out)?;
        Ok(())
    })();
    if let Err(e) = written {
        let _ = std::fs::remove_file(&temp);
        anyhow::bail!("cannot write {shown}: {}", clean(&e.to_string()));
    }
    Ok(())
}

/// `relief assets DIR` (hidden): writes the built-in textures as PNGs; this
/// is how `assets/` is made.
fn write_assets(dir: &std::path::Path) -> anyhow::Result<()> {
    for path in relief::texture::builtin::write_assets(dir)? {
        println!("{}", relief::sanitize::display_path(&path));
    }
    Ok(())
}
