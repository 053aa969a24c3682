//! The command line: relief render and relief bench end to end.

mod bench_quick;
mod output;
mod preview;
mod render;
