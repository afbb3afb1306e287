//! The scheme commands: thin shells over the generators.

use std::process::Command;

fn bcifs(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_bcifs")).args(args).output().expect("run bcifs");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into(),
        String::from_utf8_lossy(&out.stderr).into(),
    )
}

fn temp(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("bcifs-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir.join(name)
}

/// `bcifs scheme normal --print` writes an automaton that `bcifs check` passes
/// (vertex dimension 1), for a preset and for free parameters with a sign pattern.
#[test]
fn printed_normal_automata_pass_check() {
    for args in [
        vec!["scheme", "normal", "--preset", "snowflake", "--print"],
        vec![
            "scheme",
            "normal",
            "--p",
            "3",
            "--alpha",
            "0,1/4,3/4",
            "--beta",
            "0,sqrt(3)/4,sqrt(3)/4",
            "--sign",
            "level-index",
            "--polygon",
            "triangle",
            "--print",
        ],
    ] {
        let (code, text, err) = bcifs(&args);
        assert_eq!(code, 0, "{err}");
        let file = temp(&format!("{}.toml", args.len()));
        std::fs::write(&file, text).unwrap();
        let (code, out, err) = bcifs(&["check", file.to_str().unwrap(), "--json"]);
        assert_eq!(code, 0, "{out}{err}");
        let v: serde_json::Value = serde_json::from_str(&out).unwrap();
        assert_eq!(v["ok"], true);
        assert_eq!(v["contractive"], true);
    }
}

#[test]
fn scheme_renders_and_reports_bad_input() {
    let png = temp("koch.png");
    let (code, _, err) = bcifs(&["scheme", "normal", "--preset", "koch", "--depth", "3", "-o", png.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    assert!(std::fs::metadata(&png).unwrap().len() > 1000);
    let (code, _, err) =
        bcifs(&["scheme", "normal", "--preset", "approximating", "--form", "automaton", "-o", png.to_str().unwrap()]);
    assert_eq!(code, 2);
    assert!(err.contains("interpolatory"), "{err}");
    let (code, _, err) = bcifs(&["scheme", "normal", "--preset", "koch", "--p", "3", "-o", png.to_str().unwrap()]);
    assert_eq!(code, 2);
    assert!(err.contains("--p 3"), "{err}");
    let (code, _, err) = bcifs(&["scheme", "normal", "--sign", "alternat", "--print"]);
    assert_eq!(code, 2);
    assert!(err.contains("did you mean `alternate`"), "{err}");
    let obj = temp("torus.obj");
    let (code, _, err) = bcifs(&["scheme", "ifs", "ternary5-torus", "--depth", "1", "-o", obj.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    let (models, _) = tobj::load_obj(&obj, &tobj::LoadOptions::default()).unwrap();
    assert_eq!(models.iter().map(|m| m.mesh.positions.len() / 3).sum::<usize>(), 8 * 12 * 9);
    let (code, _, err) = bcifs(&["scheme", "ifs", "bezier", "--points", "0,0 1", "-o", obj.to_str().unwrap()]);
    assert_eq!(code, 2, "{err}");
    let (code, _, err) = bcifs(&["scheme", "ifs", "bezier", "--points", "0,0 1,x 2,0", "-o", obj.to_str().unwrap()]);
    assert_eq!(code, 2);
    assert!(err.contains("`x` is not a finite number"), "the bad token is named: {err}");
}

/// `bcifs analyze ternary5` prints the table and the ranges and writes the plot.
#[test]
fn analyze_ternary5_prints_ranges_and_plots() {
    let png = temp("t5.png");
    let (code, out, err) =
        bcifs(&["analyze", "ternary5", "--omega-range", "-0.1", "0.1", "--steps", "20", "-o", png.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(out.lines().filter(|l| l.trim_start().starts_with(['-', '0'])).count(), 21, "{out}");
    assert!(out.contains("fractal (C0 and length growth proven > 1) on ("), "{out}");
    assert!(out.contains("paper: (-0.01235, 0.16358)"), "{out}");
    let img = image::open(&png).unwrap();
    assert_eq!((img.width(), img.height()), (900, 600));
    let (code, _, _) = bcifs(&["analyze", "ternary5", "--omega-range", "0.1", "-0.1", "-o", png.to_str().unwrap()]);
    assert_eq!(code, 2);
}

/// Issue 14: the verdicts of `--omega-range 0.03 0.04` follow from the bounds:
/// C1 and fractal never meet (a C1 curve has finite length), and the JSON has
/// one object per row.
#[test]
fn analyze_ternary5_verdicts_never_contradict() {
    let png = temp("t5c.png");
    let (code, out, err) = bcifs(&[
        "analyze",
        "ternary5",
        "--omega-range",
        "0.03",
        "0.04",
        "--steps",
        "4",
        "--json",
        "-o",
        png.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let rows = v["rows"].as_array().unwrap();
    assert_eq!(rows.len(), 5);
    for r in rows {
        let c1 = r["c1_upper"].as_f64().unwrap() < 1.0;
        let fractal = r["verdict"] == "fractal";
        assert!(!(c1 && fractal), "{r}");
        if fractal {
            assert!(r["length_lower"].as_f64().unwrap() > 1.0 && r["c0_upper"].as_f64().unwrap() < 1.0, "{r}");
        }
    }
    let hi = |name: &str| {
        v["ranges"][name].as_array().unwrap().iter().map(|r| r[1].as_f64().unwrap()).fold(f64::NEG_INFINITY, f64::max)
    };
    let lo = |name: &str| {
        v["ranges"][name].as_array().unwrap().iter().map(|r| r[0].as_f64().unwrap()).fold(f64::INFINITY, f64::min)
    };
    assert!(hi("c1") < lo("fractal"), "C1 ends before the fractal range starts: {}", v["ranges"]);
}

/// `bcifs analyze map`: a verdict map of the corner cutting; the counts add
/// up, the paper's domain has diverging pixels, bad axes are usage errors.
#[test]
fn analyze_map_draws_the_verdicts() {
    let png = temp("map.png");
    let (code, out, err) = bcifs(&[
        "analyze",
        "map",
        "corner_cutting",
        "--x",
        "a=-1:2",
        "--y",
        "b=-1:2",
        "--size",
        "48",
        "-o",
        png.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let count = |label: &str| -> usize {
        let line = out.lines().find(|l| l.contains(label)).unwrap_or_else(|| panic!("{label} in {out}"));
        line.split_whitespace().last().unwrap().parse().unwrap()
    };
    let (green, red, grey, yellow) =
        (count("converges"), count("each matrix passes"), count("a matrix fails"), count("undecided"));
    assert_eq!(green + red + grey + yellow, 48 * 48);
    assert!(green > 100 && red > 0, "{out}");
    // Framed (issue 23, item 18): title, axes and a legend beside the 48 × 48 map, in its colours.
    let img = image::open(&png).unwrap().to_rgb8();
    assert_eq!((img.width(), img.height()), (980, 720));
    for colour in [[150, 205, 150], [215, 60, 60], [228, 228, 228]] {
        assert!(img.pixels().filter(|p| p.0 == colour).count() > 1000, "{colour:?} is drawn");
    }
    let (code, _, err) =
        bcifs(&["analyze", "map", "corner_cutting", "--x", "a=2:-1", "--y", "b=-1:2", "-o", png.to_str().unwrap()]);
    assert_eq!(code, 2);
    assert!(err.contains("FROM < TO"), "{err}");
    let (code, _, _) =
        bcifs(&["analyze", "map", "corner_cutting", "--x", "q=0:1", "--y", "b=-1:2", "-o", png.to_str().unwrap()]);
    assert_eq!(code, 2);
}

/// `analyze map --what region|angle -o map.csv` holds, pixel for pixel, the
/// regions and junction angles of `analyze curve --map … -o map.csv` (one
/// sweep, two commands); the verdict CSV's codes are the PNG's counts; a
/// band of a sweep is the whole sweep's rows, bit for bit; a dimension
/// sweep gives a plane curve's dimensions (between 1 and 2, 1 where Chaikin).
#[test]
fn analyze_map_sweeps_regions_angles_and_dimensions() {
    use bcifs::analysis::ParameterPlane;
    use bcifs::render::{SweepKind, SweepValues, sweep};
    let csv = |args: &[&str], name: &str| -> Vec<Vec<String>> {
        let path = temp(name);
        let mut all = args.to_vec();
        all.extend(["-o", path.to_str().unwrap()]);
        let (code, _, err) = bcifs(&all);
        assert_eq!(code, 0, "{err}");
        std::fs::read_to_string(&path)
            .unwrap()
            .lines()
            .skip(1)
            .map(|l| l.split(',').map(String::from).collect())
            .collect()
    };
    let axes = ["corner_cutting", "--x", "a=-0.5:1", "--y", "b=-0.5:1", "--size", "20"];
    let map =
        |what: &str| csv(&[&["analyze", "map"], &axes[..], &["--what", what]].concat(), &format!("sweep-{what}.csv"));
    let curve = csv(&[&["analyze", "curve"], &axes[..], &["--map", "regions"]].concat(), "curve-map.csv");
    let (regions, angles) = (map("region"), map("angle"));
    assert_eq!(curve.len(), 400);
    for ((c, r), a) in curve.iter().zip(&regions).zip(&angles) {
        assert_eq!((&c[0], &c[1]), (&r[0], &r[1]), "the same pixel centres");
        let region = if c[4].is_empty() { "undecided" } else { c[4].as_str() };
        assert_eq!(region, r[3], "the region's label");
        assert_eq!(c[5], a[2], "the junction angle, to the last digit");
    }
    let verdicts = map("verdict");
    let codes: Vec<i8> = verdicts.iter().map(|r| r[2].parse().unwrap()).collect();
    assert!(codes.contains(&1) && codes.contains(&-2));
    assert!(verdicts.iter().all(|r| (r[2] == "1") == (r[3] == "converges")));
    let design = bcifs::builtin_design("corner_cutting").unwrap();
    let plane = ParameterPlane { x: ("a".into(), -0.5, 1.0), y: ("b".into(), -0.5, 1.0), size: (20, 20) };
    let SweepValues::Codes(whole) = sweep(&design, &plane, SweepKind::Verdict, false, 0..20).unwrap() else {
        panic!("verdicts are codes")
    };
    assert_eq!(whole, codes, "the library's sweep is the CSV");
    let SweepValues::Codes(band) = sweep(&design, &plane, SweepKind::Verdict, false, 7..13).unwrap() else {
        panic!("verdicts are codes")
    };
    assert_eq!(band, whole[7 * 20..13 * 20]);
    let chaikin = ParameterPlane { x: ("a".into(), 0.2, 0.3), y: ("b".into(), 0.2, 0.3), size: (2, 2) };
    let SweepValues::Values(d) = sweep(&design, &chaikin, SweepKind::Dimension, false, 0..2).unwrap() else {
        panic!("dimensions are values")
    };
    // Near Chaikin (a = b = 1/4) the curve is C1: box dimension 1 within the fit's error.
    assert!(d.iter().all(|x| (x - 1.0).abs() < 0.05), "{d:?}");
    let err = sweep(&bcifs::builtin_design("doo_sabin_torus").unwrap(), &plane, SweepKind::Region, false, 0..1);
    assert!(err.is_err(), "regions are for curve families");
}

/// `bcifs contour ifs --json` lists the maps in segment order in the
/// paper's convention (the heart: L1 as printed), `contour automaton`
/// prints an automaton that `check` passes and `render --random` draws;
/// a bad segments file exits 1 with its position.
#[test]
fn contour_commands() {
    let file = temp("heart.toml");
    std::fs::write(
        &file,
        "[[segment]]\npoints = [[-1, 0], [-1, 1], [0, 0]]\n[[segment]]\npoints = [[0, 0], [1, 1], [1, 0]]\n\
         [[segment]]\npoints = [[-1, 0], [-1, -1], [0, -2]]\n[[segment]]\npoints = [[0, -2], [1, -1], [1, 0]]\n",
    )
    .unwrap();
    let (code, out, err) = bcifs(&["contour", "ifs", file.to_str().unwrap(), "--json"]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let maps = v["maps"].as_array().unwrap();
    assert_eq!(maps.len(), 8);
    assert_eq!((maps[0]["segment"].as_u64(), maps[0]["name"].as_str()), (Some(0), Some("L")));
    assert_eq!(maps[7]["name"].as_str(), Some("M"));
    assert_eq!(maps[0]["matrix"], serde_json::json!([[0.25, 0.5, 0.0], [0.0, 0.5, 0.0], [-0.75, 0.5, 1.0]]));
    let (code, automaton, err) = bcifs(&["contour", "automaton", file.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    let auto = temp("heart_automaton.toml");
    std::fs::write(&auto, automaton).unwrap();
    let (code, _, err) = bcifs(&["check", auto.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    let png = temp("heart.png");
    let (code, _, err) = bcifs(&["render", auto.to_str().unwrap(), "--random", "4000", "-o", png.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    // One closed polyline: the pieces share their ends (64 vertices and 64 edges at depth 4, not 4 × 17).
    let obj = temp("heart.obj");
    let (code, _, err) = bcifs(&["render", auto.to_str().unwrap(), "--depth", "4", "-o", obj.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    let text = std::fs::read_to_string(&obj).unwrap();
    let count = |tag: &str| text.lines().filter(|l| l.starts_with(tag)).count();
    assert_eq!((count("v "), count("l ")), (64, 64), "{text}");
    std::fs::write(&file, "[[segment]]\npoints = [[0, 0]]\n").unwrap();
    let (code, _, err) = bcifs(&["contour", "ifs", file.to_str().unwrap()]);
    assert!(code != 0 && err.contains("heart.toml:2:10"), "{code}: {err}");
}

/// `bcifs contour fit`: a PNG of a rotated square (light on dark, to check
/// the side choice) gives 4 line segments within the tolerance, as a
/// segments file that `contour automaton` and `check` take; a file that is
/// not a picture, or a blank one, exits 1 with a message and writes nothing.
#[test]
fn contour_fit_command() {
    let (w, h) = (160u32, 120u32);
    let corners: Vec<[f64; 2]> = (0..4)
        .map(|k| {
            let t = 0.3 + k as f64 * std::f64::consts::FRAC_PI_2;
            [80.0 + 45.0 * t.cos(), 60.0 + 45.0 * t.sin()]
        })
        .collect();
    let inside = |x: f64, y: f64| {
        (0..4).all(|k| {
            let (a, b) = (corners[k], corners[(k + 1) % 4]);
            (b[0] - a[0]) * (y - a[1]) - (b[1] - a[1]) * (x - a[0]) >= 0.0
        })
    };
    let img = image::GrayImage::from_fn(w, h, |x, y| image::Luma([if inside(x as f64, y as f64) { 230 } else { 20 }]));
    let png = temp("square.png");
    img.save(&png).unwrap();
    let seg = temp("square.toml");
    let (code, out, err) = bcifs(&["contour", "fit", png.to_str().unwrap(), "-o", seg.to_str().unwrap(), "--json"]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let segments = v["segments"].as_array().unwrap();
    assert_eq!(segments.len(), 4, "{out}");
    assert!(segments.iter().all(|s| s.as_array().unwrap().len() == 2), "{out}");
    assert!(v["max_distance"].as_f64().unwrap() <= 1.0, "{out}");
    let (code, automaton, err) = bcifs(&["contour", "automaton", seg.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    let auto = temp("square_automaton.toml");
    std::fs::write(&auto, automaton).unwrap();
    assert_eq!(bcifs(&["check", auto.to_str().unwrap()]).0, 0);
    let not_png = temp("not.png");
    std::fs::write(&not_png, "hello").unwrap();
    let missing = temp("never.toml");
    let (code, _, err) = bcifs(&["contour", "fit", not_png.to_str().unwrap(), "-o", missing.to_str().unwrap()]);
    assert!(code != 0 && err.contains("not a readable PNG or JPEG"), "{err}");
    image::GrayImage::from_pixel(20, 20, image::Luma([128])).save(&png).unwrap();
    let (code, _, err) = bcifs(&["contour", "fit", png.to_str().unwrap(), "-o", missing.to_str().unwrap()]);
    assert!(code != 0 && err.contains("nothing to trace"), "{err}");
    assert!(!missing.exists());
}
