//! Evaluation of instantiated automata with a model: deterministic (fixed
//! depth or tolerance) and random (chaos game).
//!
//! The files, bottom first: `settings` (what to evaluate, what can fail),
//! `plan` and `pieces` (per-state preparation, the model cut into root
//! cells), `prepared` (the `Evaluator`: plan, pieces, tabulated levels,
//! thread pool), `curve` and `surface` (curves and points; welded meshes),
//! `polygons` (faces of several states: a mesh's generated automaton),
//! `evaluate` (into memory or streamed), `random` (the chaos game).

mod ball;
mod colour;
mod curve;
mod evaluate;
mod lattice;
mod pieces;
mod plan;
mod polygons;
mod prepared;
mod random;
mod sampling;
mod settings;
mod surface;
mod tangents;

pub use colour::Colouring;
pub use pieces::{ModelError, Piece, Pieces};
pub use plan::{PlanError, StatePlan};
pub use polygons::CellVisitor;
pub use prepared::Evaluator;
pub use random::{ChaosGame, chaos_game};
pub use sampling::{
    DEFAULT_BURN_IN, MAX_SAMPLES, RandomSettings, SINGULAR_FLOOR, arrow_colour, check_samples, det_weights,
};
pub use settings::{
    DEFAULT_DEPTH, DEFAULT_MEMORY_LIMIT, Depth, EvalError, EvalSettings, MAX_ADAPTIVE_DEPTH, MAX_DEPTH,
};
pub use tangents::{Directions, Tangents};
