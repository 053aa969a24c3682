//! A real SSH session over a slow link, all inside network namespaces made here.
//!
//! Three namespaces: the client (`…c`), the link (`…m`) and the server (`…s`), joined by
//! two veth pairs. The link namespace holds the bottleneck: a `tbf` rate limit on each of
//! its two ports (the same rate both ways) and a user-space delay line between them (see
//! `delay_line`). The client and the server have one address each in a private /30 and
//! see each other as on one wire; nothing outside the namespaces is touched.
//!
//! The server runs its own `sshd` (own config, keys and port, no `AcceptEnv`, so
//! `COLORTERM` is not forwarded, as on a typical server); the client runs a private tmux
//! server whose one pane runs `ssh -tt` to it, executing a relief binary there.
//! Everything is undone on drop, also after a failed assertion.

#![allow(dead_code)]

pub mod delay_line;

use std::os::fd::AsRawFd;
use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use delay_line::DelayLine;

const CLIENT_ADDR: &str = "10.77.0.1";
const SERVER_ADDR: &str = "10.77.0.2";
const SSH_PORT: u16 = 2222;
/// The pane's marker line once the session has ended, followed by ssh's exit status.
pub const EXITED: &str = "RELIEF-EXITED ";

/// What one session is made of.
pub struct Options {
    /// The relief binary run on the server.
    pub binary: PathBuf,
    /// Rate of the link in kbit/s, each way.
    pub rate_kbit: u32,
    /// One-way delay of the link.
    pub delay: Duration,
    /// Value of relief's `--color`.
    pub color: String,
    pub width: u16,
    pub height: u16,
    /// Run relief inside a terminal multiplexer on the server, as people who
    /// keep their work in tmux or GNU screen do.
    pub server_mux: Option<Mux>,
    /// Extra arguments of relief (e.g. `--link 1M`).
    pub relief_args: Vec<String>,
}

/// A terminal multiplexer on the server.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mux {
    /// tmux, its status bar off.
    Tmux,
    /// GNU screen, no configuration (no status line).
    Screen,
}

impl Mux {
    /// `RELIEF_SSH_MUX`'s value: `tmux` or `screen`.
    pub fn from_name(name: &str) -> Option<Mux> {
        match name {
            "tmux" => Some(Mux::Tmux),
            "screen" => Some(Mux::Screen),
            _ => None,
        }
    }

    pub fn program(self) -> &'static str {
        match self {
            Mux::Tmux => "tmux",
            Mux::Screen => "screen",
        }
    }
}

/// Why a session cannot be had on this machine (the test then fails, saying so).
pub struct Unavailable(pub String);

/// The namespaces, the link, sshd and the tmux pane running `ssh -tt … relief`.
pub struct Session {
    tag: String,
    dir: PathBuf,
    namespaces: Vec<String>,
    delay: Option<DelayLine>,
    sshd: Option<Child>,
    tmux: Option<String>,
    /// Link bytes towards the client when the pane started (the login check's).
    bytes_before_pane: u64,
}

/// The first missing prerequisite, if any: root, and the tools run here.
pub fn missing_prerequisite() -> Option<String> {
    missing_for(None)
}

/// [`missing_prerequisite`], and the multiplexer run on the server.
pub fn missing_for(mux: Option<Mux>) -> Option<String> {
    if let Some(mux) = mux
        && find_program(mux.program()).is_none()
    {
        let p = mux.program();
        return Some(format!("`{p}` not found (apt-get install {p})"));
    }
    // SAFETY: geteuid has no preconditions.
    if unsafe { libc::geteuid() } != 0 {
        return Some("not root (network namespaces need it)".into());
    }
    for (tool, package) in [
        ("ip", "iproute2"),
        ("tc", "iproute2"),
        ("ssh", "openssh-client"),
        ("ssh-keygen", "openssh-client"),
        ("tmux", "tmux"),
    ] {
        if find_program(tool).is_none() {
            return Some(format!("`{tool}` not found (apt-get install {package})"));
        }
    }
    if find_program("sshd").is_none() {
        return Some("`sshd` not found (apt-get install openssh-server)".into());
    }
    None
}

/// A program on PATH or in the usual sbin directories (sshd must be run by its full path).
fn find_program(name: &str) -> Option<PathBuf> {
    let path = std::env::var_os("PATH").unwrap_or_default();
    std::env::split_paths(&path)
        .chain(["/usr/sbin", "/sbin", "/usr/local/sbin"].map(PathBuf::from))
        .map(|d| d.join(name))
        .find(|p| p.is_file())
}

/// Runs a command to completion; its stdout, or what went wrong.
fn run(program: &str, args: &[&str]) -> Result<String, String> {
    let out = Command::new(program)
        .args(args)
        .stdin(Stdio::null())
        .output()
        .map_err(|e| format!("{program}: {e}"))?;
    if out.status.success() {
        Ok(String::from_utf8_lossy(&out.stdout).into_owned())
    } else {
        Err(format!(
            "`{program} {}` failed: {}",
            args.join(" "),
            String::from_utf8_lossy(&out.stderr).trim()
        ))
    }
}

/// Runs a command given as one line of words (none with a space inside).
fn words(line: &str) -> Result<String, String> {
    let mut words = line.split_whitespace();
    let program = words.next().expect("a program");
    run(program, &words.collect::<Vec<_>>())
}

/// Runs a command inside a namespace.
fn run_in(ns: &str, args: &[&str]) -> Result<String, String> {
    let mut all = vec!["netns", "exec", ns];
    all.extend_from_slice(args);
    run("ip", &all)
}

impl Session {
    /// Builds the link, starts sshd, checks a login, then starts the pane.
    /// `Err` when namespaces or the rate limit cannot be had; panics when they can
    /// but the session still fails (that is a bug in relief or here).
    pub fn start(opts: &Options) -> Result<Session, Unavailable> {
        static COUNT: AtomicUsize = AtomicUsize::new(0);
        let tag = format!(
            "relief-ssh-{}-{}",
            std::process::id(),
            COUNT.fetch_add(1, Ordering::Relaxed)
        );
        let mut s = Session {
            dir: std::env::temp_dir().join(&tag),
            tag,
            namespaces: Vec::new(),
            delay: None,
            sshd: None,
            tmux: None,
            bytes_before_pane: 0,
        };
        s.build_link(opts).map_err(Unavailable)?;
        s.start_sshd().unwrap_or_else(|e| panic!("sshd: {e}"));
        s.start_pane(opts);
        Ok(s)
    }

    fn ns(&self, side: char) -> String {
        format!("{}{side}", self.tag)
    }

    fn build_link(&mut self, opts: &Options) -> Result<(), String> {
        for side in ['c', 'm', 's'] {
            let ns = self.ns(side);
            run("ip", &["netns", "add", &ns])?;
            self.namespaces.push(ns.clone());
            // No IPv6: its neighbour discovery would only add chatter to the counts.
            let no_ipv6 = "echo 1 > /proc/sys/net/ipv6/conf/default/disable_ipv6";
            let _ = run_in(&ns, &["sh", "-c", no_ipv6]);
            words(&format!("ip -n {ns} link set lo up"))?;
        }
        let (c, m, s) = (self.ns('c'), self.ns('m'), self.ns('s'));
        // Client port "vc" <-> link port "mc"; link port "ms" <-> server port "vs".
        for (end, end_ns, port) in [("vc", &c, "mc"), ("vs", &s, "ms")] {
            words(&format!(
                "ip link add {end} netns {end_ns} type veth peer name {port} netns {m}"
            ))?;
            // Frames of one MTU at most, as on a real wire (and through the delay line).
            words(&format!(
                "ip -n {end_ns} link set {end} gso_max_size 1500 gso_max_segs 1"
            ))?;
        }
        words(&format!("ip -n {c} addr add {CLIENT_ADDR}/30 dev vc"))?;
        words(&format!("ip -n {s} addr add {SERVER_ADDR}/30 dev vs"))?;
        // The bottleneck: the same rate each way, a bucket of a few ms of data
        // (at least three full frames) and up to 200 ms of queue.
        let rate = opts.rate_kbit;
        let burst = (rate as u64 * 1000 / 8 / 250).max(4542);
        for port in ["mc", "ms"] {
            words(&format!(
                "tc -n {m} qdisc add dev {port} root tbf rate {rate}kbit burst {burst} latency 200ms"
            ))?;
        }
        let delay = DelayLine::start(&m, "mc", "ms", opts.delay);
        self.delay = Some(delay.map_err(|e| format!("delay line: {e}"))?);
        for (ns, dev) in [(&c, "vc"), (&m, "mc"), (&m, "ms"), (&s, "vs")] {
            words(&format!("ip -n {ns} link set {dev} up"))?;
        }
        Ok(())
    }

    fn start_sshd(&mut self) -> Result<(), String> {
        std::fs::create_dir_all(&self.dir).map_err(|e| e.to_string())?;
        // sshd's privilege-separation directory, absent where sshd never ran.
        std::fs::create_dir_all("/run/sshd").map_err(|e| format!("/run/sshd: {e}"))?;
        let d = &self.dir;
        for key in ["host", "client"] {
            let path = d.join(key);
            run(
                "ssh-keygen",
                &[
                    "-q",
                    "-t",
                    "ed25519",
                    "-N",
                    "",
                    "-f",
                    &path.to_string_lossy(),
                ],
            )?;
        }
        std::fs::copy(d.join("client.pub"), d.join("authorized_keys"))
            .map_err(|e| e.to_string())?;
        let config = format!(
            "ListenAddress {SERVER_ADDR}\n\
             Port {SSH_PORT}\n\
             HostKey {host}\n\
             AuthorizedKeysFile {keys}\n\
             PidFile none\n\
             PermitRootLogin prohibit-password\n\
             PubkeyAuthentication yes\n\
             PasswordAuthentication no\n\
             KbdInteractiveAuthentication no\n\
             UsePAM no\n\
             StrictModes no\n\
             UseDNS no\n\
             PrintMotd no\n\
             PrintLastLog no\n\
             LogLevel ERROR\n",
            host = d.join("host").display(),
            keys = d.join("authorized_keys").display(),
        );
        let config_path = d.join("sshd_config");
        std::fs::write(&config_path, config).map_err(|e| e.to_string())?;
        let log = std::fs::File::create(d.join("sshd.log")).map_err(|e| e.to_string())?;
        let sshd = find_program("sshd").ok_or("sshd not found")?;
        self.sshd = Some(
            Command::new("ip")
                .args(["netns", "exec", &self.ns('s')])
                .arg(&sshd)
                .args(["-D", "-e", "-f"])
                .arg(&config_path)
                .stdin(Stdio::null())
                .stdout(Stdio::null())
                .stderr(log)
                .spawn()
                .map_err(|e| e.to_string())?,
        );
        // Logged in once without a terminal: sshd listens and the key is accepted.
        let start = Instant::now();
        loop {
            let mut args = vec!["ssh".to_string()];
            args.extend(self.ssh_args());
            args.push("true".into());
            let args: Vec<&str> = args.iter().map(String::as_str).collect();
            match run_in(&self.ns('c'), &args) {
                Ok(_) => return Ok(()),
                Err(e) if start.elapsed() > Duration::from_secs(20) => {
                    let log = std::fs::read_to_string(d.join("sshd.log")).unwrap_or_default();
                    return Err(format!("no login: {e}\nsshd log:\n{log}"));
                }
                Err(_) => std::thread::sleep(Duration::from_millis(100)),
            }
        }
    }

    /// The client's arguments up to the destination: no user or system config,
    /// no known-hosts file, only the session's key.
    fn ssh_args(&self) -> Vec<String> {
        let key = self.dir.join("client");
        let line = format!(
            "-F /dev/null -p {SSH_PORT} -i {} -o IdentitiesOnly=yes -o BatchMode=yes \
             -o StrictHostKeyChecking=no -o UserKnownHostsFile=/dev/null -o LogLevel=ERROR \
             root@{SERVER_ADDR}",
            key.display()
        );
        line.split_whitespace().map(String::from).collect()
    }

    fn start_pane(&mut self, opts: &Options) {
        let socket = self.tag.clone();
        let ssh = self.ssh_args().join(" ");
        let relief = format!(
            "{} --color {} {}",
            opts.binary.display(),
            opts.color,
            opts.relief_args.join(" ")
        );
        let remote = match opts.server_mux {
            Some(Mux::Tmux) => format!(
                "exec tmux -u -L {socket}-server -f /dev/null new-session \"{relief}\" \\; set status off"
            ),
            Some(Mux::Screen) => {
                // Its own socket directory (screen wants it private).
                let dir = self.dir.join("screen");
                format!(
                    "mkdir -m 700 {d} && SCREENDIR={d} exec screen -U -c /dev/null -S {socket} {relief}",
                    d = dir.display()
                )
            }
            None => format!("exec {relief}"),
        };
        let command = format!("ssh -tt {ssh} '{remote}'; echo {EXITED}$?; sleep 600");
        let size = format!("-x {} -y {}", opts.width, opts.height);
        let mut args = vec![
            "tmux",
            "-L",
            &socket,
            "-f",
            "/dev/null",
            "new-session",
            "-d",
        ];
        args.extend(size.split_whitespace());
        args.push(&command);
        self.bytes_before_pane = self.bytes_to_client();
        run_in(&self.ns('c'), &args).unwrap_or_else(|e| panic!("tmux: {e}"));
        self.tmux = Some(socket);
    }

    /// The namespaces and the directory this session made (all gone after drop).
    pub fn leftovers(&self) -> (Vec<String>, PathBuf) {
        (self.namespaces.clone(), self.dir.clone())
    }

    /// The link's round trip as TCP sees it: the median time of five connections
    /// from the client to sshd (SYN out, SYN-ACK back), idle link.
    pub fn round_trip(&self) -> Duration {
        let mut times = delay_line::in_namespace(&self.ns('c'), || {
            (0..5)
                .map(|_| {
                    let t = Instant::now();
                    std::net::TcpStream::connect((SERVER_ADDR, SSH_PORT))?;
                    Ok(t.elapsed())
                })
                .collect::<std::io::Result<Vec<Duration>>>()
        })
        .expect("a connection to sshd");
        times.sort();
        times[2]
    }

    /// Starts reading, every 10 ms, the server's send queue towards the client
    /// (`tx_queue` of sshd's sockets to the client in the server's `/proc/net/tcp`:
    /// the signal relief reads inside a multiplexer, read here independently).
    pub fn queue_sampler(&self) -> QueueSampler {
        let samples = Arc::new(Mutex::new(Vec::new()));
        let stop = Arc::new(AtomicBool::new(false));
        let path = format!("/run/netns/{}", self.ns('s'));
        let (out, halt) = (samples.clone(), stop.clone());
        let server: std::net::SocketAddr = format!("{SERVER_ADDR}:{SSH_PORT}").parse().unwrap();
        let client: std::net::IpAddr = CLIENT_ADDR.parse().unwrap();
        let thread = std::thread::spawn(move || {
            let ns = std::fs::File::open(path).expect("the server namespace");
            // SAFETY: setns on a valid descriptor affects only this thread.
            if unsafe { libc::setns(ns.as_raw_fd(), libc::CLONE_NEWNET) } != 0 {
                panic!("setns: {}", std::io::Error::last_os_error());
            }
            while !halt.load(Ordering::Relaxed) {
                // thread-self: /proc/net follows the process's first thread.
                let table =
                    std::fs::read_to_string("/proc/thread-self/net/tcp").unwrap_or_default();
                let queued = relief_term::backlog::sockets(&table)
                    .filter(|s| s.state == 1 && s.local == server && s.remote.ip() == client)
                    .map(|s| s.tx_queue)
                    .max()
                    .unwrap_or(0);
                out.lock().unwrap().push((Instant::now(), queued));
                std::thread::sleep(Duration::from_millis(10));
            }
        });
        QueueSampler {
            samples,
            stop,
            thread: Some(thread),
        }
    }

    /// Starts reading, every 5 ms, the bytes that crossed the link towards the
    /// client (the link namespace's `/proc/net/dev`, read from a thread that
    /// joined it: cheaper than [`Session::bytes_to_client`], which runs a program).
    pub fn link_sampler(&self) -> LinkSampler {
        let samples = Arc::new(Mutex::new(Vec::new()));
        let stop = Arc::new(AtomicBool::new(false));
        let path = format!("/run/netns/{}", self.ns('m'));
        let (out, halt) = (samples.clone(), stop.clone());
        let thread = std::thread::spawn(move || {
            let ns = std::fs::File::open(path).expect("the link namespace");
            // SAFETY: setns on a valid descriptor affects only this thread.
            if unsafe { libc::setns(ns.as_raw_fd(), libc::CLONE_NEWNET) } != 0 {
                panic!("setns: {}", std::io::Error::last_os_error());
            }
            while !halt.load(Ordering::Relaxed) {
                let table =
                    std::fs::read_to_string("/proc/thread-self/net/dev").unwrap_or_default();
                // `  mc: rx_bytes rx_packets … (8 fields) tx_bytes …`
                let sent = table.lines().find_map(|l| {
                    let (name, rest) = l.split_once(':')?;
                    (name.trim() == "mc").then(|| rest.split_whitespace().nth(8)?.parse().ok())?
                });
                if let Some(sent) = sent {
                    out.lock().unwrap().push((Instant::now(), sent));
                }
                std::thread::sleep(Duration::from_millis(5));
            }
        });
        LinkSampler {
            samples,
            stop,
            thread: Some(thread),
        }
    }

    /// Bytes that crossed the link towards the client since the pane started.
    pub fn bytes_since_pane_start(&self) -> u64 {
        self.bytes_to_client() - self.bytes_before_pane
    }

    /// Bytes that crossed the link from the server to the client so far
    /// (Ethernet frames: relief's output with SSH, TCP and IP around it).
    pub fn bytes_to_client(&self) -> u64 {
        self.port_bytes("mc")
    }

    /// Bytes that crossed the link from the client to the server so far.
    pub fn bytes_to_server(&self) -> u64 {
        self.port_bytes("ms")
    }

    fn port_bytes(&self, port: &str) -> u64 {
        let path = format!("/sys/class/net/{port}/statistics/tx_bytes");
        run_in(&self.ns('m'), &["cat", &path])
            .expect("the link's counters")
            .trim()
            .parse()
            .expect("a byte count")
    }

    pub fn tmux(&self, args: &[&str]) -> String {
        let socket = self.tmux.as_deref().expect("the pane runs");
        let mut all = vec!["-L", socket];
        all.extend_from_slice(args);
        run("tmux", &all).unwrap_or_else(|e| panic!("tmux: {e}"))
    }

    /// The pane's text with colours (what a frame put there).
    pub fn picture(&self) -> String {
        self.tmux(&["capture-pane", "-p", "-e", "-N"])
    }

    /// The pane's text.
    pub fn screen(&self) -> String {
        self.tmux(&["capture-pane", "-p"])
    }

    /// A tmux format of the pane, e.g. `#{alternate_on}`.
    pub fn format(&self, f: &str) -> String {
        self.tmux(&["display-message", "-p", f]).trim().to_string()
    }

    /// Named keys (`Right`, `q`), as typed.
    pub fn keys(&self, keys: &[&str]) {
        let mut args = vec!["send-keys"];
        args.extend_from_slice(keys);
        self.tmux(&args);
    }

    /// Bytes as typed, e.g. an SGR mouse report.
    pub fn literal(&self, text: &str) {
        self.tmux(&["send-keys", "-l", text]);
    }

    /// Starts copying what the pane receives (the ssh client's output: relief's
    /// bytes as they arrive, before the pane's terminal parses them) to a file,
    /// its length read every 5 ms.
    pub fn record_pane(&self) -> PaneRecorder {
        let path = self.dir.join("pane.out");
        std::fs::write(&path, b"").expect("the pane's record");
        self.tmux(&["pipe-pane", "-O", &format!("cat >> {}", path.display())]);
        let samples = Arc::new(Mutex::new(Vec::new()));
        let stop = Arc::new(AtomicBool::new(false));
        let (out, halt, file) = (samples.clone(), stop.clone(), path.clone());
        let thread = std::thread::spawn(move || {
            while !halt.load(Ordering::Relaxed) {
                if let Ok(m) = std::fs::metadata(&file) {
                    out.lock().unwrap().push((Instant::now(), m.len()));
                }
                std::thread::sleep(Duration::from_millis(5));
            }
        });
        PaneRecorder {
            path,
            samples,
            stop,
            thread: Some(thread),
        }
    }

    /// The server's log so far (for a failure message).
    pub fn sshd_log(&self) -> String {
        std::fs::read_to_string(self.dir.join("sshd.log")).unwrap_or_default()
    }
}

/// Readings of the server's send queue towards the client: (when, bytes).
pub struct QueueSampler {
    samples: Arc<Mutex<Vec<(Instant, u64)>>>,
    stop: Arc<AtomicBool>,
    thread: Option<std::thread::JoinHandle<()>>,
}

impl QueueSampler {
    /// The readings taken at or after `from`.
    pub fn since(&self, from: Instant) -> Vec<(Instant, u64)> {
        let all = self.samples.lock().unwrap();
        all.iter().filter(|(t, _)| *t >= from).copied().collect()
    }
}

impl Drop for QueueSampler {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

/// What the pane received, in a file: its bytes, and its length over time.
pub struct PaneRecorder {
    path: PathBuf,
    samples: Arc<Mutex<Vec<(Instant, u64)>>>,
    stop: Arc<AtomicBool>,
    thread: Option<std::thread::JoinHandle<()>>,
}

impl PaneRecorder {
    /// Everything received so far.
    pub fn bytes(&self) -> Vec<u8> {
        std::fs::read(&self.path).unwrap_or_default()
    }

    /// How many bytes were received so far.
    pub fn received(&self) -> u64 {
        std::fs::metadata(&self.path).map_or(0, |m| m.len())
    }

    /// When the record first reached `len` bytes (the first reading that saw it).
    pub fn reached(&self, len: u64) -> Option<Instant> {
        let all = self.samples.lock().unwrap();
        all.iter().find(|(_, l)| *l >= len).map(|(t, _)| *t)
    }
}

impl Drop for PaneRecorder {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

/// Readings of the bytes that crossed the link towards the client: (when, total).
pub struct LinkSampler {
    samples: Arc<Mutex<Vec<(Instant, u64)>>>,
    stop: Arc<AtomicBool>,
    thread: Option<std::thread::JoinHandle<()>>,
}

impl LinkSampler {
    /// When bytes last crossed the link, if the link has then been quiet for
    /// `quiet` (and the latest total); `None` while bytes still flow.
    pub fn quiet_since(&self, quiet: Duration) -> Option<(Instant, u64)> {
        let all = self.samples.lock().unwrap();
        let &(now, total) = all.last()?;
        // The first reading with today's total: the bytes came just before it.
        let first = all.iter().rev().take_while(|(_, b)| *b == total).last()?;
        (now - first.0 >= quiet).then_some((first.0, total))
    }
}

impl Drop for LinkSampler {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

impl Drop for Session {
    fn drop(&mut self) {
        if let Some(socket) = self.tmux.take() {
            let _ = run("tmux", &["-L", &socket, "kill-server"]);
        }
        if let Some(mut sshd) = self.sshd.take() {
            let _ = sshd.kill();
            let _ = sshd.wait();
        }
        // Whatever still runs inside the namespaces was started by this session
        // (sshd's session processes, relief, ssh): end each by its id.
        for ns in &self.namespaces {
            for pid in run("ip", &["netns", "pids", ns])
                .unwrap_or_default()
                .split_whitespace()
            {
                if let Ok(pid) = pid.parse::<libc::pid_t>() {
                    // SAFETY: kill has no memory preconditions.
                    unsafe { libc::kill(pid, libc::SIGKILL) };
                }
            }
        }
        self.delay = None;
        for ns in self.namespaces.drain(..).rev() {
            let _ = run("ip", &["netns", "del", &ns]);
        }
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}
