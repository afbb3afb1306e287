//! Generators: functions that return automata (as files or designs) for the
//! topologies and schemes of the seeds.

mod topology;

pub use topology::{TopologyError, bspline_segment_matrices, curve_file, quad_patch_file};
