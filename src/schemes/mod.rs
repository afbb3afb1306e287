//! Generators: functions that return automata (as files or designs) for the
//! topologies and schemes of the seeds.
//!
//! - [`curve_file`], [`quad_patch_file`]: BC-IFS topologies with unknown
//!   matrices, for the solver (seed 004);
//! - [`NormalScheme`]: the normal-vector p-ary scheme of seed 000, direct and
//!   as an automaton, with the paper's figures as [`normal_preset`]s;
//! - [`Surd`]: exact numbers `q + q'√r`, so generated files stay exact.

mod normal;
mod surd;
mod topology;

pub use normal::{
    NormalDirection, NormalPreset, NormalScheme, NormalSchemeError, PRESET_NAMES, Point2, SignPattern, normal_preset,
    unit_segment, unit_square, unit_triangle,
};
pub use surd::{Surd, SurdError};
pub use topology::{TopologyError, bspline_segment_matrices, curve_file, quad_patch_file};
