//! The render API: one call renders a design, or a polygon mesh with a
//! subdivision scheme, to a file whose format is chosen by its extension,
//! and reports what it wrote. The route (streamed or in memory, chaos game
//! or deterministic evaluation, the depth a picture needs, the size
//! estimates and refusals) is decided here, once: the command line, the
//! Python module and the explorer all call these functions.
//!
//! ```
//! use bcifs::render::{Options, render};
//! let design = bcifs::builtin_design("corner_cutting").expect("shipped");
//! let dir = std::env::temp_dir().join(format!("bcifs-render-doc-{}", std::process::id()));
//! std::fs::create_dir_all(&dir)?;
//! let options = Options::default().with_depth(6).with_size(200, 200);
//! let report = render(&design, &options, &dir.join("chaikin.obj"))?;
//! assert!(report.vertices > 64);
//! render(&design, &options, &dir.join("chaikin.png"))?;
//! # std::fs::remove_dir_all(&dir)?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! A new file format is a writer in [`crate::export`] and a line in
//! [`Format`]; a new subdivision scheme is a rule in [`crate::mesh`].

mod checked;
mod design;
mod job;
mod keys;
mod load;
mod mesh;
mod options;
mod output;
mod picture;
mod shape;

pub use crate::export::{Compression, png_bytes};
pub use design::{density, evaluate_design, picture, picture_png, print_report, render, render_bytes};
pub use keys::{Group, KEYS, Key, Kind, OptionError, Profile, Value, key_named};
pub use load::{LoadError, is_mesh_path, load, load_with_scheme};
pub use mesh::{MeshJob, check_weights, face_sources, render_mesh, rule_weights, subdivide_mesh};
pub use options::{Budget, DEFAULT_SEED, FileStyle, Look, Options, Sampling};
pub use output::{Format, RenderError, Report, check_disk, check_room};
pub use picture::{
    POINTS_PER_PIXEL, SEGMENTS_PER_PIXEL, curve_picture_depth, depth_within, picture_depth, point_picture_depth,
    tolerance_within,
};
// The reports, for the front ends that import the library through this module alone.
pub use crate::report::{
    CheckReport, CheckReportError, CurveAnalysis, DIMENSION_MEMORY, DimensionReport, LacunarityReport, ParameterRange,
    REGIONS, ReportError, Residual, Rounding, SolveReport, SweepKind, SweepValues, TopologyReport, check_report,
    curve_analysis, curve_halves, dimension_report, dimension_within, lacunarity_depth, lacunarity_report, model_of,
    parameter_ranges, region_meaning, solve_report, sweep, sweep_cancellable, sweep_colour, sweep_csv, sweep_image,
    topology_report,
};
pub use crate::report::{PrintReport, angle_colour, dimension_colour, print_report_of, region_colour, verdict_colour};
pub use shape::{control_net, write_shape, write_shape_text};
// Patterns, for the front ends that generate designs from one (`new pattern`, `bcifs.pattern`).
pub use crate::schemes::{Basis, Pattern, PatternCell, PatternError, Polyhedron, PolyhedronError, polyhedral_lace};

// The front ends' vocabulary: everything the command line, the explorer and
// the Python module use of the library, named here once (a test checks that
// they reach nothing past this module). A new front-end feature adds its
// names here, or better a function to this module that decides for it:
// designs (reading, writing, solving, instantiating), exact numbers,
// analyses, contour fitting, evaluation settings and the chaos game (the
// gallery's density sheet counts one game three ways), palettes and atomic
// writes, shapes and sinks, polygon meshes, the papers' schemes and presets.
pub use crate::algebra::{Num, Surd, tolerance::DEGENERATE};
pub use crate::analysis::{
    CurveCell, DEFAULT_CHECK_TOLERANCE, JsrSettings, ParameterPlane, Verdict, blending, check, curve_map, ternary,
};
pub use crate::contour::{
    FitSettings, Ipan, Segment, chaos_points, contour_design, fit_contour, iterate_polygon, read_segments,
    write_segments,
};
pub use crate::design::{Design, DesignBuilder, Layout, Model, Value as MatrixValue};
pub use crate::eval::{ChaosGame, Depth, EvalError, RandomSettings};
pub use crate::export::{
    Palette, RasterSettings, Tone, check_target, density_counts, remove_temporary_files, same_file, write_atomic,
    write_png, write_png_text,
};
pub use crate::family::{DesignInstantiateError, Family, InstantiateError, SolveError, instantiate, solution, solve};
pub use crate::fit::{
    BOX_SPREAD, FitError, FitOptions, FitReport, FitTarget, NumberFit, fit, fit_starts, fitted_design, is_picture,
    picture_points, read_target, read_target_bytes,
};
pub use crate::format::{BUILTIN_AUTOMATA, builtin_design, parse_design, write_design};
pub use crate::geometry::{Shape, Sink, area_normals, fan};
pub use crate::mesh::{LoopWeights, PolyMesh, QuadWeights, RuleWeights, Scheme, SubdivideError, read_mesh};
pub use crate::names::suggest;
pub use crate::progress::{Cancel, Progress};
pub use crate::schemes::{
    IFS_NAMES, NormalDirection, NormalPreset, NormalScheme, NormalSchemeError, PRESET_NAMES, SignPattern, curve,
    ifs_preset, mesh_automaton, normal_preset, quad_patch, ternary_family, unit_segment, unit_square, unit_triangle,
};
pub use crate::space::CellKind;
