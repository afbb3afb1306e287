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

proptest! {
    /// Printed numbers read back to the same exact value: rationals and
    /// sums of rational multiples of square roots.
    #[test]
    fn printed_surds_read_back(p in -1000i64..1000, q in 1i64..1000, r in -50i64..50, s in 1i64..50, k in 2u64..40) {
        let x: bcifs::algebra::Num = format!("{p}/{q} + ({r}/{s})*sqrt({k})").parse().unwrap();
        prop_assert!(x.is_exact());
        let back: bcifs::algebra::Num = x.to_string().parse().unwrap();
        prop_assert_eq!(&back, &x);
        let value = p as f64 / q as f64 + r as f64 / s as f64 * (k as f64).sqrt();
        prop_assert!((x.to_f64() - value).abs() < 1e-9);
    }

    /// A float given to a design is read as the decimal it prints as.
    #[test]
    fn floats_read_as_printed(x in -1e6f64..1e6) {
        let n = bcifs::algebra::Num::from_f64(x);
        prop_assert!(n.is_exact());
        prop_assert_eq!(n.to_f64(), x);
        let back: bcifs::algebra::Num = format!("{x:?}").parse().unwrap();
        prop_assert_eq!(back, n);
    }
}
