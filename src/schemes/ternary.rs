//! The ternary 5-point interpolatory scheme with tension ω of Siddiqi,
//! Siddiqui and Ahmad (*Fractal generation using ternary 5-point
//! interpolatory subdivision scheme*, Siddiqi et al. 2014), eq. (1):
//!
//! ```text
//! P_{3i-1} = (ω - 4/81) P_{i-2} + (-4ω + 10/27) P_{i-1} + (6ω + 20/27) P_i + (-4ω - 5/81) P_{i+1} + ω P_{i+2}
//! P_{3i}   = P_i
//! P_{3i+1} = ω P_{i-2} + (-4ω - 5/81) P_{i-1} + (6ω + 20/27) P_i + (-4ω + 10/27) P_{i+1} + (ω - 4/81) P_{i+2}
//! ```
//!
//! As an IFS (Schaefer et al. 2005's construction) the scheme has three 7×7 blocks on 7
//! consecutive control points: the attractor is the piece of the curve
//! around `P_3` (parameters `[2.5, 3.5]`), and its ends have a vertex support
//! of 6 control points. Curves on open and closed polygons are unions of
//! such pieces (windows of 7 points sliding by 1), surfaces are their tensor
//! products on a control grid (3×3 sub-faces).
//!
//! Its continuity and fractal ranges are analysed in
//! [`crate::analysis::ternary`] (the derivation the paper's text breaks off).

use super::stationary::Rules;
use crate::algebra::Surd;

/// The rules of eq. (1) for tension `omega`.
pub fn ternary_five_point(omega: &Surd) -> Rules {
    let w = omega.clone();
    let f = Surd::frac;
    let c = |k: i64, q: Surd| w.mul(&Surd::int(k)).add(&q);
    let near = c(6, f(20, 27)); // 6ω + 20/27
    let mid = c(-4, f(10, 27)); // -4ω + 10/27
    let far = c(-4, f(-5, 81)); // -4ω - 5/81
    let edge = c(1, f(-4, 81)); // ω - 4/81
    Rules {
        arity: 3,
        rules: vec![
            vec![(0, Surd::int(1))],
            vec![(-2, w.clone()), (-1, far.clone()), (0, near.clone()), (1, mid.clone()), (2, edge.clone())],
            vec![(-1, edge), (0, mid), (1, near), (2, far), (3, w)],
        ],
    }
}

/// Control points of one IFS piece of the ternary 5-point scheme.
pub const TERNARY_WINDOW: usize = 7;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::subdivision::Mask;

    #[test]
    fn mask_of_eq_1() {
        let a = Mask::from_rules(&ternary_five_point(&Surd::frac(1, 100)));
        assert_eq!(a.start, -7);
        let w = 0.01;
        let expected =
            [w, 0.0, w - 4.0 / 81.0, -4.0 * w - 5.0 / 81.0, 0.0, -4.0 * w + 10.0 / 27.0, 6.0 * w + 20.0 / 27.0, 1.0];
        for (i, e) in expected.iter().enumerate() {
            assert!((a.coeffs[i] - e).abs() < 1e-15 && (a.coeffs[14 - i] - e).abs() < 1e-15, "a_{}", i as i64 - 7);
        }
        assert!((a.coeffs.iter().sum::<f64>() - 3.0).abs() < 1e-14);
    }
}
