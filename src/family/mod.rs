//! The constraint system of a design, its exact solver, and instantiation.

mod solve;

pub use solve::{
    DesignInstantiateError, Equation, Family, Instance, InstantiateError, Label, NumericFamily, Parameter, SolveError,
    equations, instantiate, numeric, solution, solve,
};
