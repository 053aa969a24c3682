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
use relief::term::{ColorDepth, SgrBackend, kitty, sixel};

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
/// while `keys` last, and ends the input once the exact picture has come
/// after them: a kitty image as wide as the first, or strips of it over
/// all 12 rows of the picture.
struct SlowLink {
    out: Vec<u8>,
    tx: mpsc::Sender<Msg>,
    keys: usize,
    full_width: Option<usize>,
    strip_rows: usize,
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
        } else {
            for (keys, _) in &images {
                if key_value(keys, "i") == kitty::IMAGE_ID as usize {
                    self.strip_rows = 0;
                    if Some(key_value(keys, "s")) == self.full_width {
                        self.strip_rows = 12;
                    }
                } else {
                    self.strip_rows += key_value(keys, "r");
                }
            }
            if self.strip_rows >= 12 {
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
    let link = SlowLink {
        out: Vec::new(),
        tx,
        keys: 8,
        full_width: None,
        strip_rows: 0,
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
    let all = kitty_images(&term.backend().writer().out);
    // The pictures (relief's image), then the strips of the last one.
    let split = all
        .iter()
        .rposition(|(k, _)| key_value(k, "i") == kitty::IMAGE_ID as usize)
        .unwrap();
    let (images, strips) = all.split_at(split + 1);
    let widths: Vec<usize> = images.iter().map(|(k, _)| key_value(k, "s")).collect();
    let full = widths[0];
    assert!(
        widths.iter().any(|&w| w < full),
        "a smaller preview while the keys came: {widths:?}"
    );
    for (keys, raw) in images {
        // Every image covers the picture's cells, whatever its pixels.
        assert_eq!((key_value(keys, "c"), key_value(keys, "r")), (60, 12));
        assert_eq!(raw.len(), key_value(keys, "s") * key_value(keys, "v") * 3);
    }
    // The exact frame last: whole, or in strips at full width over all rows.
    let rows: usize = strips.iter().map(|(k, _)| key_value(k, "r")).sum();
    assert!(
        *widths.last().unwrap() == full || rows == 12,
        "the exact frame last: {widths:?}, strips over {rows} rows"
    );
    for (keys, _) in strips {
        assert_eq!((key_value(keys, "s"), key_value(keys, "c")), (full, 60));
    }
    let _ = pixel_view::take_cleanup();
}

/// One image of a write: the cell row it is placed at (0-based, from the
/// `CSI row;col H` before it) and its sequence.
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
        // The image runs to the next placement or the end of the write.
        // (A kitty image's chunks hold no `ESC [`; a sixel's neither.)
        let len = find(&rest[1..], b"\x1b[").map_or(rest.len(), |n| n + 1);
        out.push((row - 1, rest[..len].to_vec()));
    }
    out
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

/// Draws `fb` into `view` as the loop does (inside one synchronized
/// frame) and returns the bytes written.
fn draw_pixels(
    view: &mut PixelView,
    term: &mut Terminal<SgrBackend<Vec<u8>>>,
    output: &Output,
    fb: &Framebuffer,
    preview: Option<&Framebuffer>,
    throughput: f64,
) -> Vec<u8> {
    let viewport = Rect::new(0, 0, 60, 12);
    let look = pixel_view::TextLook {
        symbols: relief::term::Symbols::Half,
        depth: ColorDepth::Truecolor,
        dither: false,
        pad: [0, 0, 0],
    };
    let frame = pixel_view::PixelFrame {
        output,
        fb,
        preview,
        new_picture: true,
        look,
        throughput: Some(throughput),
    };
    term.backend_mut().begin_frame().unwrap();
    view.draw(term, frame, viewport, |f, pic| {
        f.render_widget(
            relief::term::SymbolCells {
                fb: pic,
                symbols: look.symbols,
                depth: look.depth,
                dither: look.dither,
                pad: look.pad,
            },
            viewport,
        );
    })
    .unwrap();
    term.backend_mut().end_frame().unwrap();
    std::mem::take(term.backend_mut().writer_mut())
}

/// Over a link too slow for the exact frame, the first write after input
/// stops is the exact frame scaled down to what the link carries in
/// `LINK_SECONDS`, over the whole picture; then one strip per write, top
/// to bottom, whose images composed over it decode to the exact frame;
/// a new picture drops the strips not sent (and deletes kitty's that
/// were). A link fast enough gets the exact image at once.
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
    for format in [Format::Kitty, Format::Sixels] {
        let out = output(format);
        let mut term = Terminal::new(SgrBackend::with_size(Vec::new(), 60, 14)).unwrap();
        let mut view = PixelView::new();
        let first = draw_pixels(&mut view, &mut term, &out, &fb, None, rate);
        let images = placed_images(&first);
        assert_eq!(images.len(), 1, "{format:?}: one picture first");
        let (row, image) = &images[0];
        assert_eq!(*row, 0);
        assert!(
            image.len() as f64 <= budget,
            "{format:?}: the first picture takes {} bytes, more than {budget}",
            image.len()
        );
        // The exact picture, composed: what sixel shows of it (its
        // palette), kitty's exactly.
        let want = match format {
            Format::Sixels => sixel::shown_frame(&fb, sixel::Palette::CHOSEN, false),
            _ => fb.clone(),
        };
        let mut canvas = Framebuffer::new(w, h);
        let mut covered = vec![false; h];
        if format == Format::Kitty {
            let (keys, raw) = &kitty_images(image)[0];
            // Scaled over the picture's 60 × 12 cells, from fewer pixels.
            assert_eq!((key_value(keys, "c"), key_value(keys, "r")), (60, 12));
            let (sw, sh) = (key_value(keys, "s"), key_value(keys, "v"));
            assert!(sw < w && sh < h, "{sw}×{sh}");
            let mut small = Framebuffer::new(sw, sh);
            pixel_view::downscale(&fb, &mut small);
            assert!(raw == &small.pixels().concat(), "the frame scaled down");
        } else {
            let (sw, sh, px) = decode_sixel(image);
            assert_eq!((sw, sh), (w, h), "sixel fills the cells at full size");
            for (p, got) in canvas.pixels_mut().iter_mut().zip(&px) {
                *p = got.expect("every pixel drawn");
            }
        }
        // Then one strip per write.
        let mut writes = 0;
        let mut next_row = 0;
        while let Some(strip) = view.next_strip() {
            writes += 1;
            let images = placed_images(&strip);
            assert_eq!(images.len(), 1, "{format:?}: one strip a write");
            let (row, image) = &images[0];
            assert_eq!(*row, next_row, "{format:?}: strips top to bottom");
            let y0 = row * cell_h;
            let (sw, sh, px): (usize, usize, Vec<[u8; 3]>) = if format == Format::Kitty {
                let (keys, raw) = &kitty_images(image)[0];
                assert_eq!(key_value(keys, "i"), kitty::strip_id(writes - 1) as usize);
                assert_eq!(key_value(keys, "c"), 60);
                assert_eq!(key_value(keys, "v"), key_value(keys, "r") * cell_h);
                let px = raw.chunks(3).map(|c| [c[0], c[1], c[2]]).collect();
                (key_value(keys, "s"), key_value(keys, "v"), px)
            } else {
                let (sw, sh, px) = decode_sixel(image);
                (sw, sh, px.into_iter().map(|p| p.unwrap()).collect())
            };
            assert_eq!(sw, w);
            for y in 0..sh {
                covered[y0 + y] = true;
                for x in 0..w {
                    canvas.set(x, y0 + y, px[y * w + x]);
                }
            }
            next_row = row + sh / cell_h;
        }
        assert!(writes > 1, "{format:?}: {writes} strips");
        assert!(covered.iter().all(|&c| c), "{format:?}: every row");
        assert!(
            canvas.pixels() == want.pixels(),
            "{format:?}: the strips compose to the exact frame"
        );
        assert!(!view.pending());
        if format == Format::Kitty {
            let cleanup = pixel_view::take_cleanup();
            assert!(cleanup.starts_with(kitty::DELETE));
            assert_eq!(
                count(&cleanup, b"a=d"),
                1 + writes,
                "the strips deleted on exit"
            );
        }

        // Preempted: two strips, then a new picture (a preview of a new
        // orientation) drops the rest.
        let mut view = PixelView::new();
        draw_pixels(&mut view, &mut term, &out, &fb, None, rate);
        view.next_strip().unwrap();
        view.next_strip().unwrap();
        assert!(view.pending());
        let next = busy_frame(w, h, 1);
        let coarse = busy_frame(w / 4, h / 4, 1);
        let bytes = draw_pixels(&mut view, &mut term, &out, &next, Some(&coarse), rate);
        assert!(!view.pending(), "{format:?}: the unsent strips dropped");
        assert_eq!(view.next_strip(), None);
        assert_eq!(placed_images(&bytes).len(), 1, "the new picture alone");
        if format == Format::Kitty {
            let mut gone = Vec::new();
            for k in 0..3 {
                let mut one = Vec::new();
                kitty::delete(kitty::strip_id(k), &mut one);
                gone.push(count(&bytes, &one));
            }
            assert_eq!(gone, [1, 1, 0], "the strips sent are deleted");
            let (keys, _) = &kitty_images(&bytes)[0];
            assert_eq!(key_value(keys, "s"), w / 4, "the preview");
        }
        let _ = pixel_view::take_cleanup();

        // A link that carries the exact frame in time: it goes whole.
        let mut view = PixelView::new();
        let bytes = draw_pixels(&mut view, &mut term, &out, &fb, None, 1e9);
        assert!(!view.pending());
        let images = placed_images(&bytes);
        assert_eq!(images.len(), 1);
        if format == Format::Kitty {
            assert_eq!(key_value(&kitty_images(&images[0].1)[0].0, "s"), w);
        }
        let _ = pixel_view::take_cleanup();
    }
}
