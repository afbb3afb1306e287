//! Hausdorff distances between point sets, for tests (nearest neighbours by
//! a `kiddo` k-d tree; 2D points have z = 0).

use kiddo::{ImmutableKdTree, SquaredEuclidean};

/// `max_{a ∈ A} min_{b ∈ B} |a - b|` (0 when `A` is empty, ∞ when only `B` is).
pub fn directed_hausdorff(a: &[[f64; 3]], b: &[[f64; 3]]) -> f64 {
    if a.is_empty() {
        return 0.0;
    }
    if b.is_empty() {
        return f64::INFINITY;
    }
    let tree = ImmutableKdTree::<f64, 3>::new_from_slice(b).expect("a k-d tree of finite points");
    a.iter().map(|p| tree.query(p).nearest_one::<SquaredEuclidean<f64>>().execute().distance).fold(0.0, f64::max).sqrt()
}

/// The Hausdorff distance `max(h(A, B), h(B, A))`.
pub fn hausdorff(a: &[[f64; 3]], b: &[[f64; 3]]) -> f64 {
    directed_hausdorff(a, b).max(directed_hausdorff(b, a))
}

#[test]
fn hausdorff_of_shifted_sets() {
    let a = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]];
    let b = [[0.0, 0.5, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]];
    assert_eq!(directed_hausdorff(&a, &b), 0.5);
    assert_eq!(directed_hausdorff(&b, &a), 1.0);
    assert_eq!(hausdorff(&a, &b), 1.0);
}

/// The k-d tree agrees with brute force on random sets.
#[test]
fn tree_agrees_with_brute_force() {
    let mut state = 3u64;
    let mut r = || {
        state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let a: Vec<[f64; 3]> = (0..500).map(|_| [r(), r(), r()]).collect();
    let b: Vec<[f64; 3]> = (0..700).map(|_| [r(), r(), 0.0]).collect();
    let brute = |a: &[[f64; 3]], b: &[[f64; 3]]| {
        a.iter()
            .map(|p| b.iter().map(|q| (0..3).map(|k| (p[k] - q[k]).powi(2)).sum::<f64>()).fold(f64::INFINITY, f64::min))
            .fold(0.0, f64::max)
            .sqrt()
    };
    approx::assert_abs_diff_eq!(hausdorff(&a, &b), brute(&a, &b).max(brute(&b, &a)), epsilon = 1e-15);
}
