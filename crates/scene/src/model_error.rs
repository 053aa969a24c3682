//! Why a model could not be loaded, in one printable line.

use thiserror::Error;

use relief_core::sanitize::clean;

/// Why a model (of any format) could not be loaded: one line, already safe to print.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum ObjError {
    #[error("model {name} not found")]
    NotFound { name: String },
    #[error("cannot read model {name}: {reason}")]
    Read { name: String, reason: String },
    #[error("model {name} is not a regular file")]
    NotAFile { name: String },
    #[error("model {name} is not a text file (a NUL byte at offset {at})")]
    NotText { name: String, at: usize },
    #[error("model {name}, line {line}: {problem}")]
    Line {
        name: String,
        line: usize,
        problem: String,
    },
    /// A binary file's problem, at its byte offset.
    #[error("model {name}, byte {offset}: {problem}")]
    Byte {
        name: String,
        offset: u64,
        problem: String,
    },
    #[error("model {name} has no faces")]
    Empty { name: String },
    #[error("model {name} has no face with an area (all points coincide or lie on a line)")]
    Degenerate { name: String },
    #[error("model {name} could not be parsed: {reason}")]
    Parse { name: String, reason: String },
    #[error("model {name}: {what}")]
    Unsupported { name: String, what: String },
    /// `reason` names the model and the limit.
    #[error("{reason}")]
    Budget { name: String, reason: String },
    /// The view asked the load to stop (Esc, or another model asked for).
    #[error("loading model {name} was cancelled")]
    Cancelled { name: String },
}

/// A short, printable quote of a token from the file.
pub(crate) fn quote(token: &str) -> String {
    let mut s: String = clean(token).chars().take(24).collect();
    if token.chars().count() > 24 {
        s.push('…');
    }
    format!("'{s}'")
}
