//! Writing any design back as a commented automaton file.

use std::fmt::Write as _;

/// A constraint group as written: its name, its comment, and its equations with theirs.
pub(crate) type Group<'a> = (&'a str, String, Vec<(String, String)>);

use crate::automaton::ArrowKind;
use crate::design::{Design, Matrix, Value};
use crate::space::CellKind;

/// The design as an automaton file, with its comments ([`Design::docs`]):
/// reading the text back gives the same design (same family, same letters,
/// exact entries such as `1/2 - sqrt(3)/6`).
///
/// ```
/// let design = bcifs::builtin_design("corner_cutting").unwrap();
/// let text = bcifs::write_design(&design);
/// let again = bcifs::parse_design(&text, "again.toml", "again").unwrap();
/// assert_eq!(bcifs::solve(&again).unwrap().matrices_text(), bcifs::solve(&design).unwrap().matrices_text());
/// ```
pub fn write_design(design: &Design) -> String {
    let spec = design.to_builder();
    let docs = design.docs();
    let doc = |map: &std::collections::HashMap<String, String>, name: &str| map.get(name).cloned().unwrap_or_default();
    let mut w = TomlWriter::new();
    w.comment(&docs.header).header(design.name(), design.description());
    for (name, dim, kind, patch) in spec.state_items() {
        w.state(name, dim, kind, patch, &doc(&docs.states, name));
    }
    for (name, from, to, kind, matrix) in spec.arrow_items() {
        let comment = doc(&docs.arrows, name);
        match matrix {
            Matrix::Unknown => w.arrow_unknown(name, from, to, kind, &comment),
            Matrix::Select(picks) => w.arrow_select(name, from, to, kind, picks, &comment),
            Matrix::Rows(rows) => {
                let rows: Vec<Vec<String>> = rows.iter().map(|r| r.iter().map(Value::to_string).collect()).collect();
                w.arrow_rows(name, from, to, kind, &rows, &comment)
            }
        };
    }
    let mut groups: Vec<Group<'_>> = Vec::new();
    for (group, text) in spec.equation_items() {
        let line = (text.to_string(), doc(&docs.equations, text));
        match groups.iter_mut().find(|(g, _, _)| *g == group) {
            Some((_, _, list)) => list.push(line),
            None => groups.push((group, doc(&docs.groups, group), vec![line])),
        }
    }
    if !groups.is_empty() {
        w.constraints(&groups);
    }
    let params: Vec<(String, Option<String>, Option<String>)> = spec
        .parameter_items()
        .map(|(name, entry, default)| (name.to_string(), entry.map(str::to_string), default.map(Value::to_string)))
        .collect();
    if !params.is_empty() {
        w.parameters(&params, &docs.parameters);
    }
    if let Some(m) = design.model() {
        let mut extra = String::new();
        if let Some((r, c)) = m.grid {
            let _ = writeln!(extra, "grid = [{r}, {c}]");
        }
        if let Some(s) = m.step {
            let _ = writeln!(extra, "step = {s}");
        }
        if m.y_up {
            let _ = writeln!(extra, "up = \"y\"  # the points are Y-up (a mesh file's axes)");
        }
        if !m.net.is_empty() {
            let faces: Vec<String> = m.net.iter().map(|f| format!("{f:?}")).collect();
            let _ = writeln!(
                extra,
                "net = {}",
                if faces.len() <= 8 { format!("[{}]", faces.join(", ")) } else { lines(&faces, 8) }
            );
        }
        if !m.patches.is_empty() {
            let lists: Vec<String> = m.patches.iter().map(|f| format!("  {f:?},")).collect();
            let _ = writeln!(extra, "patches = [\n{}\n]", lists.join("\n"));
        }
        let roots: Vec<&str> = m.roots.iter().map(String::as_str).collect();
        w.model(&roots, &m.points, m.layout.keyword(), extra.trim_end(), &docs.model);
        if !m.start.is_empty() {
            w.out.push_str("\n[model.start]\n");
            for (state, set) in &m.start {
                let rows: Vec<String> = set.iter().map(|p| format!("[{}]", floats(p))).collect();
                let _ = writeln!(w.out, "{} = [{}]", quote(state), rows.join(", "));
            }
        }
        if !m.start_faces.is_empty() {
            w.out.push_str("\n[model.start_faces]\n");
            for (state, faces) in &m.start_faces {
                let lists: Vec<String> = faces.iter().map(|f| format!("{f:?}")).collect();
                let _ = writeln!(w.out, "{} = {}", quote(state), lines(&lists, 8));
            }
        }
    }
    w.finish()
}

/// A TOML array of `items` over several lines, `per_line` to a line.
fn lines(items: &[String], per_line: usize) -> String {
    let rows: Vec<String> = items.chunks(per_line).map(|c| format!("  {},", c.join(", "))).collect();
    format!("[\n{}\n]", rows.join("\n"))
}

fn floats(p: &[f64]) -> String {
    // `x + 0.0` writes -0.0 as 0.0 (what it reads back as).
    p.iter().map(|x| format!("{:?}", x + 0.0)).collect::<Vec<_>>().join(", ")
}

/// Builds the text of an automaton file in the order a reader expects:
/// header, states, arrows, constraint groups, parameters, model.
///
/// The caller emits sections in that order (TOML requires top-level keys
/// before tables); every item can carry a comment.
#[derive(Default)]
pub(crate) struct TomlWriter {
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

    /// A `[[state]]` table (its `patch` when it has one).
    pub fn state(
        &mut self,
        name: &str,
        dim: usize,
        kind: CellKind,
        patch: Option<crate::space::Patch>,
        comment: &str,
    ) -> &mut Self {
        self.blank().comment(comment);
        let _ = writeln!(self.out, "[[state]]\nname = {}\ndim = {dim}\nkind = {}", quote(name), quote(kind.keyword()));
        if let Some(p) = patch {
            let _ = writeln!(self.out, "patch = {}", quote(p.keyword()));
        }
        self
    }

    fn arrow_head(&mut self, name: &str, from: &str, to: &str, kind: ArrowKind, comment: &str) {
        self.blank().comment(comment);
        let _ = writeln!(self.out, "[[arrow]]\nname = {}\nfrom = {}\nto = {}", quote(name), quote(from), quote(to));
        if kind != ArrowKind::Subdivision {
            let _ = writeln!(self.out, "kind = {}", quote(kind.keyword()));
        }
    }

    /// An arrow whose matrix is unknown.
    pub fn arrow_unknown(&mut self, name: &str, from: &str, to: &str, kind: ArrowKind, comment: &str) -> &mut Self {
        self.arrow_head(name, from, to, kind, comment);
        self.out.push_str("matrix = \"unknown\"\n");
        self
    }

    /// An arrow given by a selection.
    pub fn arrow_select(
        &mut self,
        name: &str,
        from: &str,
        to: &str,
        kind: ArrowKind,
        select: &[usize],
        comment: &str,
    ) -> &mut Self {
        self.arrow_head(name, from, to, kind, comment);
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
    /// An equation may have its own comment, written above it.
    pub fn constraints(&mut self, groups: &[Group<'_>]) -> &mut Self {
        self.blank().out.push_str("[constraints]\n");
        for (name, comment, equations) in groups {
            self.comment(comment);
            let _ = writeln!(self.out, "{name} = [");
            for (e, why) in equations {
                for line in why.lines() {
                    let _ = writeln!(self.out, "  # {line}");
                }
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
            few if few.len() <= 8 => format!("[{}]", few.iter().map(|r| quote(r)).collect::<Vec<_>>().join(", ")),
            many => lines(&many.iter().map(|r| quote(r)).collect::<Vec<_>>(), 8),
        };
        let _ = writeln!(self.out, "[model]\nroot = {root}\nlayout = {}", quote(layout));
        if !extra.is_empty() {
            let _ = writeln!(self.out, "{extra}");
        }
        self.out.push_str("points = [\n");
        for p in points {
            let _ = writeln!(self.out, "  [{}],", floats(p));
        }
        self.out.push_str("]\n");
        self
    }

    /// The text.
    pub fn finish(&mut self) -> String {
        std::mem::take(&mut self.out)
    }
}
