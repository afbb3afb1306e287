//! The checked builder: the one way a [`Design`] is made, by the file
//! parser, by every scheme generator and by code.
//!
//! Items are recorded as given (names, not indices); [`DesignBuilder::build`]
//! resolves and checks everything and either returns a design whose parts
//! agree or a [`BuildError`] naming the item at fault. It never panics.

use std::collections::HashMap;

use super::model::{Docs, Model, Variable};
use super::value::{Matrix, Value};
use crate::algebra::Affine;
use crate::automaton::{ArrowKind, Automaton};
use crate::space::{CellKind, Patch};

/// Most entries of one matrix (a 2000 × 2000 matrix): larger dimensions are mistakes.
pub const MAX_MATRIX_ENTRIES: usize = 4_000_000;

/// Most unknowns of a constraint system: the exact solver stays within
/// seconds and a few hundred megabytes (the quad patch has 484).
pub const MAX_UNKNOWNS: usize = 20_000;

/// Parameters that name entries, by entry: `(name, order of the parameter)`.
pub(super) type NamedEntries = HashMap<(String, usize, usize), (String, usize)>;

#[derive(Clone, Debug, PartialEq)]
pub(super) struct StateItem {
    pub(super) name: String,
    pub(super) dim: usize,
    pub(super) kind: CellKind,
    pub(super) patch: Option<Patch>,
}

#[derive(Clone, Debug, PartialEq)]
pub(super) struct ArrowItem {
    pub(super) name: String,
    pub(super) from: String,
    pub(super) to: String,
    pub(super) kind: ArrowKind,
    pub(super) matrix: Matrix,
}

#[derive(Clone, Debug, PartialEq)]
pub(super) struct EquationItem {
    pub(super) group: String,
    pub(super) text: String,
}

#[derive(Clone, Debug, PartialEq)]
pub(super) struct ParamItem {
    pub(super) name: String,
    pub(super) entry: Option<String>,
    pub(super) default: Option<Value>,
}

#[derive(Clone, Debug, Default, PartialEq)]
pub(super) enum Last {
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
/// // The local corner-cutting curve of Sokolov et al. 2010 §3, as in automata/corner_cutting.toml.
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
    pub(super) name: String,
    pub(super) description: String,
    pub(super) states: Vec<StateItem>,
    pub(super) arrows: Vec<ArrowItem>,
    pub(super) equations: Vec<EquationItem>,
    pub(super) parameters: Vec<ParamItem>,
    pub(super) orphan_defaults: Vec<(String, Value)>,
    pub(super) model: Option<Model>,
    pub(super) docs: Docs,
    pub(super) last: Last,
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
        self.states.push(StateItem { name, dim, kind, patch: None });
        self
    }

    /// The patch the control points of the state added last make ([`Patch`]):
    /// what a porosity measures its cells on.
    pub fn patch(&mut self, patch: Patch) -> &mut Self {
        if let (Last::State(name), Some(s)) = (&self.last, self.states.last_mut())
            && s.name == *name
        {
            s.patch = Some(patch);
        }
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

    /// A comment on the last equation given (what it glues), written above
    /// it in its group; the group keeps its own [`DesignBuilder::doc`].
    pub fn explain(&mut self, text: impl Into<String>) -> &mut Self {
        if let Last::Group(group) = &self.last
            && let Some(e) = self.equations.iter().rev().find(|e| &e.group == group)
        {
            self.docs.equations.insert(e.text.clone(), text.into());
        }
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

    /// This builder (the design at `name = origin`) with every known entry
    /// made affine in a new plain parameter `name`, from `next` and `third`,
    /// the same design at `name = origin + 1` and `origin + 2`: an entry is
    /// `e + (e' − e)·(name − origin)`, checked on the third. For families
    /// whose entries are affine in one constant (the ternary scheme's
    /// tension ω in its curves).
    ///
    /// # Errors
    /// The designs differ in anything but their known entries, an entry is
    /// already an expression, or an entry is not affine (the third differs).
    pub(crate) fn affine_in(
        mut self,
        [next, third]: [&DesignBuilder; 2],
        name: &str,
        origin: &crate::algebra::Num,
    ) -> Result<DesignBuilder, String> {
        if self.arrows.len() != next.arrows.len() || self.arrows.len() != third.arrows.len() {
            return Err("the designs have different arrows".into());
        }
        for ((a, b), c) in self.arrows.iter_mut().zip(&next.arrows).zip(&third.arrows) {
            match (&mut a.matrix, &b.matrix, &c.matrix) {
                (Matrix::Rows(ra), Matrix::Rows(rb), Matrix::Rows(rc))
                    if ra.len() == rb.len() && ra.len() == rc.len() =>
                {
                    for ((row_a, row_b), row_c) in ra.iter_mut().zip(rb).zip(rc) {
                        if row_a.len() != row_b.len() || row_a.len() != row_c.len() {
                            return Err(format!("arrow `{}`: the matrices differ in shape", a.name));
                        }
                        for ((ea, eb), ec) in row_a.iter_mut().zip(row_b).zip(row_c) {
                            let (Value::Num(e0), Value::Num(e1), Value::Num(e2)) = (&*ea, eb, ec) else {
                                return Err(format!("arrow `{}`: an entry is already an expression", a.name));
                            };
                            let slope = e1.sub(e0);
                            if e2.sub(e1) != slope {
                                return Err(format!(
                                    "arrow `{}`: its entries are not affine in {name} (products of blocks are not)",
                                    a.name
                                ));
                            }
                            if !slope.is_zero() {
                                let constant = e0.sub(&slope.mul(origin));
                                let slope = slope.to_string();
                                let term = match slope.strip_prefix('-') {
                                    Some("1") => format!("- {name}"),
                                    Some(s) => format!("- {s}*{name}"),
                                    None if slope == "1" => format!("+ {name}"),
                                    None => format!("+ {slope}*{name}"),
                                };
                                let text = if constant.is_zero() {
                                    term.trim_start_matches("+ ").replace("- ", "-")
                                } else {
                                    format!("{constant} {term}")
                                };
                                *ea = Value::Text(text);
                            }
                        }
                    }
                }
                (ma, mb, mc) if ma == mb && mb == mc => {}
                _ => return Err(format!("arrow `{}`: the designs differ in more than known entries", a.name)),
            }
        }
        self.parameter(name);
        Ok(self)
    }

    pub(crate) fn description_text(&self) -> &str {
        &self.description
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
    pub(crate) fn state_items(&self) -> impl Iterator<Item = (&str, usize, CellKind, Option<Patch>)> {
        self.states.iter().map(|s| (s.name.as_str(), s.dim, s.kind, s.patch))
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
}

/// An automaton whose entries are affine in the variables of its constraint
/// system, made by a [`DesignBuilder`] (from a file, a generator or code),
/// with its model.
///
/// Its parts agree by construction: every variable of an entry exists, every
/// parameter is declared, the model's roots and start sets name states.
#[derive(Clone, Debug)]
pub struct Design {
    pub(super) automaton: std::sync::Arc<Automaton<Affine>>,
    pub(super) variables: Vec<Variable>,
    pub(super) defaults: HashMap<String, f64>,
    pub(super) declared: Vec<String>,
    pub(super) spec: DesignBuilder,
    /// Who the design is: clones share it, so the family layer keeps one
    /// solution for a design and its clones ([`crate::family::solution`]).
    pub(crate) identity: Identity,
}

/// A design's identity: a design does not change once built, so every
/// render, check and request of a server can share one solution, kept by
/// the family layer under this identity (and dropped with its last clone).
#[derive(Clone, Default)]
pub(crate) struct Identity(pub(crate) std::sync::Arc<()>);

impl std::fmt::Debug for Identity {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("design")
    }
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

    /// The automaton, shared (a family whose forms are the design's holds it too).
    pub(crate) fn shared_automaton(&self) -> std::sync::Arc<Automaton<Affine>> {
        self.automaton.clone()
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
