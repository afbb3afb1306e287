//! Analysis of instantiated automata.

mod check;
mod hausdorff;

pub use check::{CheckReport, DEFAULT_CHECK_TOLERANCE, check, contractive_spectrum};
pub use hausdorff::{KdTree, directed_hausdorff, hausdorff};
