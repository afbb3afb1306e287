//! Analysis of instantiated automata and of subdivision schemes.

mod check;
pub mod subdivision;
pub mod ternary;

pub use check::{CheckReport, DEFAULT_CHECK_TOLERANCE, check};
