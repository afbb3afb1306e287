//! Errors of automaton files, with their position.

use std::fmt;
use std::ops::Range;

/// A problem in an automaton file, at `file:line:column`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FormatError {
    /// The file name as given (or `<string>`).
    pub file: String,
    /// Line, from 1.
    pub line: usize,
    /// Column, from 1, in characters.
    pub column: usize,
    /// What is wrong and what was expected.
    pub message: String,
    /// A suggestion, such as the name the user probably meant.
    pub help: Option<String>,
}

impl std::error::Error for FormatError {}

impl fmt::Display for FormatError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}:{}: {}", self.file, self.line, self.column, self.message)?;
        if let Some(help) = &self.help {
            write!(f, " ({help})")?;
        }
        Ok(())
    }
}

/// Maps byte offsets of a source text to lines and columns.
pub(crate) struct Source<'a> {
    pub file: &'a str,
    pub text: &'a str,
}

impl Source<'_> {
    /// `(line, column)` of byte `offset`, both from 1.
    pub fn position(&self, offset: usize) -> (usize, usize) {
        let offset = offset.min(self.text.len());
        let before = &self.text[..offset];
        let line = before.matches('\n').count() + 1;
        let line_start = before.rfind('\n').map_or(0, |i| i + 1);
        (line, before[line_start..].chars().count() + 1)
    }

    /// An error at byte `offset`.
    pub fn error(&self, offset: usize, message: impl Into<String>) -> FormatError {
        let (line, column) = self.position(offset);
        FormatError { file: self.file.to_string(), line, column, message: message.into(), help: None }
    }

    /// An error at the start of `span`.
    pub fn at(&self, span: &Range<usize>, message: impl Into<String>) -> FormatError {
        self.error(span.start, message)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn positions_count_lines_and_chars() {
        let s = Source { file: "f", text: "ab\ncdé\nx" };
        assert_eq!(s.position(0), (1, 1));
        assert_eq!(s.position(3), (2, 1));
        assert_eq!(s.position(8), (3, 1));
        assert_eq!(s.error(5, "m").to_string(), "f:2:3: m");
    }
}
