//! relief through a real `ssh -tt` over a slow link: lag and bytes per input.
//!
//! Another build of relief (another branch, say) is measured by giving its binary:
//! `RELIEF_SSH_BIN=/path/to/relief cargo test --release --test suite ssh_link::measure -- --ignored --nocapture`
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
//! The server's send queue towards the client (sshd's socket in the server's
//! `/proc/net/tcp`) is read every 10 ms; its peak after the last input is printed.
//!
//! The assertions are functional (the final picture shows the expected orientation,
//! `q` restores the terminal, nothing is left behind) and, inside a multiplexer, count
//! bytes: what crosses the link after the last input and what the send queue holds
//! stay within a few frames (no backlog). Times are printed as a Markdown table, never
//! asserted. Needs root, iproute2 (`ip netns`, `tc`), OpenSSH (client and server) and
//! tmux (GNU screen for its case): every test here is ignored in a plain `cargo test`,
//! and fails, saying what is missing, when run without them.
//!
//! `.ci/run` installs them and runs by name one plain session at 8 Mbit/s, one inside
//! tmux and one inside screen at 1 Mbit/s, and one each with `--format kitty` and
//! `--format sixels` at 1 Mbit/s (~100 s; the tests ignored as "end-to-end"). Pixel pictures are not in the pane's
//! text: the exact picture is complete when the link goes quiet (`Session::link_sampler`);
//! what the pane received is recorded (`tmux pipe-pane`), and the final picture after the
//! drag is checked by its bytes and order (`final_picture_in_time`). Plain SSH against tmux and
//! screen at 1 and 50 Mbit/s, 3 sessions each, interleaved:
//!
//! ```sh
//! cargo test --release --test suite ssh_link::compare -- --ignored --nocapture
//! ```
//!
//! The full measurement (1 and 8 Mbit/s, 3 sessions each, medians):
//!
//! ```sh
//! cargo test --release --test suite ssh_link::measure -- --ignored --nocapture
//! ```
//!
//! Environment (all optional):
//! - `RELIEF_SSH_BIN=/path/to/relief` the binary run on the server (default: this
//!   checkout's release binary)
//! - `RELIEF_SSH_COLOR=truecolor` relief's `--color` (`256`, `16`)
//! - `RELIEF_SSH_RATES=1000,8000` link rates of the full run, in kbit/s
//! - `RELIEF_SSH_REPS=3` sessions per rate in the full run (interleaved across rates)
//! - `RELIEF_SSH_MUX=tmux` relief runs inside tmux on the server (`tmux new-session`
//!   in the `ssh -tt` session, status bar off); `screen`: inside GNU screen
//! - `RELIEF_SSH_ARGS="--link 1M"` more arguments of relief
//! - `RELIEF_SSH_TRACE=1` prints the server's send queue through the drag

use std::collections::BTreeMap;
use std::path::PathBuf;
use std::sync::{Mutex, MutexGuard};
use std::time::{Duration, Instant};

use crate::glb_writer;
use crate::ssh::{self, EXITED, LinkSampler, Mux, Options, PaneRecorder, QueueSampler, Session};

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
#[derive(Clone)]
struct Figure {
    input: &'static str,
    /// Bytes towards the client (none for the round trip).
    bytes: Option<u64>,
    lag: Duration,
    /// The largest send queue of the server's socket from the last input on.
    queued: Option<u64>,
    /// Bytes towards the client from the last input on.
    after: Option<u64>,
}

/// The moment of the last input and the link's byte count then.
struct LastInput {
    at: Instant,
    bytes: u64,
}

fn last_input(s: &Session) -> LastInput {
    let at = Instant::now();
    LastInput {
        at,
        bytes: s.bytes_to_client(),
    }
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

/// The session; the test fails, saying why, when it cannot be had here.
fn session(opts: &Options) -> Session {
    if let Some(why) = ssh::missing_for(opts.server_mux) {
        panic!("this test cannot run here: {why}");
    }
    match Session::start(opts) {
        Ok(s) => s,
        Err(ssh::Unavailable(why)) => panic!("this test cannot run here: {why}"),
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
    input: LastInput,
    want: [i32; 3],
) -> Figure {
    let (_, lag) = final_picture(s, before, input.at, name);
    let end = s.bytes_to_client();
    let screen = s.screen();
    assert_eq!(orientation(&screen), Some(want), "after {name}:\n{screen}");
    Figure {
        input: name,
        bytes: Some(end - bytes_before),
        lag,
        queued: peak(q, input.at),
        after: Some(end - input.bytes),
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
fn run_session(opts: &Options) -> Vec<Figure> {
    let s = session(opts);
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
        after: None,
    });
    // The link's round trip, idle (what a terminal query's answer takes at least).
    figures.push(Figure {
        input: "round trip (TCP connect, idle link)",
        bytes: None,
        lag: s.round_trip(),
        queued: None,
        after: None,
    });

    // One arrow key: Y + 5°.
    let before = s.picture();
    let b0 = s.bytes_to_client();
    s.keys(&["Right"]);
    let input = last_input(&s);
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
    let input = last_input(&s);
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
    let input = last_input(&s);
    let want = [x + 40, y + 25, z];
    let drag_start = input.at - Duration::from_millis(20 * DRAG_STEPS as u64);
    let fig = measure(
        &s,
        &q,
        "40-step mouse drag in 0.8 s",
        &before,
        b0,
        input,
        want,
    );
    if std::env::var_os("RELIEF_SSH_TRACE").is_some() {
        // The send queue through the drag and after it: ms since the drag began, kB.
        let trace: Vec<String> = q
            .since(drag_start)
            .iter()
            .map(|(t, b)| format!("{}:{:.1}", (*t - drag_start).as_millis(), *b as f64 / 1e3))
            .collect();
        eprintln!("send queue during the drag (ms:kB): {}", trace.join(" "));
    }
    figures.push(fig);

    // Another drag, and `q` right after its release: the shell again.
    let b0 = s.bytes_to_client();
    drag(&s);
    s.keys(&["q"]);
    let last = last_input(&s);
    let input = last.at;
    wait_until_ended(&s, input);
    let lag = input.elapsed();
    figures.push(Figure {
        input: "`q` right after a drag (screen restored)",
        bytes: Some(s.bytes_to_client() - b0),
        lag,
        queued: peak(&q, input),
        after: Some(s.bytes_to_client() - last.bytes),
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
    figures
}

/// Polls until the pane shows the shell again (relief's exit and the
/// alternate screen left), `input` being when `q` was sent.
fn wait_until_ended(s: &Session, input: Instant) {
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
            return;
        }
        assert!(input.elapsed() < TIMEOUT, "q did not end relief:\n{out}");
        std::thread::sleep(Duration::from_millis(10));
    }
}

/// Polls the pane's text until `ok`; returns it.
fn wait_for(s: &Session, input: Instant, what: &str, ok: impl Fn(&str) -> bool) -> String {
    loop {
        let screen = s.screen();
        if ok(&screen) {
            return screen;
        }
        if input.elapsed() > TIMEOUT {
            panic!("nothing after {what}; screen:\n{screen}");
        }
        std::thread::sleep(Duration::from_millis(10));
    }
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
    type Row<'a> = (
        &'a str,
        Vec<Option<u64>>,
        Vec<Duration>,
        Vec<Option<u64>>,
        Vec<Option<u64>>,
    );
    let mut by: BTreeMap<(u32, usize), Row> = BTreeMap::new();
    for (rate, figures) in runs {
        for (i, f) in figures.iter().enumerate() {
            let e = by.entry((*rate, i)).or_insert((
                f.input,
                Vec::new(),
                Vec::new(),
                Vec::new(),
                Vec::new(),
            ));
            e.1.push(f.bytes);
            e.2.push(f.lag);
            e.3.push(f.queued);
            e.4.push(f.after);
        }
    }
    let kb = |b: Option<u64>| b.map_or("—".into(), |b| format!("{:.0} kB", b as f64 / 1000.0));
    let mut out = format!(
        "relief{} over ssh -tt, 160x48, --color {} {}, link 20 ms each way ({})\n\n\
         | link | input | bytes to client | time: last input → final picture | range | n | peak send queue | bytes after the last input |\n\
         |---|---|--:|--:|--:|--:|--:|--:|\n",
        opts.server_mux.map_or(String::new(), |m| format!(
            " inside {} on the server",
            m.program()
        )),
        opts.color,
        opts.relief_args.join(" "),
        opts.binary.display(),
    );
    for ((rate, _), (input, bytes, lags, queued, after)) in by {
        let n = lags.len();
        let (lo, hi) = (*lags.iter().min().unwrap(), *lags.iter().max().unwrap());
        out += &format!(
            "| {} | {input} | {} | {:.3} s | {:.3}–{:.3} s | {n} | {} | {} |\n",
            rate_name(rate),
            kb(median(bytes)),
            median(lags).as_secs_f64(),
            lo.as_secs_f64(),
            hi.as_secs_f64(),
            kb(median(queued)),
            kb(median(after)),
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

/// Sessions one at a time: the figures printed are not those of a shared machine.
static ONE_AT_A_TIME: Mutex<()> = Mutex::new(());

fn one_at_a_time() -> MutexGuard<'static, ()> {
    ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner())
}

/// One session at 8 Mbit/s: everything works through real SSH; the figures printed.
#[test]
#[ignore = "end-to-end: needs root, iproute2, OpenSSH and tmux; .ci/run runs it by name"]
fn keys_drag_and_quit_over_a_slow_ssh_link() {
    let _one = one_at_a_time();
    let figures = run_session(&options(8000, None));
    report(&[(8000, figures)], None);
}

/// What 1 Mbit/s carries in the hold's acknowledgement delay (40 ms):
/// the queue a frame may join (`crates/term/src/hold.rs`).
const ALLOWANCE_1_MBIT: u64 = 125_000 * 40 / 1000;

/// The link carried the newest frames, not a backlog of stale ones. The pacing keeps
/// one frame on the link: from the last input on, what crosses it is the rest of the
/// frame in flight, at most one preview sent before input counts as stopped, and the
/// exact picture (with the status line's refresh) — three frames, an exact frame
/// being what one arrow key took; half a frame more is allowed because the last
/// picture of a turn need not cost what the first key's did (inside screen, which
/// re-encodes every cell, one run on a loaded machine sent 3.04 such frames). The server's send queue then holds at most
/// a frame and what the hold lets stay unacknowledged when the next one goes: what
/// the link carries in the hold's 40 ms (5 kB at 1 Mbit/s), up to one frame more —
/// two frames and those 5 kB (screen's 8 kB frames once peaked at 17 kB). Without the
/// pacing, inside a multiplexer the multiplexer queues seconds of frames: the send
/// queue stays at the kernel's send buffer (80 kB) and about 900 kB follow the last
/// input at 1 Mbit/s (docs/ssh-tmux.md).
fn assert_no_backlog(figures: &[Figure]) {
    let frame = figures
        .iter()
        .find(|f| f.input == "one arrow key")
        .and_then(|f| f.bytes)
        .expect("one arrow key measured");
    for f in figures.iter().filter(|f| f.input != "one arrow key") {
        if let Some(after) = f.after {
            assert!(
                after <= 3 * frame + frame / 2,
                "{}: {after} bytes crossed the link after the last input, more than \
                 three and a half frames of {frame}",
                f.input
            );
        }
        if let Some(queued) = f.queued {
            assert!(
                queued <= 2 * frame + ALLOWANCE_1_MBIT,
                "{}: the send queue held {queued} bytes, more than two frames of {frame} \
                 and {ALLOWANCE_1_MBIT} bytes",
                f.input
            );
        }
    }
}

/// relief inside a multiplexer on the server at 1 Mbit/s: everything works, and
/// frames are paced by the SSH connection (no backlog); the figures printed.
fn inside_a_multiplexer(mux: Mux) {
    let _one = one_at_a_time();
    let opts = options(1000, Some(mux));
    let figures = run_session(&opts);
    report(&[(1000, figures.clone())], Some(mux));
    assert_no_backlog(&figures);
}

#[test]
#[ignore = "end-to-end: needs root, iproute2, OpenSSH and tmux; .ci/run runs it by name"]
fn inside_tmux_on_the_server_frames_are_paced_by_the_ssh_connection() {
    inside_a_multiplexer(Mux::Tmux);
}

#[test]
#[ignore = "end-to-end: needs root, iproute2, OpenSSH, tmux and GNU screen; .ci/run runs it by name"]
fn inside_screen_on_the_server_frames_are_paced_by_the_ssh_connection() {
    inside_a_multiplexer(Mux::Screen);
}

/// Waits until bytes crossed the link towards the client after `input` and then
/// none for `SETTLE`; returns when the last one crossed, after `input`, and the
/// link's total then.
fn link_quiet(link: &LinkSampler, input: Instant, what: &str) -> (Duration, u64) {
    loop {
        if let Some((at, total)) = link.quiet_since(SETTLE)
            && at > input
        {
            return (at - input, total);
        }
        assert!(
            input.elapsed() < TIMEOUT,
            "the link never went quiet after {what}"
        );
        std::thread::sleep(Duration::from_millis(10));
    }
}

/// One session at 1 Mbit/s with relief sending real pixels (`--format kitty` or
/// `sixels`, forced: the client's tmux draws neither, so the pane shows only the
/// text around the image). The picture is an image, so the final one is when the
/// link goes quiet: the last byte of the last frame crossed it. Once the first
/// frame's text is on screen (its picture still coming: no reply has measured the
/// link yet), one arrow key, whose final picture must come in time (by bytes,
/// [`final_picture_in_time`]: the first frame does not hold it back); then the drag
/// (the same check) and an idle second, and `q`.
fn pixels_over_a_slow_link(format: &str) -> Vec<Figure> {
    let mut opts = options(1000, None);
    opts.relief_args
        .splice(0..0, ["--format".to_string(), format.to_string()]);
    let s = session(&opts);
    let link = s.link_sampler();
    let q = s.queue_sampler();
    let pane = s.record_pane();
    let start = Instant::now();
    let (_, appeared) = final_picture_where(&s, start, "the first frame", |p| p.contains("Phong"));
    let mut figures = vec![Figure {
        input: "connect, first frame's text (+1.5 s)",
        bytes: Some(s.bytes_since_pane_start()),
        lag: appeared,
        queued: None,
        after: None,
    }];
    let [x, y, z] = START;

    // The key lands while the first frame's strips come, as the check
    // below means: the status text can come before the link-sized picture
    // is through, and a key then would land on that picture instead.
    wait_for_a_strip(&pane);
    let b0 = s.bytes_to_client();
    let p0 = pane.received();
    s.keys(&["Right"]);
    let input = last_input(&s);
    let received_then = pane.received();
    let (lag, end) = link_quiet(&link, input.at, "one arrow key");
    let screen = s.screen();
    assert_eq!(orientation(&screen), Some([x, y + 5, z]), "{screen}");
    // The strip of the first frame in flight goes first: a cell row of the
    // exact frame, 26 kB in kitty at 1280 pixels wide.
    let shown = final_picture_in_time(&pane, received_then, (end - b0, pane.received() - p0), true);
    figures.push(shown.figure(
        "arrow key during the first frame: final picture (link-sized)",
        input.at,
    ));
    let frame = end - b0;
    figures.push(Figure {
        input: "one arrow key",
        bytes: Some(frame),
        lag,
        queued: peak(&q, input.at),
        after: Some(end - input.bytes),
    });

    let b0 = s.bytes_to_client();
    let p0 = pane.received();
    drag(&s);
    let input = last_input(&s);
    let received_then = pane.received();
    let (lag, end) = link_quiet(&link, input.at, "the drag");
    let screen = s.screen();
    // Angles show within 0°–360°.
    assert_eq!(
        orientation(&screen),
        Some([x + 40, (y + 5 - 80).rem_euclid(360), z]),
        "{screen}"
    );
    // The exact picture, not a preview: the status line shows its time.
    assert!(!status(&screen).contains("preview"), "{screen}");
    let shown = final_picture_in_time(
        &pane,
        received_then,
        (end - b0, pane.received() - p0),
        false,
    );
    figures.push(shown.figure("40-step drag: final picture (link-sized)", input.at));
    figures.push(Figure {
        input: "40-step mouse drag in 0.8 s",
        bytes: Some(end - b0),
        lag,
        queued: peak(&q, input.at),
        after: Some(end - input.bytes),
    });
    // Idle: nothing more is written (the link quiet for another second).
    std::thread::sleep(Duration::from_secs(1));
    assert_eq!(s.bytes_to_client(), end, "bytes written while idle");
    assert_no_backlog(&figures);

    s.keys(&["q"]);
    let input = Instant::now();
    while !(s.screen().contains(EXITED) && s.format("#{alternate_on}") == "0") {
        assert!(
            input.elapsed() < TIMEOUT,
            "q did not end relief:\n{}",
            s.screen()
        );
        std::thread::sleep(Duration::from_millis(10));
    }
    drop((q, link));
    assert_restored(&s);
    figures
}

/// An image in what the pane received.
#[derive(Debug)]
struct ImageSent {
    /// Where its last byte is in the record.
    end: usize,
    /// kitty: relief's image (the picture, link-sized or exact), not a strip.
    /// sixel: filled in by [`images_sent`] for images as tall as the tallest.
    whole: bool,
    /// Its height: kitty in cell rows (`r=`), sixel in pixel rows.
    height: usize,
}

/// The images in `bytes`, in order: kitty's pictures (`a=T` of relief's image)
/// and strips (the placement, `a=p`, of a strip's image sent just before it),
/// sixel's images.
/// Waits until a strip of an exact frame has begun to reach the pane (so
/// the link-sized picture before it is through).
fn wait_for_a_strip(pane: &PaneRecorder) {
    let start = Instant::now();
    while !images_sent(&pane.bytes()).iter().any(|i| !i.whole) {
        assert!(
            start.elapsed() < TIMEOUT,
            "no strip of the first frame came"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
}

fn images_sent(bytes: &[u8]) -> Vec<ImageSent> {
    let find = |from: usize, needle: &[u8]| {
        bytes[from..]
            .windows(needle.len())
            .position(|w| w == needle)
            .map(|p| p + from)
    };
    let mut out = Vec::new();
    let mut i = 0;
    while let Some(at) = find(i, b"\x1b") {
        i = at + 1;
        let rest = &bytes[at..];
        if rest.starts_with(b"\x1b_Ga=T") {
            let keys_end = find(at, b";").unwrap_or(bytes.len());
            let keys = String::from_utf8_lossy(&bytes[at + 3..keys_end]).into_owned();
            let key = |name: &str| {
                keys.split(',')
                    .find_map(|k| k.strip_prefix(&format!("{name}=")))
                    .and_then(|v| v.parse::<u64>().ok())
            };
            // The chunks run to the one with `m=0`.
            let mut chunk = at;
            let mut end = bytes.len();
            while let Some(st) = find(chunk, b"\x1b\\") {
                let head =
                    String::from_utf8_lossy(&bytes[chunk..(chunk + 80).min(st)]).into_owned();
                if head.contains("m=0") {
                    end = st + 2;
                    break;
                }
                match find(st, b"\x1b_G") {
                    Some(next) => chunk = next,
                    None => break,
                }
            }
            out.push(ImageSent {
                end,
                whole: key("i") == Some(u64::from(relief_term::kitty::IMAGE_ID)),
                height: key("r").unwrap_or(0) as usize,
            });
            i = end;
        } else if rest.starts_with(b"\x1b_Ga=p") {
            let end = find(at, b"\x1b\\").map_or(bytes.len(), |st| st + 2);
            let keys = String::from_utf8_lossy(&bytes[at + 3..end.saturating_sub(2)]);
            let key = |name: &str| {
                keys.split(',')
                    .find_map(|k| k.strip_prefix(&format!("{name}=")))
                    .and_then(|v| v.parse::<u64>().ok())
            };
            if key("i") != Some(u64::from(relief_term::kitty::IMAGE_ID)) {
                out.push(ImageSent {
                    end,
                    whole: false,
                    height: key("r").unwrap_or(0) as usize,
                });
            }
            i = end;
        } else if rest.starts_with(b"\x1bP0;1;0q\"1;1;") {
            let raster = String::from_utf8_lossy(&rest[9..rest.len().min(40)]).into_owned();
            let height = raster
                .split(|c: char| !c.is_ascii_digit())
                .filter(|v| !v.is_empty())
                .nth(3)
                .and_then(|v| v.parse().ok())
                .unwrap_or(0);
            let end = find(at, b"\x1b\\").map_or(bytes.len(), |st| st + 2);
            out.push(ImageSent {
                end,
                whole: false,
                height,
            });
            i = end;
        }
    }
    if !bytes.windows(6).any(|w| w == b"\x1b_Ga=T") {
        let tallest = out.iter().map(|s| s.height).max().unwrap_or(0);
        for s in &mut out {
            s.whole = s.height == tallest;
        }
    }
    out
}

/// When the picture of the final orientation was shown after the drag.
struct FinalShown {
    /// Bytes the pane received from the last input until it was complete.
    bytes: u64,
    /// When the pane had received them.
    at: Option<Instant>,
}

impl FinalShown {
    /// The row of `input`'s final picture, its lag counted from `since`.
    fn figure(&self, input: &'static str, since: Instant) -> Figure {
        Figure {
            input,
            bytes: Some(self.bytes),
            lag: self
                .at
                .map_or(Duration::ZERO, |t| t.saturating_duration_since(since)),
            queued: None,
            after: None,
        }
    }
}

/// What "the final picture within 0.5 s of the last input" means here, checked by
/// bytes: the last image over the whole picture area (the exact frame scaled down
/// to what the link carries, relief's `pixel_view::LINK_SECONDS`) is complete after
/// at most what the link carries in 0.5 s has crossed it from the last input on
/// (the pane's bytes, scaled by the link's overhead over the whole drag, `link`
/// bytes for `pane` bytes); after it come only strips of the exact frame, top to
/// bottom, that cover the picture once. With `strip_in_flight`, the input came
/// while strips of an earlier exact frame were coming: the one in flight then
/// (the first image ending after `from`, when a strip) counts on top.
fn final_picture_in_time(
    pane: &PaneRecorder,
    from: u64,
    (link, received): (u64, u64),
    strip_in_flight: bool,
) -> FinalShown {
    let bytes = pane.bytes();
    let images = images_sent(&bytes);
    let last_whole = images
        .iter()
        .rposition(|i| i.whole)
        .expect("a picture over the whole area");
    let whole = &images[last_whole];
    let strips = &images[last_whole + 1..];
    let shown = (whole.end as u64).saturating_sub(from);
    let at = pane.reached(whole.end as u64);
    if std::env::var_os("RELIEF_SSH_BIN").is_some() {
        // Another build: its figures only.
        return FinalShown { bytes: shown, at };
    }
    assert!(
        whole.end as u64 > from,
        "the final picture came after the last input"
    );
    let overhead = link as f64 / received.max(1) as f64;
    let half_second = 1_000_000.0 / 8.0 * 0.5;
    // The strip in flight: from the image before it to its end.
    let next = images.iter().position(|i| i.end as u64 > from);
    let in_flight = match next {
        Some(k) if strip_in_flight && k < last_whole && !images[k].whole => {
            let start = k.checked_sub(1).map_or(0, |j| images[j].end);
            (images[k].end - start) as u64
        }
        _ => 0,
    };
    assert!(
        shown.saturating_sub(in_flight) as f64 * overhead <= half_second,
        "{shown} bytes ({in_flight} of them the strip in flight; ×{overhead:.3} on the \
         link) before the final picture: more than the link carries in 0.5 s ({half_second})"
    );
    // The strips cover the picture (kitty: its cell rows; sixel: its pixel rows).
    let covered: usize = strips.iter().map(|s| s.height).sum();
    assert!(!strips.is_empty(), "the exact frame follows in strips");
    assert_eq!(
        covered, whole.height,
        "the strips cover the picture once: {strips:?}"
    );
    FinalShown { bytes: shown, at }
}

/// A drag over a 1 Mbit/s link in kitty graphics: the final picture within what the
/// link carries in 0.5 s, then the exact one in strips; from the last input on at
/// most three exact frames cross the link, and idle writes nothing.
#[test]
#[ignore = "end-to-end: needs root, iproute2, OpenSSH and tmux; .ci/run runs it by name"]
fn kitty_images_over_a_slow_link_are_paced() {
    let _one = one_at_a_time();
    let figures = pixels_over_a_slow_link("kitty");
    println!("--format kitty");
    report(&[(1000, figures)], None);
}

/// The same in sixels.
#[test]
#[ignore = "end-to-end: needs root, iproute2, OpenSSH and tmux; .ci/run runs it by name"]
fn sixel_images_over_a_slow_link_are_paced() {
    let _one = one_at_a_time();
    let figures = pixels_over_a_slow_link("sixels");
    println!("--format sixels");
    report(&[(1000, figures)], None);
}

/// Plain SSH, inside tmux and inside screen, sessions interleaved, at each rate of
/// `RELIEF_SSH_RATES` (default 1 and 50 Mbit/s): each table, then the median time to
/// the final picture inside each multiplexer against plain SSH.
#[test]
#[ignore = "the comparison (minutes): cargo test --release --test suite ssh_link::compare -- --ignored --nocapture"]
fn compare_multiplexers_with_plain_ssh() {
    let _one = one_at_a_time();
    let rates = env_list("RELIEF_SSH_RATES", "1000,50000");
    let reps = env_list("RELIEF_SSH_REPS", "3")[0];
    let muxes = [None, Some(Mux::Tmux), Some(Mux::Screen)];
    let mut runs: Vec<Vec<(u32, Vec<Figure>)>> = vec![Vec::new(); muxes.len()];
    for rep in 0..reps {
        for &rate in &rates {
            for (m, &mux) in muxes.iter().enumerate() {
                let name = mux.map_or("plain SSH", Mux::program);
                eprintln!(
                    "session {} of {reps} at {}, {name}",
                    rep + 1,
                    rate_name(rate)
                );
                let figures = run_session(&options(rate, mux));
                runs[m].push((rate, figures));
            }
        }
    }
    for (m, &mux) in muxes.iter().enumerate() {
        report(&runs[m], mux);
    }
    println!(
        "| link | input | plain SSH | inside tmux | tmux / plain | inside screen | screen / plain |\n\
         |---|---|--:|--:|--:|--:|--:|"
    );
    let lag = |m: usize, rate: u32, i: usize| {
        median(
            runs[m]
                .iter()
                .filter(|(r, _)| *r == rate)
                .map(|(_, f)| f[i].lag)
                .collect(),
        )
        .as_secs_f64()
    };
    for &rate in &rates {
        let first = &runs[0].iter().find(|(r, _)| *r == rate).unwrap().1;
        for (i, f) in first.iter().enumerate().skip(2) {
            let (p, t, s) = (lag(0, rate, i), lag(1, rate, i), lag(2, rate, i));
            println!(
                "| {} | {} | {p:.3} s | {t:.3} s | {:.2} | {s:.3} s | {:.2} |",
                rate_name(rate),
                f.input,
                t / p,
                s / p
            );
        }
    }
}

/// The full measurement: every rate, several sessions each, medians.
#[test]
#[ignore = "the full measurement (minutes): cargo test --release --test suite ssh_link::measure -- --ignored --nocapture"]
fn measure_lag_and_bytes_over_ssh() {
    let _one = one_at_a_time();
    let rates = env_list("RELIEF_SSH_RATES", "1000,8000");
    let reps = env_list("RELIEF_SSH_REPS", "3")[0];
    let mux = env_mux();
    let mut runs = Vec::new();
    for rep in 0..reps {
        for &rate in &rates {
            eprintln!("session {} of {reps} at {}", rep + 1, rate_name(rate));
            let figures = run_session(&options(rate, mux));
            runs.push((rate, figures));
        }
    }
    report(&runs, mux);
}

/// Orientation of a model file's start view (`0,-35,0`).
const MODEL_START: [i32; 3] = [0, 325, 0];

/// An animated model playing at 1 Mbit/s: frames keep coming by themselves
/// (previews while it plays), a drag still lands, and the lag from its
/// release to the orientation it asks on screen is printed; the clip plays
/// on after it, and `q` ends cleanly. The picture never settles while a
/// clip plays, so the lag is read from the status line's orientation.
#[test]
#[ignore = "end-to-end: needs root, iproute2, OpenSSH and tmux; .ci/run runs it by name"]
fn a_playing_animation_keeps_the_drag_landing_over_a_slow_link() {
    animation_over_a_slow_link(None);
}

/// The same with relief inside tmux on the server, as people run it over
/// SSH to keep it across a dropped connection.
#[test]
#[ignore = "end-to-end: needs root, iproute2, OpenSSH and tmux; .ci/run runs it by name"]
fn a_playing_animation_inside_tmux_on_the_server_keeps_the_drag_landing() {
    animation_over_a_slow_link(Some(Mux::Tmux));
}

/// An animated model playing at 1 Mbit/s, relief run directly or inside
/// `mux` on the server.
fn animation_over_a_slow_link(mux: Option<Mux>) {
    let _one = one_at_a_time();
    let name = mux.map_or("plain", |_| "mux");
    let dir = std::env::temp_dir().join(format!("relief-ssh-anim-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let model = dir.join("strip.glb");
    std::fs::write(&model, glb_writer::two_joint_strip()).unwrap();
    let mut opts = options(1000, mux);
    opts.relief_args.push(model.display().to_string());
    let s = session(&opts);
    let mut figures = Vec::new();

    let start = Instant::now();
    let has_status = |screen: &str| status(screen).starts_with("Phong │");
    let screen = wait_for(&s, start, "the first frame", has_status);
    figures.push(Figure {
        input: "connect, first frame (clip playing)",
        bytes: Some(s.bytes_since_pane_start()),
        lag: start.elapsed(),
        queued: None,
        after: None,
    });
    assert_eq!(orientation(&screen), Some(MODEL_START), "{screen}");
    let moving = |what: &str| {
        let before = s.picture();
        let since = Instant::now();
        while s.picture() == before {
            assert!(since.elapsed() < TIMEOUT, "the clip stopped {what}");
            std::thread::sleep(Duration::from_millis(10));
        }
    };
    moving("before the drag");

    let b0 = s.bytes_to_client();
    drag(&s);
    let input = last_input(&s);
    let [x, y, z] = MODEL_START;
    let want = [x + 40, (y - 80).rem_euclid(360), z];
    wait_for(&s, input.at, "the drag", |screen| {
        orientation(screen) == Some(want)
    });
    figures.push(Figure {
        input: "drag 40 steps in 0.8 s, clip playing (to its orientation shown)",
        bytes: Some(s.bytes_to_client() - b0),
        lag: input.at.elapsed(),
        queued: None,
        after: Some(s.bytes_to_client() - input.bytes),
    });
    moving("after the drag");

    s.keys(&["q"]);
    wait_until_ended(&s, Instant::now());
    assert_restored(&s);
    report(&[(1000, figures)], mux);
    drop(s);
    std::fs::remove_dir_all(&dir).unwrap();
}
