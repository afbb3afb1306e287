//! Issue 47: inverse design. Members rendered at known parameters are fitted
//! back from the defaults; numbers are reached exactly where the family
//! allows; a target beyond the proven region gets a proven member and the
//! reason; bad input is refused before any work.

use std::process::Command;

use bcifs::fit::{BOX_SPREAD, FitError, FitOptions, FitReport, FitTarget, fit};
use bcifs::render::{Design, Options, evaluate_design, load};

/// The depth-`depth` vertices of `design` at `params`.
fn member(design: &Design, depth: usize, params: &[(&str, f64)]) -> Vec<[f64; 3]> {
    let params = params.iter().map(|(n, v)| (n.to_string(), *v)).collect();
    let options = Options { params, ..Options::default() }.with_depth(depth);
    evaluate_design(design, &options, &mut Vec::new()).unwrap().points()
}

fn value(report: &FitReport, name: &str) -> f64 {
    report.parameters.iter().find(|(n, _)| n == name).unwrap().1
}

/// The ternary 5-point curve with ω free (`bcifs scheme ifs ternary5 --omega w --print`).
fn ternary() -> Design {
    let out = Command::new(env!("CARGO_BIN_EXE_bcifs"))
        .args(["scheme", "ifs", "ternary5", "--omega", "w", "--print"])
        .output()
        .unwrap();
    assert!(out.status.success());
    let path = std::env::temp_dir().join(format!("bcifs-fit-ternary-{}.toml", std::process::id()));
    std::fs::write(&path, &out.stdout).unwrap();
    let design = load(path.to_str().unwrap()).unwrap();
    std::fs::remove_file(&path).unwrap();
    design
}

/// Noise-free targets: corner cutting (two parameters), the ternary 5-point
/// curve (ω) and the Doo-Sabin torus (α, β, γ: a surface) come back to 1e-6
/// from their defaults, proven to converge, the points to rounding.
#[test]
fn members_are_recovered_from_their_points() {
    type Case = (Design, usize, Vec<(&'static str, f64)>);
    let cases: Vec<Case> = vec![
        (load("corner_cutting").unwrap(), 6, vec![("a", 0.1), ("b", 0.35)]),
        (ternary(), 3, vec![("w", 0.03)]),
        (load("doo_sabin_torus").unwrap(), 2, vec![("alpha", 0.62), ("beta", 0.13), ("gamma", 0.2)]),
    ];
    for (design, depth, truth) in cases {
        let target = FitTarget { points: member(&design, depth, &truth), ..FitTarget::default() };
        let report = fit(&design, &target, &FitOptions::default()).unwrap();
        for (name, v) in &truth {
            assert!(
                (value(&report, name) - v).abs() < 1e-6,
                "{}: {name} = {} for {v}",
                design.name(),
                value(&report, name)
            );
        }
        assert!(report.converges && report.jsr_upper < 1.0 && report.depth == depth, "{report:?}");
        assert!(report.distance.unwrap() < 1e-9, "{report:?}");
    }
}

/// 1 % noise (uniform, a hundredth of the target's extent on each
/// coordinate): the fitted curve lies within the noise of the clean one (their
/// symmetric RMS distance as sets below the noise's RMS) and its parameters
/// within three times the noise's level of the truth.
#[test]
fn noisy_points_give_a_member_within_the_noise() {
    let design = load("corner_cutting").unwrap();
    let clean = member(&design, 6, &[("a", 0.1), ("b", 0.35)]);
    let extent = clean.iter().flat_map(|p| p.iter().copied()).fold(0.0f64, |m, x| m.max(x.abs()));
    let mut state = 12345u64;
    let mut noise = || {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0) * 0.01 * extent
    };
    let noisy: Vec<[f64; 3]> = clean.iter().map(|p| [p[0] + noise(), p[1] + noise(), 0.0]).collect();
    let rms_noise = (noisy.iter().zip(&clean).map(|(a, b)| (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sum::<f64>()
        / clean.len() as f64)
        .sqrt();
    let report = fit(&design, &FitTarget { points: noisy, ..FitTarget::default() }, &FitOptions::default()).unwrap();
    let fitted = member(&design, 6, &[("a", value(&report, "a")), ("b", value(&report, "b"))]);
    // The curves' distance as sets (each point's nearest on the other, both ways): where the
    // samples fall along the curve is not what points without order can tell.
    let nearest = |p: &[f64; 3], set: &[[f64; 3]]| {
        set.iter().map(|q| (p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)).fold(f64::INFINITY, f64::min)
    };
    let one_way = |a: &[[f64; 3]], b: &[[f64; 3]]| a.iter().map(|p| nearest(p, b)).sum::<f64>() / a.len() as f64;
    let rms_fit = ((one_way(&fitted, &clean) + one_way(&clean, &fitted)) / 2.0).sqrt();
    assert!(rms_fit < rms_noise, "the fit is {rms_fit} from the clean points, the noise {rms_noise}");
    // The parameters move the curve less than they move (a set changes slower than its
    // parametrization): within three times the noise's level.
    assert!((value(&report, "a") - 0.1).abs() < 0.03 && (value(&report, "b") - 0.35).abs() < 0.03, "{report:?}");
    assert!(report.converges);
}

/// The Cantor set's two pieces have lengths a and 1 − b: Moran's equation
/// a^D + (1 − b)^D = 1 holds at the fitted member to 1e-9 for every
/// dimension asked, and the report's value is the one asked.
#[test]
fn dimension_targets_hit_the_moran_value() {
    let design = load("cantor").unwrap();
    for dimension in [0.3, 0.5, 0.6309297535714574, 0.8] {
        let target = FitTarget { dimension: Some(dimension), ..FitTarget::default() };
        let report = fit(&design, &target, &FitOptions::default()).unwrap();
        let (a, b) = (value(&report, "a"), value(&report, "b"));
        let moran = a.powf(dimension) + (1.0 - b).powf(dimension);
        assert!((moran - 1.0).abs() < 1e-9, "D = {dimension}: a = {a}, b = {b}, Σ r^D = {moran}");
        assert!((report.numbers[0].value - dimension).abs() < 1e-9 && report.converges, "{report:?}");
    }
}

/// Points only a diverging member would reach (the ternary curve's bulge at
/// ω = 0.08 tripled, as ω ≈ 0.2 would give, where the bounds prove
/// divergence from 0.1 on): the answer is a member proven to converge, near
/// the edge of the proven region, with the reason and the cycle that stops it.
#[test]
fn a_target_beyond_the_proven_region_gets_a_proven_member_and_the_reason() {
    let design = ternary();
    let (flat, bulged) = (member(&design, 3, &[("w", 0.0)]), member(&design, 3, &[("w", 0.08)]));
    let points = flat.iter().zip(&bulged).map(|(f, b)| [0, 1, 2].map(|k| f[k] + 3.0 * (b[k] - f[k]))).collect();
    let report = fit(&design, &FitTarget { points, ..FitTarget::default() }, &FitOptions::default()).unwrap();
    assert!(report.converges && report.jsr_upper < 1.0, "{report:?}");
    let w = value(&report, "w");
    assert!(w > 0.08 && w < 0.1, "w = {w}: near the edge of the proven region");
    let reason = report.reason.as_deref().unwrap_or_default();
    assert!(reason.contains("not proven") && reason.contains("T0"), "{reason}");
}

/// A junction angle is reached exactly (corner cutting: 150°).
#[test]
fn an_angle_target_is_reached() {
    let design = load("corner_cutting").unwrap();
    let report =
        fit(&design, &FitTarget { angle: Some(150.0), ..FitTarget::default() }, &FitOptions::default()).unwrap();
    assert!((report.numbers[0].value - 150.0).abs() < 1e-9 && report.converges, "{report:?}");
}

/// A three-parameter curve family (`curve_4_3`: the uniform cubic B-spline at its defaults) comes
/// back from members far from the defaults, from the defaults alone, where the weights stay in
/// [0, 1]. (Rougher members, a weight below 0 or above 1, have narrow basins: the guide gives the
/// share recovered.)
#[test]
fn a_three_parameter_curve_is_recovered_far_from_its_defaults() {
    let design = load("curve_4_3").unwrap();
    for [a, b, c] in [[0.764, 0.368, 0.437], [0.844, 0.191, 0.583], [0.871, 0.039, 0.282], [0.309, 0.335, 0.356]] {
        let points = member(&design, 6, &[("a", a), ("b", b), ("c", c)]);
        let report = fit(&design, &FitTarget { points, ..FitTarget::default() }, &FitOptions::default()).unwrap();
        let got = [value(&report, "a"), value(&report, "b"), value(&report, "c")];
        let error = (0..3).map(|k| (got[k] - [a, b, c][k]).abs()).fold(0.0, f64::max);
        assert!(error < 1e-9 && report.converges && report.starts == 1, "{a} {b} {c}: {report:?}");
    }
}

/// Porosity targets on a lace: the carpet (a cells pattern, 16 split points) reaches 0.3, 0.5 and
/// 0.7 from its defaults (0.16 on its saddle), the value its lacunarity report gives, proven to
/// converge. (Before the damping's floor, Marquardt's `diag(JᵀJ)` moved the parameters the
/// porosity hardly sees by the residual over their slopes, and the fit stalled at 0.25.)
#[test]
fn porosity_targets_are_reached_on_a_lace() {
    let design = load("carpet").unwrap();
    for porosity in [0.3, 0.5, 0.7] {
        let target = FitTarget { porosity: Some(porosity), ..FitTarget::default() };
        let report = fit(&design, &target, &FitOptions::default()).unwrap();
        let number = &report.numbers[0];
        assert!(number.reached && (number.value - porosity).abs() < 1e-9 && report.converges, "{report:?}");
        let measured = bcifs::report::lacunarity_report(&design, &report.parameters, 1).unwrap();
        assert!((measured.porosity[0] - number.value).abs() < 1e-12, "{measured:?}");
    }
}

/// The box count's spread, which a box-counted dimension target is met within
/// ([`BOX_SPREAD`]): corner cutting's members with a + b ≤ 0.9 (a, b ≥ 0.1) cut corners
/// proper (each new point on an old edge, in order), so their polygons never grow longer and
/// their curves are rectifiable: dimension exactly 1. Their box counts read within the spread of
/// 1 (0.018 at worst, root mean square 0.011, when this was written).
#[test]
fn box_count_spread() {
    let design = load("corner_cutting").unwrap();
    let mut errors = Vec::new();
    for i in 1..=8 {
        for j in 1..=8 {
            let (a, b) = (0.1 * f64::from(i), 0.1 * f64::from(j));
            if a + b > 0.9 + 1e-9 {
                continue;
            }
            let params = [("a".to_string(), a), ("b".to_string(), b)];
            let d = bcifs::report::dimension_report(&design, &params).unwrap().fit.unwrap().dimension;
            errors.push(d - 1.0);
        }
    }
    let rms = (errors.iter().map(|e| e * e).sum::<f64>() / errors.len() as f64).sqrt();
    let worst = errors.iter().fold(0.0f64, |w, e| w.max(e.abs()));
    assert!(rms <= BOX_SPREAD / 1.5 && worst <= BOX_SPREAD, "rms {rms}, worst {worst} over {} members", errors.len());
}

/// A box-counted dimension (corner cutting's maps are not similarities) is met within the box
/// count's spread, from 1 (the defaults) to 1.2 and 1.3; the value is the dimension report's at
/// the fitted member. (Differences over 10⁻⁶ of a parameter see a box count's steps, not its
/// slope: the fit stalled at 1.31 for 1.6.)
#[test]
fn box_counted_dimensions_are_met_within_their_spread() {
    let design = load("corner_cutting").unwrap();
    for dimension in [1.2, 1.3] {
        let target = FitTarget { dimension: Some(dimension), ..FitTarget::default() };
        let report = fit(&design, &target, &FitOptions::default()).unwrap();
        let number = &report.numbers[0];
        assert!(number.within == BOX_SPREAD && number.reached && report.converges, "{report:?}");
        assert!((number.value - dimension).abs() <= BOX_SPREAD, "{report:?}");
        let measured = bcifs::report::dimension_report(&design, &report.parameters).unwrap();
        assert_eq!(measured.fit.unwrap().dimension, number.value);
    }
}

/// Points and a number together: the least-squares compromise. Corner cutting's member (0.1, 0.35)
/// is smooth (junction angle 0°); asked for its points and an angle of 170° as well, the fit meets
/// the angle to within a right angle's thousandth and stays nearer the points than the member the
/// angle alone gives, and the reason says it is a compromise.
#[test]
fn points_and_a_number_are_fitted_together() {
    let design = load("corner_cutting").unwrap();
    let points = member(&design, 6, &[("a", 0.1), ("b", 0.35)]);
    let both = FitTarget { points: points.clone(), angle: Some(170.0), ..FitTarget::default() };
    let report = fit(&design, &both, &FitOptions::default()).unwrap();
    assert!((report.numbers[0].value - 170.0).abs() < 0.09 && report.converges, "{report:?}");
    let alone =
        fit(&design, &FitTarget { angle: Some(170.0), ..FitTarget::default() }, &FitOptions::default()).unwrap();
    // The points' distance at the angle-only member: a fit to the points from there, no iteration.
    let start = Some(alone.parameters.iter().map(|(_, v)| *v).collect());
    let at_alone = fit(
        &design,
        &FitTarget { points, ..FitTarget::default() },
        &FitOptions { start, iterations: 0, ..FitOptions::default() },
    )
    .unwrap();
    assert!(report.distance.unwrap() < at_alone.distance.unwrap(), "{report:?} against {at_alone:?}");
    if !report.numbers[0].reached {
        assert!(report.reason.as_deref().unwrap_or_default().contains("compromise"), "{report:?}");
    }
}

/// Control points too (`--control-points`): a member of corner cutting with three of its six
/// control points moved comes back, points and parameters, to 1e-9, and the fitted design (`-o`)
/// carries them in its model.
#[test]
fn control_points_are_fitted_when_asked() {
    let design = load("corner_cutting").unwrap();
    let mut moved = design.model().unwrap().clone();
    moved.points[0] = vec![0.2, -0.1];
    moved.points[2] = vec![3.3, 1.6];
    moved.points[4] = vec![0.1, 2.8];
    let mut builder = design.to_builder();
    builder.model(moved.clone());
    let member_design = builder.build().unwrap();
    let target = FitTarget { points: member(&member_design, 6, &[("a", 0.1), ("b", 0.35)]), ..FitTarget::default() };
    let options = FitOptions { control_points: true, ..FitOptions::default() };
    let report = fit(&design, &target, &options).unwrap();
    assert!((value(&report, "a") - 0.1).abs() < 1e-9 && (value(&report, "b") - 0.35).abs() < 1e-9, "{report:?}");
    let points = report.control_points.clone().unwrap();
    for (got, want) in points.iter().zip(&moved.points) {
        assert!(got.iter().zip(want).all(|(x, y)| (x - y).abs() < 1e-9), "{got:?} for {want:?}");
    }
    let fitted = bcifs::fit::fitted_design(&design, &report).unwrap();
    assert_eq!(fitted.model().unwrap().points, points);
    // Without the flag, the points stay the model's: the fit cannot reach the member.
    let plain = fit(&design, &target, &FitOptions::default()).unwrap();
    assert!(plain.control_points.is_none() && plain.residual > 1e-6);
}

/// Bad input is refused before any work, each with its reason.
#[test]
fn bad_targets_are_refused_before_any_work() {
    let cc = load("corner_cutting").unwrap();
    let refused = |design: &Design, target: FitTarget| fit(design, &target, &FitOptions::default()).unwrap_err();
    assert!(matches!(refused(&cc, FitTarget::default()), FitError::EmptyTarget));
    let nan = FitTarget { points: vec![[0.0, f64::NAN, 0.0]], ..FitTarget::default() };
    assert!(matches!(refused(&cc, nan), FitError::NotFinite(_)));
    assert!(matches!(
        refused(&cc, FitTarget { dimension: Some(f64::INFINITY), ..FitTarget::default() }),
        FitError::NotFinite(_)
    ));
    let space = FitTarget { points: vec![[0.0, 0.0, 1.0], [1.0, 0.0, 0.0]], ..FitTarget::default() };
    assert!(matches!(refused(&cc, space), FitError::Dimension { model: 2, target: 3 }));
    // Numbers no member can have: a fraction above 1, an angle past a straight one, a dimension
    // above the model space's (corner cutting is planar).
    for target in [
        FitTarget { porosity: Some(1e308), ..FitTarget::default() },
        FitTarget { porosity: Some(-0.1), ..FitTarget::default() },
        FitTarget { angle: Some(200.0), ..FitTarget::default() },
        FitTarget { dimension: Some(2.5), ..FitTarget::default() },
    ] {
        let e = refused(&cc, target);
        assert!(matches!(e, FitError::OutOfRange(_)) && e.to_string().contains("outside ["), "{e}");
    }
    // On the command line a negative number is the value, not a flag, and gets the same answer.
    let out = Command::new(env!("CARGO_BIN_EXE_bcifs")).args(["fit", "carpet", "--porosity", "-0.1"]).output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && stderr.contains("outside [0, 1]"), "{stderr}");
    // A porosity on a curve whose cells make no patch of their own (corner cutting's three
    // control points are no Bézier or B-spline segment the design declares).
    let e = refused(&cc, FitTarget { porosity: Some(0.3), ..FitTarget::default() });
    assert!(matches!(e, FitError::OutOfRange(_)) && e.to_string().contains("no length, area or volume"), "{e}");
    // ... and on one whose sub-cells are longer than the cell (Koch's, drawn as segments).
    let text = bcifs::BUILTIN_AUTOMATA
        .iter()
        .find(|(n, _)| *n == "koch")
        .unwrap()
        .1
        .replace("kind = \"edge\"", "kind = \"edge\"\npatch = \"polygon\"");
    let koch = bcifs::parse_design(&text, "koch.toml", "koch").unwrap();
    let e = bcifs::report::porosity(&koch, &[], 2).unwrap_err().to_string();
    assert!(e.contains("measure 1.333333 times their cell") && e.contains("leave no share"), "{e}");
    // A depth far past the target's, or a million starts: refused with the estimate, not a hang.
    let points = FitTarget { points: member(&cc, 3, &[]), ..FitTarget::default() };
    let deep = fit(&cc, &points, &FitOptions { depth: Some(40), ..FitOptions::default() }).unwrap_err();
    assert!(matches!(deep, FitError::TooLarge(_)) && deep.to_string().contains("lower the depth"), "{deep}");
    let many = fit(&cc, &points, &FitOptions { starts: 1_000_000, ..FitOptions::default() }).unwrap_err();
    assert!(matches!(many, FitError::TooLarge(_)), "{many}");
    let gasket = load("gasket").unwrap();
    let e = refused(&gasket, FitTarget { dimension: Some(1.5), ..FitTarget::default() });
    assert!(matches!(e, FitError::NoParameter(_)) && e.to_string().contains("no free parameter"), "{e}");
}

/// The command line on real files: `bcifs render` writes the member as OBJ
/// and binary PLY, `bcifs fit --to` reads either back and writes the fitted
/// design (`-o`), whose defaults are the member's; `--json` has the fields
/// scripts read.
#[test]
fn the_command_line_fits_files_and_writes_the_fitted_design() {
    let dir = std::env::temp_dir().join(format!("bcifs-fit-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let bcifs = |args: &[&str]| {
        let out = Command::new(env!("CARGO_BIN_EXE_bcifs")).args(args).output().unwrap();
        assert!(out.status.success(), "{args:?}: {}", String::from_utf8_lossy(&out.stderr));
        String::from_utf8(out.stdout).unwrap()
    };
    for ext in ["obj", "ply"] {
        let target = dir.join(format!("member.{ext}"));
        let fitted = dir.join(format!("fitted-{ext}.toml"));
        bcifs(&[
            "render",
            "corner_cutting",
            "--depth",
            "6",
            "--param",
            "a=0.1",
            "--param",
            "b=0.35",
            "-o",
            target.to_str().unwrap(),
        ]);
        let json = bcifs(&[
            "fit",
            "corner_cutting",
            "--to",
            target.to_str().unwrap(),
            "--json",
            "-o",
            fitted.to_str().unwrap(),
        ]);
        let report: serde_json::Value = serde_json::from_str(&json).unwrap();
        assert!((report["parameters"]["a"].as_f64().unwrap() - 0.1).abs() < 1e-6, "{json}");
        assert!(report["residual"].as_f64().unwrap() < 1e-9 && report["converges"] == true, "{json}");
        let check = bcifs(&["check", fitted.to_str().unwrap(), "--json"]);
        let check: serde_json::Value = serde_json::from_str(&check).unwrap();
        assert!((check["parameters"]["b"].as_f64().unwrap() - 0.35).abs() < 1e-6, "the fitted design's defaults");
    }
    // 3D meshes as bcifs writes them (Y-up) are read back into the model's axes: the Doo-Sabin
    // torus from a PLY, and a cells pattern (the carpet lace: sixteen split points) from an OBJ.
    for (name, params, ext) in
        [("doo_sabin_torus", ["alpha=0.62", "gamma=0.2"], "ply"), ("carpet", ["a=0.25", "d=0.4"], "obj")]
    {
        let target = dir.join(format!("{name}.{ext}"));
        let mut args = vec!["render", name, "--depth", "2", "-o", target.to_str().unwrap()];
        params.iter().for_each(|p| args.extend(["--param", p]));
        bcifs(&args);
        let report: serde_json::Value =
            serde_json::from_str(&bcifs(&["fit", name, "--to", target.to_str().unwrap(), "--json"])).unwrap();
        for p in params {
            let (key, v) = p.split_once('=').unwrap();
            let got = report["parameters"][key].as_f64().unwrap();
            assert!((got - v.parse::<f64>().unwrap()).abs() < 1e-6, "{name}: {key} = {got}");
        }
    }
    // A picture (the member drawn by `bcifs render`, 800 pixels): its outline has no model units,
    // so a scale and a shift are fitted with the parameters; they come back to a pixel's worth
    // (the outline runs along the drawn stroke, a pixel or two wide).
    let png = dir.join("member.png");
    bcifs(&[
        "render",
        "corner_cutting",
        "--depth",
        "7",
        "--param",
        "a=0.1",
        "--param",
        "b=0.35",
        "-o",
        png.to_str().unwrap(),
    ]);
    let report: serde_json::Value = serde_json::from_str(&bcifs(&[
        "fit",
        "corner_cutting",
        "--to",
        png.to_str().unwrap(),
        "--depth",
        "6",
        "--json",
    ]))
    .unwrap();
    let (a, b) = (report["parameters"]["a"].as_f64().unwrap(), report["parameters"]["b"].as_f64().unwrap());
    assert!((a - 0.1).abs() < 5e-3 && (b - 0.35).abs() < 5e-3, "{report}");
    assert!(report["converges"] == true && report["pose"]["scale"].as_f64().is_some(), "{report}");
    let out = Command::new(env!("CARGO_BIN_EXE_bcifs")).args(["fit", "corner_cutting"]).output().unwrap();
    assert!(!out.status.success() && String::from_utf8_lossy(&out.stderr).contains("nothing to fit to"));
    std::fs::remove_dir_all(&dir).unwrap();
}
