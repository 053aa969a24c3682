//! Abandoning a frame: the view asks the renderer to stop when a frame runs
//! long and the user pressed a key meanwhile (`q` must quit at once). The
//! renderer asks its hook before each band of rows, every
//! [`CHECK_EVERY`] triangles within a band and in the shadow pass; once
//! the hook says stop, every band still to come stops too, and the frame
//! reports itself abandoned (its picture is incomplete).

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use super::progress::FrameProgress;
use crate::shadow::Watch;

/// Asked during a frame: `true` abandons it. Called from the threads that
/// draw the bands, so it must be cheap and thread-safe.
pub type CancelHook = Arc<dyn Fn() -> bool + Send + Sync>;

/// Triangles drawn into a band between two questions to the hook.
pub(super) const CHECK_EVERY: usize = 1024;

/// One frame's view of the hook: remembers a stop so the hook is not asked
/// again. It also carries the frame's progress counter, if the view keeps
/// one: the hook and the counter are met at the same places.
pub(crate) struct Abandon<'a> {
    hook: Option<&'a (dyn Fn() -> bool + Send + Sync)>,
    stopped: AtomicBool,
    progress: Option<&'a FrameProgress>,
}

impl<'a> Abandon<'a> {
    pub(crate) fn new(
        hook: Option<&'a (dyn Fn() -> bool + Send + Sync)>,
        progress: Option<&'a FrameProgress>,
    ) -> Self {
        if let Some(p) = progress {
            p.start();
        }
        Abandon {
            hook,
            stopped: AtomicBool::new(false),
            progress,
        }
    }

    /// The bands start, to make `visits` triangle visits in all.
    pub(crate) fn drawing(&self, visits: u64) {
        if let Some(p) = self.progress {
            p.drawing(visits);
        }
    }

    /// `visits` more triangle visits made by a band or the shadow map.
    #[inline]
    pub(crate) fn advance(&self, visits: usize) {
        if let Some(p) = self.progress {
            p.advance(visits as u64);
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

/// The shadow pass counts its visits and asks to stop at the same places.
impl Watch for Abandon<'_> {
    fn start(&self, visits: u64) {
        if let Some(p) = self.progress {
            p.shadow(visits);
        }
    }
    fn advance(&self, visits: usize) {
        Abandon::advance(self, visits);
    }
    fn stop(&self) -> bool {
        self.now()
    }
}
