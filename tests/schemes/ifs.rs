//! Subdivision schemes as IFS (Schaefer et al. 2005): limit points equal closed forms,
//! the lifted IFS of eq. (2) has the same attractor, fractals with control
//! points reproduce the classic ones and deform locally, dropped maps give subsets.

use crate::hausdorff::{directed_hausdorff, hausdorff};
use bcifs::analysis::{DEFAULT_CHECK_TOLERANCE, check};
use bcifs::eval::{EvalSettings, Evaluator};
use bcifs::schemes::{BSpline, IFS_NAMES, LiftError, LiftedIfs, Rules, ifs_preset, koch_blocks, normal_preset, to_f64};

use super::{evaluate, lift, points2};

/// Cox-de Boor: the B-spline of degree `d` over the conventional knot vector
/// `knots` (the blossoming knots with one extra knot at each end) at `t`.
fn bspline_point(d: usize, knots: &[f64], control: &[Vec<f64>], t: f64) -> [f64; 2] {
    let n = control.len();
    let basis = |i: usize, t: f64| -> f64 {
        // N_{i,d}(t) by the triangular recursion, half-open intervals, last one closed.
        let mut nn: Vec<f64> = (0..=d)
            .map(|j| {
                let (a, b) = (knots[i + j], knots[i + j + 1]);
                let last = (b - knots[knots.len() - 1]).abs() < 1e-15 && t == b;
                f64::from((a <= t && t < b) || (last && a < b))
            })
            .collect();
        for k in 1..=d {
            for j in 0..=d - k {
                let (a0, a1) = (knots[i + j], knots[i + j + k]);
                let (b0, b1) = (knots[i + j + 1], knots[i + j + k + 1]);
                let left = if a1 > a0 { (t - a0) / (a1 - a0) * nn[j] } else { 0.0 };
                let right = if b1 > b0 { (b1 - t) / (b1 - b0) * nn[j + 1] } else { 0.0 };
                nn[j] = left + right;
            }
        }
        nn[0]
    };
    let mut p = [0.0; 2];
    for i in 0..n {
        let b = basis(i, t);
        p[0] += b * control[i][0];
        p[1] += b * control[i][1];
    }
    p
}

/// The leaves of an edge at depth k start at equally spaced parameters of
/// the domain [t_(d-1), t_(n-1)]; every point agrees with Cox-de Boor within
/// 1e-12 (products of k dyadic matrices: rounding ~1e-15).
#[test]
fn bspline_limit_points_are_the_closed_form() {
    for (name, knots) in [
        ("bspline", vec![-1.0, 0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0]),
        ("bspline-end", vec![0.0, 0.0, 0.0, 0.0, 1.0, 2.0, 2.0, 2.0, 2.0]),
    ] {
        let g = ifs_preset(name, None, None).unwrap();
        let design = g;
        let control = design.model().cloned().unwrap().points;
        let (lo, hi) = (knots[3], knots[5]);
        for k in [1, 4, 8] {
            let pts = points2(&evaluate(&design, k));
            assert_eq!(pts.len(), (1 << k) + 1);
            for (j, p) in pts.iter().enumerate() {
                let t = lo + (hi - lo) * j as f64 / (1 << k) as f64;
                let q = bspline_point(3, &knots, &control, t);
                assert!(approx::abs_diff_eq!(p[..2], q[..2], epsilon = 1e-12), "{name} k={k} j={j}: {p:?} {q:?}");
            }
        }
    }
}

#[test]
fn bezier_limit_points_are_bernstein_and_the_union_is_two_curves() {
    let g = ifs_preset("bezier-union", None, None).unwrap();
    let design = g;
    let control = design.model().cloned().unwrap().points;
    let k = 7;
    let shape = evaluate(&design, k);
    let lines: Vec<_> = shape.polylines().collect();
    let per = (1 << k) + 1;
    assert_eq!(lines, vec![(0, per, false), (per, per, false)], "two separate curves");
    let pts = points2(&shape);
    for (c, piece) in control.chunks(3).enumerate() {
        for j in 0..per {
            let t = j as f64 / (per - 1) as f64;
            let w = [(1.0 - t).powi(2), 2.0 * t * (1.0 - t), t * t];
            for a in 0..2 {
                let expected: f64 = (0..3).map(|i| w[i] * piece[i][a]).sum();
                approx::assert_abs_diff_eq!(pts[c * per + j][a], expected, epsilon = 1e-12);
            }
        }
    }
    // The paper's construction: one IFS with block-diagonal maps diag(P⁻¹S_iP, Q⁻¹S_iQ),
    // started from a point with a 1 in each homogeneous component, draws both curves.
    let blocks: Vec<_> = BSpline::bezier(2).blocks(2).unwrap().iter().map(to_f64).collect();
    let (lp, lq) = (LiftedIfs::new(&blocks, &control[..3]).unwrap(), LiftedIfs::new(&blocks, &control[3..]).unwrap());
    let mut union = Vec::new();
    let start = vec![0.3, -0.7, 1.0];
    for l in [&lp, &lq] {
        union.extend(l.iterate(std::slice::from_ref(&start), 12).into_iter().map(|p| [p[0], p[1], 0.0]));
    }
    let dense = lift(&points2(&evaluate(&design, 12)));
    let h = hausdorff(&union, &dense);
    // 2^-12 of a unit-sized curve, twice (sampling of both sets).
    assert!(h < 2e-3, "{h}");
}

/// The four-point limit interpolates its control points: the 7-point
/// attractor runs from P2 to P4 through P3, at parameters 0, 1/2 and 1.
#[test]
fn four_point_limit_interpolates() {
    let design = ifs_preset("four-point", None, None).unwrap();
    let control = design.model().cloned().unwrap().points;
    let k = 6;
    let pts = points2(&evaluate(&design, k));
    for (j, i) in [(0, 2), (1 << (k - 1), 3), (1 << k, 4)] {
        approx::assert_abs_diff_eq!(pts[j][..2], control[i][..2], epsilon = 1e-12);
    }
    // Every point of the closed-polygon limit of the plain rules is a control point at some level.
    let rules = Rules::four_point();
    let square = vec![vec![0.0, 0.0], vec![1.0, 0.0], vec![1.0, 1.0], vec![0.0, 1.0]];
    let refined = rules.polygon(&square, true, 3);
    for (i, p) in square.iter().enumerate() {
        assert_eq!(&refined[i * 8], p);
    }
}

/// Eq. (2): with affinely independent control points the lifted IFS
/// f_i(X) = X P⁻¹ S_i P has the same attractor as the barycentric automaton,
/// from any start set (a point, a segment, a triangle).
#[test]
fn lifted_ifs_has_the_same_attractor() {
    let design = ifs_preset("bspline", None, None).unwrap();
    let control = design.model().cloned().unwrap().points;
    let curve = lift(&points2(&evaluate(&design, 12)));
    let blocks: Vec<_> = BSpline::uniform(3, 5).unwrap().blocks(2).unwrap().iter().map(to_f64).collect();
    let ifs = LiftedIfs::new(&blocks, &control).unwrap();
    let homogeneous = |x: f64, y: f64| vec![x, y, 0.2, -0.4, 1.0];
    let starts: [Vec<Vec<f64>>; 3] = [
        vec![homogeneous(10.0, -3.0)],
        (0..20).map(|i| homogeneous(i as f64 / 2.0, 1.0)).collect(),
        (0..30).map(|i| homogeneous((i % 10) as f64, (i / 10) as f64 * 3.0)).collect(),
    ];
    for start in starts {
        let pts: Vec<[f64; 3]> = ifs.iterate(&start, 14).into_iter().map(|p| [p[0], p[1], 0.0]).collect();
        let h = hausdorff(&pts, &curve);
        // Contraction 1/2 per level from a start ~10 units away: ~10 · 2^-14 plus the sampling of the curve.
        assert!(h < 5e-3, "{h}");
    }
    // Collinear control points: the lift is singular, the barycentric form still works.
    let line: Vec<Vec<f64>> = (0..5).map(|i| vec![i as f64, 2.0 * i as f64]).collect();
    assert_eq!(LiftedIfs::new(&blocks, &line).unwrap_err(), LiftError::Singular);
    assert!(LiftError::Singular.to_string().contains("barycentric form"));
    let straight = ifs_preset("bspline", Some(line), None).unwrap();
    let pts = points2(&evaluate(&straight, 5));
    assert!(pts.iter().all(|p| (p[1] - 2.0 * p[0]).abs() < 1e-12));
}

/// With its natural control points the Koch IFS of §4.1 is the classic Koch
/// curve: the same points as the normal-vector Koch scheme (Li et al. 2013 eq. 5).
#[test]
fn koch_with_control_points_is_the_classic_koch_curve() {
    let design = ifs_preset("koch-control", None, None).unwrap();
    let koch = normal_preset("koch").unwrap();
    for k in 1..=5 {
        let ours = points2(&evaluate(&design, k));
        let classic = koch.scheme.polygon(&koch.polygon, false, k);
        assert_eq!(ours.len(), classic.len());
        for (a, b) in ours.iter().zip(&classic) {
            approx::assert_abs_diff_eq!(a[..2], b[..2], epsilon = 1e-12);
        }
    }
}

/// Moving control point P1 deforms the Koch curve only on its left half:
/// the maps S3 and S4 do not use P1 (§4.1, Fig. 10 bottom).
#[test]
fn moving_a_control_point_deforms_locally() {
    let natural = ifs_preset("koch-control", None, None).unwrap();
    let mut points = natural.model().cloned().unwrap().points;
    points[1] = vec![0.25, 0.15];
    let moved = ifs_preset("koch-control", Some(points), None).unwrap();
    let k = 4;
    let (a, b) = (points2(&evaluate(&natural, k)), points2(&evaluate(&moved, k)));
    let half = a.len() / 2;
    assert!(a[..half].iter().zip(&b[..half]).any(|(p, q)| (p[0] - q[0]).abs() > 1e-3));
    for (p, q) in a[half..].iter().zip(&b[half..]) {
        assert_eq!(p, q, "the right half does not move");
    }
    assert!(koch_blocks()[2].iter().chain(&koch_blocks()[3]).all(|row| row[1].is_zero()));
}

/// The Sierpinski IFS of §4.2 with its natural control points is the classic
/// gasket: its cells are the classic IFS images of the control triangle, so
/// the cell centroids are the classic IFS images of the centroid (exactly).
/// Moving the edge points bends the gasket.
#[test]
fn sierpinski_with_control_points_is_the_classic_gasket() {
    let design = ifs_preset("sierpinski-control", None, None).unwrap();
    let control = design.model().cloned().unwrap().points;
    let corners = [&control[0], &control[2], &control[4]];
    let k = 6;
    let ours = lift(&points2(&evaluate(&design, k)));
    let centroid: Vec<f64> = (0..2).map(|a| control.iter().map(|p| p[a]).sum::<f64>() / 6.0).collect();
    let mut classic = vec![[centroid[0], centroid[1], 0.0]];
    for _ in 0..k {
        classic = corners
            .iter()
            .flat_map(|c| classic.iter().map(move |p| [(p[0] + c[0]) / 2.0, (p[1] + c[1]) / 2.0, 0.0]))
            .collect();
    }
    assert!(hausdorff(&ours, &classic) < 1e-12);
    let mut bent = control.clone();
    bent[1] = vec![0.5, -0.2];
    let other = lift(&points2(&evaluate(&ifs_preset("sierpinski-control", Some(bent), None).unwrap(), k)));
    assert!(hausdorff(&ours, &other) > 0.01);
}

/// §3.3: dropping maps gives a subset of the attractor. The points of the
/// IFS without T2 lie on the full attractor (directed Hausdorff distance at
/// the sampling scale), the converse fails.
#[test]
fn dropping_maps_gives_a_subset() {
    for name in ["sierpinski-control", "bspline", "koch-control"] {
        let design = ifs_preset(name, None, None).unwrap();
        let inst = bcifs::instantiate(&design, &[]).unwrap();
        let model = design.model().cloned().unwrap();
        let run = |k: usize, drop: &[&str]| {
            let s = Evaluator::new(&inst.automaton, &model, EvalSettings::default().with_depth(k).without(drop))
                .unwrap()
                .evaluate()
                .unwrap();
            lift(&points2(&s))
        };
        let full = run(8, &[]);
        let subset = run(5, &["T1"]);
        let into = directed_hausdorff(&subset, &full);
        let back = directed_hausdorff(&full, &subset);
        assert!(into < 0.02, "{name}: {into}");
        assert!(back > 5.0 * into.max(1e-3), "{name}: {back} vs {into}");
    }
}

/// Every catalogue automaton passes `check` (constraints, column sums, contractivity).
#[test]
fn every_catalogue_automaton_passes_check() {
    for name in IFS_NAMES {
        let design = ifs_preset(name, None, None).unwrap();
        let inst = bcifs::instantiate(&design, &[]).unwrap();
        let report = check(&inst.automaton, &inst.values, DEFAULT_CHECK_TOLERANCE).unwrap();
        assert!(report.ok && report.contractive, "{name}: {:?}", report.constraints);
    }
}
