//! A terminal that reports 65535×65535 cells: the view draws a capped
//! picture in its top-left corner instead of allocating hundreds of gigabytes.

use std::sync::mpsc;

use ratatui::Terminal;
use ratatui::backend::Backend;
use relief::app::State;
use relief::app::event_loop::{Looper, Msg};
use relief_core::budget::{MAX_VIEW_COLUMNS, MAX_VIEW_ROWS};
use relief_core::settings::Settings;
use relief_term::{ColorDepth, SgrBackend};

#[test]
fn a_huge_terminal_gets_a_capped_view() {
    let backend = SgrBackend::with_size(Vec::new(), u16::MAX, u16::MAX);
    let size = backend.size().unwrap();
    assert_eq!((size.width, size.height), (MAX_VIEW_COLUMNS, MAX_VIEW_ROWS));
    let mut term = Terminal::new(backend).unwrap();
    let (tx, rx) = mpsc::channel();
    tx.send(Msg::Resized).unwrap();
    drop(tx);
    let mut state = State::new(Settings::default(), ColorDepth::Truecolor);
    let mut frames = Vec::new();
    Looper::new(
        &mut term,
        &rx,
        |_: &State, fb: &mut relief_core::framebuffer::Framebuffer| {
            frames.push((fb.width(), fb.height()));
            fb.fill([200, 10, 10]);
            relief_core::stats::FrameStats::default()
        },
    )
    .run(&mut state)
    .unwrap();
    assert!(!frames.is_empty());
    for (w, h) in frames {
        assert!(w > 0 && h > 0);
        assert!(w <= MAX_VIEW_COLUMNS as usize && h <= 2 * MAX_VIEW_ROWS as usize);
    }
    let bytes = term.backend().writer().len();
    assert!(bytes > 0, "something was drawn");
}
