//! relief through a real `ssh -tt` over a slow link: lag and bytes per input.
//!
//! Another build of relief (another branch, say) is measured by giving its binary:
//! `RELIEF_SSH_BIN=/path/to/relief cargo test --release --test ssh_link -- --ignored --nocapture`
//!
//! Each session builds its own network namespaces, a rate-limited link with 20 ms each
//! way, an sshd and a tmux pane (160×48) running `ssh -tt server relief --color …` (see
//! `tests/ssh/mod.rs`). Then: one arrow key, 20 arrow keys 30 ms apart, a 40-step mouse
//! drag in 0.8 s, and `q` right after a second drag. For each, the bytes that crossed the
//! link towards the client and the time from the last input to the final picture: the
//! pane is captured every ~10 ms, and the final picture is the one that then stays
//! unchanged for 1.5 s; the lag is when it first appeared. For `q`, the time until the
//! pane shows the shell again with the alternate screen left.
//!
//! The assertions are functional only (the final picture shows the expected orientation,
//! `q` restores the terminal, nothing is left behind); the times and bytes are printed
//! as a Markdown table. Needs root, iproute2 (`ip netns`, `tc`), OpenSSH (client and
//! server) and tmux; skipped with a notice otherwise.
//!
//! `cargo test --release --test ssh_link` runs one session at 8 Mbit/s (~20 s). The full
//! measurement (1 and 8 Mbit/s, 3 sessions each, medians):
//!
//! ```sh
//! cargo test --release --test ssh_link -- --ignored --nocapture
//! ```
//!
//! Environment (all optional):
//! - `RELIEF_SSH_BIN=/path/to/relief` the binary run on the server (default: this
//!   checkout's release binary)
//! - `RELIEF_SSH_COLOR=truecolor` relief's `--color` (`256`, `16`)
//! - `RELIEF_SSH_RATES=1000,8000` link rates of the full run, in kbit/s
//! - `RELIEF_SSH_REPS=3` sessions per rate in the full run (interleaved across rates)
//! - `RELIEF_SSH_MUX=tmux` relief runs inside tmux on the server (`tmux new-session`
//!   in the `ssh -tt` session, status bar off)

mod ssh;

use std::collections::BTreeMap;
use std::path::PathBuf;
use std::time::{Duration, Instant};

use ssh::{EXITED, Mux, Options, QueueSampler, Session};

/// How long the picture must stay unchanged to be the final one.
const SETTLE: Duration = Duration::from_millis(1500);
/// Longest wait for any picture (far beyond the slowest link measured).
const TIMEOUT: Duration = Duration::from_secs(120);
const DELAY: Duration = Duration::from_millis(20);
/// Orientation at start (`--rotate` default).
const START: [i32; 3] = [25, 35, 0];
/// The drag: press at this cell, then 40 steps one column left, one row down every
/// fourth step: 40 columns left (Y −80°) and 10 rows down (X +40°).
const DRAG_FROM: (i32, i32) = (100, 20);
const DRAG_STEPS: i32 = 40;

/// One measured input of one session.
struct Figure {
    input: &'static str,
    /// Bytes towards the client (none for the round trip).
    bytes: Option<u64>,
    lag: Duration,
    /// The largest send queue of the server's socket from the last input on.
    queued: Option<u64>,
}

/// The multiplexer `RELIEF_SSH_MUX` names (`tmux`, `screen`), if any.
fn env_mux() -> Option<Mux> {
    let name = std::env::var("RELIEF_SSH_MUX").ok()?;
    Some(
        Mux::from_name(&name)
            .unwrap_or_else(|| panic!("RELIEF_SSH_MUX: tmux or screen, not {name}")),
    )
}

fn options(rate_kbit: u32, server_mux: Option<Mux>) -> Options {
    let binary = std::env::var_os("RELIEF_SSH_BIN")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_BIN_EXE_relief")));
    let binary = std::fs::canonicalize(&binary)
        .unwrap_or_else(|e| panic!("relief binary {}: {e}", binary.display()));
    Options {
        binary,
        rate_kbit,
        delay: DELAY,
        color: std::env::var("RELIEF_SSH_COLOR").unwrap_or_else(|_| "truecolor".into()),
        width: 160,
        height: 48,
        server_mux,
        relief_args: std::env::var("RELIEF_SSH_ARGS")
            .map(|a| a.split_whitespace().map(String::from).collect())
            .unwrap_or_default(),
    }
}

/// The session, or `None` after a printed notice when it cannot be had here.
fn session(opts: &Options) -> Option<Session> {
    if let Some(why) = ssh::missing_for(opts.server_mux) {
        println!("ssh link test skipped: {why}");
        return None;
    }
    match Session::start(opts) {
        Ok(s) => Some(s),
        Err(ssh::Unavailable(why)) => {
            println!("ssh link test skipped: {why}");
            None
        }
    }
}

/// Polls the pane until its picture differs from `before` and then stays the same
/// for `SETTLE`; returns the final picture and how long after `input` it first appeared.
fn final_picture(s: &Session, before: &str, input: Instant, what: &str) -> (String, Duration) {
    final_picture_where(s, input, what, |p| p != before)
}

/// Polls the pane until its picture satisfies `ok` and then stays the same for
/// `SETTLE`; returns the final picture and how long after `input` it first appeared.
fn final_picture_where(
    s: &Session,
    input: Instant,
    what: &str,
    ok: impl Fn(&str) -> bool,
) -> (String, Duration) {
    let mut last = String::new();
    let mut appeared = input;
    loop {
        let picture = s.picture();
        let now = Instant::now();
        if picture != last {
            last = picture;
            appeared = now;
        } else if ok(&last) && now - appeared >= SETTLE {
            return (last, appeared.saturating_duration_since(input));
        }
        if now - input > TIMEOUT {
            panic!("no final picture after {what}; screen:\n{}", s.screen());
        }
        std::thread::sleep(Duration::from_millis(10));
    }
}

/// The orientation fields of the screen's text (` X     25° Y     40° Z      0°`).
fn orientation(screen: &str) -> Option<[i32; 3]> {
    let line = screen
        .lines()
        .find(|l| l.trim_start().starts_with("X ") && l.contains('°'))?;
    let mut out = [0; 3];
    for (i, axis) in ["X", "Y", "Z"].iter().enumerate() {
        let rest = line.split(&format!("{axis} ")).nth(1)?;
        out[i] = rest.split('°').next()?.trim().parse().ok()?;
    }
    Some(out)
}

fn status(screen: &str) -> &str {
    screen
        .lines()
        .rev()
        .find(|l| !l.trim().is_empty())
        .unwrap_or("")
}

/// Waits for the final picture after `input`, checks the orientation it shows
/// and returns the figure (bytes counted from `bytes_before`).
#[allow(clippy::too_many_arguments)]
fn measure(
    s: &Session,
    q: &QueueSampler,
    name: &'static str,
    before: &str,
    bytes_before: u64,
    input: Instant,
    want: [i32; 3],
) -> Figure {
    let (_, lag) = final_picture(s, before, input, name);
    let bytes = s.bytes_to_client() - bytes_before;
    let screen = s.screen();
    assert_eq!(orientation(&screen), Some(want), "after {name}:\n{screen}");
    Figure {
        input: name,
        bytes: Some(bytes),
        lag,
        queued: peak(q, input),
    }
}

/// The largest send queue read from `from` on.
fn peak(q: &QueueSampler, from: Instant) -> Option<u64> {
    q.since(from).iter().map(|&(_, b)| b).max()
}

/// Sends the drag, one event every 20 ms (40 steps in 0.8 s), ending with the release.
fn drag(s: &Session) {
    let (c, r) = DRAG_FROM;
    let start = Instant::now();
    s.literal(&format!("\x1b[<0;{c};{r}M"));
    for i in 1..=DRAG_STEPS {
        let due = start + Duration::from_millis(20 * i as u64);
        std::thread::sleep(due.saturating_duration_since(Instant::now()));
        s.literal(&format!("\x1b[<32;{};{}M", c - i, r + i / 4));
    }
    s.literal(&format!(
        "\x1b[<0;{};{}m",
        c - DRAG_STEPS,
        r + DRAG_STEPS / 4
    ));
}

/// One session: connect, the four inputs, and checks that it all ends cleanly.
/// `None` when the session cannot be had here.
fn run_session(opts: &Options) -> Option<Vec<Figure>> {
    let s = session(opts)?;
    let q = s.queue_sampler();
    let mut figures = Vec::new();

    // Connecting (ssh's handshake included) up to the first full frame.
    let start = Instant::now();
    let (_, lag) = final_picture_where(&s, start, "the first frame", |p| p.contains("Phong"));
    let screen = s.screen();
    assert!(
        status(&screen).starts_with("Phong │"),
        "{screen}\n{}",
        s.sshd_log()
    );
    assert_eq!(orientation(&screen), Some(START), "{screen}");
    let bytes = s.bytes_since_pane_start();
    figures.push(Figure {
        input: "connect, first frame",
        bytes: Some(bytes),
        lag,
        queued: None,
    });
    // The link's round trip, idle (what a terminal query's answer takes at least).
    figures.push(Figure {
        input: "round trip (TCP connect, idle link)",
        bytes: None,
        lag: s.round_trip(),
        queued: None,
    });

    // One arrow key: Y + 5°.
    let before = s.picture();
    let b0 = s.bytes_to_client();
    s.keys(&["Right"]);
    let input = Instant::now();
    let [x, y, z] = START;
    figures.push(measure(
        &s,
        &q,
        "one arrow key",
        &before,
        b0,
        input,
        [x, y + 5, z],
    ));

    // 20 arrow keys 30 ms apart: Y + 100°.
    let before = s.picture();
    let b0 = s.bytes_to_client();
    let t0 = Instant::now();
    for i in 0..20 {
        std::thread::sleep(
            (t0 + Duration::from_millis(30 * i)).saturating_duration_since(Instant::now()),
        );
        s.keys(&["Right"]);
    }
    let input = Instant::now();
    let want = [x, y + 105, z];
    figures.push(measure(
        &s,
        &q,
        "20 arrow keys, 30 ms apart",
        &before,
        b0,
        input,
        want,
    ));

    // The drag: X + 40°, Y − 80°.
    let before = s.picture();
    let b0 = s.bytes_to_client();
    drag(&s);
    let input = Instant::now();
    let want = [x + 40, y + 25, z];
    figures.push(measure(
        &s,
        &q,
        "40-step mouse drag in 0.8 s",
        &before,
        b0,
        input,
        want,
    ));

    // Another drag, and `q` right after its release: the shell again.
    let b0 = s.bytes_to_client();
    drag(&s);
    s.keys(&["q"]);
    let input = Instant::now();
    loop {
        let out = s.tmux(&[
            "capture-pane",
            "-p",
            ";",
            "display-message",
            "-p",
            "#{alternate_on}",
        ]);
        if out.contains(EXITED) && out.trim_end().ends_with('0') {
            break;
        }
        assert!(input.elapsed() < TIMEOUT, "q did not end relief:\n{out}");
        std::thread::sleep(Duration::from_millis(10));
    }
    let lag = input.elapsed();
    figures.push(Figure {
        input: "`q` right after a drag (screen restored)",
        bytes: Some(s.bytes_to_client() - b0),
        lag,
        queued: peak(&q, input),
    });
    drop(q);
    assert_restored(&s);

    let (namespaces, dir) = s.leftovers();
    drop(s);
    let listed = std::process::Command::new("ip")
        .args(["netns", "list"])
        .output()
        .unwrap();
    let listed = String::from_utf8_lossy(&listed.stdout);
    for ns in namespaces {
        assert!(!listed.contains(&ns), "namespace {ns} left behind");
    }
    assert!(!dir.exists(), "{} left behind", dir.display());
    Some(figures)
}

/// relief ended with status 0 and left the terminal as it found it.
fn assert_restored(s: &Session) {
    assert_eq!(s.format("#{alternate_on}"), "0", "alternate screen left");
    assert_eq!(s.format("#{mouse_any_flag}"), "0", "mouse reporting off");
    assert_eq!(s.format("#{mouse_sgr_flag}"), "0", "SGR mouse off");
    assert_eq!(s.format("#{cursor_flag}"), "1", "cursor visible");
    let screen = s.screen();
    assert!(
        screen.contains(&format!("{EXITED}0")),
        "relief's exit status:\n{screen}"
    );
    assert!(
        !screen.contains('▀') && !screen.contains('▄'),
        "picture left on the shell screen:\n{screen}"
    );
}

fn median<T: Copy + Ord>(mut v: Vec<T>) -> T {
    v.sort();
    v[v.len() / 2]
}

fn rate_name(kbit: u32) -> String {
    if kbit.is_multiple_of(1000) {
        format!("{} Mbit/s", kbit / 1000)
    } else {
        format!("{kbit} kbit/s")
    }
}

/// The Markdown table: per rate and input, the median bytes, lag and peak send
/// queue over the sessions.
fn table(runs: &[(u32, Vec<Figure>)], opts: &Options) -> String {
    // (rate, input's place) -> (input, bytes, lag and queue of each session)
    type Row<'a> = (&'a str, Vec<Option<u64>>, Vec<Duration>, Vec<Option<u64>>);
    let mut by: BTreeMap<(u32, usize), Row> = BTreeMap::new();
    for (rate, figures) in runs {
        for (i, f) in figures.iter().enumerate() {
            let e = by
                .entry((*rate, i))
                .or_insert((f.input, Vec::new(), Vec::new(), Vec::new()));
            e.1.push(f.bytes);
            e.2.push(f.lag);
            e.3.push(f.queued);
        }
    }
    let kb = |b: Option<u64>| b.map_or("—".into(), |b| format!("{:.0} kB", b as f64 / 1000.0));
    let mut out = format!(
        "relief{} over ssh -tt, 160x48, --color {} {}, link 20 ms each way ({})\n\n\
         | link | input | bytes to client | time: last input → final picture | range | n | peak send queue |\n\
         |---|---|--:|--:|--:|--:|--:|\n",
        opts.server_mux.map_or(String::new(), |m| format!(
            " inside {} on the server",
            m.program()
        )),
        opts.color,
        opts.relief_args.join(" "),
        opts.binary.display(),
    );
    for ((rate, _), (input, bytes, lags, queued)) in by {
        let n = lags.len();
        let (lo, hi) = (*lags.iter().min().unwrap(), *lags.iter().max().unwrap());
        out += &format!(
            "| {} | {input} | {} | {:.3} s | {:.3}–{:.3} s | {n} | {} |\n",
            rate_name(rate),
            kb(median(bytes)),
            median(lags).as_secs_f64(),
            lo.as_secs_f64(),
            hi.as_secs_f64(),
            kb(median(queued)),
        );
    }
    out
}

fn env_list(name: &str, default: &str) -> Vec<u32> {
    std::env::var(name)
        .unwrap_or_else(|_| default.into())
        .split(',')
        .map(|v| {
            v.trim()
                .parse()
                .unwrap_or_else(|_| panic!("{name}: not a number: {v}"))
        })
        .collect()
}

fn report(runs: &[(u32, Vec<Figure>)], mux: Option<Mux>) {
    println!("{}", table(runs, &options(1, mux)));
}

/// One session at 8 Mbit/s: everything works through real SSH; the figures printed.
#[test]
fn keys_drag_and_quit_over_a_slow_ssh_link() {
    let Some(figures) = run_session(&options(8000, None)) else {
        return;
    };
    report(&[(8000, figures)], None);
}

/// The full measurement: every rate, several sessions each, medians.
#[test]
#[ignore = "the full measurement (minutes): cargo test --release --test ssh_link -- --ignored --nocapture"]
fn measure_lag_and_bytes_over_ssh() {
    let rates = env_list("RELIEF_SSH_RATES", "1000,8000");
    let reps = env_list("RELIEF_SSH_REPS", "3")[0];
    let mux = env_mux();
    let mut runs = Vec::new();
    for rep in 0..reps {
        for &rate in &rates {
            eprintln!("session {} of {reps} at {}", rep + 1, rate_name(rate));
            let Some(figures) = run_session(&options(rate, mux)) else {
                return;
            };
            runs.push((rate, figures));
        }
    }
    report(&runs, mux);
}
