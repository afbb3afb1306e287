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

/// The control net of a Bézier triangle of `d` control points a side
/// (degree `d − 1`): the multi-indices `(a, b)` (the powers of the second
/// and third barycentric coordinates), row by row from the first side
/// (`b = 0`), `a` increasing: `d(d + 1)/2` points.
pub fn triangle_net(d: usize) -> Vec<(usize, usize)> {
    let m = d.saturating_sub(1);
    (0..=m).flat_map(|b| (0..=m - b).map(move |a| (a, b))).collect()
}

/// The matrix of the sub-triangle with corners `corners` (barycentric
/// coordinates over the triangle's corners) of a Bézier triangle of `d`
/// control points a side: column `j` holds the weights of the old net's
/// points in the sub-triangle's point `j` of [`triangle_net`], the blossom
/// at its corners repeated by that point's multi-index.
pub fn bezier_triangle_part(d: usize, corners: &[[BigRational; 3]; 3]) -> Vec<Vec<BigRational>> {
    let net = triangle_net(d);
    let index = |a: usize, b: usize| net.iter().position(|&p| p == (a, b)).unwrap_or(0);
    let m = d - 1;
    let mut matrix = vec![vec![BigRational::zero(); net.len()]; net.len()];
    for (j, &(a, b)) in net.iter().enumerate() {
        let args = std::iter::repeat_n(&corners[0], m - a - b)
            .chain(std::iter::repeat_n(&corners[1], a))
            .chain(std::iter::repeat_n(&corners[2], b));
        // The blossom's weights: every way of sending each argument to one corner of the old net.
        let mut weights: Vec<BigRational> = vec![BigRational::zero(); net.len()];
        weights[index(0, 0)] = BigRational::one();
        let mut used = 0;
        for t in args {
            let mut next = vec![BigRational::zero(); net.len()];
            for (q, &(x, y)) in net.iter().enumerate() {
                if x + y > used || weights[q].is_zero() {
                    continue;
                }
                next[q] += &weights[q] * &t[0];
                next[index(x + 1, y)] += &weights[q] * &t[1];
                next[index(x, y + 1)] += &weights[q] * &t[2];
            }
            weights = next;
            used += 1;
        }
        for (row, w) in matrix.iter_mut().zip(weights) {
            row[j] = w;
        }
    }
    matrix
}
