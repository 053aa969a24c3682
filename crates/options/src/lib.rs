//! The options of the view, each declared once in [`OPTIONS`]: the
//! command line's flags ([`flags`]), the keys and their help lines
//! (`app/keys.rs`), the status line's fields (`app/view/status.rs`), the
//! key messages (`app/feedback.rs`) and the bench's rows
//! (`bench/config.rs`) are all read from the table.

mod entry;
mod enums;
pub mod flags;
mod id;
mod table;
pub mod text;

pub use entry::{
    Bench, Ctx, Field, Flag, Form, KeyHelp, Kind, Opt, OptKey, Press, Shows, Status, Step, Value,
};
pub use enums::{index_of, values, variant};
pub use flags::OptionArgs;
pub use id::OptId;
pub use table::{OPTIONS, get, help_keys};
