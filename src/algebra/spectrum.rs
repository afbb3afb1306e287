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
    if !all_finite(m) {
        return None;
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

/// Whether every entry of `m` is finite: nalgebra's iterations on a matrix
/// with an infinite or NaN entry never converge (its SVD loops for ever).
pub fn all_finite(m: &nalgebra::DMatrix<f64>) -> bool {
    m.iter().all(|x| x.is_finite())
}

/// The singular value decomposition of `m` (with `V` when `with_v`), with
/// a bounded iteration count; `None` when an entry is not finite or the
/// iteration does not converge (nalgebra's unbounded one spins for ever on
/// entries near `f64::MAX`, whose products overflow).
pub fn svd(
    m: &nalgebra::DMatrix<f64>,
    with_v: bool,
) -> Option<nalgebra::linalg::SVD<f64, nalgebra::Dyn, nalgebra::Dyn>> {
    if !all_finite(m) {
        return None;
    }
    let budget = 200 * m.nrows().max(m.ncols()) + 1000;
    m.clone().try_svd(false, with_v, f64::EPSILON, budget)
}

/// Whether a column-stochastic square matrix is proven contractive by norms
/// alone: on the vectors whose entries sum to 0 (which it maps into
/// themselves, its columns summing to 1) it acts as `R` (`R[r][c] = M[r][c] −
/// M[r][n−1]` in the basis `eᵢ − e_{n−1}`), and `ρ(R) ≤ ‖R^(2^j)‖^(1/2^j)` for
/// the row-sum norm; `ρ(R) < 1 − tol` is the eigenvalue 1 simple and every
/// other of modulus below `1 − tol` ([`contractive_spectrum`]). Five
/// squarings at most; `false` proves nothing (then compute the spectrum).
/// Kronecker products of subdivision matrices (a tricubic volume's), whose
/// defective eigenvalue clusters slow the Schur iteration, pass in a few
/// products.
pub fn contracts_by_norm(m: &nalgebra::DMatrix<f64>, tol: f64) -> bool {
    let n = m.nrows();
    if n < 2 || !m.is_square() || !all_finite(m) {
        return false;
    }
    let mut r = nalgebra::DMatrix::from_fn(n - 1, n - 1, |i, j| m[(i, j)] - m[(i, n - 1)]);
    let norm = |a: &nalgebra::DMatrix<f64>| {
        a.row_iter().map(|row| row.iter().map(|x| x.abs()).sum::<f64>()).fold(0.0, f64::max)
    };
    for j in 0..6 {
        // The rounding of the products is far below the margin asked (entries of stochastic maps are O(1)).
        if norm(&r).powf(1.0 / f64::from(1u32 << j)) < 1.0 - tol - 1e-9 {
            return true;
        }
        r = &r * &r;
    }
    false
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

/// Iterations allowed per eigenvalue in [`hessenberg_eigenvalues`] before it
/// gives up (the classic routine allows 30, with exceptional shifts at 10 and 20).
const FRANCIS_ITERATIONS: usize = 60;

/// The eigenvalues of a square matrix, in no particular order, without the
/// Schur vectors: a Householder reduction to Hessenberg form, then Francis
/// double-shift QR steps on the active block only, deflating one real
/// eigenvalue or a pair at a time (the EISPACK `orthes` and `hqr` scheme).
/// About a third of the work of a Schur decomposition with its orthogonal
/// factor, and no allocation but the matrix's copy: the joint spectral
/// radius's lower bound computes thousands of these. `None` when an
/// eigenvalue takes more than 60 iterations or the matrix is not finite
/// (then [`eigenvalues`], with its retries, is the fallback).
///
/// ```
/// use nalgebra::DMatrix;
/// // A rotation by a quarter turn scaled by 2, and 3: eigenvalues ±2i and 3.
/// let m = DMatrix::from_row_slice(3, 3, &[0.0, -2.0, 0.0, 2.0, 0.0, 0.0, 0.0, 0.0, 3.0]);
/// let mut eig = bcifs::algebra::hessenberg_eigenvalues(&m).unwrap();
/// eig.sort_by(|a, b| a.re.total_cmp(&b.re).then(a.im.total_cmp(&b.im)));
/// assert!((eig[0].im + 2.0).abs() < 1e-12 && (eig[1].im - 2.0).abs() < 1e-12 && (eig[2].re - 3.0).abs() < 1e-12);
/// ```
pub fn hessenberg_eigenvalues(m: &nalgebra::DMatrix<f64>) -> Option<Vec<Complex<f64>>> {
    let n = m.nrows();
    if n == 0 || !m.is_square() {
        return Some(Vec::new());
    }
    if m.iter().any(|x| !x.is_finite()) {
        return None;
    }
    // Row by row.
    let mut a: Vec<f64> = (0..n * n).map(|k| m[(k / n, k % n)]).collect();
    to_hessenberg(&mut a, n);
    let eig = francis(&mut a, n)?;
    eig.iter().all(|l| l.re.is_finite() && l.im.is_finite()).then_some(eig)
}

/// `a` (`n × n`, row by row) made upper Hessenberg by Householder
/// similarities (the same eigenvalues); the entries below the subdiagonal
/// are set to zero.
fn to_hessenberg(a: &mut [f64], n: usize) {
    let mut v = vec![0.0; n];
    for m in 1..n.saturating_sub(1) {
        let scale: f64 = (m..n).map(|i| a[i * n + m - 1].abs()).sum();
        if scale == 0.0 {
            continue;
        }
        let mut h = 0.0;
        for i in m..n {
            v[i] = a[i * n + m - 1] / scale;
            h += v[i] * v[i];
        }
        // The reflection I − v vᵀ / h maps the scaled column below the
        // diagonal to g e_m, g of the sign that avoids cancellation.
        let g = if v[m] > 0.0 { -h.sqrt() } else { h.sqrt() };
        h -= v[m] * g;
        v[m] -= g;
        for j in m..n {
            let f = (m..n).map(|i| v[i] * a[i * n + j]).sum::<f64>() / h;
            for i in m..n {
                a[i * n + j] -= f * v[i];
            }
        }
        for row in a.chunks_exact_mut(n) {
            let f = (m..n).map(|j| v[j] * row[j]).sum::<f64>() / h;
            for j in m..n {
                row[j] -= f * v[j];
            }
        }
        a[m * n + m - 1] = scale * g;
        for i in m + 1..n {
            a[i * n + m - 1] = 0.0;
        }
    }
}

/// The eigenvalues of the upper Hessenberg `a` (`n × n`, row by row, overwritten).
fn francis(a: &mut [f64], n: usize) -> Option<Vec<Complex<f64>>> {
    let mut h = Hessenberg { a, n };
    let mut eig = vec![Complex::new(0.0, 0.0); n];
    let mut norm = 0.0;
    for i in 0..n {
        for j in i.saturating_sub(1)..n {
            norm += h.at(i, j).abs();
        }
    }
    // The active block is rows and columns l..=hi; `shift` is the sum of
    // the exceptional shifts subtracted from the diagonal.
    let mut top = n;
    let mut shift = 0.0;
    while top > 0 {
        let hi = top - 1;
        let mut its = 0;
        loop {
            let l = h.split_row(hi, norm);
            let mut x = h.at(hi, hi);
            if l == hi {
                eig[hi] = Complex::new(x + shift, 0.0);
                top -= 1;
                break;
            }
            let mut y = h.at(hi - 1, hi - 1);
            let mut w = h.at(hi, hi - 1) * h.at(hi - 1, hi);
            if l == hi - 1 {
                [eig[hi - 1], eig[hi]] = pair(x, y, w, shift);
                top -= 2;
                break;
            }
            if its == FRANCIS_ITERATIONS {
                return None;
            }
            if its == 10 || its == 20 {
                // Exceptional shifts, to break a cycle.
                shift += x;
                for i in 0..=hi {
                    *h.at_mut(i, i) -= x;
                }
                let s = h.at(hi, hi - 1).abs() + h.at(hi - 1, hi - 2).abs();
                x = 0.75 * s;
                y = x;
                w = -0.4375 * s * s;
            }
            its += 1;
            let (m, pqr) = h.start_row(l, hi, x, y, w);
            h.double_shift_step(l, m, hi, pqr);
        }
    }
    Some(eig)
}

/// The eigenvalues of a trailing 2 × 2 block with the diagonal `y`, `x`
/// and the off-diagonal product `w`, the exceptional shifts `shift` added
/// back: a real pair or a complex one.
fn pair(x: f64, y: f64, w: f64, shift: f64) -> [Complex<f64>; 2] {
    let p = 0.5 * (y - x);
    let q = p * p + w;
    let z = q.abs().sqrt();
    let x = x + shift;
    if q >= 0.0 {
        let z = p + z.copysign(p);
        let second = if z != 0.0 { x - w / z } else { x + z };
        [Complex::new(x + z, 0.0), Complex::new(second, 0.0)]
    } else {
        [Complex::new(x + p, -z), Complex::new(x + p, z)]
    }
}

/// An upper Hessenberg matrix, row-major, reduced in place by [`francis`].
struct Hessenberg<'a> {
    a: &'a mut [f64],
    n: usize,
}

impl Hessenberg<'_> {
    fn at(&self, i: usize, j: usize) -> f64 {
        self.a[i * self.n + j]
    }

    fn at_mut(&mut self, i: usize, j: usize) -> &mut f64 {
        &mut self.a[i * self.n + j]
    }

    /// The lowest negligible subdiagonal entry at or above `hi` (set to
    /// zero): the active block starts at its row (0 when there is none).
    fn split_row(&mut self, hi: usize, norm: f64) -> usize {
        let mut l = hi;
        while l >= 1 {
            let mut s = self.at(l - 1, l - 1).abs() + self.at(l, l).abs();
            if s == 0.0 {
                s = norm;
            }
            if self.at(l, l - 1).abs() + s == s {
                *self.at_mut(l, l - 1) = 0.0;
                break;
            }
            l -= 1;
        }
        l
    }

    /// Where the double-shift step starts in the block `l..=hi` (two
    /// consecutive small subdiagonal entries), and its first Householder
    /// vector `(p, q, r)`, scaled; the entries below the bulge's path zeroed.
    fn start_row(&mut self, l: usize, hi: usize, x: f64, y: f64, w: f64) -> (usize, [f64; 3]) {
        let mut m = hi - 2;
        let (mut p, mut q, mut r);
        loop {
            let z = self.at(m, m);
            let (r0, s0) = (x - z, y - z);
            p = (r0 * s0 - w) / self.at(m + 1, m) + self.at(m, m + 1);
            q = self.at(m + 1, m + 1) - z - r0 - s0;
            r = self.at(m + 2, m + 1);
            let s = p.abs() + q.abs() + r.abs();
            (p, q, r) = (p / s, q / s, r / s);
            if m == l {
                break;
            }
            let u = self.at(m, m - 1).abs() * (q.abs() + r.abs());
            let v = p.abs() * (self.at(m - 1, m - 1).abs() + z.abs() + self.at(m + 1, m + 1).abs());
            if u + v == v {
                break;
            }
            m -= 1;
        }
        for i in m + 2..=hi {
            *self.at_mut(i, i - 2) = 0.0;
            if i != m + 2 {
                *self.at_mut(i, i - 3) = 0.0;
            }
        }
        (m, [p, q, r])
    }

    /// The double-shift step: chase the bulge down the active block `l..=hi` from row `m`.
    fn double_shift_step(&mut self, l: usize, m: usize, hi: usize, [mut p, mut q, mut r]: [f64; 3]) {
        let mut x = 0.0;
        for k in m..hi {
            if k != m {
                p = self.at(k, k - 1);
                q = self.at(k + 1, k - 1);
                r = if k != hi - 1 { self.at(k + 2, k - 1) } else { 0.0 };
                x = p.abs() + q.abs() + r.abs();
                if x != 0.0 {
                    (p, q, r) = (p / x, q / x, r / x);
                }
            }
            let s = (p * p + q * q + r * r).sqrt().copysign(p);
            if s == 0.0 {
                continue;
            }
            if k == m {
                if l != m {
                    *self.at_mut(k, k - 1) = -self.at(k, k - 1);
                }
            } else {
                *self.at_mut(k, k - 1) = -s * x;
            }
            p += s;
            x = p / s;
            let y = q / s;
            let z = r / s;
            q /= p;
            r /= p;
            self.reflect(k, l, hi, [x, y, z], [q, r]);
        }
    }

    /// Applies the reflection of step `k` to rows `k..k + 3` (columns from
    /// `k`) and to columns `k..k + 3` (rows `l` to `k + 3`).
    fn reflect(&mut self, k: usize, l: usize, hi: usize, [x, y, z]: [f64; 3], [q, r]: [f64; 2]) {
        for j in k..=hi {
            let mut t = self.at(k, j) + q * self.at(k + 1, j);
            if k != hi - 1 {
                t += r * self.at(k + 2, j);
                *self.at_mut(k + 2, j) -= t * z;
            }
            *self.at_mut(k + 1, j) -= t * y;
            *self.at_mut(k, j) -= t * x;
        }
        for i in l..=hi.min(k + 3) {
            let mut t = x * self.at(i, k) + y * self.at(i, k + 1);
            if k != hi - 1 {
                t += z * self.at(i, k + 2);
                *self.at_mut(i, k + 2) -= t * r;
            }
            *self.at_mut(i, k + 1) -= t * q;
            *self.at_mut(i, k) -= t;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::DMatrix;

    /// The norm test proves what the spectrum says, and nothing it does not:
    /// a triangular stochastic map (eigenvalues 1, 1/3, 1/5) and its
    /// Kronecker cube (repeated eigenvalues, as a tricubic volume's), a map
    /// with a second eigenvalue 1, and one whose second is 1 − 10⁻⁶.
    #[test]
    fn contraction_by_norms_agrees_with_the_spectrum() {
        let m: DMatrix<f64> = DMatrix::from_row_slice(3, 3, &[1.0, 2.0 / 3.0, 0.5, 0.0, 1.0 / 3.0, 0.3, 0.0, 0.0, 0.2]);
        let cube = m.kronecker(&m).kronecker(&m);
        for m in [&m, &cube] {
            assert!(m.column_iter().all(|c| (c.sum() - 1.0).abs() < 1e-12));
            assert!(contractive_spectrum(&eigenvalues(m).unwrap(), 1e-9) && contracts_by_norm(m, 1e-9));
        }
        let two_ones = DMatrix::from_row_slice(3, 3, &[1.0, 0.0, 0.5, 0.0, 1.0, 0.5, 0.0, 0.0, 0.0]);
        assert!(!contracts_by_norm(&two_ones, 1e-9));
        let slow = DMatrix::from_row_slice(2, 2, &[1.0, 1e-6, 0.0, 1.0 - 1e-6]);
        assert!(!contracts_by_norm(&slow, 1e-5) && contracts_by_norm(&slow, 1e-7));
    }

    /// Uniform numbers in [-1, 1) from a fixed seed (a 64-bit LCG's high bits).
    fn numbers(seed: u64) -> impl FnMut() -> f64 {
        let mut s = seed;
        move || {
            s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 52) as f64 - 1.0
        }
    }

    /// Each eigenvalue of `a` has one of `b` within `tol`, matched one to one.
    fn same_spectrum(a: &[Complex<f64>], b: &[Complex<f64>], tol: f64) -> bool {
        let mut left: Vec<Complex<f64>> = b.to_vec();
        a.len() == b.len()
            && a.iter().all(|l| {
                let near = left.iter().enumerate().min_by(|x, y| (x.1 - l).norm().total_cmp(&(y.1 - l).norm()));
                match near {
                    Some((k, m)) if (m - l).norm() <= tol => {
                        left.swap_remove(k);
                        true
                    }
                    _ => false,
                }
            })
    }

    /// The Hessenberg–Francis eigenvalues are nalgebra's Schur eigenvalues
    /// (within 1e-10 of the matrix's size) on random matrices of every size
    /// up to 40 (real and complex pairs), symmetric ones, triangular ones
    /// (their diagonal), and scaled by 1e-6 and 1e6.
    #[test]
    fn hessenberg_eigenvalues_are_the_schur_eigenvalues() {
        let mut x = numbers(29);
        for n in 1..=40 {
            for scale in [1.0, 1e-6, 1e6] {
                let m = DMatrix::from_fn(n, n, |_, _| x() * scale);
                let sym = &m + m.transpose();
                let upper = DMatrix::from_fn(n, n, |i, j| if i <= j { m[(i, j)] } else { 0.0 });
                for a in [m.clone(), sym, upper] {
                    let ours = hessenberg_eigenvalues(&a).expect("converges");
                    let theirs = eigenvalues(&a).expect("converges");
                    let size = a.norm().max(f64::MIN_POSITIVE);
                    assert!(same_spectrum(&ours, &theirs, 1e-10 * size), "n = {n}: {ours:?} against {theirs:?}");
                }
            }
        }
        let upper = DMatrix::from_row_slice(3, 3, &[2.0, 5.0, 7.0, 0.0, -3.0, 1.0, 0.0, 0.0, 0.5]);
        let eig = hessenberg_eigenvalues(&upper).unwrap();
        assert!(same_spectrum(&eig, &[2.0, -3.0, 0.5].map(|r| Complex::new(r, 0.0)), 1e-15));
    }

    /// Hard cases: zero and scaled identity matrices, a nilpotent Jordan
    /// block, a companion matrix with known roots, a rotation, and the
    /// Kronecker square of a cubic B-spline subdivision matrix (repeated
    /// eigenvalues, as in the products of surface schemes): the spectral
    /// radius is right; a matrix with a NaN is refused.
    #[test]
    fn hessenberg_eigenvalues_of_hard_matrices() {
        let radius = |m: &DMatrix<f64>| hessenberg_eigenvalues(m).unwrap().iter().map(|l| l.norm()).fold(0.0, f64::max);
        assert_eq!(radius(&DMatrix::zeros(7, 7)), 0.0);
        assert!((radius(&(DMatrix::identity(9, 9) * 0.5)) - 0.5).abs() < 1e-15);
        let jordan = DMatrix::from_fn(8, 8, |i, j| if j == i + 1 { 1.0 } else { 0.0 });
        assert!(radius(&jordan) < 1e-12);
        // x⁴ − 10x³ + 35x² − 50x + 24 = (x − 1)(x − 2)(x − 3)(x − 4).
        let companion = DMatrix::from_row_slice(
            4,
            4,
            &[10.0, -35.0, 50.0, -24.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0],
        );
        let mut roots: Vec<f64> = hessenberg_eigenvalues(&companion).unwrap().iter().map(|l| l.re).collect();
        roots.sort_by(f64::total_cmp);
        assert!(roots.iter().zip([1.0, 2.0, 3.0, 4.0]).all(|(r, e)| (r - e).abs() < 1e-10), "{roots:?}");
        let (c, s) = (0.6f64, 0.8f64);
        let rotation = DMatrix::from_row_slice(2, 2, &[c, -s, s, c]) * 0.9;
        let eig = hessenberg_eigenvalues(&rotation).unwrap();
        assert!(same_spectrum(&eig, &[Complex::new(0.54, 0.72), Complex::new(0.54, -0.72)], 1e-15));
        // A cubic B-spline subdivision matrix (eigenvalues 1, 1/2, 1/4, 1/8, 0).
        let b = DMatrix::from_row_slice(
            5,
            5,
            &[
                4.0, 4.0, 0.0, 0.0, 0.0, 1.0, 6.0, 1.0, 0.0, 0.0, 0.0, 4.0, 4.0, 0.0, 0.0, 0.0, 1.0, 6.0, 1.0, 0.0,
                0.0, 0.0, 4.0, 4.0, 0.0,
            ],
        ) / 8.0;
        let k = b.kronecker(&b);
        let theirs = eigenvalues(&k).unwrap().iter().map(|l| l.norm()).fold(0.0, f64::max);
        assert!((radius(&k) - theirs).abs() < 1e-9, "{} against {theirs}", radius(&k));
        let mut nan = DMatrix::identity(3, 3);
        nan[(1, 2)] = f64::NAN;
        assert!(hessenberg_eigenvalues(&nan).is_none());
    }
}
