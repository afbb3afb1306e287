//! # bcifs: iterative geometric modelling with Boundary Controlled IFS
//!
//! Every shape is an **automaton**: states are barycentric spaces
//! `BI^n = { λ ∈ R^n : Σ λ_i = 1 }` (a vertex, an edge, a face or a free IFS
//! space), arrows carry matrices `M` of shape `dim(from) × dim(to)` mapping
//! target coordinates into source coordinates (`λ_A = M λ_B`, every column
//! sums to 1). *Subdivision* arrows form a graph-directed IFS; *boundary*
//! arrows embed a boundary cell into the cell it bounds. Topology is stated
//! as equalities between paths (adjacency `T0·b1 = T1·b0`, incidence
//! `T0·b0 = b0·Tv`), which are linear in the unknown entries: the exact
//! solver turns them into the **admissible family** of subdivision
//! matrices, an affine function of a few free parameters. A **model**
//! (control points) projects the attractor into the plane or space.
//!
//! The local corner-cutting curve of Sokolov, Gentil and Bensoudane (seed
//! 004 §3), built in code, solved, evaluated and written as OBJ (the same
//! design as `automata/corner_cutting.toml`, and `examples/corner_cutting.rs`):
//!
//! ```
//! use bcifs::{CellKind, Design, Layout, Model};
//! use bcifs::eval::{EvalSettings, Evaluator};
//!
//! let hexagon = vec![vec![0.0, 0.0], vec![2.0, 0.0], vec![3.0, 1.5], vec![2.0, 3.0], vec![0.0, 3.0], vec![-1.0, 1.5]];
//! let design = Design::builder("corner_cutting")
//!     .state("e", 3, CellKind::Edge)            // an edge with 3 control points
//!     .state("v", 2, CellKind::Vertex)          // its ends depend on 2 of them
//!     .unknown("T0", "e", "e")                  // the two halves: solved for
//!     .unknown("T1", "e", "e")
//!     .unknown("Tv", "v", "v")
//!     .select("b0", "e", "v", [0, 1])           // left end: points 0, 1
//!     .select("b1", "e", "v", [1, 2])           // right end: points 1, 2
//!     .adjacency("T0 b1 = T1 b0")               // the halves meet
//!     .incidence("T0 b0 = b0 Tv")               // the ends subdivide as vertices
//!     .incidence("T1 b1 = b1 Tv")
//!     .name_entry("a", "T0[1][0]")
//!     .name_entry("b", "T0[0][1]")
//!     .model(Model::new("e", hexagon).with_layout(Layout::Closed))
//!     .build()?;
//!
//! // The admissible family, exactly as the paper prints it.
//! let family = bcifs::solve(&design)?;
//! assert_eq!(family.parameter_names(), ["a", "b"]);
//! assert_eq!(family.entry_text("T0", 1, 2), "1 - a");
//! assert_eq!(family.entry_text("T1", 1, 0), "1 - b");
//!
//! // Pick a = b = 1/4 (Chaikin's scheme), check it, evaluate, export.
//! let instance = family.instantiate(&[("a".into(), 0.25), ("b".into(), 0.25)])?;
//! let report = bcifs::analysis::check(&instance.automaton, &instance.values, 1e-9)?;
//! assert!(report.ok && report.contractive);
//! let model = design.model().expect("the design has a model");
//! let shape = Evaluator::new(&instance.automaton, model, EvalSettings::default().with_depth(6))?.evaluate()?;
//! assert_eq!(shape.vertex_count(), 6 << 6); // 6 closed windows, 2^6 edges each
//! let path = std::env::temp_dir().join("bcifs-doc-corner-cutting.obj");
//! bcifs::export::write_obj(&shape, "corner_cutting", &path)?;
//! # std::fs::remove_file(&path)?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! Data flows one way: file, generator or code → [`DesignBuilder`] →
//! [`Design`] → [`solve`] → [`Family`] → [`Family::instantiate`] → numeric
//! [`Automaton`] → [`eval`] → [`geometry`] → [`export`].
//!
//! Automaton files ([`parse_design`], [`write_design`]) go through the same
//! builder, and so do the papers' schemes in [`schemes`]: each generator
//! returns a [`Design`] with a model.
//!
//! ```
//! // The Koch curve of the normal-vector scheme (Li et al. 2013, eq. 5) as an automaton.
//! let koch = bcifs::schemes::normal_preset("koch").unwrap();
//! let design = koch.design().unwrap();
//! let instance = bcifs::instantiate(&design, &[]).unwrap();
//! let settings = bcifs::eval::EvalSettings::default().with_depth(3);
//! let shape = bcifs::eval::Evaluator::new(&instance.automaton, design.model().unwrap(), settings)
//!     .unwrap()
//!     .evaluate()
//!     .unwrap();
//! assert_eq!(shape.vertex_count(), 4usize.pow(3) + 1);
//! // Entries stay exact through a printed file: sqrt(3)/6, not 0.2886…
//! assert!(bcifs::write_design(&design).contains("sqrt(3)/6"));
//! ```

#![forbid(unsafe_code)]
// Library code reports failures; an `unwrap` would turn bad input into a panic.
#![cfg_attr(not(test), warn(clippy::unwrap_used))]

pub mod algebra;
pub mod analysis;
mod automaton;
pub mod contour;
mod design;
pub mod eval;
pub mod export;
mod family;
pub mod fit;
mod format;
pub mod geometry;
mod input;
pub mod mesh;
mod names;
mod progress;
pub mod render;
pub mod report;
pub mod schemes;
mod space;

pub use automaton::{Arrow, ArrowKind, Automaton, AutomatonError, Constraint, Entry, Relation};
pub use design::{
    BuildError, Design, DesignBuilder, Docs, Field, Layout, Locus, MAX_UNKNOWNS, Matrix, Model, Origin, Value, Variable,
};
pub use family::{
    APPROX_TOLERANCE, DesignInstantiateError, Equation, Family, Instance, InstantiateError, Label, NumericFamily,
    Parameter, SolveError, equations, instantiate, numeric, solution, solve,
};
pub use format::{BUILTIN_AUTOMATA, FormatError, ReadError, builtin_design, parse_design, read_design, write_design};
pub use input::{TEXT_FILE_LIMIT, read_text};
/// Re-exported: its matrices appear in bcifs signatures.
pub use nalgebra;
pub use names::suggest;
/// Re-exported: its indices appear in bcifs signatures.
pub use petgraph;
pub use progress::{Cancel, Progress, bytes_text};
pub use space::{CellKind, Patch, State};
