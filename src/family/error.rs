//! Why a design has no admissible family.

use crate::algebra::ExprError;

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
