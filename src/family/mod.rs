//! Exact rationals, affine expressions, the constraint system and its solver.

mod affine;
mod expr;
mod num;
mod solve;

pub use affine::{Affine, AffineDisplay, Nonlinear};
pub use expr::{Env, EvalError, Expr, ExprSyntaxError, ExprValue};
pub use num::Num;
pub use solve::{
    DesignInstantiateError, Equation, Family, Instance, InstantiateError, Parameter, SolveError, equations,
    instantiate, numeric, solve,
};
