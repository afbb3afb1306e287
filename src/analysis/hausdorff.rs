//! Hausdorff distance between point sets, with a k-d tree.

use rayon::prelude::*;

/// A static 3D k-d tree over points (2D points have z = 0).
pub struct KdTree {
    points: Vec<[f64; 3]>,
}

impl KdTree {
    /// Builds the tree in `O(n log² n)` (median splits by sorting).
    pub fn new(mut points: Vec<[f64; 3]>) -> KdTree {
        fn build(p: &mut [[f64; 3]], depth: usize) {
            if p.len() <= 1 {
                return;
            }
            let axis = depth % 3;
            let mid = p.len() / 2;
            p.select_nth_unstable_by(mid, |a, b| a[axis].total_cmp(&b[axis]));
            let (left, right) = p.split_at_mut(mid);
            build(left, depth + 1);
            build(&mut right[1..], depth + 1);
        }
        build(&mut points, 0);
        KdTree { points }
    }

    /// Squared distance from `q` to the nearest point (`∞` when empty).
    pub fn nearest_sq(&self, q: [f64; 3]) -> f64 {
        fn go(p: &[[f64; 3]], depth: usize, q: [f64; 3], best: &mut f64) {
            if p.is_empty() {
                return;
            }
            let mid = p.len() / 2;
            let m = p[mid];
            let d = (m[0] - q[0]).powi(2) + (m[1] - q[1]).powi(2) + (m[2] - q[2]).powi(2);
            if d < *best {
                *best = d;
            }
            let axis = depth % 3;
            let diff = q[axis] - m[axis];
            let (near, far) = if diff < 0.0 { (&p[..mid], &p[mid + 1..]) } else { (&p[mid + 1..], &p[..mid]) };
            go(near, depth + 1, q, best);
            if diff * diff < *best {
                go(far, depth + 1, q, best);
            }
        }
        let mut best = f64::INFINITY;
        go(&self.points, 0, q, &mut best);
        best
    }
}

/// `max_{a ∈ A} min_{b ∈ B} |a - b|`.
pub fn directed_hausdorff(a: &[[f64; 3]], b: &[[f64; 3]]) -> f64 {
    let tree = KdTree::new(b.to_vec());
    a.par_iter().map(|p| tree.nearest_sq(*p)).reduce(|| 0.0, f64::max).sqrt()
}

/// The Hausdorff distance `max(h(A, B), h(B, A))`, `O((n + m) log(n + m))`.
///
/// ```
/// let a = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]];
/// let b = [[0.0, 0.5, 0.0]];
/// assert!((bcifs::analysis::hausdorff(&a, &b) - 1.25f64.sqrt()).abs() < 1e-15);
/// ```
pub fn hausdorff(a: &[[f64; 3]], b: &[[f64; 3]]) -> f64 {
    directed_hausdorff(a, b).max(directed_hausdorff(b, a))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tree_agrees_with_brute_force() {
        let mut rng = crate::eval::Rng::new(3);
        let mut r = || (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
        let a: Vec<[f64; 3]> = (0..500).map(|_| [r(), r(), r()]).collect();
        let b: Vec<[f64; 3]> = (0..700).map(|_| [r(), r(), 0.0]).collect();
        let brute = |a: &[[f64; 3]], b: &[[f64; 3]]| {
            a.iter()
                .map(|p| {
                    b.iter().map(|q| (0..3).map(|k| (p[k] - q[k]).powi(2)).sum::<f64>()).fold(f64::INFINITY, f64::min)
                })
                .fold(0.0, f64::max)
                .sqrt()
        };
        assert_eq!(hausdorff(&a, &b), brute(&a, &b).max(brute(&b, &a)));
    }
}
