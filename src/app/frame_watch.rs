//! A frame that runs long shows its progress on the status line.
//!
//! The loop renders on its own thread and cannot draw while a frame runs,
//! so a watcher thread lives for the frame: once the frame has run
//! [`LONG_FRAME`], it writes one line over the status row every
//! [`REFRESH`] until the frame ends. The line is written between frames
//! (the loop writes nothing while it renders), cursor and attributes saved
//! and restored around it; afterwards the loop puts the row back as
//! ratatui last drew it, so ratatui's picture of the screen stays true.

use std::io::Write;
use std::sync::Arc;
use std::sync::mpsc::{RecvTimeoutError, channel};
use std::time::{Duration, Instant};

use super::load_status::percent;
use relief_pipeline::render::{FrameProgress, FrameStep};

/// A frame running this long shows its progress (and a key pressed
/// meanwhile abandons it: see `app::abandon_when_keys`).
pub const LONG_FRAME: Duration = Duration::from_millis(500);
/// How often the progress line is written again.
pub const REFRESH: Duration = Duration::from_millis(250);

/// What the loop needs to show a long frame's progress: the counter the
/// renderer keeps, and where the line goes (the terminal, written to
/// directly while the loop waits for the frame).
pub struct FrameWatch {
    pub progress: Arc<FrameProgress>,
    pub out: Box<dyn Write + Send>,
}

/// The status row's place: row (from 0) and width in cells.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StatusRow {
    pub row: u16,
    pub width: u16,
}

impl FrameWatch {
    /// Runs `render`; if it takes over [`LONG_FRAME`] and there is a
    /// status row, writes the progress line meanwhile. Returns what
    /// `render` returned, and whether a line was written (the row must then
    /// be drawn again).
    pub fn watch<T>(&mut self, status: Option<StatusRow>, render: impl FnOnce() -> T) -> (T, bool) {
        let Some(status) = status else {
            return (render(), false);
        };
        let (done, ended) = channel::<()>();
        let progress = &*self.progress;
        let out = &mut self.out;
        std::thread::scope(|s| {
            let watcher = s.spawn(move || {
                let start = Instant::now();
                let mut wait = LONG_FRAME;
                let mut wrote = false;
                while let Err(RecvTimeoutError::Timeout) = ended.recv_timeout(wait) {
                    let line = progress_line(progress.now(), start.elapsed(), status);
                    // A write that fails leaves the line out; the frame goes on.
                    wrote |= out.write_all(&line).and_then(|()| out.flush()).is_ok();
                    wait = REFRESH;
                }
                wrote
            });
            let value = render();
            drop(done);
            (value, watcher.join().unwrap_or(true))
        })
    }
}

/// The words of the progress line.
pub fn progress_text(step: FrameStep, elapsed: Duration) -> String {
    let what = match step {
        FrameStep::Preparing => "preparing the frame".to_string(),
        FrameStep::Shadow { done, total } => {
            format!("drawing the shadow map: {}%", percent(done, total))
        }
        FrameStep::Drawing { done, total } => {
            format!("drawing the frame: {}%", percent(done, total))
        }
    };
    format!(
        "{what} · {:.1} s (a key abandons it, q quits)",
        elapsed.as_secs_f32()
    )
}

/// The bytes that write the progress line over the status row, as the
/// status line looks (reversed video, the whole row), leaving the cursor
/// and attributes as they were.
pub fn progress_line(step: FrameStep, elapsed: Duration, status: StatusRow) -> Vec<u8> {
    // Every character of the line is one cell wide.
    let width = usize::from(status.width);
    let text: String = progress_text(step, elapsed).chars().take(width).collect();
    let pad = width.saturating_sub(text.chars().count());
    let mut line = Vec::new();
    line.extend_from_slice(b"\x1b7");
    line.extend_from_slice(format!("\x1b[{};1H\x1b[0;7m", status.row + 1).as_bytes());
    line.extend_from_slice(text.as_bytes());
    line.extend(std::iter::repeat_n(b' ', pad));
    line.extend_from_slice(b"\x1b[0m\x1b8");
    line
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_line_says_the_step_and_fills_the_row() {
        let status = StatusRow { row: 47, width: 59 };
        let line = progress_line(
            FrameStep::Drawing {
                done: 37,
                total: 100,
            },
            Duration::from_millis(1250),
            status,
        );
        let text = String::from_utf8(line).unwrap();
        let body = "drawing the frame: 37% · 1.2 s (a key abandons it, q quits)";
        assert_eq!(body.chars().count(), 59);
        assert_eq!(text, format!("\x1b7\x1b[48;1H\x1b[0;7m{body}\x1b[0m\x1b8"));
    }

    #[test]
    fn a_narrow_row_cuts_the_line_and_a_wide_one_is_padded() {
        let narrow = StatusRow { row: 0, width: 10 };
        let text =
            String::from_utf8(progress_line(FrameStep::Preparing, Duration::ZERO, narrow)).unwrap();
        assert_eq!(text, "\x1b7\x1b[1;1H\x1b[0;7mpreparing \x1b[0m\x1b8");
        let wide = StatusRow { row: 0, width: 80 };
        let text =
            String::from_utf8(progress_line(FrameStep::Preparing, Duration::ZERO, wide)).unwrap();
        let body = "preparing the frame · 0.0 s (a key abandons it, q quits)";
        assert!(text.contains(&format!(
            "{body}{}\x1b[0m",
            " ".repeat(80 - body.chars().count())
        )));
    }

    #[test]
    fn each_step_says_what_it_is_drawing() {
        let at = Duration::from_millis(2049);
        let text = |step| progress_text(step, at);
        assert_eq!(
            text(FrameStep::Shadow { done: 1, total: 3 }),
            "drawing the shadow map: 33% · 2.0 s (a key abandons it, q quits)"
        );
        assert_eq!(
            text(FrameStep::Drawing { done: 3, total: 3 }),
            "drawing the frame: 100% · 2.0 s (a key abandons it, q quits)"
        );
    }

    #[test]
    fn a_short_frame_writes_nothing() {
        let mut watch = FrameWatch {
            progress: Arc::new(FrameProgress::new()),
            out: Box::new(std::io::sink()),
        };
        let status = Some(StatusRow { row: 1, width: 40 });
        assert_eq!(watch.watch(status, || 7), (7, false));
        assert_eq!(watch.watch(None, || 8), (8, false));
    }
}
