//! The real binary in a real terminal (tmux): keys, an SGR mouse drag,
//! quitting, signals, and the terminal left as it was found.
//!
//! Ignored in a plain `cargo test`, as they need tmux (and `script`):
//! `.ci/run` installs them and runs these tests by name. Run without tmux,
//! a test fails and says what to install.

use std::process::Command;
use std::time::{Duration, Instant};

/// A private tmux server, killed on drop.
struct Tmux {
    socket: String,
}

impl Tmux {
    fn start(name: &str, width: u16, height: u16, command: &str) -> Tmux {
        need("tmux", "-V", "tmux");
        let t = Tmux {
            socket: format!("relief-e2e-{}-{name}", std::process::id()),
        };
        t.run(&[
            "-f",
            "/dev/null",
            "new-session",
            "-d",
            "-x",
            &width.to_string(),
            "-y",
            &height.to_string(),
            command,
        ]);
        t
    }

    fn run(&self, args: &[&str]) -> String {
        let out = Command::new("tmux")
            .arg("-L")
            .arg(&self.socket)
            .args(args)
            .output()
            .expect("tmux runs");
        String::from_utf8_lossy(&out.stdout).into_owned()
    }

    fn screen(&self) -> String {
        self.run(&["capture-pane", "-p"])
    }

    /// The screen with colours.
    fn picture(&self) -> String {
        self.run(&["capture-pane", "-p", "-e", "-N"])
    }

    fn format(&self, f: &str) -> String {
        self.run(&["display-message", "-p", f]).trim().to_string()
    }

    fn keys(&self, keys: &[&str]) {
        let mut args = vec!["send-keys"];
        args.extend_from_slice(keys);
        self.run(&args);
    }

    fn literal(&self, text: &str) {
        self.run(&["send-keys", "-l", text]);
    }

    /// Waits (up to 20 s) until the screen satisfies `ok`; panics with the screen otherwise.
    fn wait_for(&self, what: &str, ok: impl Fn(&str) -> bool) -> String {
        let start = Instant::now();
        loop {
            let screen = self.screen();
            if ok(&screen) {
                return screen;
            }
            if start.elapsed() > Duration::from_secs(20) {
                panic!("timed out waiting for {what}; screen:\n{screen}");
            }
            std::thread::sleep(Duration::from_millis(30));
        }
    }

    /// Waits for relief to end; returns its exit status as the shell reports it.
    fn wait_exit(&self) -> String {
        let screen = self.wait_for("relief to exit", |s| s.contains("RELIEF-EXITED "));
        let line = screen
            .lines()
            .find(|l| l.contains("RELIEF-EXITED "))
            .unwrap();
        line.split("RELIEF-EXITED ")
            .nth(1)
            .unwrap()
            .trim()
            .to_string()
    }

    /// Process id of relief (written by the shell before it became relief).
    fn relief_pid(&self) -> String {
        let start = Instant::now();
        loop {
            if let Ok(pid) = std::fs::read_to_string(pid_file(&self.socket))
                && !pid.trim().is_empty()
            {
                return pid.trim().to_string();
            }
            assert!(start.elapsed() < Duration::from_secs(20), "no pid file");
            std::thread::sleep(Duration::from_millis(30));
        }
    }
}

fn pid_file(socket: &str) -> std::path::PathBuf {
    std::env::temp_dir().join(format!("{socket}.pid"))
}

impl Drop for Tmux {
    fn drop(&mut self) {
        self.run(&["kill-server"]);
        let _ = std::fs::remove_file(pid_file(&self.socket));
    }
}

/// A shell command that records relief's pid, runs it with `env` and
/// `args`, then reports its exit status and keeps the pane alive.
fn command(name: &str, env: &str, args: &str) -> String {
    let socket = format!("relief-e2e-{}-{name}", std::process::id());
    format!(
        "sh -c 'echo $$ > {}; exec env {env} {} {args}'; echo RELIEF-EXITED $?; sleep 60",
        pid_file(&socket).display(),
        env!("CARGO_BIN_EXE_relief")
    )
}

fn status(screen: &str) -> String {
    screen
        .lines()
        .rev()
        .find(|l| !l.trim().is_empty())
        .unwrap_or("")
        .to_string()
}

/// Everything above the last two lines (a status line wrapped onto more
/// rows leaves text rows in it, which hold no half block).
fn viewport(picture: &str) -> String {
    let lines: Vec<&str> = picture.lines().collect();
    lines[..lines.len().saturating_sub(2)].join("\n")
}

fn assert_restored(t: &Tmux) {
    assert_eq!(t.format("#{alternate_on}"), "0", "alternate screen left");
    assert_eq!(t.format("#{mouse_any_flag}"), "0", "mouse reporting off");
    assert_eq!(t.format("#{mouse_sgr_flag}"), "0", "SGR mouse off");
    assert_eq!(t.format("#{cursor_flag}"), "1", "cursor visible");
    let screen = t.screen();
    assert!(
        !screen.contains('▀') && !screen.contains('▄') && screen.contains("RELIEF-EXITED"),
        "picture left on the shell screen:\n{screen}"
    );
}

#[test]
#[ignore = "end-to-end: needs tmux (apt-get install tmux); .ci/run runs it by name"]
fn keys_drag_and_quit_in_a_real_terminal() {
    let t = Tmux::start("keys", 160, 48, &command("keys", "COLORTERM=truecolor", ""));
    let s = t.wait_for("first frame", |s| status(s).starts_with("Phong │ vertex"));
    assert!(
        status(&s).contains("│ 24b │") && status(&s).ends_with("? help"),
        "{s}"
    );
    // Only button and drag reports with SGR coordinates: no all-motion mode.
    assert_eq!(t.format("#{alternate_on}"), "1");
    assert_eq!(t.format("#{mouse_button_flag}"), "1");
    assert_eq!(t.format("#{mouse_all_flag}"), "0");
    assert_eq!(t.format("#{mouse_sgr_flag}"), "1");

    // `n` before `m`: flat lighting takes the facets' normals, and refuses it.
    let steps: [(&str, &[&str], &[&str]); 5] = [
        ("n", &["│ face │"], &[]),
        ("m", &["flat │", "bump on (Phong only)"], &[]),
        ("t", &["tex off"], &[]),
        ("c", &["col off"], &[]),
        ("b", &["bump off"], &["Phong only"]),
    ];
    for (key, want, not) in steps {
        t.keys(&[key]);
        t.wait_for(&format!("status after {key}"), |s| {
            let st = status(s);
            want.iter().all(|w| st.contains(w)) && !not.iter().any(|n| st.contains(n))
        });
    }

    // Back to Phong with texture for a detailed picture, then drag.
    t.keys(&["m", "m", "t", "c", "b"]);
    t.wait_for("Phong again", |s| {
        let st = status(s);
        st.starts_with("Phong") && st.contains("tex on") && st.contains("bump on")
    });
    let before = viewport(&t.picture());
    t.literal("\x1b[<0;70;18M");
    for i in 1..=6 {
        t.literal(&format!("\x1b[<32;{};{}M", 70 + 3 * i, 18 + i));
    }
    t.literal("\x1b[<0;88;24m");
    // 18 columns right → Y + 36°, 6 rows down → X + 24°.
    t.wait_for("fields updated by the drag", |s| {
        s.contains("X     49°") && s.contains("Y     71°")
    });
    let after = viewport(&t.picture());
    assert_ne!(before, after, "the picture changed");

    // Technique, anti-aliasing and display show in the status line.
    let steps: [(&str, &str); 3] = [
        ("e", "│ emboss │"),
        ("a", "│ AA SSAA 2x2 │"),
        ("d", "│ points │"),
    ];
    for (key, want) in steps {
        t.keys(&[key]);
        t.wait_for(&format!("status after {key}"), |s| status(s).contains(want));
    }

    // Twice `p`: the plasma, the only scene asking for every pointer motion.
    t.keys(&["p"]);
    t.wait_for("shadow scene", |s| status(s).contains("│ shadow │"));
    assert_eq!(t.format("#{mouse_all_flag}"), "0");
    t.keys(&["p"]);
    t.wait_for("plasma", |s| {
        status(s).starts_with("plasma │ Z² table │ light centre")
    });
    assert_eq!(t.format("#{mouse_all_flag}"), "1");
    let before = viewport(&t.picture());
    // Motion without a button (SGR code 35) at column 30, row 8 (1-based):
    // the light goes to pixel (29, 2·7 + 1).
    t.literal("\x1b[<35;30;8M");
    t.wait_for("light at the pointer", |s| {
        status(s).contains("light 29,15")
    });
    let after = viewport(&t.picture());
    assert_ne!(before, after, "the light moved");
    t.keys(&["p"]);
    t.wait_for("back to the model", |s| status(s).contains("│ cube │"));
    assert_eq!(t.format("#{mouse_all_flag}"), "0");
    // tmux, like xterm, clears all mouse reporting on `?1003l`: leaving
    // the plasma puts button and drag reports back.
    assert_eq!(t.format("#{mouse_button_flag}"), "1");
    assert_eq!(t.format("#{mouse_sgr_flag}"), "1");
    // Into the plasma and out through `o`.
    t.keys(&["p", "p"]);
    t.wait_for("plasma again", |s| status(s).starts_with("plasma │"));
    assert_eq!(t.format("#{mouse_all_flag}"), "1");
    t.keys(&["o"]);
    t.wait_for("the model after `o`", |s| status(s).contains("│ cube │"));
    assert_eq!(t.format("#{mouse_all_flag}"), "0");
    assert_eq!(t.format("#{mouse_button_flag}"), "1");

    t.keys(&["q"]);
    assert_eq!(t.wait_exit(), "0");
    assert_restored(&t);
}

#[test]
#[ignore = "end-to-end: needs tmux (apt-get install tmux); .ci/run runs it by name"]
fn small_terminal_resizes_and_signals_restore_the_terminal() {
    for (signal, code) in [("TERM", "143"), ("HUP", "129"), ("INT", "130")] {
        let t = Tmux::start(signal, 40, 12, &command(signal, "COLORTERM=truecolor", ""));
        t.wait_for("first frame", |s| {
            // 40×12: one status row, counting the modes it leaves out.
            let st = status(s);
            st.starts_with("Phong │") && st.contains("│ 24b │ +") && st.ends_with(" more │ ? help")
        });
        for (w, h) in [("1", "1"), ("3", "2"), ("60", "20"), ("40", "12")] {
            t.run(&["resize-window", "-x", w, "-y", h]);
        }
        t.wait_for("redrawn after the resizes", |s| {
            s.lines().count() >= 12 && status(s).starts_with("Phong │")
        });
        let pid = t.relief_pid();
        let ok = Command::new("kill")
            .args([&format!("-{signal}"), &pid])
            .status()
            .expect("kill runs");
        assert!(ok.success());
        assert_eq!(t.wait_exit(), code, "SIG{signal}");
        assert_restored(&t);
    }
}

#[test]
#[ignore = "end-to-end: needs tmux (apt-get install tmux); .ci/run runs it by name"]
fn forced_palette_shows_in_the_status_line() {
    let cmd = command("palette", "-u COLORTERM", "--color 256");
    let t = Tmux::start("palette", 120, 20, &cmd);
    // 120×20: the status line wraps onto two rows, in long or short forms.
    t.wait_for("256 colours", |s| {
        let st = status(s);
        st.ends_with("? help") && (st.contains("│ 256c │") || st.contains("│ 256 colours │"))
    });
    // The picture uses palette colours, not 24-bit ones.
    let pic = t.picture();
    assert!(pic.contains("8;5;") && !pic.contains("8;2;"), "{pic}");
    t.keys(&["Escape"]);
    assert_eq!(t.wait_exit(), "0");
    assert_restored(&t);
}

/// The cells of the picture (everything above the two text lines) left of
/// column `from` show no half block: the picture there is not text.
fn no_text_picture(screen: &str, from: usize) -> bool {
    viewport(screen)
        .lines()
        .all(|l| !l.chars().take(from).any(|c| c == '▀' || c == '▄'))
}

/// kitty forced inside tmux with passthrough on (the images go to no
/// terminal; tmux shows the text relief writes): the cost panel is text
/// in its corner and the picture around it stays an image (no half
/// blocks), also after a resize with the panel open; quitting with the
/// panel open leaves the alternate screen and the mouse modes.
#[test]
#[ignore = "end-to-end: needs tmux (apt-get install tmux); .ci/run runs it by name"]
fn a_panel_over_a_kitty_picture_and_a_resize_then_quit_restore_the_terminal() {
    let cmd = format!(
        "tmux set -g allow-passthrough on; {}",
        command("panel", "RELIEF_FORMAT=kitty", "")
    );
    let t = Tmux::start("panel", 100, 30, &cmd);
    let s = t.wait_for("a kitty frame", |s| status(s).contains("kitty │"));
    assert!(no_text_picture(&s, 100), "{s}");
    t.keys(&["k"]);
    let s = t.wait_for("the cost panel", |s| s.contains(" cost (k) "));
    let title = s.lines().find(|l| l.contains(" cost (k) ")).unwrap();
    // The panel is 44 columns wide at the right edge.
    assert_eq!(title.chars().count(), 100, "{s}");
    assert!(no_text_picture(&s, 100 - 44), "{s}");
    t.run(&["resize-window", "-x", "80", "-y", "26"]);
    let s = t.wait_for("the panel after the resize", |s| {
        s.lines().count() >= 26
            && s.lines()
                .find(|l| l.contains(" cost (k) "))
                .is_some_and(|l| l.chars().count() == 80)
    });
    assert!(no_text_picture(&s, 80 - 44), "{s}");
    t.keys(&["q"]);
    assert_eq!(t.wait_exit(), "0");
    assert_restored(&t);
}

/// The child half of `a_panic_restores_the_terminal`: run by it inside tmux
/// (ignored in a normal run, where it would take over the test's terminal).
#[test]
#[ignore = "run by a_panic_restores_the_terminal in its own terminal"]
fn panic_child_with_a_frame_in_flight() {
    use relief_term::guard::{GuardedStdout, TerminalGuard};
    use std::io::Write;
    let _guard = TerminalGuard::enter().expect("a terminal");
    let mut out = std::io::BufWriter::new(GuardedStdout::new().unwrap());
    // A frame half written when the panic comes: unwinding flushes it after
    // the hook has restored the terminal, and it must go nowhere.
    out.write_all("\x1b[H▀▀▀▀▀▀▀▀".repeat(50).as_bytes())
        .unwrap();
    panic!("relief-test-panic");
}

#[test]
#[ignore = "end-to-end: needs tmux (apt-get install tmux); .ci/run runs it by name"]
fn a_panic_restores_the_terminal() {
    let exe = std::env::current_exe().unwrap();
    let cmd = format!(
        "RUST_BACKTRACE=0 {} --ignored --exact e2e_tmux::panic_child_with_a_frame_in_flight \
         --nocapture --test-threads 1; echo RELIEF-EXITED $?; \
         echo TTY $(stty -a | tr -s ' ;' '\\n\\n' | grep -x -E -- '-?(icanon|echo)'); sleep 60",
        exe.display()
    );
    let t = Tmux::start("panic", 100, 30, &cmd);
    // libtest reports a failed test with 101.
    assert_eq!(t.wait_exit(), "101");
    let screen = t.wait_for("stty's report", |s| s.contains("TTY "));
    assert!(screen.contains("relief-test-panic"), "{screen}");
    assert_restored(&t);
    // Raw mode is off again: canonical input and echo.
    let stty = screen.lines().find(|l| l.starts_with("TTY ")).unwrap();
    assert_eq!(stty.trim_end(), "TTY icanon echo", "{screen}");
}

/// relief inside tmux, whose client runs (through `script`) in a pty that
/// answers nothing, as `TERM=xterm-256color`. tmux answers the terminal
/// queries itself (device attributes only), so the depth comes from what
/// tmux says of its client: 24-bit with the `RGB` terminal feature, 256
/// colours without (tmux would turn 24-bit colours into its palette
/// anyway). The cost panel says so.
#[test]
#[ignore = "end-to-end: needs tmux and script (apt-get install tmux bsdutils); .ci/run runs it by name"]
fn inside_tmux_the_colour_depth_comes_from_the_client() {
    need("script", "--version", "bsdutils");
    let cases = [
        ("rgb", true, "│ 24b │", "24-bit: tmux client RGB", "8;2;"),
        (
            "norgb",
            false,
            "│ 256c │",
            "256 colours: tmux client no RGB",
            "8;5;",
        ),
    ];
    for (name, rgb, status_end, panel, colours) in cases {
        let inner_name = format!("colour-{name}");
        // The pane waits for a client before it starts relief, which asks
        // tmux at start-up.
        let script =
            std::env::temp_dir().join(format!("relief-e2e-{}-{inner_name}.sh", std::process::id()));
        std::fs::write(
            &script,
            format!(
                "until [ -n \"$(tmux display-message -p '#{{client_termname}}')\" ]; do sleep 0.05; done\n\
                 exec env -u COLORTERM {}\n",
                env!("CARGO_BIN_EXE_relief")
            ),
        )
        .unwrap();
        let cmd = format!("sh {}; echo RELIEF-EXITED $?; sleep 60", script.display());
        let inner = Tmux::start(&inner_name, 100, 30, &cmd);
        if rgb {
            inner.run(&["set", "-as", "terminal-features", ",xterm-256color:RGB"]);
        }
        // The client: its terminal is script's pty, whose output goes nowhere.
        let mut client = Command::new("script")
            .args([
                "-qfec",
                &format!("tmux -L {} attach", inner.socket),
                "/dev/null",
            ])
            .env_remove("TMUX")
            .env("TERM", "xterm-256color")
            .stdin(std::process::Stdio::piped())
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .spawn()
            .expect("script runs");
        inner.wait_for("first frame", |s| status(s).contains(status_end));
        let pic = inner.picture();
        assert!(pic.contains(colours), "{name}: {pic}");
        inner.keys(&["k"]);
        inner.wait_for("the cost panel", |s| s.contains(panel));
        inner.keys(&["q"]);
        assert_eq!(inner.wait_exit(), "0");
        drop(inner);
        let _ = client.kill();
        let _ = client.wait();
        let _ = std::fs::remove_file(script);
    }
}

// ---- Inside a real terminal under Xvfb: the pixel format through tmux ----

/// A process killed (and waited for) on drop.
struct Child(std::process::Child);

impl Drop for Child {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// Fails the test, saying what to install, when `program` cannot be run.
fn need(program: &str, arg: &str, package: &str) {
    assert!(
        installed(program, arg),
        "`{program}` is not installed: this test needs it (apt-get install {package})"
    );
}

fn installed(program: &str, arg: &str) -> bool {
    Command::new(program)
        .arg(arg)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .status()
        .is_ok()
}

/// tmux started inside `terminal` (on X display `display`), its server on
/// socket `socket`; waits until its client is attached.
fn tmux_in_terminal(display: &str, terminal: &[&str], socket: &str) -> (Child, Tmux) {
    let mut args: Vec<&str> = terminal[1..].to_vec();
    args.extend(["tmux", "-L", socket, "-f", "/dev/null", "new-session"]);
    let child = Command::new(terminal[0])
        .args(&args)
        .env("DISPLAY", display)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .expect("the terminal starts");
    let t = Tmux {
        socket: socket.to_string(),
    };
    let start = Instant::now();
    while t.format("#{client_termname}").is_empty() {
        assert!(
            start.elapsed() < Duration::from_secs(60),
            "{} did not start tmux",
            terminal[0]
        );
        std::thread::sleep(Duration::from_millis(200));
    }
    (Child(child), t)
}

#[test]
#[ignore = "needs Xvfb, xterm and kitty (apt-get install xvfb xterm kitty) and takes a minute: cargo test --test suite e2e_tmux::inside_tmux_in_kitty -- --ignored"]
fn inside_tmux_in_kitty_and_xterm_the_pixel_format_needs_passthrough() {
    for (program, arg) in [
        ("Xvfb", "-help"),
        ("xterm", "-version"),
        ("kitty", "--version"),
    ] {
        assert!(installed(program, arg), "{program} is not installed");
    }
    let display = format!(":{}", 300 + std::process::id() % 400);
    let _x = Child(
        Command::new("Xvfb")
            .args([
                display.as_str(),
                "-screen",
                "0",
                "1280x800x24",
                "-nolisten",
                "tcp",
            ])
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .spawn()
            .expect("Xvfb starts"),
    );
    std::thread::sleep(Duration::from_secs(1));
    let terminals: [(&[&str], &str); 2] = [
        (
            &["xterm", "-ti", "vt340", "-geometry", "100x36", "-e"],
            "sixels",
        ),
        (
            &[
                "kitty",
                "-o",
                "initial_window_width=100c",
                "-o",
                "initial_window_height=36c",
            ],
            "kitty",
        ),
    ];
    for (terminal, format) in terminals {
        for passthrough in [true, false] {
            let socket = format!(
                "relief-x-{}-{}-{passthrough}",
                std::process::id(),
                terminal[0]
            );
            let (_term, t) = tmux_in_terminal(&display, terminal, &socket);
            t.run(&[
                "set",
                "-g",
                "allow-passthrough",
                if passthrough { "on" } else { "off" },
            ]);
            t.literal(&format!("clear; {}", env!("CARGO_BIN_EXE_relief")));
            t.keys(&["Enter"]);
            let screen = t.wait_for("relief's status line", |s| s.contains("? help"));
            let line = status(&screen);
            let what = format!("{} passthrough {passthrough}:\n{screen}", terminal[0]);
            if passthrough {
                assert!(line.contains(&format!("{format} │")), "{what}");
            } else {
                // The long or the short form, as the terminal's width allows.
                assert!(line.contains("24-bit") || line.contains("24b"), "{what}");
                // kitty is known by tmux's client name: the hint says how to
                // turn passthrough on. xterm's sixel cannot be asked without it.
                let hint = format!(
                    "{format} images need tmux passthrough: tmux set -g allow-passthrough on"
                );
                assert_eq!(screen.contains(&hint), format == "kitty", "{what}");
            }
            t.keys(&["q"]);
        }
    }
}
