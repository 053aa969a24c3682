//! Pixel frames in the interactive view: what the loop writes in kitty and
//! sixel, decoded back; placement, tmux passthrough, deletion, fallbacks.

use std::collections::VecDeque;
use std::io::Read;
use std::sync::mpsc;

use base64::Engine;
use crossterm::event::{Event, KeyCode, KeyEvent, KeyModifiers};
use ratatui::Terminal;
use ratatui::layout::Rect;
use relief::app::State;
use relief::app::event_loop::{Exit, Looper, Msg};
use relief_core::framebuffer::Framebuffer;
use relief_core::settings::Settings;
use relief_term::format::{Clues, Format, TmuxPixels};
use relief_term::pixel_view::{self, Output, PixelView};
use relief_term::{ColorDepth, SgrBackend, kitty, sixel};

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
    let exit = Looper::new(&mut term, &rx, |_: &State, fb: &mut Framebuffer| {
        let (w, h) = (fb.width(), fb.height());
        sizes.push((w, h));
        for y in 0..h {
            for x in 0..w {
                fb.set(x, y, pattern(x, y, w, h));
            }
        }
        relief_core::stats::FrameStats::default()
    })
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
/// its decoded RGB bytes (deletes and placements, which carry none, are
/// left out).
fn kitty_images(bytes: &[u8]) -> Vec<(String, Vec<u8>)> {
    let text = String::from_utf8_lossy(bytes);
    let mut images = Vec::new();
    let mut current: Option<(String, String)> = None;
    for command in text.split("\x1b_G").skip(1) {
        let body = &command[..command.find("\x1b\\").expect("ends with ST")];
        let (keys, data) = body.split_once(';').unwrap_or((body, ""));
        if keys.contains("a=d") || keys.split(',').any(|k| k == "a=p") {
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
/// refresh after it does not resend it); the guard's clean-up then
/// deletes it; switching to sixel deletes it at once and draws a sixel
/// image that decodes to the picture. (Panels over it: below.)
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
    Looper::new(&mut term, &rx, |_: &State, fb: &mut Framebuffer| {
        fb.fill([200, 10, 10]);
        relief_core::stats::FrameStats::default()
    })
    .run(&mut state)
    .unwrap();
    assert_eq!(count(term.backend().writer(), b"\x1bP0;1;0q"), 0);
}

/// A terminal over a slow link: it answers each query (`CSI c`) as a link
/// of `rate` bytes a second would (the reply's time stamp is when the
/// frame would have arrived), sends an arrow key after each write while
/// `keys` last, and ends the input once the exact picture has come after
/// them: a kitty image of the `full` frame's size, or strips of it (kitty
/// images of their own) over all its pixel rows. Each write is kept.
struct SlowLink {
    out: Vec<u8>,
    writes: Vec<Vec<u8>>,
    tx: mpsc::Sender<Msg>,
    rate: f64,
    keys: usize,
    full: (usize, usize),
    strip_rows: usize,
}

/// The frame's pixels on the 60 × 14 screen of the loop tests in kitty:
/// its 60 × 12-cell picture area.
fn loop_frame() -> (usize, usize) {
    let screen = Rect::new(0, 0, 60, 14);
    let area = relief::app::view::areas(screen).viewport;
    assert_eq!((area.width, area.height), (60, 12));
    PixelView::framebuffer_size(&output(Format::Kitty), area, 14, relief_term::Symbols::Half)
}

impl SlowLink {
    fn new(tx: mpsc::Sender<Msg>, rate: f64, keys: usize) -> Self {
        SlowLink {
            out: Vec::new(),
            writes: Vec::new(),
            tx,
            rate,
            keys,
            full: loop_frame(),
            strip_rows: 0,
        }
    }
}

impl std::io::Write for SlowLink {
    fn write(&mut self, data: &[u8]) -> std::io::Result<usize> {
        self.out.extend_from_slice(data);
        self.writes.push(data.to_vec());
        let now = std::time::Instant::now();
        let base = std::time::Duration::from_millis(10);
        let queries = count(data, b"\x1b[c");
        for i in 0..queries {
            // A probe before the frame comes back after the latency alone.
            let transfer = if i + 1 < queries {
                0.0
            } else {
                data.len() as f64 / self.rate
            };
            let at = now + base + std::time::Duration::from_secs_f64(transfer);
            let _ = self.tx.send(Msg::Shown(at));
        }
        let images = kitty_images(data);
        if self.keys > 0 {
            self.keys -= 1;
            let _ = self.tx.send(Msg::Input(Event::Key(KeyEvent::new(
                KeyCode::Right,
                KeyModifiers::NONE,
            ))));
        } else {
            let full = self.full;
            for (keys, _) in &images {
                let size = (key_value(keys, "s"), key_value(keys, "v"));
                if key_value(keys, "i") == kitty::IMAGE_ID as usize {
                    self.strip_rows = if size == full { full.1 } else { 0 };
                } else {
                    self.strip_rows += size.1;
                }
            }
            if self.strip_rows >= full.1 {
                let _ = self.tx.send(Msg::InputClosed("end of input".into()));
            }
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
    let term = run_slow_link(SlowLink::new(tx, 20_000.0, 8), rx, |s, fb| {
        // A picture that changes everywhere with the rotation.
        let turn = s.settings.rotation.y as usize;
        for y in 0..fb.height() {
            for x in 0..fb.width() {
                let v = (x * 7 + y * 13 + turn * 31) % 251;
                fb.set(x, y, [v as u8, (v * 3 % 256) as u8, (255 - v) as u8]);
            }
        }
    });
    let all = kitty_images(&term.backend().writer().out);
    // The pictures (relief's image), then the strips of the last one.
    let split = all
        .iter()
        .rposition(|(k, _)| key_value(k, "i") == kitty::IMAGE_ID as usize)
        .unwrap();
    let (images, strips) = all.split_at(split + 1);
    let widths: Vec<usize> = images.iter().map(|(k, _)| key_value(k, "s")).collect();
    let full = loop_frame().0;
    assert!(
        widths.iter().any(|&w| w < full),
        "a smaller preview while the keys came: {widths:?}"
    );
    for (keys, raw) in images {
        // Every image covers the picture's cells, whatever its pixels.
        assert_eq!((key_value(keys, "c"), key_value(keys, "r")), (60, 12));
        assert_eq!(raw.len(), key_value(keys, "s") * key_value(keys, "v") * 3);
    }
    // The exact frame last: whole, or in strips at full width over all
    // its pixel rows.
    let full_height = loop_frame().1;
    let rows: usize = strips.iter().map(|(k, _)| key_value(k, "v")).sum();
    assert!(
        *widths.last().unwrap() == full || rows == full_height,
        "the exact frame last: {widths:?}, strips over {rows} pixel rows"
    );
    for (keys, _) in strips {
        assert_eq!(key_value(keys, "s"), full);
    }
    let _ = pixel_view::take_cleanup();
}

/// Runs the loop in kitty over `link` (a 60 × 14 screen), the pacer
/// measuring the link by its replies, `render` drawing each picture, to
/// the end of input.
fn run_slow_link(
    link: SlowLink,
    rx: mpsc::Receiver<Msg>,
    mut render: impl FnMut(&State, &mut Framebuffer),
) -> Terminal<SgrBackend<SlowLink>> {
    let mut term = Terminal::new(SgrBackend::with_size(link, 60, 14)).unwrap();
    let mut state = State::new(Settings::default(), ColorDepth::Truecolor);
    state.output = output(Format::Kitty);
    let exit = Looper {
        pacer: relief_term::pacing::Pacer::default(),
        ..Looper::new(&mut term, &rx, |s: &State, fb: &mut Framebuffer| {
            render(s, fb);
            relief_core::stats::FrameStats::default()
        })
    }
    .run(&mut state)
    .unwrap();
    assert!(matches!(exit, Exit::InputClosed(_)));
    term
}

/// Noise (a hash of the pixel and the rotation): the exact kitty image of
/// the loop's 480 × 192 frame is about 370 kB, far more than a slow link
/// carries in [`pixel_view::LINK_SECONDS`].
fn noise(s: &State, fb: &mut Framebuffer) {
    let turn = s.settings.rotation.y.to_bits() as usize;
    for y in 0..fb.height() {
        for x in 0..fb.width() {
            let h = ((x * 73_856_093) ^ (y * 19_349_663) ^ (turn * 83_492_791))
                .wrapping_mul(2_654_435_761);
            fb.set(x, y, [(h >> 8) as u8, (h >> 16) as u8, (h >> 24) as u8]);
        }
    }
}

/// The bytes of the kitty sequences (`ESC _ G … ESC \`) in `bytes`.
fn kitty_bytes(bytes: &[u8]) -> usize {
    let mut total = 0;
    let mut i = 0;
    while let Some(at) = find(&bytes[i..], b"\x1b_G") {
        let start = i + at;
        let end = find(&bytes[start..], b"\x1b\\").map_or(bytes.len(), |e| start + e + 2);
        total += end - start;
        i = end;
    }
    total
}

/// Right after start no reply has measured the link yet: a large exact
/// frame still goes as over a slow link, the picture sized for
/// [`pixel_view::UNMEASURED_RATE`] first. So the first write, after which
/// input is taken, is bounded (whole, this one was 370 kB: ten seconds at
/// 1 Mbit/s with the key waiting behind it), and a key right after it gets
/// its own picture next, the first frame's strips dropped. Over a fast
/// link the strips are cut again once its reply has measured it: the rest
/// of the exact frame follows in one.
#[test]
fn before_the_link_is_measured_the_first_frame_is_link_sized_and_input_preempts_it() {
    let _turn = IMAGE_SHOWN.lock().unwrap_or_else(|e| e.into_inner());
    let _ = pixel_view::take_cleanup();
    let budget = pixel_view::UNMEASURED_RATE * pixel_view::LINK_SECONDS;

    // 20 kB/s, a key after the first write.
    let (tx, rx) = mpsc::channel();
    let term = run_slow_link(SlowLink::new(tx, 20_000.0, 1), rx, noise);
    let writes = &term.backend().writer().writes;
    // The first frame's write ends with its query: input is taken then.
    let n = 1 + writes
        .iter()
        .position(|w| find(w, b"\x1b[c").is_some())
        .unwrap();
    let (before, after) = writes.split_at(n);
    let before = before.concat();
    let first = kitty_bytes(&before);
    assert!(
        first > 0 && first as f64 <= budget,
        "the first write's image takes {first} bytes, more than {budget}"
    );
    let images = kitty_images(&before);
    assert_eq!(images.len(), 1, "one picture first");
    let (keys, _) = &images[0];
    assert_eq!(key_value(keys, "i"), kitty::IMAGE_ID as usize);
    let full = loop_frame();
    assert!(key_value(keys, "s") < full.0, "{keys}: scaled down");
    // The key's picture is the next image: no strip of the first went.
    let next = after
        .iter()
        .flat_map(|w| kitty_images(w))
        .next()
        .expect("the key's picture");
    assert_eq!(
        key_value(&next.0, "i"),
        kitty::IMAGE_ID as usize,
        "{}",
        next.0
    );
    let turned = kitty_images(&term.backend().writer().out);
    assert!(turned.len() > 2, "the key's picture, then its strips");
    let _ = pixel_view::take_cleanup();

    // A fast link, no key: the link-sized picture, then one strip.
    let (tx, rx) = mpsc::channel();
    let term = run_slow_link(SlowLink::new(tx, 1e9, 0), rx, noise);
    let images = kitty_images(&term.backend().writer().out);
    assert_eq!(images.len(), 2, "a picture and one strip");
    let (keys, _) = &images[0];
    assert_eq!(key_value(keys, "i"), kitty::IMAGE_ID as usize);
    assert!(key_value(keys, "s") < full.0, "{keys}: scaled down");
    let (keys, raw) = &images[1];
    assert_ne!(key_value(keys, "i"), kitty::IMAGE_ID as usize, "a strip");
    assert_eq!((key_value(keys, "s"), key_value(keys, "v")), full);
    let mut fb = Framebuffer::new(full.0, full.1);
    noise(
        &State::new(Settings::default(), ColorDepth::Truecolor),
        &mut fb,
    );
    assert!(raw == &fb.pixels().concat(), "the strip is the exact frame");
    let _ = pixel_view::take_cleanup();
}

/// A placement of a kitty image: the cells it covers, the image's pixels
/// it shows there, the image and its z-index.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Placement {
    cells: Rect,
    source: [usize; 4],
    image: usize,
    z: i64,
}

/// A kitty image the terminal holds: width, height, RGB bytes.
type KittyImage = (usize, usize, Vec<u8>);

/// What a terminal shows of the loop's output, replayed: the cursor, which
/// cells last got text, the sixel pixels (last writer wins per cell: text
/// written into a cell hides its pixels, pixels drawn hide its text), and
/// kitty's images and their placements (drawn over the text, the highest
/// z-index on top).
struct Replay {
    cols: usize,
    rows: usize,
    cell: (usize, usize),
    x: usize,
    y: usize,
    /// The cell shows text (not sixel pixels).
    text: Vec<bool>,
    /// Sixel pixels of the whole screen.
    canvas: Vec<Option<[u8; 3]>>,
    /// kitty's images by id.
    images: std::collections::BTreeMap<usize, KittyImage>,
    /// kitty's placements by image and placement id.
    placements: std::collections::BTreeMap<(usize, usize), Placement>,
    /// Images sent (kitty data, sixel or iTerm2 images), in pixels.
    sent_pixels: usize,
    /// A kitty transmission spread over chunks: its keys and payload.
    chunks: Option<(String, String)>,
    /// The largest sixel image drawn (xterm's `maxGraphicSize`): a larger
    /// one is dropped whole.
    sixel_max: Option<(usize, usize)>,
    /// Sixel images dropped for their size.
    dropped: usize,
}

impl Replay {
    fn new(cols: usize, rows: usize, cell: (usize, usize)) -> Self {
        Replay {
            cols,
            rows,
            cell,
            x: 0,
            y: 0,
            text: vec![true; cols * rows],
            canvas: vec![None; cols * rows * cell.0 * cell.1],
            images: Default::default(),
            placements: Default::default(),
            sent_pixels: 0,
            chunks: None,
            sixel_max: None,
            dropped: 0,
        }
    }

    /// relief's kitty image (not a strip).
    fn image(&self) -> Option<&KittyImage> {
        self.images.get(&(kitty::IMAGE_ID as usize))
    }

    /// The end of the sequence starting at `i` (after its `ESC \` or BEL).
    fn string_end(bytes: &[u8], i: usize) -> usize {
        let mut j = i + 2;
        while j < bytes.len() {
            if bytes[j] == 0x07 {
                return j + 1;
            }
            if bytes[j] == 0x1b && bytes.get(j + 1) == Some(&b'\\') {
                return j + 2;
            }
            j += 1;
        }
        panic!("unterminated string sequence at {i}");
    }

    fn feed(&mut self, bytes: &[u8]) {
        let mut i = 0;
        while i < bytes.len() {
            match bytes[i] {
                0x1b => match bytes[i + 1] {
                    b'[' => {
                        let mut j = i + 2;
                        while !(0x40..=0x7e).contains(&bytes[j]) {
                            j += 1;
                        }
                        let params = std::str::from_utf8(&bytes[i + 2..j]).unwrap();
                        let p: Vec<usize> =
                            params.split(';').map(|n| n.parse().unwrap_or(0)).collect();
                        match bytes[j] {
                            b'H' => {
                                self.y = p[0].max(1) - 1;
                                self.x = p.get(1).copied().unwrap_or(1).max(1) - 1;
                            }
                            b'C' => self.x += p[0].max(1),
                            b'J' if params == "2" => {
                                self.text.fill(true);
                                self.canvas.fill(None);
                            }
                            _ => {}
                        }
                        i = j + 1;
                    }
                    b'_' => {
                        let end = Self::string_end(bytes, i);
                        self.kitty(std::str::from_utf8(&bytes[i + 3..end - 2]).unwrap());
                        i = end;
                    }
                    b'P' => {
                        let end = Self::string_end(bytes, i);
                        let (w, h, pixels) = decode_sixel(&bytes[i..end]);
                        if self.sixel_max.is_some_and(|(mw, mh)| w > mw || h > mh) {
                            self.dropped += 1;
                            i = end;
                            continue;
                        }
                        self.sent_pixels += w * h;
                        let (x0, y0) = (self.x * self.cell.0, self.y * self.cell.1);
                        let width = self.cols * self.cell.0;
                        for y in 0..h {
                            for x in 0..w {
                                if let Some(p) = pixels[y * w + x] {
                                    self.canvas[(y0 + y) * width + x0 + x] = Some(p);
                                    let c =
                                        (y0 + y) / self.cell.1 * self.cols + (x0 + x) / self.cell.0;
                                    self.text[c] = false;
                                }
                            }
                        }
                        i = end;
                    }
                    b']' => {
                        let end = Self::string_end(bytes, i);
                        self.sent_pixels += 1;
                        i = end;
                    }
                    other => panic!("unexpected ESC {}", other as char),
                },
                b'\r' => {
                    self.x = 0;
                    i += 1;
                }
                b'\n' => {
                    self.y += 1;
                    i += 1;
                }
                b => {
                    // One character: the cell gets text.
                    let len = match b {
                        0..=0x7f => 1,
                        0xc0..=0xdf => 2,
                        0xe0..=0xef => 3,
                        _ => 4,
                    };
                    assert!(
                        self.x < self.cols && self.y < self.rows,
                        "text off the screen"
                    );
                    self.text[self.y * self.cols + self.x] = true;
                    self.x += 1;
                    i += len;
                }
            }
        }
    }

    /// One kitty command (between `ESC _G` and `ESC \`).
    fn kitty(&mut self, body: &str) {
        let (keys, data) = body.split_once(';').unwrap_or((body, ""));
        let value = |name: &str| -> Option<String> {
            keys.split(',')
                .find_map(|k| k.strip_prefix(&format!("{name}=")))
                .map(str::to_string)
        };
        let number = |name: &str| value(name).map_or(0, |v| v.parse::<usize>().unwrap());
        if let Some((first, payload)) = self.chunks.as_mut() {
            payload.push_str(data);
            if number("m") == 0 {
                let (first, payload) = (first.clone(), payload.clone());
                self.chunks = None;
                self.transmitted(&first, &payload);
            }
            return;
        }
        match value("a").as_deref() {
            Some("T") | Some("t") => {
                if number("m") == 1 {
                    self.chunks = Some((keys.to_string(), data.to_string()));
                } else {
                    self.transmitted(keys, data);
                }
            }
            Some("p") => {
                let z = value("z").map_or(0, |v| v.parse().unwrap());
                self.place(
                    (number("i"), number("p")),
                    [number("x"), number("y"), number("w"), number("h")],
                    (number("c"), number("r")),
                    z,
                );
            }
            Some("d") => {
                let id = number("i");
                assert!(id >= kitty::IMAGE_ID as usize, "relief's ids only");
                self.placements.retain(|k, _| k.0 != id);
                if value("d").as_deref() == Some("I") {
                    self.images.remove(&id);
                }
            }
            other => panic!("unexpected kitty action {other:?}"),
        }
    }

    /// A whole kitty transmission: the image replaces the last one and its
    /// placements (kitty's rule); `a=T` also places it.
    fn transmitted(&mut self, keys: &str, payload: &str) {
        let value = |name: &str| key_value(keys, name);
        let packed = base64::engine::general_purpose::STANDARD
            .decode(payload)
            .unwrap();
        let mut raw = Vec::new();
        flate2::read::ZlibDecoder::new(&packed[..])
            .read_to_end(&mut raw)
            .unwrap();
        let (w, h) = (value("s"), value("v"));
        assert_eq!(raw.len(), w * h * 3);
        self.sent_pixels += w * h;
        let id = value("i");
        self.images.insert(id, (w, h, raw));
        self.placements.retain(|k, _| k.0 != id);
        if keys.starts_with("a=T") {
            let z = if keys.contains(",z=") {
                value("z") as i64
            } else {
                0
            };
            self.place((id, value("p")), [0, 0, 0, 0], (value("c"), value("r")), z);
        }
    }

    fn place(&mut self, id: (usize, usize), source: [usize; 4], cells: (usize, usize), z: i64) {
        let (iw, ih, _) = self
            .images
            .get(&id.0)
            .expect("placing an image sent before");
        // kitty's defaults: no width or height is the rest of the image.
        let [x, y, w, h] = source;
        let w = if w == 0 { iw - x } else { w };
        let h = if h == 0 { ih - y } else { h };
        assert!(x + w <= *iw && y + h <= *ih, "source within the image");
        let cells = Rect::new(self.x as u16, self.y as u16, cells.0 as u16, cells.1 as u16);
        self.placements.insert(
            id,
            Placement {
                cells,
                source: [x, y, w, h],
                image: id.0,
                z,
            },
        );
    }

    /// What the kitty placements show at pixel (x, y) of the screen, when
    /// one covers it (each placement scaled from its source to its cells;
    /// the highest z-index on top).
    fn kitty_pixel(&self, x: usize, y: usize) -> Option<[u8; 3]> {
        let (cx, cy) = (x / self.cell.0, y / self.cell.1);
        let p = self
            .placements
            .values()
            .filter(|p| p.cells.contains((cx as u16, cy as u16).into()))
            .max_by_key(|p| p.z)?;
        let (iw, _, data) = &self.images[&p.image];
        let [sx, sy, sw, sh] = p.source;
        let (px, py) = (
            x - usize::from(p.cells.x) * self.cell.0,
            y - usize::from(p.cells.y) * self.cell.1,
        );
        let u = sx + px * sw / (usize::from(p.cells.width) * self.cell.0);
        let v = sy + py * sh / (usize::from(p.cells.height) * self.cell.1);
        let i = (v * iw + u) * 3;
        Some([data[i], data[i + 1], data[i + 2]])
    }

    /// The cells the kitty placements cover, each counted once per
    /// placement.
    fn placed_cells(&self) -> Vec<usize> {
        let mut n = vec![0; self.cols * self.rows];
        for p in self.placements.values() {
            for y in p.cells.top()..p.cells.bottom() {
                for x in p.cells.left()..p.cells.right() {
                    n[usize::from(y) * self.cols + usize::from(x)] += 1;
                }
            }
        }
        n
    }
}

/// The bytes of each frame (from one start of a synchronized update to the
/// next).
fn frames(bytes: &[u8]) -> Vec<&[u8]> {
    let mark = relief_term::backend::BEGIN_SYNC;
    let starts: Vec<usize> = bytes
        .windows(mark.len())
        .enumerate()
        .filter(|(_, w)| *w == mark)
        .map(|(i, _)| i)
        .collect();
    let mut out = vec![&bytes[..starts[0]]];
    for (k, &s) in starts.iter().enumerate() {
        out.push(&bytes[s..starts.get(k + 1).copied().unwrap_or(bytes.len())]);
    }
    out
}

/// A picture of few colours (sixel shows each exactly, up to its 1 %
/// steps) that changes with the rotation.
fn few_colours(s: &State, fb: &mut Framebuffer) {
    let turn = (s.settings.rotation.y.to_bits() % 7) as usize;
    for y in 0..fb.height() {
        for x in 0..fb.width() {
            fb.set(
                x,
                y,
                [
                    (x / 8 % 8 * 32) as u8,
                    (y / 16 % 8 * 32) as u8,
                    (turn * 36) as u8,
                ],
            );
        }
    }
}

/// Runs the loop on an 80×30 screen with `format`, `msgs` one after each
/// frame; returns the bytes and the last exact picture.
fn run_panels(format: Format, msgs: Vec<Msg>) -> (Vec<u8>, Framebuffer) {
    run_panels_with(output(format), msgs)
}

/// [`run_panels`] with `output`.
fn run_panels_with(output: Output, msgs: Vec<Msg>) -> (Vec<u8>, Framebuffer) {
    let (tx, rx) = mpsc::channel();
    let feeder = Feeder {
        out: Vec::new(),
        tx,
        next: msgs.into(),
    };
    let mut term = Terminal::new(SgrBackend::with_size(feeder, 80, 30)).unwrap();
    let mut state = State::new(Settings::default(), ColorDepth::Truecolor);
    state.output = output;
    let mut last = Framebuffer::new(0, 0);
    Looper::new(
        &mut term,
        &rx,
        // The exact picture, not a smaller preview.
        |s: &State, fb: &mut Framebuffer| {
            few_colours(s, fb);
            if fb.width() >= last.width() {
                last = fb.clone();
            }
            relief_core::stats::FrameStats::default()
        },
    )
    .run(&mut state)
    .unwrap();
    (term.backend().writer().out.clone(), last)
}

/// The cost panel's cells on an 80×30 screen: 44 × 18 at the top right of
/// the picture.
const COST_PANEL: Rect = Rect::new(36, 0, 44, 18);

/// The picture's area on the 80×30 screen of [`run_panels`]: 80 columns,
/// and the rows above the text lines (the status line takes two rows).
fn panels_picture(format: Format) -> Rect {
    let mut s = State::new(Settings::default(), ColorDepth::Truecolor);
    s.output = output(format);
    let area = relief::app::view::layout(&s, Rect::new(0, 0, 80, 30)).viewport;
    assert_eq!(area, Rect::new(0, 0, 80, 27));
    area
}

fn right() -> Msg {
    Msg::Input(Event::Key(KeyEvent::new(
        KeyCode::Right,
        KeyModifiers::NONE,
    )))
}

/// kitty under the cost panel: the image stays as placements of the image
/// already sent, tiling exactly the cells around the panel (each showing
/// its own pixels); opening and closing the panel sends no pixels; a new
/// picture under the panel is sent once and placed around it; closing
/// leaves one placement showing the whole picture.
#[test]
fn under_a_panel_kitty_shows_the_picture_around_it_without_sending_it_again() {
    let _turn = IMAGE_SHOWN.lock().unwrap_or_else(|e| e.into_inner());
    let _ = pixel_view::take_cleanup();
    let keys = vec![key('k'), key('k'), key('k'), right(), key('k')];
    let (bytes, last) = run_panels(Format::Kitty, keys);
    let (w, h) = (last.width(), last.height());
    let rows = panels_picture(Format::Kitty).height;
    let mut screen = Replay::new(80, 30, (w / 80, h / usize::from(rows)));
    // Per frame: pixels sent, and whether the panel was open.
    let mut seen = Vec::new();
    for frame in frames(&bytes) {
        let before = screen.sent_pixels;
        screen.feed(frame);
        if screen.image().is_none() {
            continue;
        }
        let panel = screen.placements.len() > 1;
        seen.push((screen.sent_pixels - before, panel));
        let placed = screen.placed_cells();
        for y in 0..rows {
            for x in 0..80u16 {
                let i = usize::from(y) * 80 + usize::from(x);
                let under = panel && COST_PANEL.contains((x, y).into());
                // Every picture cell once: under the panel text, else the image.
                assert_eq!(placed[i], usize::from(!under), "cell {x},{y}");
                assert!(!under || screen.text[i]);
            }
        }
        if panel {
            assert_eq!(screen.placements.len(), 2, "left of the panel and below it");
        }
        // Each placement shows its own cells' pixels: its source is its
        // cells' rectangle at the image's pixels per cell.
        let (iw, ih, _) = screen.image().unwrap();
        let (sx, sy) = (iw / 80, ih / usize::from(rows));
        for p in screen.placements.values() {
            let c = p.cells;
            assert_eq!(
                p.source,
                [
                    usize::from(c.x) * sx,
                    usize::from(c.y) * sy,
                    usize::from(c.width) * sx,
                    usize::from(c.height) * sy
                ]
            );
        }
    }
    // Opening or closing the panel sends no pixels.
    for pair in seen.windows(2) {
        if pair[0].1 != pair[1].1 {
            assert_eq!(pair[1].0, 0, "{seen:?}");
        }
    }
    let toggles = seen.windows(2).filter(|p| p[0].1 != p[1].1).count();
    assert_eq!(toggles, 4, "{seen:?}");
    // Pixels went only with new pictures: the first, then the turned one
    // (after its half-size preview) under the panel.
    let sent: Vec<(usize, bool)> = seen.iter().copied().filter(|s| s.0 > 0).collect();
    assert!(
        sent == [(w * h, false), (w * h, true)]
            || sent == [(w * h, false), (w * h / 4, true), (w * h, true)],
        "{seen:?}"
    );
    // After the last key the screen is the last picture, whole.
    assert_eq!(screen.placements.len(), 1);
    for y in 0..h {
        for x in 0..w {
            assert_eq!(screen.kitty_pixel(x, y), Some(last.get(x, y)), "{x},{y}");
        }
    }
    assert_eq!(pixel_view::take_cleanup(), kitty::DELETE, "deleted on exit");
}

/// Sixel under the cost panel: the panel's cells are text drawn over the
/// image, nothing else is sent; closing it sends the panel's rectangle of
/// the picture only; a new picture under the panel is sent around it; at
/// the end the screen is the whole last picture again, each pixel as the
/// terminal shows its colour.
#[test]
fn under_a_panel_sixel_sends_only_the_cells_the_panel_leaves() {
    let _turn = IMAGE_SHOWN.lock().unwrap_or_else(|e| e.into_inner());
    let keys = vec![key('k'), key('k'), key('k'), right(), key('k')];
    let (bytes, last) = run_panels(Format::Sixels, keys);
    let (w, h) = (last.width(), last.height());
    let rows = panels_picture(Format::Sixels).height;
    let cell = (w / 80, h / usize::from(rows));
    let panel_pixels =
        usize::from(COST_PANEL.width) * cell.0 * usize::from(COST_PANEL.height) * cell.1;
    let mut screen = Replay::new(80, 30, cell);
    let mut seen = Vec::new();
    let mut shown_once = false;
    for frame in frames(&bytes) {
        let before = screen.sent_pixels;
        screen.feed(frame);
        shown_once |= screen.sent_pixels > 0;
        if !shown_once {
            continue;
        }
        // The panel is open when any picture cell shows text: then exactly
        // the panel's cells do.
        let text: Vec<(u16, u16)> = (0..rows)
            .flat_map(|y| (0..80u16).map(move |x| (x, y)))
            .filter(|&(x, y)| screen.text[usize::from(y) * 80 + usize::from(x)])
            .collect();
        let panel = !text.is_empty();
        if panel {
            assert_eq!(
                text.len(),
                usize::from(COST_PANEL.width * COST_PANEL.height)
            );
            assert!(
                text.iter()
                    .all(|&(x, y)| COST_PANEL.contains((x, y).into()))
            );
        }
        seen.push((screen.sent_pixels - before, panel));
    }
    let picture = w * h;
    for pair in seen.windows(2) {
        match (pair[0].1, pair[1].1) {
            // Opened: text over the image, no pixels.
            (false, true) => assert_eq!(pair[1].0, 0, "{seen:?}"),
            // Closed: the panel's rectangle of the picture, nothing more.
            (true, false) => assert_eq!(pair[1].0, panel_pixels, "{seen:?}"),
            _ => {}
        }
    }
    let toggles = seen.windows(2).filter(|p| p[0].1 != p[1].1).count();
    assert_eq!(toggles, 4, "{seen:?}");
    let sent: Vec<(usize, bool)> = seen.iter().copied().filter(|s| s.0 > 0).collect();
    // The first picture whole; the turned one (its preview enlarged, then
    // exact) around the panel; twice the panel's rectangle when it closed.
    let around = (picture - panel_pixels, true);
    let closed = (panel_pixels, false);
    assert!(
        sent == [(picture, false), closed, around, closed]
            || sent == [(picture, false), closed, around, around, closed],
        "{seen:?}"
    );
    // The screen is the whole last picture.
    let width = 80 * cell.0;
    for y in 0..h {
        for x in 0..w {
            let want = relief_term::sixel::shown(relief_term::sixel::percent(last.get(x, y)));
            assert_eq!(screen.canvas[y * width + x], Some(want), "{x},{y}");
        }
    }
    assert!(
        (0..panels_picture(Format::Sixels).height)
            .all(|y| (0..80u16).all(|x| !screen.text[usize::from(y) * 80 + usize::from(x)]))
    );
}

/// A terminal that answered its largest sixel image (xterm: 1000×1000 by
/// default, and it drops a larger image without a trace): the picture is
/// the most whole cells whose image fits, centred in the picture area, the
/// rest of the area text; with the cost panel opened and closed over it
/// nothing is dropped and the screen ends as the whole picture. Without the
/// answer the same terminal drops the whole image (the blank screen in
/// xterm; only the smaller rectangles sent around the panel show).
#[test]
fn sixel_images_stay_within_the_largest_the_terminal_answered() {
    let _turn = IMAGE_SHOWN.lock().unwrap_or_else(|e| e.into_inner());
    // The cell size the loop uses here (the window's, or 8 × 16).
    let (cell, _) = pixel_view::cell_pixels(pixel_view::window_size(), None);
    let (cw, ch) = (usize::from(cell.0), usize::from(cell.1));
    assert!(ch >= 10, "a cell {cw}×{ch} too small for this test");
    // Room for 50 of the 80 columns and 20 of the picture's rows, and part
    // of a cell: the 50 × 20 cells centred in the picture area.
    let max = (50 * cw + cw / 2, 20 * ch + ch / 2);
    let picture = panels_picture(Format::Sixels);
    let (left, top) = ((picture.width - 50) / 2, (picture.height - 20) / 2);
    let area = Rect::new(left, top, 50, 20);
    let rows = usize::from(picture.height);
    let mut capped = output(Format::Sixels);
    capped.sixel_max = Some((max.0 as u32, max.1 as u32));
    let keys = || vec![key('k'), key('k'), right()];
    let (bytes, last) = run_panels_with(capped, keys());
    assert_eq!((last.width(), last.height()), (50 * cw, 20 * ch));
    let mut screen = Replay::new(80, 30, (cw, ch));
    screen.sixel_max = Some(max);
    for (row, image) in placed_images(&bytes) {
        let (w, h, _) = decode_sixel(&image);
        assert!(w <= max.0 && h <= max.1, "{w}×{h} over {max:?}");
        assert!(row >= usize::from(area.y), "row {row}");
    }
    screen.feed(&bytes);
    assert_eq!(screen.dropped, 0);
    assert!(screen.sent_pixels > 0);
    let width = 80 * cw;
    for y in 0..rows * ch {
        for x in 0..width {
            let cell = (x / cw, y / ch);
            let got = screen.canvas[y * width + x];
            if area.contains((cell.0 as u16, cell.1 as u16).into()) {
                let (px, py) = (x - usize::from(left) * cw, y - usize::from(top) * ch);
                let want = sixel::shown(sixel::percent(last.get(px, py)));
                assert_eq!(got, Some(want), "{x},{y}");
            } else {
                assert_eq!(got, None, "no image outside the area at {x},{y}");
                assert!(screen.text[cell.1 * 80 + cell.0]);
            }
        }
    }
    // The same terminal, not asked: every image dropped.
    let (bytes, _) = run_panels(Format::Sixels, keys());
    let mut screen = Replay::new(80, 30, (cw, ch));
    screen.sixel_max = Some(max);
    screen.feed(&bytes);
    assert!(screen.dropped > 0);
    let blank = (0..rows * ch)
        .flat_map(|y| (0..width).map(move |x| (x, y)))
        .filter(|&(x, y)| screen.canvas[y * width + x].is_none())
        .count();
    assert!(blank > 0, "the whole picture was never drawn");
}

/// The terminal resized while the cost panel is open, drawn by the view
/// and [`PixelView`] on the real backend: the new picture is sent at the
/// new size around the panel at its new place (kitty: placements tiling
/// the cells around it; sixel: pixels everywhere but the panel's text).
#[test]
fn a_resize_with_a_panel_open_sends_the_new_picture_around_the_panel() {
    let _turn = IMAGE_SHOWN.lock().unwrap_or_else(|e| e.into_inner());
    for format in [Format::Kitty, Format::Sixels] {
        let mut term = Terminal::new(SgrBackend::with_size(Vec::new(), 80, 30)).unwrap();
        let mut state = State::new(Settings::default(), ColorDepth::Truecolor);
        state.output = output(format);
        state.cost_panel = true;
        let mut view = PixelView::new();
        // 8 × 16 pixels a cell.
        let mut draw = |term: &mut Terminal<SgrBackend<Vec<u8>>>, cols: u16, rows: u16| {
            let area = relief::app::view::layout(&state, Rect::new(0, 0, cols, rows)).viewport;
            let mut fb =
                Framebuffer::new(usize::from(area.width) * 8, usize::from(area.height) * 16);
            let (w, h) = (fb.width(), fb.height());
            for y in 0..h {
                for x in 0..w {
                    fb.set(x, y, pattern(x, y, w, h));
                }
            }
            let frame = pixel_view::PixelFrame {
                output: &state.output,
                fb: &fb,
                preview: None,
                new_picture: true,
                look: pixel_view::TextLook {
                    symbols: state.symbols,
                    depth: state.depth,
                    dither: false,
                    pad: [0, 0, 0],
                },
                throughput: None,
                unmeasured: false,
            };
            term.backend_mut().begin_frame().unwrap();
            view.draw(term, frame, area, |f, pic| {
                relief::app::view(f, &state, pic, [0, 0, 0])
            })
            .unwrap();
            term.backend_mut().end_frame().unwrap();
            (area, fb)
        };
        draw(&mut term, 80, 30);
        let first = term.backend().writer().len();
        term.backend_mut().set_fixed_size(70, 26);
        let (area, fb) = draw(&mut term, 70, 26);
        // Three status rows at 70 columns.
        assert_eq!(area, Rect::new(0, 0, 70, 22));
        let panel = Rect::new(26, 0, 44, 18);
        let bytes = term.backend().writer().clone();
        let resized = &bytes[first..];
        assert!(
            find(resized, b"\x1b[2J").is_some(),
            "{format:?}: the screen cleared"
        );
        let mut screen = Replay::new(80, 30, (8, 16));
        screen.feed(&bytes);
        for y in 0..area.height {
            for x in 0..70u16 {
                let i = usize::from(y) * 80 + usize::from(x);
                let under = panel.contains((x, y).into());
                if format == Format::Kitty {
                    assert_eq!(screen.placed_cells()[i], usize::from(!under), "{x},{y}");
                    let px = (usize::from(x) * 8 + 3, usize::from(y) * 16 + 5);
                    let want = (!under).then(|| fb.get(px.0, px.1));
                    assert_eq!(screen.kitty_pixel(px.0, px.1), want, "{x},{y}");
                } else {
                    assert_eq!(screen.text[i], under, "{x},{y}");
                }
            }
        }
        if format == Format::Kitty {
            assert_eq!(screen.image().map(|i| (i.0, i.1)), Some((560, 22 * 16)));
        }
        let _ = pixel_view::take_cleanup();
    }
}

/// An iTerm2 image: the cell it is placed at, its width and height in
/// cells, its pixels.
type ItermImage = ((usize, usize), (usize, usize), image::RgbImage);

/// The iTerm2 images in `bytes` (each placed by the cursor move before it).
fn iterm_images(bytes: &[u8]) -> Vec<ItermImage> {
    let text = String::from_utf8_lossy(bytes);
    let mut out = Vec::new();
    let mut rest = &text[..];
    while let Some(at) = rest.find("\x1b]1337;File=") {
        let before = &rest[..at];
        let mv = &before[before.rfind("\x1b[").unwrap() + 2..before.len() - 1];
        let (row, col) = mv.split_once(';').unwrap_or((mv, "1"));
        let cell = (
            col.parse::<usize>().unwrap() - 1,
            row.parse::<usize>().unwrap() - 1,
        );
        let body = &rest[at..];
        let end = body.find('\x07').unwrap();
        let (keys, data) = body[..end].split_once(':').unwrap();
        let number = |name: &str| -> usize {
            keys.split(';')
                .find_map(|k| k.strip_prefix(&format!("{name}=")))
                .unwrap()
                .parse()
                .unwrap()
        };
        let png = base64::engine::general_purpose::STANDARD
            .decode(data)
            .unwrap();
        let img = relief_texture::picture::decode(&png).unwrap().to_rgb8();
        out.push((cell, (number("width"), number("height")), img));
        rest = &body[end..];
    }
    out
}

/// iTerm2 under the cost panel: opening it sends no image; closing it
/// sends one, of the panel's cells only, stretched over them, holding the
/// picture's pixels there.
#[test]
fn under_a_panel_iterm_sends_the_panels_cells_when_it_closes() {
    let _turn = IMAGE_SHOWN.lock().unwrap_or_else(|e| e.into_inner());
    let (bytes, last) = run_panels(Format::Iterm, vec![key('k'), key('k')]);
    let (w, h) = (last.width(), last.height());
    let rows = panels_picture(Format::Iterm).height;
    let (cw, ch) = (w / 80, h / usize::from(rows));
    let per_frame: Vec<_> = frames(&bytes).iter().map(|f| iterm_images(f)).collect();
    let sent: Vec<usize> = per_frame.iter().map(Vec::len).collect();
    // The whole picture, then (panel open) nothing, then the panel's part.
    let first = sent.iter().position(|&n| n > 0).unwrap();
    assert_eq!(per_frame[first][0].1, (80, usize::from(rows)));
    let next = first + 1 + sent[first + 1..].iter().position(|&n| n > 0).unwrap();
    assert!(next > first + 1, "the panel opened with no image: {sent:?}");
    assert_eq!(sent.iter().sum::<usize>(), 2, "{sent:?}");
    let (cell, cells, img) = &per_frame[next][0];
    assert_eq!(*cell, (36, 0));
    assert_eq!(*cells, (44, 18));
    assert_eq!(img.dimensions(), (44 * cw as u32, 18 * ch as u32));
    for (x, y, p) in img.enumerate_pixels() {
        assert_eq!(p.0, last.get(36 * cw + x as usize, y as usize), "{x},{y}");
    }
}

/// A picture of many colours, smooth like a rendered one (gradients and
/// a wave), `seed` moving the wave: its exact image is far larger than its
/// scaled-down one.
fn busy_frame(w: usize, h: usize, seed: usize) -> Framebuffer {
    let mut fb = Framebuffer::new(w, h);
    for y in 0..h {
        for x in 0..w {
            let wave = ((x + seed * 13) as f32 / 9.0).sin() * ((y as f32) / 7.0).cos();
            fb.set(
                x,
                y,
                [
                    (x * 255 / w) as u8,
                    (y * 255 / h) as u8,
                    (128.0 + 100.0 * wave) as u8,
                ],
            );
        }
    }
    fb
}

/// One frame for [`draw_pixels`].
#[derive(Clone, Copy, Default)]
struct Draw<'a> {
    preview: Option<&'a Framebuffer>,
    /// The link's bytes a second (none: unknown).
    throughput: Option<f64>,
    /// Cells of the picture cleared as a panel would be.
    panel: Option<Rect>,
    /// The same picture as the last frame's.
    same: bool,
    dither: bool,
}

/// The picture area of [`draw_pixels`]: 60 × 12 cells of a 60 × 14 screen.
const AREA: Rect = Rect::new(0, 0, 60, 12);

/// Draws `fb` into `view` as the loop does (inside one synchronized
/// frame) and returns the bytes written.
fn draw_pixels(
    view: &mut PixelView,
    term: &mut Terminal<SgrBackend<Vec<u8>>>,
    output: &Output,
    fb: &Framebuffer,
    d: Draw,
) -> Vec<u8> {
    let look = pixel_view::TextLook {
        symbols: relief_term::Symbols::Half,
        depth: ColorDepth::Truecolor,
        dither: d.dither,
        pad: [0, 0, 0],
    };
    let frame = pixel_view::PixelFrame {
        output,
        fb,
        preview: d.preview,
        new_picture: !d.same,
        look,
        throughput: d.throughput,
        unmeasured: false,
    };
    term.backend_mut().begin_frame().unwrap();
    view.draw(term, frame, AREA, |f, pic| {
        f.render_widget(
            relief_term::SymbolCells {
                fb: pic,
                symbols: look.symbols,
                depth: look.depth,
                dither: look.dither,
                pad: look.pad,
            },
            AREA,
        );
        if let Some(panel) = d.panel {
            f.render_widget(ratatui::widgets::Clear, panel);
        }
    })
    .unwrap();
    term.backend_mut().end_frame().unwrap();
    std::mem::take(term.backend_mut().writer_mut())
}

/// The images (kitty `a=T`, sixel) in `bytes`, each with the cell row the
/// cursor move before it names (0-based) and its sequence.
fn placed_images(bytes: &[u8]) -> Vec<(usize, Vec<u8>)> {
    let mut out = Vec::new();
    let mut i = 0;
    while let Some(at) = find(&bytes[i..], b"\x1b[") {
        let start = i + at + 2;
        let digits = bytes[start..]
            .iter()
            .take_while(|b| b.is_ascii_digit() || **b == b';')
            .count();
        let end = start + digits;
        i = end;
        if bytes.get(end) != Some(&b'H') {
            continue;
        }
        let rest = &bytes[end + 1..];
        if !(rest.starts_with(b"\x1b_Ga=T") || rest.starts_with(b"\x1bP0;1;0q")) {
            continue;
        }
        let row: usize = std::str::from_utf8(&bytes[start..end])
            .unwrap()
            .split(';')
            .next()
            .unwrap()
            .parse()
            .unwrap();
        // The image runs to the next cursor move or the end of the write
        // (a kitty image's chunks hold no `ESC [`; a sixel's neither).
        let len = find(&rest[1..], b"\x1b[").map_or(rest.len(), |n| n + 1);
        out.push((row - 1, rest[..len].to_vec()));
    }
    out
}

/// The cell row of the first cursor move in `bytes` (0-based).
fn first_row(bytes: &[u8]) -> usize {
    let at = find(bytes, b"\x1b[").unwrap() + 2;
    let digits = bytes[at..]
        .iter()
        .take_while(|b| b.is_ascii_digit())
        .count();
    std::str::from_utf8(&bytes[at..at + digits])
        .unwrap()
        .parse::<usize>()
        .unwrap()
        - 1
}

/// What the replayed screen shows at picture pixel (x, y): kitty's top
/// placement, or the sixel pixels.
fn shown_pixel(screen: &Replay, format: Format, x: usize, y: usize) -> Option<[u8; 3]> {
    match format {
        Format::Kitty => screen.kitty_pixel(x, y),
        _ => screen.canvas[y * screen.cols * screen.cell.0 + x],
    }
}

/// Over a link too slow for the exact frame, the first write after input
/// stops is the exact frame scaled down to what the link carries in
/// `LINK_SECONDS`, over the whole picture; then one strip per write, top
/// to bottom, which replayed over it on a terminal model give the exact
/// frame pixel for pixel (kitty: images of their own above relief's;
/// sixel: the frame in its palette; iTerm2: each strip decodes to its
/// rows of the frame); a new picture drops the strips not sent (and
/// deletes kitty's that were). A link fast enough gets the exact image at
/// once.
#[test]
fn the_exact_frame_follows_a_link_sized_picture_in_strips_that_compose_to_it() {
    let _turn = IMAGE_SHOWN.lock().unwrap_or_else(|e| e.into_inner());
    let _ = pixel_view::take_cleanup();
    // 60 × 12 cells of 8 × 16 pixels.
    let (w, h, cell_h) = (480, 192, 16);
    let fb = busy_frame(w, h, 0);
    // 40 kB/s: the link-sized picture may take 10 kB, a strip about 2.7 kB.
    let rate = 40_000.0;
    let budget = rate * pixel_view::LINK_SECONDS;
    let slow = Draw {
        throughput: Some(rate),
        ..Draw::default()
    };
    for format in [Format::Kitty, Format::Sixels, Format::Iterm] {
        let out = output(format);
        let mut term = Terminal::new(SgrBackend::with_size(Vec::new(), 60, 14)).unwrap();
        let mut view = PixelView::new();
        let mut screen = Replay::new(60, 14, (8, cell_h));
        let first = draw_pixels(&mut view, &mut term, &out, &fb, slow);
        screen.feed(&first);
        let image_len = match format {
            Format::Iterm => iterm_images(&first).len(),
            _ => placed_images(&first).len(),
        };
        assert_eq!(image_len, 1, "{format:?}: one picture first");
        let start = find(&first, b"\x1b[1;1H").unwrap();
        let image = &first[start..];
        assert!(
            image.len() as f64 <= budget,
            "{format:?}: the first picture takes {} bytes, more than {budget}",
            image.len()
        );
        match format {
            Format::Kitty => {
                let (keys, raw) = &kitty_images(image)[0];
                // Scaled over the picture's 60 × 12 cells, from fewer pixels.
                assert_eq!((key_value(keys, "c"), key_value(keys, "r")), (60, 12));
                let (sw, sh) = (key_value(keys, "s"), key_value(keys, "v"));
                assert!(sw < w && sh < h, "{sw}×{sh}");
                let mut small = Framebuffer::new(sw, sh);
                pixel_view::downscale(&fb, &mut small);
                assert!(raw == &small.pixels().concat(), "the frame scaled down");
            }
            Format::Sixels => {
                let (sw, sh, _) = decode_sixel(image);
                assert_eq!((sw, sh), (w, h), "sixel fills the cells at full size");
            }
            _ => {
                let (cell, cells, img) = &iterm_images(image)[0];
                assert_eq!((*cell, *cells), ((0, 0), (60, 12)));
                assert!(img.width() < w as u32, "iTerm2 scales a smaller picture");
            }
        }
        // Then one strip per write, top to bottom.
        let mut rows = Vec::new();
        let mut iterm_rows = 0;
        while let Some(strip) = view.next_strip(None).unwrap() {
            rows.push(first_row(&strip));
            screen.feed(&strip);
            if format == Format::Iterm {
                let images = iterm_images(&strip);
                assert_eq!(images.len(), 1, "one image a strip");
                let ((x0, y0), (c, r), img) = &images[0];
                assert_eq!((*x0, *y0, *c), (0, iterm_rows, 60));
                assert_eq!(img.dimensions(), (w as u32, (r * cell_h) as u32));
                for (x, y, p) in img.enumerate_pixels() {
                    let (x, y) = (x as usize, y as usize + y0 * cell_h);
                    assert_eq!(p.0, fb.get(x, y), "{x},{y}");
                }
                iterm_rows += r;
            }
        }
        assert!(rows.len() > 1, "{format:?}: {rows:?}");
        assert_eq!(rows[0], 0);
        assert!(rows.windows(2).all(|p| p[0] < p[1]), "{format:?}: {rows:?}");
        assert!(!view.pending());
        match format {
            Format::Iterm => assert_eq!(iterm_rows, 12, "the strips cover the rows"),
            _ => {
                // The exact picture, composed: what sixel shows of it (its
                // palette), kitty's exactly.
                let want = match format {
                    Format::Sixels => sixel::shown_frame(&fb, sixel::Palette::CHOSEN, false),
                    _ => fb.clone(),
                };
                for y in 0..h {
                    for x in 0..w {
                        let got = shown_pixel(&screen, format, x, y);
                        assert_eq!(got, Some(want.get(x, y)), "{format:?}: {x},{y}");
                    }
                }
            }
        }
        if format == Format::Kitty {
            let cleanup = pixel_view::take_cleanup();
            assert!(cleanup.starts_with(kitty::DELETE));
            assert_eq!(
                count(&cleanup, b"a=d"),
                1 + rows.len(),
                "the strips deleted on exit"
            );
        }

        // Preempted: two strips, then a new picture (a preview of a new
        // orientation) drops the rest.
        let mut view = PixelView::new();
        draw_pixels(&mut view, &mut term, &out, &fb, slow);
        view.next_strip(None).unwrap().unwrap();
        view.next_strip(None).unwrap().unwrap();
        assert!(view.pending());
        let next = busy_frame(w, h, 1);
        let coarse = busy_frame(w / 4, h / 4, 1);
        let preview = Draw {
            preview: Some(&coarse),
            ..slow
        };
        let bytes = draw_pixels(&mut view, &mut term, &out, &next, preview);
        assert!(!view.pending(), "{format:?}: the unsent strips dropped");
        assert_eq!(view.next_strip(None).unwrap(), None);
        if format == Format::Kitty {
            let gone: Vec<usize> = (0..3)
                .map(|k| count(&bytes, &kitty::delete(kitty::strip_id(k))))
                .collect();
            assert_eq!(gone, [1, 1, 0], "the strips sent are deleted");
            let images = kitty_images(&bytes);
            assert_eq!(images.len(), 1, "the new picture alone");
            assert_eq!(key_value(&images[0].0, "s"), w / 4, "the preview");
        }
        let _ = pixel_view::take_cleanup();

        // A link that carries the exact frame in time: it goes whole.
        let mut view = PixelView::new();
        let fast = Draw {
            throughput: Some(1e9),
            ..Draw::default()
        };
        let bytes = draw_pixels(&mut view, &mut term, &out, &fb, fast);
        assert!(!view.pending());
        match format {
            Format::Kitty => assert_eq!(key_value(&kitty_images(&bytes)[0].0, "s"), w),
            Format::Sixels => assert_eq!(placed_images(&bytes).len(), 1),
            _ => assert_eq!(iterm_images(&bytes)[0].2.width(), w as u32),
        }
        let _ = pixel_view::take_cleanup();
    }
}

/// A panel opens while the exact frame comes in strips: the link-sized
/// picture and the strips go around it (kitty: placements that never
/// cover its cells; sixel: its cells stay text); when it closes the
/// picture comes back over its cells, and once the last strip is in, the
/// screen is the exact frame everywhere.
#[test]
fn strips_go_around_a_panel_and_the_exact_frame_completes_when_it_closes() {
    let _turn = IMAGE_SHOWN.lock().unwrap_or_else(|e| e.into_inner());
    let _ = pixel_view::take_cleanup();
    let (w, h) = (480, 192);
    let fb = busy_frame(w, h, 2);
    let panel = Rect::new(20, 2, 30, 6);
    for format in [Format::Kitty, Format::Sixels] {
        let out = output(format);
        let mut term = Terminal::new(SgrBackend::with_size(Vec::new(), 60, 14)).unwrap();
        let mut view = PixelView::new();
        let mut screen = Replay::new(60, 14, (8, 16));
        let open = Draw {
            throughput: Some(40_000.0),
            panel: Some(panel),
            ..Draw::default()
        };
        screen.feed(&draw_pixels(&mut view, &mut term, &out, &fb, open));
        // Strips while the panel is open: through its rows too.
        for _ in 0..6 {
            screen.feed(&view.next_strip(None).unwrap().unwrap());
        }
        assert!(view.pending(), "{format:?}: strips still to come");
        for y in 0..12u16 {
            for x in 0..60u16 {
                let i = usize::from(y) * 60 + usize::from(x);
                let under = panel.contains((x, y).into());
                match format {
                    Format::Kitty => {
                        let px = (usize::from(x) * 8 + 4, usize::from(y) * 16 + 8);
                        let shown = screen.kitty_pixel(px.0, px.1);
                        assert_eq!(shown.is_none(), under, "{format:?}: {x},{y}");
                    }
                    _ => assert_eq!(screen.text[i], under, "{format:?}: {x},{y}"),
                }
            }
        }
        // The panel closes (the same picture), then the rest of the strips.
        let closed = Draw {
            panel: None,
            same: true,
            ..open
        };
        screen.feed(&draw_pixels(&mut view, &mut term, &out, &fb, closed));
        while let Some(strip) = view.next_strip(None).unwrap() {
            screen.feed(&strip);
        }
        let want = match format {
            Format::Sixels => sixel::shown_frame(&fb, sixel::Palette::CHOSEN, false),
            _ => fb.clone(),
        };
        for y in 0..h {
            for x in 0..w {
                let got = shown_pixel(&screen, format, x, y);
                assert_eq!(got, Some(want.get(x, y)), "{format:?}: {x},{y}");
            }
        }
        let _ = pixel_view::take_cleanup();
    }
}

/// The sixel rectangle sent when a panel closes is cut from the frame as
/// the whole image mapped it: the same palette entries and the dither
/// pattern in the same phase, so the screen is then exactly the whole
/// image's picture (no seam at the rectangle's edges), and the rectangle
/// defines only palette entries the whole image defined alike.
#[test]
fn a_sixel_rectangle_after_a_panel_has_the_frames_palette_and_dither() {
    let _turn = IMAGE_SHOWN.lock().unwrap_or_else(|e| e.into_inner());
    let (w, h) = (480, 192);
    let fb = busy_frame(w, h, 3);
    // Odd cells: the rectangle's corner is not on the dither's 4×4 grid.
    let panel = Rect::new(13, 3, 21, 5);
    let out = output(Format::Sixels);
    let mut term = Terminal::new(SgrBackend::with_size(Vec::new(), 60, 14)).unwrap();
    let mut view = PixelView::new();
    let mut screen = Replay::new(60, 14, (8, 16));
    let whole = Draw {
        dither: true,
        ..Draw::default()
    };
    let first = draw_pixels(&mut view, &mut term, &out, &fb, whole);
    screen.feed(&first);
    let opened = Draw {
        panel: Some(panel),
        same: true,
        ..whole
    };
    screen.feed(&draw_pixels(&mut view, &mut term, &out, &fb, opened));
    let closed = draw_pixels(
        &mut view,
        &mut term,
        &out,
        &fb,
        Draw {
            same: true,
            ..whole
        },
    );
    screen.feed(&closed);
    let images = placed_images(&closed);
    assert_eq!(images.len(), 1, "the panel's rectangle alone");
    let (row, part) = &images[0];
    assert_eq!(*row, 3);
    let (pw, ph, _) = decode_sixel(part);
    assert_eq!((pw, ph), (21 * 8, 5 * 16));
    let want = sixel::shown_frame(&fb, sixel::Palette::CHOSEN, true);
    for y in 0..h {
        for x in 0..w {
            assert_eq!(screen.canvas[y * w + x], Some(want.get(x, y)), "{x},{y}");
        }
    }
    // Its palette entries, each as the whole image defined it.
    let entries = |seq: &[u8]| -> Vec<String> {
        let text = String::from_utf8_lossy(seq);
        text.split('#')
            .filter(|e| e.contains(";2;"))
            .map(|e| {
                e.chars()
                    .take_while(|c| c.is_ascii_digit() || *c == ';')
                    .collect()
            })
            .collect()
    };
    let all = entries(&placed_images(&first)[0].1);
    let used = entries(part);
    assert!(!used.is_empty() && used.len() < all.len(), "{}", used.len());
    assert!(used.iter().all(|e| all.contains(e)));
}
