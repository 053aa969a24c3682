//! Ctrl-Z: the terminal is given back to the shell, the process stops as
//! a job does (SIGTSTP), and when the shell resumes it (SIGCONT, `fg`) the
//! terminal is taken again and the whole screen redrawn.

use std::io;

/// Restores the terminal, stops the process, and on resuming sets the
/// terminal up again. The caller redraws everything (the screen is new).
pub fn suspend() -> io::Result<()> {
    relief_term::guard::restore();
    // SIGTSTP has its default action here (stop): the call returns once
    // the process is continued.
    signal_hook::low_level::raise(signal_hook::consts::SIGTSTP)?;
    relief_term::guard::reenter()
}
