//! Evaluation of instantiated automata with a model: deterministic
//! (fixed depth or tolerance) and random (chaos game).

mod deterministic;
mod pieces;
mod plan;
mod random;
mod surface;

pub use deterministic::{
    DEFAULT_DEPTH, DEFAULT_MEMORY_LIMIT, Depth, EvalError, EvalSettings, Evaluator, MAX_ADAPTIVE_DEPTH,
};
pub use pieces::{ModelError, Piece, Pieces};
pub use plan::PlanError;
pub use random::{ChaosGame, DEFAULT_BURN_IN, RandomSettings, SINGULAR_FLOOR, chaos_game};
