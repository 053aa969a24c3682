//! What relief sets for its whole process, once, at the start of `main`.
//! The libraries hold the mechanisms, next to the data they serve, but
//! change no process-wide state until the program asks:
//!
//! - the SIGBUS handler that lets a model file be mapped into memory and
//!   shrink under relief without ending it in raw mode
//!   (`relief_scene::file_map`);
//! - glibc's allocator keeping what one step of a model load frees for the
//!   next (`relief_scene::load_memory`).

/// Makes the process-wide settings; later calls change nothing.
pub fn tune() {
    relief_scene::file_map::install_bus_guard();
    relief_scene::load_memory::keep_freed_memory_during_loads();
}
