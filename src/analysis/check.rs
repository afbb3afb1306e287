//! Numeric verification of an instantiated automaton: constraint residuals,
//! column sums, spectra, and the convergence verdict of the joint spectral
//! radius bounds.

use std::collections::HashMap;

use nalgebra::Complex;

use super::jsr::{Jsr, JsrSettings, jsr};
use crate::algebra::{Env, ExprError, contractive_spectrum, eigenvalues};
use crate::automaton::{ArrowKind, Automaton, Relation};

/// Residuals up to this size count as zero: products of a few matrices with
/// entries of order 1 carry rounding errors of order 1e-15, far below it.
pub const DEFAULT_CHECK_TOLERANCE: f64 = 1e-9;

/// The outcome of [`check`].
#[derive(Clone, Debug)]
pub struct CheckReport {
    /// Whether every constraint and column sum holds within the tolerance.
    pub ok: bool,
    /// Every constraint (`group: text`) with its largest absolute residual.
    pub constraints: Vec<(String, f64)>,
    /// The largest `|Σ_i M_ij - 1|` over all arrows and columns.
    pub max_column_sum_error: f64,
    /// The first column whose entries are so large that floating point
    /// cannot tell whether it sums to 1 (`arrow`, column, largest absolute
    /// entry): its error is rounding's, not the design's, and such
    /// parameters cannot be evaluated. Its sum is left out of `ok`.
    pub rounding: Option<(String, usize, f64)>,
    /// Eigenvalues of every square subdivision arrow, by arrow name, by
    /// decreasing modulus (then real part).
    pub spectra: Vec<(String, Vec<Complex<f64>>)>,
    /// Whether every square subdivision arrow has, besides one eigenvalue 1,
    /// only eigenvalues of modulus < 1: the per-matrix condition of Sokolov et al. 2010
    /// §3, which is necessary for convergence but not sufficient.
    pub contractive: bool,
    /// Bounds on the joint spectral radius on the difference subspaces
    /// (`None` when a subdivision matrix is not column-stochastic).
    pub jsr: Option<Jsr>,
    /// The verdict of the bounds: converges, diverges, or `None` (undecided).
    pub converges: Option<bool>,
}

struct Numbers<'a> {
    automaton: &'a Automaton<f64>,
    values: &'a HashMap<String, f64>,
}

impl Env<f64> for Numbers<'_> {
    fn param(&self, name: &str) -> Option<f64> {
        self.values.get(name).copied()
    }
    fn entry(&self, arrow: &str, row: usize, col: usize) -> Option<f64> {
        let m = &self.automaton.arrow(self.automaton.arrow_id(arrow)?).matrix;
        (row < m.nrows() && col < m.ncols()).then(|| m[(row, col)])
    }
}

/// Checks an instantiated automaton; `values` gives the parameters that
/// entry equations refer to.
///
/// # Errors
/// An entry equation that refers to a missing name.
pub fn check(automaton: &Automaton<f64>, values: &HashMap<String, f64>, tol: f64) -> Result<CheckReport, ExprError> {
    let mut constraints = Vec::new();
    for c in automaton.constraints() {
        let residual = match &c.relation {
            Relation::Paths { lhs, rhs } => {
                let l = automaton.product(lhs)?;
                let r = automaton.product(rhs)?;
                (l - r).amax()
            }
            Relation::Entries { lhs, rhs } => {
                let env = Numbers { automaton, values };
                (lhs.eval(&env)? - rhs.eval(&env)?).abs()
            }
        };
        constraints.push((c.to_string(), residual));
    }
    let mut max_column_sum_error: f64 = 0.0;
    let mut spectra = Vec::new();
    let mut contractive = true;
    let mut rounding = None;
    let mut sums_hold = true;
    for (id, arrow) in automaton.arrows() {
        for j in 0..arrow.matrix.ncols() {
            let column = arrow.matrix.column(j);
            let error = (column.sum() - 1.0).abs();
            max_column_sum_error = max_column_sum_error.max(error);
            // A sum of n entries of magnitude m is known to within n·m·ε at best.
            let magnitude = column.amax();
            let told = magnitude * column.len() as f64 * f64::EPSILON <= tol;
            if told {
                sums_hold &= error <= tol;
            } else {
                rounding.get_or_insert((arrow.name.clone(), j, magnitude));
            }
        }
        if arrow.kind == ArrowKind::Subdivision && arrow.matrix.is_square() && automaton.on_cycle(id) {
            let mut eig = eigenvalues(&arrow.matrix).unwrap_or_default();
            eig.sort_by(|a, b| b.norm().total_cmp(&a.norm()).then(b.re.total_cmp(&a.re)).then(a.im.total_cmp(&b.im)));
            contractive &= !eig.is_empty() && contractive_spectrum(&eig, tol);
            spectra.push((arrow.name.clone(), eig));
        }
    }
    let ok = sums_hold && constraints.iter().all(|(_, r)| *r <= tol);
    let jsr = jsr(automaton, &JsrSettings::default()).ok();
    let converges = jsr.as_ref().and_then(|j| j.verdict().converges());
    Ok(CheckReport { ok, constraints, max_column_sum_error, rounding, spectra, contractive, jsr, converges })
}
