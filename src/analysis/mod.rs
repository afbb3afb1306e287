//! Analysis of instantiated automata and of subdivision schemes.

mod check;
mod hausdorff;
pub mod subdivision;
pub mod ternary;

pub use check::{CheckReport, DEFAULT_CHECK_TOLERANCE, check};
pub use hausdorff::{KdTree, directed_hausdorff, hausdorff};
