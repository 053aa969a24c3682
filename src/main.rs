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
    let (width, height) = (args.width as usize, args.height as usize);
    // The frame's memory is reserved before any of it exists.
    let _frame = relief::budget::reserve(
        &format!("a {width}x{height} frame"),
        relief::budget::frame_bytes_for(width, height, settings.aa),
    )?;
    let mut fb = Framebuffer::new(width, height);
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
    if args.ansi {
        let mut out = std::io::BufWriter::new(std::io::stdout().lock());
        write_ansi_halfblocks(&fb, &mut out)?;
        out.flush()?;
        return Ok(());
    }
    let out = args.out.as_ref().context("--out FILE.png is required")?;
    fb.save_png(out)
}

/// `relief assets DIR` (hidden): writes the built-in textures as PNGs; this
/// is how `assets/` is made.
fn write_assets(dir: &std::path::Path) -> anyhow::Result<()> {
    for path in relief::texture::builtin::write_assets(dir)? {
        println!("{}", relief::sanitize::display_path(&path));
    }
    Ok(())
}

/// Truecolor `▀` text, one cell per two pixel rows, written row by row so
/// the text is never held whole (a 16384² frame would be gigabytes of it).
fn write_ansi_halfblocks(fb: &Framebuffer, out: &mut impl Write) -> std::io::Result<()> {
    for y in (0..fb.height()).step_by(2) {
        for x in 0..fb.width() {
            let top = fb.get(x, y);
            let bottom = if y + 1 < fb.height() {
                fb.get(x, y + 1)
            } else {
                [0, 0, 0]
            };
            write!(
                out,
                "\x1b[38;2;{};{};{}m\x1b[48;2;{};{};{}m▀",
                top[0], top[1], top[2], bottom[0], bottom[1], bottom[2]
            )?;
        }
        out.write_all(b"\x1b[0m\n")?;
    }
    Ok(())
}
