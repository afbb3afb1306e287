//! Eigenvalues of small dense matrices, with a bounded iteration count.

use nalgebra::Complex;

/// The convergence tolerances of the Schur iteration, tried in turn (with
/// a balancing similarity after the first) until one converges.
const SCHUR_TOLERANCES: [f64; 4] = [f64::EPSILON, 1e-13, 1e-11, 1e-9];

/// The eigenvalues of a square matrix by a Schur decomposition with a
/// bounded number of iterations (nalgebra's unbounded one can stall on
/// matrices with large defective eigenvalue clusters, such as Kronecker
/// products of subdivision matrices). On a stall it retries with a looser
/// tolerance and after a diagonal similarity (same eigenvalues, other
/// rounding); `None` if every attempt stalls.
pub fn eigenvalues(m: &nalgebra::DMatrix<f64>) -> Option<Vec<Complex<f64>>> {
    let n = m.nrows();
    if n == 0 || !m.is_square() {
        return Some(Vec::new());
    }
    let budget = 200 * n + 1000;
    for (attempt, eps) in SCHUR_TOLERANCES.into_iter().enumerate() {
        let mut a = m.clone();
        if attempt > 0 {
            // D A D⁻¹ with D = diag(1 + 0.1 sin(i)): a similarity, so the same eigenvalues.
            let d: Vec<f64> = (0..n).map(|i| 1.0 + 0.1 * ((i * attempt) as f64).sin()).collect();
            for r in 0..n {
                for c in 0..n {
                    a[(r, c)] *= d[r] / d[c];
                }
            }
        }
        if let Some(schur) = nalgebra::linalg::Schur::try_new(a, eps, budget) {
            return Some(schur.complex_eigenvalues().iter().copied().collect());
        }
    }
    None
}

/// Whether a spectrum is that of a contractive stochastic map: one
/// eigenvalue 1 (within `tol`) and all others of modulus below `1 - tol`.
pub fn contractive_spectrum(eigenvalues: &[Complex<f64>], tol: f64) -> bool {
    let Some(one) = eigenvalues
        .iter()
        .enumerate()
        .filter(|(_, l)| (*l - Complex::new(1.0, 0.0)).norm() < tol)
        .map(|(i, _)| i)
        .next()
    else {
        return false;
    };
    eigenvalues.iter().enumerate().all(|(i, l)| i == one || l.norm() < 1.0 - tol)
}
