//! What `solve --json` and `check --json` print, as JSON values: the one
//! place these objects are made (the command line prints them, the Python
//! module returns them as dicts).

use serde_json::{Value, json};

use crate::algebra::ExprError;
use crate::analysis::{DEFAULT_CHECK_TOLERANCE, check};
use crate::design::Design;
use crate::family::{DesignInstantiateError, SolveError, instantiate, solve};

/// The solved family of `design`: `{automaton, consistent: true, dof,
/// parameters, matrices}` (entries as exact text), or `{automaton,
/// consistent: false, conflicts}` naming the conflicting equations.
///
/// # Errors
/// A system the solver refuses for another reason than inconsistency.
pub fn solve_report(design: &Design) -> Result<Value, SolveError> {
    let name = design.name();
    match solve(design) {
        Ok(family) => {
            let matrices: serde_json::Map<String, Value> =
                family.matrices_text().iter().map(|(n, rows)| (n.clone(), json!(rows))).collect();
            Ok(json!({
                "automaton": name, "consistent": true, "dof": family.dof(),
                "parameters": family.parameter_names(), "matrices": matrices,
            }))
        }
        Err(SolveError::Inconsistent { conflicts }) => {
            Ok(json!({"automaton": name, "consistent": false, "conflicts": conflicts}))
        }
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

/// The check of `design` at `params`: `{automaton, ok, parameters,
/// constraints: [{equation, max_abs_residual}], max_column_sum_error,
/// spectra, per_matrix_condition, jsr: {lower, upper, witness} | null,
/// converges, contractive}`.
///
/// # Errors
/// Parameters that do not instantiate, or the check's error.
pub fn check_report(design: &Design, params: &[(String, f64)]) -> Result<Value, CheckReportError> {
    let instance = instantiate(design, params)?;
    let report = check(&instance.automaton, &instance.values, DEFAULT_CHECK_TOLERANCE)?;
    let parameters: serde_json::Map<String, Value> =
        instance.parameters.iter().map(|(n, v)| (n.clone(), json!(v))).collect();
    let spectra: serde_json::Map<String, Value> = report
        .spectra
        .iter()
        .map(|(n, eig)| (n.clone(), json!(eig.iter().map(|l| [l.re, l.im]).collect::<Vec<_>>())))
        .collect();
    let constraints: Vec<Value> =
        report.constraints.iter().map(|(e, r)| json!({"equation": e, "max_abs_residual": r})).collect();
    let jsr = report.jsr.as_ref().map(|j| json!({"lower": j.lower, "upper": j.upper, "witness": j.witness}));
    Ok(json!({
        "automaton": design.name(), "ok": report.ok, "parameters": parameters,
        "constraints": constraints, "max_column_sum_error": report.max_column_sum_error,
        "spectra": spectra, "per_matrix_condition": report.contractive,
        "jsr": jsr, "converges": report.converges, "contractive": report.converges,
    }))
}
