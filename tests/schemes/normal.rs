//! The normal-vector p-ary scheme of Li et al. 2013: direct and automaton forms
//! agree, the automata pass `check`, and the paper's properties hold.

use crate::hausdorff::hausdorff;
use bcifs::algebra::Surd;
use bcifs::analysis::{DEFAULT_CHECK_TOLERANCE, check};
use bcifs::schemes::{
    NormalDirection, NormalPreset, NormalScheme, NormalSchemeError, PRESET_NAMES, SignPattern, normal_preset,
    unit_segment, unit_triangle,
};

use super::{evaluate, length, lift, points2};

/// Every preset that has an automaton form, with its automaton.
fn interpolatory_presets() -> Vec<(&'static str, NormalPreset, bcifs::Design)> {
    PRESET_NAMES
        .iter()
        .map(|name| normal_preset(name).unwrap())
        .filter(|p| p.scheme.is_interpolatory())
        .map(|p| {
            let design = p.scheme.design(p.name, &p.polygon, p.closed).unwrap();
            (p.name, p, design)
        })
        .collect()
}

/// For every interpolatory preset (and every sign pattern on other polygons),
/// the automaton's output at depth k is the polygon of eq. (1) after k steps,
/// point for point, within 1e-12 (both are products of k exact-in-spirit
/// matrices with entries ≤ 2 in modulus on unit-sized polygons: ~1e-15).
#[test]
fn automaton_form_equals_direct_form() {
    for (name, preset, design) in interpolatory_presets() {
        let max_depth = preset.depth.min(if preset.scheme.arity() > 4 { 3 } else { 5 });
        for k in 0..=max_depth {
            let direct = preset.scheme.polygon(&preset.polygon, preset.closed, k);
            let auto = points2(&evaluate(&design, k));
            assert_eq!(auto.len(), direct.len(), "{name} depth {k}");
            for (i, (a, b)) in auto.iter().zip(&direct).enumerate() {
                let gap = (a[0] - b[0]).abs().max((a[1] - b[1]).abs());
                assert!(gap < 1e-12, "{name} depth {k} point {i}: {a:?} vs {b:?}");
            }
        }
    }
}

#[test]
fn every_sign_pattern_and_direction_agrees_on_open_and_closed_polygons() {
    let pentagon: Vec<[f64; 2]> = (0..5)
        .map(|i| {
            let t = std::f64::consts::TAU * i as f64 / 5.0;
            [t.cos(), 0.7 * t.sin()]
        })
        .collect();
    for p in [2, 3, 4] {
        let alpha: Vec<String> = (0..p).map(|j| format!("{j}/{p}")).collect();
        let beta: Vec<String> = (0..p).map(|j| if j == 0 { "0".into() } else { format!("1/{}", 3 + j) }).collect();
        let a: Vec<&str> = alpha.iter().map(String::as_str).collect();
        let b: Vec<&str> = beta.iter().map(String::as_str).collect();
        for sign in SignPattern::ALL {
            for normal in [NormalDirection::Positive, NormalDirection::Negative] {
                for closed in [false, true] {
                    let scheme = NormalScheme::parse(&a, &b).unwrap().with_sign(sign).with_normal(normal);
                    let design = scheme.design("t", &pentagon, closed).unwrap();
                    for k in 0..4 {
                        let direct = scheme.polygon(&pentagon, closed, k);
                        let auto = points2(&evaluate(&design, k));
                        assert_eq!(auto.len(), direct.len());
                        let gap = auto
                            .iter()
                            .zip(&direct)
                            .map(|(x, y)| (x[0] - y[0]).abs().max((x[1] - y[1]).abs()))
                            .fold(0.0, f64::max);
                        assert!(gap < 1e-12, "p={p} {sign:?} {normal:?} closed={closed} k={k}: {gap}");
                    }
                }
            }
        }
    }
}

/// `bcifs check` on every generated automaton: every constraint holds, columns
/// sum to 1, every subdivision map is contractive; and the system is
/// consistent with no free parameter (all matrices are known).
#[test]
fn generated_automata_pass_check_and_solve() {
    for (name, _, design) in interpolatory_presets() {
        let v = design.automaton().state_id("v").expect("vertex state");
        assert_eq!(design.automaton().state(v).dim, 1, "{name}: vertices of dimension 1");
        let inst = bcifs::instantiate(&design, &[]).unwrap();
        let report = check(&inst.automaton, &inst.values, DEFAULT_CHECK_TOLERANCE).unwrap();
        assert!(report.ok, "{name}: {:?}", report.constraints);
        assert!(report.contractive, "{name}");
        assert!(report.max_column_sum_error < 1e-15, "{name}");
        let family = bcifs::solve(&design).unwrap();
        assert_eq!(family.dof(), 0, "{name}");
    }
}

/// The paper's sign patterns are two-state automata (and a constant sign one state).
#[test]
fn sign_patterns_become_two_state_automata() {
    let states = |name: &str| {
        let p = normal_preset(name).unwrap();
        let d = p.scheme.design(name, &p.polygon, p.closed).unwrap();
        d.automaton().states().filter(|(_, s)| s.kind == bcifs::CellKind::Edge).count()
    };
    assert_eq!(states("koch"), 1);
    assert_eq!(states("dragon"), 2); // (−1)^i
    assert_eq!(states("sierpinski"), 2); // (−1)^(k+i), p = 3
    assert_eq!(states("human"), 2); // (−1)^(k+1)
}

/// The generated Koch and Lévy automata have the matrices of the shipped,
/// hand-written files (Li et al. 2013 eqs. 2 and 5).
#[test]
fn generated_matrices_equal_the_hand_written_files() {
    for name in ["koch", "levy"] {
        let p = normal_preset(name).unwrap();
        let generated = bcifs::instantiate(&p.scheme.design(name, &p.polygon, p.closed).unwrap(), &[]).unwrap();
        let shipped = bcifs::instantiate(&bcifs::builtin_design(name).unwrap(), &[]).unwrap();
        for (_, arrow) in shipped.automaton.arrows() {
            let g = generated.automaton.arrow(generated.automaton.arrow_id(&arrow.name).expect(&arrow.name));
            assert!((&g.matrix - &arrow.matrix).amax() < 1e-15, "{name} {}", arrow.name);
        }
    }
}

/// Theorem 2: the Koch polygon between two fixed points has length (4/3)^k
/// times the initial length (each edge becomes four edges of a third).
#[test]
fn koch_length_grows_by_four_thirds() {
    let koch = normal_preset("koch").unwrap();
    let design = koch.scheme.design("koch", &koch.polygon, false).unwrap();
    for k in 0..=6 {
        let direct = koch.scheme.polygon(&koch.polygon, false, k);
        let expected = (4.0f64 / 3.0).powi(k as i32);
        assert!(approx::abs_diff_eq!(length(&direct, false), expected, epsilon = 1e-12 * expected), "k={k}");
        let auto = points2(&evaluate(&design, k));
        assert!(approx::abs_diff_eq!(length(&auto, false), expected, epsilon = 1e-12 * expected), "k={k}");
    }
    // On a closed polygon too: the snowflake's perimeter is 3 (4/3)^k.
    let flake = normal_preset("snowflake").unwrap();
    for k in 0..=5 {
        let pts = flake.scheme.polygon(&flake.polygon, true, k);
        approx::assert_abs_diff_eq!(length(&pts, true), 3.0 * (4.0f64 / 3.0).powi(k as i32), epsilon = 1e-11);
    }
}

/// Theorem 1: ‖F^(k+1) − F^(k)‖∞ ≤ (√3/6) ((√3+1)/6)^k max|P⁰_{i+1} − P⁰_i|,
/// where F^(k) is the piecewise linear interpolant with F^(k)(4^-k i) = P^k_i.
/// The difference of two piecewise linear functions on the finer grid is
/// largest at a fine node, so it is measured there. The proof's first
/// equality gives the exact value (√3/6) max|P^k_{i+1} − P^k_i| = (√3/6) 3^-k.
#[test]
fn koch_convergence_bound_of_theorem_1() {
    let koch = normal_preset("koch").unwrap();
    let start = vec![[0.0, 0.0], [1.0, 0.0], [1.5, 0.8], [2.7, 0.4]];
    let max0 = start.windows(2).map(|w| length(w, false)).fold(0.0, f64::max);
    let s3 = 3f64.sqrt();
    for k in 0..7 {
        let coarse = koch.scheme.polygon(&start, false, k);
        let fine = koch.scheme.polygon(&start, false, k + 1);
        let mut dist: f64 = 0.0;
        for (i, p) in fine.iter().enumerate() {
            // Fine node i sits at 1/4 of the way i % 4 along coarse segment i / 4.
            let (seg, t) = (i / 4, (i % 4) as f64 / 4.0);
            let q = if seg + 1 < coarse.len() {
                let (a, b) = (coarse[seg], coarse[seg + 1]);
                [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]
            } else {
                coarse[seg]
            };
            dist = dist.max(((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)).sqrt());
        }
        let bound = s3 / 6.0 * ((s3 + 1.0) / 6.0).powi(k as i32) * max0;
        assert!(dist <= bound * (1.0 + 1e-12), "k={k}: {dist} > {bound}");
        let max_k = coarse.windows(2).map(|w| length(w, false)).fold(0.0, f64::max);
        assert!(approx::abs_diff_eq!(dist, s3 / 6.0 * max_k, epsilon = 1e-12), "k={k}");
        approx::assert_abs_diff_eq!(max_k, max0 / 3f64.powi(k as i32), epsilon = 1e-12);
    }
}

fn segments_cross(a: [f64; 2], b: [f64; 2], c: [f64; 2], d: [f64; 2]) -> bool {
    let orient = |p: [f64; 2], q: [f64; 2], r: [f64; 2]| (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]);
    let (o1, o2, o3, o4) = (orient(a, b, c), orient(a, b, d), orient(c, d, a), orient(c, d, b));
    o1 * o2 < -1e-18 && o3 * o4 < -1e-18
}

/// The snowflake (Fig. 7b) is a closed curve: the automaton output is one
/// closed polyline whose last point leads back to the first, and it does not
/// cross itself.
#[test]
fn snowflake_is_a_closed_simple_curve() {
    let flake = normal_preset("snowflake").unwrap();
    let design = flake.scheme.design("snowflake", &flake.polygon, true).unwrap();
    let shape = evaluate(&design, 3);
    let lines: Vec<_> = shape.polylines().collect();
    assert_eq!(lines, vec![(0, 3 * 64, true)]);
    let pts = points2(&shape);
    let n = pts.len();
    for i in 0..n {
        for j in i + 2..n {
            if i == 0 && j == n - 1 {
                continue;
            }
            assert!(!segments_cross(pts[i], pts[(i + 1) % n], pts[j], pts[(j + 1) % n]), "edges {i} and {j} cross");
        }
    }
    // Outward bumps: every point lies outside or on the initial triangle's incircle,
    // and the curve reaches the circumcircle of the hexagram (radius 1/√3 around the centre).
    let centre = [0.5, 3f64.sqrt() / 6.0];
    let r = |p: &[f64; 2]| ((p[0] - centre[0]).powi(2) + (p[1] - centre[1]).powi(2)).sqrt();
    let rmax = pts.iter().map(r).fold(0.0, f64::max);
    assert!(approx::abs_diff_eq!(rmax, 1.0 / 3f64.sqrt(), epsilon = 1e-12), "{rmax}");
}

/// Scheme (3) on a segment converges to the Sierpinski gasket of the triangle
/// it spans, (0,0), (1,0), (1/2, √3/2): the Hausdorff distance to the gasket
/// (the classic three-map IFS, depth 8) shrinks with depth, roughly halving.
#[test]
fn scheme_3_converges_to_the_sierpinski_gasket() {
    let tri = unit_triangle();
    let mut gasket: Vec<[f64; 2]> = tri.clone();
    for _ in 0..8 {
        gasket =
            tri.iter().flat_map(|c| gasket.iter().map(move |p| [(p[0] + c[0]) / 2.0, (p[1] + c[1]) / 2.0])).collect();
    }
    let preset = normal_preset("sierpinski").unwrap();
    let mut last = f64::INFINITY;
    for k in 1..=7 {
        let curve = preset.scheme.polygon(&unit_segment(), false, k);
        let h = hausdorff(&lift(&curve), &lift(&gasket));
        assert!(h < 0.75 * last, "k={k}: {h} vs {last}");
        last = h;
    }
    assert!(last < 0.01, "{last}");
}

#[test]
fn non_interpolatory_schemes_have_no_automaton_form() {
    let p = normal_preset("approximating").unwrap();
    let err = p.scheme.design("a", &p.polygon, true).unwrap_err();
    assert!(matches!(err, NormalSchemeError::NotInterpolatory { .. }));
    assert!(err.to_string().contains("α_0 = -1/2"), "{err}");
    // The direct form still works and keeps p points per segment of the closed polygon.
    assert_eq!(p.scheme.polygon(&p.polygon, true, 3).len(), 4 * 64);
}

#[test]
fn bad_parameters_are_reported() {
    assert!(matches!(NormalScheme::parse(&["0"], &["0"]), Err(NormalSchemeError::Arity { .. })));
    assert!(matches!(NormalScheme::parse(&["0", "1/2"], &["0"]), Err(NormalSchemeError::Arity { .. })));
    assert!(NormalScheme::parse(&["0", "x"], &["0", "1"]).is_err());
    let err = normal_preset("kosh").unwrap_err();
    assert!(err.to_string().contains("did you mean `koch`"), "{err}");
    let exact = Surd::parse("sqrt(3)/6").unwrap();
    assert_eq!(normal_preset("koch").unwrap().scheme.beta[2], exact);
}

/// The first step of each preset on the unit segment gives the points the
/// paper's parameters define: P_j = (α_j, ±β_j) for the unit segment (0,0)–(1,0).
#[test]
fn first_steps_are_the_papers_points() {
    let s3 = 3f64.sqrt();
    let cases: [(&str, Vec<[f64; 2]>); 6] = [
        ("levy", vec![[0.0, 0.0], [0.5, 0.5], [1.0, 0.0]]),
        // (−1)^(k+i) at k = i = 0 is +1.
        ("sierpinski", vec![[0.0, 0.0], [0.25, s3 / 4.0], [0.75, s3 / 4.0], [1.0, 0.0]]),
        ("tigerhead", vec![[0.0, 0.0], [-0.25, 1.0 / 3.0], [0.5, 0.5], [1.25, 1.0 / 3.0], [1.0, 0.0]]),
        // (−1)^(k+1) at k = 0 is −1: the first bumps point down.
        ("human", vec![[0.0, 0.0], [5.0 / 9.0, -1.0 / 3.0], [0.5, -0.5], [4.0 / 9.0, -1.0 / 3.0], [1.0, 0.0]]),
        (
            "crown",
            vec![
                [0.0, 0.0],
                [1.0 / 3.0, -s3 / 9.0],
                [1.0 / 3.0, s3 / 9.0],
                [0.5, -s3 / 18.0],
                [2.0 / 3.0, s3 / 9.0],
                [2.0 / 3.0, -s3 / 9.0],
                [1.0, 0.0],
            ],
        ),
        (
            "minkowski",
            vec![
                [0.0, 0.0],
                [0.25, 0.0],
                [0.25, 0.25],
                [0.5, 0.25],
                [0.5, -0.25],
                [0.75, -0.25],
                [0.75, 0.0],
                [1.0, 0.0],
            ],
        ),
    ];
    for (name, expected) in cases {
        let p = normal_preset(name).unwrap();
        let got = p.scheme.polygon(&unit_segment(), false, 1);
        assert_eq!(got.len(), expected.len(), "{name}");
        for (g, e) in got.iter().zip(&expected) {
            assert!(approx::abs_diff_eq!(g[..], e[..], epsilon = 1e-15), "{name}: {g:?} vs {e:?}");
        }
    }
    // The second step of the human-like curve flips the sign: (−1)^(k+1) = +1 at k = 1.
    let human = normal_preset("human").unwrap();
    let two = human.scheme.polygon(&unit_segment(), false, 2);
    let one = human.scheme.polygon(&unit_segment(), false, 1);
    let (a, b) = (one[0], one[1]);
    let d = [-(b[1] - a[1]), b[0] - a[0]];
    let expected = [a[0] + 5.0 / 9.0 * (b[0] - a[0]) + d[0] / 3.0, a[1] + 5.0 / 9.0 * (b[1] - a[1]) + d[1] / 3.0];
    approx::assert_abs_diff_eq!(two[1][..], expected[..], epsilon = 1e-15);
}
