//! Model files load on a worker thread, so the view keeps drawing (and
//! quits at once) while a big one is read and built.
//!
//! One load at a time: asking for another scene cancels the one under way
//! (its worker stops at its next check, see
//! [`relief_scene::load_progress`], and what it still sends is ignored).
//! The worker ends by calling the loop's wake-up with its load's number;
//! the loop then takes the result with [`Loader::finished`] and shows it,
//! or keeps the scene shown when it failed. Quitting does not wait for a
//! worker: it dies with the process.

use std::sync::Arc;
use std::sync::mpsc::{self, Receiver};
use std::time::Instant;

use super::load_status::LoadStatus;
use super::stage::{BuildOrder, Ready};
use relief_core::sanitize::display_path;
use relief_scene::load_progress::{self, LoadProgress};
use relief_scene::{ModelChoice, SceneKind};

/// Tells the loop that load number `id` is done (sends it a message).
pub type Wake = Arc<dyn Fn(u64) + Send + Sync>;

/// The load under way, if any, and how the worker wakes the loop.
pub struct Loader {
    wake: Wake,
    job: Option<Job>,
    next_id: u64,
}

/// One load on its worker.
struct Job {
    id: u64,
    kind: SceneKind,
    model: ModelChoice,
    name: String,
    progress: Arc<LoadProgress>,
    result: Receiver<Result<Ready, String>>,
    started: Instant,
}

/// A load that ended: what it was for and what came of it.
pub struct Finished {
    pub kind: SceneKind,
    pub model: ModelChoice,
    pub result: Result<Ready, String>,
}

impl Loader {
    pub fn new(wake: impl Fn(u64) + Send + Sync + 'static) -> Loader {
        Loader {
            wake: Arc::new(wake),
            job: None,
            next_id: 0,
        }
    }

    /// Whether building `kind` with `model` goes to a worker: a model file
    /// (the built-in scenes take milliseconds).
    pub fn wants(kind: SceneKind, model: &ModelChoice) -> bool {
        kind == SceneKind::Cube && matches!(model, ModelChoice::File(_))
    }

    /// Starts building `order` on a worker (cancelling the load under way)
    /// and says so.
    pub fn start(&mut self, order: BuildOrder, now: Instant) -> LoadStatus {
        self.cancel();
        let id = self.next_id;
        self.next_id += 1;
        let progress = LoadProgress::new();
        let (tx, result) = mpsc::channel();
        let name = match &order.model {
            ModelChoice::File(path) => display_path(path),
            other => format!("{other:?}"),
        };
        let job = Job {
            id,
            kind: order.kind,
            model: order.model.clone(),
            name,
            progress: progress.clone(),
            result,
            started: now,
        };
        let wake = self.wake.clone();
        std::thread::spawn(move || {
            let built = load_progress::run_with(&progress, || {
                relief_core::contain::contain(|| order.build())
                    .unwrap_or_else(|cause| Err(format!("the load failed ({cause})")))
            });
            // The loop may have moved on (cancelled, or quit): then no one hears.
            if tx.send(built).is_ok() {
                wake(id);
            }
        });
        self.job = Some(job);
        self.status(now).expect("a load was just started")
    }

    /// The scene and model being loaded, if any.
    pub fn loading(&self) -> Option<(SceneKind, &ModelChoice)> {
        self.job.as_ref().map(|j| (j.kind, &j.model))
    }

    /// Stops the load under way, if any: the worker stops at its next
    /// check and its result is dropped.
    pub fn cancel(&mut self) {
        if let Some(job) = self.job.take() {
            job.progress.cancel();
        }
    }

    /// How far the load under way is at `now`.
    pub fn status(&self, now: Instant) -> Option<LoadStatus> {
        self.job.as_ref().map(|j| LoadStatus {
            name: j.name.clone(),
            progress: j.progress.now(),
            elapsed: now.saturating_duration_since(j.started),
        })
    }

    /// The outcome of load `id` once its worker woke the loop; `None` for a
    /// load that was cancelled or replaced since.
    pub fn finished(&mut self, id: u64) -> Option<Finished> {
        if self.job.as_ref().is_none_or(|j| j.id != id) {
            return None;
        }
        let job = self.job.take()?;
        let result = job
            .result
            .recv()
            .unwrap_or_else(|_| Err(format!("loading {} stopped", job.name)));
        Some(Finished {
            kind: job.kind,
            model: job.model,
            result,
        })
    }
}
