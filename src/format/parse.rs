//! Reading automaton files (TOML) into a [`Design`].

use std::collections::{HashMap, HashSet};
use std::fmt;
use std::ops::Range;
use std::path::Path;

use indexmap::IndexMap;
use nalgebra::DMatrix;
use serde::Deserialize;
use serde::de::{self, Deserializer, SeqAccess, Visitor};
use toml::Spanned;

use super::error::{FormatError, Source};
use crate::algebra::{Affine, Env, EvalError, Expr, Num};
use crate::automaton::{Arrow, ArrowKind, Automaton, Constraint, Relation, selection};
use crate::design::{Design, Layout, Model, Origin, Variable};
use crate::names::suggest;
use crate::space::{CellKind, State};

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FileSpec {
    name: Option<String>,
    extends: Option<Spanned<String>>,
    #[serde(default)]
    description: String,
    #[serde(default, rename = "state")]
    states: Vec<StateSpec>,
    #[serde(default, rename = "arrow")]
    arrows: Vec<ArrowSpec>,
    #[serde(default)]
    constraints: IndexMap<String, Vec<Spanned<String>>>,
    #[serde(default)]
    parameters: IndexMap<String, Spanned<ParamSpec>>,
    model: Option<Spanned<ModelSpec>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct StateSpec {
    name: Spanned<String>,
    dim: Spanned<i64>,
    kind: Option<Spanned<String>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ArrowSpec {
    name: Spanned<String>,
    from: Spanned<String>,
    to: Spanned<String>,
    kind: Option<Spanned<String>>,
    matrix: Option<Spanned<MatrixSpec>>,
    select: Option<Spanned<Vec<Spanned<i64>>>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ParamSpec {
    entry: Option<Spanned<String>>,
    default: Option<Spanned<EntrySpec>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ModelSpec {
    root: Spanned<RootSpec>,
    points: Spanned<Vec<Vec<Spanned<EntrySpec>>>>,
    layout: Option<Spanned<String>>,
    step: Option<Spanned<i64>>,
    grid: Option<Spanned<Vec<i64>>>,
    #[serde(default)]
    start: IndexMap<String, Spanned<Vec<Vec<Spanned<EntrySpec>>>>>,
}

/// `root = "e"` or `root = ["even", "odd"]` (piece `i` takes the `i mod len`-th).
struct RootSpec(Vec<String>);

impl<'de> Deserialize<'de> for RootSpec {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<RootSpec, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = RootSpec;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a state name or a list of state names such as [\"even\", \"odd\"]")
            }
            fn visit_str<E: de::Error>(self, s: &str) -> Result<RootSpec, E> {
                Ok(RootSpec(vec![s.to_string()]))
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<RootSpec, A::Error> {
                let mut names = Vec::new();
                while let Some(name) = seq.next_element::<String>()? {
                    names.push(name);
                }
                Ok(RootSpec(names))
            }
        }
        d.deserialize_any(V)
    }
}

/// `matrix = "unknown"` or `matrix = [[row], [row], ...]`.
enum MatrixSpec {
    Word(String),
    Rows(Vec<Vec<Spanned<EntrySpec>>>),
}

/// A matrix entry or number: a TOML number (re-read exactly from the source
/// text) or a string holding an expression.
enum EntrySpec {
    Number,
    Text(String),
}

impl<'de> Deserialize<'de> for MatrixSpec {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<MatrixSpec, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = MatrixSpec;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("\"unknown\" or a list of rows such as [[1, 0], [0, 1]]")
            }
            fn visit_str<E: de::Error>(self, s: &str) -> Result<MatrixSpec, E> {
                Ok(MatrixSpec::Word(s.to_string()))
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<MatrixSpec, A::Error> {
                let mut rows = Vec::new();
                while let Some(row) = seq.next_element()? {
                    rows.push(row);
                }
                Ok(MatrixSpec::Rows(rows))
            }
        }
        d.deserialize_any(V)
    }
}

impl<'de> Deserialize<'de> for EntrySpec {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<EntrySpec, D::Error> {
        struct V;
        impl Visitor<'_> for V {
            type Value = EntrySpec;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a number or an expression in quotes such as \"1 - a\"")
            }
            fn visit_i64<E: de::Error>(self, _: i64) -> Result<EntrySpec, E> {
                Ok(EntrySpec::Number)
            }
            fn visit_u64<E: de::Error>(self, _: u64) -> Result<EntrySpec, E> {
                Ok(EntrySpec::Number)
            }
            fn visit_f64<E: de::Error>(self, _: f64) -> Result<EntrySpec, E> {
                Ok(EntrySpec::Number)
            }
            fn visit_str<E: de::Error>(self, s: &str) -> Result<EntrySpec, E> {
                Ok(EntrySpec::Text(s.to_string()))
            }
        }
        d.deserialize_any(V)
    }
}

/// Why a file could not be read.
#[derive(Debug, thiserror::Error)]
pub enum ReadError {
    /// The file could not be opened or read.
    #[error("{path}: {error}")]
    Io {
        /// The path.
        path: String,
        /// The underlying error.
        error: std::io::Error,
    },
    /// The file is malformed.
    #[error(transparent)]
    Format(#[from] FormatError),
}

/// Reads and validates the automaton file at `path`.
///
/// # Errors
/// [`ReadError::Io`] if it cannot be read, [`ReadError::Format`] with
/// `file:line:column` if it is malformed.
pub fn read_design(path: &Path) -> Result<Design, ReadError> {
    let text =
        std::fs::read_to_string(path).map_err(|error| ReadError::Io { path: path.display().to_string(), error })?;
    let stem = path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    Ok(parse_design(&text, &path.display().to_string(), &stem)?)
}

/// Parses and validates an automaton file held in `text`; `file` labels
/// errors and `default_name` names the automaton when the file does not.
///
/// # Errors
/// The first problem found, at its `file:line:column`.
///
/// # Example
/// ```
/// let text = r#"
/// [[state]]
/// name = "x"
/// dim = 1
/// [[arrow]]
/// name = "T"
/// from = "x"
/// to = "x"
/// matrix = [[1]]
/// "#;
/// let design = bcifs::parse_design(text, "inline.toml", "inline").unwrap();
/// assert_eq!(design.automaton.name, "inline");
/// let err = bcifs::parse_design("[[state]]\nname = \"x\"\ndim = 0\n", "bad.toml", "bad").unwrap_err();
/// assert_eq!(err.to_string(), "bad.toml:3:7: a state needs at least one control point (dim ≥ 1)");
/// ```
pub fn parse_design(text: &str, file: &str, default_name: &str) -> Result<Design, FormatError> {
    let src = Source { file, text };
    let spec: FileSpec = toml::from_str(text).map_err(|e| {
        let offset = e.span().map_or(0, |s| s.start);
        src.error(offset, e.message().trim().to_string())
    })?;
    if let Some(base) = &spec.extends {
        return extend(&src, &spec, base, default_name);
    }
    Builder { src: &src, vars: Vec::new(), var_by_name: HashMap::new() }.build(spec, default_name)
}

/// A file with `extends = "NAME"`: the shipped automaton NAME (or the file
/// NAME relative to this one) with this file's model and parameter defaults.
fn extend(src: &Source, spec: &FileSpec, base: &Spanned<String>, default_name: &str) -> Result<Design, FormatError> {
    if !spec.states.is_empty() || !spec.arrows.is_empty() || !spec.constraints.is_empty() {
        return Err(src.at(&base.span(), "a file that extends another may only add a model and parameter defaults"));
    }
    let name = base.get_ref();
    let mut design = match crate::BUILTIN_AUTOMATA.iter().find(|(n, _)| n == name) {
        Some((n, text)) => parse_design(text, &format!("automata/{n}.toml"), n)?,
        None => {
            let path = std::path::Path::new(src.file).parent().unwrap_or(std::path::Path::new(".")).join(name);
            let text = std::fs::read_to_string(&path).map_err(|e| {
                let mut err = src.at(&base.span(), format!("cannot read `{}`: {e}", path.display()));
                err.help = suggest(name, crate::BUILTIN_AUTOMATA.iter().map(|(n, _)| *n))
                    .map(|s| format!("did you mean `{s}`?"));
                err
            })?;
            parse_design(&text, &path.display().to_string(), name)?
        }
    };
    design.automaton.name = spec.name.clone().unwrap_or_else(|| default_name.to_string());
    if !spec.description.is_empty() {
        design.description = spec.description.clone();
    }
    let var_by_name = design.variables.iter().enumerate().map(|(i, v)| (v.name.clone(), i)).collect();
    let b = Builder { src, vars: design.variables.clone(), var_by_name };
    for (pname, p) in &spec.parameters {
        if p.get_ref().entry.is_some() {
            return Err(src.at(&p.span(), "a file that extends another may only give parameter defaults"));
        }
        if !design.declared.contains(pname) {
            let mut e = src.at(&p.span(), format!("`{name}` has no parameter `{pname}`"));
            e.help = suggest(pname, design.declared.iter().map(String::as_str)).map(|s| format!("did you mean `{s}`?"));
            return Err(e);
        }
        if let Some(d) = &p.get_ref().default {
            let v = b.number(d, &format!("the default of `{pname}`"))?;
            let v = v.as_constant().ok_or_else(|| src.at(&d.span(), "a default must be a constant"))?;
            design.defaults.insert(pname.clone(), v.to_f64());
        }
    }
    if let Some(m) = &spec.model {
        design.model = Some(b.model(&design.automaton, m)?);
    }
    Ok(design)
}

struct Builder<'a> {
    src: &'a Source<'a>,
    vars: Vec<Variable>,
    var_by_name: HashMap<String, usize>,
}

/// Resolves names while known matrices and equations are evaluated.
struct SymbolEnv<'a> {
    vars: &'a HashMap<String, usize>,
    automaton: Option<&'a Automaton<Affine>>,
}

impl Env<Affine> for SymbolEnv<'_> {
    fn param(&self, name: &str) -> Option<Affine> {
        self.vars.get(name).map(|v| Affine::var(*v))
    }
    fn entry(&self, arrow: &str, row: usize, col: usize) -> Option<Affine> {
        let a = self.automaton?;
        let m = &a.arrow(a.arrow_id(arrow)?).matrix;
        (row < m.nrows() && col < m.ncols()).then(|| m[(row, col)].clone())
    }
}

fn string_offset(span: &Range<usize>, inner: usize) -> usize {
    span.start + 1 + inner
}

impl Builder<'_> {
    fn with_help(&self, mut e: FormatError, name: &str, candidates: Vec<&str>) -> FormatError {
        e.help = suggest(name, candidates).map(|s| format!("did you mean `{s}`?"));
        e
    }

    fn state_ref(
        &self,
        a: &Automaton<Affine>,
        name: &Spanned<String>,
    ) -> Result<petgraph::stable_graph::NodeIndex, FormatError> {
        a.state_id(name.get_ref()).ok_or_else(|| {
            let e = self.src.at(&name.span(), format!("no state named `{}`", name.get_ref()));
            self.with_help(e, name.get_ref(), a.states().map(|(_, s)| s.name.as_str()).collect())
        })
    }

    fn new_var(&mut self, name: String, named: bool, origin: Origin) -> usize {
        let id = self.vars.len();
        self.var_by_name.insert(name.clone(), id);
        self.vars.push(Variable { name, named, origin });
        id
    }

    fn eval_error(&self, span: &Range<usize>, e: EvalError, what: &str) -> FormatError {
        match e {
            EvalError::UnknownParam(name, off) => {
                let err = self.src.error(string_offset(span, off), format!("unknown parameter `{name}` in {what}"));
                let names: Vec<&str> = self.var_by_name.keys().map(String::as_str).collect();
                let mut err = self.with_help(err, &name, names);
                if err.help.is_none() {
                    err.help = Some("declare it in [parameters]".into());
                }
                err
            }
            EvalError::UnknownEntry { arrow, row, col, offset } => self.src.error(
                string_offset(span, offset),
                format!("{what} refers to {arrow}[{row}][{col}], which does not exist"),
            ),
            other => self.src.at(span, format!("{what}: {other}")),
        }
    }

    fn number(&self, spec: &Spanned<EntrySpec>, what: &str) -> Result<Affine, FormatError> {
        let span = spec.span();
        match spec.get_ref() {
            EntrySpec::Number => {
                let raw: String = self.src.text[span.clone()].chars().filter(|c| *c != '_').collect();
                let raw = raw.trim_start_matches('+');
                let (neg, digits) = match raw.strip_prefix('-') {
                    Some(d) => (true, d),
                    None => (false, raw),
                };
                let n = Num::parse_decimal(digits).ok_or_else(|| {
                    self.src.at(&span, format!("`{raw}` is not a decimal number; write it as a quoted expression"))
                })?;
                Ok(Affine::constant(if neg { n.neg() } else { n }))
            }
            EntrySpec::Text(text) => {
                let expr = Expr::parse(text)
                    .map_err(|e| self.src.error(string_offset(&span, e.offset), format!("in {what}: {}", e.message)))?;
                if let Some((arrow, row, col, off)) = expr.entries().first() {
                    return Err(self.src.error(
                        string_offset(&span, *off),
                        format!("{what} cannot refer to the matrix entry {arrow}[{row}][{col}]; use a parameter"),
                    ));
                }
                let env = SymbolEnv { vars: &self.var_by_name, automaton: None };
                expr.eval(&env).map_err(|e| self.eval_error(&span, e, what))
            }
        }
    }

    fn build(mut self, spec: FileSpec, default_name: &str) -> Result<Design, FormatError> {
        let src = self.src;
        let mut a: Automaton<Affine> = Automaton::new(spec.name.clone().unwrap_or_else(|| default_name.to_string()));
        if spec.states.is_empty() {
            return Err(src.error(0, "the file declares no state: expected at least one [[state]] table"));
        }
        for s in &spec.states {
            let dim = *s.dim.get_ref();
            if dim < 1 {
                return Err(src.at(&s.dim.span(), "a state needs at least one control point (dim ≥ 1)"));
            }
            let kind = match &s.kind {
                None => CellKind::Free,
                Some(k) => k.get_ref().parse().map_err(|()| {
                    let e = src.at(
                        &k.span(),
                        format!("unknown cell kind `{}`: expected vertex, edge, face or free", k.get_ref()),
                    );
                    self.with_help(e, k.get_ref(), CellKind::ALL.iter().map(|k| k.keyword()).collect())
                })?,
            };
            a.add_state(State::new(s.name.get_ref().clone(), dim as usize, kind)).map_err(|_| {
                src.at(&s.name.span(), format!("a state named `{}` is declared twice", s.name.get_ref()))
            })?;
        }

        // Parameters that name entries of unknown matrices, and plain parameters.
        let mut named_entries: HashMap<(String, usize, usize), (String, Range<usize>)> = HashMap::new();
        for (name, p) in &spec.parameters {
            if let Some(entry) = &p.get_ref().entry {
                let span = entry.span();
                match Expr::parse(entry.get_ref()) {
                    Ok(Expr::Entry { arrow, row, col, .. }) => {
                        if let Some((other, _)) =
                            named_entries.insert((arrow.clone(), row, col), (name.clone(), span.clone()))
                        {
                            return Err(src.at(&span, format!("{arrow}[{row}][{col}] is already named `{other}`")));
                        }
                    }
                    _ => {
                        return Err(src.at(
                            &span,
                            format!(
                                "`{}` is not a matrix entry: expected ARROW[ROW][COL], such as \"T0[1][0]\"",
                                entry.get_ref()
                            ),
                        ));
                    }
                }
            } else {
                self.new_var(name.clone(), true, Origin::Parameter);
            }
        }

        // Variables of unknown matrices first, so that known matrices may use their names.
        let mut seen_arrows = HashSet::new();
        let mut unknown_base: HashMap<String, usize> = HashMap::new();
        for arrow in &spec.arrows {
            let name = arrow.name.get_ref();
            if !seen_arrows.insert(name.clone()) {
                return Err(src.at(&arrow.name.span(), format!("an arrow named `{name}` is declared twice")));
            }
            if let Some(m) = &arrow.matrix
                && let MatrixSpec::Word(w) = m.get_ref()
            {
                {
                    if w != "unknown" {
                        return Err(
                            src.at(&m.span(), format!("`{w}` is not a matrix: expected \"unknown\" or a list of rows"))
                        );
                    }
                    let rows = a.state(self.state_ref(&a, &arrow.from)?).dim;
                    let cols = a.state(self.state_ref(&a, &arrow.to)?).dim;
                    unknown_base.insert(name.clone(), self.vars.len());
                    for r in 0..rows {
                        for c in 0..cols {
                            match named_entries.remove(&(name.clone(), r, c)) {
                                Some((pname, _)) => {
                                    self.new_var(pname, true, Origin::Entry { arrow: name.clone(), row: r, col: c })
                                }
                                None => self.new_var(
                                    format!("{name}_{r}_{c}"),
                                    false,
                                    Origin::Entry { arrow: name.clone(), row: r, col: c },
                                ),
                            };
                        }
                    }
                }
            }
        }
        if let Some(((arrow, row, col), (_, span))) = named_entries.iter().min_by_key(|(_, (_, s))| s.start) {
            let mut e = src.at(span, format!("{arrow}[{row}][{col}] is not an entry of an unknown matrix"));
            let unknown: Vec<&str> = spec
                .arrows
                .iter()
                .filter(|x| matches!(x.matrix.as_ref().map(|m| m.get_ref()), Some(MatrixSpec::Word(_))))
                .map(|x| x.name.get_ref().as_str())
                .collect();
            e.help = suggest(arrow, unknown).map(|s| format!("did you mean `{s}`?"));
            return Err(e);
        }

        for arrow in &spec.arrows {
            let name = arrow.name.get_ref();
            let from = self.state_ref(&a, &arrow.from)?;
            let to = self.state_ref(&a, &arrow.to)?;
            let (rows, cols) = (a.state(from).dim, a.state(to).dim);
            let kind = match &arrow.kind {
                None => ArrowKind::Subdivision,
                Some(k) => match k.get_ref().as_str() {
                    "subdivision" => ArrowKind::Subdivision,
                    "boundary" => ArrowKind::Boundary,
                    other => {
                        let e = src
                            .at(&k.span(), format!("unknown arrow kind `{other}`: expected subdivision or boundary"));
                        return Err(self.with_help(e, other, vec!["subdivision", "boundary"]));
                    }
                },
            };
            let matrix = match (&arrow.matrix, &arrow.select) {
                (Some(_), Some(s)) => {
                    return Err(src.at(&s.span(), format!("arrow `{name}` has both `matrix` and `select`: give one")));
                }
                (None, None) => {
                    return Err(src.at(
                        &arrow.name.span(),
                        format!("arrow `{name}` needs `matrix = [[...]]`, `matrix = \"unknown\"` or `select = [...]`"),
                    ));
                }
                (None, Some(sel)) => {
                    let mut picks = Vec::new();
                    for i in sel.get_ref() {
                        let v = *i.get_ref();
                        if v < 0 || v as usize >= rows {
                            return Err(src.at(
                                &i.span(),
                                format!(
                                    "index {v} is out of range: `{}` has dim {rows}, so indices go from 0 to {}",
                                    a.state(from).name,
                                    rows - 1
                                ),
                            ));
                        }
                        if picks.contains(&(v as usize)) {
                            return Err(src.at(
                                &i.span(),
                                format!("index {v} is selected twice: a selection must be an embedding"),
                            ));
                        }
                        picks.push(v as usize);
                    }
                    if picks.len() != cols {
                        return Err(src.at(
                            &sel.span(),
                            format!(
                                "`{}` has dim {cols}, so `select` needs {cols} indices, not {}",
                                a.state(to).name,
                                picks.len()
                            ),
                        ));
                    }
                    selection(rows, &picks)
                }
                (Some(m), None) => match m.get_ref() {
                    MatrixSpec::Word(_) => {
                        let base = unknown_base[name];
                        DMatrix::from_fn(rows, cols, |r, c| Affine::var(base + r * cols + c))
                    }
                    MatrixSpec::Rows(data) => {
                        if data.len() != rows || data.iter().any(|r| r.len() != cols) {
                            let got_cols = data.iter().map(Vec::len).max().unwrap_or(0);
                            return Err(src.at(&m.span(), format!(
                                "arrow `{name}` goes from `{}` (dim {rows}) to `{}` (dim {cols}), so its matrix must be {rows}×{cols} ({rows} rows of {cols}), not {} rows of up to {got_cols}",
                                a.state(from).name, a.state(to).name, data.len()
                            )));
                        }
                        let mut entries = Vec::with_capacity(rows * cols);
                        for (r, row) in data.iter().enumerate() {
                            for (c, e) in row.iter().enumerate() {
                                entries.push(self.number(e, &format!("entry [{r}][{c}] of `{name}`"))?);
                            }
                        }
                        DMatrix::from_row_iterator(rows, cols, entries)
                    }
                },
            };
            a.add_arrow(from, to, Arrow { name: name.clone(), kind, matrix })
                .map_err(|e| src.at(&arrow.name.span(), e.to_string()))?;
        }

        for (group, equations) in &spec.constraints {
            for eq in equations {
                let c = self.constraint(&a, group, eq)?;
                a.add_constraint(c).map_err(|e| src.at(&eq.span(), e.to_string()))?;
            }
        }

        let mut defaults = HashMap::new();
        for (name, p) in &spec.parameters {
            if let Some(d) = &p.get_ref().default {
                let value = self.number(d, &format!("the default of `{name}`"))?;
                let value = value.as_constant().ok_or_else(|| src.at(&d.span(), "a default must be a constant"))?;
                defaults.insert(name.clone(), value.to_f64());
            }
        }

        let model = match &spec.model {
            Some(m) => Some(self.model(&a, m)?),
            None => None,
        };
        let declared = spec.parameters.keys().cloned().collect();
        Ok(Design { automaton: a, variables: self.vars, defaults, declared, model, description: spec.description })
    }

    fn constraint(&self, a: &Automaton<Affine>, group: &str, eq: &Spanned<String>) -> Result<Constraint, FormatError> {
        let src = self.src;
        let span = eq.span();
        let text = eq.get_ref();
        let Some(eq_at) = text.find('=') else {
            return Err(src.at(&span, format!("`{text}` is not an equation: expected LEFT = RIGHT")));
        };
        if text[eq_at + 1..].contains('=') {
            return Err(src.error(
                string_offset(&span, eq_at + 1 + text[eq_at + 1..].find('=').unwrap_or(0)),
                "an equation has exactly one `=`",
            ));
        }
        let sides = [(&text[..eq_at], 0), (&text[eq_at + 1..], eq_at + 1)];
        let relation = if text.contains('[') {
            let mut exprs = Vec::new();
            for (side, off) in sides {
                let e = Expr::parse(side).map_err(|e| src.error(string_offset(&span, off + e.offset), e.message))?;
                for (arrow, row, col, o) in e.entries() {
                    let Some(id) = a.arrow_id(arrow) else {
                        let err = src.error(string_offset(&span, off + o), format!("no arrow named `{arrow}`"));
                        return Err(self.with_help(err, arrow, a.arrows().map(|(_, x)| x.name.as_str()).collect()));
                    };
                    let m = &a.arrow(id).matrix;
                    if row >= m.nrows() || col >= m.ncols() {
                        return Err(src.error(
                            string_offset(&span, off + o),
                            format!(
                                "`{arrow}` is {}×{}, so {arrow}[{row}][{col}] is out of range",
                                m.nrows(),
                                m.ncols()
                            ),
                        ));
                    }
                }
                for (name, o) in e.params() {
                    if !self.var_by_name.contains_key(name) {
                        let err = src.error(string_offset(&span, off + o), format!("unknown parameter `{name}`"));
                        return Err(self.with_help(err, name, self.var_by_name.keys().map(String::as_str).collect()));
                    }
                }
                exprs.push(e);
            }
            let rhs = exprs.pop().expect("two sides");
            let lhs = exprs.pop().expect("two sides");
            Relation::Entries { lhs, rhs }
        } else {
            let mut paths = Vec::new();
            for (side, off) in sides {
                let mut path = Vec::new();
                let mut pos = 0;
                for token in side.split(|c: char| c.is_whitespace() || c == '*' || c == '·') {
                    let start = pos;
                    pos += token.len() + 1;
                    if token.is_empty() {
                        continue;
                    }
                    let token_off = string_offset(&span, off + side[..start].len());
                    match a.arrow_id(token) {
                        Some(id) => path.push(id),
                        None => {
                            let err = src.error(token_off, format!("no arrow named `{token}`"));
                            return Err(self.with_help(err, token, a.arrows().map(|(_, x)| x.name.as_str()).collect()));
                        }
                    }
                }
                if path.is_empty() {
                    return Err(src.error(string_offset(&span, off), "expected a path of arrow names, such as `T0 b1`"));
                }
                paths.push(path);
            }
            let rhs = paths.pop().expect("two sides");
            let lhs = paths.pop().expect("two sides");
            Relation::Paths { lhs, rhs }
        };
        Ok(Constraint { group: group.to_string(), text: text.trim().to_string(), relation })
    }

    fn model(&self, a: &Automaton<Affine>, m: &Spanned<ModelSpec>) -> Result<Model, FormatError> {
        let src = self.src;
        let spec = m.get_ref();
        let root_names = &spec.root.get_ref().0;
        if root_names.is_empty() {
            return Err(src.at(&spec.root.span(), "expected at least one root state"));
        }
        let roots = root_names
            .iter()
            .map(|n| self.state_ref(a, &Spanned::new(spec.root.span(), n.clone())))
            .collect::<Result<Vec<_>, _>>()?;
        let root = roots[0];
        let mut points = Vec::new();
        for row in spec.points.get_ref() {
            let mut p = Vec::new();
            for x in row {
                let v = self.number(x, "a control point coordinate")?;
                let v =
                    v.as_constant().ok_or_else(|| src.at(&x.span(), "control point coordinates must be constants"))?;
                p.push(v.to_f64());
            }
            points.push(p);
        }
        let d = points.first().map_or(0, Vec::len);
        if !(2..=3).contains(&d) || points.iter().any(|p| p.len() != d) {
            return Err(src.at(&spec.points.span(), "control points must all have 2 or all have 3 coordinates"));
        }
        let layout = match &spec.layout {
            None => Layout::Single,
            Some(l) => *Layout::ALL.iter().find(|x| x.keyword() == l.get_ref()).ok_or_else(|| {
                let e = src.at(
                    &l.span(),
                    format!(
                        "unknown layout `{}`: expected single, open, closed, grid, torus, frames, closed-frames or union",
                        l.get_ref()
                    ),
                );
                self.with_help(e, l.get_ref(), Layout::ALL.iter().map(|x| x.keyword()).collect())
            })?,
        };
        let step = match &spec.step {
            Some(s) if *s.get_ref() < 1 => {
                return Err(src.at(&s.span(), "the step must be at least 1"));
            }
            Some(s) => Some(*s.get_ref() as usize),
            None => None,
        };
        let grid = match &spec.grid {
            Some(g) if g.get_ref().len() != 2 || g.get_ref().iter().any(|x| *x < 1) => {
                return Err(src.at(&g.span(), "expected grid = [ROWS, COLS] with positive sizes"));
            }
            Some(g) => Some((g.get_ref()[0] as usize, g.get_ref()[1] as usize)),
            None => None,
        };
        let dim = a.state(root).dim;
        if layout != Layout::Union
            && let Some(other) = roots.iter().find(|r| a.state(**r).dim != dim)
        {
            return Err(src.at(
                &m.span(),
                format!(
                    "the roots of this layout must have the same dimension: `{}` has {dim}, `{}` has {}",
                    a.state(root).name,
                    a.state(*other).name,
                    a.state(*other).dim
                ),
            ));
        }
        let mut start = Vec::new();
        for (state, pts) in &spec.start {
            let Some(id) = a.state_id(state) else {
                let e = src.at(&pts.span(), format!("no state named `{state}` for a start set"));
                return Err(self.with_help(e, state, a.states().map(|(_, s)| s.name.as_str()).collect()));
            };
            let n = a.state(id).dim;
            let mut set = Vec::new();
            for row in pts.get_ref() {
                if row.len() != n {
                    return Err(src.at(
                        &pts.span(),
                        format!("start points of `{state}` are barycentric: {n} coordinates each, not {}", row.len()),
                    ));
                }
                let mut p = Vec::new();
                for x in row {
                    let v = self.number(x, "a start point coordinate")?;
                    p.push(
                        v.as_constant().ok_or_else(|| src.at(&x.span(), "start points must be constants"))?.to_f64(),
                    );
                }
                let sum: f64 = p.iter().sum();
                if (sum - 1.0).abs() > 1e-9 {
                    return Err(src.at(
                        &pts.span(),
                        format!("start points are barycentric: coordinates must sum to 1 (one sums to {sum})"),
                    ));
                }
                set.push(p);
            }
            start.push((state.clone(), set));
        }
        let needed = match layout {
            Layout::Frames | Layout::ClosedFrames => {
                if d != 2 || dim != 3 {
                    return Err(
                        src.at(&m.span(), "frame layouts need 2D points and a root of dim 3 (segment and frame point)")
                    );
                }
                2
            }
            Layout::Single | Layout::Open | Layout::Closed => dim,
            Layout::Union => {
                let total: usize = roots.iter().map(|r| a.state(*r).dim).sum();
                if points.len() % total != 0 {
                    return Err(src.at(
                        &spec.points.span(),
                        format!("a union of the roots takes {total} control points per round, not {}", points.len()),
                    ));
                }
                total
            }
            Layout::Grid | Layout::Torus => {
                let (r, c) = grid.ok_or_else(|| src.at(&m.span(), "grid layouts need grid = [ROWS, COLS]"))?;
                if r * c != points.len() {
                    return Err(src.at(
                        &spec.points.span(),
                        format!("grid = [{r}, {c}] needs {} control points, not {}", r * c, points.len()),
                    ));
                }
                dim
            }
        };
        if points.len() < needed {
            return Err(src.at(
                &spec.points.span(),
                format!("this layout needs at least {needed} control points, not {}", points.len()),
            ));
        }
        let roots = root_names.clone();
        Ok(Model { roots, points, layout, step, grid, start })
    }
}
