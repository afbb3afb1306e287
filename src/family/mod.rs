//! The constraint system of a design, its exact solver, and instantiation.

mod eliminate;
mod equations;
mod error;
mod solve;

pub use equations::{Equation, Label, equations};
pub use error::{APPROX_TOLERANCE, SolveError};
pub use solve::{
    DesignInstantiateError, Family, Instance, InstantiateError, NumericFamily, Parameter, instantiate, numeric,
    solution, solve,
};
