//! The command line's option flags, made from the library's one
//! description of them ([`bcifs::render::KEYS`]): the flag, its help, its
//! default and its placeholder are the library's; the values are passed
//! through as text and checked by [`bcifs::render::Options::set`].

use std::marker::PhantomData;

use bcifs::render::{KEYS, Key, Kind, OptionError, Options, Value};
use clap::parser::ValueSource;
use clap::{Arg, ArgAction, ArgMatches, Args, Command, FromArgMatches};

/// Which keys a command takes.
pub trait KeySet {
    /// Their names; empty: every key.
    const NAMES: &'static [&'static str];
}

/// Every key: `bcifs render`.
pub struct AllKeys;
impl KeySet for AllKeys {
    const NAMES: &'static [&'static str] = &[];
}

/// The keys of a picture: size, view, memory, transparency.
pub struct PictureKeys;
impl KeySet for PictureKeys {
    const NAMES: &'static [&'static str] = &["size", "view", "memory_mib", "transparent"];
}

/// The keys of a polygon mesh's render: a picture's, the file's style and size.
pub struct MeshKeys;
impl KeySet for MeshKeys {
    const NAMES: &'static [&'static str] =
        &["size", "view", "memory_mib", "transparent", "ascii", "up", "precision", "max_output_gib", "threads"];
}

/// The option flags a command was given, as text for [`Options::set`].
pub struct KeyArgs<S: KeySet> {
    /// Each key given on the command line (defaults left out), in the description's order.
    pub given: Vec<(&'static str, Value)>,
    set: PhantomData<S>,
}

impl<S: KeySet> KeyArgs<S> {
    fn keys() -> impl Iterator<Item = &'static Key> {
        KEYS.iter().filter(|k| S::NAMES.is_empty() || S::NAMES.contains(&k.name))
    }

    /// Options with these keys over `options`, checked by the library.
    ///
    /// # Errors
    /// The library's refusal, the key spelled as its flag.
    pub fn apply(&self, options: &mut Options) -> anyhow::Result<()> {
        options.set_values(self.given.iter().cloned()).map_err(|e| anyhow::anyhow!(spelled(&e)))
    }

    /// Options with these keys over the defaults.
    ///
    /// # Errors
    /// As [`KeyArgs::apply`].
    pub fn options(&self) -> anyhow::Result<Options> {
        let mut options = Options::default();
        self.apply(&mut options)?;
        Ok(options)
    }

    /// Whether `name` was given.
    pub fn has(&self, name: &str) -> bool {
        self.given.iter().any(|(k, _)| *k == name)
    }
}

/// A library refusal with its key spelled as the flag (`--depth`).
pub fn spelled(e: &OptionError) -> String {
    e.spelled(|k| format!("--{}", k.flag))
}

/// The clap argument of a key.
fn arg(key: &'static Key) -> Arg {
    let mut arg = Arg::new(key.name).long(key.flag).help(key.help.strip_suffix('.').unwrap_or(key.help));
    arg = match key.kind {
        Kind::Switch => arg.action(ArgAction::SetTrue),
        Kind::Names | Kind::Values => arg.action(ArgAction::Append),
        _ => arg.action(ArgAction::Set),
    };
    if key.kind != Kind::Switch {
        // clap's derive shows a value as its field's name in capitals: so do these (made once per run).
        let placeholder: &'static str = match key.value_name {
            "" => Box::leak(key.name.to_uppercase().into_boxed_str()),
            shown => shown,
        };
        arg = arg.value_name(placeholder).allow_hyphen_values(true);
    }
    if let Kind::Choice(words) = key.kind {
        arg = arg.value_parser(clap::builder::PossibleValuesParser::new(words));
    }
    if let Some(default) = key.default {
        arg = arg.default_value(default);
    }
    if key.name == "colour" {
        arg = arg.alias("colour-by");
    }
    arg
}

impl<S: KeySet> Args for KeyArgs<S> {
    fn augment_args(cmd: Command) -> Command {
        Self::keys().fold(cmd, |cmd, key| cmd.arg(arg(key)))
    }

    fn augment_args_for_update(cmd: Command) -> Command {
        Self::augment_args(cmd)
    }
}

impl<S: KeySet> FromArgMatches for KeyArgs<S> {
    fn from_arg_matches(matches: &ArgMatches) -> Result<Self, clap::Error> {
        let mut given = Vec::new();
        for key in Self::keys() {
            if matches.value_source(key.name) != Some(ValueSource::CommandLine) {
                continue;
            }
            let value = match key.kind {
                Kind::Switch => Value::Switch(matches.get_flag(key.name)),
                Kind::Names | Kind::Values => {
                    Value::Texts(matches.get_many::<String>(key.name).into_iter().flatten().cloned().collect())
                }
                _ => Value::Text(matches.get_one::<String>(key.name).cloned().unwrap_or_default()),
            };
            given.push((key.name, value));
        }
        Ok(KeyArgs { given, set: PhantomData })
    }

    fn update_from_arg_matches(&mut self, matches: &ArgMatches) -> Result<(), clap::Error> {
        *self = Self::from_arg_matches(matches)?;
        Ok(())
    }
}
