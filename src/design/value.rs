//! The values a builder is given: numbers and expressions, matrices, and where an item is.

use std::fmt;

use crate::algebra::{Num, Surd};

/// A number or an expression given to the builder: a matrix entry or a
/// parameter default.
///
/// Numbers are exact: an `f64` is read as its shortest decimal form (`0.1`
/// is `1/10`). Text is an expression (`"1 - a"`, `"sqrt(3)/6"`) in the
/// language of automaton files.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    /// A number.
    Num(Num),
    /// An expression in parameters and constants.
    Text(String),
}

impl From<Num> for Value {
    fn from(n: Num) -> Value {
        Value::Num(n)
    }
}
impl From<Surd> for Value {
    fn from(s: Surd) -> Value {
        Value::Num(Num::Exact(s))
    }
}
impl From<&Surd> for Value {
    fn from(s: &Surd) -> Value {
        Value::Num(Num::Exact(s.clone()))
    }
}
impl From<i64> for Value {
    fn from(n: i64) -> Value {
        Value::Num(Num::int(n))
    }
}
impl From<i32> for Value {
    fn from(n: i32) -> Value {
        Value::Num(Num::int(i64::from(n)))
    }
}
impl From<f64> for Value {
    fn from(x: f64) -> Value {
        Value::Num(Num::from_f64(x))
    }
}
impl From<&str> for Value {
    fn from(s: &str) -> Value {
        Value::Text(s.to_string())
    }
}
impl From<String> for Value {
    fn from(s: String) -> Value {
        Value::Text(s)
    }
}

impl fmt::Display for Value {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Value::Num(n) => write!(f, "{n}"),
            Value::Text(t) => f.write_str(t),
        }
    }
}

/// The matrix of an arrow.
#[derive(Clone, Debug, PartialEq)]
pub enum Matrix {
    /// Every entry is an unknown of the constraint system.
    Unknown,
    /// The selection matrix whose column `j` is `e_{select[j]}` (a boundary
    /// cell whose control points are these points of the bounded cell).
    Select(Vec<usize>),
    /// Known rows (entries may use parameters).
    Rows(Vec<Vec<Value>>),
}

/// Which part of an item an error is about.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Field {
    /// The item as a whole.
    Whole,
    /// Its name.
    Name,
    /// A state's dimension.
    Dim,
    /// An arrow's source state.
    From,
    /// An arrow's target state.
    To,
    /// An arrow's matrix (or selection) as a whole.
    Matrix,
    /// Index `k` of an arrow's selection.
    Select(usize),
    /// Entry `[row][col]` of an arrow's known matrix.
    Entry(usize, usize),
    /// The entry a parameter names.
    NamedEntry,
    /// A parameter's default.
    Default,
    /// The model's roots.
    Root,
    /// The model's control points.
    Points,
    /// The model's window step.
    Step,
    /// The model's grid size.
    Grid,
    /// The model's `k`-th start set.
    Start(usize),
    /// The model's `k`-th list of start faces.
    StartFaces(usize),
    /// The model's control net.
    Net,
    /// The model's patches.
    Patches,
}

/// Where an error is, by the order items were given to the builder (the
/// file parser maps it back to `file:line:column`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Locus {
    /// The design as a whole.
    Design,
    /// The `index`-th state.
    State {
        /// Order of the state.
        index: usize,
        /// The part at fault.
        field: Field,
    },
    /// The `index`-th arrow.
    Arrow {
        /// Order of the arrow.
        index: usize,
        /// The part at fault.
        field: Field,
    },
    /// The `index`-th equation, counted group by group (groups in order of first use).
    Equation {
        /// Order of the equation.
        index: usize,
    },
    /// The `index`-th parameter.
    Parameter {
        /// Order of the parameter.
        index: usize,
        /// The part at fault.
        field: Field,
    },
    /// The model.
    Model {
        /// The part at fault.
        field: Field,
    },
}
