//! What the last frames cost, stage by stage: the state keeps it, the cost
//! panel ([`super::view::cost`]) shows it.

use std::collections::VecDeque;
use std::time::Duration;

use relief_core::stats::{Counters, FrameStats};

/// Frames the panel remembers (and the sparkline shows at most).
pub const HISTORY: usize = 120;

/// The cost of one frame shown on the terminal.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FrameCost {
    /// Deciding what runs and transforming vertices.
    pub plan: Duration,
    /// Rasterizing and shading.
    pub raster: Duration,
    /// Turning the framebuffer into terminal cells and escape sequences.
    pub encode: Duration,
    /// Handing the bytes to the terminal.
    pub write: Duration,
    pub counters: Counters,
    /// Bytes sent to the terminal.
    pub bytes: u64,
}

impl FrameCost {
    /// A frame whose picture was rendered (`stats`), then encoded and written.
    pub fn new(stats: &FrameStats, encode: Duration, write: Duration, bytes: u64) -> Self {
        FrameCost {
            plan: stats.plan_time,
            raster: stats.raster_time,
            encode,
            write,
            counters: stats.counters,
            bytes,
        }
    }

    pub fn total(&self) -> Duration {
        self.plan + self.raster + self.encode + self.write
    }
}

/// The last [`HISTORY`] frames, oldest first.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CostHistory {
    frames: VecDeque<FrameCost>,
}

impl CostHistory {
    pub fn push(&mut self, cost: FrameCost) {
        if self.frames.len() == HISTORY {
            self.frames.pop_front();
        }
        self.frames.push_back(cost);
    }

    pub fn len(&self) -> usize {
        self.frames.len()
    }

    pub fn is_empty(&self) -> bool {
        self.frames.is_empty()
    }

    pub fn last(&self) -> Option<&FrameCost> {
        self.frames.back()
    }

    /// Mean time of each stage over the remembered frames (counters and bytes
    /// of the last frame).
    pub fn mean(&self) -> Option<FrameCost> {
        let last = *self.frames.back()?;
        let n = self.frames.len() as u32;
        let sum = |f: fn(&FrameCost) -> Duration| self.frames.iter().map(f).sum::<Duration>() / n;
        Some(FrameCost {
            plan: sum(|c| c.plan),
            raster: sum(|c| c.raster),
            encode: sum(|c| c.encode),
            write: sum(|c| c.write),
            ..last
        })
    }

    /// Total time of each frame in microseconds, oldest first: the sparkline's data.
    pub fn totals_us(&self) -> Vec<u64> {
        self.frames
            .iter()
            .map(|c| c.total().as_micros().min(u64::MAX as u128) as u64)
            .collect()
    }
}
