//! The checked builder: designs built in code equal the shipped files,
//! mistakes are named, printing and reading back is exact, nothing panics.

use bcifs::{BuildError, CellKind, Design, DesignBuilder, Layout, Model, builtin_design, solve};
use bcifs::{Field, Locus};
use proptest::prelude::*;

/// The corner-cutting curve of Sokolov et al. 2010 §3 as code.
fn corner_cutting() -> DesignBuilder {
    let mut b = Design::builder("corner_cutting");
    b.state("e", 3, CellKind::Edge)
        .state("v", 2, CellKind::Vertex)
        .unknown("T0", "e", "e")
        .unknown("T1", "e", "e")
        .unknown("Tv", "v", "v")
        .select("b0", "e", "v", [0, 1])
        .select("b1", "e", "v", [1, 2])
        .adjacency("T0 b1 = T1 b0")
        .incidence("T0 b0 = b0 Tv")
        .incidence("T1 b1 = b1 Tv")
        .name_entry("a", "T0[1][0]")
        .default_value("a", 0.25)
        .name_entry("b", "T0[0][1]")
        .default_value("b", 0.25);
    b
}

fn error(b: &DesignBuilder) -> BuildError {
    b.build().expect_err("the design is wrong")
}

/// Issue 9: a design built in code gives the same family, letters included,
/// as the shipped TOML file.
#[test]
fn code_built_design_equals_the_shipped_file() {
    let code = solve(&corner_cutting().build().unwrap()).unwrap();
    let file = solve(&builtin_design("corner_cutting").unwrap()).unwrap();
    assert_eq!(code.parameter_names(), ["a", "b"]);
    assert_eq!(code.matrices_text(), file.matrices_text());
    assert_eq!(code.instantiate(&[]).unwrap().parameters, vec![("a".to_string(), 0.25), ("b".to_string(), 0.25)]);
}

/// Known matrices may be given as numbers or expressions; an f64 is read as
/// the decimal it prints as, so 0.1 is exactly 1/10.
#[test]
fn known_matrices_and_defaults_are_exact() {
    let mut b = Design::builder("m");
    b.state("x", 2, CellKind::Free)
        .matrix("A", "x", "x", [[0.1, 0.25], [0.9, 0.75]])
        .matrix("B", "x", "x", [["1 - t", "t"], ["t", "1 - t"]])
        .parameter("t")
        .default_value("t", "1/3");
    let d = b.build().unwrap();
    let f = solve(&d).unwrap();
    assert_eq!(f.entry_text("A", 0, 0), "1/10");
    assert_eq!(f.entry_text("B", 0, 0), "1 - t");
    approx::assert_abs_diff_eq!(d.defaults()["t"], 1.0 / 3.0, epsilon = 1e-16);
}

#[test]
fn mistakes_are_named_never_a_panic() {
    let mut b = corner_cutting();
    b.unknown("T2", "e", "ee");
    let e = error(&b);
    assert_eq!(e.to_string(), "arrow `T2`: no state named `ee` (did you mean `e`?)");
    assert_eq!(e.at(), Locus::Arrow { index: 5, field: Field::To });

    let mut b = corner_cutting();
    b.adjacency("T0 b1 = T2 b0");
    let e = error(&b);
    assert_eq!(e.to_string(), "equation `adjacency: T0 b1 = T2 b0`: no arrow named `T2` (did you mean `T0`?)");
    assert_eq!((e.at(), e.offset()), (Locus::Equation { index: 1 }, Some(8)));

    let mut b = corner_cutting();
    b.incidence("T0 = b1");
    assert!(error(&b).to_string().contains("the two sides go e → e and e → v"), "{}", error(&b));

    let mut b = corner_cutting();
    b.select("b2", "e", "v", [0, 0]);
    assert_eq!(error(&b).to_string(), "arrow `b2`: index 0 is selected twice: a selection must be an embedding");

    let mut b = corner_cutting();
    b.select("b2", "e", "v", [0, 3]);
    assert!(error(&b).to_string().contains("index 3 is out of range: `e` has dim 3"), "{}", error(&b));

    let mut b = corner_cutting();
    b.matrix("M", "e", "v", [[1, 0], [0, 1]]);
    assert!(error(&b).to_string().contains("so its matrix must be 3×2 (3 rows of 2), not 2 rows"), "{}", error(&b));

    let mut b = corner_cutting();
    b.matrix("M", "v", "v", [["1 - q", "0"], ["q", "1"]]);
    let e = error(&b);
    assert!(e.to_string().starts_with("arrow `M`: unknown parameter `q` in entry [0][0] of `M`"), "{e}");
    assert_eq!(e.offset(), Some(4));

    let mut b = corner_cutting();
    b.name_entry("c", "b0[0][1]");
    assert_eq!(
        error(&b).to_string(),
        "parameter `c`: b0[0][1] is not an entry of an unknown matrix (did you mean `T0`?)"
    );

    let mut b = corner_cutting();
    b.default_value("z", 1.0);
    assert!(error(&b).to_string().contains("`z` is not a parameter"), "{}", error(&b));

    let mut b = corner_cutting();
    b.state("e", 2, CellKind::Vertex);
    assert_eq!(error(&b).to_string(), "state `e`: a state named `e` is declared twice");

    let mut b = corner_cutting();
    b.state("w", 0, CellKind::Vertex);
    assert_eq!(error(&b).to_string(), "state `w`: a state needs at least one control point (dim ≥ 1)");

    let mut b = corner_cutting();
    b.model(Model::new("e", vec![vec![0.0, 0.0], vec![1.0, 1.0]]).with_layout(Layout::Closed));
    assert_eq!(error(&b).to_string(), "model: this layout needs at least 3 control points, not 2");

    let mut b = corner_cutting();
    b.model(Model::new("ee", vec![vec![0.0, 0.0]; 3]));
    assert_eq!(error(&b).to_string(), "model: no state named `ee` (did you mean `e`?)");

    let mut b = corner_cutting();
    b.model(Model::new("e", vec![vec![0.0, f64::NAN], vec![1.0, 1.0], vec![2.0, 0.0]]));
    assert_eq!(error(&b).to_string(), "model: control points must be finite numbers");

    let mut b = corner_cutting();
    b.model(Model::new("e", vec![vec![0.0, 0.0]; 3]).with_start("v", vec![vec![0.5, 0.6]]));
    assert!(error(&b).to_string().contains("coordinates must sum to 1"), "{}", error(&b));

    assert!(Design::builder("empty").build().unwrap_err().to_string().contains("no state"));
}

/// Every shipped file and every generator, printed and read back: the same
/// family (same letters, same exact entries) and the same model.
#[test]
fn printing_and_reading_back_is_exact() {
    let mut designs: Vec<Design> = bcifs::BUILTIN_AUTOMATA.iter().map(|(n, _)| builtin_design(n).unwrap()).collect();
    designs.push(bcifs::schemes::curve(4, 3, 2).unwrap());
    designs.push(bcifs::schemes::curve(5, 2, 3).unwrap());
    designs.push(bcifs::schemes::quad_patch(false).unwrap());
    for name in bcifs::schemes::PRESET_NAMES {
        if let Ok(d) = bcifs::schemes::normal_preset(name).unwrap().design() {
            designs.push(d);
        }
    }
    for name in bcifs::schemes::IFS_NAMES {
        designs.push(bcifs::schemes::ifs_preset(name, None, None).unwrap());
    }
    assert!(designs.len() > 30);
    for d in &designs {
        let text = bcifs::write_design(d);
        let again = bcifs::parse_design(&text, "printed.toml", d.name())
            .unwrap_or_else(|e| panic!("{}: the printed file does not parse: {e}\n{text}", d.name()));
        assert_eq!(again.name(), d.name());
        assert_eq!(again.description(), d.description());
        assert_eq!(again.model(), d.model(), "{}: model", d.name());
        assert_eq!(again.defaults(), d.defaults(), "{}: defaults", d.name());
        let (f, g) = (solve(d).unwrap(), solve(&again).unwrap());
        assert_eq!(f.matrices_text(), g.matrices_text(), "{}: family", d.name());
        // A second round prints the same text (less the comments, which a
        // file read back does not keep): printing is a fixed point.
        // (A generated preset's constraints carry their explanations as comments inside the arrays.)
        let uncommented =
            |t: &str| t.lines().filter(|l| !l.trim_start().starts_with('#')).collect::<Vec<_>>().join("\n");
        assert_eq!(uncommented(&bcifs::write_design(&again)), uncommented(&text), "{}: second print", d.name());
    }
}

/// Generators keep irrational entries exact (`sqrt(3)/6`), and the solver
/// compares them exactly: a constant equation off by 1e-17 is a conflict.
#[test]
fn irrational_entries_are_exact_through_the_solver() {
    let koch = bcifs::schemes::normal_preset("koch").unwrap().design().unwrap();
    let text = bcifs::write_design(&koch);
    assert!(text.contains("sqrt(3)/6"), "{text}");
    let f = solve(&koch).unwrap();
    assert!(f.matrices_text().iter().flat_map(|(_, r)| r.iter().flatten()).any(|e| e == "sqrt(3)/6"));

    let mut b = Design::builder("s");
    b.state("x", 2, CellKind::Free)
        .matrix("A", "x", "x", [["1/2 - sqrt(3)/6", "0"], ["1/2 + sqrt(3)/6", "1"]])
        .unknown("B", "x", "x")
        .constraint("pins", "B[0][0] = A[0][0]")
        .constraint("pins", "B[0][1] = sqrt(12)/12");
    let f = solve(&b.build().unwrap()).unwrap();
    assert_eq!(f.entry_text("B", 0, 0), "1/2 - sqrt(3)/6");
    assert_eq!(f.entry_text("B", 1, 1), "1 - sqrt(3)/6");

    let mut b = Design::builder("s");
    b.state("x", 1, CellKind::Free)
        .matrix("A", "x", "x", [["sqrt(2)*sqrt(2)/2"]])
        .matrix("C", "x", "x", [["1 + 1e-17"]])
        .constraint("same", "A[0][0] = C[0][0]");
    match solve(&b.build().unwrap()) {
        Err(bcifs::SolveError::Inconsistent { conflicts }) => assert!(conflicts.iter().any(|c| c.contains("same"))),
        other => panic!("exact comparison expected, got {other:?}"),
    }
}

fn name() -> impl Strategy<Value = String> {
    prop_oneof![Just("e".to_string()), Just("v".to_string()), Just("T0".to_string()), "[a-z]{1,2}"]
}

fn entry() -> impl Strategy<Value = String> {
    prop_oneof![
        Just("1".to_string()),
        Just("1 - t".to_string()),
        Just("sqrt(3)/6".to_string()),
        Just("T0[0][0]".to_string()),
        "[-+*/()a-z0-9 .\\[\\]]{0,6}"
    ]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 400, .. ProptestConfig::default() })]

    /// Any sequence of builder calls builds or fails with a message; solving
    /// what builds never panics.
    #[test]
    fn random_designs_never_panic(
        states in prop::collection::vec((name(), 0usize..4), 0..4),
        arrows in prop::collection::vec((name(), name(), name(), 0u8..3, prop::collection::vec(0usize..4, 0..4), prop::collection::vec(entry(), 0..9)), 0..5),
        equations in prop::collection::vec("[a-zT0-9 =\\[\\]]{0,12}", 0..4),
        params in prop::collection::vec((name(), prop::option::of("[a-zT0-9\\[\\]]{0,8}")), 0..3),
    ) {
        let mut b = Design::builder("random");
        for (n, d) in &states {
            b.state(n.clone(), *d, CellKind::Free);
        }
        for (n, from, to, kind, select, entries) in &arrows {
            match kind {
                0 => { b.unknown(n.clone(), from.clone(), to.clone()); }
                1 => { b.select(n.clone(), from.clone(), to.clone(), select.clone()); }
                _ => {
                    let side = (entries.len() as f64).sqrt() as usize;
                    let rows: Vec<Vec<String>> = entries.chunks(side.max(1)).map(<[String]>::to_vec).collect();
                    b.matrix(n.clone(), from.clone(), to.clone(), rows);
                }
            }
        }
        for e in &equations {
            b.constraint("c", e.clone());
        }
        for (n, e) in &params {
            match e {
                Some(e) => b.name_entry(n.clone(), e.clone()),
                None => b.parameter(n.clone()),
            };
        }
        match b.build() {
            Ok(d) => { let _ = solve(&d); }
            Err(e) => prop_assert!(!e.message().is_empty()),
        }
    }
}

/// Parameters keep the order the file declares them in (not alphabetical).
#[test]
fn parameters_keep_the_file_order() {
    let text = include_str!("../../automata/corner_cutting.toml").replace(
        "a = { entry = \"T0[1][0]\", default = 0.25 }\nb = { entry = \"T0[0][1]\", default = 0.25 }",
        "zeta = { entry = \"T0[0][1]\", default = 0.25 }\nalpha = { entry = \"T0[1][0]\", default = 0.25 }",
    );
    let d = bcifs::parse_design(&text, "f.toml", "f").unwrap();
    assert_eq!(d.declared(), ["zeta", "alpha"]);
    assert_eq!(solve(&d).unwrap().parameter_names(), ["zeta", "alpha"]);
}
