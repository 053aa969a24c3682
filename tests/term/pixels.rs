//! Pixel frames in the interactive view: what the loop writes in kitty and
//! sixel, decoded back; placement, tmux passthrough, deletion, fallbacks.

use std::collections::VecDeque;
use std::io::Read;
use std::sync::mpsc;

use base64::Engine;
use crossterm::event::{Event, KeyCode, KeyEvent, KeyModifiers};
use ratatui::Terminal;
use ratatui::layout::Rect;
use relief::Framebuffer;
use relief::app::State;
use relief::app::event_loop::{Exit, Looper, Msg};
use relief::settings::Settings;
use relief::term::format::{Clues, Format, TmuxPixels};
use relief::term::pixel_view::{self, Output, PixelView};
use relief::term::{ColorDepth, SgrBackend, kitty};

use super::encoder::decode_sixel;

/// The tests that show a kitty image take turns: the clean-up the
/// terminal guard reads is one for the process.
static IMAGE_SHOWN: std::sync::Mutex<()> = std::sync::Mutex::new(());

fn key(c: char) -> Msg {
    Msg::Input(Event::Key(KeyEvent::new(
        KeyCode::Char(c),
        KeyModifiers::NONE,
    )))
}

/// The colour the test scene draws at (x, y) of a w × h frame.
fn pattern(x: usize, y: usize, w: usize, h: usize) -> [u8; 3] {
    [
        (x * 255 / w.max(1)) as u8,
        (y * 255 / h.max(1)) as u8,
        ((x / 7 + y / 5) % 2 * 200) as u8,
    ]
}

/// A terminal that, after each write (a frame leaves in one), sends the
/// loop its next message: one message per frame, then end of input.
struct Feeder {
    out: Vec<u8>,
    tx: mpsc::Sender<Msg>,
    next: VecDeque<Msg>,
}

impl std::io::Write for Feeder {
    fn write(&mut self, data: &[u8]) -> std::io::Result<usize> {
        self.out.extend_from_slice(data);
        let msg = self
            .next
            .pop_front()
            .unwrap_or_else(|| Msg::InputClosed("end of input".into()));
        let _ = self.tx.send(msg);
        Ok(data.len())
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

/// Runs the loop on a 60×14 screen with `output`, `msgs` one after each
/// frame (then end of input); returns the bytes written, the sizes
/// rendered and the state.
fn run(output: Output, msgs: Vec<Msg>) -> (Vec<u8>, Vec<(usize, usize)>, State) {
    let (tx, rx) = mpsc::channel();
    let feeder = Feeder {
        out: Vec::new(),
        tx,
        next: msgs.into(),
    };
    let mut term = Terminal::new(SgrBackend::with_size(feeder, 60, 14)).unwrap();
    let mut state = State::new(Settings::default(), ColorDepth::Truecolor);
    state.output = output;
    let mut sizes = Vec::new();
    let exit = Looper {
        terminal: &mut term,
        render: |_: &State, fb: &mut Framebuffer| {
            let (w, h) = (fb.width(), fb.height());
            sizes.push((w, h));
            for y in 0..h {
                for x in 0..w {
                    fb.set(x, y, pattern(x, y, w, h));
                }
            }
            relief::FrameStats::default()
        },
        background: [0, 0, 0],
        rx: &rx,
        textures: None,
        stage: None,
        pacer: relief::term::pacing::Pacer::by_writes(),
    }
    .run(&mut state)
    .unwrap();
    assert!(matches!(exit, Exit::InputClosed(_)));
    (term.backend().writer().out.clone(), sizes, state)
}

fn output(format: Format) -> Output {
    Output::from_clues(
        &Clues {
            forced: Some((format, "--format")),
            ..Clues::default()
        },
        None,
    )
}

fn count(hay: &[u8], needle: &[u8]) -> usize {
    hay.windows(needle.len()).filter(|w| *w == needle).count()
}

fn find(hay: &[u8], needle: &[u8]) -> Option<usize> {
    hay.windows(needle.len()).position(|w| w == needle)
}

/// The kitty images in `bytes`: each one's keys (of its first chunk) and
/// its decoded RGB bytes.
fn kitty_images(bytes: &[u8]) -> Vec<(String, Vec<u8>)> {
    let text = String::from_utf8_lossy(bytes);
    let mut images = Vec::new();
    let mut current: Option<(String, String)> = None;
    for command in text.split("\x1b_G").skip(1) {
        let body = &command[..command.find("\x1b\\").expect("ends with ST")];
        let (keys, data) = body.split_once(';').unwrap_or((body, ""));
        if keys.contains("a=d") {
            continue;
        }
        let entry = current.get_or_insert_with(|| (keys.to_string(), String::new()));
        entry.1.push_str(data);
        if keys.split(',').any(|k| k == "m=0") {
            let (keys, payload) = current.take().unwrap();
            let packed = base64::engine::general_purpose::STANDARD
                .decode(payload)
                .unwrap();
            let mut raw = Vec::new();
            flate2::read::ZlibDecoder::new(&packed[..])
                .read_to_end(&mut raw)
                .unwrap();
            images.push((keys, raw));
        }
    }
    images
}

fn key_value(keys: &str, name: &str) -> usize {
    keys.split(',')
        .find_map(|k| k.strip_prefix(&format!("{name}=")))
        .unwrap()
        .parse()
        .unwrap()
}

/// The kitty frame decodes to the rendered picture, is placed at the
/// picture's top-left over its 60×12 cells, is sent once (the status
/// refresh after it does not resend it), a panel over the picture deletes
/// it and closing the panel sends it again; the guard's clean-up then
/// deletes it; switching to sixel deletes it at once and draws a sixel
/// image that decodes to the picture.
#[test]
fn the_view_sends_kitty_frames_that_decode_to_the_picture_and_deletes_them() {
    let _turn = IMAGE_SHOWN.lock().unwrap_or_else(|e| e.into_inner());
    let _ = pixel_view::take_cleanup();
    let (bytes, sizes, state) = run(output(Format::Kitty), vec![]);
    assert_eq!(state.output.format(), Format::Kitty);
    let (w, h) = sizes[0];
    // The picture's cells (60 × 12) at the cell size in pixels.
    assert_eq!((w % 60, h % 12), (0, 0), "{w}×{h}");
    let images = kitty_images(&bytes);
    assert_eq!(images.len(), 1, "one image for one picture");
    let (keys, raw) = &images[0];
    assert_eq!((key_value(keys, "s"), key_value(keys, "v")), (w, h));
    assert_eq!((key_value(keys, "c"), key_value(keys, "r")), (60, 12));
    assert_eq!(key_value(keys, "i"), kitty::IMAGE_ID as usize);
    let want: Vec<u8> = (0..h)
        .flat_map(|y| (0..w).flat_map(move |x| pattern(x, y, w, h)))
        .collect();
    assert!(raw == &want, "the payload is the frame");
    // Placed at the top-left cell right before the image.
    let at = find(&bytes, b"\x1b_G").unwrap();
    assert!(bytes[..at].ends_with(b"\x1b[1;1H"));
    // The picture's cells are not written as text: no half blocks.
    assert_eq!(
        count(&bytes, "▀".as_bytes()) + count(&bytes, "▄".as_bytes()),
        0
    );
    assert_eq!(count(&bytes, kitty::DELETE), 0);
    assert_eq!(pixel_view::take_cleanup(), kitty::DELETE, "deleted on exit");
    assert!(pixel_view::take_cleanup().is_empty(), "once");

    // The cost panel (44 columns) over the picture: text, the image
    // deleted; closed: sent again.
    let (bytes, _, _) = run(output(Format::Kitty), vec![key('k'), key('k')]);
    let del = find(&bytes, kitty::DELETE).expect("deleted under the panel");
    let images: Vec<usize> = bytes
        .windows(6)
        .enumerate()
        .filter(|(_, w)| *w == b"\x1b_Ga=T")
        .map(|(i, _)| i)
        .collect();
    assert!(images.iter().any(|&i| i > del), "{images:?} {del}");
    assert!(count(&bytes, "▀".as_bytes()) + count(&bytes, "▄".as_bytes()) > 0);
    let _ = pixel_view::take_cleanup();

    // U: kitty → sixels; the kitty image goes, a sixel image comes.
    let (bytes, sizes, state) = run(output(Format::Kitty), vec![key('U')]);
    assert_eq!(state.output.format(), Format::Sixels);
    let del = find(&bytes, kitty::DELETE).expect("kitty image deleted");
    let six = find(&bytes, b"\x1bP0;1;0q").expect("a sixel image");
    assert!(del < six);
    // The whole screen is drawn again for the new format.
    let clear = find(&bytes[del..], b"\x1b[2J").expect("the screen cleared") + del;
    assert!(clear < six);
    assert!(bytes[..six].ends_with(b"\x1b[1;1H"));
    let (w, h) = *sizes.last().unwrap();
    let (sw, sh, pixels) = decode_sixel(&bytes[six..]);
    assert_eq!((sw, sh), (w, h));
    for y in 0..h {
        for x in 0..w {
            let p = pixels[y * w + x].expect("every pixel drawn");
            let q = pattern(x, y, w, h);
            for c in 0..3 {
                // The 6×7×6 cube: within half a step (25.5, 21.25, 25.5).
                assert!(p[c].abs_diff(q[c]) <= 26, "{x},{y}: {p:?} vs {q:?}");
            }
        }
    }
    // Sixel leaves nothing to delete: the restore clears the screen.
    assert!(pixel_view::take_cleanup().is_empty());
}

#[test]
fn symbols_write_no_image() {
    let (bytes, sizes, _) = run(output(Format::Symbols), vec![]);
    assert_eq!(
        sizes[0],
        (60, 24),
        "half blocks: 60 × 12 cells, 2 pixels each"
    );
    assert_eq!(count(&bytes, b"\x1b_G") + count(&bytes, b"\x1bP0;1;0q"), 0);
}

#[test]
fn inside_tmux_without_passthrough_the_view_falls_back_to_symbols_and_says_how() {
    let clues = Clues {
        kitty_reply: false,
        tmux: Some(TmuxPixels {
            termname: "xterm-kitty".into(),
            features: "256,RGB".into(),
            passthrough: false,
        }),
        ..Clues::default()
    };
    let out = Output::from_clues(&clues, None);
    assert_eq!((out.wanted, out.format()), (Format::Kitty, Format::Symbols));
    let note = out.choice.note.clone().unwrap();
    assert!(note.contains("allow-passthrough on"), "{note}");
    let (bytes, _, state) = run(out, vec![]);
    assert_eq!(count(&bytes, b"\x1b_G") + count(&bytes, b"\x1bPtmux;"), 0);
    assert_eq!(state.output.format(), Format::Symbols);
    // The key cycles what is wanted; each pixel format falls back and says so.
    let mut s = state;
    relief::app::update(&mut s, relief::app::Action::CycleFormat);
    assert_eq!(
        (s.output.wanted, s.output.format()),
        (Format::Sixels, Format::Symbols)
    );
    assert!(
        s.message
            .unwrap()
            .starts_with("sixels images need tmux passthrough")
    );
}

/// Undoes [`pixel_view::wrap_tmux`]: the sequences inside each passthrough.
fn unwrap_tmux(bytes: &[u8]) -> (Vec<u8>, Vec<u8>) {
    let (mut inner, mut outside) = (Vec::new(), Vec::new());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i..].starts_with(b"\x1bPtmux;") {
            i += 7;
            loop {
                match (bytes[i], bytes.get(i + 1)) {
                    (0x1b, Some(0x1b)) => {
                        inner.push(0x1b);
                        i += 2;
                    }
                    (0x1b, Some(b'\\')) => {
                        i += 2;
                        break;
                    }
                    (0x1b, _) => panic!("a lone ESC inside the passthrough at {i}"),
                    (b, _) => {
                        inner.push(b);
                        i += 1;
                    }
                }
            }
        } else {
            outside.push(bytes[i]);
            i += 1;
        }
    }
    (inner, outside)
}

#[test]
fn tmux_passthrough_wraps_every_sequence_and_unwraps_to_the_same_bytes() {
    let mut fb = Framebuffer::new(90, 70);
    for y in 0..70 {
        for x in 0..90 {
            fb.set(x, y, pattern(x, y, 90, 70));
        }
    }
    let area = Rect::new(3, 2, 30, 10);
    for format in [Format::Kitty, Format::Sixels, Format::Iterm] {
        let plain = pixel_view::image_bytes(&fb, format, area, false, false).unwrap();
        let wrapped = pixel_view::image_bytes(&fb, format, area, false, true).unwrap();
        let (inner, outside) = unwrap_tmux(&wrapped);
        // The cursor move stays outside (tmux moves its pane's cursor).
        assert_eq!(outside, b"\x1b[3;4H", "{format:?}");
        assert!(plain.starts_with(b"\x1b[3;4H"));
        assert_eq!(inner, plain[6..], "{format:?}");
        if format == Format::Kitty {
            // One passthrough per chunk, each within tmux's limits.
            let n = count(&wrapped, b"\x1bPtmux;");
            assert_eq!(n, count(&plain, b"\x1b_G"));
            assert!(n > 1);
        }
    }
    let mut out = Vec::new();
    pixel_view::wrap_tmux(kitty::DELETE, &mut out);
    assert_eq!(out, pixel_view::kitty_delete(true));
    assert_eq!(unwrap_tmux(&out).0, kitty::DELETE);
}

#[test]
fn an_image_never_reaches_the_last_row() {
    // The picture ends two rows above the bottom: usable.
    assert!(PixelView::usable(
        Format::Sixels,
        Rect::new(0, 0, 40, 10),
        12
    ));
    // A 2-row screen: the picture's row is next to the last, still clear of it.
    assert!(PixelView::usable(Format::Kitty, Rect::new(0, 0, 40, 1), 2));
    // A 1-row screen: the picture is the last row: text.
    assert!(!PixelView::usable(
        Format::Sixels,
        Rect::new(0, 0, 40, 1),
        1
    ));
    assert!(!PixelView::usable(
        Format::Symbols,
        Rect::new(0, 0, 40, 10),
        12
    ));
    // On a 1-row screen the loop writes text even with sixels wanted.
    let (tx, rx) = mpsc::channel();
    tx.send(Msg::InputClosed("end".into())).unwrap();
    let mut term = Terminal::new(SgrBackend::with_size(Vec::new(), 20, 1)).unwrap();
    let mut state = State::new(Settings::default(), ColorDepth::Truecolor);
    state.output = output(Format::Sixels);
    Looper {
        terminal: &mut term,
        render: |_: &State, fb: &mut Framebuffer| {
            fb.fill([200, 10, 10]);
            relief::FrameStats::default()
        },
        background: [0, 0, 0],
        rx: &rx,
        textures: None,
        stage: None,
        pacer: relief::term::pacing::Pacer::by_writes(),
    }
    .run(&mut state)
    .unwrap();
    assert_eq!(count(term.backend().writer(), b"\x1bP0;1;0q"), 0);
}

/// A terminal over a slow link: it answers each query (`CSI c`) as a link
/// of [`LINK_RATE`] bytes a second would (the reply's time stamp is when
/// the frame would have arrived), sends an arrow key after each write
/// while `keys` last, and ends the input once the exact picture (a kitty
/// image as wide as the first) has come after them.
struct SlowLink {
    out: Vec<u8>,
    tx: mpsc::Sender<Msg>,
    keys: usize,
    full_width: Option<usize>,
}

const LINK_RATE: f64 = 20_000.0;

impl std::io::Write for SlowLink {
    fn write(&mut self, data: &[u8]) -> std::io::Result<usize> {
        self.out.extend_from_slice(data);
        let now = std::time::Instant::now();
        let base = std::time::Duration::from_millis(10);
        let queries = count(data, b"\x1b[c");
        for i in 0..queries {
            // A probe before the frame comes back after the latency alone.
            let transfer = if i + 1 < queries {
                0.0
            } else {
                data.len() as f64 / LINK_RATE
            };
            let at = now + base + std::time::Duration::from_secs_f64(transfer);
            let _ = self.tx.send(Msg::Shown(at));
        }
        let images = kitty_images(data);
        if let Some((keys, _)) = images.first() {
            self.full_width.get_or_insert(key_value(keys, "s"));
        }
        if self.keys > 0 {
            self.keys -= 1;
            let _ = self.tx.send(Msg::Input(Event::Key(KeyEvent::new(
                KeyCode::Right,
                KeyModifiers::NONE,
            ))));
        } else if images
            .iter()
            .any(|(keys, _)| Some(key_value(keys, "s")) == self.full_width)
        {
            let _ = self.tx.send(Msg::InputClosed("end of input".into()));
        }
        Ok(data.len())
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

/// While keys keep coming over a link too slow for the exact kitty frame
/// at 15 frames a second, smaller images are sent (the terminal scales
/// them over the same cells); once the keys stop the exact frame comes.
#[test]
fn pixel_previews_shrink_over_a_slow_link_and_the_exact_frame_follows() {
    let _turn = IMAGE_SHOWN.lock().unwrap_or_else(|e| e.into_inner());
    let _ = pixel_view::take_cleanup();
    let (tx, rx) = mpsc::channel();
    let link = SlowLink {
        out: Vec::new(),
        tx,
        keys: 8,
        full_width: None,
    };
    let mut term = Terminal::new(SgrBackend::with_size(link, 60, 14)).unwrap();
    let mut state = State::new(Settings::default(), ColorDepth::Truecolor);
    state.output = output(Format::Kitty);
    let exit = Looper {
        terminal: &mut term,
        // A picture that changes everywhere with the rotation.
        render: |s: &State, fb: &mut Framebuffer| {
            let turn = s.settings.rotation.y as usize;
            for y in 0..fb.height() {
                for x in 0..fb.width() {
                    let v = (x * 7 + y * 13 + turn * 31) % 251;
                    fb.set(x, y, [v as u8, (v * 3 % 256) as u8, (255 - v) as u8]);
                }
            }
            relief::FrameStats::default()
        },
        background: [0, 0, 0],
        rx: &rx,
        textures: None,
        stage: None,
        pacer: relief::term::pacing::Pacer::default(),
    }
    .run(&mut state)
    .unwrap();
    assert!(matches!(exit, Exit::InputClosed(_)));
    let images = kitty_images(&term.backend().writer().out);
    let widths: Vec<usize> = images.iter().map(|(k, _)| key_value(k, "s")).collect();
    let full = widths[0];
    assert!(
        widths.iter().any(|&w| w < full),
        "a smaller preview while the keys came: {widths:?}"
    );
    for (keys, raw) in &images {
        // Every image covers the picture's cells, whatever its pixels.
        assert_eq!((key_value(keys, "c"), key_value(keys, "r")), (60, 12));
        assert_eq!(raw.len(), key_value(keys, "s") * key_value(keys, "v") * 3);
    }
    assert_eq!(
        *widths.last().unwrap(),
        full,
        "the exact frame last: {widths:?}"
    );
    let _ = pixel_view::take_cleanup();
}
