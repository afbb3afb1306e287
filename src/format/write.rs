//! Writing automaton files, with comments, for generators.

use std::fmt::Write as _;

use crate::automaton::ArrowKind;
use crate::space::CellKind;

/// Builds the text of an automaton file in the order a reader expects:
/// header, states, arrows, constraint groups, parameters, model.
///
/// The caller emits sections in that order (TOML requires top-level keys
/// before tables); every item can carry a comment.
#[derive(Default)]
pub struct TomlWriter {
    out: String,
}

fn quote(s: &str) -> String {
    format!("\"{}\"", s.replace('\\', "\\\\").replace('"', "\\\""))
}

impl TomlWriter {
    /// An empty file.
    pub fn new() -> TomlWriter {
        TomlWriter::default()
    }

    /// `# text`, one comment line per line of `text`.
    pub fn comment(&mut self, text: &str) -> &mut Self {
        for line in text.lines() {
            if line.is_empty() {
                self.out.push_str("#\n");
            } else {
                let _ = writeln!(self.out, "# {line}");
            }
        }
        self
    }

    /// An empty line.
    pub fn blank(&mut self) -> &mut Self {
        self.out.push('\n');
        self
    }

    /// `name = ...` and `description = ...`.
    pub fn header(&mut self, name: &str, description: &str) -> &mut Self {
        let _ = writeln!(self.out, "name = {}", quote(name));
        let _ = writeln!(self.out, "description = {}", quote(description));
        self
    }

    /// A `[[state]]` table.
    pub fn state(&mut self, name: &str, dim: usize, kind: CellKind, comment: &str) -> &mut Self {
        self.blank().comment(comment);
        let _ = writeln!(self.out, "[[state]]\nname = {}\ndim = {dim}\nkind = {}", quote(name), quote(kind.keyword()));
        self
    }

    fn arrow_head(&mut self, name: &str, from: &str, to: &str, kind: ArrowKind, comment: &str) {
        self.blank().comment(comment);
        let _ = writeln!(self.out, "[[arrow]]\nname = {}\nfrom = {}\nto = {}", quote(name), quote(from), quote(to));
        if kind == ArrowKind::Boundary {
            let _ = writeln!(self.out, "kind = \"boundary\"");
        }
    }

    /// An arrow whose matrix is unknown.
    pub fn arrow_unknown(&mut self, name: &str, from: &str, to: &str, kind: ArrowKind, comment: &str) -> &mut Self {
        self.arrow_head(name, from, to, kind, comment);
        self.out.push_str("matrix = \"unknown\"\n");
        self
    }

    /// A boundary arrow given by a selection.
    pub fn arrow_select(&mut self, name: &str, from: &str, to: &str, select: &[usize], comment: &str) -> &mut Self {
        self.arrow_head(name, from, to, ArrowKind::Boundary, comment);
        let list: Vec<String> = select.iter().map(usize::to_string).collect();
        let _ = writeln!(self.out, "select = [{}]", list.join(", "));
        self
    }

    /// An arrow with a known matrix; entries are numbers or expressions.
    pub fn arrow_rows(
        &mut self,
        name: &str,
        from: &str,
        to: &str,
        kind: ArrowKind,
        rows: &[Vec<String>],
        comment: &str,
    ) -> &mut Self {
        self.arrow_head(name, from, to, kind, comment);
        self.out.push_str("matrix = [\n");
        for row in rows {
            let cells: Vec<String> =
                row.iter().map(|e| if e.parse::<f64>().is_ok() { e.clone() } else { quote(e) }).collect();
            let _ = writeln!(self.out, "  [{}],", cells.join(", "));
        }
        self.out.push_str("]\n");
        self
    }

    /// The `[constraints]` table: groups of equations, each with a comment.
    pub fn constraints(&mut self, groups: &[(&str, &str, Vec<String>)]) -> &mut Self {
        self.blank().out.push_str("[constraints]\n");
        for (name, comment, equations) in groups {
            self.comment(comment);
            let _ = writeln!(self.out, "{name} = [");
            for e in equations {
                let _ = writeln!(self.out, "  {},", quote(e));
            }
            self.out.push_str("]\n");
        }
        self
    }

    /// The `[parameters]` table: `(name, entry it names, default)`.
    pub fn parameters(&mut self, params: &[(String, Option<String>, Option<String>)], comment: &str) -> &mut Self {
        self.blank().comment(comment);
        self.out.push_str("[parameters]\n");
        for (name, entry, default) in params {
            let mut fields = Vec::new();
            if let Some(e) = entry {
                fields.push(format!("entry = {}", quote(e)));
            }
            if let Some(d) = default {
                fields.push(if d.parse::<f64>().is_ok() {
                    format!("default = {d}")
                } else {
                    format!("default = {}", quote(d))
                });
            }
            let _ = writeln!(self.out, "{name} = {{ {} }}", fields.join(", "));
        }
        self
    }

    /// A `[model]` table; several roots are taken in turn by the pieces.
    pub fn model(
        &mut self,
        roots: &[&str],
        points: &[Vec<f64>],
        layout: &str,
        extra: &str,
        comment: &str,
    ) -> &mut Self {
        self.blank().comment(comment);
        let root = match roots {
            [one] => quote(one),
            many => format!("[{}]", many.iter().map(|r| quote(r)).collect::<Vec<_>>().join(", ")),
        };
        let _ = writeln!(self.out, "[model]\nroot = {root}\nlayout = {}", quote(layout));
        if !extra.is_empty() {
            let _ = writeln!(self.out, "{extra}");
        }
        self.out.push_str("points = [\n");
        for p in points {
            let cells: Vec<String> = p.iter().map(|x| format!("{x:?}")).collect();
            let _ = writeln!(self.out, "  [{}],", cells.join(", "));
        }
        self.out.push_str("]\n");
        self
    }

    /// The text.
    pub fn finish(&mut self) -> String {
        std::mem::take(&mut self.out)
    }
}
