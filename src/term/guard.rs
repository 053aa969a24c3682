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
pub const RESTORE: &[u8] =
    b"\x1b[?2026l\x1b[?2004l\x1b[?1006l\x1b[?1003l\x1b[?1002l\x1b[?1000l\x1b[0m\x1b[2J\x1b[?25h\x1b[?1049l";

static ACTIVE: AtomicBool = AtomicBool::new(false);
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
                if crate::contain::is_containing() {
                    return;
                }
                restore();
                previous(info);
            }));
        });
        crossterm::terminal::enable_raw_mode()?;
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
    if ACTIVE.swap(false, Ordering::SeqCst) {
        let mut out = io::stdout().lock();
        let _ = out.write_all(RESTORE);
        let _ = out.flush();
        let _ = crossterm::terminal::disable_raw_mode();
    }
}

/// Standard output that drops writes once the terminal is restored, so a
/// frame still buffered during a panic never lands on the user's shell screen.
/// It writes to its own handle on fd 1, bypassing `Stdout`'s line buffer, so
/// a frame is one `write` call.
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
            self.file.write(data)
        } else {
            Ok(data.len())
        }
    }

    fn flush(&mut self) -> io::Result<()> {
        Ok(())
    }
}
