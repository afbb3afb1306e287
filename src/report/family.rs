//! What `solve` and `check` find: a design's family and its check at
//! parameter values, one struct per report, so that a key is spelt once
//! (the fields in the order the printed JSON always had its keys).

use std::collections::BTreeMap;

use serde::Serialize;

use crate::algebra::ExprError;
use crate::analysis::{DEFAULT_CHECK_TOLERANCE, Jsr, check};
use crate::design::Design;
use crate::family::{DesignInstantiateError, SolveError, instantiate, solve};

/// The solved family of a design ([`solve_report`]): its free parameters and
/// every matrix with exact entries, or the equations that conflict.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SolveReport {
    /// The design's name.
    pub automaton: String,
    /// A small set of conflicting equations, when the constraints are inconsistent.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub conflicts: Option<Vec<String>>,
    /// Whether the constraints have a solution.
    pub consistent: bool,
    /// The number of free parameters (consistent systems).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub dof: Option<usize>,
    /// Every arrow's matrix, rows of exact entries affine in the parameters (consistent systems).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub matrices: Option<BTreeMap<String, Vec<Vec<String>>>>,
    /// The free parameters' names (consistent systems).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub parameters: Option<Vec<String>>,
}

/// The solved family of `design`, or the equations that conflict.
///
/// ```
/// let design = bcifs::render::load("corner_cutting")?;
/// let report = bcifs::report::solve_report(&design)?;
/// assert!(report.consistent);
/// assert_eq!(report.parameters.as_deref(), Some(&["a".to_string(), "b".to_string()][..]));
/// let json = serde_json::to_value(&report)?;
/// assert_eq!(json["dof"], 2);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # Errors
/// A system the solver refuses for another reason than inconsistency.
pub fn solve_report(design: &Design) -> Result<SolveReport, SolveError> {
    let automaton = design.name().to_string();
    match solve(design) {
        Ok(family) => Ok(SolveReport {
            automaton,
            conflicts: None,
            consistent: true,
            dof: Some(family.dof()),
            matrices: Some(family.matrices_text().into_iter().collect()),
            parameters: Some(family.parameter_names()),
        }),
        Err(SolveError::Inconsistent { conflicts }) => Ok(SolveReport {
            automaton,
            conflicts: Some(conflicts),
            consistent: false,
            dof: None,
            matrices: None,
            parameters: None,
        }),
        Err(e) => Err(e),
    }
}

/// Why a design could not be checked.
#[derive(Debug, thiserror::Error)]
pub enum CheckReportError {
    /// Parameters or constraints.
    #[error(transparent)]
    Instantiate(#[from] DesignInstantiateError),
    /// The check itself.
    #[error(transparent)]
    Check(#[from] ExprError),
}

/// A constraint and how far its two sides are apart.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Residual {
    /// `group: text`, as written.
    pub equation: String,
    /// The largest absolute difference between an entry of one side and the other's.
    pub max_abs_residual: f64,
}

/// A column whose entries are so large that floating point cannot tell its sum from 1.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Rounding {
    /// The arrow.
    pub arrow: String,
    /// The column.
    pub column: usize,
    /// Its largest absolute entry.
    pub magnitude: f64,
}

/// The check of a design at parameter values ([`check_report`]): residuals,
/// column sums, spectra and the convergence verdict.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CheckReport {
    /// The design's name.
    pub automaton: String,
    /// Every constraint with its residual.
    pub constraints: Vec<Residual>,
    /// The same as `converges`: the name scripts read before `converges` was added.
    pub contractive: Option<bool>,
    /// The joint spectral radius bounds' verdict: `true` converges, `false` diverges, `None` undecided.
    pub converges: Option<bool>,
    /// Bounds on the joint spectral radius on the difference subspaces (`None`: a matrix is not
    /// column-stochastic).
    pub jsr: Option<Jsr>,
    /// The largest `|Σ_i M_ij − 1|` over every arrow and column.
    pub max_column_sum_error: f64,
    /// Whether every constraint and column sum holds within the tolerance.
    pub ok: bool,
    /// The value of every free parameter used.
    pub parameters: BTreeMap<String, f64>,
    /// Whether every square subdivision matrix has, besides one eigenvalue 1, only eigenvalues of
    /// modulus below 1 (necessary for convergence, not sufficient).
    pub per_matrix_condition: bool,
    /// The first column floating point cannot sum (its sum is left out of `ok`).
    pub rounding: Option<Rounding>,
    /// Eigenvalues `[re, im]` of every square subdivision matrix, by decreasing modulus.
    pub spectra: BTreeMap<String, Vec<[f64; 2]>>,
}

/// The check of `design` at `params` (then the defaults).
///
/// ```
/// let design = bcifs::render::load("corner_cutting")?;
/// let report = bcifs::report::check_report(&design, &[("a".into(), 0.25)])?;
/// assert!(report.ok && report.converges == Some(true));
/// assert_eq!(report.parameters["b"], 0.25);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # Errors
/// Parameters that do not instantiate, or the check's error.
pub fn check_report(design: &Design, params: &[(String, f64)]) -> Result<CheckReport, CheckReportError> {
    let instance = instantiate(design, params)?;
    let report = check(&instance.automaton, &instance.values, DEFAULT_CHECK_TOLERANCE)?;
    Ok(CheckReport {
        automaton: design.name().to_string(),
        constraints: report
            .constraints
            .into_iter()
            .map(|(equation, max_abs_residual)| Residual { equation, max_abs_residual })
            .collect(),
        contractive: report.converges,
        converges: report.converges,
        jsr: report.jsr,
        max_column_sum_error: report.max_column_sum_error,
        ok: report.ok,
        parameters: instance.parameters.into_iter().collect(),
        per_matrix_condition: report.contractive,
        rounding: report.rounding.map(|(arrow, column, magnitude)| Rounding { arrow, column, magnitude }),
        spectra: report
            .spectra
            .into_iter()
            .map(|(arrow, eig)| (arrow, eig.iter().map(|l| [l.re, l.im]).collect()))
            .collect(),
    })
}
