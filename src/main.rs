//! `relief`: the interactive view, `relief render` (`still`) and `relief bench`.

use std::io::Write;
use std::process::ExitCode;

use clap::Parser;

use relief::cli::{Cli, Command};
use relief_core::sanitize::clean;

/// Whether standard output is closed, noted before the Rust runtime puts
/// `/dev/null` in its place (`relief render` refuses to write into it).
#[cfg(target_os = "linux")]
#[used]
#[unsafe(link_section = ".init_array")]
static RECORD_STDOUT: extern "C" fn() = relief::still::stdout::record_at_start;

fn main() -> ExitCode {
    relief::process::tune();
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => return parse_failure(&e),
    };
    let result = match cli.command {
        Some(Command::Render(args)) => relief::still::render(&args),
        Some(Command::Assets { dir }) => write_assets(&dir),
        Some(Command::Bench(args)) => {
            relief_bench::run(&args, &mut std::io::stdout().lock(), &mut std::io::stderr())
                .map(|_| ())
        }
        None if cli.symbols_test => symbols_test(),
        None => relief::app::run(cli),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        // The reader of the output stopped reading: a filter ends quietly.
        Err(err)
            if err
                .downcast_ref::<relief::still::stdout::ClosedPipe>()
                .is_some() =>
        {
            ExitCode::SUCCESS
        }
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
    let text = relief_core::sanitize::clean_lines(&e.render().to_string());
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
    for symbols in relief_term::Symbols::ALL {
        writeln!(out, "{}", relief_term::symbols::test_line(symbols))?;
    }
    Ok(())
}

/// `relief assets DIR` (hidden): writes the built-in textures as PNGs; this
/// is how `assets/` is made.
fn write_assets(dir: &std::path::Path) -> anyhow::Result<()> {
    for path in relief_texture::decode::builtin::write_assets(dir)? {
        println!("{}", relief_core::sanitize::display_path(&path));
    }
    Ok(())
}
