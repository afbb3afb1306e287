//! Why a report could not be made, and the model it projects with.

use crate::design::{Design, Model};
use crate::eval::EvalError;
use crate::family::DesignInstantiateError;

/// Why a report could not be made.
#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    /// The design has no model to project with.
    #[error("`{0}` has no [model]: add control points to render it")]
    NoModel(String),
    /// Parameters or constraints.
    #[error(transparent)]
    Instantiate(#[from] DesignInstantiateError),
    /// Evaluation.
    #[error(transparent)]
    Eval(#[from] EvalError),
    /// A design or a request this report does not apply to.
    #[error("{0}")]
    Unsupported(String),
    /// The caller's [`crate::progress::Cancel`] was set.
    #[error("cancelled")]
    Cancelled,
}

/// The model of a design.
///
/// # Errors
/// [`ReportError::NoModel`] when it has none.
pub fn model_of(design: &Design) -> Result<Model, ReportError> {
    design.model().cloned().ok_or_else(|| ReportError::NoModel(design.name().to_string()))
}
