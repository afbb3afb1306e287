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

use std::collections::HashMap;

use nalgebra::DMatrix;
use num_rational::BigRational;

use super::eliminate::{Eliminator, eliminate};
use super::equations::{System, system};
use super::error::{APPROX_TOLERANCE, SolveError};
use crate::algebra::{Affine, Num};
use crate::automaton::Automaton;
use crate::design::{Design, Origin};

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
    solution(design).as_ref().clone()
}

/// [`solve`] without a copy: the design's solution, computed once for a
/// design and its clones (a server's requests share it).
///
/// # Example
/// ```
/// let design = bcifs::builtin_design("corner_cutting").unwrap();
/// let family = bcifs::solution(&design);
/// assert_eq!(family.as_ref().as_ref().unwrap().dof(), 2);
/// assert!(std::sync::Arc::ptr_eq(&family, &bcifs::solution(&design.clone())));
/// ```
pub fn solution(design: &Design) -> std::sync::Arc<Result<Family, SolveError>> {
    let once = slot(design);
    once.get_or_init(|| std::sync::Arc::new(solve_now(design))).clone()
}

/// A design's solution, computed once: shared by its clones.
type Slot = std::sync::Arc<std::sync::OnceLock<std::sync::Arc<Result<Family, SolveError>>>>;
/// Slots by the address of their design's identity, with a weak handle on it.
type Slots = std::collections::HashMap<usize, (std::sync::Weak<()>, Slot)>;

/// The solutions of the designs alive (a slot whose design is gone is
/// dropped when the next one is made).
static SLOTS: std::sync::Mutex<Option<Slots>> = std::sync::Mutex::new(None);

/// The slot of `design`'s solution (the lock is held only to find it: designs solve in parallel).
fn slot(design: &Design) -> Slot {
    let identity = &design.identity.0;
    let key = std::sync::Arc::as_ptr(identity) as usize;
    let mut slots = SLOTS.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
    let slots = slots.get_or_insert_with(Slots::new);
    if let Some((alive, slot)) = slots.get(&key)
        && alive.upgrade().is_some()
    {
        return slot.clone();
    }
    slots.retain(|_, (alive, _)| alive.strong_count() > 0);
    let slot = Slot::default();
    slots.insert(key, (std::sync::Arc::downgrade(identity), slot.clone()));
    slot
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
    family_of(design, &elim, [constraints, eqs.len(), identities])
}

/// The family read off the reduced system: every variable in the free ones.
/// `counts`: the distinct constraints, the scalar equations solved, those that held identically.
fn family_of(design: &Design, elim: &Eliminator, counts: [usize; 3]) -> Result<Family, SolveError> {
    let [constraints, equations, identities] = counts;
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
    Ok(Family { automaton, parameters, variables, constraints, equations, identities, rank: elim.rows.len() })
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
    #[error("no value for {}: give it a value, or a default in [parameters]", names.iter().map(|n| format!("`{n}`")).collect::<Vec<_>>().join(", "))]
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
    match solution(design).as_ref() {
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
