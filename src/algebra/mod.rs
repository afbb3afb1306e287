//! The bottom layer: exact numbers ([`Surd`] inside [`Num`]), affine forms
//! in the unknowns ([`Affine`]), the expression language of automaton
//! files ([`Expr`]), and numeric spectra. Nothing here knows automata.

mod affine;
mod expr;
mod num;
mod rat;
mod spectrum;
mod surd;
pub mod tolerance;

pub use affine::{Affine, AffineDisplay, Nonlinear};
pub use expr::{Env, Expr, ExprError, ExprSyntaxError, ExprValue};
pub use num::Num;
pub use spectrum::{all_finite, contractive_spectrum, contracts_by_norm, eigenvalues, hessenberg_eigenvalues, svd};
pub use surd::{Surd, SurdError};
