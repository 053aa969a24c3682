//! How far a frame has come, for a view that shows the progress of a long
//! one. The renderer counts the triangles its bands have gone through (a
//! band goes through every triangle of the frame, twice when it draws depth
//! first), and before them the triangle visits of its shadow map's bands
//! (a caster triangle is visited by each band of the map's rows it
//! crosses); the rest of the frame (placing, culling, setting up, the
//! shadow casters' setup included) is "preparing".

use std::sync::atomic::{AtomicU8, AtomicU64, Ordering};

/// Shared between the renderer (which counts) and a watcher on another
/// thread (which reads). Counting costs one relaxed addition per
/// [`super::abandon::CHECK_EVERY`] triangles of a band.
#[derive(Debug, Default)]
pub struct FrameProgress {
    /// 0: preparing, 1: the shadow map, 2: the bands.
    step: AtomicU8,
    /// Triangle visits the step has made, and will make in all.
    done: AtomicU64,
    total: AtomicU64,
}

/// A frame's progress as read at one moment.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FrameStep {
    /// Placing, culling, setting up.
    Preparing,
    /// The shadow map is drawing: about `done` of its `total` triangle
    /// visits made.
    Shadow { done: u64, total: u64 },
    /// The bands are drawing: `done` of `total` triangle visits made.
    Drawing { done: u64, total: u64 },
}

impl FrameProgress {
    pub fn new() -> Self {
        FrameProgress::default()
    }

    /// A frame starts.
    pub(crate) fn start(&self) {
        self.enter(0, 0);
    }

    /// The shadow map's fills start: they will make `total` triangle visits.
    pub(crate) fn shadow(&self, total: u64) {
        self.enter(1, total);
    }

    /// The bands start: they will make `total` triangle visits.
    pub(crate) fn drawing(&self, total: u64) {
        self.enter(2, total);
    }

    fn enter(&self, step: u8, total: u64) {
        self.done.store(0, Ordering::Relaxed);
        self.total.store(total.max(1), Ordering::Relaxed);
        self.step.store(step, Ordering::Relaxed);
    }

    /// `visits` more triangle visits made.
    #[inline]
    pub(crate) fn advance(&self, visits: u64) {
        self.done.fetch_add(visits, Ordering::Relaxed);
    }

    /// Where the frame is now.
    pub fn now(&self) -> FrameStep {
        let step = self.step.load(Ordering::Relaxed);
        let total = self.total.load(Ordering::Relaxed).max(1);
        let done = self.done.load(Ordering::Relaxed).min(total);
        match step {
            0 => FrameStep::Preparing,
            1 => FrameStep::Shadow { done, total },
            _ => FrameStep::Drawing { done, total },
        }
    }
}
