//! The seeds' errata (docs/errata.md): each statement that is wrong, shown
//! wrong by a computation.

use bcifs::algebra::Surd;
use bcifs::analysis::ternary::ternary5_analysis;
use bcifs::schemes::{Rules, normal_preset, unit_segment};

/// Schaefer et al. 2005 §2.1 splits "the 8×5 subdivision matrix S" of the cubic
/// B-spline on five control points; five points determine 7 new points, and
/// the two 5×5 blocks overlap in 3 rows: S is 7×5.
#[test]
fn the_cubic_bspline_matrix_has_seven_rows() {
    let blocks = Rules::cubic_bspline().blocks(5).unwrap();
    assert_eq!(blocks.len(), 2);
    assert_eq!(blocks[0][2..], blocks[1][..3], "S1 and S2 share three rows");
    let mut distinct: Vec<&Vec<Surd>> = Vec::new();
    for row in blocks.iter().flatten() {
        if !distinct.contains(&row) {
            distinct.push(row);
        }
    }
    assert_eq!(distinct.len(), 7);
}

/// Siddiqi et al. 2014 states C0 for -1/81 < ω < 53/324. The difference scheme's
/// blocks have the exact eigenvalue 11ω − 4/81 (from ω = 85/891 ≈ 0.0954 on
/// it is ≥ 1): the scheme is not C0 there, inside the paper's interval.
#[test]
fn the_ternary_c0_bound_is_too_large() {
    for omega in [0.1, 0.12, 0.15] {
        let r = ternary5_analysis(omega);
        let exact = 11.0 * omega - 4.0 / 81.0;
        assert!(r.c0_lower >= exact - 1e-9, "ω = {omega}: lower bound {} vs 11ω − 4/81 = {exact}", r.c0_lower);
        assert!(r.fails(), "not C0 at ω = {omega} < 53/324");
    }
    // 11ω − 4/81 reaches 1 exactly at ω = 85/891, inside the paper's range.
    let at = Surd::int(11).mul(&Surd::frac(85, 891)).sub(&Surd::frac(4, 81));
    assert_eq!(at, Surd::int(1));
    // 85/891 ≈ 0.0954 < 53/324 ≈ 0.1636: just above it the scheme is not C0.
    assert!(ternary5_analysis(85.0 / 891.0 + 1e-6).fails());
}

/// Li et al. 2013 calls its 7-ary preset (Fig. 9b) the Minkowski curve. One step
/// on the unit segment gives sub-segments of lengths ¼ ¼ ¼ ½ ¼ ¼ ¼, whose
/// similarity dimension (Moran: 6·4^(−s) + 2^(−s) = 1) is log 3 / log 2 ≈
/// 1.585, not the Minkowski sausage's 1.5 (eight segments of ¼).
#[test]
fn the_minkowski_preset_is_not_the_minkowski_curve() {
    let p = normal_preset("minkowski").unwrap();
    let pts = p.scheme.polygon(&unit_segment(), false, 1);
    let lengths: Vec<f64> = pts.windows(2).map(|w| (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1])).collect();
    let expected = [0.25, 0.25, 0.25, 0.5, 0.25, 0.25, 0.25];
    assert_eq!(lengths.len(), 7);
    for (l, e) in lengths.iter().zip(expected) {
        approx::assert_abs_diff_eq!(*l, e, epsilon = 1e-12);
    }
    // Moran's equation Σ r_i^s = 1, solved by bisection (the sum decreases in s).
    let moran = |s: f64| lengths.iter().map(|r| r.powf(s)).sum::<f64>() - 1.0;
    let (mut lo, mut hi) = (1.0, 2.0);
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if moran(mid) > 0.0 { lo = mid } else { hi = mid }
    }
    approx::assert_abs_diff_eq!(lo, 3f64.log2(), epsilon = 1e-12);
    assert!((lo - 1.5).abs() > 0.08);
    // The same from the automaton form by the dimension analysis (its maps are similarities).
    let design = p.scheme.design("minkowski", &p.polygon, p.closed).unwrap();
    let instance = bcifs::instantiate(&design, &[]).unwrap();
    let model = design.model().unwrap();
    let ev = bcifs::eval::Evaluator::new(&instance.automaton, model, bcifs::eval::EvalSettings::default()).unwrap();
    let piece = &ev.pieces().pieces[0];
    let root = bcifs::petgraph::graph::NodeIndex::new(piece.state);
    let s = bcifs::analysis::similarity_dimension(&instance.automaton, root, &piece.control, ev.pieces().dim).unwrap();
    approx::assert_abs_diff_eq!(s, 3f64.log2(), epsilon = 1e-9);
}

/// the Bézier-fractal contours paper eq. 13: with φ = arctan((y1 − y0)/s) the maps of the segment
/// (0, 0) → (3, 4) have the attractor (0, 0) → (3.904, 3.124); with the
/// segment's direction (atan2) each segment's two maps have exactly that
/// segment as attractor, in every quadrant: F1 fixes P0, F2 fixes P1, and
/// F1(P1) = F2(P0) is the midpoint (the two half-segments meet, so their
/// union, the attractor, is the segment).
#[test]
fn segment_maps_use_the_segment_direction() {
    use bcifs::schemes::{RowMap, segment_ifs, segment_ifs_as_printed};
    let apply = |f: &RowMap, p: [f64; 2]| [0, 1].map(|j| p[0] * f[0][j] + p[1] * f[1][j] + f[2][j]);
    let close = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).abs() < 1e-12 && (a[1] - b[1]).abs() < 1e-12;
    let [_, printed] = segment_ifs_as_printed([0.0, 0.0], [3.0, 4.0]);
    // The fixed point of F2 is where the printed maps put the end: iterate towards it.
    let mut end = [0.0, 0.0];
    for _ in 0..200 {
        end = apply(&printed, end);
    }
    assert!((end[0] - 3.904).abs() < 1e-3 && (end[1] - 3.124).abs() < 1e-3, "{end:?}");
    for (p0, p1) in [
        ([0.0, 0.0], [3.0, 4.0]),
        ([1.0, 2.0], [-3.0, 5.0]),
        ([0.5, -1.0], [-2.0, -4.0]),
        ([-1.0, 1.0], [2.0, -3.0]),
        ([2.0, 2.0], [2.0, -1.0]),
    ] {
        let [f1, f2] = segment_ifs(p0, p1);
        let mid = [(p0[0] + p1[0]) / 2.0, (p0[1] + p1[1]) / 2.0];
        assert!(close(apply(&f1, p0), p0) && close(apply(&f2, p1), p1), "{p0:?} → {p1:?}: fixed points");
        assert!(close(apply(&f1, p1), mid) && close(apply(&f2, p0), mid), "{p0:?} → {p1:?}: halves");
    }
}
