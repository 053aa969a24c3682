//! Waiting for the terminal to send something, with a time-out: the
//! blocking reads elsewhere cannot tell "nothing yet" from "nothing coming".

use std::io;
use std::os::fd::RawFd;
use std::time::Duration;

/// True when `fd` has bytes to read (or has reached its end) within
/// `timeout`; false when the time ran out first.
pub fn readable_within(fd: RawFd, timeout: Duration) -> io::Result<bool> {
    // Whole milliseconds, rounded up: a caller waiting for a deadline is
    // not woken just before it, to wait again for nothing.
    let ms = timeout.as_micros().div_ceil(1000).min(i32::MAX as u128) as libc::c_int;
    loop {
        let mut fds = libc::pollfd {
            fd,
            events: libc::POLLIN,
            revents: 0,
        };
        // SAFETY: one valid pollfd, its count, a time-out.
        let ready = unsafe { libc::poll(&mut fds, 1, ms) };
        if ready >= 0 {
            return Ok(ready > 0);
        }
        let err = io::Error::last_os_error();
        if err.kind() != io::ErrorKind::Interrupted {
            return Err(err);
        }
    }
}
