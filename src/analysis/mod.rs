//! Analysis of instantiated automata and of subdivision schemes.

mod check;
mod curve;
mod dimension;
mod exact;
mod jsr;
mod map;
pub mod subdivision;
pub mod ternary;
mod weights;

pub use check::{CheckReport, DEFAULT_CHECK_TOLERANCE, check};
pub use curve::{Blending, CurveReport, blending, curve_query};
pub use dimension::{
    BOX_KEY_BYTES, BoxCount, Cancelled, OpenSet, box_dimension, box_dimension_of, open_set_condition,
    similarity_dimension,
};
pub use exact::{ExactCurveReport, curve_query_exact};
pub use jsr::{Jsr, JsrError, JsrSettings, ROUNDING, Verdict, jsr, jsr_verdict};
pub use map::{
    CurveCell, MapCell, ParameterPlane, curve_map, curve_map_rows, per_matrix_condition, verdict_map, verdict_map_rows,
};
pub use weights::{WeightsError, WeightsVerdict, check_loop_weights, check_quad_weights};
