//! Asking the terminal whether it takes 24-bit colour, for when the
//! environment does not say (over SSH `COLORTERM` is rarely forwarded).
//!
//! Two questions, then a sentinel:
//! - XTGETTCAP (`DCS + q <hex names> ST`) for the terminfo capabilities `RGB`
//!   and `Tc`: a terminal that has one answers `DCS 1 + r <name>[=…] ST`, one
//!   that lacks it `DCS 0 + r ST`.
//! - DECRQSS: set the background to the 24-bit colour 1,2,3 and ask for the
//!   current SGR (`DCS $ q m ST`); a terminal that keeps 24-bit colours reports
//!   the same colour (`DCS 1 $ r …48:2::1:2:3m ST`), others a palette index.
//! - For pixel output ([`crate::format`]): the kitty graphics query
//!   (`APC G a=q` of a 1×1 image; a kitty-speaking terminal answers
//!   `APC G i=31;OK ST`), XTVERSION (`CSI > q`, answered `DCS > | name
//!   version ST`) and the cell size in pixels (`CSI 16 t`, answered
//!   `CSI 6 ; height ; width t`).
//! - The largest sixel image (XTSMGRAPHICS, `CSI ? 2 ; 1 ; 0 S` for the
//!   current one and `CSI ? 2 ; 4 ; 0 S` for the most allowed, answered
//!   `CSI ? 2 ; 0 ; width ; height S` by xterm, foot, mlterm, WezTerm…):
//!   xterm drops an image larger than its `maxGraphicSize` (1000×1000 by
//!   default) without a trace, so relief never sends a larger one. xterm's
//!   current size is that limit cut to the window at start (1000×672 in a
//!   160×48 window of 14-pixel rows): the larger of the two answers counts,
//!   so a window enlarged later is not held to its first size. An error
//!   status or no answer leaves no limit.
//! - Primary device attributes (`CSI c`), which every terminal answers, and
//!   answers after the questions before it: once its reply is in, no other
//!   answer is coming and there is nothing to wait for. A parameter `4` in
//!   it says the terminal draws sixel images.
//!
//! Inside tmux with `allow-passthrough` on, tmux answers these questions
//! itself; once its answers are in, the device attributes are asked again
//! of its client terminal through the passthrough ([`CLIENT_DA1`]), whose
//! reply tmux hands to the pane: a `4` there says the client draws sixel.
//! Not in the same burst: tmux 3.3 loses a passthrough that arrives in one
//! read with the switch to the alternate screen, and tmux's answer to the
//! first burst comes after that switch is done.
//!
//! Bytes that are not replies (keys typed meanwhile) are kept for the input
//! decoder.

use std::io::{self, Write};
use std::os::fd::{AsRawFd, BorrowedFd};
use std::time::{Duration, Instant};

/// The questions, in the order the replies come back.
pub const QUERY: &[u8] = b"\x1bP+q524742;5463\x1b\\\x1b[48:2::1:2:3m\x1bP$qm\x1b\\\x1b[0m\
\x1b_Gi=31,s=1,v=1,a=q,t=d,f=24;AAAA\x1b\\\x1b[>q\x1b[16t\x1b[?2;1;0S\x1b[?2;4;0S\x1b[c";

/// The kitty graphics query in [`QUERY`]: left out inside tmux, which has
/// no answer to it and takes an `APC` string as a new window name.
pub const KITTY_QUERY: &[u8] = b"\x1b_Gi=31,s=1,v=1,a=q,t=d,f=24;AAAA\x1b\\";

/// [`QUERY`] without [`KITTY_QUERY`] (inside tmux).
pub fn query_in_tmux() -> Vec<u8> {
    let at = QUERY
        .windows(KITTY_QUERY.len())
        .position(|w| w == KITTY_QUERY)
        .expect("the query holds the kitty query");
    [&QUERY[..at], &QUERY[at + KITTY_QUERY.len()..]].concat()
}

/// The device attributes asked of tmux's client terminal, through tmux's
/// passthrough (`CSI c` with its `ESC` doubled).
pub const CLIENT_DA1: &[u8] = b"\x1bPtmux;\x1b\x1b[c\x1b\\";

/// Longest wait for the replies (over SSH the round trip counts).
pub const TIMEOUT: Duration = Duration::from_millis(250);

/// What the replies said.
#[derive(Debug, Default, PartialEq, Eq)]
pub struct Outcome {
    /// A positive answer to one of the questions.
    pub truecolor: bool,
    /// The device-attributes reply came (false: timed out).
    pub answered: bool,
    /// The kitty graphics query was answered OK.
    pub kitty: bool,
    /// The device attributes list `4`: sixel graphics.
    pub sixel: bool,
    /// Inside tmux with passthrough: whether the client terminal's device
    /// attributes list `4` (`None`: not asked, or no reply in time).
    pub client_sixel: Option<bool>,
    /// The XTVERSION reply (`kitty(0.35.2)`, `XTerm(390)`, `WezTerm 2024…`).
    pub version: Option<String>,
    /// The cell size in pixels (width, height) from the `CSI 16 t` reply.
    pub cell_pixels: Option<(u16, u16)>,
    /// The largest sixel image (width, height) in pixels, from the
    /// XTSMGRAPHICS reply (`None`: no answer, or an error status).
    pub sixel_max: Option<(u32, u32)>,
    /// Input that was not part of a reply, in arrival order.
    pub other: Vec<u8>,
}

/// Separates replies from other input, across reads of any size.
#[derive(Debug, Default)]
pub struct ReplyScanner {
    pending: Vec<u8>,
    outcome: Outcome,
}

/// A complete escape sequence at the start of `bytes`, or why not.
enum Seq {
    /// Needs more bytes.
    Partial,
    /// A device-control or application-program-command string: its body
    /// (between `ESC P` or `ESC _` and `ESC \`) and length.
    Dcs(usize, usize),
    /// A control sequence: parameters end and length.
    Csi(usize),
    /// Not a sequence this scanner knows: pass one byte on.
    Other,
}

fn sequence(bytes: &[u8]) -> Seq {
    match bytes.get(1) {
        None => Seq::Partial,
        Some(b'P') | Some(b'_') => match bytes[2..].windows(2).position(|w| w == b"\x1b\\") {
            Some(end) => Seq::Dcs(2 + end, 2 + end + 2),
            None => Seq::Partial,
        },
        Some(b'[') => match bytes[2..].iter().position(|b| (0x40..=0x7e).contains(b)) {
            Some(fin) => Seq::Csi(2 + fin + 1),
            None => Seq::Partial,
        },
        Some(_) => Seq::Other,
    }
}

/// True for a reply that says 24-bit colour.
fn positive(body: &[u8]) -> bool {
    if let Some(names) = body.strip_prefix(b"1+r") {
        // `name[=value]` pairs separated by `;`; names hex-encoded.
        return names.split(|&b| b == b';').any(|pair| {
            let name = pair.split(|&b| b == b'=').next().unwrap_or(&[]);
            name.eq_ignore_ascii_case(b"524742") || name.eq_ignore_ascii_case(b"5463")
        });
    }
    if let Some(sgr) = body.strip_prefix(b"1$r") {
        // The colour set before the question, with `:` or `;` separators and
        // the colour-space field present or not.
        let text: String = sgr.iter().map(|&b| b as char).collect();
        let text = text.replace(';', ":");
        return text.contains("48:2::1:2:3") || text.contains("48:2:1:2:3");
    }
    false
}

/// True for the kitty graphics reply to relief's query (image id 31) that
/// says OK; an error reply (`i=31;ENOTSUPPORTED:…`) is not.
fn kitty_ok(body: &[u8]) -> bool {
    let Some(rest) = body.strip_prefix(b"G") else {
        return false;
    };
    let (keys, message) = match rest.iter().position(|&b| b == b';') {
        Some(at) => (&rest[..at], &rest[at + 1..]),
        None => return false,
    };
    keys.split(|&b| b == b',').any(|k| k == b"i=31") && message == b"OK"
}

/// The cell size (width, height) in a `CSI 6 ; height ; width t` reply's
/// parameters; none for other replies or a zero size.
fn cell_size(params: &[u8]) -> Option<(u16, u16)> {
    let text = std::str::from_utf8(params).ok()?;
    let mut it = text.split(';');
    if it.next()? != "6" {
        return None;
    }
    let h: u16 = it.next()?.parse().ok()?;
    let w: u16 = it.next()?.parse().ok()?;
    (w > 0 && h > 0 && it.next().is_none()).then_some((w, h))
}

/// The size (width, height) in a successful XTSMGRAPHICS sixel-geometry
/// reply's parameters (`?2;0;W;H`); none for an error status (`?2;3;0`),
/// another item or a zero size.
fn sixel_geometry(params: &[u8]) -> Option<(u32, u32)> {
    let text = std::str::from_utf8(params).ok()?;
    let mut it = text.strip_prefix('?')?.split(';');
    if (it.next()?, it.next()?) != ("2", "0") {
        return None;
    }
    let w: u32 = it.next()?.parse().ok()?;
    let h: u32 = it.next()?.parse().ok()?;
    (w > 0 && h > 0 && it.next().is_none()).then_some((w, h))
}

impl ReplyScanner {
    pub fn new() -> Self {
        Self::default()
    }

    /// Takes the next bytes read from the terminal.
    pub fn feed(&mut self, bytes: &[u8]) {
        self.pending.extend_from_slice(bytes);
        let mut i = 0;
        while i < self.pending.len() && !self.outcome.answered {
            let rest = &self.pending[i..];
            if rest[0] != 0x1b {
                self.outcome.other.push(rest[0]);
                i += 1;
                continue;
            }
            match sequence(rest) {
                Seq::Partial => break,
                Seq::Dcs(end, len) => {
                    let body = &rest[2..end];
                    if rest[1] == b'_' {
                        self.outcome.kitty |= kitty_ok(body);
                    } else if let Some(name) = body.strip_prefix(b">|") {
                        self.outcome.version = Some(String::from_utf8_lossy(name).into_owned());
                    } else if positive(body) {
                        self.outcome.truecolor = true;
                    }
                    i += len;
                }
                Seq::Csi(len) => {
                    let params = &rest[2..len - 1];
                    if rest[2] == b'?' && rest[len - 1] == b'c' {
                        self.outcome.answered = true;
                        self.outcome.sixel = params[1..].split(|&b| b == b';').any(|p| p == b"4");
                    } else if rest[len - 1] == b't'
                        && let Some(size) = cell_size(params)
                    {
                        self.outcome.cell_pixels = Some(size);
                    } else if rest[2] == b'?' && rest[len - 1] == b'S' {
                        // A graphics attribute reply, success or error: no
                        // key. The larger answer is the most allowed.
                        let answer = sixel_geometry(params);
                        self.outcome.sixel_max = match (self.outcome.sixel_max, answer) {
                            (Some((w0, h0)), Some((w1, h1))) => Some((w0.max(w1), h0.max(h1))),
                            (known, None) | (None, known) => known,
                        };
                    } else {
                        // A key (arrows, function keys): the decoder's.
                        self.outcome.other.extend_from_slice(&rest[..len]);
                    }
                    i += len;
                }
                Seq::Other => {
                    self.outcome.other.push(0x1b);
                    i += 1;
                }
            }
        }
        self.pending.drain(..i);
    }

    /// True once the sentinel's reply is in.
    pub fn done(&self) -> bool {
        self.outcome.answered
    }

    /// The outcome so far, and the bytes not read yet (after the sentinel,
    /// or an unfinished sequence).
    pub fn split(self) -> (Outcome, Vec<u8>) {
        (self.outcome, self.pending)
    }

    /// The outcome; unfinished sequences and anything after the sentinel
    /// go to the other input.
    pub fn finish(mut self) -> Outcome {
        self.outcome.other.append(&mut self.pending);
        self.outcome
    }
}

/// Asks the terminal on `out` and reads its replies from `input` (in raw
/// mode) until the sentinel's reply or `timeout`; then, when
/// `through_tmux`, tmux's client's device attributes ([`CLIENT_DA1`])
/// within what is left of `timeout`. `in_tmux`: [`query_in_tmux`].
pub fn ask(
    input: BorrowedFd,
    out: &mut impl Write,
    timeout: Duration,
    in_tmux: bool,
    through_tmux: bool,
) -> io::Result<Outcome> {
    let deadline = Instant::now() + timeout;
    let questions = if in_tmux {
        query_in_tmux()
    } else {
        QUERY.to_vec()
    };
    let first = ask_until(input, out, &questions, deadline, ReplyScanner::new())?;
    if !(through_tmux && first.done()) {
        return Ok(first.finish());
    }
    // What came after tmux's answers is read as the client's.
    let (mut outcome, rest) = first.split();
    let mut second = ReplyScanner::new();
    second.feed(&rest);
    let client = ask_until(input, out, CLIENT_DA1, deadline, second)?.finish();
    outcome.client_sixel = client.answered.then_some(client.sixel);
    outcome.other.extend(client.other);
    Ok(outcome)
}

/// Writes `questions` and reads until the device attributes' reply or
/// `deadline`.
fn ask_until(
    input: BorrowedFd,
    out: &mut impl Write,
    questions: &[u8],
    deadline: Instant,
    mut scanner: ReplyScanner,
) -> io::Result<ReplyScanner> {
    out.write_all(questions)?;
    out.flush()?;
    let mut buf = [0u8; 1024];
    while !scanner.done() {
        let left = deadline.saturating_duration_since(Instant::now());
        if left.is_zero() {
            break;
        }
        match super::wait::readable_within(input.as_raw_fd(), left) {
            Ok(true) => {}
            Ok(false) => break,
            Err(e) => return Err(e),
        }
        // SAFETY: reads at most buf.len() bytes into buf from an open descriptor.
        let n = unsafe { libc::read(input.as_raw_fd(), buf.as_mut_ptr().cast(), buf.len()) };
        if n < 0 {
            let err = io::Error::last_os_error();
            if err.kind() == io::ErrorKind::Interrupted {
                continue;
            }
            return Err(err);
        }
        if n == 0 {
            break;
        }
        scanner.feed(&buf[..n as usize]);
    }
    Ok(scanner)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scan(chunks: &[&[u8]]) -> Outcome {
        let mut s = ReplyScanner::new();
        for c in chunks {
            s.feed(c);
        }
        s.finish()
    }

    const DA1: &[u8] = b"\x1b[?64;1;2;6;22c";

    #[test]
    fn xtgettcap_positive_answers() {
        // kitty style: the name with a value; xterm style: the bare name.
        let o = scan(&[b"\x1bP1+r524742=382F382F38\x1b\\", DA1]);
        assert!(o.truecolor && o.answered && o.other.is_empty(), "{o:?}");
        let o = scan(&[b"\x1bP0+r524742\x1b\\\x1bP1+r5463\x1b\\", DA1]);
        assert!(o.truecolor, "{o:?}");
    }

    #[test]
    fn negative_answers_and_da1_alone_mean_no() {
        let o = scan(&[b"\x1bP0+r\x1b\\\x1bP0$r\x1b\\", DA1]);
        assert_eq!(
            o,
            Outcome {
                truecolor: false,
                answered: true,
                ..Outcome::default()
            }
        );
        let o = scan(&[DA1]);
        assert!(!o.truecolor && o.answered);
    }

    #[test]
    fn decrqss_replies() {
        for reply in [
            &b"\x1bP1$r0;48:2::1:2:3m\x1b\\"[..],
            b"\x1bP1$r48;2;1;2;3m\x1b\\",
            b"\x1bP1$r0;48:2:1:2:3m\x1b\\",
        ] {
            assert!(scan(&[reply, DA1]).truecolor, "{reply:?}");
        }
        // A 256-colour terminal reports the palette colour it chose.
        assert!(!scan(&[b"\x1bP1$r0;48;5;16m\x1b\\", DA1]).truecolor);
    }

    #[test]
    fn kitty_sixel_version_and_cell_size_replies() {
        // kitty: the graphics reply, its version, no sixel in DA1.
        let o = scan(&[
            b"\x1b_Gi=31;OK\x1b\\",
            b"\x1bP>|kitty(0.35.2)\x1b\\",
            b"\x1b[6;20;10t",
            b"\x1b[?62;c",
        ]);
        assert!(
            o.kitty && !o.sixel && o.answered && o.other.is_empty(),
            "{o:?}"
        );
        assert_eq!(o.version.as_deref(), Some("kitty(0.35.2)"));
        assert_eq!(o.cell_pixels, Some((10, 20)));
        // xterm -ti vt340: no graphics reply, sixel in DA1.
        let o = scan(&[b"\x1bP>|XTerm(390)\x1b\\\x1b[?63;1;2;4;6;9;15;16;22;28;29c"]);
        assert!(!o.kitty && o.sixel, "{o:?}");
        assert_eq!(o.version.as_deref(), Some("XTerm(390)"));
        // A refusal is not support; 4 must be a whole parameter (not 64, 14 or 42).
        let o = scan(&[b"\x1b_Gi=31;ENOTSUPPORTED:no\x1b\\", b"\x1b[?64;14;42c"]);
        assert!(!o.kitty && !o.sixel && o.cell_pixels.is_none(), "{o:?}");
        // Another image's OK is not an answer to relief's query.
        assert!(!scan(&[b"\x1b_Gi=7;OK\x1b\\", DA1]).kitty);
        // Other t replies (window size in characters, 8 t) are not a cell size.
        assert!(scan(&[b"\x1b[8;24;80t", DA1]).cell_pixels.is_none());
        assert!(scan(&[b"\x1b[6;0;0t", DA1]).cell_pixels.is_none());
    }

    #[test]
    fn the_largest_sixel_image_is_read_from_a_successful_reply_only() {
        // xterm 379 by default, in a 160×48 window: the current size, then
        // the most allowed; foot.
        let o = scan(&[b"\x1b[?2;0;1000;672S\x1b[?2;0;1000;1000S", DA1]);
        assert_eq!(o.sixel_max, Some((1000, 1000)));
        // Only the current size answered, or the other an error.
        let o = scan(&[b"\x1b[?2;0;1000;672S\x1b[?2;2;0S", DA1]);
        assert_eq!(o.sixel_max, Some((1000, 672)));
        assert!(o.other.is_empty(), "{o:?}");
        let o = scan(&[b"\x1b[?2;0;10000;10000S\x1b[?63;4c"]);
        assert_eq!((o.sixel_max, o.sixel), (Some((10000, 10000)), true));
        // Error statuses (item, action, failure) and odd replies: no limit,
        // and never taken for a key.
        for reply in [
            // xterm 379 without `-ti vt340` (no sixel): failure, no value.
            &b"\x1b[?2;3S"[..],
            b"\x1b[?2;1;0S",
            b"\x1b[?2;2;0S",
            b"\x1b[?2;3;0S",
            b"\x1b[?2;0;0;0S",
            b"\x1b[?2;0;640S",
            b"\x1b[?2;0;640;480;1S",
            b"\x1b[?1;0;256S",
        ] {
            let o = scan(&[reply, DA1]);
            assert_eq!(o.sixel_max, None, "{reply:?}");
            assert!(o.answered && o.other.is_empty(), "{reply:?}: {o:?}");
        }
        // No answer (most terminals without sixel): no limit, as before.
        assert_eq!(scan(&[DA1]).sixel_max, None);
    }

    #[test]
    fn the_query_asks_every_question_before_the_device_attributes() {
        let text = String::from_utf8_lossy(QUERY);
        let da1 = text.find("\x1b[c").unwrap();
        assert_eq!(da1 + 3, text.len(), "DA1 is the fence, last");
        for q in [
            "\x1b_Gi=31,s=1,v=1,a=q,t=d,f=24;AAAA\x1b\\",
            "\x1b[>q",
            "\x1b[16t",
            "\x1b[?2;1;0S",
            "\x1b[?2;4;0S",
        ] {
            assert!(text[..da1].contains(q), "{q:?}");
        }
    }

    #[test]
    fn through_tmux_the_client_is_asked_after_tmux_answered() {
        // A pipe that already holds tmux's answers (no 4) and the client's
        // device attributes (with 4), and a key typed in between.
        let mut fds = [0; 2];
        // SAFETY: fds has room for the two descriptors.
        assert_eq!(unsafe { libc::pipe(fds.as_mut_ptr()) }, 0);
        use std::os::fd::{FromRawFd, OwnedFd};
        // SAFETY: both descriptors were just opened and are owned here only.
        let (read, write) = unsafe { (OwnedFd::from_raw_fd(fds[0]), OwnedFd::from_raw_fd(fds[1])) };
        let replies = b"\x1bP>|tmux 3.3a\x1b\\\x1b[?1;2cq\x1b[?63;1;2;4;6;9c";
        let mut w = std::fs::File::from(write);
        w.write_all(replies).unwrap();
        let mut out = Vec::new();
        let o = ask(
            std::os::fd::AsFd::as_fd(&read),
            &mut out,
            Duration::from_secs(5),
            true,
            true,
        )
        .unwrap();
        // No kitty query inside tmux (it would rename the window).
        let plain = query_in_tmux();
        assert_eq!(plain.len(), QUERY.len() - KITTY_QUERY.len());
        assert!(!String::from_utf8_lossy(&plain).contains("\x1b_"));
        assert_eq!(out, [plain.as_slice(), CLIENT_DA1].concat());
        assert!(!o.sixel, "tmux itself draws no sixel");
        assert_eq!(o.client_sixel, Some(true));
        assert_eq!(o.version.as_deref(), Some("tmux 3.3a"));
        assert_eq!(o.other, b"q");
        // Outside tmux the client is not asked.
        w.write_all(b"\x1b[?1;2c").unwrap();
        out.clear();
        let o = ask(
            std::os::fd::AsFd::as_fd(&read),
            &mut out,
            Duration::from_secs(5),
            false,
            false,
        )
        .unwrap();
        assert_eq!((out.as_slice(), o.client_sixel), (QUERY, None));
    }

    #[test]
    fn replies_split_anywhere_are_read_whole() {
        let all: Vec<u8> = [
            &b"\x1bP1+r5463\x1b\\"[..],
            b"\x1b_Gi=31;OK\x1b\\\x1b[6;16;8t\x1b[?2;0;1000;800S",
            DA1,
        ]
        .concat();
        for cut in 1..all.len() {
            let (a, b) = all.split_at(cut);
            let mut s = ReplyScanner::new();
            s.feed(a);
            assert!(!s.done() || cut == all.len());
            s.feed(b);
            assert!(s.done());
            let o = s.finish();
            assert!(
                o.truecolor && o.kitty && o.other.is_empty(),
                "cut {cut}: {o:?}"
            );
            assert_eq!(o.cell_pixels, Some((8, 16)));
            assert_eq!(o.sixel_max, Some((1000, 800)), "cut {cut}");
        }
    }

    #[test]
    fn keys_typed_meanwhile_are_kept_in_order() {
        let o = scan(&[
            b"q",
            b"\x1b[A\x1bP0+r\x1b\\x",
            b"\x1b",
            b"\x1b[1;5C",
            DA1,
            b"zz",
        ]);
        assert!(!o.truecolor && o.answered);
        assert_eq!(o.other, b"q\x1b[Ax\x1b\x1b[1;5Czz");
    }

    #[test]
    fn no_answer_keeps_everything() {
        let o = scan(&[b"ab\x1b"]);
        assert!(!o.answered && !o.truecolor);
        assert_eq!(o.other, b"ab\x1b");
    }

    #[test]
    fn a_terminal_that_answers_nothing_times_out() {
        // A pipe nobody writes to: the time-out ends the wait.
        let mut fds = [0; 2];
        // SAFETY: fds has room for the two descriptors.
        assert_eq!(unsafe { libc::pipe(fds.as_mut_ptr()) }, 0);
        use std::os::fd::{FromRawFd, OwnedFd};
        // SAFETY: both descriptors were just opened and are owned here only.
        let (read, write) = unsafe { (OwnedFd::from_raw_fd(fds[0]), OwnedFd::from_raw_fd(fds[1])) };
        let mut out = Vec::new();
        let o = ask(
            std::os::fd::AsFd::as_fd(&read),
            &mut out,
            Duration::from_millis(20),
            false,
            false,
        )
        .unwrap();
        assert_eq!(out, QUERY);
        assert!(!o.answered && !o.truecolor);
        drop(write);
    }
}
