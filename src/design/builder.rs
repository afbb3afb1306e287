//! The checked builder: the one way a [`Design`] is made, by the file
//! parser, by every scheme generator and by code.
//!
//! Items are recorded as given (names, not indices); [`DesignBuilder::build`]
//! resolves and checks everything and either returns a design whose parts
//! agree or a [`BuildError`] naming the item at fault. It never panics.

use std::collections::{HashMap, HashSet};
use std::fmt;

use nalgebra::DMatrix;

use super::model::{Docs, Layout, Model, Origin, Variable};
use crate::algebra::{Affine, Env, Expr, ExprError, Num, Surd};
use crate::automaton::{Arrow, ArrowKind, Automaton, Constraint, Relation, selection};
use crate::names::suggest;
use crate::space::{CellKind, State};

/// A number or an expression given to the builder: a matrix entry or a
/// parameter default.
///
/// Numbers are exact: an `f64` is read as its shortest decimal form (`0.1`
/// is `1/10`). Text is an expression (`"1 - a"`, `"sqrt(3)/6"`) in the
/// language of automaton files.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    /// A number.
    Num(Num),
    /// An expression in parameters and constants.
    Text(String),
}

impl From<Num> for Value {
    fn from(n: Num) -> Value {
        Value::Num(n)
    }
}
impl From<Surd> for Value {
    fn from(s: Surd) -> Value {
        Value::Num(Num::Exact(s))
    }
}
impl From<&Surd> for Value {
    fn from(s: &Surd) -> Value {
        Value::Num(Num::Exact(s.clone()))
    }
}
impl From<i64> for Value {
    fn from(n: i64) -> Value {
        Value::Num(Num::int(n))
    }
}
impl From<i32> for Value {
    fn from(n: i32) -> Value {
        Value::Num(Num::int(i64::from(n)))
    }
}
impl From<f64> for Value {
    fn from(x: f64) -> Value {
        Value::Num(Num::from_f64(x))
    }
}
impl From<&str> for Value {
    fn from(s: &str) -> Value {
        Value::Text(s.to_string())
    }
}
impl From<String> for Value {
    fn from(s: String) -> Value {
        Value::Text(s)
    }
}

impl fmt::Display for Value {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Value::Num(n) => write!(f, "{n}"),
            Value::Text(t) => f.write_str(t),
        }
    }
}

/// The matrix of an arrow.
#[derive(Clone, Debug, PartialEq)]
pub enum Matrix {
    /// Every entry is an unknown of the constraint system.
    Unknown,
    /// The selection matrix whose column `j` is `e_{select[j]}` (a boundary
    /// cell whose control points are these points of the bounded cell).
    Select(Vec<usize>),
    /// Known rows (entries may use parameters).
    Rows(Vec<Vec<Value>>),
}

/// Which part of an item an error is about.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Field {
    /// The item as a whole.
    Whole,
    /// Its name.
    Name,
    /// A state's dimension.
    Dim,
    /// An arrow's source state.
    From,
    /// An arrow's target state.
    To,
    /// An arrow's matrix (or selection) as a whole.
    Matrix,
    /// Index `k` of an arrow's selection.
    Select(usize),
    /// Entry `[row][col]` of an arrow's known matrix.
    Entry(usize, usize),
    /// The entry a parameter names.
    NamedEntry,
    /// A parameter's default.
    Default,
    /// The model's roots.
    Root,
    /// The model's control points.
    Points,
    /// The model's window step.
    Step,
    /// The model's grid size.
    Grid,
    /// The model's `k`-th start set.
    Start(usize),
    /// The model's control net.
    Net,
    /// The model's patches.
    Patches,
}

/// Where an error is, by the order items were given to the builder (the
/// file parser maps it back to `file:line:column`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Locus {
    /// The design as a whole.
    Design,
    /// The `index`-th state.
    State {
        /// Order of the state.
        index: usize,
        /// The part at fault.
        field: Field,
    },
    /// The `index`-th arrow.
    Arrow {
        /// Order of the arrow.
        index: usize,
        /// The part at fault.
        field: Field,
    },
    /// The `index`-th equation, counted group by group (groups in order of first use).
    Equation {
        /// Order of the equation.
        index: usize,
    },
    /// The `index`-th parameter.
    Parameter {
        /// Order of the parameter.
        index: usize,
        /// The part at fault.
        field: Field,
    },
    /// The model.
    Model {
        /// The part at fault.
        field: Field,
    },
}

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
    fn new(at: Locus, label: String, message: impl Into<String>) -> BuildError {
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

    fn at_offset(mut self, offset: usize) -> BuildError {
        self.0.offset = Some(offset);
        self
    }

    fn with_message(mut self, message: String) -> BuildError {
        self.0.message = message;
        self
    }

    fn suggesting<'a>(mut self, name: &str, candidates: impl IntoIterator<Item = &'a str>) -> BuildError {
        self.0.help = suggest(name, candidates).map(|s| format!("did you mean `{s}`?"));
        self
    }
}

/// Most entries of one matrix (a 2000 × 2000 matrix): larger dimensions are mistakes.
pub const MAX_MATRIX_ENTRIES: usize = 4_000_000;

/// Most unknowns of a constraint system: the exact solver stays within
/// seconds and a few hundred megabytes (the quad patch has 484).
pub const MAX_UNKNOWNS: usize = 20_000;

/// Parameters that name entries, by entry: `(name, order of the parameter)`.
type NamedEntries = HashMap<(String, usize, usize), (String, usize)>;

#[derive(Clone, Debug, PartialEq)]
struct StateItem {
    name: String,
    dim: usize,
    kind: CellKind,
}

#[derive(Clone, Debug, PartialEq)]
struct ArrowItem {
    name: String,
    from: String,
    to: String,
    kind: ArrowKind,
    matrix: Matrix,
}

#[derive(Clone, Debug, PartialEq)]
struct EquationItem {
    group: String,
    text: String,
}

#[derive(Clone, Debug, PartialEq)]
struct ParamItem {
    name: String,
    entry: Option<String>,
    default: Option<Value>,
}

#[derive(Clone, Debug, Default, PartialEq)]
enum Last {
    #[default]
    Header,
    State(String),
    Arrow(String),
    Group(String),
    Parameters,
    Model,
}

/// Builds a [`Design`]: states, arrows (unknown, known or selection
/// matrices), constraints as path or entry equations, parameters and a
/// model, checked as a whole by [`DesignBuilder::build`].
///
/// Paths read in arrow order (`T0 b1` is `e -T0-> e -b1-> v`); a matrix maps
/// target coordinates into source coordinates, so it is `dim(from) × dim(to)`.
///
/// ```
/// use bcifs::{CellKind, Design, Layout, Model};
/// // The local corner-cutting curve of seed 004 §3, as in automata/corner_cutting.toml.
/// let design = Design::builder("corner_cutting")
///     .state("e", 3, CellKind::Edge)
///     .state("v", 2, CellKind::Vertex)
///     .unknown("T0", "e", "e")
///     .unknown("T1", "e", "e")
///     .unknown("Tv", "v", "v")
///     .select("b0", "e", "v", [0, 1])
///     .select("b1", "e", "v", [1, 2])
///     .adjacency("T0 b1 = T1 b0")
///     .incidence("T0 b0 = b0 Tv")
///     .incidence("T1 b1 = b1 Tv")
///     .name_entry("a", "T0[1][0]")
///     .name_entry("b", "T0[0][1]")
///     .build()
///     .unwrap();
/// let family = bcifs::solve(&design).unwrap();
/// assert_eq!(family.parameter_names(), ["a", "b"]);
/// assert_eq!(family.entry_text("T1", 1, 0), "1 - b");
///
/// // Mistakes are named, never a panic.
/// let err = Design::builder("x").state("e", 3, CellKind::Edge).unknown("T0", "e", "ee").build().unwrap_err();
/// assert_eq!(err.to_string(), "arrow `T0`: no state named `ee` (did you mean `e`?)");
/// ```
#[derive(Clone, Debug, Default, PartialEq)]
pub struct DesignBuilder {
    name: String,
    description: String,
    states: Vec<StateItem>,
    arrows: Vec<ArrowItem>,
    equations: Vec<EquationItem>,
    parameters: Vec<ParamItem>,
    orphan_defaults: Vec<(String, Value)>,
    model: Option<Model>,
    docs: Docs,
    last: Last,
}

impl DesignBuilder {
    /// An empty design called `name`.
    pub fn new(name: impl Into<String>) -> DesignBuilder {
        DesignBuilder { name: name.into(), ..DesignBuilder::default() }
    }

    /// Renames the design.
    pub fn rename(&mut self, name: impl Into<String>) -> &mut Self {
        self.name = name.into();
        self
    }

    /// Free text describing the design.
    pub fn description(&mut self, text: impl Into<String>) -> &mut Self {
        self.description = text.into();
        self
    }

    /// A comment on the item added last (the whole design before any item),
    /// written above it when the design is printed as a file.
    pub fn doc(&mut self, text: impl Into<String>) -> &mut Self {
        let text = text.into();
        let docs = &mut self.docs;
        match &self.last {
            Last::Header => docs.header = text,
            Last::State(n) => _ = docs.states.insert(n.clone(), text),
            Last::Arrow(n) => _ = docs.arrows.insert(n.clone(), text),
            Last::Group(n) => _ = docs.groups.insert(n.clone(), text),
            Last::Parameters => docs.parameters = text,
            Last::Model => docs.model = text,
        }
        self
    }

    /// A state: the barycentric space `BI^dim` of a cell of kind `kind`.
    pub fn state(&mut self, name: impl Into<String>, dim: usize, kind: CellKind) -> &mut Self {
        let name = name.into();
        self.last = Last::State(name.clone());
        self.states.push(StateItem { name, dim, kind });
        self
    }

    /// An arrow `from → to` of any kind with any matrix.
    pub fn arrow(
        &mut self,
        name: impl Into<String>,
        from: impl Into<String>,
        to: impl Into<String>,
        kind: ArrowKind,
        matrix: Matrix,
    ) -> &mut Self {
        let name = name.into();
        self.last = Last::Arrow(name.clone());
        self.arrows.push(ArrowItem { name, from: from.into(), to: to.into(), kind, matrix });
        self
    }

    /// A subdivision arrow whose matrix the solver finds.
    pub fn unknown(&mut self, name: impl Into<String>, from: impl Into<String>, to: impl Into<String>) -> &mut Self {
        self.arrow(name, from, to, ArrowKind::Subdivision, Matrix::Unknown)
    }

    /// A subdivision arrow with a known matrix, given by rows of numbers
    /// or expressions (`[[1, 0], [0, 1]]`, `[["1 - t", "t"], ["t", "1 - t"]]`).
    pub fn matrix<R, V>(
        &mut self,
        name: impl Into<String>,
        from: impl Into<String>,
        to: impl Into<String>,
        rows: impl IntoIterator<Item = R>,
    ) -> &mut Self
    where
        R: IntoIterator<Item = V>,
        V: Into<Value>,
    {
        let rows = rows.into_iter().map(|r| r.into_iter().map(Into::into).collect()).collect();
        self.arrow(name, from, to, ArrowKind::Subdivision, Matrix::Rows(rows))
    }

    /// A boundary arrow: the boundary cell `to` has the control points
    /// `select` of the cell `from` (column `j` of the matrix is `e_{select[j]}`).
    pub fn select(
        &mut self,
        name: impl Into<String>,
        from: impl Into<String>,
        to: impl Into<String>,
        select: impl IntoIterator<Item = usize>,
    ) -> &mut Self {
        self.arrow(name, from, to, ArrowKind::Boundary, Matrix::Select(select.into_iter().collect()))
    }

    /// An equation of the constraint group `group`: two paths
    /// (`"T0 b1 = T1 b0"`), or two expressions in entries and parameters
    /// (`"W[1][1] = W[0][0]"`, `"T0[2][2] = 1/2"`).
    pub fn constraint(&mut self, group: impl Into<String>, equation: impl Into<String>) -> &mut Self {
        let group = group.into();
        self.last = Last::Group(group.clone());
        // Equations are kept group by group (groups in order of first use), as a file holds them.
        let at = self.equations.iter().rposition(|e| e.group == group).map_or(self.equations.len(), |i| i + 1);
        self.equations.insert(at, EquationItem { group, text: equation.into() });
        self
    }

    /// An adjacency equation: neighbouring sub-cells share their boundary.
    pub fn adjacency(&mut self, equation: impl Into<String>) -> &mut Self {
        self.constraint("adjacency", equation)
    }

    /// An incidence equation: the boundary of a sub-cell is the subdivided boundary.
    pub fn incidence(&mut self, equation: impl Into<String>) -> &mut Self {
        self.constraint("incidence", equation)
    }

    /// Names the unknown entry `entry` (`"T0[1][0]"`): the family prints in
    /// this letter, and it stays free when the constraints allow.
    pub fn name_entry(&mut self, name: impl Into<String>, entry: impl Into<String>) -> &mut Self {
        self.last = Last::Parameters;
        self.parameters.push(ParamItem { name: name.into(), entry: Some(entry.into()), default: None });
        self
    }

    /// A plain parameter, used by known matrices and entry equations.
    pub fn parameter(&mut self, name: impl Into<String>) -> &mut Self {
        self.last = Last::Parameters;
        self.parameters.push(ParamItem { name: name.into(), entry: None, default: None });
        self
    }

    /// The default value of parameter `name` (a named entry or a plain parameter).
    pub fn default_value(&mut self, name: &str, value: impl Into<Value>) -> &mut Self {
        let value = value.into();
        match self.parameters.iter_mut().find(|p| p.name == name) {
            Some(p) => p.default = Some(value),
            None => self.orphan_defaults.push((name.to_string(), value)),
        }
        self
    }

    /// The projection into modelling space.
    pub fn model(&mut self, model: Model) -> &mut Self {
        self.last = Last::Model;
        self.model = Some(model);
        self
    }

    pub(crate) fn model_ref(&self) -> Option<&Model> {
        self.model.as_ref()
    }

    pub(crate) fn description_ref(&self) -> &str {
        &self.description
    }

    pub(crate) fn docs_ref(&self) -> &Docs {
        &self.docs
    }

    /// The name of the design.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// What the builder holds, for printing: states `(name, dim, kind)`.
    pub(crate) fn state_items(&self) -> impl Iterator<Item = (&str, usize, CellKind)> {
        self.states.iter().map(|s| (s.name.as_str(), s.dim, s.kind))
    }

    /// Arrows `(name, from, to, kind, matrix)`.
    pub(crate) fn arrow_items(&self) -> impl Iterator<Item = (&str, &str, &str, ArrowKind, &Matrix)> {
        self.arrows.iter().map(|a| (a.name.as_str(), a.from.as_str(), a.to.as_str(), a.kind, &a.matrix))
    }

    /// Equations `(group, text)`.
    pub(crate) fn equation_items(&self) -> impl Iterator<Item = (&str, &str)> {
        self.equations.iter().map(|e| (e.group.as_str(), e.text.as_str()))
    }

    /// Parameters `(name, named entry, default)`.
    pub(crate) fn parameter_items(&self) -> impl Iterator<Item = (&str, Option<&str>, Option<&Value>)> {
        self.parameters.iter().map(|p| (p.name.as_str(), p.entry.as_deref(), p.default.as_ref()))
    }

    /// Checks everything and makes the design.
    ///
    /// # Errors
    /// The first problem found, naming its item (see [`BuildError`]):
    /// duplicate or unknown names, dimensions, matrix shapes, selections
    /// that are not embeddings, expressions that do not parse or use unknown
    /// names, paths that do not chain, equations whose sides end at different
    /// states, defaults that are not constants, and models that do not fit
    /// the automaton.
    pub fn build(&self) -> Result<Design, BuildError> {
        Compiler::new(self).run()
    }
}

/// Resolves names while known matrices are evaluated.
struct Symbols<'a> {
    vars: &'a HashMap<String, usize>,
}

impl Env<Affine> for Symbols<'_> {
    fn param(&self, name: &str) -> Option<Affine> {
        self.vars.get(name).map(|v| Affine::var(*v))
    }
    fn entry(&self, _: &str, _: usize, _: usize) -> Option<Affine> {
        None
    }
}

struct Compiler<'a> {
    spec: &'a DesignBuilder,
    vars: Vec<Variable>,
    var_by_name: HashMap<String, usize>,
    /// The first variable of each unknown matrix (its entries follow row by row).
    unknown_base: HashMap<String, usize>,
    automaton: Automaton<Affine>,
}

fn parse_entry(text: &str) -> Option<(String, usize, usize)> {
    match Expr::parse(text) {
        Ok(Expr::Entry { arrow, row, col, .. }) => Some((arrow, row, col)),
        _ => None,
    }
}

impl<'a> Compiler<'a> {
    fn new(spec: &'a DesignBuilder) -> Compiler<'a> {
        Compiler {
            spec,
            vars: Vec::new(),
            var_by_name: HashMap::new(),
            unknown_base: HashMap::new(),
            automaton: Automaton::new(spec.name.clone()),
        }
    }

    fn state_error(&self, index: usize, field: Field, message: impl Into<String>) -> BuildError {
        BuildError::new(Locus::State { index, field }, format!("state `{}`", self.spec.states[index].name), message)
    }

    fn arrow_error(&self, index: usize, field: Field, message: impl Into<String>) -> BuildError {
        BuildError::new(Locus::Arrow { index, field }, format!("arrow `{}`", self.spec.arrows[index].name), message)
    }

    fn param_error(&self, index: usize, field: Field, message: impl Into<String>) -> BuildError {
        let label = format!("parameter `{}`", self.spec.parameters[index].name);
        BuildError::new(Locus::Parameter { index, field }, label, message)
    }

    fn equation_error(&self, index: usize, message: impl Into<String>) -> BuildError {
        let e = &self.spec.equations[index];
        BuildError::new(Locus::Equation { index }, format!("equation `{}: {}`", e.group, e.text), message)
    }

    fn model_error(field: Field, message: impl Into<String>) -> BuildError {
        BuildError::new(Locus::Model { field }, "model".into(), message)
    }

    fn new_var(&mut self, name: String, named: bool, origin: Origin) {
        self.var_by_name.insert(name.clone(), self.vars.len());
        self.vars.push(Variable { name, named, origin });
    }

    fn state_names(&self) -> impl Iterator<Item = &str> {
        self.spec.states.iter().map(|s| s.name.as_str())
    }

    fn run(mut self) -> Result<Design, BuildError> {
        self.states()?;
        let named = self.named_entries()?;
        self.unknowns(named)?;
        for index in 0..self.spec.arrows.len() {
            self.arrow(index)?;
        }
        for index in 0..self.spec.equations.len() {
            let c = self.equation(index)?;
            self.automaton.add_constraint(c).map_err(|e| self.equation_error(index, e.to_string()))?;
        }
        let defaults = self.defaults()?;
        if let Some(m) = &self.spec.model {
            self.check_model(m)?;
        }
        let declared = self.spec.parameters.iter().map(|p| p.name.clone()).collect();
        Ok(Design { automaton: self.automaton, variables: self.vars, defaults, declared, spec: self.spec.clone() })
    }

    fn states(&mut self) -> Result<(), BuildError> {
        if self.spec.states.is_empty() {
            return Err(BuildError::new(
                Locus::Design,
                String::new(),
                "the design declares no state: expected at least one state",
            ));
        }
        for (index, s) in self.spec.states.iter().enumerate() {
            if s.dim < 1 {
                return Err(self.state_error(index, Field::Dim, "a state needs at least one control point (dim ≥ 1)"));
            }
            self.automaton.add_state(State::new(s.name.clone(), s.dim, s.kind)).map_err(|_| {
                self.state_error(index, Field::Name, format!("a state named `{}` is declared twice", s.name))
            })?;
        }
        Ok(())
    }

    /// Parameters that name entries of unknown matrices (by entry), after
    /// declaring the plain parameters as variables.
    fn named_entries(&mut self) -> Result<NamedEntries, BuildError> {
        let mut named = HashMap::new();
        let mut seen = HashSet::new();
        for (index, p) in self.spec.parameters.iter().enumerate() {
            if !seen.insert(p.name.as_str()) {
                return Err(self.param_error(
                    index,
                    Field::Name,
                    format!("a parameter named `{}` is declared twice", p.name),
                ));
            }
            let Some(entry) = &p.entry else {
                self.new_var(p.name.clone(), true, Origin::Parameter);
                continue;
            };
            let Some((arrow, row, col)) = parse_entry(entry) else {
                return Err(self.param_error(
                    index,
                    Field::NamedEntry,
                    format!("`{entry}` is not a matrix entry: expected ARROW[ROW][COL], such as \"T0[1][0]\""),
                ));
            };
            if let Some((other, _)) = named.insert((arrow.clone(), row, col), (p.name.clone(), index)) {
                return Err(self.param_error(
                    index,
                    Field::NamedEntry,
                    format!("{arrow}[{row}][{col}] is already named `{other}`"),
                ));
            }
        }
        Ok(named)
    }

    fn endpoint(&self, index: usize, field: Field, name: &str) -> Result<usize, BuildError> {
        let id = self.automaton.state_id(name).ok_or_else(|| {
            self.arrow_error(index, field, format!("no state named `{name}`")).suggesting(name, self.state_names())
        })?;
        Ok(self.automaton.state(id).dim)
    }

    /// Variables of unknown matrices, so that known matrices may use their names.
    fn unknowns(&mut self, mut named: NamedEntries) -> Result<(), BuildError> {
        let mut seen = HashSet::new();
        for (index, arrow) in self.spec.arrows.iter().enumerate() {
            if !seen.insert(arrow.name.as_str()) {
                return Err(self.arrow_error(
                    index,
                    Field::Name,
                    format!("an arrow named `{}` is declared twice", arrow.name),
                ));
            }
            if arrow.matrix != Matrix::Unknown {
                continue;
            }
            let rows = self.endpoint(index, Field::From, &arrow.from)?;
            let cols = self.endpoint(index, Field::To, &arrow.to)?;
            if self.vars.len().saturating_add(rows.saturating_mul(cols)) > MAX_UNKNOWNS {
                return Err(self.arrow_error(
                    index,
                    Field::Matrix,
                    format!(
                        "its {rows}×{cols} unknown matrix would bring the system over {MAX_UNKNOWNS} unknowns (is a dim mistyped?)"
                    ),
                ));
            }
            self.unknown_base.insert(arrow.name.clone(), self.vars.len());
            for r in 0..rows {
                for c in 0..cols {
                    let origin = Origin::Entry { arrow: arrow.name.clone(), row: r, col: c };
                    match named.remove(&(arrow.name.clone(), r, c)) {
                        Some((pname, _)) => self.new_var(pname, true, origin),
                        None => self.new_var(format!("{}_{r}_{c}", arrow.name), false, origin),
                    }
                }
            }
        }
        if let Some(((arrow, row, col), (_, index))) = named.into_iter().min_by_key(|(_, (_, i))| *i) {
            let unknown = self.spec.arrows.iter().filter(|a| a.matrix == Matrix::Unknown).map(|a| a.name.as_str());
            return Err(self
                .param_error(
                    index,
                    Field::NamedEntry,
                    format!("{arrow}[{row}][{col}] is not an entry of an unknown matrix"),
                )
                .suggesting(&arrow, unknown));
        }
        Ok(())
    }

    fn eval_error(&self, at: BuildError, e: ExprError, what: &str) -> BuildError {
        match e {
            ExprError::UnknownParam(name, off) => {
                let mut err = at
                    .with_message(format!("unknown parameter `{name}` in {what}"))
                    .at_offset(off)
                    .suggesting(&name, self.var_by_name.keys().map(String::as_str));
                if err.0.help.is_none() {
                    err.0.help = Some("declare it as a parameter".into());
                }
                err
            }
            other => at.with_message(format!("{what}: {other}")),
        }
    }

    /// An expression of constants and parameters (no matrix entries).
    fn value(&self, value: &Value, at: BuildError, what: &str) -> Result<Affine, BuildError> {
        match value {
            Value::Num(n) => Ok(Affine::constant(n.clone())),
            Value::Text(text) => {
                let expr = Expr::parse(text)
                    .map_err(|e| at.clone().with_message(format!("in {what}: {}", e.message)).at_offset(e.offset))?;
                if let Some((arrow, row, col, off)) = expr.entries().first() {
                    return Err(at
                        .with_message(format!(
                            "{what} cannot refer to the matrix entry {arrow}[{row}][{col}]; use a parameter"
                        ))
                        .at_offset(*off));
                }
                expr.eval(&Symbols { vars: &self.var_by_name }).map_err(|e| self.eval_error(at, e, what))
            }
        }
    }

    fn arrow(&mut self, index: usize) -> Result<(), BuildError> {
        let arrow = &self.spec.arrows[index];
        let name = &arrow.name;
        let rows = self.endpoint(index, Field::From, &arrow.from)?;
        let cols = self.endpoint(index, Field::To, &arrow.to)?;
        if rows.saturating_mul(cols) > MAX_MATRIX_ENTRIES {
            return Err(self.arrow_error(
                index,
                Field::Matrix,
                format!("its matrix would be {rows}×{cols}: at most {MAX_MATRIX_ENTRIES} entries (is a dim mistyped?)"),
            ));
        }
        let matrix = match &arrow.matrix {
            Matrix::Unknown => {
                let Some(&base) = self.unknown_base.get(name) else {
                    return Err(self.arrow_error(index, Field::Whole, "internal error: no unknowns (please report)"));
                };
                DMatrix::from_fn(rows, cols, |r, c| Affine::var(base + r * cols + c))
            }
            Matrix::Select(picks) => {
                for (k, &v) in picks.iter().enumerate() {
                    if v >= rows {
                        return Err(self.arrow_error(
                            index,
                            Field::Select(k),
                            format!(
                                "index {v} is out of range: `{}` has dim {rows}, so indices go from 0 to {}",
                                arrow.from,
                                rows - 1
                            ),
                        ));
                    }
                    if picks[..k].contains(&v) {
                        return Err(self.arrow_error(
                            index,
                            Field::Select(k),
                            format!("index {v} is selected twice: a selection must be an embedding"),
                        ));
                    }
                }
                if picks.len() != cols {
                    return Err(self.arrow_error(
                        index,
                        Field::Matrix,
                        format!("`{}` has dim {cols}, so `select` needs {cols} indices, not {}", arrow.to, picks.len()),
                    ));
                }
                selection(rows, picks)
            }
            Matrix::Rows(data) => {
                if data.len() != rows || data.iter().any(|r| r.len() != cols) {
                    let got_cols = data.iter().map(Vec::len).max().unwrap_or(0);
                    return Err(self.arrow_error(index, Field::Matrix, format!(
                        "arrow `{name}` goes from `{}` (dim {rows}) to `{}` (dim {cols}), so its matrix must be {rows}×{cols} ({rows} rows of {cols}), not {} rows of up to {got_cols}",
                        arrow.from, arrow.to, data.len()
                    )));
                }
                let mut entries = Vec::with_capacity(rows * cols);
                for (r, row) in data.iter().enumerate() {
                    for (c, e) in row.iter().enumerate() {
                        let at = self.arrow_error(index, Field::Entry(r, c), "");
                        entries.push(self.value(e, at, &format!("entry [{r}][{c}] of `{name}`"))?);
                    }
                }
                DMatrix::from_row_iterator(rows, cols, entries)
            }
        };
        let (from, to) = (self.automaton.state_id(&arrow.from), self.automaton.state_id(&arrow.to));
        let (Some(from), Some(to)) = (from, to) else {
            return Err(self.arrow_error(index, Field::Whole, "internal error: endpoints vanished (please report)"));
        };
        self.automaton
            .add_arrow(from, to, Arrow { name: name.clone(), kind: arrow.kind, matrix })
            .map_err(|e| self.arrow_error(index, Field::Name, e.to_string()))?;
        Ok(())
    }

    fn arrow_names(&self) -> Vec<&str> {
        self.automaton.arrows().map(|(_, x)| x.name.as_str()).collect()
    }

    fn equation(&self, index: usize) -> Result<Constraint, BuildError> {
        let EquationItem { group, text } = &self.spec.equations[index];
        let err = |off: usize, message: String| self.equation_error(index, message).at_offset(off);
        let Some(eq_at) = text.find('=') else {
            return Err(self.equation_error(index, format!("`{text}` is not an equation: expected LEFT = RIGHT")));
        };
        if let Some(second) = text[eq_at + 1..].find('=') {
            return Err(err(eq_at + 1 + second, "an equation has exactly one `=`".into()));
        }
        let sides = [(&text[..eq_at], 0), (&text[eq_at + 1..], eq_at + 1)];
        let relation = if text.contains('[') {
            let mut exprs = Vec::new();
            for (side, off) in sides {
                let e = Expr::parse(side).map_err(|e| err(off + e.offset, e.message))?;
                for (arrow, row, col, o) in e.entries() {
                    let Some(id) = self.automaton.arrow_id(arrow) else {
                        return Err(
                            err(off + o, format!("no arrow named `{arrow}`")).suggesting(arrow, self.arrow_names())
                        );
                    };
                    let m = &self.automaton.arrow(id).matrix;
                    if row >= m.nrows() || col >= m.ncols() {
                        return Err(err(
                            off + o,
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
                        return Err(err(off + o, format!("unknown parameter `{name}`"))
                            .suggesting(name, self.var_by_name.keys().map(String::as_str)));
                    }
                }
                exprs.push(e);
            }
            let (Some(rhs), Some(lhs)) = (exprs.pop(), exprs.pop()) else {
                return Err(self.equation_error(index, "internal error: an equation without two sides (please report)"));
            };
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
                    match self.automaton.arrow_id(token) {
                        Some(id) => path.push(id),
                        None => {
                            return Err(err(off + side[..start].len(), format!("no arrow named `{token}`"))
                                .suggesting(token, self.arrow_names()));
                        }
                    }
                }
                if path.is_empty() {
                    return Err(err(off, "expected a path of arrow names, such as `T0 b1`".into()));
                }
                paths.push(path);
            }
            let (Some(rhs), Some(lhs)) = (paths.pop(), paths.pop()) else {
                return Err(self.equation_error(index, "internal error: an equation without two sides (please report)"));
            };
            Relation::Paths { lhs, rhs }
        };
        Ok(Constraint { group: group.clone(), text: text.trim().to_string(), relation })
    }

    fn defaults(&self) -> Result<HashMap<String, f64>, BuildError> {
        if let Some((name, _)) = self.spec.orphan_defaults.first() {
            let names = self.spec.parameters.iter().map(|p| p.name.as_str());
            return Err(BuildError::new(
                Locus::Design,
                format!("default of `{name}`"),
                format!("`{name}` is not a parameter"),
            )
            .suggesting(name, names));
        }
        let mut defaults = HashMap::new();
        for (index, p) in self.spec.parameters.iter().enumerate() {
            if let Some(d) = &p.default {
                let at = self.param_error(index, Field::Default, "");
                let value = self.value(d, at, &format!("the default of `{}`", p.name))?;
                let value = value
                    .as_constant()
                    .ok_or_else(|| self.param_error(index, Field::Default, "a default must be a constant"))?;
                defaults.insert(p.name.clone(), value.to_f64());
            }
        }
        Ok(defaults)
    }

    fn check_model(&self, m: &Model) -> Result<(), BuildError> {
        let roots = self.model_roots(m)?;
        let d = m.points.first().map_or(0, Vec::len);
        if !(2..=3).contains(&d) || m.points.iter().any(|p| p.len() != d) {
            return Err(Self::model_error(Field::Points, "control points must all have 2 or all have 3 coordinates"));
        }
        if m.points.iter().flatten().any(|x| !x.is_finite()) {
            return Err(Self::model_error(Field::Points, "control points must be finite numbers"));
        }
        if m.step == Some(0) {
            return Err(Self::model_error(Field::Step, "the step must be at least 1"));
        }
        if let Some((r, c)) = m.grid
            && (r == 0 || c == 0)
        {
            return Err(Self::model_error(Field::Grid, "expected grid = [ROWS, COLS] with positive sizes"));
        }
        self.model_starts(m)?;
        if let Some(face) = m.net.iter().find(|f| f.len() < 3 || f.iter().any(|&i| i >= m.points.len())) {
            return Err(Self::model_error(
                Field::Net,
                format!("net faces need at least 3 control point indices below {}: {face:?}", m.points.len()),
            ));
        }
        let needed = self.model_points_needed(m, &roots, d)?;
        if m.points.len() < needed {
            return Err(Self::model_error(
                Field::Points,
                format!("this layout needs at least {needed} control points, not {}", m.points.len()),
            ));
        }
        Ok(())
    }

    /// The dimensions of the model's roots, which must all name states (and,
    /// but for a union, have the same dimension).
    fn model_roots(&self, m: &Model) -> Result<Vec<usize>, BuildError> {
        let a = &self.automaton;
        if m.roots.is_empty() {
            return Err(Self::model_error(Field::Root, "expected at least one root state"));
        }
        let mut dims = Vec::new();
        for name in &m.roots {
            let id = a.state_id(name).ok_or_else(|| {
                Self::model_error(Field::Root, format!("no state named `{name}`")).suggesting(name, self.state_names())
            })?;
            dims.push(a.state(id).dim);
        }
        if !matches!(m.layout, Layout::Union | Layout::Patches)
            && let Some(k) = dims.iter().position(|&n| n != dims[0])
        {
            return Err(Self::model_error(
                Field::Whole,
                format!(
                    "the roots of this layout must have the same dimension: `{}` has {}, `{}` has {}",
                    m.roots[0], dims[0], m.roots[k], dims[k]
                ),
            ));
        }
        Ok(dims)
    }

    /// Start sets name states and hold barycentric points of their dimension.
    fn model_starts(&self, m: &Model) -> Result<(), BuildError> {
        for (k, (state, set)) in m.start.iter().enumerate() {
            let Some(id) = self.automaton.state_id(state) else {
                return Err(Self::model_error(Field::Start(k), format!("no state named `{state}` for a start set"))
                    .suggesting(state, self.state_names()));
            };
            let n = self.automaton.state(id).dim;
            for p in set {
                if p.len() != n {
                    return Err(Self::model_error(
                        Field::Start(k),
                        format!("start points of `{state}` are barycentric: {n} coordinates each, not {}", p.len()),
                    ));
                }
                let sum: f64 = p.iter().sum();
                if !sum.is_finite() || (sum - 1.0).abs() > crate::algebra::tolerance::STOCHASTIC {
                    return Err(Self::model_error(
                        Field::Start(k),
                        format!("start points are barycentric: coordinates must sum to 1 (one sums to {sum})"),
                    ));
                }
            }
        }
        Ok(())
    }

    /// How many control points the layout needs at least (`dims`: of the
    /// roots; `d`: of the points).
    fn model_points_needed(&self, m: &Model, dims: &[usize], d: usize) -> Result<usize, BuildError> {
        let dim = dims[0];
        Ok(match m.layout {
            Layout::Frames | Layout::ClosedFrames => {
                if d != 2 || dim != 3 {
                    return Err(Self::model_error(
                        Field::Whole,
                        "frame layouts need 2D points and a root of dim 3 (segment and frame point)",
                    ));
                }
                2
            }
            Layout::Single | Layout::Open | Layout::Closed => dim,
            Layout::Union => {
                let total: usize = dims.iter().sum();
                if !m.points.len().is_multiple_of(total) {
                    return Err(Self::model_error(
                        Field::Points,
                        format!("a union of the roots takes {total} control points per round, not {}", m.points.len()),
                    ));
                }
                total
            }
            Layout::Patches => {
                if m.patches.is_empty() {
                    return Err(Self::model_error(Field::Whole, "a patches layout needs patches = [[I, J, ...], ...]"));
                }
                for (i, patch) in m.patches.iter().enumerate() {
                    let want = dims[i % dims.len()];
                    if patch.len() != want {
                        return Err(Self::model_error(
                            Field::Patches,
                            format!(
                                "patch {i} lists {} control points; its root `{}` has dim {want}",
                                patch.len(),
                                m.roots[i % m.roots.len()]
                            ),
                        ));
                    }
                    if let Some(&bad) = patch.iter().find(|&&p| p >= m.points.len()) {
                        return Err(Self::model_error(
                            Field::Patches,
                            format!("patch {i} uses control point {bad}; there are {}", m.points.len()),
                        ));
                    }
                }
                0
            }
            Layout::Grid | Layout::Torus => {
                let (r, c) =
                    m.grid.ok_or_else(|| Self::model_error(Field::Whole, "grid layouts need grid = [ROWS, COLS]"))?;
                if r * c != m.points.len() {
                    return Err(Self::model_error(
                        Field::Points,
                        format!("grid = [{r}, {c}] needs {} control points, not {}", r * c, m.points.len()),
                    ));
                }
                dim
            }
        })
    }
}

/// An automaton whose entries are affine in the variables of its constraint
/// system, made by a [`DesignBuilder`] (from a file, a generator or code),
/// with its model.
///
/// Its parts agree by construction: every variable of an entry exists, every
/// parameter is declared, the model's roots and start sets name states.
#[derive(Clone, Debug)]
pub struct Design {
    automaton: Automaton<Affine>,
    variables: Vec<Variable>,
    defaults: HashMap<String, f64>,
    declared: Vec<String>,
    spec: DesignBuilder,
}

impl Design {
    /// Starts a design called `name`: see [`DesignBuilder`].
    pub fn builder(name: impl Into<String>) -> DesignBuilder {
        DesignBuilder::new(name)
    }

    /// The automaton; unknown entries are variables, known entries may use parameters.
    pub fn automaton(&self) -> &Automaton<Affine> {
        &self.automaton
    }

    /// The name.
    pub fn name(&self) -> &str {
        &self.automaton.name
    }

    /// The variables of the constraint system, indexed as in the affine entries.
    pub fn variables(&self) -> &[Variable] {
        &self.variables
    }

    /// Default values of parameters, by name.
    pub fn defaults(&self) -> &HashMap<String, f64> {
        &self.defaults
    }

    /// The parameter names in the order they were declared.
    pub fn declared(&self) -> &[String] {
        &self.declared
    }

    /// The model, if the design has one.
    pub fn model(&self) -> Option<&Model> {
        self.spec.model_ref()
    }

    /// Free text describing the design.
    pub fn description(&self) -> &str {
        self.spec.description_ref()
    }

    /// Comments of the parts, for printing.
    pub fn docs(&self) -> &Docs {
        self.spec.docs_ref()
    }

    /// A builder holding everything this design was built from, to change
    /// and build again (another model, other defaults, more constraints).
    pub fn to_builder(&self) -> DesignBuilder {
        self.spec.clone()
    }

    /// The variable called `name`.
    pub fn variable(&self, name: &str) -> Option<usize> {
        self.variables.iter().position(|v| v.name == name)
    }

    /// The names of all variables, indexed like them.
    pub fn variable_names(&self) -> Vec<String> {
        self.variables.iter().map(|v| v.name.clone()).collect()
    }
}
