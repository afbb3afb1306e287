//! Bad input: positioned errors, conflicting equations, nonlinear
//! constraints; never a panic.

use bcifs::{SolveError, parse_design, solve};
use proptest::prelude::*;

const CORNER: &str = include_str!("../../automata/corner_cutting.toml");

fn error_of(text: &str) -> String {
    parse_design(text, "f.toml", "f").err().map(|e| e.to_string()).unwrap_or_default()
}

/// Position of the first occurrence of `needle` as `line:column` (1-based).
fn pos(text: &str, needle: &str) -> String {
    let at = text.find(needle).expect("needle in text");
    let line = text[..at].matches('\n').count() + 1;
    let col = at - text[..at].rfind('\n').map_or(0, |i| i + 1) + 1;
    format!("{line}:{col}")
}

#[test]
fn misspelt_names_get_positions_and_suggestions() {
    let text = CORNER.replace("adjacency = [\"T0 b1 = T1 b0\"]", "adjacency = [\"T0 b1 = T2 b0\"]");
    let e = error_of(&text);
    let at = pos(&text, "T2 b0");
    assert_eq!(e, format!("f.toml:{at}: no arrow named `T2` (did you mean `T0`?)"));

    let text = CORNER.replacen("to = \"v\"", "to = \"vv\"", 1);
    let e = error_of(&text);
    assert!(e.starts_with(&format!("f.toml:{}:", pos(&text, "\"vv\"").split(':').next().unwrap())), "{e}");
    assert!(e.contains("no state named `vv`") && e.contains("did you mean `v`?"), "{e}");

    let text = CORNER.replacen("kind = \"edge\"", "kind = \"edgy\"", 1);
    let e = error_of(&text);
    assert_eq!(
        e,
        format!(
            "f.toml:{}: unknown cell kind `edgy`: expected vertex, edge, face, volume or free (did you mean `edge`?)",
            pos(&text, "\"edgy\"")
        )
    );
}

#[test]
fn syntax_and_shape_errors_say_what_was_expected() {
    // TOML syntax.
    let e = error_of("[[state]\nname = \"e\"\n");
    assert!(e.starts_with("f.toml:1:"), "{e}");
    // An expression error points into the string.
    let text = "[[state]]\nname = \"x\"\ndim = 2\n[[arrow]]\nname = \"T\"\nfrom = \"x\"\nto = \"x\"\nmatrix = [[\"1 - * a\", 0], [0, 1]]\n";
    let e = error_of(text);
    assert_eq!(e, "f.toml:8:17: in entry [0][0] of `T`: found `*`, expected a number, a name or `(`");
    // Wrong shape.
    let text = "[[state]]\nname = \"x\"\ndim = 2\n[[arrow]]\nname = \"T\"\nfrom = \"x\"\nto = \"x\"\nmatrix = [[1, 0, 0], [0, 1]]\n";
    let e = error_of(text);
    assert!(
        e.starts_with("f.toml:8:10: arrow `T` goes from `x` (dim 2) to `x` (dim 2), so its matrix must be 2×2"),
        "{e}"
    );
    // Unknown field.
    let e = error_of("[[state]]\nname = \"x\"\ndim = 2\nkidn = \"edge\"\n");
    assert!(e.starts_with("f.toml:4:1: unknown field `kidn`"), "{e}");
    // A selection that is not an embedding.
    let text = CORNER.replace("select = [1, 2]", "select = [1, 1]");
    assert!(error_of(&text).contains("index 1 is selected twice"));
    // A parameter naming an entry of a known matrix.
    let text = CORNER.replace("entry = \"T0[0][1]\"", "entry = \"b0[0][1]\"");
    assert!(error_of(&text).contains("b0[0][1] is not an entry of an unknown matrix"), "{}", error_of(&text));
    // Unknown parameter in an expression.
    let text = CORNER.replace("select = [1, 2]", "matrix = [[0, 0], [1, 0], [0, \"1 - q\"]]");
    assert!(error_of(&text).contains("unknown parameter `q`"), "{}", error_of(&text));
}

#[test]
fn inconsistent_systems_name_a_small_conflicting_subset() {
    let text = CORNER.replace(
        "incidence = [\"T0 b0 = b0 Tv\", \"T1 b1 = b1 Tv\"]",
        "incidence = [\"T0 b0 = b0 Tv\", \"T1 b1 = b1 Tv\"]\npins = [\"T0[2][2] = 1/2\", \"T1[2][1] = 1/3\"]",
    );
    let d = parse_design(&text, "f.toml", "f").unwrap();
    match solve(&d) {
        Err(SolveError::Inconsistent { conflicts }) => {
            // T0[2][2] = a = T1[2][1]: the two pins and the path from one to the other.
            assert!(conflicts.iter().any(|c| c.contains("pins: T0[2][2] = 1/2")), "{conflicts:?}");
            assert!(conflicts.iter().any(|c| c.contains("pins: T1[2][1] = 1/3")), "{conflicts:?}");
            assert!(conflicts.len() <= 4, "small subset expected: {conflicts:?}");
        }
        other => panic!("expected a conflict, got {other:?}"),
    }
}

#[test]
fn a_determined_parameter_is_reported() {
    let text = CORNER.replace("[parameters]", "[constraints.extra]\n").replace(
        "incidence = [\"T0 b0 = b0 Tv\", \"T1 b1 = b1 Tv\"]",
        "incidence = [\"T0 b0 = b0 Tv\", \"T1 b1 = b1 Tv\"]\npins = [\"T0[2][2] = 1/2\"]",
    );
    // Without a [parameters] table the pin just fixes an entry: 1 dof left.
    let text = text.replace("[constraints.extra]\n\na = { entry = \"T0[1][0]\", default = 0.25 }\nb = { entry = \"T0[0][1]\", default = 0.25 }\n", "");
    let d = parse_design(&text, "f.toml", "f").unwrap();
    assert_eq!(solve(&d).unwrap().dof(), 1);
    let text = CORNER.replace(
        "incidence = [\"T0 b0 = b0 Tv\", \"T1 b1 = b1 Tv\"]",
        "incidence = [\"T0 b0 = b0 Tv\", \"T1 b1 = b1 Tv\"]\npins = [\"T0[2][2] = 1/2\"]",
    );
    let d = parse_design(&text, "f.toml", "f").unwrap();
    assert_eq!(solve(&d).unwrap_err().to_string(), "parameter `a` is not free: the constraints give a = 1/2");
}

#[test]
fn a_side_with_two_unknown_matrices_is_refused() {
    let text = CORNER
        .replace("adjacency = [\"T0 b1 = T1 b0\"]", "adjacency = [\"T0 b1 = T1 b0\"]\ncommute = [\"T0 T1 = T1 T0\"]");
    let d = parse_design(&text, "f.toml", "f").unwrap();
    assert_eq!(
        solve(&d).unwrap_err().to_string(),
        "`commute: T0 T1 = T1 T0` is not linear: its left side multiplies two matrices that depend on unknowns (at most one factor per side may be unknown)"
    );
}

#[test]
fn parameters_in_known_matrices_are_solved_for() {
    // The corner-cutting T0 written with a parameter t; T1 and Tv unknown.
    let text = "[[state]]\nname = \"e\"\ndim = 3\n[[state]]\nname = \"v\"\ndim = 2\n\
        [[arrow]]\nname = \"T0\"\nfrom = \"e\"\nto = \"e\"\nmatrix = [[\"1 - t\", \"t\", 0], [\"t\", \"1 - t\", \"1 - t\"], [0, 0, \"t\"]]\n\
        [[arrow]]\nname = \"T1\"\nfrom = \"e\"\nto = \"e\"\nmatrix = \"unknown\"\n\
        [[arrow]]\nname = \"Tv\"\nfrom = \"v\"\nto = \"v\"\nmatrix = \"unknown\"\n\
        [[arrow]]\nname = \"b0\"\nfrom = \"e\"\nto = \"v\"\nkind = \"boundary\"\nselect = [0, 1]\n\
        [[arrow]]\nname = \"b1\"\nfrom = \"e\"\nto = \"v\"\nkind = \"boundary\"\nselect = [1, 2]\n\
        [constraints]\nall = [\"T0 b1 = T1 b0\", \"T0 b0 = b0 Tv\", \"T1 b1 = b1 Tv\"]\n\
        [parameters]\nt = { default = 0.25 }\n";
    let d = parse_design(text, "f.toml", "f").unwrap();
    let f = solve(&d).unwrap();
    assert_eq!(f.parameter_names(), ["t"]);
    assert_eq!(f.entry_text("T1", 1, 0), "1 - t");
    assert_eq!(f.entry_text("Tv", 0, 1), "t");
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, .. ProptestConfig::default() })]

    /// Any edit of a valid file parses or fails with a positioned error; solving never panics.
    #[test]
    fn mutated_files_never_panic(at in 0usize..CORNER.len(), len in 0usize..6, insert in "[\\[\\]=\"a-z0-9 \n.,-]{0,4}") {
        let mut text = CORNER.to_string();
        let at = (0..=at).rev().find(|i| text.is_char_boundary(*i)).unwrap_or(0);
        let end = (at + len..=text.len()).find(|i| text.is_char_boundary(*i)).unwrap_or(text.len());
        text.replace_range(at..end, &insert);
        match parse_design(&text, "m.toml", "m") {
            Ok(d) => { let _ = solve(&d); }
            Err(e) => prop_assert!(e.line >= 1 && e.column >= 1 && !e.message.is_empty()),
        }
    }
}

/// Hostile inputs of issue 15: each ends with a clear error, at once, with
/// no panic, abort, hang or unbounded allocation.
mod hostile {
    use super::*;

    fn one_state(entry: &str) -> String {
        format!(
            "[[state]]\nname = \"x\"\ndim = 1\n[[arrow]]\nname = \"T\"\nfrom = \"x\"\nto = \"x\"\nmatrix = [[\"{entry}\"]]\n"
        )
    }

    #[test]
    fn deeply_nested_expressions_are_refused() {
        let deep = format!("{}1{}", "(".repeat(20_000), ")".repeat(20_000));
        let e = error_of(&one_state(&deep));
        assert!(e.contains("nested more than 200 levels"), "{e}");
        let signs = format!("{}1", "-".repeat(20_000));
        assert!(error_of(&one_state(&signs)).contains("nested"));
    }

    /// Issue 23, item 5: a long flat expression (20,000 terms in a file,
    /// 12,000 in `--param`) is refused with its position, no stack overflow.
    #[test]
    fn long_flat_expressions_are_refused() {
        let flat = format!("1{}", "-1".repeat(20_000));
        let e = error_of(&one_state(&flat));
        assert!(e.starts_with("f.toml:8:") && e.contains("more than 1000 operations"), "{e}");
        let products = format!("1{}", "*1".repeat(20_000));
        assert!(error_of(&one_state(&products)).contains("more than 1000 operations"));
        // Just under the limit parses and evaluates (1 − 1 − … = 1 − 999).
        let ok = format!("1{}", "-1".repeat(999));
        assert_eq!(
            bcifs::algebra::Expr::parse(&ok).unwrap().eval_constant().unwrap(),
            bcifs::algebra::Num::from_f64(-998.0)
        );
        let param = format!("a=({})", vec!["1"; 12_000].join("-"));
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_bcifs"))
            .args(["check", "corner_cutting", "--param", &param, "--param", "b=1/4"])
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{stderr}");
        assert!(stderr.contains("more than 1000 operations"), "{stderr}");
    }

    #[test]
    fn huge_exponents_are_refused_at_once() {
        let started = std::time::Instant::now();
        let e = error_of(&one_state("1e900000000"));
        assert!(e.contains("exponent is beyond ±4000"), "{e}");
        let e = error_of(
            "[[state]]\nname = \"x\"\ndim = 1\n[[arrow]]\nname = \"T\"\nfrom = \"x\"\nto = \"x\"\nmatrix = [[1e900000000]]\n",
        );
        assert!(e.starts_with("f.toml:8:"), "a positioned error: {e}");
        assert!(started.elapsed().as_secs() < 5);
    }

    #[test]
    fn extends_cycles_are_refused() {
        let dir = std::env::temp_dir().join(format!("bcifs-extends-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("a.toml"), "extends = \"b.toml\"\n").unwrap();
        std::fs::write(dir.join("b.toml"), "extends = \"a.toml\"\n").unwrap();
        let e = bcifs::read_design(&dir.join("a.toml")).unwrap_err().to_string();
        assert!(e.contains("cycle") && e.contains("a.toml") && e.contains("b.toml"), "{e}");
        std::fs::write(dir.join("c.toml"), "extends = \"c.toml\"\n").unwrap();
        assert!(bcifs::read_design(&dir.join("c.toml")).unwrap_err().to_string().contains("cycle"));
        // Issue 23, item 15: a chain of 17 files is too long, not a cycle.
        for i in 0..17 {
            std::fs::write(dir.join(format!("l{i}.toml")), format!("extends = \"l{}.toml\"\n", i + 1)).unwrap();
        }
        std::fs::write(dir.join("l17.toml"), "extends = \"corner_cutting\"\n").unwrap();
        let e = bcifs::read_design(&dir.join("l0.toml")).unwrap_err().to_string();
        assert!(e.contains("more than 16 files") && !e.contains("cycle"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// Issue 23, item 15: sizes over the solver's limit are said as such, not
    /// as an internal error; parameters so large that a column's sum is lost
    /// to rounding are said as such, not as a column that sums to 0.
    #[test]
    fn limits_are_not_internal_errors() {
        let e = bcifs::schemes::curve(100_000, 3, 2).unwrap_err().to_string();
        assert!(e.contains("at most 20000") && !e.contains("internal"), "{e}");
        assert!(bcifs::schemes::curve(20, 3, 2).is_ok());
        let design = bcifs::builtin_design("corner_cutting").unwrap();
        let inst = bcifs::instantiate(&design, &[("a".into(), 1e300), ("b".into(), 1e300)]).unwrap();
        let settings = bcifs::eval::EvalSettings::default().with_force();
        let e =
            bcifs::eval::Evaluator::new(&inst.automaton, design.model().unwrap(), settings).err().unwrap().to_string();
        assert!(e.contains("lost to rounding") && e.contains("1e300"), "{e}");
    }

    #[test]
    fn a_grid_of_points_of_dimension_one_is_a_layout_error() {
        let text = "[[state]]\nname = \"x\"\ndim = 1\n[[arrow]]\nname = \"T\"\nfrom = \"x\"\nto = \"x\"\nmatrix = [[1]]\n\
            [model]\nroot = \"x\"\nlayout = \"grid\"\ngrid = [2, 2]\npoints = [[0, 0], [1, 0], [0, 1], [1, 1]]\n";
        let d = parse_design(text, "g.toml", "g").unwrap();
        let inst = bcifs::instantiate(&d, &[]).unwrap();
        let e = bcifs::eval::Evaluator::new(&inst.automaton, d.model().unwrap(), Default::default());
        assert!(e.err().unwrap().to_string().contains("w ≥ 2"));
    }

    /// A control net is written and read back; a face with an index past the
    /// points, or a negative one, is refused at the `net` line.
    #[test]
    fn control_nets_round_trip_and_bad_faces_are_positioned() {
        let base = "[[state]]\nname = \"x\"\ndim = 3\n[[arrow]]\nname = \"T\"\nfrom = \"x\"\nto = \"x\"\n\
            matrix = [[1, 0.5, 0.5], [0, 0.5, 0], [0, 0, 0.5]]\n[model]\nroot = \"x\"\n\
            points = [[0, 0], [1, 0], [0, 1], [1, 1]]\n";
        let d = parse_design(&format!("{base}net = [[0, 1, 3, 2]]\n"), "n.toml", "n").unwrap();
        assert_eq!(d.model().unwrap().net, vec![vec![0, 1, 3, 2]]);
        let again = parse_design(&bcifs::write_design(&d), "n.toml", "n").unwrap();
        assert_eq!(again.model().unwrap().net, d.model().unwrap().net);
        for bad in ["net = [[0, 1, 4]]", "net = [[0, 1]]", "net = [[0, -1, 2]]"] {
            let e = error_of(&format!("{base}{bad}\n"));
            assert!(e.starts_with("f.toml:12:"), "{bad}: {e}");
            assert!(e.contains("net") || e.contains("indices"), "{bad}: {e}");
        }
    }

    /// A patches layout names each piece's points; a patch with an index past
    /// the points, a negative one, or as many points as its root's dimension
    /// not, is refused at the `patches` line. It round-trips.
    #[test]
    fn patches_round_trip_and_bad_patches_are_positioned() {
        let base = "[[state]]\nname = \"x\"\ndim = 3\n[[arrow]]\nname = \"T\"\nfrom = \"x\"\nto = \"x\"\n\
            matrix = [[1, 0.5, 0.5], [0, 0.5, 0], [0, 0, 0.5]]\n[model]\nroot = [\"x\", \"x\"]\nlayout = \"patches\"\n\
            points = [[0, 0], [1, 0], [0, 1], [1, 1]]\n";
        let d = parse_design(&format!("{base}patches = [[0, 1, 2], [1, 3, 2]]\n"), "p.toml", "p").unwrap();
        assert_eq!(d.model().unwrap().patches, vec![vec![0, 1, 2], vec![1, 3, 2]]);
        let again = parse_design(&bcifs::write_design(&d), "p.toml", "p").unwrap();
        assert_eq!(again.model().unwrap().patches, d.model().unwrap().patches);
        for (bad, at, says) in [
            ("patches = [[0, 1, 4], [1, 3, 2]]", "f.toml:13:", "uses control point 4"),
            ("patches = [[0, 1], [1, 3, 2]]", "f.toml:13:", "lists 2 control points"),
            ("patches = [[0, -1, 2]]", "f.toml:13:", "indices"),
            ("", "f.toml:9:", "needs patches"),
        ] {
            let e = error_of(&format!("{base}{bad}\n"));
            assert!(e.starts_with(at), "{bad}: {e}");
            assert!(e.contains(says), "{bad}: {e}");
        }
    }

    #[test]
    fn absurd_depths_are_refused_at_once() {
        let d = bcifs::builtin_design("levy").unwrap();
        let inst = bcifs::instantiate(&d, &[]).unwrap();
        let started = std::time::Instant::now();
        for depth in [60, 1000, 4_294_967_296] {
            let ev = bcifs::eval::Evaluator::new(
                &inst.automaton,
                d.model().unwrap(),
                bcifs::eval::EvalSettings::default().with_depth(depth),
            );
            // Refused by the depth limit, or by the memory estimate before any output.
            assert!(ev.and_then(|e| e.evaluate()).is_err(), "depth {depth}");
        }
        assert!(started.elapsed().as_secs() < 5, "no exponential count");
    }

    #[test]
    fn mistyped_dimensions_are_refused_before_solving() {
        let text = "[[state]]\nname = \"x\"\ndim = 100000\n[[arrow]]\nname = \"T\"\nfrom = \"x\"\nto = \"x\"\nmatrix = \"unknown\"\n";
        let started = std::time::Instant::now();
        let e = error_of(text);
        assert!(e.contains("100000×100000") && e.contains("mistyped"), "{e}");
        let text = text.replace("100000", "300");
        assert!(error_of(&text).contains("unknowns"), "{}", error_of(&text));
        assert!(started.elapsed().as_secs() < 5);
    }
}
