//! Standard output as `relief render` writes it (`--ansi`, `--out -`): a
//! closed one is refused before anything is rendered, a write that fails
//! names it in plain words, and a reader that stops reading ends the
//! program quietly, as a filter does.

use std::io;

use crate::sanitize::io_reason;

/// The reader at the other end of standard output closed it (a pager
/// quit, a file manager moved on to another file): no error for a filter,
/// `main` exits with status 0 and says nothing.
#[derive(Debug, thiserror::Error)]
#[error("the reader of standard output closed it")]
pub struct ClosedPipe;

/// Fails when standard output was closed when relief started. The Rust
/// runtime opens `/dev/null` read-write in place of a closed standard
/// descriptor, so that is how a closed one looks from here (a shell's
/// `> /dev/null` opens it write-only).
pub fn check_open() -> anyhow::Result<()> {
    if stdout_was_closed() {
        anyhow::bail!(
            "standard output is closed, so there is nowhere to write the frame: redirect it to a file or a pipe"
        );
    }
    Ok(())
}

fn stdout_was_closed() -> bool {
    // SAFETY: fcntl and fstat on descriptor 1 only read its flags and
    // status into a local struct.
    unsafe {
        let flags = libc::fcntl(1, libc::F_GETFL);
        if flags == -1 {
            return true;
        }
        let mut stat: libc::stat = std::mem::zeroed();
        if libc::fstat(1, &mut stat) != 0 {
            return true;
        }
        let dev_null = std::fs::metadata("/dev/null")
            .map(|m| std::os::unix::fs::MetadataExt::rdev(&m))
            .ok();
        (flags & libc::O_ACCMODE) == libc::O_RDWR
            && (stat.st_mode & libc::S_IFMT) == libc::S_IFCHR
            && dev_null == Some(stat.st_rdev)
    }
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
