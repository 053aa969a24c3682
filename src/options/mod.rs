//! The options of the view, each declared once in [`OPTIONS`]: the
//! command line's flags ([`flags`]), the keys and their help lines
//! (`app/keys.rs`), the status line's fields (`app/view/status.rs`), the
//! key messages (`app/feedback.rs`) and the bench's rows
//! (`bench/config.rs`) are all read from the table.

mod entry;
pub mod flags;
mod table;
pub mod text;

use clap::ValueEnum;
use clap::builder::PossibleValue;

pub use entry::{
    Bench, Ctx, Field, Flag, Form, KeyHelp, Kind, Opt, OptKey, Press, Shows, Status, Step, Value,
};
pub use flags::OptionArgs;
pub use table::OPTIONS;

use crate::settings::Settings;

/// The option named `name` (its [`Settings`] field).
pub fn find(name: &str) -> Option<&'static Opt> {
    OPTIONS.iter().find(|o| o.name == name)
}

/// The position of `x` among its enum's values.
pub fn index_of<T: ValueEnum + PartialEq>(x: T) -> usize {
    T::value_variants()
        .iter()
        .position(|v| *v == x)
        .unwrap_or(0)
}

/// The enum's value at position `i` (the default past the end).
pub fn variant<T: ValueEnum + Copy + Default>(i: usize) -> T {
    T::value_variants().get(i).copied().unwrap_or_default()
}

/// The command line's spellings of an enum's values, with their help.
pub fn values<T: ValueEnum>() -> Vec<PossibleValue> {
    T::value_variants()
        .iter()
        .filter_map(ValueEnum::to_possible_value)
        .collect()
}

impl Opt {
    /// The flag: the name with `-` for `_`.
    pub fn flag_name(&self) -> String {
        self.name.replace('_', "-")
    }

    pub fn get(&self, settings: &Settings) -> Value {
        (self.field.get)(settings)
    }

    pub fn set(&self, settings: &mut Settings, value: Value) {
        (self.field.set)(settings, value)
    }

    /// Whether the value is the default's.
    pub fn is_default(&self, settings: &Settings) -> bool {
        self.get(settings) == self.get(&Settings::default())
    }

    /// What a key does: the next value, or a number a step up or down.
    pub fn press(&self, settings: &mut Settings, press: Press) {
        let value = match (&self.kind, self.get(settings), press) {
            (Kind::Toggle, Value::Bool(b), Press::Next) => Value::Bool(!b),
            (Kind::Choice { values }, Value::Index(i), Press::Next) => {
                Value::Index((i + 1) % values().len().max(1))
            }
            (Kind::Number { step, .. }, Value::Number(x), Press::Up) => Value::Number(step.up(x)),
            (Kind::Number { step, .. }, Value::Number(x), Press::Down) => {
                Value::Number(step.down(x))
            }
            _ => return,
        };
        self.set(settings, value);
    }

    /// Every value a toggle or an enum takes, in order (a number: none).
    pub fn all_values(&self) -> Vec<Value> {
        match &self.kind {
            Kind::Toggle => vec![Value::Bool(true), Value::Bool(false)],
            Kind::Choice { values } => (0..values().len()).map(Value::Index).collect(),
            Kind::Number { .. } => Vec::new(),
        }
    }

    /// A value as the command line spells it (`on`, `nearest`, `2x2`, `0.006`).
    pub fn spell(&self, value: Value) -> String {
        match (&self.kind, value) {
            (Kind::Choice { values }, Value::Index(i)) => values()
                .get(i)
                .map_or_else(|| "?".into(), |v| v.get_name().to_string()),
            (_, Value::Bool(b)) => text::on_off(b).into(),
            (_, Value::Number(x)) => format!("{x}"),
            (_, Value::Index(i)) => format!("{i}"),
        }
    }

    /// The value as the key messages word it (numbers only: "bump strength 0.0075").
    pub fn shown(&self, settings: &Settings) -> Option<String> {
        match (&self.kind, self.get(settings)) {
            (Kind::Number { show, .. }, Value::Number(x)) => {
                Some(format!("{} {}", self.title, show(x)))
            }
            _ => None,
        }
    }

    /// The keys as the key messages name them: the first of each press ("+ -").
    pub fn key_names(&self) -> String {
        let names: Vec<String> = self
            .keys
            .iter()
            .filter_map(|k| k.keys.first().map(char::to_string))
            .collect();
        names.join(" ")
    }

    /// "keys (title)", how the key messages start.
    pub fn key_title(&self) -> String {
        format!("{} ({})", self.key_names(), self.title)
    }

    /// The message refusing a key of this option where its change would
    /// not show (`None`: it shows).
    pub fn refusal(&self, ctx: &Ctx) -> Option<String> {
        let shows = self.shows.as_ref()?;
        (!(shows.when)(ctx)).then(|| format!("{}: {}", self.key_title(), shows.why))
    }
}
