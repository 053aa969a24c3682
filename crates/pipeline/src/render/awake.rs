//! The pool's other workers kept awake while a frame is drawn. A frame
//! has several short parallel stages (placing, projecting, the triangle
//! stage and its join, the shadow map, the bands); between them a worker
//! of rayon's pool that finds no work goes to sleep, and waking it for the
//! next stage takes 30–70 µs on the 2-core build machine: on a frame under
//! a millisecond the second thread then cost more than it gave
//! (docs/bench.md, "The model view's benchmark targets"). So at the start
//! of a frame each other worker is given a task that takes the pool's work
//! as it comes (`rayon::yield_now`) until the frame ends.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

/// While it lives, the pool's other workers look for work without sleeping.
pub(super) struct Awake {
    running: Arc<AtomicBool>,
}

impl Awake {
    /// Sets the other workers of the current pool looking for work; `None`
    /// on a pool of one thread.
    pub(super) fn start() -> Option<Awake> {
        let others = rayon::current_num_threads().saturating_sub(1);
        if others == 0 {
            return None;
        }
        let running = Arc::new(AtomicBool::new(true));
        // The thread drawing the frame may take one of these tasks back
        // while it waits for its own: it must not stay in it, or the frame
        // would never end.
        let drawing = rayon::current_thread_index();
        for _ in 0..others {
            let running = Arc::clone(&running);
            rayon::spawn(move || {
                if drawing.is_some() && rayon::current_thread_index() == drawing {
                    return;
                }
                while running.load(Ordering::Acquire) {
                    // Without work the core goes to whatever else is
                    // runnable (the terminal, sshd), but the worker stays
                    // awake.
                    if rayon::yield_now() != Some(rayon::Yield::Executed) {
                        std::thread::yield_now();
                    }
                }
            });
        }
        Some(Awake { running })
    }
}

impl Drop for Awake {
    fn drop(&mut self) {
        self.running.store(false, Ordering::Release);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::mpsc::channel;
    use std::time::Duration;

    /// The task left in the drawing thread's own queue (the other worker
    /// busy elsewhere) is taken back by that thread while it waits, as a
    /// join does: it must return at once, the frame still being drawn, or
    /// the frame would never end.
    #[test]
    fn the_drawing_thread_does_not_keep_itself_awake() {
        let (done_tx, done_rx) = channel();
        std::thread::spawn(move || {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(2)
                .build()
                .unwrap();
            let (hold_tx, hold_rx) = channel::<()>();
            let (held_tx, held_rx) = channel();
            let ran = pool.install(move || {
                // The other worker takes this task and is held in it.
                rayon::spawn(move || {
                    held_tx.send(()).unwrap();
                    hold_rx.recv().ok();
                });
                held_rx.recv().unwrap();
                let awake = Awake::start().expect("a pool of two");
                let ran = rayon::yield_local();
                drop(awake);
                hold_tx.send(()).unwrap();
                ran
            });
            done_tx.send(ran).unwrap();
        });
        // A liveness bound, not a speed: the task returns at once.
        let ran = done_rx.recv_timeout(Duration::from_secs(60));
        assert_eq!(
            ran,
            Ok(Some(rayon::Yield::Executed)),
            "the frame never ended"
        );
    }

    /// On one thread nothing is started.
    #[test]
    fn one_thread_has_nothing_to_keep_awake() {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap();
        assert!(pool.install(Awake::start).is_none());
    }
}
