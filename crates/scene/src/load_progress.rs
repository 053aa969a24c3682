//! How far a model load has gone, and a way to stop it: the view loads on
//! a worker thread and shows this on its status line a few times a second;
//! Esc sets the cancel flag, which the readers check between chunks.
//!
//! The loaders do not take it as a parameter: the worker runs the load
//! inside [`run_with`], and the readers find it with [`current`] (a
//! parallel pass takes it before it fans out). A load run any other way
//! (`relief render`, the tests) has none, and every report is a no-op.

use std::cell::RefCell;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU8, AtomicU64, Ordering};

use super::model_error::ObjError;

/// What a load is doing now.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum LoadStep {
    /// Not started yet (the worker is starting).
    #[default]
    Starting,
    /// The file's bytes: `done` of `total` bytes read.
    Reading,
    /// The text or records: `done` of `total` units (bytes for OBJ, one
    /// unit a pass over the file) parsed; `total` 0 when not known.
    Parsing,
    /// Building the mesh from `total` triangles (normals, vertices,
    /// tangents): no finer count.
    Building,
}

impl LoadStep {
    const ALL: [LoadStep; 4] = [
        LoadStep::Starting,
        LoadStep::Reading,
        LoadStep::Parsing,
        LoadStep::Building,
    ];

    pub fn label(self) -> &'static str {
        match self {
            LoadStep::Starting => "starting",
            LoadStep::Reading => "reading",
            LoadStep::Parsing => "parsing",
            LoadStep::Building => "building",
        }
    }
}

/// A load's progress, shared between the worker (which writes it) and the
/// view (which reads it and may cancel).
#[derive(Debug, Default)]
pub struct LoadProgress {
    step: AtomicU8,
    done: AtomicU64,
    total: AtomicU64,
    cancel: AtomicBool,
}

/// What [`LoadProgress`] says at one moment.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ProgressNow {
    pub step: LoadStep,
    pub done: u64,
    pub total: u64,
}

impl LoadProgress {
    pub fn new() -> Arc<LoadProgress> {
        Arc::new(LoadProgress::default())
    }

    /// Asks the load to stop at its next check.
    pub fn cancel(&self) {
        self.cancel.store(true, Ordering::Relaxed);
    }

    pub fn cancelled(&self) -> bool {
        self.cancel.load(Ordering::Relaxed)
    }

    /// A new step of `total` units, none done.
    pub fn begin(&self, step: LoadStep, total: u64) {
        // `done` first: a reader that sees the new step sees no old count
        // above the new total for long (the view clamps anyway).
        self.done.store(0, Ordering::Relaxed);
        self.total.store(total, Ordering::Relaxed);
        self.step.store(step as u8, Ordering::Relaxed);
    }

    /// `units` more of the step done.
    pub fn advance(&self, units: u64) {
        self.done.fetch_add(units, Ordering::Relaxed);
    }

    pub fn now(&self) -> ProgressNow {
        let step = LoadStep::ALL
            .get(self.step.load(Ordering::Relaxed) as usize)
            .copied()
            .unwrap_or_default();
        let total = self.total.load(Ordering::Relaxed);
        let done = self.done.load(Ordering::Relaxed);
        ProgressNow {
            step,
            done: if total > 0 { done.min(total) } else { done },
            total,
        }
    }
}

thread_local! {
    static CURRENT: RefCell<Option<Arc<LoadProgress>>> = const { RefCell::new(None) };
}

/// Runs `load` with `progress` as the current load's: the readers it calls
/// on this thread report to it and stop when it is cancelled.
pub fn run_with<T>(progress: &Arc<LoadProgress>, load: impl FnOnce() -> T) -> T {
    let before = CURRENT.with(|c| c.replace(Some(progress.clone())));
    // Put back even if `load` panics (a contained panic must not leave a
    // stale progress on a thread that loads again).
    struct Restore(Option<Arc<LoadProgress>>);
    impl Drop for Restore {
        fn drop(&mut self) {
            let before = self.0.take();
            CURRENT.with(|c| *c.borrow_mut() = before);
        }
    }
    let _restore = Restore(before);
    load()
}

/// The progress of the load running on this thread, if any.
pub fn current() -> Option<Arc<LoadProgress>> {
    CURRENT.with(|c| c.borrow().clone())
}

/// Starts `step` of `total` units on the current load, if any.
pub fn begin(step: LoadStep, total: u64) {
    if let Some(p) = current() {
        p.begin(step, total);
    }
}

/// An error when the current load was cancelled (a reader calls this
/// between chunks and steps).
pub fn check(name: &str) -> Result<(), ObjError> {
    match current() {
        Some(p) if p.cancelled() => Err(cancelled(name)),
        _ => Ok(()),
    }
}

/// The error a cancelled load ends with.
pub fn cancelled(name: &str) -> ObjError {
    ObjError::Cancelled {
        name: name.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reports_reach_the_progress_run_with_and_only_it() {
        let p = LoadProgress::new();
        begin(LoadStep::Reading, 10); // no load here: nothing happens
        assert_eq!(p.now(), ProgressNow::default());
        run_with(&p, || {
            begin(LoadStep::Parsing, 300);
            current().unwrap().advance(120);
            assert!(check("m.obj").is_ok());
        });
        assert!(current().is_none(), "the thread's progress is put back");
        assert_eq!(
            p.now(),
            ProgressNow {
                step: LoadStep::Parsing,
                done: 120,
                total: 300
            }
        );
        p.cancel();
        let err = run_with(&p, || check("m.obj")).unwrap_err();
        assert_eq!(err, cancelled("m.obj"));
        assert!(check("m.obj").is_ok(), "outside the load: nothing to stop");
    }

    #[test]
    fn done_never_reads_above_its_total() {
        let p = LoadProgress::new();
        p.begin(LoadStep::Reading, 100);
        p.advance(150);
        assert_eq!(p.now().done, 100);
        p.begin(LoadStep::Building, 0);
        p.advance(7);
        assert_eq!(p.now().done, 7, "no total: the count as it is");
    }
}
