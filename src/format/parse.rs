//! Reading automaton files (TOML) into a [`Design`].

use std::fmt;
use std::ops::Range;
use std::path::Path;

use indexmap::IndexMap;
use rayon::prelude::*;
use serde::Deserialize;
use serde::de::{self, Deserializer, SeqAccess, Visitor};
use toml::Spanned;

use super::builtin::BUILTIN_AUTOMATA;
use super::error::{FormatError, Source};
use crate::algebra::{Expr, Num};
use crate::automaton::ArrowKind;
use crate::design::{BuildError, Design, DesignBuilder, Field, Layout, Locus, Matrix, Model, Value};
use crate::names::suggest;
use crate::space::{CellKind, Patch};

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
    /// `None` when the file has no `[constraints]` (told apart from an
    /// empty one, which two pieces of a file may not both define).
    constraints: Option<IndexMap<String, Vec<Spanned<String>>>>,
    parameters: Option<IndexMap<String, Spanned<ParamSpec>>>,
    model: Option<Spanned<ModelSpec>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct StateSpec {
    name: Spanned<String>,
    dim: Spanned<i64>,
    kind: Option<Spanned<String>>,
    patch: Option<Spanned<String>>,
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
    up: Option<Spanned<String>>,
    step: Option<Spanned<i64>>,
    grid: Option<Spanned<Vec<i64>>>,
    net: Option<Spanned<Vec<Vec<i64>>>>,
    patches: Option<Spanned<Vec<Vec<i64>>>>,
    #[serde(default)]
    start: IndexMap<String, Spanned<Vec<Vec<Spanned<EntrySpec>>>>>,
    #[serde(default)]
    start_faces: IndexMap<String, Spanned<Vec<Vec<i64>>>>,
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
    let text = crate::input::read_text(path, crate::input::TEXT_FILE_LIMIT)
        .map_err(|error| ReadError::Io { path: path.display().to_string(), error })?;
    let stem = path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    Ok(parse_design(&text, &path.display().to_string(), &stem)?)
}

/// Parses and validates an automaton file held in `text`; `file` labels
/// errors and `default_name` names the automaton when the file does not.
/// The file goes through the [`DesignBuilder`], whose errors come back at
/// the `file:line:column` of the item at fault.
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
/// assert_eq!(design.name(), "inline");
/// let err = bcifs::parse_design("[[state]]\nname = \"x\"\ndim = 0\n", "bad.toml", "bad").unwrap_err();
/// assert_eq!(err.to_string(), "bad.toml:3:7: a state needs at least one control point (dim ≥ 1)");
/// ```
pub fn parse_design(text: &str, file: &str, default_name: &str) -> Result<Design, FormatError> {
    parse_in_chain(text, file, default_name, &mut Vec::new())
}

/// Files that `extends` may chain through: a longer chain is refused.
const MAX_EXTENDS: usize = 16;

/// [`parse_design`] inside a chain of `extends` (the files being read, outermost first).
fn parse_in_chain(text: &str, file: &str, default_name: &str, chain: &mut Vec<String>) -> Result<Design, FormatError> {
    let src = Source { file, text };
    let spec = match in_pieces(text) {
        Some(spec) => spec,
        None => toml::from_str(text).map_err(|e| {
            let offset = e.span().map_or(0, |s| s.start);
            src.error(offset, e.message().trim().to_string())
        })?,
    };
    let (builder, spans) = match &spec.extends {
        Some(base) => extend(&src, &spec, base, default_name, chain)?,
        None => Reader { src: &src, spans: Spans::default() }.read(&spec, default_name)?,
    };
    builder.into_design().map_err(|e| spans.locate(&src, e))
}

/// The least length of a piece of a file read in pieces (a file under
/// twice this is read whole).
const PIECE: usize = 256 << 10;

/// A long file (a mesh's generated automaton: Suzanne's is 2.2 MB, four
/// tenths of `check`'s time in reading it) read as pieces on the pool's
/// threads: cut before `[[arrow]]` lines, each piece read as TOML with the
/// text before it blanked (so that its spans are the file's), the arrays of
/// tables joined in order. `None` (read the file whole, which also reports
/// its errors) when it cannot be cut (multi-line strings), a piece does not
/// read, or the pieces would not make the file's document: a table defined
/// by two of them, or states after the first (which a static `state = [...]`
/// before them would forbid).
fn in_pieces(text: &str) -> Option<FileSpec> {
    let pieces = (text.len() / PIECE).min(rayon::current_num_threads());
    if pieces < 2 || text.contains("\"\"\"") || text.contains("'''") {
        return None;
    }
    // Line starts of `[[arrow]]` after the first (so that the first piece holds one:
    // a static `arrow = [...]` and a `[[arrow]]` do not read together).
    let heads: Vec<usize> = text
        .match_indices("\n[[arrow]]")
        .map(|(at, _)| at + 1)
        .filter(|&at| text[at + 9..].starts_with(['\n', '\r']))
        .skip(1)
        .collect();
    // The first `[[arrow]]` past each equal share of the text.
    let mut cuts = vec![0];
    for k in 1..pieces {
        let want = (text.len() * k / pieces).max(cuts[cuts.len() - 1] + 1);
        match heads.iter().find(|&&at| at >= want) {
            Some(&at) => cuts.push(at),
            None => break,
        }
    }
    if cuts.len() < 2 {
        return None;
    }
    cuts.push(text.len());
    let specs: Vec<Option<FileSpec>> = cuts
        .par_windows(2)
        .map(|w| {
            let piece = if w[0] == 0 { text[..w[1]].to_string() } else { " ".repeat(w[0]) + &text[w[0]..w[1]] };
            toml::from_str(&piece).ok()
        })
        .collect();
    let mut specs = specs.into_iter();
    let mut whole = specs.next()??;
    for spec in specs {
        let spec = spec?;
        if !spec.states.is_empty() {
            return None;
        }
        whole.arrows.extend(spec.arrows);
        once(&mut whole.constraints, spec.constraints)?;
        once(&mut whole.parameters, spec.parameters)?;
        once(&mut whole.model, spec.model)?;
    }
    Some(whole)
}

/// Keeps the one piece's table, `None` when two pieces define it.
fn once<T>(whole: &mut Option<T>, piece: Option<T>) -> Option<()> {
    if piece.is_some() {
        if whole.is_some() {
            return None;
        }
        *whole = piece;
    }
    Some(())
}

/// Where the items given to the builder are in the file.
#[derive(Default)]
struct Spans {
    states: Vec<StateSpans>,
    arrows: Vec<ArrowSpans>,
    equations: Vec<Range<usize>>,
    params: Vec<ParamSpans>,
    model: ModelSpans,
}

struct StateSpans {
    name: Range<usize>,
    dim: Range<usize>,
}

struct ArrowSpans {
    name: Range<usize>,
    from: Range<usize>,
    to: Range<usize>,
    matrix: Range<usize>,
    select: Vec<Range<usize>>,
    entries: Vec<Vec<Range<usize>>>,
}

#[derive(Clone, Default)]
struct ParamSpans {
    whole: Range<usize>,
    entry: Option<Range<usize>>,
    default: Option<Range<usize>>,
}

#[derive(Default)]
struct ModelSpans {
    whole: Range<usize>,
    root: Range<usize>,
    points: Range<usize>,
    step: Option<Range<usize>>,
    grid: Option<Range<usize>>,
    net: Option<Range<usize>>,
    patches: Option<Range<usize>>,
    starts: Vec<Range<usize>>,
    start_faces: Vec<Range<usize>>,
}

impl Spans {
    /// The span of the item at fault, and whether it is a quoted string
    /// (so that an offset inside the text is counted from after the quote).
    fn span(&self, at: Locus) -> (Range<usize>, bool) {
        let none = 0..0;
        match at {
            Locus::Design => (none, false),
            Locus::State { index, field } => self.states.get(index).map_or((none, false), |s| match field {
                Field::Dim => (s.dim.clone(), false),
                _ => (s.name.clone(), false),
            }),
            Locus::Arrow { index, field } => self.arrows.get(index).map_or((none, false), |a| match field {
                Field::From => (a.from.clone(), false),
                Field::To => (a.to.clone(), false),
                Field::Matrix => (a.matrix.clone(), false),
                Field::Select(k) => (a.select.get(k).cloned().unwrap_or(a.matrix.clone()), false),
                Field::Entry(r, c) => {
                    (a.entries.get(r).and_then(|row| row.get(c)).cloned().unwrap_or(a.matrix.clone()), true)
                }
                _ => (a.name.clone(), false),
            }),
            Locus::Equation { index } => (self.equations.get(index).cloned().unwrap_or(none), true),
            Locus::Parameter { index, field } => self.params.get(index).map_or((none, false), |p| match field {
                Field::NamedEntry => (p.entry.clone().unwrap_or(p.whole.clone()), true),
                Field::Default => (p.default.clone().unwrap_or(p.whole.clone()), true),
                _ => (p.whole.clone(), false),
            }),
            Locus::Model { field } => {
                let m = &self.model;
                let span = match field {
                    Field::Root => m.root.clone(),
                    Field::Points => m.points.clone(),
                    Field::Step => m.step.clone().unwrap_or(m.whole.clone()),
                    Field::Grid => m.grid.clone().unwrap_or(m.whole.clone()),
                    Field::Start(k) => m.starts.get(k).cloned().unwrap_or(m.whole.clone()),
                    Field::StartFaces(k) => m.start_faces.get(k).cloned().unwrap_or(m.whole.clone()),
                    Field::Net => m.net.clone().unwrap_or(m.whole.clone()),
                    Field::Patches => m.patches.clone().unwrap_or(m.whole.clone()),
                    _ => m.whole.clone(),
                };
                (span, false)
            }
        }
    }

    /// The builder's error at its `file:line:column`.
    fn locate(&self, src: &Source, e: BuildError) -> FormatError {
        let (span, quoted) = self.span(e.at());
        let offset = match e.offset() {
            Some(inner) if quoted => string_offset(&span, inner),
            _ => span.start,
        };
        let mut out = src.error(offset, e.message());
        out.help = e.help().map(str::to_string);
        out
    }
}

/// The shipped automaton called `name`, parsed.
///
/// ```
/// let design = bcifs::builtin_design("corner_cutting").unwrap();
/// assert_eq!(design.name(), "corner_cutting");
/// assert!(bcifs::builtin_design("nope").is_none());
/// ```
///
/// # Errors
/// `None` if there is no such automaton. The shipped files are tested to parse.
pub fn builtin_design(name: &str) -> Option<Design> {
    let (_, text) = BUILTIN_AUTOMATA.iter().find(|(n, _)| *n == name)?;
    parse_design(text, &format!("automata/{name}.toml"), name).ok()
}

/// A file with `extends = "NAME"`: the shipped automaton NAME (or the file
/// NAME relative to this one) with this file's model and parameter defaults.
fn extend(
    src: &Source,
    spec: &FileSpec,
    base: &Spanned<String>,
    default_name: &str,
    chain: &mut Vec<String>,
) -> Result<(DesignBuilder, Spans), FormatError> {
    if !spec.states.is_empty() || !spec.arrows.is_empty() || spec.constraints.as_ref().is_some_and(|c| !c.is_empty()) {
        return Err(src.at(&base.span(), "a file that extends another may only add a model and parameter defaults"));
    }
    let name = base.get_ref();
    let design = match BUILTIN_AUTOMATA.iter().find(|(n, _)| n == name) {
        Some((n, text)) => parse_design(text, &format!("automata/{n}.toml"), n)?,
        None => {
            let path = Path::new(src.file).parent().unwrap_or(Path::new(".")).join(name);
            let here =
                std::fs::canonicalize(src.file).map_or_else(|_| src.file.to_string(), |p| p.display().to_string());
            let there =
                std::fs::canonicalize(&path).map_or_else(|_| path.display().to_string(), |p| p.display().to_string());
            chain.push(here);
            if chain.contains(&there) {
                let mut names: Vec<String> = chain.clone();
                names.push(there);
                return Err(src.at(&base.span(), format!("`extends` goes round in a cycle: {}", names.join(" → "))));
            }
            if chain.len() > MAX_EXTENDS {
                return Err(src.at(
                    &base.span(),
                    format!(
                        "`extends` chains through more than {MAX_EXTENDS} files (from {}): merge some of them",
                        chain[0]
                    ),
                ));
            }
            let text = crate::input::read_text(&path, crate::input::TEXT_FILE_LIMIT).map_err(|e| {
                let mut err = src.at(&base.span(), format!("cannot read `{}`: {e}", path.display()));
                err.help =
                    suggest(name, BUILTIN_AUTOMATA.iter().map(|(n, _)| *n)).map(|s| format!("did you mean `{s}`?"));
                err
            })?;
            let design = parse_in_chain(&text, &path.display().to_string(), name, chain)?;
            chain.pop();
            design
        }
    };
    let mut b = design.to_builder();
    b.rename(spec.name.clone().unwrap_or_else(|| default_name.to_string()));
    if !spec.description.is_empty() {
        b.description(spec.description.clone());
    }
    let mut reader = Reader { src, spans: Spans::default() };
    reader.spans.params = vec![ParamSpans::default(); design.declared().len()];
    for (pname, p) in spec.parameters.iter().flatten() {
        if p.get_ref().entry.is_some() {
            return Err(src.at(&p.span(), "a file that extends another may only give parameter defaults"));
        }
        let Some(index) = design.declared().iter().position(|n| n == pname) else {
            let mut e = src.at(&p.span(), format!("`{name}` has no parameter `{pname}`"));
            e.help =
                suggest(pname, design.declared().iter().map(String::as_str)).map(|s| format!("did you mean `{s}`?"));
            return Err(e);
        };
        if let Some(d) = &p.get_ref().default {
            b.default_value(pname, reader.value(d)?);
            reader.spans.params[index] = ParamSpans { whole: p.span(), entry: None, default: Some(d.span()) };
        }
    }
    if let Some(m) = &spec.model {
        b.model(reader.model(m)?);
    }
    Ok((b, reader.spans))
}

/// Turns the deserialized file into builder calls, remembering where each item is.
struct Reader<'a> {
    src: &'a Source<'a>,
    spans: Spans,
}

fn string_offset(span: &Range<usize>, inner: usize) -> usize {
    span.start + 1 + inner
}

fn keyword<T: Copy>(
    src: &Source,
    word: &Spanned<String>,
    what: &str,
    options: &[(&'static str, T)],
) -> Result<T, FormatError> {
    let w = word.get_ref();
    options.iter().find(|(k, _)| k == w).map(|(_, v)| *v).ok_or_else(|| {
        let names: Vec<&str> = options.iter().map(|(k, _)| *k).collect();
        let expected = match names.split_last() {
            Some((last, rest)) if !rest.is_empty() => format!("{} or {last}", rest.join(", ")),
            _ => names.join(""),
        };
        let mut e = src.at(&word.span(), format!("unknown {what} `{w}`: expected {expected}"));
        e.help = suggest(w, names).map(|s| format!("did you mean `{s}`?"));
        e
    })
}

impl Reader<'_> {
    /// A number of the file (re-read exactly from the source text) or an expression.
    fn value(&self, spec: &Spanned<EntrySpec>) -> Result<Value, FormatError> {
        let span = spec.span();
        match spec.get_ref() {
            EntrySpec::Number => {
                // Most numbers of a large file are a bare `0`: no copy unless digits are grouped.
                let text = &self.src.text[span.clone()];
                let grouped: String;
                let raw = if text.contains('_') {
                    grouped = text.chars().filter(|c| *c != '_').collect();
                    grouped.as_str()
                } else {
                    text
                };
                let raw = raw.trim_start_matches('+');
                let (neg, digits) = match raw.strip_prefix('-') {
                    Some(d) => (true, d),
                    None => (false, raw),
                };
                let n = Num::parse_decimal(digits).ok_or_else(|| {
                    self.src.at(&span, format!("`{raw}` is not a decimal number; write it as a quoted expression"))
                })?;
                Ok(Value::Num(if neg { n.neg() } else { n }))
            }
            EntrySpec::Text(text) => Ok(Value::Text(text.clone())),
        }
    }

    /// A constant coordinate.
    fn constant(&self, spec: &Spanned<EntrySpec>, what: &str) -> Result<f64, FormatError> {
        let span = spec.span();
        match self.value(spec)? {
            Value::Num(n) => Ok(n.to_f64()),
            Value::Text(text) => {
                let expr = Expr::parse(&text)
                    .map_err(|e| self.src.error(string_offset(&span, e.offset), format!("in {what}: {}", e.message)))?;
                let v = expr
                    .eval_constant()
                    .map_err(|_| self.src.at(&span, format!("{what}s must be constants (numbers, + - * /, sqrt)")))?;
                Ok(v.to_f64())
            }
        }
    }

    fn read(mut self, spec: &FileSpec, default_name: &str) -> Result<(DesignBuilder, Spans), FormatError> {
        let src = self.src;
        let mut b = DesignBuilder::new(spec.name.clone().unwrap_or_else(|| default_name.to_string()));
        b.description(spec.description.clone());
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
                Some(k) => keyword(src, k, "cell kind", &CellKind::ALL.map(|k| (k.keyword(), k)))?,
            };
            b.state(s.name.get_ref().clone(), dim as usize, kind);
            if let Some(p) = &s.patch {
                b.patch(keyword(src, p, "patch", &Patch::ALL.map(|p| (p.keyword(), p)))?);
            }
            self.spans.states.push(StateSpans { name: s.name.span(), dim: s.dim.span() });
        }
        // The arrows' entries on the pool's threads, given to the builder in order (the first error in
        // that order is the one reported).
        let arrows: Vec<_> = {
            let this = &self;
            spec.arrows.par_iter().map(|arrow| this.arrow(arrow)).collect()
        };
        for (arrow, read) in spec.arrows.iter().zip(arrows) {
            let (kind, matrix, spans) = read?;
            b.arrow(
                arrow.name.get_ref().clone(),
                arrow.from.get_ref().clone(),
                arrow.to.get_ref().clone(),
                kind,
                matrix,
            );
            self.spans.arrows.push(spans);
        }
        for (group, equations) in spec.constraints.iter().flatten() {
            for eq in equations {
                b.constraint(group.clone(), eq.get_ref().clone());
                self.spans.equations.push(eq.span());
            }
        }
        for (name, p) in spec.parameters.iter().flatten() {
            let ParamSpec { entry, default } = p.get_ref();
            match entry {
                Some(e) => b.name_entry(name.clone(), e.get_ref().clone()),
                None => b.parameter(name.clone()),
            };
            if let Some(d) = default {
                b.default_value(name, self.value(d)?);
            }
            self.spans.params.push(ParamSpans {
                whole: p.span(),
                entry: entry.as_ref().map(Spanned::span),
                default: default.as_ref().map(Spanned::span),
            });
        }
        if let Some(m) = &spec.model {
            let model = self.model(m)?;
            b.model(model);
        }
        Ok((b, self.spans))
    }

    /// An arrow's kind, matrix and spans.
    fn arrow(&self, arrow: &ArrowSpec) -> Result<(ArrowKind, Matrix, ArrowSpans), FormatError> {
        let src = self.src;
        let name = arrow.name.get_ref();
        let kind = match &arrow.kind {
            None => ArrowKind::Subdivision,
            Some(k) => keyword(
                src,
                k,
                "arrow kind",
                &[("subdivision", ArrowKind::Subdivision), ("boundary", ArrowKind::Boundary)],
            )?,
        };
        let mut spans = ArrowSpans {
            name: arrow.name.span(),
            from: arrow.from.span(),
            to: arrow.to.span(),
            matrix: arrow.name.span(),
            select: Vec::new(),
            entries: Vec::new(),
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
                spans.matrix = sel.span();
                let mut picks = Vec::new();
                for i in sel.get_ref() {
                    let v = usize::try_from(*i.get_ref()).map_err(|_| {
                        src.at(&i.span(), format!("index {} is out of range: indices start at 0", i.get_ref()))
                    })?;
                    picks.push(v);
                    spans.select.push(i.span());
                }
                Matrix::Select(picks)
            }
            (Some(m), None) => {
                spans.matrix = m.span();
                match m.get_ref() {
                    MatrixSpec::Word(w) if w == "unknown" => Matrix::Unknown,
                    MatrixSpec::Word(w) => {
                        return Err(
                            src.at(&m.span(), format!("`{w}` is not a matrix: expected \"unknown\" or a list of rows"))
                        );
                    }
                    MatrixSpec::Rows(data) => {
                        let mut rows = Vec::with_capacity(data.len());
                        for row in data {
                            rows.push(row.iter().map(|e| self.value(e)).collect::<Result<Vec<_>, _>>()?);
                            spans.entries.push(row.iter().map(Spanned::span).collect());
                        }
                        Matrix::Rows(rows)
                    }
                }
            }
        };
        Ok((kind, matrix, spans))
    }

    fn model(&mut self, m: &Spanned<ModelSpec>) -> Result<Model, FormatError> {
        let src = self.src;
        let spec = m.get_ref();
        let mut points = Vec::new();
        for row in spec.points.get_ref() {
            points.push(row.iter().map(|x| self.constant(x, "control point coordinate")).collect::<Result<_, _>>()?);
        }
        let layout = match &spec.layout {
            None => Layout::Single,
            Some(l) => keyword(src, l, "layout", &Layout::ALL.map(|x| (x.keyword(), x)))?,
        };
        let mut model = Model::new("", points).with_roots(spec.root.get_ref().0.clone()).with_layout(layout);
        if let Some(up) = &spec.up {
            model.y_up = keyword(src, up, "up axis", &[("z", false), ("y", true)])?;
        }
        if let Some(s) = &spec.step {
            model.step =
                Some(usize::try_from(*s.get_ref()).map_err(|_| src.at(&s.span(), "the step must be at least 1"))?);
        }
        if let Some(g) = &spec.grid {
            let bad = || src.at(&g.span(), "expected grid = [ROWS, COLS] with positive sizes");
            let [r, c] = g.get_ref()[..] else { return Err(bad()) };
            model.grid = Some((usize::try_from(r).map_err(|_| bad())?, usize::try_from(c).map_err(|_| bad())?));
        }
        if let Some(net) = &spec.net {
            let bad = || src.at(&net.span(), "expected net = [[I, J, K, ...], ...]: faces of control point indices");
            for face in net.get_ref() {
                model.net.push(face.iter().map(|&i| usize::try_from(i).map_err(|_| bad())).collect::<Result<_, _>>()?);
            }
        }
        if let Some(patches) = &spec.patches {
            let bad =
                || src.at(&patches.span(), "expected patches = [[I, J, ...], ...]: control point indices per piece");
            for patch in patches.get_ref() {
                model
                    .patches
                    .push(patch.iter().map(|&i| usize::try_from(i).map_err(|_| bad())).collect::<Result<_, _>>()?);
            }
        }
        let mut starts = Vec::new();
        for (state, pts) in &spec.start {
            let mut set = Vec::new();
            for row in pts.get_ref() {
                set.push(row.iter().map(|x| self.constant(x, "start point coordinate")).collect::<Result<_, _>>()?);
            }
            model.start.push((state.clone(), set));
            starts.push(pts.span());
        }
        let mut start_faces = Vec::new();
        for (state, faces) in &spec.start_faces {
            let bad = || src.at(&faces.span(), "expected STATE = [[I, J, K, ...], ...]: faces of start point indices");
            let mut list = Vec::new();
            for face in faces.get_ref() {
                list.push(face.iter().map(|&i| usize::try_from(i).map_err(|_| bad())).collect::<Result<_, _>>()?);
            }
            model.start_faces.push((state.clone(), list));
            start_faces.push(faces.span());
        }
        self.spans.model = ModelSpans {
            whole: m.span(),
            root: spec.root.span(),
            points: spec.points.span(),
            step: spec.step.as_ref().map(Spanned::span),
            grid: spec.grid.as_ref().map(Spanned::span),
            net: spec.net.as_ref().map(Spanned::span),
            patches: spec.patches.as_ref().map(Spanned::span),
            starts,
            start_faces,
        };
        Ok(model)
    }
}
