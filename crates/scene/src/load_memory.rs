//! While a model loads, the memory one step frees stays with the allocator
//! for the next step. By default glibc gives each large block a mapping of
//! its own and unmaps it when the block is freed, so every step of a build
//! takes fresh pages the kernel clears on first touch: about 22,000 of the
//! 50,000 such pages of a 100 MB OBJ's load, a tenth of its time, were
//! pages an earlier step had just given back. During a load blocks come
//! from the heap, which keeps what is freed; when the last load ends the
//! defaults come back and what is free is returned to the system. This is
//! a process-wide setting, made only once the program asks for it (relief's
//! binary does, through [`keep_freed_memory_during_loads`]): a program that
//! does not keeps its allocator as it is.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Mutex, PoisonError};

/// Whether the program asked for the allocator to be tuned during loads.
static TUNED: AtomicBool = AtomicBool::new(false);

/// From now on, glibc keeps what each step of a load frees for the next.
pub fn keep_freed_memory_during_loads() {
    TUNED.store(true, Ordering::Release);
}

/// Loads under way (several may overlap: a view's load beside a test's).
static LOADS: Mutex<usize> = Mutex::new(0);

/// Keeps freed memory for reuse while it lives.
pub(crate) struct KeepFreed(());

impl KeepFreed {
    pub fn new() -> KeepFreed {
        let mut loads = LOADS.lock().unwrap_or_else(PoisonError::into_inner);
        if *loads == 0 {
            keep(true);
        }
        *loads += 1;
        KeepFreed(())
    }
}

impl Drop for KeepFreed {
    fn drop(&mut self) {
        let mut loads = LOADS.lock().unwrap_or_else(PoisonError::into_inner);
        *loads -= 1;
        if *loads == 0 {
            keep(false);
        }
    }
}

/// Whether freed memory is being kept (a load is under way).
#[cfg(test)]
fn keeping() -> bool {
    *LOADS.lock().unwrap_or_else(PoisonError::into_inner) > 0
}

/// glibc's settings: no block gets a mapping of its own and the heap is
/// never trimmed (on), or its defaults again and what is free returned
/// (off). Other allocators keep their own ways.
#[cfg(all(target_os = "linux", target_env = "gnu"))]
fn keep(on: bool) {
    if !TUNED.load(Ordering::Acquire) {
        return;
    }
    // glibc's defaults (mallopt(3)).
    const MMAP_MAX: i32 = 65_536;
    const TRIM_THRESHOLD: i32 = 128 * 1024;
    // SAFETY: mallopt and malloc_trim only change the allocator's
    // settings and release free memory; no block in use moves.
    unsafe {
        if on {
            libc::mallopt(libc::M_MMAP_MAX, 0);
            libc::mallopt(libc::M_TRIM_THRESHOLD, i32::MAX);
        } else {
            libc::mallopt(libc::M_MMAP_MAX, MMAP_MAX);
            libc::mallopt(libc::M_TRIM_THRESHOLD, TRIM_THRESHOLD);
            libc::malloc_trim(0);
        }
    }
}

#[cfg(not(all(target_os = "linux", target_env = "gnu")))]
fn keep(_on: bool) {
    let _ = &TUNED;
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn freed_memory_is_kept_while_any_load_lasts() {
        // Other tests load models alongside: only this test's own guards
        // are certain, so it checks while it holds one.
        let outer = KeepFreed::new();
        assert!(keeping());
        let inner = KeepFreed::new();
        drop(outer);
        assert!(keeping(), "the inner load still runs");
        drop(inner);
    }
}
