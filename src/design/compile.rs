//! [`DesignBuilder::build`]: the items resolved and checked into a [`Design`].

use std::collections::{HashMap, HashSet};

use nalgebra::DMatrix;

use super::builder::{Design, DesignBuilder, EquationItem, MAX_MATRIX_ENTRIES, MAX_UNKNOWNS, NamedEntries};
use super::error::BuildError;
use super::model::{Layout, Model, Origin, Variable};
use super::value::{Field, Locus, Matrix, Value};
use crate::algebra::{Affine, Env, Expr, ExprError};
use crate::automaton::{Arrow, Automaton, Constraint, Relation, selection};
use crate::space::State;

impl DesignBuilder {
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
        Ok(Compiler::new(self).run()?.with_spec(self.clone()))
    }

    /// [`DesignBuilder::build`], keeping this builder in the design without a copy.
    ///
    /// # Errors
    /// As [`DesignBuilder::build`].
    pub fn into_design(self) -> Result<Design, BuildError> {
        Ok(Compiler::new(&self).run()?.with_spec(self))
    }
}

/// What the compiler makes: a [`Design`] but its builder.
struct Compiled {
    automaton: Automaton<Affine>,
    variables: Vec<Variable>,
    defaults: HashMap<String, f64>,
    declared: Vec<String>,
}

impl Compiled {
    fn with_spec(self, spec: DesignBuilder) -> Design {
        let Compiled { automaton, variables, defaults, declared } = self;
        Design { automaton: automaton.into(), variables, defaults, declared, spec, identity: Default::default() }
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

/// Expressions already evaluated (a generated mesh automaton repeats a few
/// entry texts thousands of times): the text's value. One a thread.
type Known = HashMap<String, Affine>;

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

    fn run(mut self) -> Result<Compiled, BuildError> {
        self.states()?;
        let named = self.named_entries()?;
        self.unknowns(named)?;
        // The matrices on the pool's threads, added in order (the first error in that order is the one
        // reported, as if they were made one by one).
        let matrices: Vec<Result<DMatrix<Affine>, BuildError>> = {
            use rayon::prelude::*;
            let this = &self;
            (0..self.spec.arrows.len()).into_par_iter().map_init(Known::new, |known, i| this.matrix(i, known)).collect()
        };
        for (index, matrix) in matrices.into_iter().enumerate() {
            self.add_arrow(index, matrix?)?;
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
        Ok(Compiled { automaton: self.automaton, variables: self.vars, defaults, declared })
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
            self.automaton.add_state(State::new(s.name.clone(), s.dim, s.kind).with_patch(s.patch)).map_err(|_| {
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
            ExprError::UnknownParam(name, off) => at
                .with_message(format!("unknown parameter `{name}` in {what}"))
                .at_offset(off)
                .suggesting(&name, self.var_by_name.keys().map(String::as_str))
                .or_help("declare it as a parameter"),
            other => at.with_message(format!("{what}: {other}")),
        }
    }

    /// An expression of constants and parameters (no matrix entries).
    /// The value of an entry or a default; `at` and `what` (where it is, what it is) are made
    /// only for an error.
    fn value(
        &self,
        known: &mut Known,
        value: &Value,
        at: impl Fn() -> BuildError,
        what: impl Fn() -> String,
    ) -> Result<Affine, BuildError> {
        match value {
            Value::Num(n) => Ok(Affine::constant(n.clone())),
            Value::Text(text) => {
                if let Some(value) = known.get(text) {
                    return Ok(value.clone());
                }
                let (at, what) = (at(), what());
                let expr = Expr::parse(text)
                    .map_err(|e| at.clone().with_message(format!("in {what}: {}", e.message)).at_offset(e.offset))?;
                if let Some((arrow, row, col, off)) = expr.entries().first() {
                    return Err(at
                        .with_message(format!(
                            "{what} cannot refer to the matrix entry {arrow}[{row}][{col}]; use a parameter"
                        ))
                        .at_offset(*off));
                }
                let value =
                    expr.eval(&Symbols { vars: &self.var_by_name }).map_err(|e| self.eval_error(at, e, &what))?;
                known.insert(text.clone(), value.clone());
                Ok(value)
            }
        }
    }

    /// The matrix of arrow `index`, checked against its endpoints.
    fn matrix(&self, index: usize, known: &mut Known) -> Result<DMatrix<Affine>, BuildError> {
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
        Ok(match &arrow.matrix {
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
                        entries.push(self.value(
                            known,
                            e,
                            || self.arrow_error(index, Field::Entry(r, c), ""),
                            || format!("entry [{r}][{c}] of `{name}`"),
                        )?);
                    }
                }
                DMatrix::from_row_iterator(rows, cols, entries)
            }
        })
    }

    fn add_arrow(&mut self, index: usize, matrix: DMatrix<Affine>) -> Result<(), BuildError> {
        let arrow = &self.spec.arrows[index];
        let name = &arrow.name;
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
                let at = || self.param_error(index, Field::Default, "");
                let value = self.value(&mut Known::new(), d, at, || format!("the default of `{}`", p.name))?;
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
        for (k, (state, faces)) in m.start_faces.iter().enumerate() {
            let Some((_, set)) = m.start.iter().find(|(s, _)| s == state) else {
                return Err(Self::model_error(
                    Field::StartFaces(k),
                    format!(
                        "faces over the start set of `{state}`, which has none: give [model.start] {state} = [...]"
                    ),
                ));
            };
            if let Some(face) = faces.iter().find(|f| f.len() < 3 || f.iter().any(|&i| i >= set.len())) {
                return Err(Self::model_error(
                    Field::StartFaces(k),
                    format!(
                        "start faces of `{state}` need at least 3 indices below {} (its start points): {face:?}",
                        set.len()
                    ),
                ));
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
