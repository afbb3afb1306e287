//! Reports: what bcifs finds about a design, as typed values — its solved
//! family and its check ([`SolveReport`], [`CheckReport`]), a curve's
//! tangents and junction ([`CurveAnalysis`]), the attractor's dimensions
//! ([`DimensionReport`]), the parameters' convergence ranges
//! ([`ParameterRange`]), sweeps of a parameter plane ([`sweep`]) and the
//! topology of the depth-k cells ([`TopologyReport`]). Each
//! serialises to the JSON object the command line prints with `--json` (keys
//! in alphabetical order), the Python module returns as a dict and the
//! explorer and the Blender add-on read. Writing files is [`crate::render`]'s.

mod colours;
mod curve;
mod dimension;
mod error;
mod family;
mod lacunarity;
mod measure;
mod print;
mod solid_holes;
mod sweep;
mod topology;
mod walls;

pub use colours::{angle_colour, dimension_colour, region_colour, sweep_colour, sweep_image, verdict_colour};
pub use curve::{CurveAnalysis, curve_analysis, curve_halves, region_meaning};
pub use dimension::{
    DIMENSION_MEMORY, DimensionReport, ParameterRange, dimension_report, dimension_within, parameter_ranges,
    similarity_dimension,
};
pub use error::{ReportError, model_of};
pub use family::{CheckReport, CheckReportError, Residual, Rounding, SolveReport, check_report, solve_report};
pub use lacunarity::{LacunarityReport, lacunarity_depth, lacunarity_report, porosity};
pub use print::{DEFAULT_NOZZLE, PrintReport, PrintStyle, print_report_of, printed};
pub use sweep::{REGIONS, SWEEP_DEPTH, SWEEP_MEMORY, SweepKind, SweepValues, sweep, sweep_cancellable, sweep_csv};
pub use topology::{TopologyReport, topology_of, topology_report};
pub use walls::{Measured, walls_and_holes};
