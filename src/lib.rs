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
//! matrices, an affine function of a few free parameters.
//!
//! ```
//! // The local corner-cutting curve of Sokolov, Gentil and Bensoudane (§3).
//! let design = bcifs::builtin_design("corner_cutting").unwrap();
//! let family = bcifs::solve(&design).unwrap();
//! assert_eq!(family.parameter_names(), ["a", "b"]);
//! assert_eq!(family.entry_text("T1", 1, 0), "1 - b");
//!
//! // Pick parameters (a = b = 1/4 is Chaikin's scheme) and verify numerically.
//! let instance = family.instantiate(&[("a".into(), 0.25), ("b".into(), 0.25)]).unwrap();
//! let report = bcifs::analysis::check(&instance.automaton, &instance.values, 1e-9).unwrap();
//! assert!(report.ok && report.contractive);
//! ```
//!
//! Data flows one way: file or generator → [`Design`] → [`solve`] →
//! [`Family`] → [`Family::instantiate`] → numeric [`Automaton`] →
//! [`eval`] → [`geometry`] → [`export`].
//!
//! The seeds' schemes are generators in [`schemes`]: each returns an
//! automaton file with a model, so everything above works on it.
//!
//! ```
//! // The Koch curve of the normal-vector scheme (seed 000, eq. 5) as an automaton.
//! let koch = bcifs::schemes::normal_preset("koch").unwrap();
//! let design = koch.scheme.design("koch", &koch.polygon, koch.closed).unwrap();
//! let instance = bcifs::instantiate(&design, &[]).unwrap();
//! let model = design.model.clone().unwrap();
//! let settings = bcifs::eval::EvalSettings::default().with_depth(3);
//! let shape = bcifs::eval::Evaluator::new(&instance.automaton, &model, settings).unwrap().evaluate().unwrap();
//! assert_eq!(shape.vertex_count(), 4usize.pow(3) + 1);
//! ```

#![forbid(unsafe_code)]

mod algebra;
pub mod analysis;
mod automaton;
mod design;
pub mod eval;
pub mod export;
mod family;
mod format;
pub mod geometry;
mod names;
mod render;
pub mod schemes;
mod space;

pub use algebra::{
    Affine, AffineDisplay, Env, EvalError, Expr, ExprSyntaxError, ExprValue, Nonlinear, Num, Surd, SurdError,
};
pub use automaton::{Arrow, ArrowKind, Automaton, AutomatonError, Constraint, Entry, Relation, mat_mul, selection};
pub use design::{Design, Layout, Model, Origin, Variable};
pub use family::{
    DesignInstantiateError, Equation, Family, Instance, InstantiateError, Parameter, SolveError, equations,
    instantiate, numeric, solve,
};
pub use format::{FormatError, ReadError, TomlWriter, parse_design, read_design};
pub use names::suggest;
pub use render::{
    GALLERY_BUDGET_BYTES, GALLERY_MAX_DEPTH, GalleryEntry, GallerySource, RenderError, RenderOptions, RenderSummary,
    SchemeForm, evaluate_design, gallery, gallery_depth, gallery_items, normal_shape, render, ternary5_plot,
    write_shape,
};
pub use space::{CellKind, State};

/// The automata shipped in `automata/`, embedded in the library:
/// `(name, file text)`.
pub const BUILTIN_AUTOMATA: &[(&str, &str)] = &[
    ("corner_cutting", include_str!("../automata/corner_cutting.toml")),
    ("curve_4_3", include_str!("../automata/curve_4_3.toml")),
    ("doo_sabin_quad", include_str!("../automata/doo_sabin_quad.toml")),
    ("doo_sabin_torus", include_str!("../automata/doo_sabin_torus.toml")),
    ("fern", include_str!("../automata/fern.toml")),
    ("fern_sierpinski", include_str!("../automata/fern_sierpinski.toml")),
    ("koch", include_str!("../automata/koch.toml")),
    ("levy", include_str!("../automata/levy.toml")),
];

/// The shipped automaton called `name`, parsed.
///
/// # Errors
/// `None` if there is no such automaton. The shipped files are tested to parse.
pub fn builtin_design(name: &str) -> Option<Design> {
    let (_, text) = BUILTIN_AUTOMATA.iter().find(|(n, _)| *n == name)?;
    parse_design(text, &format!("automata/{name}.toml"), name).ok()
}
