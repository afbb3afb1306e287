//! A design: the automaton of a file, a generator or code before solving,
//! whose entries are affine in the unknowns and parameters, plus its model.
//! The one way to make one is the checked [`DesignBuilder`].

mod builder;
mod compile;
mod error;
mod model;
mod value;

pub use builder::{Design, DesignBuilder, MAX_UNKNOWNS};
pub use error::BuildError;
pub use model::{Docs, Layout, Model, Origin, Variable};
pub use value::{Field, Locus, Matrix, Value};
