//! Settings of deterministic evaluation, and what can go wrong.

use std::io;

use super::pieces::ModelError;
use super::plan::PlanError;
use crate::progress::Progress;

/// Default in-memory output limit: 4 GiB.
pub const DEFAULT_MEMORY_LIMIT: usize = 4 << 30;
/// Default depth.
pub const DEFAULT_DEPTH: usize = 8;
/// Deepest fixed depth accepted: beyond it no output fits any memory or disk
/// (two maps give `2^1000` cells), and counts saturate.
pub const MAX_DEPTH: usize = 1000;
/// Deepest level the adaptive mode goes to, whatever the tolerance.
pub const MAX_ADAPTIVE_DEPTH: usize = 40;

/// How deep to evaluate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Depth {
    /// Every root cell to exactly this depth.
    Fixed(usize),
    /// Until every cell is smaller than this (modelling units): for an IFS
    /// of affine contractions, its part of the attractor (the output is then
    /// within this Hausdorff distance of the attractor); otherwise its
    /// control polygon.
    Tolerance(f64),
}

impl Default for Depth {
    /// [`DEFAULT_DEPTH`] steps.
    fn default() -> Depth {
        Depth::Fixed(DEFAULT_DEPTH)
    }
}

/// Settings of an evaluation.
#[derive(Clone, Debug)]
#[non_exhaustive]
pub struct EvalSettings {
    /// Depth or tolerance.
    pub depth: Depth,
    /// Worker threads (`None`: all cores).
    pub threads: Option<usize>,
    /// In-memory output larger than this (bytes) is refused.
    pub memory_limit: usize,
    /// Start sets: barycentric points per state name, emitted at leaves instead of the kind's default.
    pub start: Vec<(String, Vec<Vec<f64>>)>,
    /// Subdivision arrows to leave out (a subset of the attractor).
    pub dropped: Vec<String>,
    /// Told how far a long evaluation is (`None`: nobody listens).
    pub progress: Option<Progress>,
    /// Evaluate even a system whose joint spectral radius bounds prove it
    /// diverges (its pictures show the divergence, not an attractor).
    pub force: bool,
    /// Texture coordinates on meshes: one parameterization `(u, v)` of the
    /// whole grid or torus (a torus repeats its seam). Off by default: a
    /// closed surface then loads as one watertight body in every client.
    pub uv: bool,
    /// Stops the evaluation when set: [`EvalError::Cancelled`], whatever was made dropped.
    pub cancel: Option<crate::progress::Cancel>,
}

impl Default for EvalSettings {
    fn default() -> EvalSettings {
        EvalSettings {
            depth: Depth::Fixed(DEFAULT_DEPTH),
            threads: None,
            memory_limit: DEFAULT_MEMORY_LIMIT,
            start: Vec::new(),
            dropped: Vec::new(),
            progress: None,
            force: false,
            uv: false,
            cancel: None,
        }
    }
}

impl EvalSettings {
    /// With a fixed depth.
    pub fn with_depth(mut self, depth: usize) -> Self {
        self.depth = Depth::Fixed(depth);
        self
    }
    /// With a tolerance.
    pub fn with_tolerance(mut self, eps: f64) -> Self {
        self.depth = Depth::Tolerance(eps);
        self
    }
    /// With a thread count.
    pub fn with_threads(mut self, threads: usize) -> Self {
        self.threads = Some(threads);
        self
    }
    /// With a memory limit in bytes.
    pub fn with_memory_limit(mut self, bytes: usize) -> Self {
        self.memory_limit = bytes;
        self
    }
    /// With a start set for a state.
    pub fn with_start(mut self, state: &str, points: Vec<Vec<f64>>) -> Self {
        self.start.push((state.to_string(), points));
        self
    }
    /// With a progress callback.
    pub fn with_progress(mut self, progress: Progress) -> Self {
        self.progress = Some(progress);
        self
    }
    /// With texture coordinates on meshes.
    pub fn with_uv(mut self) -> Self {
        self.uv = true;
        self
    }
    /// Evaluating even a divergent system.
    pub fn with_force(mut self) -> Self {
        self.force = true;
        self
    }
    /// Without the given subdivision arrows.
    pub fn without(mut self, arrows: &[&str]) -> Self {
        self.dropped.extend(arrows.iter().map(|s| s.to_string()));
        self
    }
}

/// Why an evaluation failed.
#[derive(Debug, thiserror::Error)]
pub enum EvalError {
    /// The automaton cannot be evaluated.
    #[error(transparent)]
    Plan(#[from] PlanError),
    /// The model does not fit the automaton.
    #[error(transparent)]
    Model(#[from] ModelError),
    /// The output would not fit the memory limit.
    #[error("the output would take {}, over the in-memory limit of {} (the memory budget): lower the depth or the number of points, or stream a fixed depth to an OBJ file", estimate_text(*estimate), crate::progress::bytes_text(*limit as u128))]
    TooLarge {
        /// Estimated bytes.
        estimate: u128,
        /// The limit.
        limit: usize,
    },
    /// A chaos-game probability that names no subdivision arrow, is not a
    /// finite non-negative number, or leaves a state with total probability 0.
    #[error("{0}")]
    Probability(String),
    /// A dropped arrow that does not exist.
    #[error("no subdivision arrow named `{0}` to drop")]
    UnknownArrow(String),
    /// Writing to the sink failed.
    #[error("cannot write the output: {0}")]
    Io(#[from] io::Error),
    /// The joint spectral radius bounds prove that the subdivision diverges.
    #[error(
        "the subdivision diverges: {witness} ≥ 1 on the differences (its powers do not contract); evaluate anyway by forcing it"
    )]
    Diverges {
        /// The cycle and its normalised spectral radius, `T0 T1 T1 T1: ρ^(1/4) = 1.2601`.
        witness: String,
    },
    /// Faces mixed with other root kinds, or a face evaluated adaptively past the limit.
    #[error("{0}")]
    Unsupported(String),
    /// A solid's cells turned inside out: its control lattice folds the volume.
    #[error(
        "the control points fold the solid inside out near ({:.4}, {:.4}, {:.4}): a depth-{depth} cell there is turned over (its Jacobian is {jacobian:.3e}, the solid's sign is the other); move the control lattice's points apart so that no layer crosses its neighbour",
        at[0], at[1], at[2]
    )]
    Folded {
        /// A corner of the turned cell.
        at: [f64; 3],
        /// The depth.
        depth: usize,
        /// Its corner Jacobian (the determinant of its three edges there), relative to the cell's size.
        jacobian: f64,
    },
    /// The settings' cancel flag was set: the evaluation stopped, its output incomplete.
    #[error("cancelled")]
    Cancelled,
    /// A chaos game of more samples than can finish.
    #[error(
        "{samples} samples would take about {} at 100 million samples a second per core: at most {max} (2^40, about 3 hours on one core)",
        duration(*samples as f64 / 1e8)
    )]
    TooManySamples {
        /// Samples asked for.
        samples: u128,
        /// The most allowed, [`crate::eval::MAX_SAMPLES`].
        max: u128,
    },
}

/// An estimate of bytes as a message says it: `about 123456 bytes (121 KiB)`, or past an exbibyte only that.
fn estimate_text(estimate: u128) -> String {
    match crate::progress::bytes_text(estimate) {
        huge if estimate >= 1 << 60 => huge,
        short => format!("about {estimate} bytes ({short})"),
    }
}

/// A duration in seconds, in the largest unit that keeps it above 1.
fn duration(seconds: f64) -> String {
    const UNITS: [(&str, f64); 5] =
        [("years", 365.25 * 86400.0), ("days", 86400.0), ("hours", 3600.0), ("minutes", 60.0), ("seconds", 1.0)];
    let (name, size) = UNITS.iter().find(|(_, size)| seconds >= *size).copied().unwrap_or(("seconds", 1.0));
    format!("{:.1} {name}", seconds / size)
}
