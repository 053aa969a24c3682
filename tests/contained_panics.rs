//! A panic inside a third-party decoder or the OBJ parser is contained: the
//! user gets the usual one-line error, the view keeps its texture, and the
//! panic hook (which restores the terminal and prints) stays silent.
//!
//! A test binary of its own: the hook it counts with is process-wide, and
//! another test panicking in the same process meanwhile would be counted.

mod hostile;

use std::cell::RefCell;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, mpsc};

use crossterm::event::Event;
use ratatui::Terminal;
use relief::app::State;
use relief::app::event_loop::{Looper, Msg};
use relief::app::texture_list::TextureList;
use relief_core::settings::Settings;
use relief_term::{ColorDepth, SgrBackend};
use relief_texture::decode::load::load_texture_from_bytes;

static HOOK_CALLS: AtomicUsize = AtomicUsize::new(0);

/// One test (not several) so that the counting hook is the first one set;
/// no other test of this crate sets a hook.
#[test]
fn decoder_panics_become_errors_and_leave_the_hook_silent() {
    // Stands for the terminal guard's hook: it would restore the terminal.
    let previous = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        if !relief_core::contain::is_containing() {
            HOOK_CALLS.fetch_add(1, Ordering::SeqCst);
            previous(info);
        }
    }));

    // png 0.18's palette expansion indexes past a PLTE whose length is not
    // a multiple of three.
    let bad = hostile::palette_png(4);
    let direct = std::panic::catch_unwind(|| {
        let mut d = png::Decoder::new(std::io::Cursor::new(bad.clone()));
        d.set_transformations(png::Transformations::EXPAND);
        let mut reader = d.read_info().unwrap();
        let mut buf = vec![0; reader.output_buffer_size().unwrap()];
        let _ = reader.next_frame(&mut buf);
    });
    assert!(direct.is_err(), "the constructed file no longer panics png");
    assert_eq!(HOOK_CALLS.swap(0, Ordering::SeqCst), 1);

    let err = load_texture_from_bytes("pal\x1b[2J.png", &bad).unwrap_err();
    let msg = err.to_string();
    assert!(
        msg.starts_with("pal?[2J.png: corrupt") && msg.contains("PNG") && !msg.contains('\n'),
        "{msg}"
    );
    // A valid palette of the same shape loads.
    assert!(load_texture_from_bytes("ok.png", &hostile::palette_png(3)).is_ok());

    // In the view: pasted, the file is refused, the texture stays.
    let dir = hostile::scratch("paste");
    let path = dir.join("palette.png");
    std::fs::write(&path, &bad).unwrap();
    let list = RefCell::new(TextureList::new());
    let before = Arc::clone(list.borrow().texture());
    let (tx, rx) = mpsc::channel();
    tx.send(Msg::Input(Event::Paste(format!("'{}'", path.display()))))
        .unwrap();
    tx.send(Msg::InputClosed("end".into())).unwrap();
    let mut term = Terminal::new(SgrBackend::with_size(Vec::new(), 40, 12)).unwrap();
    let mut state = State::new(Settings::default(), ColorDepth::Truecolor);
    Looper {
        textures: Some(&list),
        ..Looper::new(
            &mut term,
            &rx,
            |_: &State, fb: &mut relief_core::framebuffer::Framebuffer| {
                fb.fill([1, 2, 3]);
                relief_core::stats::FrameStats::default()
            },
        )
    }
    .run(&mut state)
    .unwrap();
    let shown = state.message.unwrap();
    assert!(shown.contains("palette.png: corrupt"), "{shown}");
    assert!(Arc::ptr_eq(&before, list.borrow().texture()));
    assert_eq!(HOOK_CALLS.load(Ordering::SeqCst), 0, "hook ran");

    // A real panic elsewhere still reaches the hook.
    let _ = std::thread::spawn(|| panic!("not contained")).join();
    assert_eq!(HOOK_CALLS.load(Ordering::SeqCst), 1);
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn render_reports_a_decoder_panic_in_one_line() {
    let dir = hostile::scratch("render");
    let bad = dir.join("palette.png");
    std::fs::write(&bad, hostile::palette_png(7)).unwrap();
    let out = dir.join("out.png");
    let o = hostile::relief(&[
        "render",
        "--out",
        out.to_str().unwrap(),
        bad.to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.contains("palette.png: corrupt") && !err.contains("panicked"),
        "{err}"
    );
    assert!(!out.exists());
    let _ = std::fs::remove_dir_all(dir);
}
