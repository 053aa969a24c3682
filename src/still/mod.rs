//! `relief render`: one still frame, written as a picture (PNG and the
//! other formats `--out` names) or as terminal text (`--ansi`), of a size
//! in pixels or of a terminal area in cells (`--cells`, a file manager's
//! preview); the model or picture may come from standard input (`-`).

use std::io::Write;
use std::path::PathBuf;
use std::sync::Arc;

use anyhow::Context;

use crate::cli::RenderArgs;
use relief_core::framebuffer::Framebuffer;
use relief_core::sanitize::clean;
use relief_core::settings::Settings;
use relief_pipeline::render::Renderer;
use relief_scene::build::LoadedNotes;
use relief_scene::flag_maps::FlagMaps;
use relief_scene::{Built, SceneKind, build_scene_noting};
use relief_texture::decode::size_cap;

pub mod input;
pub mod out;
pub mod stdout;

use input::StdinFile;
use out::{out_target, output_format, write_picture};

/// `relief render`: one frame, to a picture file or to stdout as text.
pub fn render(args: &RenderArgs) -> anyhow::Result<()> {
    for note in check_render_flags(args)? {
        eprintln!("relief: {}", clean(&note));
    }
    let (width, height) = frame_size(args);
    let mut settings = args.view.settings();
    // A preview decodes its pictures no larger than it can show them.
    let k = relief_core::settings::ssaa_factor(settings.aa, width, height);
    let cap = args
        .cells
        .map(|_| size_cap::side_for_frame(width * k, height * k));
    let (built, maps, notes) = size_cap::with_max_side(cap, || load_scene(args))?;
    // A model from standard input starts in the model view's turn, as a
    // model file named on the command line does.
    let model_view = matches!(&built, Built::Scene(s) if s.model_view.is_some());
    if model_view && args.view.rotate.is_none() {
        settings.rotation = relief_scene::model_view::START_ROTATION;
    }
    // An STL stands Z up unless `--up` says otherwise.
    if notes.z_up && !args.view.options.given(relief_options::OptId::Up) {
        settings.up = relief_core::settings::UpAxis::Z;
    }
    for warning in &notes.warnings {
        eprintln!("relief: warning: {}", clean(warning));
    }
    if notes.points && settings.display == relief_core::settings::Display::Fill {
        eprintln!("relief: the model is a point cloud: drawn as points");
        settings.display = relief_core::settings::Display::Points;
    }
    let fb = draw(args, built, &maps, &settings, (width, height))?;
    write_frame_out(args, &fb)
}

/// `--camera N`: the model seen through the file's camera N, standing as
/// the file places it.
fn through_file_camera(
    args: &RenderArgs,
    scene: &mut relief_scene::Scene,
    settings: &mut Settings,
) -> anyhow::Result<()> {
    let Some(k) = args.camera else {
        return Ok(());
    };
    let n = scene.cameras.len();
    let Some(view) = scene.model_view.as_mut().filter(|_| k < n) else {
        anyhow::bail!("--camera {k}: the model has {n} camera(s) (from 0)");
    };
    view.camera = Some(k);
    if args.view.rotate.is_none() {
        settings.rotation = glam::Vec3::ZERO;
    }
    Ok(())
}

/// An animated model posed at `--time` into `--clip` (its first clip at
/// 0 s by default); either flag for a model without animation is noted.
fn pose(args: &RenderArgs, scene: &mut relief_scene::Scene) -> anyhow::Result<()> {
    let Some(motion) = &mut scene.motion else {
        if args.time.is_some() || args.clip.is_some() {
            eprintln!("relief: the model has no animation: --time and --clip do nothing");
        }
        return Ok(());
    };
    let clips = motion.clips().len();
    let clip = match args.clip {
        Some(c) if c >= clips => anyhow::bail!(
            "--clip {c}: the model has {clips} animation{} (from 0)",
            if clips == 1 { "" } else { "s" }
        ),
        Some(c) => Some(c),
        None => (clips > 0).then_some(0),
    };
    motion.show(&mut scene.objects, clip, args.time.unwrap_or(0.0));
    Ok(())
}

/// The frame's size in pixels: `--width` × `--height`, or what fills
/// `--cells` in the symbols (or, for pixel formats, the terminal's cell size).
fn frame_size(args: &RenderArgs) -> (usize, usize) {
    let Some(cells) = args.cells else {
        return (args.width as usize, args.height as usize);
    };
    if args.ansi && args.format.is_pixels() {
        use relief_term::pixel_view::{cell_pixels, frame_size, window_size};
        let (cell, _) = cell_pixels(window_size(), None);
        return frame_size(cells.cols, cells.rows, cell);
    }
    (
        usize::from(cells.cols) * args.symbols.columns(),
        usize::from(cells.rows) * args.symbols.rows(),
    )
}

/// The scene to draw, the maps the flags name, and what loading the model
/// had to say. A positional model file is the model, an image the
/// texture; `-` is whichever of them standard input holds.
fn load_scene(args: &RenderArgs) -> anyhow::Result<(Built, FlagMaps, LoadedNotes)> {
    let view = &args.view;
    let from_stdin = args.image.as_ref().is_some_and(|p| p.as_os_str() == "-");
    let (picture, stdin_model) = match from_stdin.then(input::read_stdin_file).transpose()? {
        Some(StdinFile::Picture(t)) => (Some(t), None),
        Some(StdinFile::Model(m)) => (None, Some(m)),
        None => (None, None),
    };
    let mut model = view.model.clone();
    let mut image: Vec<PathBuf> = args.image.iter().filter(|_| !from_stdin).cloned().collect();
    crate::cli::models_from_positional(&mut image, &mut model);
    // Errors name the file and are already free of control characters.
    let height_map = view.height_map.as_deref();
    let picture_given = picture.is_some() || !image.is_empty();
    let texture = match (picture, height_map) {
        (Some(color), Some(path)) => relief_texture::decode::load::with_height_map(
            color,
            &relief_texture::decode::load::load_texture(path)?,
        )?,
        (Some(color), None) => color,
        (None, _) => relief_texture::decode::load::load_for_view(
            image.first().map(PathBuf::as_path),
            height_map,
        )?,
    };
    let maps = FlagMaps::read(
        view.specular_map.as_deref(),
        view.normal_map.as_deref(),
        view.environment_map.as_deref(),
    )
    .all()?;
    let texture = Arc::new(texture);
    let model_ignored = stdin_model.is_some() && view.scene != SceneKind::Cube;
    // An image, a height map or a surface map named is a texture chosen: a
    // model file's parts without a material take it, else they are plain.
    let chosen = picture_given || height_map.is_some() || maps.name_surface_maps();
    let (mut built, mut notes) = match stdin_model {
        Some(m) if view.scene == SceneKind::Cube => {
            let (scene, notes) = m.into_scene(texture);
            (Built::Scene(Box::new(scene)), notes)
        }
        _ => build_scene_noting(view.scene, &model, texture, view.all_faces)?,
    };
    if let Built::Scene(scene) = &mut built
        && let Some(view) = &mut scene.model_view
    {
        view.texture_chosen = chosen;
    }
    if model_ignored {
        notes.warnings.push(
            "the model from standard input is ignored: only --scene cube draws a model".into(),
        );
    }
    Ok((built, maps, notes))
}

/// The frame of `size` pixels drawn.
fn draw(
    args: &RenderArgs,
    built: Built,
    maps: &FlagMaps,
    settings: &Settings,
    (width, height): (usize, usize),
) -> anyhow::Result<Framebuffer> {
    // The frame's memory is reserved before any of it exists.
    let _frame = relief_core::budget::reserve(
        &format!("a {width}x{height} frame"),
        relief_core::budget::frame_bytes_for(width, height, settings.aa),
    )?;
    let mut fb = Framebuffer::new(width, height);
    match built {
        Built::Scene(mut scene) => {
            scene.camera = scene.camera.at_distance(args.view.distance);
            scene.camera.fov_y_degrees = settings.fov;
            maps.dress(&mut scene);
            pose(args, &mut scene)?;
            let mut settings = *settings;
            through_file_camera(args, &mut scene, &mut settings)?;
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
            plasma.render(light, args.view.plasma_normal, &mut fb);
        }
    }
    Ok(fb)
}

/// Writes the frame where the flags say: text or a terminal image on
/// standard output (`--ansi`), or a picture (`--out`).
fn write_frame_out(args: &RenderArgs, fb: &Framebuffer) -> anyhow::Result<()> {
    let depth = crate::app::color_depth(Some(args.color));
    let pad = relief_scene::BACKGROUND;
    if args.ansi {
        let mut out = std::io::BufWriter::new(std::io::stdout().lock());
        return relief_term::format::write_frame(
            fb,
            args.format,
            args.symbols,
            depth,
            args.dither,
            pad,
            args.cells.map(|c| (c.cols, c.rows)),
            &mut out,
        )
        .and_then(|()| out.flush())
        .map_err(stdout::write_error);
    }
    let out = args.out.as_ref().context("--out FILE.png is required")?;
    let format = output_format(out)?;
    let out = &out_target(out)?;
    if depth == relief_term::ColorDepth::Truecolor && args.symbols == relief_term::Symbols::Half {
        write_picture(fb, out, format)
    } else {
        // The picture a terminal with that depth shows: its cells first.
        let (w, h) = args.symbols.cells_for_pixels(fb.width(), fb.height());
        let _cells = relief_core::budget::reserve(
            &format!(
                "the {w}x{h} cells of a {}x{} frame",
                fb.width(),
                fb.height()
            ),
            (w * h * std::mem::size_of::<ratatui::buffer::Cell>()
                + fb.width() * fb.height() * relief_core::budget::FRAME_BYTES_PER_PIXEL as usize)
                as u64,
        )?;
        let cells = relief_term::ansi::symbol_cells(fb, args.symbols, depth, args.dither, pad);
        let shown =
            relief_term::cells::shown_picture(&cells, args.symbols, fb.width(), fb.height(), pad);
        drop(cells);
        write_picture(&shown, out, format)
    }
}

/// Things `render` was asked for that it cannot do, said on stderr before
/// it does the rest; and what makes it stop before rendering.
fn check_render_flags(args: &RenderArgs) -> anyhow::Result<Vec<String>> {
    use relief_scene::{ModelChoice, SceneKind};
    if args.ansi || args.out.as_ref().is_some_and(|o| o.as_os_str() == "-") {
        // Before any file is opened or anything rendered.
        stdout::check_open()?;
    }
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
    if view.normal_map.is_some() && !relief_pipeline::plan::normal_map_file_shows(&settings, true) {
        notes.push(
            "--normal-map shows with --technique dot3 (the other techniques read the height map)"
                .into(),
        );
    }
    let (w, h) = frame_size(args);
    let k = relief_core::settings::ssaa_factor(settings.aa, w, h);
    let wanted = match settings.aa {
        relief_core::settings::AntiAlias::Ssaa2 => 2,
        relief_core::settings::AntiAlias::Ssaa4 => 4,
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
            relief_core::settings::MAX_SUPERSAMPLES
        ));
    }
    if let Some(out) = &args.out {
        // Checked before rendering, so a refusal costs nothing.
        out_target(out)?;
    }
    Ok(notes)
}
