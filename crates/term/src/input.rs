//! Bytes from the terminal → key, mouse and paste events.
//!
//! relief reads the terminal itself rather than through crossterm's event
//! reader, which retries forever when the terminal reports end of file or an
//! error (an SSH connection dropped) instead of returning. Decoded here:
//! UTF-8 text, control keys, CSI/SS3 cursor keys, SGR mouse reports
//! (`ESC [ < b ; x ; y M/m`), bracketed paste (`ESC [ 200~ … ESC [ 201~`),
//! and the terminal's answer to a device attributes query (`ESC [ ? … c`),
//! which is the pacing's acknowledgement and never a key. String replies
//! (`ESC P`, `ESC ]`, `ESC _`, `ESC ^`, `ESC X` up to `ESC \` or BEL), such
//! as a capability answer arriving after the start-up probe gave up, are
//! swallowed whole: none of their bytes may turn into keys.
//!
//! Nothing left open holds the keys after it for long: a paste whose end
//! never comes is closed once its bytes stop for [`PASTE_WAIT`], a
//! sequence still unfinished [`SEQUENCE_WAIT`] after its start is
//! dropped, and a control byte (Ctrl-C) inside a sequence or a paste is
//! the key it is: terminals filter control bytes out of what they paste,
//! so one there was typed. The time is the caller's (`feed_at`,
//! [`InputParser::expire`]), so tests drive it without sleeping.

use std::time::{Duration, Instant};

use crossterm::event::{
    Event, KeyCode, KeyEvent, KeyModifiers, MouseButton, MouseEvent, MouseEventKind,
};

const PASTE_END: &[u8] = b"\x1b[201~";
/// Ctrl-C: the key that always quits.
const CTRL_C: u8 = 0x03;
/// A paste larger than this is cut (it is shown, not stored).
const PASTE_LIMIT: usize = 1 << 20;
/// A control sequence longer than this is garbage and is dropped.
const CSI_LIMIT: usize = 64;
/// A string reply longer than this without its terminator was not one:
/// its introducer is read as an Alt key and the bytes after it as input.
const STRING_LIMIT: usize = 1024;
/// A paste whose bytes stop this long without its end marker is closed
/// (what came is the paste): a lost `ESC [ 201 ~` must not hold the keys.
/// Long enough for a paste stalled on a slow link to go on.
pub const PASTE_WAIT: Duration = Duration::from_secs(1);
/// A sequence (CSI, SS3 or a string reply) not finished this long after
/// its first byte is dropped, so the keys typed after it are keys again.
/// A terminal's reply comes whole within a round trip.
pub const SEQUENCE_WAIT: Duration = Duration::from_millis(300);

/// What the terminal sent: input, or a reply to a query.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Input {
    Event(Event),
    /// A primary device attributes reply: everything written before the
    /// query has been processed.
    DeviceAttributes,
}

/// Incremental decoder: feed it whatever `read` returned.
#[derive(Debug, Default)]
pub struct InputParser {
    pending: Vec<u8>,
    /// When the first byte of what is pending (outside a paste) arrived.
    pending_since: Option<Instant>,
    paste: Option<Vec<u8>>,
    /// When the open paste's last bytes arrived.
    paste_seen: Option<Instant>,
    /// Keep a trailing lone `ESC` (or `ESC` + string introducer) for
    /// [`flush_pending`](Self::flush_pending) instead of deciding at the end
    /// of each read: over a network a reply can be split after its `ESC`.
    hold: bool,
}

fn key_event(code: KeyCode, modifiers: KeyModifiers) -> Event {
    Event::Key(KeyEvent::new(code, modifiers))
}

fn key(code: KeyCode, modifiers: KeyModifiers) -> Input {
    Input::Event(key_event(code, modifiers))
}

enum Step {
    /// Consumed `n` bytes, maybe producing an event.
    Done(usize, Option<Input>),
    /// Not enough bytes yet.
    Incomplete,
}

impl InputParser {
    pub fn new() -> Self {
        Self::default()
    }

    /// A decoder whose caller waits a moment after a read that ends in a
    /// lone `ESC` and then calls [`flush_pending`](Self::flush_pending).
    pub fn holding_escape() -> Self {
        InputParser {
            hold: true,
            ..Self::default()
        }
    }

    /// True when what is pending is a lone `ESC` or `ESC` + a string
    /// introducer: a key if nothing follows soon, else the start of a sequence.
    pub fn waiting(&self) -> bool {
        self.paste.is_none()
            && match self.pending[..] {
                [0x1b] => true,
                [0x1b, c] => is_string_introducer(c),
                _ => false,
            }
    }

    /// Nothing followed a [`waiting`](Self::waiting) `ESC`: it is the Escape
    /// key (or Alt + the introducer's key).
    pub fn flush_pending(&mut self, out: &mut Vec<Input>) {
        if !self.waiting() {
            return;
        }
        let pending = std::mem::take(&mut self.pending);
        self.pending_since = None;
        match pending[..] {
            [_, c] => {
                if let Step::Done(_, Some(Input::Event(Event::Key(mut k)))) =
                    InputParser::default().step_bytes(&[c])
                {
                    k.modifiers |= KeyModifiers::ALT;
                    out.push(Input::Event(Event::Key(k)));
                }
            }
            _ => out.push(key(KeyCode::Esc, KeyModifiers::NONE)),
        }
    }

    /// Decodes one complete item from `bytes` (for [`flush_pending`](Self::flush_pending)).
    fn step_bytes(&mut self, bytes: &[u8]) -> Step {
        self.pending = bytes.to_vec();
        self.step(0)
    }

    /// Decodes `bytes`, read now, appending events to `out` (see [`Self::feed_at`]).
    pub fn feed(&mut self, bytes: &[u8], out: &mut Vec<Input>) {
        self.feed_at(bytes, Instant::now(), out);
    }

    /// Decodes `bytes`, read at `now`, appending events to `out`. What was
    /// left open past its time by `now` is closed first (see
    /// [`Self::expire`]). A lone `ESC` at the end of a read is the Escape
    /// key (terminals send sequences in one piece), unless the decoder was
    /// made with [`holding_escape`](Self::holding_escape).
    pub fn feed_at(&mut self, bytes: &[u8], now: Instant, out: &mut Vec<Input>) {
        self.expire(now, out);
        let before = self.pending.len();
        self.pending.extend_from_slice(bytes);
        let start = self.decode(out);
        self.pending.drain(..start);
        if self.paste.is_some() && (!bytes.is_empty() || self.paste_seen.is_none()) {
            self.paste_seen = Some(now);
        }
        // A sequence started in this read dates from now; one still
        // waiting for its end keeps its start.
        self.pending_since = match self.pending_since {
            _ if self.pending.is_empty() || self.paste.is_some() => None,
            Some(t) if start == 0 && before > 0 => Some(t),
            _ => Some(now),
        };
        if !self.hold {
            self.flush_pending(out);
        }
    }

    /// When what is open (a paste, an unfinished sequence) is closed if
    /// nothing comes: the caller waits for input until then and calls
    /// [`Self::expire`]. `None`: nothing waits.
    pub fn deadline(&self) -> Option<Instant> {
        match (self.paste_seen, self.pending_since) {
            (Some(seen), _) if self.paste.is_some() => Some(seen + PASTE_WAIT),
            (_, Some(since)) => Some(since + SEQUENCE_WAIT),
            _ => None,
        }
    }

    /// Closes what has been open too long by `now`: a paste (its text so
    /// far is the paste), an unfinished sequence (dropped: its bytes may
    /// be the start of a reply, never keys), a lone `ESC` (the Escape key).
    pub fn expire(&mut self, now: Instant, out: &mut Vec<Input>) {
        if self.deadline().is_none_or(|d| now < d) {
            return;
        }
        if let Some(mut paste) = self.paste.take() {
            append_capped(&mut paste, &self.pending);
            self.pending.clear();
            self.paste_seen = None;
            if !paste.is_empty() {
                out.push(Input::Event(Event::Paste(
                    String::from_utf8_lossy(&paste).into_owned(),
                )));
            }
        } else if self.waiting() {
            self.flush_pending(out);
        } else {
            self.pending.clear();
        }
        self.pending_since = None;
    }

    /// Decodes what is pending; returns how many bytes were used.
    fn decode(&mut self, out: &mut Vec<Input>) -> usize {
        let mut start = 0;
        loop {
            if let Some(paste) = &mut self.paste {
                let rest = &self.pending[start..];
                if let Some(at) = rest.iter().position(|&c| c == CTRL_C) {
                    // Typed, not pasted: the paste is abandoned for the key.
                    if find(&rest[..at], PASTE_END).is_none() {
                        self.paste = None;
                        self.paste_seen = None;
                        start += at;
                        continue;
                    }
                }
                if let Some(end) = find(rest, PASTE_END) {
                    append_capped(paste, &rest[..end]);
                    let text = String::from_utf8_lossy(paste).into_owned();
                    self.paste = None;
                    self.paste_seen = None;
                    out.push(Input::Event(Event::Paste(text)));
                    start += end + PASTE_END.len();
                    continue;
                }
                // Keep a tail that could be the start of the end marker.
                let keep = rest.len().min(PASTE_END.len() - 1);
                let take = rest.len() - keep;
                append_capped(paste, &rest[..take]);
                start += take;
                break;
            }
            if start >= self.pending.len() {
                break;
            }
            match self.step(start) {
                Step::Done(n, event) => {
                    start += n;
                    if let Some(e) = event {
                        out.push(e);
                    }
                }
                Step::Incomplete => break,
            }
        }
        start
    }

    fn step(&mut self, start: usize) -> Step {
        let b = &self.pending[start..];
        match b[0] {
            0x1b => self.escape(start),
            b'\r' | b'\n' => Step::Done(1, Some(key(KeyCode::Enter, KeyModifiers::NONE))),
            b'\t' => Step::Done(1, Some(key(KeyCode::Tab, KeyModifiers::NONE))),
            0x7f | 0x08 => Step::Done(1, Some(key(KeyCode::Backspace, KeyModifiers::NONE))),
            c @ 0x01..=0x1a => Step::Done(
                1,
                Some(key(
                    KeyCode::Char((b'a' + c - 1) as char),
                    KeyModifiers::CONTROL,
                )),
            ),
            c if c < 0x20 => Step::Done(1, None),
            _ => match utf8_char(b) {
                Some((ch, n)) => {
                    let mods = if ch.is_uppercase() {
                        KeyModifiers::SHIFT
                    } else {
                        KeyModifiers::NONE
                    };
                    Step::Done(n, Some(key(KeyCode::Char(ch), mods)))
                }
                None if b.len() < utf8_len(b[0]) => Step::Incomplete,
                None => Step::Done(1, None),
            },
        }
    }

    fn escape(&mut self, start: usize) -> Step {
        let b = &self.pending[start..];
        if b.len() < 2 {
            return Step::Incomplete;
        }
        match b[1] {
            b'[' => self.csi(start),
            c if is_string_introducer(c) => match string_end(&b[2..]) {
                StringEnd::Found(n) => Step::Done(2 + n, None),
                StringEnd::NotYet => Step::Incomplete,
                StringEnd::NotAString => self.alt_key(start),
            },
            b'O' => {
                if b.len() < 3 {
                    return Step::Incomplete;
                }
                if b[2] < 0x20 {
                    // Alt+O, then a control key.
                    return self.alt_key(start);
                }
                let code = match b[2] {
                    b'A' => Some(KeyCode::Up),
                    b'B' => Some(KeyCode::Down),
                    b'C' => Some(KeyCode::Right),
                    b'D' => Some(KeyCode::Left),
                    b'H' => Some(KeyCode::Home),
                    b'F' => Some(KeyCode::End),
                    _ => None,
                };
                Step::Done(3, code.map(|c| key(c, KeyModifiers::NONE)))
            }
            0x1b => Step::Done(1, Some(key(KeyCode::Esc, KeyModifiers::NONE))),
            _ => self.alt_key(start),
        }
    }

    /// ESC + key: Alt held.
    fn alt_key(&mut self, start: usize) -> Step {
        match self.step(start + 1) {
            Step::Done(n, Some(Input::Event(Event::Key(mut k)))) => {
                k.modifiers |= KeyModifiers::ALT;
                Step::Done(n + 1, Some(Input::Event(Event::Key(k))))
            }
            Step::Done(n, other) => Step::Done(n + 1, other),
            Step::Incomplete => Step::Incomplete,
        }
    }

    fn csi(&mut self, start: usize) -> Step {
        let b = &self.pending[start..];
        // A control byte, `ESC` or a byte past ASCII cannot be inside a
        // sequence: what came before it is dropped, the byte is read anew.
        let Some(end) = b[2..]
            .iter()
            .position(|&c| (0x40..=0x7e).contains(&c) || !(0x20..0x7f).contains(&c))
        else {
            return if b.len() > CSI_LIMIT {
                Step::Done(b.len(), None)
            } else {
                Step::Incomplete
            };
        };
        let final_byte = b[2 + end];
        if !(0x40..=0x7e).contains(&final_byte) {
            return Step::Done(2 + end, None);
        }
        let params = &b[2..2 + end];
        let len = 3 + end;
        if params.first() == Some(&b'?') && final_byte == b'c' {
            return Step::Done(len, Some(Input::DeviceAttributes));
        }
        let event = match (params.first(), final_byte) {
            (Some(b'<'), b'M' | b'm') => sgr_mouse(&params[1..], final_byte == b'M'),
            (_, b'~') if params == b"200" => {
                self.paste = Some(Vec::new());
                self.paste_seen = None;
                None
            }
            (_, b'~') => {
                let code = match numbers(params).first().copied().unwrap_or(0) {
                    1 | 7 => Some(KeyCode::Home),
                    2 => Some(KeyCode::Insert),
                    3 => Some(KeyCode::Delete),
                    4 | 8 => Some(KeyCode::End),
                    5 => Some(KeyCode::PageUp),
                    6 => Some(KeyCode::PageDown),
                    _ => None,
                };
                code.map(|c| key_event(c, modifiers(params)))
            }
            (_, b'A') => Some(key_event(KeyCode::Up, modifiers(params))),
            (_, b'B') => Some(key_event(KeyCode::Down, modifiers(params))),
            (_, b'C') => Some(key_event(KeyCode::Right, modifiers(params))),
            (_, b'D') => Some(key_event(KeyCode::Left, modifiers(params))),
            (_, b'H') => Some(key_event(KeyCode::Home, modifiers(params))),
            (_, b'F') => Some(key_event(KeyCode::End, modifiers(params))),
            (_, b'Z') => Some(key_event(KeyCode::BackTab, KeyModifiers::SHIFT)),
            _ => None,
        };
        Step::Done(len, event.map(Input::Event))
    }
}

/// `ESC` + this byte starts a string: DCS, OSC, APC, PM or SOS.
fn is_string_introducer(c: u8) -> bool {
    matches!(c, b'P' | b']' | b'_' | b'^' | b'X')
}

enum StringEnd {
    /// The string and its terminator take this many bytes.
    Found(usize),
    NotYet,
    /// A control byte, a stray `ESC` or too many bytes: typed keys, not a reply.
    NotAString,
}

/// Where the body of a string sequence ends (after `ESC \` or BEL).
fn string_end(body: &[u8]) -> StringEnd {
    for (i, &c) in body.iter().enumerate() {
        match c {
            0x07 => return StringEnd::Found(i + 1),
            0x1b => {
                return match body.get(i + 1) {
                    Some(b'\\') => StringEnd::Found(i + 2),
                    Some(_) => StringEnd::NotAString,
                    None => StringEnd::NotYet,
                };
            }
            c if c < 0x20 || i >= STRING_LIMIT => return StringEnd::NotAString,
            _ => {}
        }
    }
    if body.len() >= STRING_LIMIT {
        StringEnd::NotAString
    } else {
        StringEnd::NotYet
    }
}

/// Semicolon-separated decimal parameters (missing ones are 0).
fn numbers(params: &[u8]) -> Vec<u32> {
    params
        .split(|&c| c == b';')
        .map(|p| {
            p.iter().filter(|c| c.is_ascii_digit()).fold(0u32, |n, &c| {
                n.saturating_mul(10).saturating_add((c - b'0') as u32)
            })
        })
        .collect()
}

/// Modifier parameter of a cursor key (`ESC [ 1 ; m A`): m − 1 is a bit set.
fn modifiers(params: &[u8]) -> KeyModifiers {
    let n = numbers(params);
    let m = n.get(1).copied().unwrap_or(1).saturating_sub(1);
    let mut mods = KeyModifiers::NONE;
    if m & 1 != 0 {
        mods |= KeyModifiers::SHIFT;
    }
    if m & 2 != 0 {
        mods |= KeyModifiers::ALT;
    }
    if m & 4 != 0 {
        mods |= KeyModifiers::CONTROL;
    }
    mods
}

/// An SGR mouse report: `b;x;y`, pressed (`M`) or released (`m`).
fn sgr_mouse(params: &[u8], pressed: bool) -> Option<Event> {
    let n = numbers(params);
    let [code, x, y] = n[..] else { return None };
    let button = match code & 3 {
        0 => MouseButton::Left,
        1 => MouseButton::Middle,
        _ => MouseButton::Right,
    };
    let kind = if code & 64 != 0 {
        match code & 3 {
            0 => MouseEventKind::ScrollUp,
            1 => MouseEventKind::ScrollDown,
            2 => MouseEventKind::ScrollLeft,
            _ => MouseEventKind::ScrollRight,
        }
    } else if code & 32 != 0 {
        if code & 3 == 3 {
            MouseEventKind::Moved
        } else {
            MouseEventKind::Drag(button)
        }
    } else if pressed {
        MouseEventKind::Down(button)
    } else {
        MouseEventKind::Up(button)
    };
    let mut modifiers = KeyModifiers::NONE;
    if code & 4 != 0 {
        modifiers |= KeyModifiers::SHIFT;
    }
    if code & 8 != 0 {
        modifiers |= KeyModifiers::ALT;
    }
    if code & 16 != 0 {
        modifiers |= KeyModifiers::CONTROL;
    }
    let clamp = |v: u32| v.saturating_sub(1).min(u16::MAX as u32) as u16;
    Some(Event::Mouse(MouseEvent {
        kind,
        column: clamp(x),
        row: clamp(y),
        modifiers,
    }))
}

/// The first UTF-8 character of `b` and its length, if complete and valid.
fn utf8_char(b: &[u8]) -> Option<(char, usize)> {
    let n = utf8_len(b[0]);
    let s = std::str::from_utf8(b.get(..n)?).ok()?;
    s.chars().next().map(|c| (c, n))
}

/// Length of the UTF-8 sequence a lead byte starts (1 for stray bytes).
fn utf8_len(lead: u8) -> usize {
    match lead {
        0xc0..=0xdf => 2,
        0xe0..=0xef => 3,
        0xf0..=0xf7 => 4,
        _ => 1,
    }
}

fn find(haystack: &[u8], needle: &[u8]) -> Option<usize> {
    haystack.windows(needle.len()).position(|w| w == needle)
}

fn append_capped(buf: &mut Vec<u8>, data: &[u8]) {
    let room = PASTE_LIMIT.saturating_sub(buf.len());
    buf.extend_from_slice(&data[..data.len().min(room)]);
}
