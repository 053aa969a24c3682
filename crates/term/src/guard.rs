//! Setting the terminal up and always putting it back: on drop, on panic,
//! and from the signal watchdog.

use std::io::{self, Write};
use std::sync::Once;
use std::sync::atomic::{AtomicBool, Ordering};

/// Alternate screen, hidden cursor, mouse buttons and drags with SGR
/// coordinates (1000, 1002, 1006: not 1003, which reports every motion),
/// bracketed paste, cleared screen.
pub const SETUP: &[u8] =
    b"\x1b[?1049h\x1b[?25l\x1b[?1000h\x1b[?1002h\x1b[?1006h\x1b[?2004h\x1b[0m\x1b[2J";
/// Everything `SETUP` switched on, switched off again, in reverse order. The
/// alternate screen is cleared before leaving it: after a resize, tmux
/// otherwise copies rows of it onto the shell's screen.
/// 1003 (all motion, switched on in the plasma scene) goes off too.
/// A synchronized update still open (a frame cut short) is ended first,
/// and only then: see [`restore`].
pub const RESTORE: &[u8] =
    b"\x1b[?2004l\x1b[?1006l\x1b[?1003l\x1b[?1002l\x1b[?1000l\x1b[0m\x1b[2J\x1b[?25h\x1b[?1049l";

static ACTIVE: AtomicBool = AtomicBool::new(false);
/// The terminal got the start of a synchronized update and not its end.
static SYNC_OPEN: AtomicBool = AtomicBool::new(false);

/// Notes whether `data`, written to the terminal, leaves a synchronized
/// update open: its last mark decides (frames put both marks in one write).
fn note_sync_marks(data: &[u8]) {
    const MARK: &[u8] = b"\x1b[?2026";
    let Some(at) = data
        .windows(MARK.len() + 1)
        .rposition(|w| w.starts_with(MARK))
    else {
        return;
    };
    match data[at + MARK.len()] {
        b'h' => SYNC_OPEN.store(true, Ordering::SeqCst),
        b'l' => SYNC_OPEN.store(false, Ordering::SeqCst),
        _ => {}
    }
}

/// The bytes that put the terminal back: [`RESTORE`], after the end of a
/// synchronized update when one is open (never an end without a start:
/// kitty warns about those).
pub fn restore_sequence(sync_open: bool) -> Vec<u8> {
    let mut out = Vec::with_capacity(RESTORE.len() + 8);
    if sync_open {
        out.extend_from_slice(super::backend::END_SYNC);
    }
    out.extend_from_slice(RESTORE);
    out
}
static HOOK: Once = Once::new();

/// While alive, the terminal is in raw mode on the alternate screen.
pub struct TerminalGuard {
    _private: (),
}

impl TerminalGuard {
    pub fn enter() -> io::Result<TerminalGuard> {
        HOOK.call_once(|| {
            let previous = std::panic::take_hook();
            std::panic::set_hook(Box::new(move |info| {
                // A decoder's panic caught by `contain` leaves the view as it is.
                if relief_core::contain::is_containing() {
                    return;
                }
                restore();
                previous(info);
            }));
        });
        crossterm::terminal::enable_raw_mode()?;
        RAW.store(true, Ordering::SeqCst);
        ACTIVE.store(true, Ordering::SeqCst);
        let mut out = io::stdout().lock();
        if let Err(e) = out.write_all(SETUP).and_then(|_| out.flush()) {
            drop(out);
            restore();
            return Err(e);
        }
        Ok(TerminalGuard { _private: () })
    }
}

/// Sets the terminal up again after [`restore`] (a job resumed after
/// Ctrl-Z): raw mode and [`SETUP`]; the guard alive puts it back at the end.
pub fn reenter() -> io::Result<()> {
    crossterm::terminal::enable_raw_mode()?;
    RAW.store(true, Ordering::SeqCst);
    ACTIVE.store(true, Ordering::SeqCst);
    let mut out = io::stdout().lock();
    out.write_all(SETUP).and_then(|_| out.flush())
}

impl Drop for TerminalGuard {
    fn drop(&mut self) {
        restore();
    }
}

/// True between setup and restore.
pub fn is_active() -> bool {
    ACTIVE.load(Ordering::SeqCst)
}

/// Puts the terminal back (once; later calls do nothing). Errors are ignored:
/// the terminal may already be gone.
pub fn restore() {
    restore_screen();
    if RAW.swap(false, Ordering::SeqCst) {
        let _ = crossterm::terminal::disable_raw_mode();
    }
}

/// Raw mode is on (set up and not yet switched off).
static RAW: AtomicBool = AtomicBool::new(false);

/// Puts the screen back (once) but leaves raw mode on, so replies to
/// queries still on their way are read by relief instead of being echoed
/// onto the shell; [`restore`] then switches raw mode off.
pub fn restore_screen() {
    if ACTIVE.swap(false, Ordering::SeqCst) {
        let mut out = io::stdout().lock();
        let open = SYNC_OPEN.swap(false, Ordering::SeqCst);
        // A pixel image still shown is deleted after the frame's end mark.
        let mut bytes = Vec::new();
        if open {
            bytes.extend_from_slice(super::backend::END_SYNC);
        }
        bytes.extend(super::pixel_view::take_cleanup());
        bytes.extend(restore_sequence(false));
        let _ = out.write_all(&bytes);
        let _ = out.flush();
    }
}

/// Standard output that drops writes once the terminal is restored, so a
/// frame still buffered during a panic never lands on the user's shell screen.
/// It writes to its own handle on fd 1, bypassing `Stdout`'s line buffer, so
/// a frame is one `write` call.
/// It also notes whether a synchronized update is left open, so the
/// restore ends it only then.
#[derive(Debug)]
pub struct GuardedStdout {
    file: std::fs::File,
}

impl GuardedStdout {
    pub fn new() -> io::Result<GuardedStdout> {
        use std::os::fd::AsFd;
        let fd = io::stdout().as_fd().try_clone_to_owned()?;
        Ok(GuardedStdout {
            file: std::fs::File::from(fd),
        })
    }
}

impl Write for GuardedStdout {
    fn write(&mut self, data: &[u8]) -> io::Result<usize> {
        if is_active() {
            let n = self.file.write(data)?;
            note_sync_marks(&data[..n]);
            Ok(n)
        } else {
            Ok(data.len())
        }
    }

    fn flush(&mut self) -> io::Result<()> {
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_restore_ends_a_synchronized_update_only_when_one_is_open() {
        let end = super::super::backend::END_SYNC;
        let count = |b: &[u8]| b.windows(end.len()).filter(|w| *w == end).count();
        assert_eq!(count(&restore_sequence(false)), 0);
        assert_eq!(count(&restore_sequence(true)), 1);
        assert!(restore_sequence(true).starts_with(end));
        // The last mark of a write decides.
        note_sync_marks(b"\x1b[?2026hframe\x1b[?2026l\x1b[c");
        assert!(!SYNC_OPEN.load(Ordering::SeqCst));
        note_sync_marks(b"\x1b[?2026l\x1b[?2026hhalf a frame");
        assert!(SYNC_OPEN.load(Ordering::SeqCst));
        note_sync_marks(b"no marks at all");
        assert!(SYNC_OPEN.load(Ordering::SeqCst));
        note_sync_marks(b"rest\x1b[?2026l");
        assert!(!SYNC_OPEN.load(Ordering::SeqCst));
    }
}
