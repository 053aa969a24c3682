//! How the picture reaches the terminal: text cells of a symbol set, or
//! pixels through the kitty graphics protocol, sixel or iTerm2 images.

use std::io::{self, Write};

use super::color::ColorDepth;
use super::symbols::Symbols;
use super::{ansi, iterm, kitty, sixel};
use relief_core::framebuffer::{Framebuffer, Rgb};

/// `--format`, chafa's names.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, clap::ValueEnum)]
pub enum Format {
    /// What the terminal is found to speak (text symbols when unsure).
    #[default]
    Auto,
    /// Text cells of the `--symbols` set.
    Symbols,
    /// The kitty graphics protocol (kitty, WezTerm, Ghostty, Konsole).
    Kitty,
    /// Sixel (xterm -ti vt340, mlterm, foot, WezTerm, Windows Terminal).
    Sixels,
    /// iTerm2 inline images (iTerm2, WezTerm).
    Iterm,
}

impl Format {
    pub fn name(self) -> &'static str {
        match self {
            Format::Auto => "auto",
            Format::Symbols => "symbols",
            Format::Kitty => "kitty",
            Format::Sixels => "sixels",
            Format::Iterm => "iterm",
        }
    }

    /// True for the formats that send pixels.
    pub fn is_pixels(self) -> bool {
        matches!(self, Format::Kitty | Format::Sixels | Format::Iterm)
    }
}

/// The frame in `format` for a file or a pipe (`relief render --ansi`),
/// starting at the cursor and ending with a newline (LF only). Pixel
/// formats show the frame at its own pixel size, or, for kitty and iTerm2,
/// scaled to fill `cells` (columns × rows) when given; a sixel image has
/// no such setting.
#[allow(clippy::too_many_arguments)]
pub fn write_frame(
    fb: &Framebuffer,
    format: Format,
    symbols: Symbols,
    depth: ColorDepth,
    dither: bool,
    pad: Rgb,
    cells: Option<(u16, u16)>,
    out: &mut impl Write,
) -> io::Result<()> {
    match format {
        Format::Auto | Format::Symbols => {
            ansi::write_symbol_text(fb, symbols, depth, dither, pad, b"\n", out)
        }
        Format::Kitty => {
            kitty::write_image(fb, cells, out)?;
            out.write_all(b"\n")
        }
        Format::Sixels => {
            sixel::write_image(fb, dither, out)?;
            out.write_all(b"\n")
        }
        Format::Iterm => {
            iterm::write_image(fb, cells, out)?;
            out.write_all(b"\n")
        }
    }
}

/// The environment variable that forces a format (`kitty`, `sixels`,
/// `iterm`, `symbols`, `auto`) when `--format` is not given.
pub const ENV: &str = "RELIEF_FORMAT";

/// What tmux says about pixel output from a pane: the client terminal's
/// name and features, and whether `allow-passthrough` is on.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct TmuxPixels {
    pub termname: String,
    pub features: String,
    pub passthrough: bool,
}

/// Everything the choice of format looks at.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Clues {
    /// `--format` (or [`ENV`]) and which of the two gave it.
    pub forced: Option<(Format, &'static str)>,
    /// The start-up probe's replies (see [`super::probe`]).
    pub kitty_reply: bool,
    pub sixel_da1: bool,
    /// Inside tmux with passthrough: the client terminal's device
    /// attributes, asked through the passthrough, list 4 (it draws sixel).
    pub client_sixel: bool,
    pub version: Option<String>,
    pub term_program: Option<String>,
    pub lc_terminal: Option<String>,
    /// Inside tmux: what tmux said.
    pub tmux: Option<TmuxPixels>,
}

/// The format in use and why (shown on the status line and in the cost
/// panel); `passthrough`: its sequences go through tmux's passthrough.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FormatChoice {
    pub format: Format,
    pub source: String,
    pub passthrough: bool,
    /// Said once on the status line (how to enable tmux passthrough).
    pub note: Option<String>,
}

/// The clues this process has before asking the terminal: `--format`,
/// else `RELIEF_FORMAT`; the environment; tmux (asked only when a pixel
/// format could be used).
pub fn clues_here(arg: Option<Format>) -> Clues {
    let env = |name: &str| std::env::var(name).ok().filter(|v| !v.is_empty());
    let forced = match arg {
        Some(f) => Some((f, "--format")),
        None => from_env_value(env(ENV).as_deref()).map(|f| (f, ENV)),
    };
    let symbols_only = matches!(forced, Some((Format::Symbols, _)));
    let tmux = (env("TMUX").is_some() && !symbols_only)
        .then(|| ask_tmux(env("TMUX_PANE").as_deref()))
        .flatten();
    Clues {
        forced,
        term_program: env("TERM_PROGRAM"),
        lc_terminal: env("LC_TERMINAL"),
        tmux,
        ..Clues::default()
    }
}

impl Clues {
    /// Whether the terminal's replies could change the choice: no format
    /// forced, and not the Linux console (which prints what it does not
    /// know).
    pub fn wants_probe(&self) -> bool {
        let forced = matches!(self.forced, Some((f, _)) if f != Format::Auto);
        !forced && std::env::var("TERM").ok().as_deref() != Some("linux")
    }

    /// The start-up probe also asks tmux's client terminal for its device
    /// attributes, through the passthrough (inside tmux with it on; see
    /// [`super::probe`]).
    pub fn asks_through_tmux(&self) -> bool {
        self.tmux.as_ref().is_some_and(|t| t.passthrough)
    }

    /// tmux draws sixel images itself (tmux ≥ 3.4 built with sixel: its
    /// device attributes list 4, or its client has the `sixel` feature).
    pub fn tmux_draws_sixel(&self) -> bool {
        self.tmux
            .as_ref()
            .is_some_and(|t| self.sixel_da1 || t.features.split(',').any(|f| f.trim() == "sixel"))
    }
}

/// Reads `tmux display -p '#{client_termname}\t#{client_termfeatures}\t#{allow-passthrough}'`
/// (the option is `1`/`on`/`all` when on, `0`/`off` when off); `show` is
/// `tmux show -gv allow-passthrough`'s answer, asked when the option did
/// not come (`None`: no such option, a tmux before 3.3, which always
/// passed sequences through).
pub fn parse_tmux(line: &str, show: impl FnOnce() -> Option<String>) -> TmuxPixels {
    let mut it = line.trim_end_matches(['\n', '\r']).split('\t');
    let termname = it.next().unwrap_or("").trim().to_string();
    let features = it.next().unwrap_or("").trim().to_string();
    let on = |v: &str| matches!(v.trim(), "1" | "on" | "all");
    let passthrough = match it.next().map(str::trim).filter(|v| !v.is_empty()) {
        Some(v) => on(v),
        None => show().is_none_or(|v| on(&v)),
    };
    TmuxPixels {
        termname,
        features,
        passthrough,
    }
}

/// What tmux says about the client of `pane` and passthrough (inside
/// tmux; `None` when tmux does not answer).
pub fn ask_tmux(pane: Option<&str>) -> Option<TmuxPixels> {
    use super::depth::run_briefly;
    let limit = std::time::Duration::from_millis(500);
    let mut args = vec!["display-message", "-p"];
    if let Some(pane) = pane {
        args.extend(["-t", pane]);
    }
    args.push("#{client_termname}\t#{client_termfeatures}\t#{allow-passthrough}");
    let line = run_briefly("tmux", &args, limit)?;
    Some(parse_tmux(&line, || {
        run_briefly("tmux", &["show", "-gv", "allow-passthrough"], limit)
    }))
}

/// What the terminal (or tmux's client terminal) speaks best, kitty >
/// iterm > sixels > symbols, and the clue that said so.
pub fn detected(c: &Clues) -> (Format, String) {
    let lower = |s: &Option<String>| s.as_deref().unwrap_or("").to_ascii_lowercase();
    let (version, program, lc) = (
        lower(&c.version),
        lower(&c.term_program),
        lower(&c.lc_terminal),
    );
    if let Some(t) = &c.tmux {
        // tmux answers the queries itself: ask it about its client.
        let name = t.termname.to_ascii_lowercase();
        if name.contains("kitty") || name.contains("ghostty") {
            return (Format::Kitty, format!("tmux client {}", t.termname));
        }
        if name.contains("wezterm") || lc == "iterm2" {
            let who = if lc == "iterm2" {
                "LC_TERMINAL iTerm2".into()
            } else {
                format!("tmux client {}", t.termname)
            };
            return (Format::Iterm, who);
        }
        if c.tmux_draws_sixel() {
            return (Format::Sixels, "tmux sixel".into());
        }
        if c.client_sixel {
            return (
                Format::Sixels,
                format!("tmux client {}: device attributes 4", t.termname),
            );
        }
        return (Format::Symbols, "tmux client has no pixel format".into());
    }
    if c.kitty_reply {
        return (Format::Kitty, "kitty graphics reply".into());
    }
    if version.starts_with("iterm2") || version.starts_with("wezterm") {
        return (
            Format::Iterm,
            format!("XTVERSION {}", c.version.as_deref().unwrap_or("")),
        );
    }
    if program == "iterm.app" || program == "wezterm" {
        return (
            Format::Iterm,
            format!("TERM_PROGRAM {}", c.term_program.as_deref().unwrap_or("")),
        );
    }
    if lc == "iterm2" {
        return (Format::Iterm, "LC_TERMINAL iTerm2".into());
    }
    if c.sixel_da1 {
        return (Format::Sixels, "device attributes 4".into());
    }
    (Format::Symbols, "no pixel format found".into())
}

/// The format to use: the forced one, else the detected one; inside tmux
/// a pixel format needs `allow-passthrough` (relief never changes it: the
/// note says how), except sixel drawn by tmux itself.
pub fn choose(c: &Clues) -> FormatChoice {
    let (format, source) = wanted(c);
    in_tmux(format, source, c.tmux.as_ref(), c.tmux_draws_sixel())
}

/// The forced format, else the detected one (before tmux's fallback).
pub fn wanted(c: &Clues) -> (Format, String) {
    match c.forced {
        Some((f, by)) if f != Format::Auto => (f, by.to_string()),
        _ => detected(c),
    }
}

/// `format` as it can be used inside tmux (`tmux` none: outside).
pub fn in_tmux(
    format: Format,
    source: String,
    tmux: Option<&TmuxPixels>,
    tmux_sixel: bool,
) -> FormatChoice {
    let plain = |format, source| FormatChoice {
        format,
        source,
        passthrough: false,
        note: None,
    };
    let Some(t) = tmux else {
        return plain(format, source);
    };
    if !format.is_pixels() {
        return plain(format, source);
    }
    if format == Format::Sixels && tmux_sixel {
        return plain(format, format!("{source}, drawn by tmux"));
    }
    if t.passthrough {
        return FormatChoice {
            format,
            source: format!("{source}, tmux passthrough"),
            passthrough: true,
            note: None,
        };
    }
    FormatChoice {
        format: Format::Symbols,
        source: format!("{} needs tmux passthrough", format.name()),
        passthrough: false,
        note: Some(format!(
            "{} images need tmux passthrough: tmux set -g allow-passthrough on",
            format.name()
        )),
    }
}

/// `RELIEF_FORMAT`'s value as a format (`None` when unset or unknown).
pub fn from_env_value(value: Option<&str>) -> Option<Format> {
    let v = value?.trim();
    <Format as clap::ValueEnum>::from_str(v, true).ok()
}

impl Format {
    /// The next format the key cycles to: symbols → kitty → sixels → iterm.
    pub fn next(self) -> Format {
        match self {
            Format::Auto | Format::Symbols => Format::Kitty,
            Format::Kitty => Format::Sixels,
            Format::Sixels => Format::Iterm,
            Format::Iterm => Format::Symbols,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tmux(termname: &str, features: &str, passthrough: bool) -> Option<TmuxPixels> {
        Some(TmuxPixels {
            termname: termname.into(),
            features: features.into(),
            passthrough,
        })
    }

    #[test]
    fn auto_prefers_kitty_then_iterm_then_sixels() {
        let mut c = Clues {
            kitty_reply: true,
            sixel_da1: true,
            term_program: Some("WezTerm".into()),
            ..Clues::default()
        };
        assert_eq!(choose(&c).format, Format::Kitty);
        c.kitty_reply = false;
        let got = choose(&c);
        assert_eq!(
            (got.format, got.source.as_str()),
            (Format::Iterm, "TERM_PROGRAM WezTerm")
        );
        c.term_program = None;
        assert_eq!(choose(&c).format, Format::Sixels);
        c.version = Some("iTerm2 3.5.0".into());
        assert_eq!(choose(&c).format, Format::Iterm);
        c.version = Some("XTerm(390)".into());
        assert_eq!(choose(&c).format, Format::Sixels);
        c.sixel_da1 = false;
        assert_eq!(choose(&c).format, Format::Symbols);
        c.lc_terminal = Some("iTerm2".into());
        assert_eq!(choose(&c).format, Format::Iterm);
    }

    #[test]
    fn a_forced_format_wins_and_auto_detects() {
        let c = Clues {
            forced: Some((Format::Sixels, "--format")),
            kitty_reply: true,
            ..Clues::default()
        };
        let got = choose(&c);
        assert_eq!(
            (got.format, got.source.as_str()),
            (Format::Sixels, "--format")
        );
        let c = Clues {
            forced: Some((Format::Auto, "RELIEF_FORMAT")),
            kitty_reply: true,
            ..c
        };
        assert_eq!(choose(&c).format, Format::Kitty);
        assert_eq!(from_env_value(Some("Kitty")), Some(Format::Kitty));
        assert_eq!(from_env_value(Some(" sixels ")), Some(Format::Sixels));
        assert_eq!(from_env_value(Some("png")), None);
        assert_eq!(from_env_value(None), None);
    }

    #[test]
    fn inside_tmux_the_client_device_attributes_ask_for_sixel_through_passthrough() {
        // xterm -ti vt340 under tmux 3.3 (no sixel feature): its own
        // device attributes, asked through the passthrough, say sixel.
        let on = Clues {
            tmux: tmux("xterm", "256,RGB,title", true),
            client_sixel: true,
            ..Clues::default()
        };
        assert!(on.asks_through_tmux());
        let got = choose(&on);
        assert_eq!((got.format, got.passthrough), (Format::Sixels, true));
        assert!(got.source.contains("device attributes 4"), "{}", got.source);
        // Without passthrough the client cannot be asked: text, no note.
        let off = Clues {
            tmux: tmux("xterm", "256,RGB,title", false),
            ..Clues::default()
        };
        assert!(!off.asks_through_tmux());
        let got = choose(&off);
        assert_eq!((got.format, got.note), (Format::Symbols, None));
        // Outside tmux the probe asks the terminal itself.
        assert!(!Clues::default().asks_through_tmux());
    }

    #[test]
    fn inside_tmux_pixels_need_passthrough() {
        let off = Clues {
            tmux: tmux("xterm-kitty", "256,RGB,title", false),
            ..Clues::default()
        };
        let got = choose(&off);
        assert_eq!(got.format, Format::Symbols);
        assert!(!got.passthrough);
        let note = got.note.unwrap();
        assert!(
            note.contains("kitty") && note.contains("tmux set -g allow-passthrough on"),
            "{note}"
        );
        let on = Clues {
            tmux: tmux("xterm-kitty", "", true),
            ..Clues::default()
        };
        let got = choose(&on);
        assert_eq!((got.format, got.passthrough), (Format::Kitty, true));
        // Sixel named by tmux's client features; drawn by tmux itself when
        // tmux's own device attributes list 4 (no passthrough needed).
        let got = choose(&Clues {
            tmux: tmux("xterm-256color", "256,sixel,RGB", false),
            sixel_da1: true,
            ..Clues::default()
        });
        assert_eq!(
            (got.format, got.passthrough, got.note),
            (Format::Sixels, false, None)
        );
        // A plain client: symbols, no note (nothing to enable).
        let got = choose(&Clues {
            tmux: tmux("xterm-256color", "256,RGB", true),
            ..Clues::default()
        });
        assert_eq!((got.format, got.note), (Format::Symbols, None));
        // A forced format without passthrough falls back too.
        let got = choose(&Clues {
            forced: Some((Format::Iterm, "--format")),
            tmux: tmux("xterm-256color", "", false),
            ..Clues::default()
        });
        assert_eq!(got.format, Format::Symbols);
        assert!(
            got.note
                .unwrap()
                .starts_with("iterm images need tmux passthrough")
        );
    }

    #[test]
    fn tmux_answers_are_read() {
        let never = || -> Option<String> { panic!("not asked") };
        let t = parse_tmux("xterm-kitty\t256,RGB,sixel\t1\n", never);
        assert_eq!(
            t,
            TmuxPixels {
                termname: "xterm-kitty".into(),
                features: "256,RGB,sixel".into(),
                passthrough: true
            }
        );
        assert!(!parse_tmux("xterm\t\t0\n", never).passthrough);
        assert!(parse_tmux("xterm\t\tall\n", never).passthrough);
        // No value: `show -gv` decides; no such option (old tmux): on.
        assert!(!parse_tmux("xterm\t\t\n", || Some("off\n".into())).passthrough);
        assert!(parse_tmux("xterm\t\t\n", || Some("on\n".into())).passthrough);
        assert!(parse_tmux("xterm", || None).passthrough);
    }

    #[test]
    fn the_key_cycles_every_format() {
        let mut f = Format::Symbols;
        let mut seen = vec![];
        for _ in 0..4 {
            f = f.next();
            seen.push(f);
        }
        assert_eq!(
            seen,
            [
                Format::Kitty,
                Format::Sixels,
                Format::Iterm,
                Format::Symbols
            ]
        );
    }
}
