//! Which colour depth to use, and what said so (the cost panel shows it).
//!
//! In order: `--color`; `COLORTERM=truecolor|24bit`; a `TERM` ending in
//! `-direct`; inside tmux, what tmux knows of the terminal its client runs
//! in (tmux answers the terminal queries itself, and turns 24-bit colours
//! into its palette unless the client has the `RGB` feature); the terminfo
//! entry of `TERM` (`Tc`, `RGB` or `setrgbf`, the capabilities neovim
//! reads); then the terminal's own reply ([`super::probe`]); else 16
//! colours on the Linux console and 256 elsewhere.

use std::io::Read;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use super::ColorDepth;

/// A depth and where it came from.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DepthChoice {
    pub depth: ColorDepth,
    /// A few words: "COLORTERM", "tmux client RGB", "terminfo Tc"…
    pub source: String,
}

impl DepthChoice {
    fn new(depth: ColorDepth, source: impl Into<String>) -> Self {
        DepthChoice {
            depth,
            source: source.into(),
        }
    }
}

/// What tmux says of the client the pane is shown on
/// (`#{client_termfeatures}` and `#{client_termname}`; both empty when no
/// client is attached).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct TmuxClient {
    pub features: String,
    pub termname: String,
}

/// The terminfo capability among `Tc`, `RGB` and `setrgbf` that `infocmp
/// -x -1` output lists, if any (one capability per line, `name,`,
/// `name#n,` or `name=value,`; a cancelled one, `name@,`, does not count).
pub fn terminfo_truecolor(infocmp: &str) -> Option<&'static str> {
    for line in infocmp.lines() {
        let cap = line.trim().trim_end_matches(',');
        let name = cap.split(['=', '#']).next().unwrap_or("");
        for want in ["Tc", "RGB", "setrgbf"] {
            if name == want {
                return Some(want);
            }
        }
    }
    None
}

/// The depth the environment settles without asking the terminal, or
/// `None` when the terminal should be asked. `tmux` is what tmux said
/// (inside tmux only); `terminfo` looks a terminal name up (`infocmp`
/// output).
pub fn settled(
    colorterm: Option<&str>,
    term: Option<&str>,
    tmux: Option<&TmuxClient>,
    terminfo: &dyn Fn(&str) -> Option<String>,
) -> Option<DepthChoice> {
    let ct = colorterm.unwrap_or("").trim().to_ascii_lowercase();
    if ct == "truecolor" || ct == "24bit" {
        return Some(DepthChoice::new(ColorDepth::Truecolor, "COLORTERM"));
    }
    let term = term.unwrap_or("").trim();
    if term.to_ascii_lowercase().ends_with("-direct") {
        return Some(DepthChoice::new(ColorDepth::Truecolor, "TERM -direct"));
    }
    let has_rgb = |name: &str| terminfo(name).as_deref().and_then(terminfo_truecolor);
    if let Some(client) = tmux {
        if !client.features.is_empty() {
            // tmux ≥ 3.2: it passes 24-bit colours on only with RGB.
            let rgb = client.features.split(',').any(|f| f.trim() == "RGB");
            return Some(if rgb {
                DepthChoice::new(ColorDepth::Truecolor, "tmux client RGB")
            } else {
                DepthChoice::new(ColorDepth::Palette256, "tmux client no RGB")
            });
        }
        // Older tmux: the client terminal's own terminfo entry.
        if !client.termname.is_empty()
            && let Some(cap) = has_rgb(&client.termname)
        {
            return Some(DepthChoice::new(
                ColorDepth::Truecolor,
                format!("tmux client terminfo {cap}"),
            ));
        }
    }
    if !term.is_empty()
        && let Some(cap) = has_rgb(term)
    {
        return Some(DepthChoice::new(
            ColorDepth::Truecolor,
            format!("terminfo {cap}"),
        ));
    }
    None
}

/// The depth when the terminal's reply was not positive (or not asked).
pub fn fallback(colorterm: Option<&str>, term: Option<&str>) -> DepthChoice {
    match ColorDepth::detect(colorterm, term) {
        ColorDepth::Palette16 => DepthChoice::new(ColorDepth::Palette16, "TERM"),
        depth => DepthChoice::new(depth, "no sign of 24-bit"),
    }
}

/// Runs `program` with `args`, its standard output if it exits with
/// success within `limit` (killed otherwise), `None` if it is missing.
pub fn run_briefly(program: &str, args: &[&str], limit: Duration) -> Option<String> {
    let mut child = Command::new(program)
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .ok()?;
    let start = Instant::now();
    loop {
        match child.try_wait() {
            Ok(Some(status)) => {
                let mut out = String::new();
                child.stdout.take()?.read_to_string(&mut out).ok()?;
                return status.success().then_some(out);
            }
            Ok(None) if start.elapsed() < limit => std::thread::sleep(Duration::from_millis(2)),
            _ => {
                let _ = child.kill();
                let _ = child.wait();
                return None;
            }
        }
    }
}

/// Longest wait for `tmux` or `infocmp`.
const LOOKUP_LIMIT: Duration = Duration::from_millis(500);

/// What tmux says of the client showing `pane` (`$TMUX_PANE`), when tmux
/// answers.
pub fn ask_tmux(pane: Option<&str>) -> Option<TmuxClient> {
    let mut args = vec!["display-message", "-p"];
    if let Some(pane) = pane {
        args.extend(["-t", pane]);
    }
    args.push("#{client_termfeatures}\t#{client_termname}");
    let out = run_briefly("tmux", &args, LOOKUP_LIMIT)?;
    let line = out.lines().next().unwrap_or("");
    let (features, termname) = line.split_once('\t').unwrap_or((line, ""));
    Some(TmuxClient {
        features: features.trim().to_string(),
        termname: termname.trim().to_string(),
    })
}

/// The terminfo entry of `name` with extended capabilities, from `infocmp`.
pub fn infocmp(name: &str) -> Option<String> {
    // A name is a terminfo file name: no path, no option.
    if name.starts_with('-') || name.contains('/') {
        return None;
    }
    run_briefly("infocmp", &["-x", "-1", name], LOOKUP_LIMIT)
}

/// [`settled`] for this process: its environment, tmux when `$TMUX` is
/// set, `infocmp`.
pub fn settled_here() -> Option<DepthChoice> {
    let colorterm = std::env::var("COLORTERM").ok();
    let term = std::env::var("TERM").ok();
    let tmux = std::env::var_os("TMUX")
        .filter(|v| !v.is_empty())
        .and_then(|_| ask_tmux(std::env::var("TMUX_PANE").ok().as_deref()));
    settled(
        colorterm.as_deref(),
        term.as_deref(),
        tmux.as_ref(),
        &infocmp,
    )
}

/// [`fallback`] for this process.
pub fn fallback_here() -> DepthChoice {
    let colorterm = std::env::var("COLORTERM").ok();
    let term = std::env::var("TERM").ok();
    fallback(colorterm.as_deref(), term.as_deref())
}

#[cfg(test)]
mod tests {
    use super::*;

    const XTERM_DIRECT: &str = "xterm-direct|xterm with direct-colour indexing,\n\tam,\n\tRGB,\n\tcolors#0x1000000,\n\tsetaf=\\E[%?%p1%{8}%<%t3%p1%d%e38:2::%p1%{65536}%/%d:%p1%{256}%/%{255}%&%d:%p1%{255}%&%d%;m,\n";
    const XTERM_256: &str = "xterm-256color|xterm with 256 colors,\n\tam,\n\tcolors#0x100,\n\tTc@,\n\tsetaf=\\E[38;5;%p1%dm,\n";
    const TC: &str = "tmux-256color|tmux,\n\tTc,\n\tsetrgbfx=\\E[,\n";

    fn lookup(name: &str) -> Option<String> {
        match name {
            "xterm-direct-ish" => Some(XTERM_DIRECT.into()),
            "xterm-256color" => Some(XTERM_256.into()),
            "with-tc" => Some(TC.into()),
            "with-setrgbf" => Some("x|y,\n\tsetrgbf=\\E[38;2;%p1%d;%p2%d;%p3%dm,\n".into()),
            _ => None,
        }
    }

    #[test]
    fn terminfo_capabilities_are_read_by_name() {
        assert_eq!(terminfo_truecolor(XTERM_DIRECT), Some("RGB"));
        // Cancelled, or a longer name that starts the same: not counted.
        assert_eq!(terminfo_truecolor(XTERM_256), None);
        assert_eq!(terminfo_truecolor(TC), Some("Tc"));
        assert_eq!(
            terminfo_truecolor(&lookup("with-setrgbf").unwrap()),
            Some("setrgbf")
        );
        assert_eq!(terminfo_truecolor(""), None);
    }

    #[test]
    fn the_environment_comes_first_then_tmux_then_terminfo() {
        let s = |ct, term, tmux: Option<&TmuxClient>| {
            settled(ct, term, tmux, &lookup).map(|c| (c.depth, c.source))
        };
        let tc = ColorDepth::Truecolor;
        let p256 = ColorDepth::Palette256;
        let rgb = TmuxClient {
            features: "bpaste,clipboard,RGB,title".into(),
            termname: "xterm-256color".into(),
        };
        let no_rgb = TmuxClient {
            features: "bpaste,clipboard,title".into(),
            termname: "xterm-direct-ish".into(),
        };
        let old = TmuxClient {
            features: String::new(),
            termname: "with-tc".into(),
        };
        assert_eq!(
            s(Some("24bit"), None, Some(&no_rgb)),
            Some((tc, "COLORTERM".into()))
        );
        assert_eq!(
            s(None, Some("xterm-direct"), None),
            Some((tc, "TERM -direct".into()))
        );
        assert_eq!(
            s(None, Some("tmux-256color"), Some(&rgb)),
            Some((tc, "tmux client RGB".into()))
        );
        // tmux without RGB turns 24-bit colours into its palette itself,
        // whatever the client's terminfo says.
        assert_eq!(
            s(None, Some("with-tc"), Some(&no_rgb)),
            Some((p256, "tmux client no RGB".into()))
        );
        assert_eq!(
            s(None, Some("screen"), Some(&old)),
            Some((tc, "tmux client terminfo Tc".into()))
        );
        // No client attached: TERM's terminfo, then the terminal is asked.
        let detached = TmuxClient::default();
        assert_eq!(
            s(None, Some("with-setrgbf"), Some(&detached)),
            Some((tc, "terminfo setrgbf".into()))
        );
        assert_eq!(s(None, Some("xterm-256color"), Some(&detached)), None);
        assert_eq!(s(Some("yes"), Some("unknown"), None), None);
        assert_eq!(s(None, None, None), None);
    }

    #[test]
    fn the_fallback_says_why() {
        assert_eq!(
            fallback(None, Some("linux")),
            DepthChoice::new(ColorDepth::Palette16, "TERM")
        );
        assert_eq!(
            fallback(None, Some("xterm")),
            DepthChoice::new(ColorDepth::Palette256, "no sign of 24-bit")
        );
    }

    #[test]
    fn a_missing_or_failing_program_is_none() {
        assert_eq!(
            run_briefly("relief-no-such-program", &[], LOOKUP_LIMIT),
            None
        );
        assert_eq!(
            run_briefly("sh", &["-c", "echo x; exit 3"], LOOKUP_LIMIT),
            None
        );
        assert_eq!(
            run_briefly("sh", &["-c", "echo ok"], LOOKUP_LIMIT).as_deref(),
            Some("ok\n")
        );
        // Too slow: killed.
        assert_eq!(
            run_briefly("sh", &["-c", "sleep 5"], Duration::from_millis(50)),
            None
        );
    }
}
