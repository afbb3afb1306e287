//! Continuity and fractal ranges of the ternary 5-point scheme with tension
//! ω (Siddiqi et al. 2014, [`crate::schemes::ternary_five_point`]): the derivation the
//! paper's text breaks off.
//!
//! The paper's text stops after eq. (4), `U_{k+1} - 35/81 U_k = -4/81 Z_k`
//! (the chord `U = P_1 - P_{-1}` across `P_0` does not depend on ω). We take
//! the equivalent, complete route of difference schemes (see
//! [`crate::analysis::subdivision`]):
//!
//! 1. The mask of eq. (1) is `a(z) = Σ a_m z^m` with `a_0 = 1`,
//!    `a_{±1} = 6ω + 20/27`, `a_{±2} = -4ω + 10/27`, `a_{±4} = -4ω - 5/81`,
//!    `a_{±5} = ω - 4/81`, `a_{±7} = ω` (and `a_{±3} = a_{±6} = 0`);
//!    `a(1) = 3` and `a(ω₃) = 0` at the cube roots of unity, so
//!    `σ(z) = 1 + z + z²` divides it.
//! 2. The edges `d_j = P_j - P_{j-1}` between two fixed control points are
//!    refined by the difference scheme `b(z) = a(z)/σ(z)`: after `k` steps the
//!    `3^k` edges between `P^0_0` and `P^0_1` are `d^k = S_b^k d^0` and the
//!    polygon length is `L_k = Σ |d^k_f|`. Since the scheme is interpolatory,
//!    the three new edges of an edge sum to it, so `L_{k+1} ≥ L_k`.
//! 3. **Convergence (C0)** holds iff `S_b` is contractive: `‖S_b^L‖∞ < 1` for
//!    some `L`. **C1** holds if the mask `3a(z)/σ(z)²` is contractive, **C2**
//!    if `9a(z)/σ(z)³` is.
//! 4. **Non-rectifiability**: `L_k` grows like `γ(ω)^k`. The edges after
//!    `k` steps are the products of the difference scheme's blocks applied
//!    to the initial differences, so by the triangle inequality
//!    `L_k ≥ |r (Σ_i s_i B_i)^k w|` for any signs `s_i`: `γ ≥ max_s ρ(Σ_i s_i B_i)`
//!    for generic control polygons. When that bound exceeds 1 the length
//!    between any two points diverges (proven); the measured rate is shown
//!    beside it.
//! 5. The **fractal range** is where the scheme is proven to converge
//!    (step 3) and the length proven to diverge (step 4): the limit is a
//!    continuous, non-rectifiable curve. C1 proves a finite length, so the
//!    C1 and fractal verdicts never meet. [`ternary5_analysis`] computes the
//!    bounds for each ω; the intervals it finds are in the README and the tests.

use super::subdivision::{Mask, contraction, l1_growth, length_growth, length_lower_bound, spectral_lower_bound};
use crate::algebra::Surd;
use crate::schemes::ternary_five_point;

/// One row of the ω table.
#[derive(Clone, Debug, PartialEq)]
pub struct TernaryRow {
    /// The tension.
    pub omega: f64,
    /// `min_L ‖S_b^L‖∞^{1/L}` (L ≤ 8): below 1 the scheme is C0.
    pub c0: f64,
    /// Lower bound of the joint spectral radius of the difference scheme: at least 1, not C0.
    pub c0_lower: f64,
    /// Contraction of `3a/σ²`: below 1 the scheme is C1.
    pub c1: f64,
    /// Contraction of `9a/σ³`: below 1 the scheme is C2.
    pub c2: f64,
    /// Measured growth rate of the polygon length per step (shown, not used by the verdicts).
    pub growth: f64,
    /// Lower bound of the growth rate of the polygon length per step
    /// ([`crate::analysis::subdivision::length_lower_bound`]): above 1 the length diverges.
    pub length_lower: f64,
    /// `‖b_k‖_1^{1/k}`: the growth rate the difference mask allows.
    pub growth_bound: f64,
}

impl TernaryRow {
    /// Whether the computation proves convergence.
    pub fn converges(&self) -> bool {
        self.c0 < 1.0
    }

    /// Whether the bound proves that the polygon length diverges
    /// geometrically (for generic control polygons): `length_lower > 1`.
    pub fn diverges(&self) -> bool {
        self.length_lower > 1.0 + LENGTH_ROUNDING
    }

    /// Continuous and non-rectifiable: in the fractal range.
    pub fn fractal(&self) -> bool {
        self.converges() && self.diverges()
    }

    /// Whether the computation proves that the scheme does not converge.
    pub fn fails(&self) -> bool {
        self.c0_lower >= 1.0
    }

    /// What the computation proves, in a word.
    pub fn verdict(&self) -> &'static str {
        if self.fails() {
            "not C0"
        } else if self.fractal() {
            "fractal"
        } else if self.c2 < 1.0 {
            "C2"
        } else if self.c1 < 1.0 {
            "C1"
        } else if self.converges() {
            "C0"
        } else {
            "undecided"
        }
    }
}

/// The continuity ranges the paper states after eq. (1): `(low, high)` for C0, C1, C2.
pub const PAPER_RANGES: [(&str, f64, f64); 3] =
    [("C0", -1.0 / 81.0, 53.0 / 324.0), ("C1", -1.0 / 324.0, 2.0 / 81.0), ("C2", 1.0 / 324.0, 1.0 / 162.0)];

/// Largest `L` of the norms `‖S^L‖∞` (the `L`-step masks have about `15 · 3^L` coefficients).
pub const CONTRACTION_STEPS: usize = 8;

/// Rounding allowed when the length bound is compared with 1 (a spectral
/// radius of a small matrix: backward error ~1e-15).
pub const LENGTH_ROUNDING: f64 = 1e-9;

/// Steps of the length measurement.
pub const GROWTH_STEPS: usize = 10;

/// The analysis of one tension value (see the module docs).
pub fn ternary5_analysis(omega: f64) -> TernaryRow {
    let w = Surd::rational(num_rational::BigRational::from_float(omega).unwrap_or_default());
    let rules = ternary_five_point(&w);
    let a = Mask::from_rules(&rules);
    let b = a.divide_by_sigma(3).expect("eq. (1) reproduces constants");
    let c1 = a.scale(3.0).divide_by_sigma(3).and_then(|m| m.divide_by_sigma(3)).expect("σ² divides 3a");
    let c2 = a.scale(9.0).divide_by_sigma(3).and_then(|m| m.divide_by_sigma(3)).and_then(|m| m.divide_by_sigma(3));
    TernaryRow {
        omega,
        c0: contraction(&b, 3, CONTRACTION_STEPS),
        c0_lower: spectral_lower_bound(&b, 3).unwrap_or(f64::NAN),
        c1: contraction(&c1, 3, CONTRACTION_STEPS),
        c2: c2.map_or(f64::INFINITY, |m| contraction(&m, 3, CONTRACTION_STEPS)),
        growth: length_growth(&rules, GROWTH_STEPS),
        length_lower: length_lower_bound(&b, 3).unwrap_or(f64::NAN),
        growth_bound: l1_growth(&b, 3, 8),
    }
}

/// The analysis of `steps + 1` equally spaced tensions from `from` to `to`.
pub fn ternary5_table(from: f64, to: f64, steps: usize) -> Vec<TernaryRow> {
    ternary5_rows(&omegas(from, to, steps))
}

/// `steps + 1` equally spaced tensions from `from` to `to`.
pub fn omegas(from: f64, to: f64, steps: usize) -> Vec<f64> {
    let steps = steps.max(1);
    (0..=steps).map(|i| from + (to - from) * i as f64 / steps as f64).collect()
}

/// The analysis of each tension, in parallel.
pub fn ternary5_rows(omegas: &[f64]) -> Vec<TernaryRow> {
    use rayon::prelude::*;
    omegas.par_iter().map(|&w| ternary5_analysis(w)).collect()
}

/// The maximal intervals of consecutive rows where `pred` holds, as `(first ω, last ω)`.
pub fn intervals(rows: &[TernaryRow], pred: impl Fn(&TernaryRow) -> bool) -> Vec<(f64, f64)> {
    let mut out = Vec::new();
    let mut open: Option<f64> = None;
    for (i, r) in rows.iter().enumerate() {
        match (pred(r), open) {
            (true, None) => open = Some(r.omega),
            (false, Some(s)) => {
                out.push((s, rows[i - 1].omega));
                open = None;
            }
            _ => {}
        }
    }
    if let (Some(s), Some(last)) = (open, rows.last()) {
        out.push((s, last.omega));
    }
    out
}

/// Refines the boundary of `pred` between `lo` (where it is `at_lo`) and
/// `hi` by bisection, to `tol`.
pub fn boundary(mut lo: f64, mut hi: f64, tol: f64, pred: impl Fn(&TernaryRow) -> bool) -> f64 {
    let at_lo = pred(&ternary5_analysis(lo));
    while hi - lo > tol {
        let mid = 0.5 * (lo + hi);
        if pred(&ternary5_analysis(mid)) == at_lo {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}
