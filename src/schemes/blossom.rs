//! Bézier curves subdivided exactly: the matrices of a curve's parts (de
//! Casteljau's algorithm on blossoms), the classical members of patterns.

use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{One, Zero};

/// The matrix of part `i` of `n` of a Bézier curve of `d` control points:
/// column `j` holds the weights of the old control points in the part's
/// control point `j` (the blossom at `a` repeated `d − 1 − j` times and `b`
/// repeated `j` times, for the part `[a, b] = [i/n, (i+1)/n]`).
pub fn bezier_part(d: usize, i: usize, n: usize) -> Vec<Vec<BigRational>> {
    let at = |x: usize| BigRational::new(BigInt::from(x), BigInt::from(n));
    bezier_between(d, &at(i), &at(i + 1))
}

/// The matrix of the part `[a, b]` of a Bézier curve of `d` control points
/// over `[0, 1]` (as [`bezier_part`], for any split points).
pub fn bezier_between(d: usize, a: &BigRational, b: &BigRational) -> Vec<Vec<BigRational>> {
    let (a, b) = (a.clone(), b.clone());
    let mut m = vec![vec![BigRational::zero(); d]; d];
    for j in 0..d {
        let args: Vec<BigRational> =
            std::iter::repeat_n(a.clone(), d - 1 - j).chain(std::iter::repeat_n(b.clone(), j)).collect();
        // De Casteljau on the unit vectors: the blossom's weights of each old point.
        let mut points: Vec<Vec<BigRational>> = (0..d)
            .map(|q| (0..d).map(|s| if s == q { BigRational::one() } else { BigRational::zero() }).collect())
            .collect();
        for t in &args {
            for q in 0..points.len() - 1 {
                let next = points[q + 1].clone();
                for (x, y) in points[q].iter_mut().zip(next) {
                    *x = (BigRational::one() - t) * x.clone() + t * y;
                }
            }
            points.pop();
        }
        for (row, w) in m.iter_mut().zip(&points[0]) {
            row[j] = w.clone();
        }
    }
    m
}
