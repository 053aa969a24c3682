//! The command line: relief render and relief bench end to end.
//!
//! One test crate per area (each file a module) so the suite links a few
//! binaries instead of one per file.

mod bench_quick;
mod output;
mod preview;
mod render;
