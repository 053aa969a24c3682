//! What one option declares: its value, its flag, its keys, its status
//! field, its bench rows and where it lives in [`Settings`].

use clap::builder::PossibleValue;

use super::text;
use relief_core::settings::Settings;

/// One option of the view: everything the command line, the keys, the
/// help, the status line, the key messages and the bench know about it.
pub struct Opt {
    /// What keys, messages and bench rows name it by.
    pub id: super::OptId,
    /// The [`Settings`] field it reads and writes; the flag is this with
    /// `-` for `_` (`bump_strength` → `--bump-strength`).
    pub name: &'static str,
    /// What the key messages call it: "m (lighting): …".
    pub title: &'static str,
    pub kind: Kind,
    pub field: Field,
    pub flag: Flag,
    /// The keys that change it, in the help's order (empty: none).
    pub keys: &'static [OptKey],
    /// When a change shows (the plan's predicate); a key pressed when it
    /// does not is refused with this text. `None`: it always shows.
    pub shows: Option<Shows>,
    /// Its field in the status line (`None`: the status line has none, or
    /// words it with another field).
    pub status: Option<Status>,
    /// Its rows in `relief bench`.
    pub bench: Bench,
}

/// The type of the value.
pub enum Kind {
    /// On or off.
    Toggle,
    /// One of an enum's values, cycled by a key in declaration order; the
    /// list gives the flag's spellings and their help.
    Choice { values: fn() -> Vec<PossibleValue> },
    /// A number, checked by `parse` on the command line, moved by keys in
    /// `step`s and shown by `show`.
    Number {
        parse: fn(&str) -> Result<f32, String>,
        step: Step,
        show: fn(f32) -> String,
        /// The flag takes a leading `-` as a value (so `-1` is refused by
        /// `parse` with its own message, not as an unknown flag).
        negative: bool,
    },
}

/// A value of any kind.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Value {
    Bool(bool),
    /// The position of an enum's value in declaration order.
    Index(usize),
    Number(f32),
}

impl Value {
    pub fn bool(self) -> bool {
        matches!(self, Value::Bool(true))
    }
    pub fn index(self) -> usize {
        match self {
            Value::Index(i) => i,
            _ => 0,
        }
    }
    pub fn number(self) -> f32 {
        match self {
            Value::Number(x) => x,
            _ => 0.0,
        }
    }
}

/// How the option reads and writes its [`Settings`] field (made by the
/// table's `field!` macro).
pub struct Field {
    pub get: fn(&Settings) -> Value,
    pub set: fn(&mut Settings, Value),
}

/// How a number moves under its keys: multiplied or divided by `factor`
/// and kept in `min..=max`; with `zero_below`, a value under it goes to 0
/// going down, and 0 comes back to it going up. With `wrap` (an angle),
/// `factor` is added or taken away instead, and the value wraps from
/// `max` back to `min`.
pub struct Step {
    pub factor: f32,
    pub min: f32,
    pub max: f32,
    pub zero_below: Option<f32>,
    pub wrap: bool,
}

impl Step {
    /// `v` brought back into `min..max` (wrapping steps).
    fn wrapped(&self, v: f32) -> f32 {
        let span = self.max - self.min;
        self.min + (v - self.min).rem_euclid(span)
    }
    pub fn up(&self, v: f32) -> f32 {
        if self.wrap {
            return self.wrapped(v + self.factor);
        }
        match self.zero_below {
            Some(m) if v < m => m,
            _ => (v * self.factor).min(self.max),
        }
    }
    pub fn down(&self, v: f32) -> f32 {
        if self.wrap {
            return self.wrapped(v - self.factor);
        }
        let k = v / self.factor;
        match self.zero_below {
            Some(m) if k < m => 0.0,
            _ => k.max(self.min),
        }
    }
}

/// How the flag is spelled.
pub struct Flag {
    /// The line of `--help`; a number's `{min}`, `{max}`, `{step}` and
    /// `{default}` are filled in from its entry ([`Opt::fill`]).
    pub help: &'static str,
    /// The value's name in `--help` (`None`: the name in capitals).
    pub value_name: Option<&'static str>,
    pub form: Form,
}

/// The flag's form.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Form {
    /// `--name VALUE`, the default shown in `--help`.
    Value,
    /// `--name VALUE` without a default: left out, the caller decides
    /// (`--environment` is on by itself when a map is given).
    Optional,
    /// `--name` alone switches a toggle on.
    Switch,
}

/// What a key does to the option.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Press {
    /// The next value (a toggle flips).
    Next,
    /// A number one step up.
    Up,
    /// A number one step down.
    Down,
}

/// The keys of one press and their help.
pub struct OptKey {
    /// The first is the one messages name; the others do the same.
    pub keys: &'static [char],
    pub press: Press,
    pub help: KeyHelp,
}

/// How a key shows in the help.
pub enum KeyHelp {
    /// Its own line: the text (filled in as [`Opt::fill`] does), after the
    /// keys it describes ([`super::help_keys`]): this one, the `Above` keys
    /// after it in the table, then `others`, keys of the app's own
    /// (`app/keys.rs`) that share the line.
    Line {
        text: &'static str,
        others: &'static str,
    },
    /// Described by the line above.
    Above,
}

/// What the status line and the key messages know of the frame beyond
/// the settings.
#[derive(Clone, Copy, Debug)]
pub struct Ctx<'a> {
    pub settings: &'a Settings,
    /// Some reference light is switched on (keys `1`–`4`).
    pub lights_on: bool,
    /// A `--normal-map` file is loaded.
    pub normal_map_loaded: bool,
    /// The shown model file has no texture until the user chooses one
    /// (its parts name no material): the texture field says `none`.
    pub texture_waits: bool,
}

/// When a change shows, and what a refused key says.
pub struct Shows {
    pub when: fn(&Ctx) -> bool,
    /// After "keys (title): ".
    pub why: &'static str,
}

/// The option's field in the status line. As the screen narrows, fields
/// shorten in increasing `shorten`, then go in increasing drop rank
/// (those at their default value first).
pub struct Status {
    /// Place in the line among all fields (see `app/view/status.rs`).
    pub at: u8,
    pub long: fn(&Ctx) -> String,
    /// `None`: one form.
    pub short: Option<fn(&Ctx) -> String>,
    pub shorten: u8,
    /// `None`: never goes.
    pub drop: Option<u8>,
    /// `None`: shown always.
    pub shown: Option<fn(&Ctx) -> bool>,
    /// Whether it counts as at its default (`None`: its value is the
    /// default's).
    pub at_default: Option<fn(&Ctx) -> bool>,
}

/// The option's rows in `relief bench`.
pub enum Bench {
    None,
    /// A row per value but the default, named `column=value`.
    Axis(&'static str),
    /// One row with the toggle away from its default, named this.
    Row(&'static str),
}

impl Opt {
    /// `text` with a number's `{min}`, `{max}`, `{step}` (its key's step)
    /// and `{default}` filled in from the entry, so a help line cannot
    /// disagree with the values it states.
    pub fn fill(&self, text: &str) -> String {
        let Kind::Number { step, .. } = &self.kind else {
            return text.to_string();
        };
        let default = self.spell(self.get(&Settings::default()));
        text.replace("{min}", &format!("{}", step.min))
            .replace("{max}", &format!("{}", step.max))
            .replace("{step}", &format!("{}", step.factor))
            .replace("{default}", &default)
    }

    /// The flag's `--help` line.
    pub fn flag_help(&self) -> String {
        self.fill(self.flag.help)
    }

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
