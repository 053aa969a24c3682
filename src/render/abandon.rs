//! Abandoning a frame: the view asks the renderer to stop when a frame runs
//! long and the user pressed a key meanwhile (`q` must quit at once). The
//! renderer asks its hook before each band of rows, every
//! [`CHECK_EVERY`] triangles within a band and in the shadow pass; once
//! the hook says stop, every band still to come stops too, and the frame
//! reports itself abandoned (its picture is incomplete).

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

/// Asked during a frame: `true` abandons it. Called from the threads that
/// draw the bands, so it must be cheap and thread-safe.
pub type CancelHook = Arc<dyn Fn() -> bool + Send + Sync>;

/// Triangles drawn into a band between two questions to the hook.
pub(super) const CHECK_EVERY: usize = 1024;

/// One frame's view of the hook: remembers a stop so the hook is not asked again.
pub(crate) struct Abandon<'a> {
    hook: Option<&'a (dyn Fn() -> bool + Send + Sync)>,
    stopped: AtomicBool,
}

impl<'a> Abandon<'a> {
    pub(crate) fn new(hook: Option<&'a (dyn Fn() -> bool + Send + Sync)>) -> Self {
        Abandon {
            hook,
            stopped: AtomicBool::new(false),
        }
    }

    /// Whether to stop now (asks the hook unless it already said so).
    #[inline]
    pub(crate) fn now(&self) -> bool {
        let Some(hook) = self.hook else {
            return false;
        };
        if self.stopped.load(Ordering::Relaxed) {
            return true;
        }
        let stop = hook();
        if stop {
            self.stopped.store(true, Ordering::Relaxed);
        }
        stop
    }

    /// Whether the frame was abandoned.
    pub(crate) fn stopped(&self) -> bool {
        self.stopped.load(Ordering::Relaxed)
    }
}
