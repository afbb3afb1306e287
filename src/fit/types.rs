//! What a fit is given, and why it may not start.

/// What the fitted member should be like: points (or a mesh's vertices) it
/// passes near, and numbers it has. Give at least one.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FitTarget {
    /// Points in modelling space (`z = 0` for a plane's).
    pub points: Vec<[f64; 3]>,
    /// The attractor's similarity dimension (its box-counting dimension where it has none).
    pub dimension: Option<f64>,
    /// The junction angle of a curve, in degrees (`analyze curve`).
    pub angle: Option<f64>,
    /// The porosity at the fit's depth (at most 4): the share of the start cell left empty.
    pub porosity: Option<f64>,
    /// The points' size and place are free (a picture's outline, whose pixels have no model
    /// units): a uniform scale and a shift of the shape onto them are fitted with the parameters.
    pub free_pose: bool,
}

/// Why a fit cannot start.
#[derive(Debug, thiserror::Error)]
pub enum FitError {
    /// No target given, or an empty one.
    #[error(
        "nothing to fit to: give target points (a mesh, a picture's outline) or a number (dimension, angle, porosity)"
    )]
    EmptyTarget,
    /// A target that is not a finite number.
    #[error("the target is not finite: {0}")]
    NotFinite(String),
    /// Points in space for a plane's model.
    #[error("the target has {target}D points but the model is {model}D")]
    Dimension {
        /// The model's dimension.
        model: usize,
        /// The target's.
        target: usize,
    },
    /// A family with nothing to fit.
    #[error("{0} has no free parameter: nothing to fit")]
    NoParameter(String),
    /// No start is proven to converge.
    #[error("{0}")]
    NoProvenStart(String),
    /// The design does not solve, instantiate or evaluate.
    #[error("{0}")]
    Design(String),
    /// A fit too large for memory (a depth far past the target's), or too many starts.
    #[error("{0}")]
    TooLarge(String),
    /// A number target no member can have (a porosity outside [0, 1], an angle outside
    /// [0°, 180°], a dimension outside [0, the model space's]).
    #[error("{0}")]
    OutOfRange(String),
    /// A target file that cannot be read.
    #[error("{0}")]
    Target(String),
}

/// A number as a message shows it: as written, or in exponent form when large.
pub(crate) fn shown(x: f64) -> String {
    if x.abs() < 1e6 { format!("{x}") } else { format!("{x:e}") }
}

/// How far a box-counting dimension can be trusted, and how closely a
/// dimension target measured by box counting is met: corner cutting's
/// members with a + b ≤ 0.9 (a, b ≥ 0.1) are rectifiable curves (dimension
/// exactly 1), and their box counts read within 0.018 of 1 (root mean square
/// 0.011, over 36 of them; the test `box_count_spread`).
pub const BOX_SPREAD: f64 = 0.02;
