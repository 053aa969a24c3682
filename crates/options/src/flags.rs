//! The options' flags, made from the table with clap's builder: each
//! entry gives `--name`, its help, its values and its default, so a new
//! option needs no field here. `cli.rs` flattens [`OptionArgs`] into the
//! view's flags.

use clap::builder::PossibleValuesParser;
use clap::parser::ValueSource;
use clap::{Arg, ArgAction, ArgMatches, Args, Command, FromArgMatches};

use super::{Form, Kind, OPTIONS, Opt, OptId, Value};
use relief_core::settings::Settings;

/// The settings the table's flags describe, and which flags were given.
#[derive(Clone, Debug, PartialEq)]
pub struct OptionArgs {
    /// The defaults with the given flags applied.
    pub settings: Settings,
    /// The options whose flag is on the command line.
    pub given: Vec<OptId>,
}

impl OptionArgs {
    /// Whether the flag of option `id` was given.
    pub fn given(&self, id: OptId) -> bool {
        self.given.contains(&id)
    }
}

/// The flag of one entry.
fn arg(opt: &'static Opt) -> Arg {
    let arg = Arg::new(opt.name)
        .long(opt.flag_name())
        .help(opt.flag_help());
    if opt.flag.form == Form::Switch {
        return arg.action(ArgAction::SetTrue);
    }
    let value_name = opt
        .flag
        .value_name
        .map_or_else(|| opt.name.to_uppercase(), String::from);
    let arg = arg.action(ArgAction::Set).value_name(value_name);
    let arg = match &opt.kind {
        Kind::Toggle => arg.value_parser(PossibleValuesParser::new(["on", "off"])),
        Kind::Choice { values } => arg.value_parser(PossibleValuesParser::new(values())),
        Kind::Number {
            parse, negative, ..
        } => arg.value_parser(*parse).allow_hyphen_values(*negative),
    };
    match opt.flag.form {
        Form::Value => arg.default_value(opt.spell(opt.get(&Settings::default()))),
        Form::Optional | Form::Switch => arg,
    }
}

/// The value the command line gives `opt` (`None`: left out and no default).
fn value_of(opt: &Opt, m: &ArgMatches) -> Option<Value> {
    if opt.flag.form == Form::Switch {
        return Some(Value::Bool(m.get_flag(opt.name)));
    }
    match &opt.kind {
        Kind::Number { .. } => m.get_one::<f32>(opt.name).copied().map(Value::Number),
        Kind::Toggle => m
            .get_one::<String>(opt.name)
            .map(|t| Value::Bool(t == "on")),
        Kind::Choice { values } => {
            let text = m.get_one::<String>(opt.name)?;
            values()
                .iter()
                .position(|v| v.matches(text, false))
                .map(Value::Index)
        }
    }
}

impl FromArgMatches for OptionArgs {
    fn from_arg_matches(m: &ArgMatches) -> Result<Self, clap::Error> {
        let mut settings = Settings::default();
        let mut given = Vec::new();
        for opt in OPTIONS {
            if m.value_source(opt.name) == Some(ValueSource::CommandLine) {
                given.push(opt.id);
            }
            if let Some(v) = value_of(opt, m) {
                opt.set(&mut settings, v);
            }
        }
        Ok(OptionArgs { settings, given })
    }

    fn update_from_arg_matches(&mut self, m: &ArgMatches) -> Result<(), clap::Error> {
        *self = OptionArgs::from_arg_matches(m)?;
        Ok(())
    }
}

impl Args for OptionArgs {
    fn augment_args(cmd: Command) -> Command {
        cmd.args(OPTIONS.iter().map(arg))
    }

    fn augment_args_for_update(cmd: Command) -> Command {
        OptionArgs::augment_args(cmd)
    }
}
