//! Generators: functions that return automata (as files or designs) for the
//! topologies and schemes of the papers.
//!
//! - [`curve`], [`quad_patch`]: BC-IFS topologies with unknown
//!   matrices, for the solver (Sokolov et al. 2010);
//! - [`NormalScheme`]: the normal-vector p-ary scheme of Li et al. 2013, direct and
//!   as an automaton, with the paper's figures as [`normal_preset`]s;
//! - [`Rules`], [`BSpline`], [`ifs_design`]: stationary subdivision schemes as
//!   IFS (Schaefer et al. 2005), lifted to ordinary IFS by [`LiftedIfs`];
//! - [`segment_ifs`]: a line segment as two maps (the Bézier-fractal contours paper §4);
//! - [`crate::algebra::Surd`]: exact numbers `q + q'√r`, so generated files stay exact.

mod blossom;
mod catalog;
mod contour;
mod lattice;
mod lift;
mod mesh;
mod normal;
mod pattern;
mod pattern_triangle;
mod pattern_volume;
mod polyhedral;
mod stationary;
mod ternary;
mod topology;

pub use blossom::{bezier_part, bezier_triangle_part, triangle_net};
pub use catalog::{CatalogError, DEFAULT_OMEGA, IFS_NAMES, ifs_preset, ternary_family};
pub use contour::{RowMap, segment_ifs, segment_ifs_as_printed};
pub use lattice::{
    Axial, LatticeIfs, LatticeScheme, NotClosed, SubPatch, box_spline_hexagon, hexagon_parts, lattice_ifs,
    lattice_triangles, parallelogram_parts, ternary_triangle_parts,
};
pub use lift::{LiftError, LiftedIfs, to_f64};
pub use mesh::{MeshAutomatonError, mesh_automaton};
pub use normal::{
    NormalDirection, NormalPreset, NormalScheme, NormalSchemeError, PRESET_NAMES, Point2, SignPattern, normal_preset,
    unit_segment, unit_square, unit_triangle,
};
pub use pattern::{Basis, Pattern, PatternCell, PatternError, pattern_design};
pub use polyhedral::{POLYHEDRON_NAMES, Polyhedron, PolyhedronError, polyhedral_lace};
pub use stationary::{
    BSpline, CurveStructure, ExactMatrix, ModelSpec, Rules, StationaryError, curve_structure, ifs_design, koch_blocks,
    sierpinski_blocks, tensor_design,
};
pub use ternary::{TERNARY_WINDOW, ternary_five_point};
pub(crate) use topology::cardinal_bspline;
pub use topology::{TopologyError, bspline_segment_matrices, bspline_segment_parts, curve, quad_patch};
