//! The named tolerances of floating-point computations: each says what it
//! is for, so that a comparison reads as its meaning and a value changes
//! in one place. Exact computations (the solver, `Num`) use none of them.

/// Column sums of a stochastic (affine-invariant) matrix are 1 to within this.
pub const STOCHASTIC: f64 = 1e-9;

/// Numerical rank: singular values below this (relative to the largest) count as zero.
pub const RANK: f64 = 1e-9;

/// Eigenvalues of modulus below `1 − CONTRACTIVE` contract.
pub const CONTRACTIVE: f64 = 1e-9;

/// Two positions closer than this, relative to the shape's size, are one
/// point (welding, matching corners, comparing control points).
pub const SAME_POINT: f64 = 1e-9;

/// Slack when a computed quantity is compared with an exact bound (a
/// barycentric coordinate with 0, a dimension with an integer, a bound with
/// another): what floating-point evaluation may have lost.
pub const SLACK: f64 = 1e-9;

/// A length, area or determinant this small (relative to its scale) is
/// zero: degenerate geometry, handled apart (and a floor that keeps a
/// division finite).
pub const DEGENERATE: f64 = 1e-12;

/// Relative rounding of a computed value that a comparison forgives (an
/// eigenvalue, a radius that stopped changing, a remainder that is zero).
pub const ROUNDING: f64 = 1e-12;
