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
    /// A target file that cannot be read.
    #[error("{0}")]
    Target(String),
}
