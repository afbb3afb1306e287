//! Property tests: any parameter values give zero residual for every constraint.

use bcifs::analysis::check;
use bcifs::{builtin_design, solve};
use proptest::prelude::*;

fn max_residual(name: &str, values: &[(&str, f64)]) -> (f64, f64) {
    let f = solve(&builtin_design(name).unwrap()).unwrap();
    let values: Vec<(String, f64)> = values.iter().map(|(n, v)| (n.to_string(), *v)).collect();
    let inst = f.instantiate(&values).unwrap();
    let r = check(&inst.automaton, &inst.values, 1e-9).unwrap();
    (r.constraints.iter().map(|(_, x)| *x).fold(0.0, f64::max), r.max_column_sum_error)
}

// Entries are sums of at most a few products of O(10) numbers: rounding stays
// below 1e-12 for parameters in [-10, 10].
const TOL: f64 = 1e-12;

proptest! {
    #[test]
    fn corner_cutting_constraints_hold_everywhere(a in -10.0f64..10.0, b in -10.0f64..10.0) {
        let (r, c) = max_residual("corner_cutting", &[("a", a), ("b", b)]);
        prop_assert!(r <= TOL && c <= TOL, "residual {r}, column sums {c}");
    }

    #[test]
    fn cubic_curve_constraints_hold_everywhere(a in -10.0f64..10.0, b in -10.0f64..10.0, c in -10.0f64..10.0) {
        let (r, s) = max_residual("curve_4_3", &[("a", a), ("b", b), ("c", c)]);
        prop_assert!(r <= TOL && s <= TOL, "residual {r}, column sums {s}");
    }

    #[test]
    fn doo_sabin_constraints_hold_everywhere(a in -10.0f64..10.0, b in -10.0f64..10.0, g in -10.0f64..10.0) {
        let (r, s) = max_residual("doo_sabin_quad", &[("alpha", a), ("beta", b), ("gamma", g)]);
        prop_assert!(r <= TOL && s <= TOL, "residual {r}, column sums {s}");
    }
}
