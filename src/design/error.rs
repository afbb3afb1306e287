//! Why a design could not be built.

use std::fmt;

use super::value::Locus;
use crate::names::suggest;

/// Why a design could not be built: where, what, and a suggestion.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct BuildError(Box<Details>);

#[derive(Clone, Debug, PartialEq, Eq)]
struct Details {
    at: Locus,
    offset: Option<usize>,
    label: String,
    message: String,
    help: Option<String>,
}

impl std::error::Error for BuildError {}

impl fmt::Display for BuildError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if !self.0.label.is_empty() {
            write!(f, "{}: ", self.0.label)?;
        }
        f.write_str(&self.0.message)?;
        if let Some(help) = &self.0.help {
            write!(f, " ({help})")?;
        }
        Ok(())
    }
}

impl BuildError {
    pub(super) fn new(at: Locus, label: String, message: impl Into<String>) -> BuildError {
        BuildError(Box::new(Details { at, offset: None, label, message: message.into(), help: None }))
    }

    /// The item at fault.
    pub fn at(&self) -> Locus {
        self.0.at
    }

    /// Byte offset inside the item's text (an expression or an equation),
    /// if the error is inside one.
    pub fn offset(&self) -> Option<usize> {
        self.0.offset
    }

    /// The item, as a person names it: ``arrow `T0` ``, ``equation `adjacency: T0 b1 = T2 b0` ``.
    pub fn label(&self) -> &str {
        &self.0.label
    }

    /// What is wrong and what was expected.
    pub fn message(&self) -> &str {
        &self.0.message
    }

    /// A suggestion, such as the name the user probably meant.
    pub fn help(&self) -> Option<&str> {
        self.0.help.as_deref()
    }

    pub(super) fn at_offset(mut self, offset: usize) -> BuildError {
        self.0.offset = Some(offset);
        self
    }

    pub(super) fn with_message(mut self, message: String) -> BuildError {
        self.0.message = message;
        self
    }

    pub(super) fn suggesting<'a>(mut self, name: &str, candidates: impl IntoIterator<Item = &'a str>) -> BuildError {
        self.0.help = suggest(name, candidates).map(|s| format!("did you mean `{s}`?"));
        self
    }

    /// The same error with `help` when it has none yet.
    pub(super) fn or_help(mut self, help: &str) -> BuildError {
        self.0.help.get_or_insert_with(|| help.to_string());
        self
    }
}
