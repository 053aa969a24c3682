//! Panics in parsers (third-party image decoders; the OBJ reader) kept inside the
//! call that fed them untrusted bytes: the caller gets an error and goes on.
//!
//! A panic hook runs for every panic, caught or not, and the terminal guard's
//! hook restores the terminal and prints. A thread-local flag tells the hooks
//! that the panic on this thread is being contained: they stay silent and the
//! view keeps its screen. (A scoped thread would not help: the hook runs on
//! whichever thread panics.) A panic on another thread at the same time is
//! not affected by the flag.

use std::cell::Cell;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::Once;

thread_local! {
    static DEPTH: Cell<u32> = const { Cell::new(0) };
}

static HOOK: Once = Once::new();

/// True while this thread runs a [`contain`]ed call: a panic now is caught.
pub fn is_containing() -> bool {
    DEPTH.with(|d| d.get() > 0)
}

/// Puts a hook in front of the present one that is silent for contained
/// panics (once per process).
fn install_hook() {
    HOOK.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if !is_containing() {
                previous(info);
            }
        }));
    });
}

/// Runs `f`; a panic inside it becomes `Err` with the panic's message (one
/// line, control characters replaced). `f` must leave nothing half-changed
/// that the caller reads afterwards: callers pass closures that only build a
/// new value from borrowed input, which is why asserting unwind safety is
/// sound here.
pub fn contain<T>(f: impl FnOnce() -> T) -> Result<T, String> {
    install_hook();
    DEPTH.with(|d| d.set(d.get() + 1));
    let result = catch_unwind(AssertUnwindSafe(f));
    DEPTH.with(|d| d.set(d.get() - 1));
    result.map_err(|payload| {
        let text = payload
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| payload.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "unknown cause".into());
        let line = text.split_whitespace().collect::<Vec<_>>().join(" ");
        let mut clean = crate::sanitize::clean(&line);
        if clean.chars().count() > 120 {
            clean = clean.chars().take(120).collect::<String>() + "…";
        }
        clean
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_panic_becomes_an_error_and_the_flag_is_cleared() {
        let r: Result<(), String> = contain(|| panic!("bad\x1b[2Jbytes\nhere"));
        assert_eq!(r, Err("bad?[2Jbytes here".to_string()));
        assert!(!is_containing());
        assert_eq!(contain(|| 7), Ok(7));
        // Nested: the inner one is caught, the outer goes on.
        let outer = contain(|| {
            let inner: Result<(), String> = contain(|| panic!("inner"));
            assert!(is_containing());
            inner.is_err()
        });
        assert_eq!(outer, Ok(true));
    }
}
