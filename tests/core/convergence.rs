//! Convergence decided soundly: joint spectral radius bounds on the
//! difference subspaces, with known values from the literature.

use bcifs::analysis::{JsrSettings, Verdict, check, jsr};
use bcifs::eval::{EvalError, EvalSettings, Evaluator};
use bcifs::{builtin_design, instantiate};

fn corner(a: f64, b: f64) -> bcifs::Automaton<f64> {
    let d = builtin_design("corner_cutting").unwrap();
    instantiate(&d, &[("a".into(), a), ("b".into(), b)]).unwrap().automaton
}

/// Chaikin (a = b = 1/4): the differences contract by exactly 1/2 (T0
/// restricted has eigenvalues 1/4 and 1/2; the adapted norm closes at 1/2).
#[test]
fn chaikin_has_jsr_one_half() {
    let j = jsr(&corner(0.25, 0.25), &JsrSettings::default()).unwrap();
    approx::assert_abs_diff_eq!(j.lower, 0.5, epsilon = 1e-12);
    assert!(j.upper >= j.lower && j.upper <= 0.5 + 1e-6, "{j}");
    assert_eq!(j.verdict(), Verdict::Converges);
}

/// Similarity maps have their ratio as JSR: Lévy (ratio 1/√2, one state)
/// and the dragon (1/√2, two states of the sign automaton).
#[test]
fn similarities_have_their_ratio() {
    let levy = instantiate(&builtin_design("levy").unwrap(), &[]).unwrap().automaton;
    let dragon = bcifs::schemes::normal_preset("dragon").unwrap().design().unwrap();
    let dragon = instantiate(&dragon, &[]).unwrap().automaton;
    for (name, a) in [("levy", levy), ("dragon", dragon)] {
        let j = jsr(&a, &JsrSettings::default()).unwrap();
        approx::assert_abs_diff_eq!(j.lower, 0.5f64.sqrt(), epsilon = 1e-12);
        assert!(j.upper <= 0.5f64.sqrt() + 1e-6, "{name}: {j}");
    }
}

/// The cubic B-spline and the four-point scheme contract differences by 1/2;
/// the Koch curve with control points by 1/3.
#[test]
fn schemes_of_seed_001_have_their_known_jsr() {
    for (name, expected) in [("bspline", 0.5), ("four-point", 0.5), ("koch-control", 1.0 / 3.0)] {
        let d = bcifs::schemes::ifs_preset(name, None, None).unwrap();
        let j = jsr(&instantiate(&d, &[]).unwrap().automaton, &JsrSettings::default()).unwrap();
        approx::assert_abs_diff_eq!(j.lower, expected, epsilon = 1e-9);
        assert!(j.upper <= expected + 1e-3, "{name}: {j}");
        assert_eq!(j.verdict(), Verdict::Converges, "{name}");
    }
}

/// Where cycles tie, the witness is the first cycle that attains the bound
/// (in the parts' order, then the search's), not the one whose last bits
/// happen to be largest: the bicubic patch's ρ = 1/2 is attained by each
/// single map (the first part's first map is the witness, as before this
/// rule a cycle of ten maps could be), and the Catmull-Clark cube's generated
/// automaton (parts repeating the same patch, rotated) names a single
/// arrow too; the bound itself is the same.
#[test]
fn the_witness_of_a_tie_is_the_first_cycle() {
    let bicubic = bcifs::schemes::ifs_preset("bicubic", None, None).unwrap();
    let j = jsr(&instantiate(&bicubic, &[]).unwrap().automaton, &JsrSettings::default()).unwrap();
    approx::assert_abs_diff_eq!(j.lower, 0.5, epsilon = 1e-12);
    assert_eq!(j.witness.len(), 1, "{}", j.witness_text());
    let cube =
        bcifs::mesh::read_mesh(std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/cube.off")))
            .unwrap();
    let design = bcifs::schemes::mesh_automaton(&cube, bcifs::mesh::Scheme::CatmullClark, None).unwrap();
    let design = bcifs::parse_design(&bcifs::write_design(&design), "cube", "cube").unwrap();
    let j = jsr(&instantiate(&design, &[]).unwrap().automaton, &JsrSettings::default()).unwrap();
    approx::assert_abs_diff_eq!(j.lower, 0.5, epsilon = 1e-12);
    assert_eq!(j.witness.len(), 1, "{}", j.witness_text());
}

/// Sokolov et al. 2010 §3 states convergence iff |a|, |b|, |1 − a − b| < 1. At
/// a = −0.9, b = 0.95 each matrix passes, yet ρ(T0 T1³)^(1/4) = 1.2601 on the
/// differences: the curve diverges (docs/errata.md).
#[test]
fn the_per_matrix_condition_is_not_sufficient() {
    let a = corner(-0.9, 0.95);
    let report = check(&a, &Default::default(), 1e-9).unwrap();
    assert!(report.ok && report.contractive, "each matrix passes the seed's test");
    assert_eq!(report.converges, Some(false));
    let j = report.jsr.unwrap();
    assert_eq!(j.witness, ["T0", "T1", "T1", "T1"]);
    approx::assert_abs_diff_eq!(j.lower, 1.2601, epsilon = 1e-4);
    assert_eq!(j.witness_text(), "T0 T1 T1 T1: ρ^(1/4) = 1.2601");
}

/// On a 0.05 grid of the parameter triangle, no verdict contradicts the
/// per-matrix condition (a matrix with ρ ≥ 1 is a cycle of length 1), the
/// JSR bounds find the points where the per-matrix test passes and the
/// curve still diverges, and every point is decided.
#[test]
fn verdicts_on_the_parameter_triangle() {
    let (mut passes_but_diverges, mut undecided, mut total) = (0, 0, 0);
    for i in -20..=20 {
        for k in -20..=20 {
            let (a, b) = (i as f64 * 0.05, k as f64 * 0.05);
            if a.abs() >= 1.0 || b.abs() >= 1.0 || (1.0 - a - b).abs() >= 1.0 {
                let j = jsr(&corner(a, b), &JsrSettings::quick()).unwrap();
                assert_eq!(j.verdict(), Verdict::Diverges, "a={a} b={b}: a matrix has ρ ≥ 1");
                continue;
            }
            total += 1;
            let j = jsr(&corner(a, b), &JsrSettings::default()).unwrap();
            assert!(j.lower <= j.upper + 1e-12, "a={a} b={b}: {j}");
            match j.verdict() {
                Verdict::Diverges => passes_but_diverges += 1,
                Verdict::Undecided => undecided += 1,
                Verdict::Converges => {}
            }
        }
    }
    // Measured: 54 of the 745 interior points diverge (cycles of length ≤ 10
    // find them; a search to length 16 finds no other and never contradicts
    // an upper bound), the 691 others are proven to converge.
    assert_eq!((passes_but_diverges, undecided, total), (54, 0, 745));
}

/// Evaluation refuses a divergent system, with the witness, unless forced;
/// the chaos game too.
#[test]
fn evaluators_refuse_divergent_systems() {
    let d = builtin_design("corner_cutting").unwrap();
    let a = corner(-0.9, 0.95);
    let model = d.model().unwrap();
    match Evaluator::new(&a, model, EvalSettings::default().with_depth(4)) {
        Err(EvalError::Diverges { witness }) => assert!(witness.contains("T0 T1 T1 T1"), "{witness}"),
        other => panic!("expected a refusal, got {:?}", other.err()),
    }
    let forced = Evaluator::new(&a, model, EvalSettings::default().with_depth(4).with_force()).unwrap();
    assert_eq!(forced.warnings().len(), 1);
    assert!(forced.evaluate().is_ok());
    let random = bcifs::eval::RandomSettings::default().with_points(100);
    assert!(matches!(bcifs::eval::chaos_game(&a, model, &random), Err(EvalError::Diverges { .. })));
    let fine = Evaluator::new(&corner(0.25, 0.25), model, EvalSettings::default()).unwrap();
    assert!(fine.warnings().is_empty());
}

/// Sokolov et al. 2010 §3: the intermediate T0 has `e_s` at (3, 3). Adjacency
/// `T0 b1 = T1 b0` compares T0's last two columns with T1's first two: at
/// (3, 2) the paper's matrices give `e_s` and `d_s`, so the paper's T0 is
/// admissible only when `e_s = d_s`; the solved family has `d_s` (= a) there.
#[test]
fn the_intermediate_t0_of_seed_004_needs_d_s() {
    let (a_s, b_s, d_s, e_s): (f64, f64, f64, f64) = (0.75, 0.25, 0.25, 0.75);
    let t0 = nalgebra::DMatrix::from_row_slice(3, 3, &[a_s, b_s, 0.0, d_s, e_s, a_s, 0.0, 0.0, e_s]);
    let t1 = nalgebra::DMatrix::from_row_slice(3, 3, &[b_s, 0.0, 0.0, e_s, a_s, b_s, 0.0, d_s, e_s]);
    let b0 = nalgebra::DMatrix::from_row_slice(3, 2, &[1.0, 0.0, 0.0, 1.0, 0.0, 0.0]);
    let b1 = nalgebra::DMatrix::from_row_slice(3, 2, &[0.0, 0.0, 1.0, 0.0, 0.0, 1.0]);
    approx::assert_abs_diff_eq!((&t0 * &b1 - &t1 * &b0).amax(), (e_s - d_s).abs(), epsilon = 1e-15);
    let family = bcifs::solve(&builtin_design("corner_cutting").unwrap()).unwrap();
    assert_eq!(family.entry_text("T0", 2, 2), family.entry_text("T0", 1, 0), "T0[3][3] is d_s");
    assert_ne!(family.entry_text("T0", 2, 2), family.entry_text("T0", 1, 1), "not e_s");
}

/// Sokolov et al. 2010 Fig. 11 lists `a = b` among the degenerate (piecewise linear)
/// cases; the footnote of §4 says `a = 0`. At a = 0 every point of the curve
/// lies on the control polygon; at a = b = 1/4 (Chaikin) it does not.
#[test]
fn the_degenerate_case_is_a_zero_not_a_equals_b() {
    let d = builtin_design("corner_cutting").unwrap();
    let model = d.model().unwrap();
    let off_polygon = |a: f64, b: f64| -> f64 {
        let inst = instantiate(&d, &[("a".into(), a), ("b".into(), b)]).unwrap();
        let shape =
            Evaluator::new(&inst.automaton, model, EvalSettings::default().with_depth(6)).unwrap().evaluate().unwrap();
        let p = &model.points;
        let dist = |q: [f64; 3]| {
            (0..p.len())
                .map(|i| {
                    let (s, e) = (&p[i], &p[(i + 1) % p.len()]);
                    let (dx, dy) = (e[0] - s[0], e[1] - s[1]);
                    let t = (((q[0] - s[0]) * dx + (q[1] - s[1]) * dy) / (dx * dx + dy * dy)).clamp(0.0, 1.0);
                    (q[0] - s[0] - t * dx).hypot(q[1] - s[1] - t * dy)
                })
                .fold(f64::INFINITY, f64::min)
        };
        shape.points().into_iter().map(dist).fold(0.0, f64::max)
    };
    assert!(off_polygon(0.0, 0.3) < 1e-12, "a = 0: piecewise linear");
    assert!(off_polygon(0.25, 0.25) > 0.05, "a = b = 1/4: Chaikin, not piecewise linear");
}

/// A verdict map of the corner cutting: outside the per-matrix domain every
/// pixel diverges; inside, converging and diverging pixels both occur.
#[test]
fn verdict_maps_agree_with_the_per_matrix_domain() {
    use bcifs::analysis::{ParameterPlane, verdict_map};
    let family = bcifs::solve(&builtin_design("corner_cutting").unwrap()).unwrap();
    let plane = ParameterPlane { x: ("a".into(), -1.5, 2.5), y: ("b".into(), -1.5, 2.5), size: (40, 40) };
    let map = verdict_map(&family, &plane, &JsrSettings::quick()).unwrap();
    let (mut inside_converge, mut inside_diverge) = (0, 0);
    for row in 0..40 {
        for column in 0..40 {
            let (a, b) = plane.at(column, row);
            let cell = map[row * 40 + column];
            let v = cell.verdict;
            let margin = 1.0 - a.abs().max(b.abs()).max((1.0 - a - b).abs());
            if margin.abs() < 1e-6 {
                continue; // on the boundary: the per-matrix test compares eigenvalues with a tolerance
            }
            let inside = margin > 0.0;
            assert_eq!(cell.per_matrix, inside, "a={a} b={b}");
            if !inside {
                assert_eq!(v, Verdict::Diverges, "a={a} b={b}");
            } else if v == Verdict::Converges {
                inside_converge += 1;
            } else if v == Verdict::Diverges {
                inside_diverge += 1;
            }
        }
    }
    assert!(inside_converge > 100 && inside_diverge > 5, "{inside_converge} converge, {inside_diverge} diverge");
    let bad = ParameterPlane { x: ("q".into(), 0.0, 1.0), ..plane };
    assert!(verdict_map(&family, &bad, &JsrSettings::quick()).is_err());
}

/// Issue 23, item 13: `check` decides what a plain norm bound decides. The
/// four-point scheme with tension w = −0.45 (mask −w, 1/2 + w: its
/// difference scheme's ∞-norms of long products fall below 1) and the
/// ternary 5-point scheme at tensions where `analyze ternary5` proves C0
/// (∞-norms of the difference mask's powers) converge, with an upper bound
/// below 1, where the ellipsoidal norm alone left them undecided (upper
/// bounds 1.3 to 1.5); the two commands agree.
#[test]
fn norm_bounds_decide_what_the_ellipsoid_leaves() {
    let four = bcifs::schemes::ifs_preset("four-point", None, None).unwrap();
    let text = bcifs::write_design(&four).replace("\"-1/16\"", "\"0.45\"").replace("\"9/16\"", "\"0.05\"");
    let tense = bcifs::parse_design(&text, "four.toml", "four").unwrap();
    let a = instantiate(&tense, &[]).unwrap().automaton;
    let j = jsr(&a, &JsrSettings::default()).unwrap();
    assert!(j.upper < 1.0 && j.lower > 0.96, "w = −0.45: {j}");
    assert_eq!(j.verdict(), Verdict::Converges);
    for omega in ["-17/225", "-29/450", "-54/625", "2/25", "0.0853", "1/20"] {
        let w = bcifs::algebra::Surd::parse(omega).unwrap();
        let design = bcifs::schemes::ifs_preset("ternary5", None, Some(&w)).unwrap();
        let a = instantiate(&design, &[]).unwrap().automaton;
        let j = jsr(&a, &JsrSettings::default()).unwrap();
        let row = bcifs::analysis::ternary::ternary5_analysis(w.to_f64());
        assert!(row.converges(), "ω = {omega}: analyze ternary5 proves C0");
        assert_eq!(j.verdict(), Verdict::Converges, "ω = {omega}: {j}");
        assert!(j.lower <= j.upper && j.upper < 1.0, "ω = {omega}: {j}");
    }
    // Past the mask method's reach (its C0 interval ends at 0.08531): long products prove 0.0905 (README).
    let w = bcifs::algebra::Surd::parse("0.0905").unwrap();
    let design = bcifs::schemes::ifs_preset("ternary5", None, Some(&w)).unwrap();
    let j = jsr(&instantiate(&design, &[]).unwrap().automaton, &JsrSettings::default()).unwrap();
    assert!(j.upper < 1.0 && !bcifs::analysis::ternary::ternary5_analysis(0.0905).converges(), "ω = 0.0905: {j}");
    // The tensor-product surfaces (maps T_i ⊗ T_j): bounded through their factors, so the
    // torus at ω = 1/20 (README) converges as its curve does, with no warning; ω = 1/10 diverges.
    for (omega, converges) in [("1/20", true), ("3/50", true), ("1/12", true), ("-2/25", true), ("1/10", false)] {
        let w = bcifs::algebra::Surd::parse(omega).unwrap();
        for name in ["ternary5-surface", "ternary5-torus"] {
            let design = bcifs::schemes::ifs_preset(name, None, Some(&w)).unwrap();
            let a = instantiate(&design, &[]).unwrap().automaton;
            let j = jsr(&a, &JsrSettings::default()).unwrap();
            let expected = if converges { Verdict::Converges } else { Verdict::Diverges };
            assert_eq!(j.verdict(), expected, "{name} at ω = {omega}: {j}");
            assert_eq!(bcifs::analysis::jsr_verdict(&a, &JsrSettings::quick()).unwrap(), expected, "{name} {omega}");
        }
    }
}

/// Issue 46 §15: an undecided member reports the best bound found. At
/// ω = 0.095 the ternary 5-point scheme's lower bound is 0.9956 and no target
/// of the branch and bound closes; its single matrices' norms bound it by 1.62
/// only, but the norms of all 3^L products of L maps (L up to 8) by 1.09 to
/// 1.11 (by the basis): the report says the latter. Checked here by forming those products in the
/// neighbour-difference basis (∞-norm), independently of the library.
#[test]
fn an_undecided_member_reports_the_best_bound_found() {
    let w = bcifs::algebra::Surd::parse("0.095").unwrap();
    let design = bcifs::schemes::ifs_preset("ternary5", None, Some(&w)).unwrap();
    let a = instantiate(&design, &[]).unwrap().automaton;
    let j = jsr(&a, &JsrSettings::default()).unwrap();
    assert_eq!(j.verdict(), Verdict::Undecided, "{j}");
    // The edge's maps (the square ones of the largest state), on differences of neighbours: each
    // map sends zero-sum vectors to zero-sum vectors (its columns sum to 1), so M Dᵀ = Dᵀ M' with
    // Dᵀ's columns the neighbour differences; a path's product is the M' in its order.
    let n = a.arrows().map(|(_, arrow)| arrow.matrix.nrows()).max().unwrap();
    let maps: Vec<nalgebra::DMatrix<f64>> = a
        .arrows()
        .filter(|(_, arrow)| arrow.matrix.nrows() == n && arrow.matrix.ncols() == n)
        .map(|(_, arrow)| arrow.matrix.clone())
        .collect();
    assert_eq!(maps.len(), 3);
    let dt = nalgebra::DMatrix::from_fn(n, n - 1, |r, c| {
        if r == c + 1 {
            1.0
        } else if r == c {
            -1.0
        } else {
            0.0
        }
    });
    let pinv = dt.clone().pseudo_inverse(1e-12).unwrap();
    let diff: Vec<nalgebra::DMatrix<f64>> = maps.iter().map(|m| &pinv * m * &dt).collect();
    let norm =
        |p: &nalgebra::DMatrix<f64>| p.row_iter().map(|r| r.iter().map(|x| x.abs()).sum::<f64>()).fold(0.0, f64::max);
    let mut level = vec![nalgebra::DMatrix::<f64>::identity(n - 1, n - 1)];
    let mut products = f64::INFINITY;
    for len in 1..=8 {
        level = level.iter().flat_map(|p| diff.iter().map(move |m| p * m)).collect();
        let worst = level.iter().map(norm).fold(0.0, f64::max);
        products = products.min(worst.powf(1.0 / f64::from(len)));
    }
    assert!(products < 1.1, "the products' bound: {products}");
    // The library's bases scale the differences its own way: its bound is the products' within 2 %,
    // far below the single maps' 1.62.
    assert!(j.lower <= j.upper && j.upper <= 1.02 * products, "{j} against the products' {products}");
}
