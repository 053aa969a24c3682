//! Standard output as `relief render` writes it (`--ansi`, `--out -`): a
//! closed one is refused before anything is rendered, a write that fails
//! names it in plain words, and a reader that stops reading ends the
//! program quietly, as a filter does.

use std::io;
use std::sync::atomic::{AtomicBool, Ordering};

use relief_core::sanitize::io_reason;

/// The reader at the other end of standard output closed it (a pager
/// quit, a file manager moved on to another file): no error for a filter,
/// `main` exits with status 0 and says nothing.
#[derive(Debug, thiserror::Error)]
#[error("the reader of standard output closed it")]
pub struct ClosedPipe;

/// Whether descriptor 1 was closed when the process started, as seen by
/// [`record_at_start`] (false when it never ran).
static CLOSED_AT_START: AtomicBool = AtomicBool::new(false);

/// Notes whether standard output is closed. It must run before the Rust
/// runtime starts: the runtime opens `/dev/null` in place of a closed
/// standard descriptor, after which a closed one cannot be told from a
/// redirection to `/dev/null`. The binary runs it from `.init_array`.
pub extern "C" fn record_at_start() {
    // SAFETY: fcntl(F_GETFD) on descriptor 1 only reads its flags.
    let closed = unsafe { libc::fcntl(1, libc::F_GETFD) } == -1;
    CLOSED_AT_START.store(closed, Ordering::Relaxed);
}

/// Fails when standard output was closed when relief started (`>&-`):
/// what is written would go nowhere, and nobody would know.
pub fn check_open() -> anyhow::Result<()> {
    if CLOSED_AT_START.load(Ordering::Relaxed) {
        anyhow::bail!(
            "standard output is closed, so there is nowhere to write the frame: redirect it to a file or a pipe"
        );
    }
    Ok(())
}

/// The error a failed write to standard output is: [`ClosedPipe`] when
/// the reader went away, else one sentence naming standard output.
pub fn write_error(e: io::Error) -> anyhow::Error {
    if e.kind() == io::ErrorKind::BrokenPipe {
        return ClosedPipe.into();
    }
    anyhow::anyhow!("cannot write to standard output: {}", io_reason(&e))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_broken_pipe_is_the_quiet_end_and_other_errors_name_standard_output() {
        let e = write_error(io::Error::from_raw_os_error(libc::EPIPE));
        assert!(e.downcast_ref::<ClosedPipe>().is_some());
        let e = write_error(io::Error::from_raw_os_error(libc::ENOSPC)).to_string();
        assert_eq!(
            e,
            "cannot write to standard output: no space left on device"
        );
    }
}
