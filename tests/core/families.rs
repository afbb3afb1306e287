//! The admissible families of the shipped automata, against the seeds.

use bcifs::analysis::check;
use bcifs::{Family, builtin_design, solve};
use nalgebra::DMatrix;

fn family(name: &str) -> Family {
    solve(&builtin_design(name).expect("shipped automaton")).expect("consistent")
}

fn texts(f: &Family, arrow: &str) -> Vec<Vec<String>> {
    f.matrices_text().into_iter().find(|(n, _)| n == arrow).expect("arrow").1
}

fn rows(r: &[&[&str]]) -> Vec<Vec<String>> {
    r.iter().map(|row| row.iter().map(|s| s.to_string()).collect()).collect()
}

/// Sokolov et al. 2010 §3.1: the corner-cutting family, exactly as printed.
#[test]
fn corner_cutting_family_is_the_papers() {
    let f = family("corner_cutting");
    assert_eq!(f.parameter_names(), ["a", "b"]);
    assert_eq!(texts(&f, "T0"), rows(&[&["1 - a", "b", "0"], &["a", "1 - b", "1 - a"], &["0", "0", "a"]]));
    assert_eq!(texts(&f, "T1"), rows(&[&["b", "0", "0"], &["1 - b", "1 - a", "b"], &["0", "a", "1 - b"]]));
    assert_eq!(texts(&f, "Tv"), rows(&[&["1 - a", "b"], &["a", "1 - b"]]));
}

fn sorted_real_spectrum(m: &DMatrix<f64>) -> Vec<f64> {
    let eig = m.complex_eigenvalues();
    assert!(eig.iter().all(|l| l.im.abs() < 1e-12), "real spectrum expected: {eig}");
    let mut v: Vec<f64> = eig.iter().map(|l| l.re).collect();
    v.sort_by(f64::total_cmp);
    v
}

/// Sokolov et al. 2010 §3.1: T0 has eigenvalues (1, a, 1-a-b), T1 has (1, b, 1-a-b).
#[test]
fn corner_cutting_eigenvalues() {
    let f = family("corner_cutting");
    for (a, b) in [(0.25, 0.25), (0.1, 0.3), (0.6, 0.2), (-0.3, 0.45), (0.9, 0.8)] {
        let inst = f.instantiate(&[("a".into(), a), ("b".into(), b)]).unwrap();
        let m = |n: &str| inst.automaton.arrow(inst.automaton.arrow_id(n).unwrap()).matrix.clone();
        for (arrow, expected) in [("T0", [1.0, a, 1.0 - a - b]), ("T1", [1.0, b, 1.0 - a - b])] {
            let mut e = expected.to_vec();
            e.sort_by(f64::total_cmp);
            let got = sorted_real_spectrum(&m(arrow));
            for (g, x) in got.iter().zip(&e) {
                // Eigenvalues of a 3×3 matrix with entries O(1): backward-stable to ~1e-15;
                // a double eigenvalue (a = 1-a-b) loses half the digits, hence 1e-7.
                assert!(approx::abs_diff_eq!(g, x, epsilon = 1e-7), "{arrow} at a={a}, b={b}: {got:?} vs {e:?}");
            }
        }
        let report = check(&inst.automaton, &inst.values, 1e-9).unwrap();
        assert!(report.ok);
        let inside = a.abs() < 1.0 && b.abs() < 1.0 && (1.0 - a - b).abs() < 1.0;
        assert_eq!(report.contractive, inside, "convergence domain of §3 at a={a}, b={b}");
    }
}

/// The Chaikin matrices (corner cutting at a = b = 1/4).
fn chaikin() -> [DMatrix<f64>; 2] {
    [
        DMatrix::from_row_slice(3, 3, &[0.75, 0.25, 0.0, 0.25, 0.75, 0.75, 0.0, 0.0, 0.25]),
        DMatrix::from_row_slice(3, 3, &[0.25, 0.0, 0.0, 0.75, 0.75, 0.25, 0.0, 0.25, 0.75]),
    ]
}

/// DESIGN §2 and Sokolov et al. 2010 §7: 3 degrees of freedom; (9/16, 3/16, 3/16) is the
/// regular Doo-Sabin rule, i.e. every sub-face is the Kronecker product of
/// Chaikin matrices (biquadratic B-spline).
#[test]
fn doo_sabin_patch_has_three_parameters_and_the_classic_weights() {
    let f = family("doo_sabin_quad");
    assert_eq!(f.parameter_names(), ["alpha", "beta", "gamma"]);
    assert_eq!(f.entry_text("W", 3, 0), "1 - alpha - beta - gamma");
    let inst = f
        .instantiate(&[("alpha".into(), 9.0 / 16.0), ("beta".into(), 3.0 / 16.0), ("gamma".into(), 3.0 / 16.0)])
        .unwrap();
    let c = chaikin();
    for (name, u, v) in [("T00", 0, 0), ("T10", 1, 0), ("T01", 0, 1), ("T11", 1, 1)] {
        let t = &inst.automaton.arrow(inst.automaton.arrow_id(name).unwrap()).matrix;
        // Index 3*row + col with row = v, col = u: T_uv = C_v ⊗ C_u. Dyadic values: exact.
        assert_eq!(t, &c[v].kronecker(&c[u]), "{name}");
    }
}

/// The general quad patch: the vertex rule is free (4×4 stochastic, 12 dof).
#[test]
fn general_quad_patch_has_twelve_parameters() {
    let d = bcifs::schemes::quad_patch(false).unwrap();
    assert_eq!(solve(&d).unwrap().dof(), 12);
    let printed = bcifs::parse_design(&bcifs::write_design(&d), "quad.toml", "quad").unwrap();
    assert_eq!(solve(&printed).unwrap().matrices_text(), solve(&d).unwrap().matrices_text());
}

/// The cubic curve with vertex support 3: 3 free parameters, and the cubic
/// B-spline (its defaults) belongs to the family.
#[test]
fn cubic_curve_family_contains_the_cubic_bspline() {
    let f = family("curve_4_3");
    assert_eq!(f.dof(), 3);
    let inst = f.instantiate(&[]).unwrap();
    let b = bcifs::schemes::bspline_segment_matrices(3, 2);
    let t0 = &inst.automaton.arrow(inst.automaton.arrow_id("T0").unwrap()).matrix;
    let t1 = &inst.automaton.arrow(inst.automaton.arrow_id("T1").unwrap()).matrix;
    let expected_t0 = DMatrix::from_row_slice(
        4,
        4,
        &[0.5, 0.125, 0.0, 0.0, 0.5, 0.75, 0.5, 0.125, 0.0, 0.125, 0.5, 0.75, 0.0, 0.0, 0.0, 0.125],
    );
    assert!((t0 - &expected_t0).amax() < 1e-12, "{t0}");
    assert!((t0 - &b[0]).amax() < 1e-12 && (t1 - &b[1]).amax() < 1e-12);
}

/// Li et al. 2013 eq. (5) on the rotated frame: fully known, dof 0, passes check,
/// and each sub-segment is a similarity of ratio 1/3 (|λ| = 1/3).
#[test]
fn koch_scheme_passes_check() {
    let d = builtin_design("koch").unwrap();
    let f = solve(&d).unwrap();
    assert_eq!(f.dof(), 0);
    let inst = f.instantiate(&[]).unwrap();
    let report = check(&inst.automaton, &inst.values, 1e-12).unwrap();
    assert!(report.ok && report.contractive);
    for (name, eig) in &report.spectra {
        if name.starts_with('T') && name != "Tv" {
            let mut m: Vec<f64> = eig.iter().map(|l| l.norm()).collect();
            m.sort_by(f64::total_cmp);
            assert!(approx::abs_diff_eq!(m[..2], [1.0 / 3.0; 2][..], epsilon = 1e-12), "{name}: {m:?}");
        }
    }
}

/// `bcifs new curve --points 3 --vertex 2 --arity 2` is the hand-written
/// corner-cutting file, and `bcifs new quad-patch --symmetric` the Doo-Sabin
/// file: same states, arrows, matrices, constraints and family; so are
/// their printed files read back.
#[test]
fn generators_equal_the_hand_written_files() {
    let corner = bcifs::schemes::curve(3, 2, 2).unwrap();
    let quad = bcifs::schemes::quad_patch(true).unwrap();
    let reread = |d: &bcifs::Design| bcifs::parse_design(&bcifs::write_design(d), "generated.toml", d.name()).unwrap();
    let pairs = [
        (reread(&corner), "corner_cutting", vec![("a", 0.2), ("b", 0.35)]),
        (corner, "corner_cutting", vec![("a", 0.2), ("b", 0.35)]),
        (reread(&quad), "doo_sabin_quad", vec![("alpha", 0.5), ("beta", 0.2), ("gamma", 0.1)]),
        (quad, "doo_sabin_quad", vec![("alpha", 0.5), ("beta", 0.2), ("gamma", 0.1)]),
    ];
    for (generated, name, values) in pairs {
        let shipped = builtin_design(name).unwrap();
        let (g, s) = (generated.automaton(), shipped.automaton());
        let states =
            |a: &bcifs::Automaton<bcifs::algebra::Affine>| a.states().map(|(_, s)| s.clone()).collect::<Vec<_>>();
        assert_eq!(states(g), states(s), "{name}: states");
        let arrows = |a: &bcifs::Automaton<bcifs::algebra::Affine>| {
            let mut v: Vec<_> = a
                .arrows()
                .map(|(id, x)| {
                    let (from, to) = a.arrow_ends(id);
                    (x.name.clone(), x.kind, a.state(from).name.clone(), a.state(to).name.clone())
                })
                .collect();
            v.sort_by(|x, y| x.0.cmp(&y.0));
            v
        };
        assert_eq!(arrows(g), arrows(s), "{name}: arrows");
        let constraints = |a: &bcifs::Automaton<bcifs::algebra::Affine>| {
            let mut v: Vec<String> = a.constraints().iter().map(ToString::to_string).collect();
            v.sort();
            v
        };
        assert_eq!(constraints(g), constraints(s), "{name}: constraints");
        // Same family: instantiated at the same values (the parameters name the
        // same quantities), every matrix agrees.
        let (fg, fs) = (solve(&generated).unwrap(), solve(&shipped).unwrap());
        assert_eq!(fg.dof(), fs.dof());
        let values: Vec<(String, f64)> = values.iter().map(|(n, v)| (n.to_string(), *v)).collect();
        let is = fs.instantiate(&values).unwrap();
        // Each generated parameter names an entry: read it off the shipped instance.
        let mapped: Vec<(String, f64)> = fg
            .parameters
            .iter()
            .map(|p| match &p.origin {
                bcifs::Origin::Entry { arrow, row, col } => {
                    let a = &is.automaton;
                    (p.name.clone(), a.arrow(a.arrow_id(arrow).unwrap()).matrix[(*row, *col)])
                }
                bcifs::Origin::Parameter => panic!("generated parameters name entries"),
            })
            .collect();
        let ig = fg.instantiate(&mapped).unwrap();
        for (id, arrow) in is.automaton.arrows() {
            let other = &ig.automaton.arrow(ig.automaton.arrow_id(&arrow.name).unwrap()).matrix;
            assert!((other - &arrow.matrix).amax() < 1e-15, "{name}: {} differs ({id:?})", arrow.name);
        }
    }
}

/// `solve`'s layout of the matrices (`Family::matrices_report`, written a
/// matrix at a time) is the entries of `Family::matrices_text` right-aligned
/// to each matrix's longest, for families with parameters, surds and
/// several states, and for a generated mesh automaton.
#[test]
fn the_matrices_report_lays_out_the_matrices_text() {
    let cube =
        bcifs::mesh::read_mesh(std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/cube.off")))
            .unwrap();
    let generated = bcifs::schemes::mesh_automaton(&cube, bcifs::mesh::Scheme::DooSabin, None).unwrap();
    let generated = bcifs::parse_design(&bcifs::write_design(&generated), "cube", "cube").unwrap();
    let sqrt3 = bcifs::schemes::ifs_preset("sqrt3-patch", None, None).unwrap();
    for design in
        [builtin_design("corner_cutting").unwrap(), builtin_design("fern_sierpinski").unwrap(), sqrt3, generated]
    {
        let f = solve(&design).unwrap();
        let mut expected = String::new();
        for (n, rows) in f.matrices_text() {
            let width = rows.iter().flatten().map(String::len).max().unwrap_or(1);
            expected.push_str(&format!("\n{n} =\n"));
            for row in rows {
                let cells: Vec<String> = row.iter().map(|c| format!("{c:>width$}")).collect();
                expected.push_str(&format!("  [ {} ]\n", cells.join("  ")));
            }
        }
        assert_eq!(f.matrices_report(), expected, "{}", design.name());
    }
}
