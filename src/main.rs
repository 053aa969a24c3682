//! `relief`: the interactive view, `relief render` and `relief bench`.

use std::io::Write;
use std::process::ExitCode;
use std::sync::Arc;

use anyhow::Context;
use clap::Parser;

use relief::cli::{Cli, Command, RenderArgs};
use relief::sanitize::clean;
use relief::scene::{Built, build_scene};
use relief::{Framebuffer, Renderer};

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Some(Command::Render(args)) => render(&args),
        Some(Command::Assets { dir }) => write_assets(&dir),
        Some(Command::Bench(args)) => {
            relief::bench::run(&args, &mut std::io::stdout().lock(), &mut std::io::stderr())
                .map(|_| ())
        }
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

/// `relief render`: one frame, to a PNG or to stdout as half-block text.
fn render(args: &RenderArgs) -> anyhow::Result<()> {
    // Errors name the file and are already free of control characters.
    let texture = relief::texture::load::load_for_view(
        args.image.as_deref(),
        args.view.height_map.as_deref(),
    )?;
    let view = &args.view;
    let built = build_scene(view.scene, &view.model, Arc::new(texture), view.all_faces)?;
    let settings = view.settings();
    let mut fb = Framebuffer::new(args.width as usize, args.height as usize);
    match built {
        Built::Scene(scene) => {
            Renderer::new().render(&scene, &settings, &mut fb);
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
        let mut out = std::io::stdout().lock();
        out.write_all(&relief::term::ansi::frame_text(
            &fb,
            depth,
            args.dither,
            pad,
        )?)?;
        out.flush()?;
        return Ok(());
    }
    let out = args.out.as_ref().context("--out FILE.png is required")?;
    if depth == relief::term::ColorDepth::Truecolor {
        fb.save_png(out)
    } else {
        let cells = relief::term::ansi::cells(&fb, depth, args.dither, pad);
        relief::term::ansi::shown_picture(&cells, fb.width(), fb.height(), pad).save_png(out)
    }
}

/// `relief assets DIR` (hidden): writes the built-in textures as PNGs; this
/// is how `assets/` is made.
fn write_assets(dir: &std::path::Path) -> anyhow::Result<()> {
    for path in relief::texture::builtin::write_assets(dir)? {
        println!("{}", relief::sanitize::display_path(&path));
    }
    Ok(())
}
