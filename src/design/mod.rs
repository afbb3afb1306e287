//! A design: the automaton of a file, a generator or code before solving,
//! whose entries are affine in the unknowns and parameters, plus its model.
//! The one way to make one is the checked [`DesignBuilder`].

mod builder;
mod model;

pub use builder::{BuildError, Design, DesignBuilder, Field, Locus, MAX_UNKNOWNS, Matrix, Value};
pub use model::{Docs, Layout, Model, Origin, Variable};
