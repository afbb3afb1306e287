//! A subdivision scheme's IFS on control points lifted to an ordinary IFS
//! of the plane or space (Schaefer et al. 2005, eq. 2): `P S_i P⁻¹` with `P` the
//! control points made square by a row of ones.

use nalgebra::DMatrix;

use super::stationary::ExactMatrix;

/// Why the lifted IFS of eq. (2) does not exist.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum LiftError {
    /// The control points do not span their space.
    #[error(
        "the control points lie in a proper affine subspace (e.g. all on a line): P is singular, so the lifted \
         IFS f_i(X) = X P⁻¹ S_i P of eq. (2) does not exist; the barycentric form T_i = S_iᵀ still works"
    )]
    Singular,
    /// More coordinates than control points allow.
    #[error("{points} control points of dimension {dim}: the lift needs at least dim + 1 points")]
    TooFew {
        /// Control points.
        points: usize,
        /// Their dimension.
        dim: usize,
    },
}

/// The ordinary IFS of eq. (2): maps `f_i(X) = X P⁻¹ S_i P` on row vectors of
/// `R^n`, where `P` is the `n × n` lift of the control points: their
/// coordinates, identity columns for `n - d - 1` of the points, and a column
/// of ones. The attractor's first `d` coordinates are the curve.
#[derive(Clone, Debug)]
pub struct LiftedIfs {
    /// `P⁻¹ S_i P`.
    pub maps: Vec<DMatrix<f64>>,
    /// Dimension of modelling space.
    pub dim: usize,
    /// The lift `P`.
    pub lift: DMatrix<f64>,
}

impl LiftedIfs {
    /// Lifts `blocks` with control points `points` (`n` points of dimension `d`).
    ///
    /// # Errors
    /// [`LiftError::Singular`] when the points do not span `R^d` (collinear in the plane).
    pub fn new(blocks: &[DMatrix<f64>], points: &[Vec<f64>]) -> Result<LiftedIfs, LiftError> {
        let n = points.len();
        let d = points.first().map_or(0, Vec::len);
        if n < d + 1 {
            return Err(LiftError::TooFew { points: n, dim: d });
        }
        // Choose d + 1 affinely independent points (greedy); the others get identity columns.
        let mut basis: Vec<usize> = Vec::new();
        for i in 0..n {
            let mut candidate = basis.clone();
            candidate.push(i);
            let m = DMatrix::from_fn(candidate.len(), d + 1, |r, c| if c < d { points[candidate[r]][c] } else { 1.0 });
            if m.rank(crate::algebra::tolerance::RANK) == candidate.len() {
                basis = candidate;
            }
            if basis.len() == d + 1 {
                break;
            }
        }
        if basis.len() < d + 1 {
            return Err(LiftError::Singular);
        }
        let others: Vec<usize> = (0..n).filter(|i| !basis.contains(i)).collect();
        let mut lift = DMatrix::zeros(n, n);
        for i in 0..n {
            for c in 0..d {
                lift[(i, c)] = points[i][c];
            }
            lift[(i, n - 1)] = 1.0;
        }
        for (k, &i) in others.iter().enumerate() {
            lift[(i, d + k)] = 1.0;
        }
        let inv = lift.clone().try_inverse().ok_or(LiftError::Singular)?;
        let maps = blocks.iter().map(|s| &inv * s * &lift).collect();
        Ok(LiftedIfs { maps, dim: d, lift })
    }

    /// Iterates `X ← ∪ f_i(X)` `depth` times from the start set (row vectors
    /// of length `n`, e.g. homogeneous points with last coordinate 1) and
    /// returns the first `d` coordinates of the points.
    pub fn iterate(&self, start: &[Vec<f64>], depth: usize) -> Vec<Vec<f64>> {
        let mut set: Vec<nalgebra::RowDVector<f64>> =
            start.iter().map(|x| nalgebra::RowDVector::from_row_slice(x)).collect();
        for _ in 0..depth {
            set = set.iter().flat_map(|x| self.maps.iter().map(move |m| x * m)).collect();
        }
        set.iter().map(|x| x.iter().take(self.dim).copied().collect()).collect()
    }
}

/// An exact matrix as `f64`.
pub fn to_f64(m: &ExactMatrix) -> DMatrix<f64> {
    DMatrix::from_fn(m.len(), m.first().map_or(0, Vec::len), |r, c| m[r][c].to_f64())
}
