//! `relief render`: one still frame, written as a picture (PNG and the
//! other formats `--out` names) or as terminal text (`--ansi`).

use std::io::Write;
use std::sync::Arc;

use anyhow::Context;

use crate::cli::RenderArgs;
use crate::sanitize::clean;
use crate::scene::flag_maps::FlagMaps;
use crate::scene::{Built, build_scene_noting};
use crate::{Framebuffer, Renderer};

pub mod out;
pub mod stdout;

use out::{out_target, output_format, write_picture};

/// `relief render`: one frame, to a PNG or to stdout as half-block text.
pub fn render(args: &RenderArgs) -> anyhow::Result<()> {
    for note in check_render_flags(args)? {
        eprintln!("relief: {}", clean(&note));
    }
    // A positional model file is the model; an image is the texture.
    let mut view = args.view.clone();
    let mut image = args.image.clone().into_iter().collect();
    crate::cli::models_from_positional(&mut image, &mut view.model);
    // Errors name the file and are already free of control characters.
    let texture = crate::texture::load::load_for_view(
        image.first().map(|p| p.as_path()),
        args.view.height_map.as_deref(),
    )?;
    let view = &view;
    let maps = FlagMaps::read(
        view.specular_map.as_deref(),
        view.normal_map.as_deref(),
        view.environment_map.as_deref(),
    )
    .all()?;
    let (built, notes) =
        build_scene_noting(view.scene, &view.model, Arc::new(texture), view.all_faces)?;
    for warning in &notes.warnings {
        eprintln!("relief: warning: {}", clean(warning));
    }
    let mut settings = view.settings();
    if notes.points && settings.display == crate::settings::Display::Fill {
        eprintln!("relief: the model is a point cloud: drawn as points");
        settings.display = crate::settings::Display::Points;
    }
    let (width, height) = (args.width as usize, args.height as usize);
    // The frame's memory is reserved before any of it exists.
    let _frame = crate::budget::reserve(
        &format!("a {width}x{height} frame"),
        crate::budget::frame_bytes_for(width, height, settings.aa),
    )?;
    let mut fb = Framebuffer::new(width, height);
    match built {
        Built::Scene(mut scene) => {
            scene.camera = scene.camera.at_distance(view.distance);
            scene.camera.fov_y_degrees = settings.fov;
            maps.dress(&mut scene);
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
    let depth = crate::app::color_depth(Some(args.color));
    let pad = crate::scene::BACKGROUND;
    if args.ansi {
        let mut out = std::io::BufWriter::new(std::io::stdout().lock());
        return crate::term::format::write_frame(
            &fb,
            args.format,
            args.symbols,
            depth,
            args.dither,
            pad,
            &mut out,
        )
        .and_then(|()| out.flush())
        .map_err(stdout::write_error);
    }
    let out = args.out.as_ref().context("--out FILE.png is required")?;
    let format = output_format(out)?;
    let out = &out_target(out)?;
    if depth == crate::term::ColorDepth::Truecolor && args.symbols == crate::term::Symbols::Half {
        write_picture(&fb, out, format)
    } else {
        // The picture a terminal with that depth shows: its cells first.
        let (w, h) = args.symbols.cells_for_pixels(fb.width(), fb.height());
        let _cells = crate::budget::reserve(
            &format!(
                "the {w}x{h} cells of a {}x{} frame",
                fb.width(),
                fb.height()
            ),
            (w * h * std::mem::size_of::<ratatui::buffer::Cell>()
                + fb.width() * fb.height() * crate::budget::FRAME_BYTES_PER_PIXEL as usize)
                as u64,
        )?;
        let cells = crate::term::ansi::symbol_cells(&fb, args.symbols, depth, args.dither, pad);
        let shown =
            crate::term::cells::shown_picture(&cells, args.symbols, fb.width(), fb.height(), pad);
        drop(cells);
        write_picture(&shown, out, format)
    }
}

/// Things `render` was asked for that it cannot do, said on stderr before
/// it does the rest; and what makes it stop before rendering.
fn check_render_flags(args: &RenderArgs) -> anyhow::Result<Vec<String>> {
    use crate::scene::{ModelChoice, SceneKind};
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
    if view.normal_map.is_some() && !crate::plan::normal_map_file_shows(&settings, true) {
        notes.push(
            "--normal-map shows with --technique dot3 (the other techniques read the height map)"
                .into(),
        );
    }
    let (w, h) = (args.width as usize, args.height as usize);
    let k = crate::raster::aa::ssaa_factor(settings.aa, w, h);
    let wanted = match settings.aa {
        crate::settings::AntiAlias::Ssaa2 => 2,
        crate::settings::AntiAlias::Ssaa4 => 4,
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
            crate::raster::aa::MAX_SUPERSAMPLES
        ));
    }
    if let Some(out) = &args.out {
        // Checked before rendering, so a refusal costs nothing.
        out_target(out)?;
    }
    Ok(notes)
}
