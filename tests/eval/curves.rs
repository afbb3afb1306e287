//! Curves and point sets: closed forms, junctions, any start set, chaos game.

use crate::hausdorff::hausdorff;
use bcifs::eval::{EvalError, EvalSettings, Evaluator, PlanError, RandomSettings, chaos_game};
use nalgebra::DMatrix;

use super::{eval, load};

/// Corner cutting at a = b = 1/4 is Chaikin's scheme: every output point lies on
/// the uniform quadratic B-spline of the closed control polygon. Leaf j of
/// piece i (points P_i, P_{i+1}, P_{i+2}) starts at t = j / 2^k.
#[test]
fn chaikin_output_is_the_quadratic_bspline() {
    let (_, model, _) = load("corner_cutting", &[]);
    let k = 9;
    let shape = eval("corner_cutting", &[("a", 0.25), ("b", 0.25)], EvalSettings::default().with_depth(k));
    let n = model.points.len();
    let per = 1 << k;
    assert_eq!(shape.vertex_count(), n * per, "closed: no repeated end point");
    for (idx, p) in shape.points().iter().enumerate() {
        let (i, j) = (idx / per, idx % per);
        let t = j as f64 / per as f64;
        let w = [(1.0 - t).powi(2) / 2.0, 0.5 + t - t * t, t * t / 2.0];
        for a in 0..2 {
            let expected: f64 = (0..3).map(|m| w[m] * model.points[(i + m) % n][a]).sum();
            // Products of 9 matrices with dyadic entries: rounding ~1e-15.
            assert!(approx::abs_diff_eq!(p[a], expected, epsilon = 1e-12), "point {idx}: {} vs {expected}", p[a]);
        }
    }
    let polylines: Vec<_> = shape.polylines().collect();
    assert_eq!(polylines, vec![(0, n * per, true)]);
}

fn matrix(a: &bcifs::Automaton<f64>, name: &str) -> DMatrix<f64> {
    a.arrow(a.arrow_id(name).unwrap()).matrix.clone()
}

/// At any admissible parameters, consecutive sub-curves meet: the end of
/// sub-curve i is the start of sub-curve i+1 (adjacency constraint), within
/// 1e-12 in modelling space, at every depth.
#[test]
fn sub_curves_meet_at_any_admissible_parameters() {
    // SplitMix64: a fixed, well-mixed sequence of parameters.
    let mut state = 11u64;
    let mut uniform = || {
        state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    };
    for _ in 0..20 {
        // Sample the convergence domain |a|, |b|, |1-a-b| < 1.
        let (a, b) = loop {
            let (a, b) = (uniform() * 2.0 - 1.0, uniform() * 2.0 - 1.0);
            if (1.0 - a - b).abs() < 0.95 && a.abs() < 0.95 && b.abs() < 0.95 {
                break (a, b);
            }
        };
        let (auto, model, _) = load("corner_cutting", &[("a", a), ("b", b)]);
        let (t0, t1, tv) = (matrix(&auto, "T0"), matrix(&auto, "T1"), matrix(&auto, "Tv"));
        // Vertex fixed point: Tv v = v, Σ v = 1.
        let v = nalgebra::DVector::from_vec(vec![b / (a + b), a / (a + b)]);
        assert!((&tv * &v - &v).amax() < 1e-12);
        let (b0, b1) = (matrix(&auto, "b0"), matrix(&auto, "b1"));
        let (start, end) = (&b0 * &v, &b1 * &v);
        let p = DMatrix::from_fn(2, 3, |r, c| model.points[c][r]);
        let mut cells = vec![p];
        for _depth in 0..7 {
            cells = cells.iter().flat_map(|c| [c * &t0, c * &t1]).collect();
            for pair in cells.windows(2) {
                let gap = (&pair[0] * &end - &pair[1] * &start).amax();
                assert!(gap < 1e-12, "a={a}, b={b}: gap {gap}");
            }
        }
    }
}

/// An open control polygon: consecutive pieces share their end points, so
/// the polyline is one connected run ending at the last piece's end.
#[test]
fn open_polygons_are_one_polyline() {
    let (a, mut model, _) = load("corner_cutting", &[]);
    model.layout = bcifs::Layout::Open;
    let shape = Evaluator::new(&a, &model, EvalSettings::default().with_depth(4)).unwrap().evaluate().unwrap();
    let pieces = model.points.len() - 2;
    assert_eq!(shape.polylines().collect::<Vec<_>>(), vec![(0, pieces * 16 + 1, false)]);
    // The first point is the start of the first piece: (P0 + P1) / 2 for Chaikin.
    let p = shape.point(0);
    assert!((p[0] - 1.0).abs() < 1e-15 && p[1].abs() < 1e-15);
}

fn points(shape: &bcifs::geometry::Shape) -> Vec<[f64; 3]> {
    shape.points()
}

/// Schaefer et al. 2005 §2 / Sokolov et al. 2010 §2.1: any compact start set converges to the same
/// attractor. Koch from a single point (the centroid of the frame) against
/// the curve's vertices: each depth-k cell is a similarity of ratio 3^-k of
/// the root frame, so the distance is at most diam(frame) · 3^-k.
#[test]
fn any_start_set_converges_to_the_attractor() {
    let reference = points(&eval("koch", &[], EvalSettings::default().with_depth(9)));
    let mut last = f64::INFINITY;
    for k in 2..=7 {
        let from_point =
            eval("koch", &[], EvalSettings::default().with_depth(k).with_start("e", vec![vec![1.0 / 3.0; 3]]));
        let h = hausdorff(&points(&from_point), &reference);
        let bound = 2f64.sqrt() * 3f64.powi(-(k as i32)) + 2f64.sqrt() * 3f64.powi(-9);
        assert!(h <= bound, "depth {k}: {h} > {bound}");
        assert!(h < last, "depth {k}: {h} did not shrink from {last}");
        last = h;
    }
    // A segment start set (two points) and a triangle converge too.
    let seg = eval(
        "koch",
        &[],
        EvalSettings::default().with_depth(7).with_start("e", vec![vec![1.0, 0.0, 0.0], vec![0.0, 0.0, 1.0]]),
    );
    assert!(hausdorff(&points(&seg), &reference) < 2f64.sqrt() * 3f64.powi(-7) * 1.01 + 1e-3);
}

/// The fern from a square and from its centroid: Hausdorff distance shrinks
/// with depth (contraction ratio of the fern is at most 0.85 per level).
#[test]
fn fern_from_different_start_sets_converges() {
    let mut previous = f64::INFINITY;
    for k in [2, 4, 6, 8] {
        let square = points(&eval("fern", &[], EvalSettings::default().with_depth(k)));
        let centroid = points(&eval(
            "fern",
            &[],
            EvalSettings::default().with_depth(k).with_start("fern", vec![vec![1.0 / 3.0; 3]]),
        ));
        let h = hausdorff(&square, &centroid);
        assert!(h < previous, "depth {k}: {h} ≥ {previous}");
        previous = h;
    }
    assert!(previous < 2.0, "{previous}");
}

/// The chaos game is reproducible with a seed, whatever the thread count,
/// and its points lie on the attractor (close to a deep deterministic set).
#[test]
fn chaos_game_is_reproducible_and_on_the_attractor() {
    let (a, model, _) = load("levy", &[]);
    let one =
        chaos_game(&a, &model, &RandomSettings::default().with_points(20_000).with_seed(5).with_threads(1)).unwrap();
    let two =
        chaos_game(&a, &model, &RandomSettings::default().with_points(20_000).with_seed(5).with_threads(2)).unwrap();
    assert_eq!(one.positions, two.positions);
    let other = chaos_game(&a, &model, &RandomSettings::default().with_points(20_000).with_seed(6)).unwrap();
    assert_ne!(one.positions, other.positions);
    let deterministic = points(&eval("levy", &[], EvalSettings::default().with_depth(16)));
    // Depth-16 cells of the Lévy curve have diameter 2^-8 · diam(frame) ≈ 0.0055.
    let h = crate::hausdorff::directed_hausdorff(&points(&one), &deterministic);
    assert!(h < 0.006, "{h}");
    // Two-state fern: the Sierpinski branch is reached.
    let (a, model, _) = load("fern_sierpinski", &[]);
    let cloud = chaos_game(&a, &model, &RandomSettings::default().with_points(200_000)).unwrap();
    let branch: Vec<[f64; 3]> = {
        // The branch T2(A_S): the triangle image under T2 = [[0.2,-0.26],[0.23,0.22]] + (0, 1.6).
        let t2 = |x: f64, y: f64| [0.2 * x - 0.26 * y, 0.23 * x + 0.22 * y + 1.6, 0.0];
        vec![t2(0.0, 0.0), t2(1.0, 0.0), t2(0.0, 1.0)]
    };
    let near_branch = crate::hausdorff::directed_hausdorff(&branch, &points(&cloud));
    assert!(near_branch < 0.05, "the chaos game misses the Sierpinski branch: {near_branch}");
    // Every point lies in the fern's hull: x in [-2.2, 2.7], y in [0, 10].
    assert!(points(&cloud).iter().all(|p| (-2.2..2.7).contains(&p[0]) && (0.0..10.0).contains(&p[1])));
}

/// Non-contractive and non-stochastic systems are refused before evaluation.
#[test]
fn bad_systems_are_refused_before_evaluation() {
    let (a, model, _) = load("corner_cutting", &[("a", 1.5), ("b", 0.25)]);
    match Evaluator::new(&a, &model, EvalSettings::default()) {
        Err(EvalError::Plan(PlanError::NotContractive { arrow, .. })) => assert_eq!(arrow, "T0"),
        Err(e) => panic!("unexpected {e}"),
        Ok(_) => panic!("accepted a non-contractive system"),
    }
    let (mut a, model, _) = load("corner_cutting", &[]);
    let id = a.arrow_id("T1").unwrap();
    a.arrow_mut(id).matrix[(0, 0)] += 0.1;
    let err = Evaluator::new(&a, &model, EvalSettings::default()).err().expect("refused");
    assert!(err.to_string().contains("`T1` is not stochastic: column 0 sums to 1.1"), "{err}");
}

/// An in-memory evaluation over the limit is refused with the estimate.
#[test]
fn oversized_output_is_refused_with_an_estimate() {
    let (a, model, _) = load("levy", &[]);
    let ev = Evaluator::new(&a, &model, EvalSettings::default().with_depth(24).with_memory_limit(1 << 20)).unwrap();
    let err = ev.evaluate().expect_err("refused");
    // 2^24 + 1 points of 2 coordinates.
    assert!(matches!(err, EvalError::TooLarge { estimate, .. } if estimate == ((1u128 << 24) + 1) * 16), "{err}");
    assert!(err.to_string().contains("stream a fixed depth"), "{err}");
}

/// Adaptive evaluation: every emitted cell is below the tolerance, so
/// consecutive points are closer than it.
#[test]
fn adaptive_evaluation_meets_the_tolerance() {
    let eps = 0.01;
    let shape = eval("corner_cutting", &[("a", 0.1), ("b", 0.4)], EvalSettings::default().with_tolerance(eps));
    let pts = shape.points();
    for w in pts.windows(2) {
        let d = ((w[0][0] - w[1][0]).powi(2) + (w[0][1] - w[1][1]).powi(2)).sqrt();
        assert!(d < eps, "{d}");
    }
    assert!(pts.len() > 100);
}

/// `Evaluator::new` uses the model's start sets; settings given for a state
/// take their place, so both ways give the same points.
#[test]
fn the_models_start_sets_are_honoured() {
    let (a, model, _) = load("fern_sierpinski", &[]);
    assert!(!model.start.is_empty(), "the shipped model has start sets");
    let settings = EvalSettings::default().with_depth(3).with_threads(1);
    let from_model = Evaluator::new(&a, &model, settings.clone()).unwrap().evaluate().unwrap();
    let mut bare = model.clone();
    let start = std::mem::take(&mut bare.start);
    let mut given = settings.clone();
    for (state, points) in &start {
        given = given.with_start(state, points.clone());
    }
    let from_settings = Evaluator::new(&a, &bare, given).unwrap().evaluate().unwrap();
    assert_eq!(from_model.positions, from_settings.positions);
    let without = Evaluator::new(&a, &bare, settings).unwrap().evaluate().unwrap();
    assert_ne!(from_model.positions, without.positions, "the start set changes the points");
}

/// Dropping an arrow of a curve leaves a subset with gaps: points, no
/// polyline joining across the gaps (Koch without its second quarter).
#[test]
fn dropped_arrows_give_points_not_lines() {
    let (a, model, _) = load("koch", &[]);
    let full = Evaluator::new(&a, &model, EvalSettings::default().with_depth(4)).unwrap().evaluate().unwrap();
    assert_eq!(full.polylines().count(), 1);
    let subset =
        Evaluator::new(&a, &model, EvalSettings::default().with_depth(4).without(&["T1"])).unwrap().evaluate().unwrap();
    assert_eq!(subset.polylines().count(), 0);
    assert_eq!(subset.vertex_count(), 3usize.pow(4) + 1);
}

/// A tolerance whose output would not fit the memory limit is refused with
/// the size reached, not by the allocator.
#[test]
fn adaptive_evaluation_respects_the_memory_limit() {
    let (a, model, _) = load("levy", &[]);
    let settings = EvalSettings::default().with_tolerance(1e-9).with_memory_limit(1 << 20);
    let err = Evaluator::new(&a, &model, settings).unwrap().evaluate().unwrap_err();
    assert!(matches!(err, bcifs::eval::EvalError::TooLarge { limit, .. } if limit == 1 << 20), "{err}");
}

/// A chaos game whose points would not fit the memory limit is refused
/// before allocating them.
#[test]
fn chaos_games_respect_the_memory_limit() {
    let (a, model, _) = load("fern", &[]);
    let mut settings = RandomSettings::default().with_points(2_000_000_000);
    settings.memory_limit = 1 << 30;
    let err = chaos_game(&a, &model, &settings).unwrap_err();
    assert!(matches!(err, EvalError::TooLarge { estimate, .. } if estimate == 32_000_000_000), "{err}");
}

/// A tolerance on a plain IFS is a Hausdorff bound: every cell stops when
/// the ball that holds its part of the attractor is smaller than ε, and
/// emits a point of that ball. A long chaos game lies on the attractor, so
/// it is within ε of the output; the output is within ε of the attractor,
/// hence within ε plus the chaos game's own gaps of its points. The fixed
/// default depth, the issue this answers, is far coarser.
#[test]
fn tolerance_on_a_plain_ifs_bounds_the_hausdorff_distance() {
    // The fern (one state), and the fern with a Sierpinski branch (graph-directed, two states).
    for (name, epsilons) in [("fern", &[0.2, 0.05][..]), ("fern_sierpinski", &[0.05][..])] {
        let (a, model, _) = load(name, &[]);
        let settings = RandomSettings::default().with_points(1_000_000).with_seed(11);
        let cloud = points(&chaos_game(&a, &model, &settings).unwrap());
        for &eps in epsilons {
            let out = points(&eval(name, &[], EvalSettings::default().with_tolerance(eps)));
            let to_output = crate::hausdorff::directed_hausdorff(&cloud, &out);
            assert!(to_output <= eps, "{name}, ε = {eps}: a chaos-game point is {to_output} from the output");
            let to_cloud = crate::hausdorff::directed_hausdorff(&out, &cloud);
            assert!(to_cloud <= 1.5 * eps, "{name}, ε = {eps}: an output point is {to_cloud} from the chaos game");
        }
        let fixed = points(&eval(name, &[], EvalSettings::default()));
        let h = crate::hausdorff::directed_hausdorff(&cloud, &fixed);
        assert!(h > 0.2, "{name}: the fixed depth was expected to be coarse: {h}");
    }
}

/// A tolerance whose output cannot fit is refused at once, with the
/// estimate (2^40 leaves for the Lévy curve at 10⁻⁹), instead of filling
/// memory first.
#[test]
fn hopeless_tolerances_are_refused_at_once() {
    let (a, model, _) = load("levy", &[]);
    let ev = Evaluator::new(&a, &model, EvalSettings::default().with_tolerance(1e-9)).unwrap();
    match ev.evaluate() {
        Err(EvalError::TooLarge { estimate, .. }) => assert!(estimate > 1 << 40, "{estimate}"),
        other => panic!("expected TooLarge, got {:?}", other.map(|s| s.vertex_count())),
    }
}

/// The half-tangents of `analysis::curve_query` are the directions of the
/// rendered curve at its ends: the first chord of a deep evaluation leaves
/// the start along `P · start`, the last one arrives at the end along
/// `P · end` (depth 14: the next eigenvalue's share is below 2⁻¹⁴ relative).
#[test]
fn half_tangents_agree_with_the_rendered_curve() {
    use bcifs::analysis::curve_query;
    for (a, b) in [(0.3, 0.1), (0.4, 0.4), (0.1, 0.3), (0.45, 0.35)] {
        let (automaton, model, _) = load("corner_cutting", &[("a", a), ("b", b)]);
        let root = automaton.state_id(model.root(0)).unwrap();
        let arrows = automaton.outgoing(root, bcifs::ArrowKind::Subdivision);
        let (t0, t1) = (&automaton.arrow(arrows[0]).matrix, &automaton.arrow(arrows[1]).matrix);
        let report = curve_query(t0, t1);
        let [start, end] = report.half_tangents.clone().unwrap_or_else(|| panic!("a = {a}, b = {b}: {report:?}"));
        let k = 14;
        let shape = eval("corner_cutting", &[("a", a), ("b", b)], EvalSettings::default().with_depth(k));
        let per = 1usize << k;
        let p = |i: usize| shape.point(i);
        let control = |j: usize| &model.points[j];
        let along = |v: &[f64]| [0, 1].map(|c| (0..3).map(|j| v[j] * control(j)[c]).sum::<f64>());
        let angle = |u: [f64; 2], w: [f64; 2]| {
            let cos = (u[0] * w[0] + u[1] * w[1]) / ((u[0].hypot(u[1])) * (w[0].hypot(w[1])));
            cos.clamp(-1.0, 1.0).acos().to_degrees()
        };
        // Piece 0 runs over samples 0 .. per; its end is the start of piece 1.
        let first = [p(1)[0] - p(0)[0], p(1)[1] - p(0)[1]];
        let last = [p(per)[0] - p(per - 1)[0], p(per)[1] - p(per - 1)[1]];
        assert!(angle(first, along(&start)) < 0.1, "a = {a}, b = {b}: start {}", angle(first, along(&start)));
        assert!(angle(last, along(&end)) < 0.1, "a = {a}, b = {b}: end {}", angle(last, along(&end)));
    }
}

/// The exact query of the corner cutting at rational points: T0 has the
/// eigenvalues (1, a, 1 − a − b) and T1 (1, b, 1 − a − b) exactly (Sokolov et al. 2010
/// §4.1), and away from ties the region is the floating-point query's.
#[test]
fn exact_query_reproduces_the_closed_forms() {
    use bcifs::algebra::{Num, Surd};
    use bcifs::analysis::{curve_query, curve_query_exact};
    let family = bcifs::solve(&bcifs::builtin_design("corner_cutting").unwrap()).unwrap();
    let names = family.parameter_names();
    let mut agreed = 0;
    for (i, j) in [(1, 3), (5, 7), (-3, 11), (13, 4), (2, 9), (-7, 5), (17, 3), (1, 1), (8, 8), (11, -2)] {
        for (p, q) in [(20, 23), (17, 19)] {
            let (a, b) = (Num::frac(i, p), Num::frac(j, q));
            let x: Vec<Num> = names.iter().map(|n| if n == "a" { a.clone() } else { b.clone() }).collect();
            let (t0, t1) = (family.exact_matrix("T0", &x).unwrap(), family.exact_matrix("T1", &x).unwrap());
            let Some(exact) = curve_query_exact(&t0, &t1) else { continue };
            let rest = Num::one().sub(&a).sub(&b);
            let sorted = |v: [&Num; 3]| {
                let mut v: Vec<Surd> = v.iter().map(|n| Surd::rational(n.as_rational().unwrap().clone())).collect();
                v.sort_by(|x, y| y.to_f64().total_cmp(&x.to_f64()));
                v
            };
            assert_eq!(exact.eigenvalues[0], sorted([&Num::one(), &a, &rest]), "a = {a:?}, b = {b:?}");
            assert_eq!(exact.eigenvalues[1], sorted([&Num::one(), &b, &rest]), "a = {a:?}, b = {b:?}");
            let to_f64 = |m: &Vec<Vec<num_rational::BigRational>>| {
                nalgebra::DMatrix::from_fn(3, 3, |r, c| num_traits::ToPrimitive::to_f64(&m[r][c]).unwrap())
            };
            let float = curve_query(&to_f64(&t0), &to_f64(&t1));
            assert_eq!(float.region, exact.region, "a = {a:?}, b = {b:?}");
            agreed += 1;
        }
    }
    assert!(agreed >= 15, "{agreed} points compared");
}

/// Where floating point cannot tell: 1 − a − b one part in 10¹³ above
/// a = 1/10 is a strict order, not a tie. The exact query finds the
/// half-tangent and a region; the floating-point one sees a tie (its
/// tolerance) and gives none. An exact tie (a = 1 − a − b) gives none in both.
#[test]
fn exact_query_separates_what_rounding_merges() {
    use bcifs::algebra::Num;
    use bcifs::analysis::{curve_query, curve_query_exact};
    let family = bcifs::solve(&bcifs::builtin_design("corner_cutting").unwrap()).unwrap();
    let names = family.parameter_names();
    let at = |a: Num, b: Num| {
        let x: Vec<Num> = names.iter().map(|n| if n == "a" { a.clone() } else { b.clone() }).collect();
        let (t0, t1) = (family.exact_matrix("T0", &x).unwrap(), family.exact_matrix("T1", &x).unwrap());
        let f = |m: &Vec<Vec<num_rational::BigRational>>| {
            nalgebra::DMatrix::from_fn(3, 3, |r, c| num_traits::ToPrimitive::to_f64(&m[r][c]).unwrap())
        };
        (curve_query_exact(&t0, &t1).unwrap(), curve_query(&f(&t0), &f(&t1)))
    };
    let near = "0.7999999999999".parse::<Num>().unwrap();
    let (exact, float) = at(Num::frac(1, 10), near);
    assert!(exact.region.is_some() && exact.half_tangents.is_some(), "{exact:?}");
    assert_eq!(float.region, None, "{float:?}");
    let (exact, _) = at(Num::frac(1, 4), Num::frac(1, 2));
    assert_eq!(exact.region, None, "a tie in modulus: {exact:?}");
}

/// Issue 46 §9: `analyze curve` says its half-tangents as directions in
/// modelling space (the barycentric weights applied to the model's control
/// points, written out here) and what its region means; the JSON has the same
/// words (`directions`, `region_meaning`).
#[test]
fn curve_analysis_speaks_in_model_directions_and_named_regions() {
    let design = bcifs::render::load("corner_cutting").unwrap();
    let values =
        [("a".to_string(), bcifs::render::Num::from_f64(0.4)), ("b".to_string(), bcifs::render::Num::from_f64(0.4))];
    let analysis = bcifs::render::curve_analysis(&design, &values).unwrap();
    let json = analysis.to_json();
    let points = &design.model().unwrap().points;
    for (k, key) in ["start", "end"].into_iter().enumerate() {
        let weights = analysis.report.half_tangents.as_ref().unwrap()[k].clone();
        let mut d = [0.0; 2];
        for (w, p) in weights.iter().zip(points) {
            d[0] += w * p[0];
            d[1] += w * p[1];
        }
        let len = (d[0] * d[0] + d[1] * d[1]).sqrt();
        let got: Vec<f64> = json["directions"][key].as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect();
        assert!((got[0] - d[0] / len).abs() < 1e-12 && (got[1] - d[1] / len).abs() < 1e-12, "{key}: {got:?}");
    }
    assert_eq!(json["region"], "4");
    assert!(json["region_meaning"].as_str().unwrap().contains("a corner"), "{}", json["region_meaning"]);
    let text = std::process::Command::new(env!("CARGO_BIN_EXE_bcifs"))
        .args(["analyze", "curve", "corner_cutting", "--param", "a=0.4", "--param", "b=0.4"])
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&text.stdout).to_string();
    assert!(
        text.contains("half-tangents in the model (unit directions)")
            && text.contains("region 4 of Sokolov et al. 2010 Fig. 8: "),
        "{text}"
    );
    assert_eq!(bcifs::render::region_meaning("2'"), bcifs::render::region_meaning("2"));
}
