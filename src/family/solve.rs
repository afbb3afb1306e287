//! The exact BC-IFS constraint solver.
//!
//! Every constraint of a [`Design`] is linear in the unknown entries (each
//! side holds at most one factor that depends on unknowns), and so is every
//! column-sum condition. The solver writes them as one sparse linear system
//! over exact rationals, reduces it to row echelon form and reads off the
//! *admissible family*: every entry as an affine expression of the free
//! variables. Named variables (the user's parameters) are kept free whenever
//! the system allows, so the family prints in the user's letters.
//!
//! Seed: Sokolov, Gentil, Bensoudane, *Tangents to fractal curves and
//! surfaces*, §3.1 (incidence and adjacency constraints).

use std::borrow::Cow;
use std::collections::HashMap;
use std::fmt;
use std::sync::Arc;

use nalgebra::DMatrix;
use num_rational::BigRational;
use num_traits::{One, Zero};
use petgraph::stable_graph::EdgeIndex;

use crate::algebra::{Affine, Env, Expr, ExprError, Num, Surd};
use crate::automaton::{Automaton, Relation};
use crate::design::{Design, Origin};

/// How far from zero an equation between *approximate* constants may be and
/// still hold. Only values outside the exact surds (`sqrt(1 + sqrt(2))`)
/// are approximate; their f64 rounding errors are of order 1e-16. Surds such
/// as `sqrt(3)/6` are compared exactly.
pub const APPROX_TOLERANCE: f64 = 1e-12;

/// Why a design has no admissible family.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SolveError {
    /// A side of a constraint multiplies two factors that depend on unknowns.
    #[error(
        "`{constraint}` is not linear: its {side} side multiplies two matrices that depend on unknowns (at most one factor per side may be unknown)"
    )]
    Nonlinear {
        /// The constraint, `group: text`.
        constraint: String,
        /// `left` or `right`.
        side: &'static str,
    },
    /// An entry equation could not be evaluated.
    #[error("`{constraint}`: {error}")]
    Eval {
        /// The constraint, `group: text`.
        constraint: String,
        /// What went wrong.
        error: ExprError,
    },
    /// An irrational constant multiplies an unknown (the exact solver needs
    /// rational coefficients), or an approximate constant (not a surd) sits in
    /// an equation with unknowns.
    #[error(
        "`{equation}` has an irrational coefficient next to an unknown; the exact solver needs rational coefficients (irrational constants are fine in known matrices and as constant terms)"
    )]
    Irrational {
        /// The scalar equation.
        equation: String,
    },
    /// The system has no solution; the listed equations already conflict.
    #[error("the constraints are inconsistent; these equations conflict:\n  {}", conflicts.join("\n  "))]
    Inconsistent {
        /// A small conflicting subset of the scalar equations.
        conflicts: Vec<String>,
    },
    /// A parameter the user named is fixed by the constraints.
    #[error("parameter `{name}` is not free: the constraints give {name} = {value}")]
    DependentParameter {
        /// The parameter.
        name: String,
        /// Its value in terms of the free parameters.
        value: String,
    },
}

/// A free parameter of an admissible family.
#[derive(Clone, Debug, PartialEq)]
pub struct Parameter {
    /// The name it prints with.
    pub name: String,
    /// What it stands for.
    pub origin: Origin,
    /// Its default value, if the file gives one.
    pub default: Option<f64>,
}

/// The admissible family of a design: every matrix entry as an exact affine
/// expression of the free parameters.
#[derive(Clone, Debug)]
pub struct Family {
    /// The automaton, with entries affine in the free parameters (indexed as [`Family::parameters`]).
    pub automaton: std::sync::Arc<Automaton<Affine>>,
    /// The free parameters (degrees of freedom).
    pub parameters: Vec<Parameter>,
    /// Every variable of the design (name, expression in the free parameters).
    pub variables: Vec<(String, Affine)>,
    /// Number of distinct constraints (one stated twice counts once).
    pub constraints: usize,
    /// Number of scalar equations (constraints entries and column sums) that
    /// hold for some parameter values only: the system solved.
    pub equations: usize,
    /// Number of scalar equations that hold whatever the parameters (equal
    /// entries on both sides, a given matrix's column summing to 1): the
    /// checks that needed no solving. A scheme's automaton, every matrix
    /// given, has only these.
    pub identities: usize,
    /// Rank of the system.
    pub rank: usize,
}

/// One scalar equation `form = 0`, with the text that names it.
#[derive(Clone, Debug)]
pub struct Equation {
    /// `group: text (row i, column j)` or `column sums: T0 column j`.
    pub label: Label,
    /// The affine form that must vanish.
    pub form: Affine,
}

/// The name of an [`Equation`], printed only when it is needed (an error names
/// it): a generated automaton has hundreds of thousands of scalar equations.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Label {
    /// A constraint's name (`group: text`) as written.
    Constraint(Arc<str>),
    /// The entry `(row, column)` of a path constraint.
    Entry {
        /// The constraint's name.
        constraint: Arc<str>,
        /// The row.
        row: usize,
        /// The column.
        column: usize,
    },
    /// The column sum of an arrow's matrix.
    ColumnSum {
        /// The arrow.
        arrow: Arc<str>,
        /// The column.
        column: usize,
    },
}

impl fmt::Display for Label {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Label::Constraint(c) => f.write_str(c),
            Label::Entry { constraint, row, column } => write!(f, "{constraint} (row {row}, column {column})"),
            Label::ColumnSum { arrow, column } => write!(f, "column sums: {arrow} column {column} sums to 1"),
        }
    }
}

struct Symbols<'a> {
    design: &'a Design,
}

impl Env<Affine> for Symbols<'_> {
    fn param(&self, name: &str) -> Option<Affine> {
        self.design.variable(name).map(Affine::var)
    }
    fn entry(&self, arrow: &str, row: usize, col: usize) -> Option<Affine> {
        let a = &self.design.automaton();
        let m = &a.arrow(a.arrow_id(arrow)?).matrix;
        (row < m.nrows() && col < m.ncols()).then(|| m[(row, col)].clone())
    }
}

/// The scalar equations of a design: every entry of every constraint, then
/// every column sum. A constraint stated again (the same equation, in any
/// group) is counted once: 20,000 copies of one made 120,000 equations.
///
/// # Errors
/// [`SolveError::Nonlinear`] or [`SolveError::Eval`] naming the constraint.
pub fn equations(design: &Design) -> Result<Vec<Equation>, SolveError> {
    system(design).map(|s| s.equations)
}

/// A design's scalar equations and how many held without solving.
struct System {
    equations: Vec<Equation>,
    /// Distinct constraints.
    constraints: usize,
    /// Scalar equations that hold identically (dropped from `equations`).
    identities: usize,
}

/// [`equations`], with the counts a report gives.
fn system(design: &Design) -> Result<System, SolveError> {
    use rayon::prelude::*;
    let a = &design.automaton();
    let picks = selections(a);
    let mut seen = std::collections::HashSet::new();
    let unique: Vec<_> = a.constraints().iter().filter(|c| seen.insert(c.text.as_str())).collect();
    // Each constraint's equations on the pool's threads, gathered in the constraints' order (the
    // first error in that order is the one reported).
    let per_constraint: Vec<Result<(Vec<Equation>, usize), SolveError>> = unique
        .par_iter()
        .map(|c| {
            let mut out = Vec::new();
            let mut compared = 0;
            match &c.relation {
                Relation::Paths { lhs, rhs } => {
                    let side = |path: &[_], side| {
                        product_view(a, path, &picks)
                            .map_err(|_| SolveError::Nonlinear { constraint: c.to_string(), side })
                    };
                    let (l, r) = (side(lhs, "left")?, side(rhs, "right")?);
                    let name: Arc<str> = c.to_string().into();
                    compared += l.matrix.nrows() * l.ncols();
                    for row in 0..l.matrix.nrows() {
                        for column in 0..l.ncols() {
                            let (l, r) = (l.at(row, column), r.at(row, column));
                            // Most entries of a constraint that holds are equal forms: no difference made.
                            if l == r {
                                continue;
                            }
                            let form = l.sub(r);
                            if !form.is_zero() {
                                let label = Label::Entry { constraint: name.clone(), row, column };
                                out.push(Equation { label, form });
                            }
                        }
                    }
                }
                Relation::Entries { lhs, rhs } => {
                    let env = Symbols { design };
                    let eval =
                        |e: &Expr| e.eval(&env).map_err(|error| SolveError::Eval { constraint: c.to_string(), error });
                    let form = eval(lhs)?.sub(&eval(rhs)?);
                    compared += 1;
                    if !form.is_zero() {
                        out.push(Equation { label: Label::Constraint(c.to_string().into()), form });
                    }
                }
            }
            Ok((out, compared))
        })
        .collect();
    let mut out = Vec::new();
    let mut compared = 0;
    for equations in per_constraint {
        let (equations, count) = equations?;
        out.extend(equations);
        compared += count;
    }
    for (_, arrow) in a.arrows() {
        let name: Arc<str> = arrow.name.as_str().into();
        compared += arrow.matrix.ncols();
        for column in 0..arrow.matrix.ncols() {
            let sum = arrow.matrix.column(column).iter().fold(Affine::zero(), |acc, e| acc.add(e));
            let form = sum.sub(&Affine::one());
            if !form.is_zero() {
                out.push(Equation { label: Label::ColumnSum { arrow: name.clone(), column }, form });
            }
        }
    }
    Ok(System { identities: compared - out.len(), constraints: unique.len(), equations: out })
}

/// The arrows whose matrices select columns (one entry exactly one in each
/// column, the others exactly zero: the boundary and turning arrows of a
/// generated automaton): the row each column picks.
fn selections(a: &Automaton<Affine>) -> HashMap<EdgeIndex, Vec<usize>> {
    use rayon::prelude::*;
    let arrows: Vec<_> = a.arrows().collect();
    arrows
        .par_iter()
        .filter_map(|(id, arrow)| {
            let m = &arrow.matrix;
            let pick = (0..m.ncols()).map(|j| {
                let column = m.column(j);
                let one = column.iter().position(Affine::is_one)?;
                column.iter().enumerate().all(|(i, e)| i == one || e.is_zero()).then_some(one)
            });
            Some((*id, pick.collect::<Option<Vec<usize>>>()?))
        })
        .collect()
}

/// A path's product as a matrix and the columns of it that its trailing
/// selections keep (composed, not multiplied out): entry `(i, j)` of the
/// product is the matrix's `(i, pick[j])`. A constraint `T0 b1 = T1 b0`
/// compares entries of `T0` and `T1` in place.
struct PathView<'a> {
    matrix: Cow<'a, DMatrix<Affine>>,
    pick: Option<Vec<usize>>,
}

impl PathView<'_> {
    fn ncols(&self) -> usize {
        self.pick.as_ref().map_or(self.matrix.ncols(), Vec::len)
    }

    fn at(&self, row: usize, column: usize) -> &Affine {
        &self.matrix[(row, self.pick.as_ref().map_or(column, |p| p[column]))]
    }
}

/// The [`PathView`] of `path`.
///
/// # Errors
/// A product of two matrices with unknowns.
fn product_view<'a>(
    a: &'a Automaton<Affine>,
    path: &[EdgeIndex],
    picks: &HashMap<EdgeIndex, Vec<usize>>,
) -> Result<PathView<'a>, ExprError> {
    let tail = path.iter().rev().take_while(|id| picks.contains_key(id)).count();
    let head = &path[..path.len() - tail];
    if tail == 0 || head.is_empty() {
        return Ok(PathView { matrix: Cow::Owned(a.product(path)?), pick: None });
    }
    let matrix = match head {
        [one] => Cow::Borrowed(&a.arrow(*one).matrix),
        _ => Cow::Owned(a.product(head)?),
    };
    let mut pick = picks[&path[path.len() - 1]].clone();
    for id in path[head.len()..path.len() - 1].iter().rev() {
        pick = pick.iter().map(|&j| picks[id][j]).collect();
    }
    Ok(PathView { matrix, pick: Some(pick) })
}

/// A sparse row `Σ c_v x_v + constant = 0` with the set of input equations
/// it was combined from.
#[derive(Clone, Debug)]
struct Row {
    terms: Vec<(usize, BigRational)>,
    constant: Surd,
    origins: Vec<u64>,
}

impl Row {
    fn coeff(&self, var: usize) -> Option<&BigRational> {
        self.terms.binary_search_by_key(&var, |(v, _)| *v).ok().map(|i| &self.terms[i].1)
    }

    /// `self - k · other`.
    fn sub_scaled(&self, other: &Row, k: &BigRational) -> Row {
        let mut terms = Vec::with_capacity(self.terms.len() + other.terms.len());
        let (mut i, mut j) = (0, 0);
        while i < self.terms.len() || j < other.terms.len() {
            let left = self.terms.get(i).map(|t| t.0);
            let right = other.terms.get(j).map(|t| t.0);
            match (left, right) {
                (Some(a), Some(b)) if a == b => {
                    let c = &self.terms[i].1 - k * &other.terms[j].1;
                    if !c.is_zero() {
                        terms.push((a, c));
                    }
                    i += 1;
                    j += 1;
                }
                (Some(a), Some(b)) if a < b => {
                    terms.push(self.terms[i].clone());
                    i += 1;
                }
                (Some(a), None) => {
                    terms.push((a, self.terms[i].1.clone()));
                    i += 1;
                }
                (_, Some(b)) => {
                    terms.push((b, -(k * &other.terms[j].1)));
                    j += 1;
                }
                (None, None) => unreachable!(),
            }
        }
        let origins = self.origins.iter().zip(&other.origins).map(|(a, b)| a | b).collect();
        Row { terms, constant: self.constant.add_scaled(&other.constant, &-k), origins }
    }

    fn scale(&mut self, k: &BigRational) {
        for (_, c) in &mut self.terms {
            *c = &*c * k;
        }
        self.constant = self.constant.scale(k);
    }

    fn origin_list(&self) -> Vec<usize> {
        let mut out = Vec::new();
        for (w, bits) in self.origins.iter().enumerate() {
            for b in 0..64 {
                if bits >> b & 1 == 1 {
                    out.push(w * 64 + b);
                }
            }
        }
        out
    }
}

/// Incremental Gauss-Jordan elimination: rows stay fully reduced.
struct Eliminator {
    rows: Vec<Row>,
    pivot_of: HashMap<usize, usize>,
    /// Pivot preference: lower keys become pivots first.
    key: Vec<(bool, usize)>,
}

impl Eliminator {
    fn new(key: Vec<(bool, usize)>) -> Eliminator {
        Eliminator { rows: Vec::new(), pivot_of: HashMap::new(), key }
    }

    /// Adds a row; returns the reduced row if it reads `0 = c ≠ 0`.
    fn insert(&mut self, mut row: Row) -> Result<(), Box<Row>> {
        let hits: Vec<(usize, BigRational)> =
            row.terms.iter().filter(|(v, _)| self.pivot_of.contains_key(v)).cloned().collect();
        for (v, c) in hits {
            row = row.sub_scaled(&self.rows[self.pivot_of[&v]], &c);
        }
        let Some(&(pivot, ref pc)) = row.terms.iter().min_by_key(|(v, _)| self.key[*v]) else {
            return if row.constant.is_zero() { Ok(()) } else { Err(Box::new(row)) };
        };
        let inv = BigRational::one() / pc;
        row.scale(&inv);
        for other in &mut self.rows {
            if let Some(c) = other.coeff(pivot).cloned() {
                *other = other.sub_scaled(&row, &c);
            }
        }
        self.pivot_of.insert(pivot, self.rows.len());
        self.rows.push(row);
        Ok(())
    }
}

fn to_row(eq: &Equation, index: usize, words: usize) -> Result<Row, SolveError> {
    let irrational = || SolveError::Irrational { equation: eq.label.to_string() };
    let terms = eq
        .form
        .terms()
        .iter()
        .map(|(v, c)| Ok((*v, c.as_rational().ok_or_else(irrational)?)))
        .collect::<Result<_, _>>()?;
    let constant = match eq.form.constant_term() {
        Num::Exact(s) => s.clone(),
        Num::Approx(_) => return Err(irrational()),
    };
    let mut origins = vec![0u64; words];
    origins[index / 64] |= 1 << (index % 64);
    Ok(Row { terms, constant, origins })
}

fn inconsistent(rows: &[&Row], key: &[(bool, usize)]) -> bool {
    let mut e = Eliminator::new(key.to_vec());
    rows.iter().any(|r| e.insert((*r).clone()).is_err())
}

/// Solves the constraints of `design` exactly.
///
/// Complexity: Gauss-Jordan elimination on sparse rational rows,
/// `O(equations · rank · row length)` rational operations; the quad patch of
/// `automata/doo_sabin_quad.toml` (484 unknowns) solves in milliseconds.
///
/// # Errors
/// A nonlinear constraint, an irrational coefficient next to an unknown, an
/// inconsistent system (with a small conflicting subset of its equations),
/// or a named parameter that the constraints fix.
///
/// # Example
/// ```
/// let design = bcifs::builtin_design("corner_cutting").unwrap();
/// let family = bcifs::solve(&design).unwrap();
/// assert_eq!(family.parameters.len(), 2);
/// assert_eq!(family.entry_text("T0", 0, 0), "1 - a");
/// ```
pub fn solve(design: &Design) -> Result<Family, SolveError> {
    solution(design).clone()
}

/// [`solve`] without a copy: the solution the design keeps (it is solved once).
///
/// # Example
/// ```
/// let design = bcifs::builtin_design("corner_cutting").unwrap();
/// let family = bcifs::family::solution(&design).as_ref().unwrap();
/// assert_eq!(family.dof(), 2);
/// ```
pub fn solution(design: &Design) -> &Result<Family, SolveError> {
    let cached = design.solved.0.get_or_init(|| Box::new(solve_now(design)));
    // The cache holds only what this function puts in it.
    cached.downcast_ref::<Result<Family, SolveError>>().expect("a design's cache holds its solution")
}

/// [`solve`], computed.
fn solve_now(design: &Design) -> Result<Family, SolveError> {
    let System { equations: mut eqs, constraints, mut identities } = system(design)?;
    // Equations between approximate constants (values outside the surds)
    // cannot be decided exactly: they hold or fail numerically, and then take
    // no part in the system. Surds are exact and go through the elimination.
    if let Some(bad) = eqs.iter().find(|e| {
        e.form.terms().is_empty()
            && !e.form.constant_term().is_exact()
            && e.form.constant_term().to_f64().abs() > APPROX_TOLERANCE
    }) {
        return Err(SolveError::Inconsistent { conflicts: vec![bad.label.to_string()] });
    }
    let before = eqs.len();
    eqs.retain(|e| !e.form.terms().is_empty() || e.form.constant_term().is_exact());
    identities += before - eqs.len();
    let elim = eliminate(design, &eqs)?;
    let mut family = family_of(design, &elim, eqs.len())?;
    family.constraints = constraints;
    family.identities = identities;
    Ok(family)
}

/// The reduced system of `eqs`, or the smallest conflicting subset found.
fn eliminate(design: &Design, eqs: &[Equation]) -> Result<Eliminator, SolveError> {
    let words = eqs.len().div_ceil(64).max(1);
    let key: Vec<(bool, usize)> = design.variables().iter().enumerate().map(|(i, v)| (v.named, i)).collect();
    let rows: Vec<Row> = eqs.iter().enumerate().map(|(i, e)| to_row(e, i, words)).collect::<Result<_, _>>()?;
    let mut elim = Eliminator::new(key.clone());
    for row in &rows {
        if let Err(bad) = elim.insert(row.clone()) {
            let mut subset: Vec<usize> = bad.origin_list();
            // Deletion filter: drop every equation whose removal keeps the conflict.
            let mut i = 0;
            while i < subset.len() {
                let trial: Vec<&Row> =
                    subset.iter().enumerate().filter(|(k, _)| *k != i).map(|(_, &e)| &rows[e]).collect();
                if inconsistent(&trial, &key) {
                    subset.remove(i);
                } else {
                    i += 1;
                }
            }
            return Err(SolveError::Inconsistent {
                conflicts: subset.iter().map(|&e| eqs[e].label.to_string()).collect(),
            });
        }
    }
    Ok(elim)
}

/// The family read off the reduced system: every variable in the free ones.
fn family_of(design: &Design, elim: &Eliminator, equations: usize) -> Result<Family, SolveError> {
    // Free variables: the user's names in declaration order, then the others.
    let nvars = design.variables().len();
    let mut free: Vec<usize> = (0..nvars).filter(|v| !elim.pivot_of.contains_key(v)).collect();
    let declared_rank = |v: usize| design.declared().iter().position(|n| *n == design.variables()[v].name);
    free.sort_by_key(|&v| (declared_rank(v).is_none(), declared_rank(v), v));
    let free_index: HashMap<usize, usize> = free.iter().enumerate().map(|(i, &v)| (v, i)).collect();

    let expression = |v: usize| -> Affine {
        match elim.pivot_of.get(&v) {
            None => Affine::var(free_index[&v]),
            Some(&r) => {
                let row = &elim.rows[r];
                let mut out = Affine::constant(Num::Exact(row.constant.neg()));
                for (w, c) in &row.terms {
                    if *w != v {
                        out = out.add_scaled(&Affine::var(free_index[w]), &Num::rational(-c.clone()));
                    }
                }
                out
            }
        }
    };
    let variables: Vec<(String, Affine)> =
        design.variables().iter().enumerate().map(|(v, var)| (var.name.clone(), expression(v))).collect();
    let free_names: Vec<String> = free.iter().map(|&v| design.variables()[v].name.clone()).collect();
    if let Some((v, var)) =
        design.variables().iter().enumerate().find(|(v, var)| var.named && elim.pivot_of.contains_key(v))
    {
        return Err(SolveError::DependentParameter {
            name: var.name.clone(),
            value: variables[v].1.display(&free_names).to_string(),
        });
    }
    // Every matrix with the variables replaced, on the pool's threads; the design's, shared, when every variable
    // is free and keeps its number (a generated mesh automaton's weights), as the substitution
    // would give the same forms.
    let identity = variables.iter().enumerate().all(|(v, (_, form))| *form == Affine::var(v));
    let automaton = if identity {
        design.shared_automaton()
    } else {
        design
            .automaton()
            .par_map_matrices(|arrow| arrow.matrix.map(|e| e.substitute(&|v| variables[v].1.clone())))
            .into()
    };
    let parameters = free
        .iter()
        .map(|&v| {
            let var = &design.variables()[v];
            Parameter {
                name: var.name.clone(),
                origin: var.origin.clone(),
                default: design.defaults().get(&var.name).copied(),
            }
        })
        .collect();
    Ok(Family { automaton, parameters, variables, constraints: 0, equations, identities: 0, rank: elim.rows.len() })
}

/// Why parameter values could not be applied.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum InstantiateError {
    /// A value was given for a name that is not a free parameter.
    #[error(
        "`{name}` is not a free parameter{}; the free parameters are {}",
        help.as_ref().map(|h| format!(" (did you mean `{h}`?)")).unwrap_or_default(),
        if free.is_empty() { "none".to_string() } else { free.iter().map(|n| format!("`{n}`")).collect::<Vec<_>>().join(", ") }
    )]
    UnknownParameter {
        /// The name given.
        name: String,
        /// The closest parameter name.
        help: Option<String>,
        /// The free parameters.
        free: Vec<String>,
    },
    /// A value that is not a finite number.
    #[error("`{name}` = {value}: parameter values must be finite numbers")]
    NotFinite {
        /// The parameter.
        name: String,
        /// The value given.
        value: f64,
    },
    /// Free parameters with neither a value nor a default.
    #[error("no value for {}: pass --param NAME=VALUE or give a default in [parameters]", names.iter().map(|n| format!("`{n}`")).collect::<Vec<_>>().join(", "))]
    Missing {
        /// The parameters without a value.
        names: Vec<String>,
    },
}

/// An automaton with numbers, and the values that made it.
#[derive(Clone, Debug)]
pub struct Instance {
    /// The numeric automaton.
    pub automaton: Automaton<f64>,
    /// The free parameter values used, in order.
    pub parameters: Vec<(String, f64)>,
    /// The value of every variable of the design, by name.
    pub values: HashMap<String, f64>,
}

impl Family {
    /// Number of free parameters.
    pub fn dof(&self) -> usize {
        self.parameters.len()
    }

    /// The names of the free parameters.
    pub fn parameter_names(&self) -> Vec<String> {
        self.parameters.iter().map(|p| p.name.clone()).collect()
    }

    /// The entry `arrow[row][col]` printed with the parameter names.
    ///
    /// # Panics
    /// If there is no such arrow or entry.
    pub fn entry_text(&self, arrow: &str, row: usize, col: usize) -> String {
        let a = &self.automaton;
        let id = a.arrow_id(arrow).unwrap_or_else(|| panic!("no arrow `{arrow}`"));
        a.arrow(id).matrix[(row, col)].display(&self.parameter_names()).to_string()
    }

    /// Every matrix printed with the parameter names: `(arrow, rows of entries)`.
    pub fn matrices_text(&self) -> Vec<(String, Vec<Vec<String>>)> {
        use rayon::prelude::*;
        let names = self.parameter_names();
        let arrows: Vec<_> = self.automaton.arrows().collect();
        arrows
            .par_iter()
            .map(|(_, a)| {
                // Most entries of a large automaton's matrices are 0: printed without the formatter.
                let text = |e: &Affine| if e.is_zero() { "0".to_owned() } else { e.display(&names).to_string() };
                let rows = (0..a.matrix.nrows())
                    .map(|i| (0..a.matrix.ncols()).map(|j| text(&a.matrix[(i, j)])).collect())
                    .collect();
                (a.name.clone(), rows)
            })
            .collect()
    }

    /// Every matrix as `bcifs solve` prints it: per arrow a blank line,
    /// `NAME =`, then its rows as `  [ a  b  c ]`, each entry right-aligned
    /// to the matrix's longest ([`Family::matrices_text`]'s entries, laid
    /// out). Each matrix is written into one buffer, on the pool's threads:
    /// a large generated automaton has hundreds of thousands of entries.
    ///
    /// ```
    /// let design = bcifs::builtin_design("corner_cutting").unwrap();
    /// let family = bcifs::solve(&design).unwrap();
    /// let text = family.matrices_report();
    /// assert!(text.starts_with("\nT0 =\n  [ "), "{text}");
    /// assert_eq!(text.lines().filter(|l| l.ends_with(" =")).count(), family.matrices_text().len());
    /// ```
    pub fn matrices_report(&self) -> String {
        use rayon::prelude::*;
        use std::fmt::Write;
        let names = self.parameter_names();
        let arrows: Vec<_> = self.automaton.arrows().collect();
        let blocks: Vec<String> = arrows
            .par_iter()
            .map(|(_, a)| {
                let m = &a.matrix;
                // The entries one after another, and where each ends.
                let (mut cells, mut ends) = (String::new(), Vec::with_capacity(m.len()));
                for i in 0..m.nrows() {
                    for j in 0..m.ncols() {
                        let e = &m[(i, j)];
                        if e.is_zero() {
                            cells.push('0');
                        } else {
                            let _ = write!(cells, "{}", e.display(&names));
                        }
                        ends.push(cells.len());
                    }
                }
                let cell = |k: usize| &cells[if k == 0 { 0 } else { ends[k - 1] }..ends[k]];
                // Aligned as `{:>width$}` aligns (in characters) to the longest entry in bytes.
                let width = (0..ends.len()).map(|k| cell(k).len()).max().unwrap_or(1);
                let mut out = String::with_capacity(a.name.len() + 4 + m.nrows() * (6 + m.ncols() * (width + 2)));
                let _ = writeln!(out, "\n{} =", a.name);
                for i in 0..m.nrows() {
                    out.push_str("  [ ");
                    for j in 0..m.ncols() {
                        let text = cell(i * m.ncols() + j);
                        if j > 0 {
                            out.push_str("  ");
                        }
                        out.extend(std::iter::repeat_n(' ', width.saturating_sub(text.chars().count())));
                        out.push_str(text);
                    }
                    out.push_str(" ]\n");
                }
                out
            })
            .collect();
        blocks.concat()
    }

    /// Instantiates the family: given values, then the file's defaults.
    ///
    /// # Errors
    /// A value for an unknown name, or a parameter with no value at all.
    pub fn instantiate(&self, values: &[(String, f64)]) -> Result<Instance, InstantiateError> {
        let x = self.parameter_values(values)?;
        let automaton = numeric(&self.automaton, &x);
        let values = self.variables.iter().map(|(n, e)| (n.clone(), e.eval(&x))).collect();
        Ok(Instance { automaton, parameters: self.parameter_names().into_iter().zip(x).collect(), values })
    }

    /// The matrix of arrow `arrow` at exact parameter values `x` (in the
    /// order of [`Family::parameter_names`]), when every entry is rational.
    pub fn exact_matrix(&self, arrow: &str, x: &[Num]) -> Option<Vec<Vec<BigRational>>> {
        let m = &self.automaton.arrow(self.automaton.arrow_id(arrow)?).matrix;
        (0..m.nrows()).map(|r| (0..m.ncols()).map(|c| m[(r, c)].eval_num(x).as_rational()).collect()).collect()
    }

    /// The value of every free parameter, in order: `values` where given,
    /// the defaults elsewhere.
    ///
    /// # Errors
    /// As [`Family::instantiate`].
    pub fn parameter_values(&self, values: &[(String, f64)]) -> Result<Vec<f64>, InstantiateError> {
        let names = self.parameter_names();
        for (name, value) in values {
            if !names.contains(name) {
                let help = crate::names::suggest(name, names.iter().map(String::as_str));
                return Err(InstantiateError::UnknownParameter { name: name.clone(), help, free: names.clone() });
            }
            if !value.is_finite() {
                return Err(InstantiateError::NotFinite { name: name.clone(), value: *value });
            }
        }
        let mut x = Vec::with_capacity(names.len());
        let mut missing = Vec::new();
        for p in &self.parameters {
            match values.iter().rev().find(|(n, _)| *n == p.name).map(|(_, v)| *v).or(p.default) {
                Some(v) => x.push(v),
                None => {
                    missing.push(p.name.clone());
                    x.push(f64::NAN);
                }
            }
        }
        if !missing.is_empty() {
            return Err(InstantiateError::Missing { names: missing });
        }
        Ok(x)
    }
}

/// A family prepared for many instantiations (a parameter map): the
/// numeric automaton is built once, and [`NumericFamily::fill`] rewrites
/// only the entries that depend on parameters, from floating-point
/// coefficients.
#[derive(Clone, Debug)]
pub struct NumericFamily {
    template: Automaton<f64>,
    /// `(arrow, row, col, constant, terms)` of every entry with terms.
    entries: Vec<NumericEntry>,
}

/// An entry of a [`NumericFamily`] that depends on parameters.
type NumericEntry = (petgraph::graph::EdgeIndex, usize, usize, f64, Vec<(usize, f64)>);

impl NumericFamily {
    /// Prepares `family`.
    pub fn new(family: &Family) -> NumericFamily {
        let mut entries = Vec::new();
        for (id, arrow) in family.automaton.arrows() {
            let m = &arrow.matrix;
            for (r, c) in (0..m.nrows()).flat_map(|r| (0..m.ncols()).map(move |c| (r, c))) {
                let (constant, terms) = m[(r, c)].to_f64_terms();
                if !terms.is_empty() {
                    entries.push((id, r, c, constant, terms));
                }
            }
        }
        let zeros = vec![0.0; family.parameters.len()];
        NumericFamily { template: numeric(&family.automaton, &zeros), entries }
    }

    /// A numeric automaton to [`NumericFamily::fill`] (one per thread).
    pub fn automaton(&self) -> Automaton<f64> {
        self.template.clone()
    }

    /// Writes the family's matrices at parameter values `x` (in the order of
    /// [`Family::parameter_names`]) into `automaton`, one made by
    /// [`NumericFamily::automaton`].
    pub fn fill(&self, x: &[f64], automaton: &mut Automaton<f64>) {
        for (id, r, c, constant, terms) in &self.entries {
            automaton.arrow_mut(*id).matrix[(*r, *c)] = terms.iter().fold(*constant, |acc, (v, k)| acc + k * x[*v]);
        }
    }
}

/// Evaluates every entry of `automaton` at variable values `x`.
pub fn numeric(automaton: &Automaton<Affine>, x: &[f64]) -> Automaton<f64> {
    automaton
        .map_matrices(|_, arrow| Ok::<DMatrix<f64>, ()>(arrow.matrix.map(|e| e.eval(x))))
        .expect("evaluation does not fail")
}

/// Why a design could not be turned into numbers.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum DesignInstantiateError {
    /// The constraints have no solution with unknowns.
    #[error(transparent)]
    Solve(#[from] SolveError),
    /// Bad or missing parameter values.
    #[error(transparent)]
    Values(#[from] InstantiateError),
}

/// Numbers for a design: its family instantiated with `values` (then the
/// defaults). A design without unknown matrices is instantiated directly even
/// when its constraints fail, so that [`crate::analysis::check`] can report
/// the residuals.
///
/// # Errors
/// A solver error for a design with unknowns, or bad parameter values.
pub fn instantiate(design: &Design, values: &[(String, f64)]) -> Result<Instance, DesignInstantiateError> {
    match solution(design) {
        Ok(family) => Ok(family.instantiate(values)?),
        Err(SolveError::Inconsistent { .. }) if design.variables().iter().all(|v| v.origin == Origin::Parameter) => {
            let family = Family {
                automaton: design.shared_automaton(),
                parameters: design
                    .variables()
                    .iter()
                    .map(|v| Parameter {
                        name: v.name.clone(),
                        origin: v.origin.clone(),
                        default: design.defaults().get(&v.name).copied(),
                    })
                    .collect(),
                variables: design
                    .variables()
                    .iter()
                    .enumerate()
                    .map(|(i, v)| (v.name.clone(), Affine::var(i)))
                    .collect(),
                constraints: 0,
                equations: 0,
                identities: 0,
                rank: 0,
            };
            Ok(family.instantiate(values)?)
        }
        Err(e) => Err(e.clone().into()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{PolyMesh, Scheme};

    /// A path's view (trailing selections and turns composed, not multiplied
    /// out) has the entries of its product, on shipped automata with
    /// selections and on generated ones whose paths end in a boundary and a turn.
    #[test]
    fn a_path_view_is_its_product() {
        let cube = PolyMesh::cube();
        let mut designs: Vec<Design> =
            ["corner_cutting", "doo_sabin_quad", "koch"].map(|n| crate::format::builtin_design(n).unwrap()).into();
        for scheme in [Scheme::CatmullClark, Scheme::DooSabin] {
            designs.push(crate::schemes::mesh_automaton(&cube, scheme, None).unwrap());
        }
        let mut composed = 0;
        for design in &designs {
            let a = design.automaton();
            let picks = selections(a);
            assert!(!picks.is_empty(), "{}", design.name());
            for c in a.constraints() {
                let Relation::Paths { lhs, rhs } = &c.relation else { continue };
                for path in [lhs, rhs] {
                    let (view, product) = (product_view(a, path, &picks).unwrap(), a.product(path).unwrap());
                    assert_eq!(view.ncols(), product.ncols());
                    for (i, j) in (0..product.nrows()).flat_map(|i| (0..product.ncols()).map(move |j| (i, j))) {
                        assert_eq!(view.at(i, j), &product[(i, j)], "{}: {c} at ({i}, {j})", design.name());
                    }
                    composed += usize::from(path.iter().rev().take_while(|id| picks.contains_key(*id)).count() > 1);
                }
            }
        }
        assert!(composed > 0, "no path ends in two selections");
    }

    /// A family whose variables are all free and keep their numbers (a
    /// generated automaton's weights) shares the design's matrices, which are
    /// those the substitution gives.
    #[test]
    fn an_identity_substitution_shares_the_design() {
        let design = crate::schemes::mesh_automaton(&PolyMesh::cube(), Scheme::CatmullClark, None).unwrap();
        let family = solve(&design).unwrap();
        assert!(family.variables.iter().enumerate().all(|(v, (_, form))| *form == Affine::var(v)));
        assert!(std::sync::Arc::ptr_eq(&family.automaton, &design.shared_automaton()));
        assert!(!family.variables.is_empty());
        for (id, arrow) in design.automaton().arrows() {
            let substituted = arrow.matrix.map(|e| e.substitute(&|v| family.variables[v].1.clone()));
            assert_eq!(family.automaton.arrow(id).matrix, substituted, "{}", arrow.name);
        }
    }
}
