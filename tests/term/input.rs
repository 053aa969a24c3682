//! Terminal bytes → events.

use crossterm::event::{
    Event, KeyCode, KeyEvent, KeyModifiers, MouseButton, MouseEvent, MouseEventKind,
};
use std::time::{Duration, Instant};

use relief_term::input::{Input, InputParser, PASTE_WAIT, SEQUENCE_WAIT};

/// Everything decoded from `chunks`, read one after the other.
fn decode(chunks: &[&[u8]]) -> Vec<Input> {
    let mut p = InputParser::new();
    let mut out = Vec::new();
    for c in chunks {
        p.feed(c, &mut out);
    }
    out
}

/// The input events only (replies to queries are not input).
fn parse(chunks: &[&[u8]]) -> Vec<Event> {
    decode(chunks)
        .into_iter()
        .filter_map(|i| match i {
            Input::Event(e) => Some(e),
            Input::DeviceAttributes => None,
        })
        .collect()
}

fn key(code: KeyCode) -> Event {
    Event::Key(KeyEvent::new(code, KeyModifiers::NONE))
}

fn mouse(kind: MouseEventKind, column: u16, row: u16) -> Event {
    Event::Mouse(MouseEvent {
        kind,
        column,
        row,
        modifiers: KeyModifiers::NONE,
    })
}

#[test]
fn letters_controls_and_cursor_keys() {
    assert_eq!(
        parse(&[b"mq\t\r\x7f \x1b[A\x1b[B\x1bOC\x1b[D\x1b[Z\x1b[5~\x1b[6~"]),
        vec![
            key(KeyCode::Char('m')),
            key(KeyCode::Char('q')),
            key(KeyCode::Tab),
            key(KeyCode::Enter),
            key(KeyCode::Backspace),
            key(KeyCode::Char(' ')),
            key(KeyCode::Up),
            key(KeyCode::Down),
            key(KeyCode::Right),
            key(KeyCode::Left),
            Event::Key(KeyEvent::new(KeyCode::BackTab, KeyModifiers::SHIFT)),
            key(KeyCode::PageUp),
            key(KeyCode::PageDown),
        ]
    );
    assert_eq!(
        parse(&[b"\x03"]),
        vec![Event::Key(KeyEvent::new(
            KeyCode::Char('c'),
            KeyModifiers::CONTROL
        ))]
    );
    assert_eq!(
        parse(&[b"R"]),
        vec![Event::Key(KeyEvent::new(
            KeyCode::Char('R'),
            KeyModifiers::SHIFT
        ))]
    );
}

#[test]
fn a_lone_escape_is_the_escape_key_and_split_sequences_wait() {
    assert_eq!(parse(&[b"\x1b"]), vec![key(KeyCode::Esc)]);
    assert_eq!(parse(&[b"\x1b[", b"A"]), vec![key(KeyCode::Up)]);
    assert_eq!(parse(&[b"\x1b[<0;1", b"0;5M"]).len(), 1);
    // Multi-byte UTF-8 split across reads.
    assert_eq!(
        parse(&[&"é".as_bytes()[..1], &"é".as_bytes()[1..]]),
        vec![key(KeyCode::Char('é'))]
    );
}

#[test]
fn device_attributes_replies_are_their_own_message_even_split_and_among_keys() {
    let up = Input::Event(key(KeyCode::Up));
    let m = Input::Event(key(KeyCode::Char('m')));
    let da = Input::DeviceAttributes;
    // xterm, tmux and the Linux console answers, mixed with keys.
    assert_eq!(
        decode(&[b"m\x1b[?64;1;2;6;22c\x1b[A\x1b[?1;2cm\x1b[?6c"]),
        vec![
            m.clone(),
            da.clone(),
            up.clone(),
            da.clone(),
            m.clone(),
            da.clone()
        ]
    );
    // Split across reads anywhere after the escape.
    for cut in 2..b"\x1b[?62;22c".len() {
        let reply = b"\x1b[?62;22c";
        let (a, b) = reply.split_at(cut);
        let mut second = b.to_vec();
        second.extend_from_slice(b"\x1b[A");
        assert_eq!(
            decode(&[b"m", a, &second]),
            vec![m.clone(), da.clone(), up.clone()],
            "cut at {cut}"
        );
    }
    // A reply never reaches the keys: no `?` (help), no digits, no Esc.
    assert!(parse(&[b"\x1b[?62;4c", b"\x1b[?1;2c"]).is_empty());
    // Modified F3 (`ESC [ 1 ; 2 R`) is not mistaken for a reply, nor a reply for it.
    assert!(!decode(&[b"\x1b[1;2R"]).contains(&da));
}

#[test]
fn sgr_mouse_press_drag_release() {
    assert_eq!(
        parse(&[b"\x1b[<0;10;5M\x1b[<32;12;6M\x1b[<0;12;6m\x1b[<2;3;4M\x1b[<34;4;4M\x1b[<2;4;4m"]),
        vec![
            mouse(MouseEventKind::Down(MouseButton::Left), 9, 4),
            mouse(MouseEventKind::Drag(MouseButton::Left), 11, 5),
            mouse(MouseEventKind::Up(MouseButton::Left), 11, 5),
            mouse(MouseEventKind::Down(MouseButton::Right), 2, 3),
            mouse(MouseEventKind::Drag(MouseButton::Right), 3, 3),
            mouse(MouseEventKind::Up(MouseButton::Right), 3, 3),
        ]
    );
    // Wheel and garbage coordinates do not panic.
    assert_eq!(
        parse(&[b"\x1b[<64;1;1M"]),
        vec![mouse(MouseEventKind::ScrollUp, 0, 0)]
    );
    assert_eq!(parse(&[b"\x1b[<0;0;99999999999M"]).len(), 1);
    assert_eq!(parse(&[b"\x1b[<0;1M"]), vec![]);
}

#[test]
fn bracketed_paste_arrives_whole_even_across_reads() {
    assert_eq!(
        parse(&[b"\x1b[200~/tmp/a b", b".png\x1b[2", b"01~q"]),
        vec![Event::Paste("/tmp/a b.png".into()), key(KeyCode::Char('q'))]
    );
    // Escape sequences inside a paste are text, not keys.
    assert_eq!(
        parse(&[b"\x1b[200~\x1b[31mred\x1b[201~"]),
        vec![Event::Paste("\x1b[31mred".into())]
    );
}

#[test]
fn garbage_is_dropped_without_panicking() {
    let mut noise = Vec::new();
    let mut s = 12345u32;
    for _ in 0..10_000 {
        s ^= s << 13;
        s ^= s >> 17;
        s ^= s << 5;
        noise.push(s as u8);
    }
    let mut p = InputParser::new();
    let mut out = Vec::new();
    for chunk in noise.chunks(7) {
        p.feed(chunk, &mut out);
    }
    // An overlong unterminated CSI is discarded, and parsing goes on.
    let mut long = b"\x1b[".to_vec();
    long.extend(std::iter::repeat_n(b'1', 100));
    assert_eq!(
        parse(&[&long, b"\x1b[Aq"]).last(),
        Some(&key(KeyCode::Char('q')))
    );
}

#[test]
fn string_replies_are_swallowed_whole_however_they_are_split() {
    // A late XTGETTCAP and DECRQSS answer (ST), an OSC colour answer (BEL),
    // and an APC, between typed keys.
    let all: &[u8] = b"m\x1bP1+r5463\x1b\\\x1bP1$r0;48:2::1:2:3m\x1b\\n\x1b]11;rgb:1010/1818/2020\x07\x1b_Gi=1;OK\x1b\\q";
    let want = vec![
        key(KeyCode::Char('m')),
        key(KeyCode::Char('n')),
        key(KeyCode::Char('q')),
    ];
    assert_eq!(parse(&[all]), want);
    for cut in 1..all.len() {
        let (a, b) = all.split_at(cut);
        let mut p = InputParser::holding_escape();
        let mut out = Vec::new();
        p.feed(a, &mut out);
        p.feed(b, &mut out);
        let events: Vec<Event> = out
            .into_iter()
            .filter_map(|i| match i {
                Input::Event(e) => Some(e),
                Input::DeviceAttributes => None,
            })
            .collect();
        assert_eq!(events, want, "cut at {cut}");
    }
}

#[test]
fn alt_keys_that_look_like_string_starts_stay_keys() {
    let alt = |c: char| {
        Event::Key(KeyEvent::new(
            KeyCode::Char(c),
            KeyModifiers::ALT | KeyModifiers::SHIFT,
        ))
    };
    // Alone in a read: Alt+P.
    assert_eq!(parse(&[b"\x1bP"]), vec![alt('P')]);
    // Followed by Enter (a control byte no reply carries): Alt+P, Enter.
    assert_eq!(
        parse(&[b"\x1bP\rq"]),
        vec![alt('P'), key(KeyCode::Enter), key(KeyCode::Char('q'))]
    );
    // Never terminated: given up after the limit, the bytes are input again.
    let mut long = b"\x1b]".to_vec();
    long.extend(std::iter::repeat_n(b'a', 2000));
    let events = parse(&[&long]);
    assert_eq!(events.len(), 2001);
    assert_eq!(
        events[0],
        Event::Key(KeyEvent::new(KeyCode::Char(']'), KeyModifiers::ALT))
    );
    assert!(events[1..].iter().all(|e| *e == key(KeyCode::Char('a'))));
}

#[test]
fn a_held_escape_waits_for_the_rest_of_its_sequence() {
    let mut p = InputParser::holding_escape();
    let mut out = Vec::new();
    // A device-attributes reply split after its ESC: no Escape key.
    p.feed(b"\x1b", &mut out);
    assert!(out.is_empty() && p.waiting());
    p.feed(b"[?62;22c", &mut out);
    assert_eq!(out, vec![Input::DeviceAttributes]);
    assert!(!p.waiting());
    // Nothing follows: the caller flushes it as the Escape key.
    out.clear();
    p.feed(b"\x1b", &mut out);
    assert!(out.is_empty());
    p.flush_pending(&mut out);
    assert_eq!(out, vec![Input::Event(key(KeyCode::Esc))]);
    // A decoder that does not hold decides at the end of the read.
    assert_eq!(parse(&[b"\x1b"]), vec![key(KeyCode::Esc)]);
}

/// What a decoder makes of `chunks`, each read `ms` after the start, then
/// of nothing more for a long time (the reader's time-out): the input
/// events only.
fn timed(hold: bool, chunks: &[(u64, &[u8])]) -> Vec<Event> {
    let t0 = Instant::now();
    let mut p = if hold {
        InputParser::holding_escape()
    } else {
        InputParser::new()
    };
    let mut out = Vec::new();
    for &(ms, bytes) in chunks {
        p.feed_at(bytes, t0 + Duration::from_millis(ms), &mut out);
    }
    p.expire(t0 + Duration::from_secs(3600), &mut out);
    assert_eq!(p.deadline(), None, "nothing is left open");
    events(out)
}

fn events(out: Vec<Input>) -> Vec<Event> {
    out.into_iter()
        .filter_map(|i| match i {
            Input::Event(e) => Some(e),
            Input::DeviceAttributes => None,
        })
        .collect()
}

fn ctrl_c() -> Event {
    Event::Key(KeyEvent::new(KeyCode::Char('c'), KeyModifiers::CONTROL))
}

#[test]
fn a_paste_without_its_end_is_closed_once_its_bytes_stop() {
    let q = key(KeyCode::Char('q'));
    // Nothing pasted: nothing to apply, and the next key is a key.
    assert_eq!(
        timed(true, &[(0, b"\x1b[200~"), (1500, b"q")]),
        vec![q.clone()]
    );
    // What came is the paste.
    assert_eq!(
        timed(false, &[(0, b"\x1b[200~/tmp/a.png"), (1000, b"q")]),
        vec![Event::Paste("/tmp/a.png".into()), q.clone()]
    );
    // Closed by the time-out alone, with no key after it.
    assert_eq!(
        timed(false, &[(0, b"\x1b[200~/tmp/a.p"), (10, b"ng\x1b[20")]),
        vec![Event::Paste("/tmp/a.png\x1b[20".into())]
    );
    // Its end marker, when it comes late, is no key.
    assert_eq!(
        timed(false, &[(0, b"\x1b[200~x"), (2000, b"q\x1b[201~m")]),
        vec![Event::Paste("x".into()), q.clone(), key(KeyCode::Char('m'))]
    );
}

#[test]
fn a_paste_that_keeps_coming_is_not_cut() {
    let wait = PASTE_WAIT.as_millis() as u64;
    assert_eq!(
        timed(
            false,
            &[
                (0, b"\x1b[200~abc"),
                (wait - 1, b"def"),
                (2 * wait - 2, b"ghi\x1b[2"),
                (3 * wait - 3, b"01~q"),
            ]
        ),
        vec![Event::Paste("abcdefghi".into()), key(KeyCode::Char('q'))]
    );
}

#[test]
fn the_deadline_is_the_last_paste_bytes_time_plus_the_wait() {
    let t0 = Instant::now();
    let mut p = InputParser::new();
    let mut out = Vec::new();
    assert_eq!(p.deadline(), None);
    p.feed_at(b"\x1b[200~ab", t0, &mut out);
    assert_eq!(p.deadline(), Some(t0 + PASTE_WAIT));
    let later = t0 + Duration::from_millis(400);
    p.feed_at(b"c", later, &mut out);
    assert_eq!(p.deadline(), Some(later + PASTE_WAIT));
    p.expire(later + PASTE_WAIT - Duration::from_millis(1), &mut out);
    assert!(out.is_empty(), "{out:?}");
    p.expire(later + PASTE_WAIT, &mut out);
    assert_eq!(events(out), vec![Event::Paste("abc".into())]);
    assert_eq!(p.deadline(), None);
}

#[test]
fn ctrl_c_always_quits_even_inside_a_paste_or_a_sequence() {
    let q = key(KeyCode::Char('q'));
    // In an open paste (terminals filter control bytes out of pastes).
    assert_eq!(parse(&[b"\x1b[200~/tmp/a", b"\x03"]), vec![ctrl_c()]);
    // In a partial CSI, an SS3 or a string.
    assert_eq!(parse(&[b"\x1b[12;", b"\x03q"]), vec![ctrl_c(), q.clone()]);
    let mut huge = b"\x1b[".to_vec();
    huge.extend(std::iter::repeat_n(b'9', 60));
    assert_eq!(parse(&[&huge, b"\x03"]), vec![ctrl_c()]);
    assert_eq!(
        parse(&[b"\x1bO\x03"]),
        vec![
            Event::Key(KeyEvent::new(
                KeyCode::Char('O'),
                KeyModifiers::ALT | KeyModifiers::SHIFT
            )),
            ctrl_c()
        ]
    );
    assert_eq!(parse(&[b"\x1b_Gi=1", b"\x03"]).last(), Some(&ctrl_c()));
    // An ESC inside a CSI starts the next sequence.
    assert_eq!(parse(&[b"\x1b[12\x1b[A"]), vec![key(KeyCode::Up)]);
}

#[test]
fn an_unfinished_sequence_is_dropped_after_its_wait() {
    let q = key(KeyCode::Char('q'));
    let late = SEQUENCE_WAIT.as_millis() as u64 + 1;
    // An APC start, a partial CSI, a huge partial CSI, a partial SS3.
    let mut huge = b"\x1b[".to_vec();
    huge.extend(std::iter::repeat_n(b'1', 60));
    for start in [&b"\x1b_Gi=31;"[..], b"\x1b[12;", &huge, b"\x1bP1+r"] {
        for hold in [false, true] {
            assert_eq!(
                timed(hold, &[(0, start), (late, b"q")]),
                vec![q.clone()],
                "{start:?}"
            );
        }
    }
    // An APC introducer alone: Alt+_ as ever, then the key.
    let alt = Event::Key(KeyEvent::new(KeyCode::Char('_'), KeyModifiers::ALT));
    for hold in [false, true] {
        assert_eq!(
            timed(hold, &[(0, b"\x1b_"), (late, b"q")]),
            vec![alt.clone(), q.clone()]
        );
    }
    // A reply split over reads within the wait is still swallowed whole.
    assert_eq!(
        timed(true, &[(0, b"\x1b_Gi=1;"), (late - 2, b"OK\x1b\\q")]),
        vec![q.clone()]
    );
    assert_eq!(
        timed(true, &[(0, b"\x1b[<0;1"), (late - 2, b"0;5M")]).len(),
        1
    );
}

#[test]
fn the_terminal_reader_closes_an_open_paste_with_no_more_input() {
    use relief::app::event_loop::{Msg, spawn_terminal_reader};
    use std::io::Write;
    use std::os::fd::AsRawFd;
    let (mut tty, reader) = std::os::unix::net::UnixStream::pair().unwrap();
    let (tx, rx) = std::sync::mpsc::channel();
    let fd = reader.as_raw_fd();
    spawn_terminal_reader(reader, fd, tx);
    tty.write_all(b"\x1b[200~/tmp/a.png").unwrap();
    // Nothing more is written: the reader's own time-out ends the paste.
    let got = rx.recv_timeout(Duration::from_secs(30)).unwrap();
    assert!(
        matches!(&got, Msg::Input(Event::Paste(p)) if p == "/tmp/a.png"),
        "{got:?}"
    );
    tty.write_all(b"q").unwrap();
    let got = rx.recv_timeout(Duration::from_secs(30)).unwrap();
    assert!(
        matches!(&got, Msg::Input(e) if *e == key(KeyCode::Char('q'))),
        "{got:?}"
    );
}
