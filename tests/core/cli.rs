//! The command line contract: JSON shapes and exit codes.

use std::process::Command;

fn bcifs(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_bcifs"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("run bcifs");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into(),
        String::from_utf8_lossy(&out.stderr).into(),
    )
}

/// A fresh scratch directory for one test (removed by the test at its end).
fn scratch(tag: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("bcifs-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn json(text: &str) -> serde_json::Value {
    serde_json::from_str(text).expect("valid JSON")
}

#[test]
fn solve_json_contract() {
    let (code, out, _) = bcifs(&["solve", "automata/corner_cutting.toml", "--json"]);
    assert_eq!(code, 0);
    let v = json(&out);
    assert_eq!(v["automaton"], "corner_cutting");
    assert_eq!(v["consistent"], true);
    assert_eq!(v["dof"], 2);
    assert_eq!(v["parameters"], serde_json::json!(["a", "b"]));
    assert_eq!(v["matrices"]["T0"], serde_json::json!([["1 - a", "b", "0"], ["a", "1 - b", "1 - a"], ["0", "0", "a"]]));
}

#[test]
fn check_json_contract_and_exit_codes() {
    let (code, out, _) =
        bcifs(&["check", "automata/corner_cutting.toml", "--param", "a=0.2", "--param", "b=1/4", "--json"]);
    assert_eq!(code, 0);
    let v = json(&out);
    assert_eq!(v["ok"], true);
    assert_eq!(v["contractive"], true);
    assert_eq!(v["parameters"]["b"], 0.25);
    assert_eq!(v["constraints"].as_array().unwrap().len(), 3);
    assert!(v["constraints"][0]["max_abs_residual"].as_f64().unwrap() < 1e-12);
    assert_eq!(v["spectra"]["T0"].as_array().unwrap().len(), 3);
    assert!(v["max_column_sum_error"].as_f64().unwrap() < 1e-12);

    assert_eq!(v["converges"], true);
    assert_eq!(v["per_matrix_condition"], true);
    assert!(v["jsr"]["upper"].as_f64().unwrap() < 1.0);

    // Outside the convergence domain: constraints hold, the system diverges (exit 1).
    let (code, out, _) = bcifs(&["check", "corner_cutting", "--param", "a=1.5", "--json"]);
    assert_eq!(code, 1);
    let v = json(&out);
    assert_eq!(
        (v["ok"].clone(), v["contractive"].clone(), v["converges"].clone()),
        (true.into(), false.into(), false.into())
    );

    // Sokolov et al. 2010's "iff" is false: each matrix passes, the JSR proves divergence.
    let (code, out, _) = bcifs(&["check", "corner_cutting", "--param", "a=-0.9", "--param", "b=0.95", "--json"]);
    assert_eq!(code, 1);
    let v = json(&out);
    assert_eq!(v["per_matrix_condition"], true);
    assert_eq!(v["converges"], false);
    assert!((v["jsr"]["lower"].as_f64().unwrap() - 1.2601).abs() < 1e-4, "{v}");
    assert_eq!(v["jsr"]["witness"], serde_json::json!(["T0", "T1", "T1", "T1"]));

    // Unknown parameter, missing file: usage/file errors, exit 2.
    let (code, _, err) = bcifs(&["check", "corner_cutting", "--param", "aa=0.2"]);
    assert_eq!(code, 2);
    assert!(err.contains("`aa` is not a free parameter (did you mean `a`?)"), "{err}");
    let (code, _, err) = bcifs(&["check", "no/such/file.toml"]);
    assert_eq!(code, 2);
    assert!(err.contains("no/such/file.toml"), "{err}");
}

#[test]
fn failing_constraints_exit_1() {
    let dir = scratch("cli");
    // Koch with a broken tip: T1's end no longer meets T2's start.
    let text = include_str!("../../automata/koch.toml")
        .replacen("[0, \"sqrt(3)/6\", \"1/6\"]", "[0, \"sqrt(3)/5\", \"1/6\"]", 1)
        .replacen(
            "[\"1/3\", \"1/2\", \"1/3 - sqrt(3)/6\"]",
            "[\"1/3\", \"1/2 + sqrt(3)/6 - sqrt(3)/5\", \"1/3 - sqrt(3)/6\"]",
            1,
        );
    let path = dir.join("broken_koch.toml");
    std::fs::write(&path, text).unwrap();
    let p = path.to_str().unwrap();
    let (code, out, _) = bcifs(&["check", p, "--json"]);
    assert_eq!(code, 1, "{out}");
    let v = json(&out);
    assert_eq!(v["ok"], false);
    let (code, out, _) = bcifs(&["solve", p, "--json"]);
    assert_eq!(code, 1);
    let v = json(&out);
    assert_eq!(v["consistent"], false);
    assert_eq!(v["conflicts"][0], "adjacency: T1 b1 = T2 b0 (row 1, column 0)");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn new_prints_files_that_solve() {
    let (code, out, _) = bcifs(&["new", "curve", "--points", "5", "--vertex", "4", "--arity", "3"]);
    assert_eq!(code, 0);
    let d = bcifs::parse_design(&out, "new.toml", "new").unwrap();
    let f = bcifs::solve(&d).unwrap();
    // The quartic ternary B-spline is in the family and gives the defaults.
    let inst = f.instantiate(&[]).unwrap();
    let r = bcifs::analysis::check(&inst.automaton, &inst.values, 1e-9).unwrap();
    assert!(r.ok && r.contractive);
    let (code, _, err) = bcifs(&["new", "curve", "--points", "3", "--vertex", "3"]);
    assert_eq!(code, 2);
    assert!(err.contains("1 ≤ vertex < points"), "{err}");
}

/// A coloured, blurred density picture from the command line: written,
/// black where no sample fell, and in more than the palette's darkest colour.
#[test]
fn coloured_density_pictures_from_the_command_line() {
    let png = std::env::temp_dir().join(format!("bcifs-flame-{}.png", std::process::id()));
    let out = png.to_str().unwrap();
    let args = ["render", "gasket", "--random", "200000", "--palette", "rainbow", "--blur", "2", "--size", "120x100"];
    let (code, _, err) = bcifs(&[&args[..], &["--color", "T0=0.1", "--vibrancy", "0.7", "-o", out]].concat());
    assert_eq!(code, 0, "{err}");
    let img = image::open(&png).unwrap().to_rgb8();
    assert_eq!((img.width(), img.height()), (120, 100));
    assert_eq!(img.get_pixel(0, 0).0, [0, 0, 0], "a black background with a palette");
    let hues: std::collections::HashSet<[u8; 3]> = img.pixels().map(|p| p.0).collect();
    assert!(hues.len() > 50, "{} colours", hues.len());
    std::fs::remove_file(&png).unwrap();
}

/// The chaos game to OBJ is streamed a few chains at a time: every point
/// is written, the same file with one thread or two.
#[test]
fn chaos_game_points_stream_to_obj() {
    let dir = scratch("chaos-obj");
    let write = |threads: &str| {
        let out = dir.join(format!("fern-{threads}.obj"));
        let args = ["render", "fern", "--random", "300001", "--threads", threads, "-o", out.to_str().unwrap()];
        let (code, _, err) = bcifs(&args);
        assert_eq!(code, 0, "{err}");
        std::fs::read_to_string(&out).unwrap()
    };
    let (one, two) = (write("1"), write("2"));
    assert_eq!(one.lines().filter(|l| l.starts_with("v ")).count(), 300_001);
    assert!(one == two, "the same points with any number of threads");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Options that make no sense get a clear error (exit 2), not a broken picture.
#[test]
fn nonsense_options_are_refused() {
    let png = std::env::temp_dir().join(format!("bcifs-cli-{}.png", std::process::id()));
    let out = png.to_str().unwrap();
    for (args, expected) in [
        (vec!["render", "levy", "--threads", "100000", "-o", out], "--threads 100000"),
        (vec!["render", "levy", "--threads", "0", "-o", out], "--threads 0"),
        (vec!["render", "levy", "--size", "0x0", "-o", out], "at least 1 pixel"),
        (vec!["render", "levy", "--size", "100000x100000", "-o", out], "needs about 102.4 GiB to draw"),
        (vec!["render", "levy", "--size", "6000x6000", "--memory-mib", "64", "-o", out], "378 MiB to draw"),
        (vec!["render", "levy", "--view", "nan,nan", "-o", out], "finite"),
        (vec!["render", "fern", "--random", "100", "--depth", "3", "-o", out], "do not apply"),
        (vec!["render", "fern", "--random", "100", "--prob", "T0=-1", "-o", out], "at least 0"),
        (vec!["render", "fern", "--random", "100", "--prob", "TX=0.5", "-o", out], "to give a probability"),
        (vec!["render", "levy", "--random", "100", "--prob", "T0=0", "--prob", "T1=0", "-o", out], "probability 0"),
        (vec!["render", "gasket", "--random", "100", "--palette", "firre", "-o", out], "fire, ocean, rainbow"),
        // A surface tolerance no depth reaches: refused at once (it used to expand every cell).
        (vec!["render", "doo_sabin_torus", "--tolerance", "1e-9", "-o", out], "still larger than 0.000000001"),
        (vec!["render", "gasket", "--random", "100", "--palette", "fire", "--color", "T9=0.5", "-o", out], "to colour"),
        (
            vec!["render", "gasket", "--random", "100", "--palette", "fire", "--color", "T1=2", "-o", out],
            "between 0 and 1",
        ),
        (vec!["render", "gasket", "--random", "100", "--background", "12345", "-o", out], "RRGGBB"),
        (vec!["render", "gasket", "--random", "100", "--blur", "100", "-o", out], "--blur"),
        (vec!["render", "gasket", "--random", "100", "--vibrancy", "2", "-o", out], "--vibrancy"),
        (vec!["check", "corner_cutting", "--param", "zzz=1"], "the free parameters are `a`, `b`"),
        (vec!["check", "corner_cutting", "--param", "a=1e400"], "finite"),
    ] {
        let (code, _, err) = bcifs(&args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(err.contains(expected), "{args:?}: {err}");
        assert!(err.matches("is not a free parameter").count() <= 1, "said once: {err}");
    }
}

/// A fully known automaton whose constraints fail: `solve` says so (exit 1),
/// `render` refuses it too unless `--force`.
#[test]
fn render_refuses_a_file_whose_constraints_fail() {
    let dir = scratch("bad");
    let file = dir.join("bad.toml");
    std::fs::write(
        &file,
        "[[state]]\nname = \"e\"\ndim = 2\nkind = \"edge\"\n[[state]]\nname = \"v\"\ndim = 1\nkind = \"vertex\"\n\
         [[arrow]]\nname = \"T0\"\nfrom = \"e\"\nto = \"e\"\nmatrix = [[1, 0.5], [0, 0.5]]\n\
         [[arrow]]\nname = \"T1\"\nfrom = \"e\"\nto = \"e\"\nmatrix = [[0.6, 0], [0.4, 1]]\n\
         [[arrow]]\nname = \"Tv\"\nfrom = \"v\"\nto = \"v\"\nmatrix = [[1]]\n\
         [[arrow]]\nname = \"b0\"\nfrom = \"e\"\nto = \"v\"\nkind = \"boundary\"\nselect = [0]\n\
         [[arrow]]\nname = \"b1\"\nfrom = \"e\"\nto = \"v\"\nkind = \"boundary\"\nselect = [1]\n\
         [constraints]\nadjacency = [\"T0 b1 = T1 b0\"]\n\
         [model]\nroot = \"e\"\npoints = [[0, 0], [1, 0]]\n",
    )
    .unwrap();
    let (f, png) = (file.to_str().unwrap(), dir.join("bad.png"));
    let (code, _, _) = bcifs(&["solve", f]);
    assert_eq!(code, 1);
    let (code, _, err) = bcifs(&["render", f, "--depth", "3", "-o", png.to_str().unwrap()]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("the constraints do not hold") && err.contains("--force"), "{err}");
    assert!(!png.exists());
    let (code, _, err) = bcifs(&["render", f, "--depth", "3", "--force", "-o", png.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    assert!(png.exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Discoverability: `list` names every shipped automaton and preset, `show`
/// prints one, and a misspelt name gets the nearest one.
#[test]
fn list_show_and_suggestions() {
    let (code, out, _) = bcifs(&["list"]);
    assert_eq!(code, 0);
    for (name, _) in bcifs::BUILTIN_AUTOMATA {
        assert!(out.contains(name), "{name} in {out}");
    }
    assert!(out.contains("bicubic") && out.contains("snowflake"), "{out}");
    let (code, out, _) = bcifs(&["show", "fern"]);
    assert_eq!(code, 0);
    assert!(bcifs::parse_design(&out, "fern.toml", "fern").is_ok());
    let (code, out, _) = bcifs(&["show", "bicubic"]);
    assert_eq!(code, 0);
    assert!(bcifs::parse_design(&out, "bicubic.toml", "bicubic").is_ok());
    let (code, _, err) = bcifs(&["show", "levvy"]);
    assert_eq!(code, 2);
    assert!(err.contains("did you mean `levy`?"), "{err}");
    let (code, _, err) = bcifs(&["solve", "fren"]);
    assert_eq!(code, 2);
    assert!(err.contains("did you mean `fern`?") && err.contains("bcifs list"), "{err}");
}

/// OBJ is Y-up: a 3D model's z becomes the file's y (so Blender shows it
/// upright); `--up z` keeps the model's axes; 2D curves stay in the xy plane;
/// STL (and 3MF) are Z-up, the printers' convention.
#[test]
fn obj_files_are_y_up_unless_asked() {
    let dir = scratch("up");
    let first_vertex = |args: &[&str], file: &str| -> Vec<f64> {
        let path = dir.join(file);
        let mut all = args.to_vec();
        all.extend(["-o", path.to_str().unwrap()]);
        let (code, _, err) = bcifs(&all);
        assert_eq!(code, 0, "{err}");
        let text = std::fs::read_to_string(&path).unwrap();
        let line = text.lines().find(|l| l.starts_with("v ")).unwrap();
        line[2..].split(' ').map(|x| x.parse().unwrap()).collect()
    };
    let y = first_vertex(&["render", "doo_sabin_quad", "--depth", "1"], "y.obj");
    let z = first_vertex(&["render", "doo_sabin_quad", "--depth", "1", "--up", "z"], "z.obj");
    assert_eq!((y[0], y[1], y[2]), (z[0], z[2], -z[1]));
    assert!(z[2] != 0.0 || z[1] != 0.0);
    let curve = first_vertex(&["render", "corner_cutting", "--depth", "2"], "c.obj");
    assert_eq!(curve[2], 0.0, "2D stays in the xy plane");
    let (code, _, err) = bcifs(&["render", "levy", "--up", "x", "-o", dir.join("x.obj").to_str().unwrap()]);
    assert_eq!(code, 2);
    assert!(err.contains("invalid value 'x' for '--up") && err.contains("possible values: auto, y, z"), "{err}");
    // The print formats are Z-up: an STL's first triangle holds the model's coordinates as they are.
    let stl = dir.join("q.stl");
    // An open sheet is no solid: written for printing only when asked.
    assert_eq!(bcifs(&["render", "doo_sabin_quad", "--depth", "1", "-o", stl.to_str().unwrap()]).0, 2);
    let args = ["render", "doo_sabin_quad", "--depth", "1", "--allow-non-manifold", "-o", stl.to_str().unwrap()];
    assert_eq!(bcifs(&args).0, 0);
    let bytes = std::fs::read(&stl).unwrap();
    let corner: Vec<f64> =
        (0..3).map(|k| f64::from(f32::from_le_bytes(bytes[96 + 4 * k..100 + 4 * k].try_into().unwrap()))).collect();
    let model = bcifs::render::evaluate_design(
        &bcifs::render::load("doo_sabin_quad").unwrap(),
        &bcifs::render::Options::default().with_depth(1),
        &mut Vec::new(),
    )
    .unwrap();
    let near = |p: [f64; 3]| (0..3).all(|k| (p[k] - corner[k]).abs() < 1e-6);
    assert!((0..model.vertex_count()).any(|v| near(model.point(v))), "{corner:?} is a model vertex as it is");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// SIGTERM, SIGINT and SIGHUP during a streamed write remove its temporary
/// files and exit with 128 + the signal's number (143, 130, 129, as shells
/// do); the target keeps its old content.
#[test]
fn an_interrupted_write_leaves_nothing_behind() {
    let dir = scratch("signal");
    let target = dir.join("big.obj");
    std::fs::write(&target, b"old content").unwrap();
    let temporary = || {
        std::fs::read_dir(&dir).unwrap().flatten().filter(|e| e.file_name().to_string_lossy().ends_with(".tmp")).count()
    };
    for (signal, code) in [("TERM", 143), ("INT", 130), ("HUP", 129)] {
        let mut child = Command::new(env!("CARGO_BIN_EXE_bcifs"))
            .args(["render", "doo_sabin_torus", "--depth", "8", "-o", target.to_str().unwrap()])
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        let started = std::time::Instant::now();
        while temporary() == 0 && started.elapsed().as_secs() < 20 {
            if let Some(status) = child.try_wait().unwrap() {
                let mut err = String::new();
                std::io::Read::read_to_string(&mut child.stderr.take().unwrap(), &mut err).unwrap();
                assert!(err.contains("free"), "the render ended early ({status}): {err}");
                println!("skipped: not enough free disk for the write ({err})");
                std::fs::remove_dir_all(&dir).unwrap();
                return;
            }
            std::thread::sleep(std::time::Duration::from_millis(5));
        }
        if temporary() == 0 {
            let _ = child.kill();
            panic!("the write did not start");
        }
        let killed = Command::new("kill").args([&format!("-{signal}"), &child.id().to_string()]).status().unwrap();
        assert!(killed.success());
        let status = child.wait().unwrap();
        assert_eq!(status.code(), Some(code), "SIG{signal}");
        assert_eq!(temporary(), 0, "SIG{signal}: no temporary file left");
        assert_eq!(std::fs::read(&target).unwrap(), b"old content");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Issue 23, items 10 and 16: an output path that cannot be written (a
/// directory, a missing directory, a picture's extension for text) is
/// refused before any work, in every command that writes, with nothing
/// left behind; the gallery refuses a directory where it writes a file;
/// temporary files of dead processes (SIGKILL) are swept by any write in
/// their directory.
#[test]
fn unwritable_outputs_are_refused_before_any_work() {
    let dir = std::env::temp_dir().join(format!("bcifs-unwritable-{}", std::process::id()));
    let taken = dir.join("taken");
    std::fs::create_dir_all(&taken).unwrap();
    for ext in ["png", "obj", "svg", "off"] {
        std::fs::create_dir_all(dir.join(format!("x.{ext}"))).unwrap();
    }
    let at = |name: &str| dir.join(name).display().to_string();
    let commands: Vec<Vec<String>> = vec![
        vec!["render".into(), "doo_sabin_torus".into(), "--depth".into(), "9".into(), "-o".into(), at("x.obj")],
        vec!["render".into(), "levy".into(), "--depth".into(), "30".into(), "-o".into(), at("x.png")],
        vec!["render".into(), "fern".into(), "--random".into(), "100000000".into(), "-o".into(), at("x.png")],
        vec!["render".into(), "levy".into(), "-o".into(), at("x.svg")],
        vec!["render".into(), "levy".into(), "-o".into(), at("missing/x.png")],
        vec![
            "surface".into(),
            "tests/data/suzanne.obj".into(),
            "--scheme".into(),
            "loop".into(),
            "--triangulate".into(),
            "--depth".into(),
            "5".into(),
            "-o".into(),
            at("x.off"),
        ],
        vec!["scheme".into(), "ifs".into(), "koch-control".into(), "-o".into(), at("x.png")],
        vec!["analyze".into(), "ternary5".into(), "-o".into(), at("x.png")],
        vec![
            "analyze".into(),
            "map".into(),
            "corner_cutting".into(),
            "--x".into(),
            "a=0:1".into(),
            "--y".into(),
            "b=0:1".into(),
            "-o".into(),
            at("x.png"),
        ],
        vec!["contour".into(), "fit".into(), "tests/data/none.png".into(), "-o".into(), at("fit.png")],
    ];
    for args in &commands {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let started = std::time::Instant::now();
        let (code, _, err) = bcifs(&args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(
            err.contains("is a directory") || err.contains("does not exist") || err.contains("expected .toml"),
            "{args:?}: {err}"
        );
        assert!(started.elapsed().as_secs() < 5, "{args:?}: refused at once");
    }
    let left: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .flatten()
        .filter(|e| e.file_name().to_string_lossy().ends_with(".tmp"))
        .collect();
    assert!(left.is_empty(), "{left:?}");
    std::fs::create_dir_all(taken.join("fern.png")).unwrap();
    let (code, _, err) = bcifs(&["gallery", &taken.display().to_string()]);
    assert_eq!(code, 2);
    assert!(err.contains("fern.png") && err.contains("directory"), "{err}");
    // A dead process's temporary (PID 2^22 + 1 is beyond Linux's largest) is swept by a write beside it.
    let stale = dir.join(".other.obj.partial.4194305.0.tmp");
    std::fs::write(&stale, b"half").unwrap();
    let (code, _, err) = bcifs(&["render", "levy", "--depth", "8", "-o", &at("levy.png")]);
    assert_eq!(code, 0, "{err}");
    assert!(!stale.exists(), "the stale temporary is swept");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// An OBJ whose estimated size is over `--max-output-gib` (4 GiB by
/// default) is refused before anything is written, with the estimate.
#[test]
fn oversized_outputs_are_refused_with_the_estimate() {
    let target = std::env::temp_dir().join(format!("bcifs-huge-{}.obj", std::process::id()));
    let (code, _, err) = bcifs(&["render", "doo_sabin_torus", "--depth", "10", "-o", target.to_str().unwrap()]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("GiB") && err.contains("--max-output-gib"), "{err}");
    assert!(!target.exists());
    let (code, _, err) =
        bcifs(&["render", "doo_sabin_torus", "--depth", "2", "--max-output-gib", "0", "-o", target.to_str().unwrap()]);
    assert_eq!(code, 2);
    assert!(err.contains("positive"), "{err}");
}

/// `--dedup` drops the exact duplicate points of a cloud and says how many:
/// the fern's stem map `(x, y) ↦ (0, 0.16 y)` sends the start square's
/// bottom corners (±3, 0) to the same point, so a fixed depth repeats points.
/// The file holds distinct points only, as many as reported.
#[test]
fn dedup_drops_and_counts_exact_duplicates() {
    let dir = scratch("dedup");
    let vertex_lines = |file: &str| -> Vec<String> {
        let text = std::fs::read_to_string(dir.join(file)).unwrap();
        text.lines().filter(|l| l.starts_with("v ")).map(str::to_string).collect()
    };
    let path = |f: &str| dir.join(f).to_str().unwrap().to_string();
    let (code, _, err) = bcifs(&["render", "fern", "--depth", "5", "-o", &path("all.obj")]);
    assert_eq!(code, 0, "{err}");
    let (code, _, err) = bcifs(&["render", "fern", "--depth", "5", "--dedup", "-o", &path("unique.obj")]);
    assert_eq!(code, 0, "{err}");
    let (all, unique) = (vertex_lines("all.obj"), vertex_lines("unique.obj"));
    let distinct: std::collections::HashSet<&String> = all.iter().collect();
    assert_eq!(unique.len(), distinct.len());
    assert!(unique.len() < all.len());
    let dropped = all.len() - unique.len();
    assert!(err.contains(&format!("({dropped} exact duplicates dropped)")), "{err}");
    // On a curve it warns and keeps the polyline.
    let (code, _, err) = bcifs(&["render", "levy", "--depth", "4", "--dedup", "-o", &path("levy.obj")]);
    assert_eq!(code, 0);
    assert!(err.contains("deduplication applies to point clouds"), "{err}");
    assert!(std::fs::read_to_string(dir.join("levy.obj")).unwrap().contains("\nl "));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `bcifs surface`: a Blender export subdivided into a closed limit surface
/// (in the input's axes), its net as OFF, and bad input refused with the
/// place and no file.
#[test]
fn surface_subdivides_a_users_mesh() {
    let dir = scratch("surface");
    let path = |f: &str| dir.join(f).to_str().unwrap().to_string();
    let (code, _, err) = bcifs(&[
        "surface",
        "tests/data/torus12.obj",
        "--scheme",
        "catmull-clark",
        "--depth",
        "2",
        "-o",
        &path("t.obj"),
    ]);
    assert_eq!(code, 0, "{err}");
    let limit = bcifs::mesh::read_mesh(&dir.join("t.obj")).unwrap();
    let input = bcifs::mesh::read_mesh(std::path::Path::new("tests/data/torus12.obj")).unwrap();
    assert!(limit.is_closed());
    assert_eq!(limit.face_count(), 16 * input.face_count());
    // Same axes as the input: the torus lies in the file's xz plane (Blender wrote it Y-up).
    let extent = |m: &bcifs::mesh::PolyMesh, a: usize| {
        m.positions.iter().map(|p| p[a]).fold(f64::NEG_INFINITY, f64::max)
            - m.positions.iter().map(|p| p[a]).fold(f64::INFINITY, f64::min)
    };
    assert!(extent(&limit, 1) < 0.5 * extent(&limit, 0), "the torus stays in the xz plane");
    assert!((extent(&limit, 1) - extent(&input, 1)).abs() < 0.5 * extent(&input, 1));
    let (code, _, err) = bcifs(&[
        "surface",
        "tests/data/torus12.obj",
        "--scheme",
        "doo-sabin",
        "--depth",
        "1",
        "--net",
        "-o",
        &path("n.off"),
    ]);
    assert_eq!(code, 0, "{err}");
    let net = bcifs::mesh::read_mesh(&dir.join("n.off")).unwrap();
    assert_eq!(net.face_count(), input.face_count() * 4, "Doo-Sabin on a quad torus: F + E + V faces = 4F");
    // Loop on the quad torus split into triangles: a closed triangle mesh, 4^2 triangles per triangle.
    let (code, _, err) = bcifs(&[
        "surface",
        "tests/data/torus12.obj",
        "--scheme",
        "loop",
        "--triangulate",
        "--depth",
        "2",
        "--net",
        "-o",
        &path("l.off"),
    ]);
    assert_eq!(code, 0, "{err}");
    let loop_net = bcifs::mesh::read_mesh(&dir.join("l.off")).unwrap();
    assert!(loop_net.is_closed() && loop_net.faces().all(|f| f.len() == 3));
    assert_eq!(loop_net.face_count(), 16 * 2 * input.face_count());
    std::fs::write(dir.join("bad.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 3\n").unwrap();
    for (args, expected) in [
        (
            vec!["surface", &path("bad.obj"), "--scheme", "doo-sabin", "-o", &path("bad.png")],
            "bad.obj:5: face 1: edge 0→1 runs the same way",
        ),
        (
            vec![
                "surface",
                "tests/data/torus12.obj",
                "--scheme",
                "doo-sabin",
                "--param",
                "alpha=1.2",
                "-o",
                &path("bad.png"),
            ],
            "alpha = 1.2",
        ),
        (
            vec![
                "surface",
                "tests/data/torus12.obj",
                "--scheme",
                "catmull-clark",
                "--param",
                "alpha=0.5",
                "-o",
                &path("bad.png"),
            ],
            "has no parameters",
        ),
        (
            vec![
                "surface",
                "tests/data/icosahedron.off",
                "--scheme",
                "loop",
                "--param",
                "sigma=5",
                "-o",
                &path("bad.png"),
            ],
            "loop weights w = 0.375, sigma = 5: at a vertex of valence 5",
        ),
        (
            vec![
                "surface",
                "tests/data/icosahedron.off",
                "--scheme",
                "loop",
                "--param",
                "beta=0.1",
                "-o",
                &path("bad.png"),
            ],
            "`beta` is not a parameter of loop: the parameters are `w`, `sigma`",
        ),
        (
            vec!["surface", "tests/data/torus12.obj", "--scheme", "butterfly", "-o", &path("bad.png")],
            "invalid value 'butterfly' for '--scheme <SCHEME>'",
        ),
        (
            vec!["surface", "tests/data/torus12.obj", "--scheme", "loop", "-o", &path("bad.png")],
            "face 0 has 4 vertices: loop subdivides triangle meshes; triangulate the faces first",
        ),
        (
            vec!["surface", "tests/data/torus12.obj", "--scheme", "doo-sabin", "--depth", "30", "-o", &path("bad.png")],
            "would have about",
        ),
    ] {
        let (code, _, err) = bcifs(&args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(err.contains(expected), "{args:?}: {err}");
        assert!(!dir.join("bad.png").exists(), "no output after an error");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `analyze dimension`: the similarity dimension where the maps are
/// similarities (Koch ln 4/ln 3, the Sierpinski gasket ln 3/ln 2, Lévy 2),
/// none otherwise; box counting within 0.03 of the known dimension on
/// Koch, the gasket, a smooth curve (1) and a surface patch (2). Lévy's
/// box count converges too slowly at these scales (its boundary has
/// dimension 1.93): only its bound is checked.
#[test]
fn dimensions_of_shipped_attractors() {
    let dir = scratch("dim");
    let (_, gasket, _) = bcifs(&["show", "sierpinski-control"]);
    let gasket_file = dir.join("gasket.toml");
    std::fs::write(&gasket_file, gasket).unwrap();
    let cases: [(&str, Option<f64>, Option<f64>); 5] = [
        ("koch", Some(4f64.ln() / 3f64.ln()), Some(4f64.ln() / 3f64.ln())),
        (gasket_file.to_str().unwrap(), Some(3f64.ln() / 2f64.ln()), Some(3f64.ln() / 2f64.ln())),
        ("levy", None, Some(2.0)),
        ("corner_cutting", Some(1.0), None),
        ("doo_sabin_quad", Some(2.0), None),
    ];
    for (name, boxes, similarity) in cases {
        let (code, out, err) = bcifs(&["analyze", "dimension", name, "--json"]);
        assert_eq!(code, 0, "{name}: {err}");
        let v = json(&out);
        let measured = v["box_dimension"].as_f64().unwrap();
        match boxes {
            Some(d) => assert!((measured - d).abs() < 0.03, "{name}: box dimension {measured}, expected {d}"),
            None => assert!(measured > 1.8 && measured <= 2.0, "{name}: box dimension {measured}"),
        }
        assert!(v["fit"]["r2"].as_f64().unwrap() > 0.99, "{name}");
        match similarity {
            Some(d) => {
                let s = v["similarity_dimension"].as_f64().unwrap();
                assert!((s - d).abs() < 1e-9, "{name}: similarity dimension {s}, expected {d}");
            }
            None => assert!(v["similarity_dimension"].is_null(), "{name}"),
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Mauldin–Williams on a graph-directed system of similarities: states A
/// and B with A → A (ratio 1/2), A → B (1/4), B → A (1/2), B → B (1/3). The
/// dimension solves ρ([[2^-s, 4^-s], [2^-s, 3^-s]]) = 1, i.e.
/// (1 − 2^-s)(1 − 3^-s) = 8^-s.
#[test]
fn mauldin_williams_dimension_of_a_graph_directed_system() {
    // x ↦ r x + t as the barycentric matrix of the triangle (0,0), (1,0), (0,1):
    // columns are the barycentric coordinates of t, r e1 + t, r e2 + t.
    let map = |r: f64, tx: f64, ty: f64| {
        let bary = |x: f64, y: f64| [1.0 - x - y, x, y];
        let cols = [bary(tx, ty), bary(r + tx, ty), bary(tx, r + ty)];
        [0, 1, 2].map(|i| [cols[0][i], cols[1][i], cols[2][i]])
    };
    let mut b = bcifs::Design::builder("gd");
    b.state("A", 3, bcifs::CellKind::Free).state("B", 3, bcifs::CellKind::Free);
    b.matrix("AA", "A", "A", map(0.5, 0.0, 0.0))
        .matrix("AB", "A", "B", map(0.25, 0.5, 0.5))
        .matrix("BA", "B", "A", map(0.5, 0.5, 0.0))
        .matrix("BB", "B", "B", map(1.0 / 3.0, 0.0, 0.6));
    b.model(bcifs::Model::new("A", vec![vec![0.0, 0.0], vec![1.0, 0.0], vec![0.0, 1.0]]));
    let design = b.build().unwrap();
    let instance = bcifs::instantiate(&design, &[]).unwrap();
    let root = instance.automaton.state_id("A").unwrap();
    let control = [0.0, 1.0, 0.0, 0.0, 0.0, 1.0];
    let s = bcifs::analysis::similarity_dimension(&instance.automaton, root, &control, 2).unwrap();
    let f = |s: f64| (1.0 - 2f64.powf(-s)) * (1.0 - 3f64.powf(-s)) - 8f64.powf(-s);
    assert!(f(s).abs() < 1e-12, "s = {s}: residual {}", f(s));
    assert!(s > 0.5 && s < 1.0, "{s}");
}

/// `analyze curve` on the corner cutting against Sokolov et al. 2010 §4's closed
/// forms, at points drawn over the convergence domain: eigenvalues
/// (1, a, 1 − a − b) and (1, b, 1 − a − b); in case 1 (1 − a − b above |a|
/// and |b|) region 1 with angle 0 exactly when α1 and β1 have the same sign,
/// else a cusp (π); case 3 regions 4/5 by the sign of 1 − a − b; the
/// divergent point of the erratum; a degenerate line.
#[test]
fn curve_query_matches_the_closed_forms() {
    let query = |a: f64, b: f64| {
        let (code, out, err) = bcifs(&[
            "analyze",
            "curve",
            "corner_cutting",
            "--param",
            &format!("a={a}"),
            "--param",
            &format!("b={b}"),
            "--json",
        ]);
        assert_eq!(code, 0, "{err}");
        json(&out)
    };
    let mut state = 7u64;
    let mut r = || {
        state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut seen = std::collections::BTreeSet::new();
    for _ in 0..40 {
        let (a, b) = (-0.4 + 1.2 * r(), -0.4 + 1.2 * r());
        let c = 1.0 - a - b;
        let v = query(a, b);
        let mut e0: Vec<f64> = v["eigenvalues"]["T0"].as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect();
        let mut e1: Vec<f64> = v["eigenvalues"]["T1"].as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect();
        let mut x0 = vec![1.0, a, c];
        let mut x1 = vec![1.0, b, c];
        for e in [&mut e0, &mut e1, &mut x0, &mut x1] {
            e.sort_by(f64::total_cmp);
        }
        for (got, want) in e0.iter().zip(&x0).chain(e1.iter().zip(&x1)) {
            assert!((got - want).abs() < 1e-9, "a = {a}, b = {b}: {e0:?} {e1:?}");
        }
        let region = v["region"].as_str().map(str::to_string);
        if v["converges"] != true {
            continue;
        }
        if c > a.abs() + 1e-6 && c > b.abs() + 1e-6 {
            let alpha1 = -b * (a + b - 1.0) / ((2.0 * a + b - 1.0) * (a + b));
            let beta1 = -a * (a + b - 1.0) / ((a + 2.0 * b - 1.0) * (a + b));
            let angle = v["junction_angle_deg"].as_f64().unwrap();
            if alpha1 * beta1 > 0.0 {
                assert_eq!(region.as_deref(), Some("1"), "a = {a}, b = {b}");
                assert!(angle < 1e-4, "a = {a}, b = {b}: {angle}");
            } else {
                assert!(matches!(region.as_deref(), Some("2" | "2'")), "a = {a}, b = {b}: {region:?}");
                assert!((angle - 180.0).abs() < 1e-4, "a = {a}, b = {b}: {angle}");
            }
            assert_eq!(v["c1_necessary"], true);
        } else if c.abs() + 1e-6 < a.abs() && c.abs() + 1e-6 < b.abs() && a > 0.0 && b > 0.0 {
            assert_eq!(region.as_deref(), Some(if c < 0.0 { "5" } else { "4" }), "a = {a}, b = {b}");
        }
        if let Some(r) = region {
            seen.insert(r);
        }
    }
    assert!(seen.len() >= 4, "regions met: {seen:?}");
    let v = query(-0.9, 0.95);
    assert_eq!(
        (v["region"].as_str(), v["converges"].as_bool(), v["per_matrix_condition"].as_bool()),
        (Some("divergent"), Some(false), Some(true))
    );
    assert_eq!(query(0.0, 0.3)["region"], "degenerate");
    assert_eq!(query(0.3, 0.7)["region"], "degenerate");
}

/// `analyze curve --map`: the raw grid as CSV; over the corner cutting's
/// plane it has every region of Fig. 8, each pixel's region is the point
/// query's, and the PNG maps are written.
#[test]
fn curve_maps_cover_the_regions() {
    let dir = scratch("cmap");
    let csv = dir.join("r.csv");
    let (code, _, err) = bcifs(&[
        "analyze",
        "curve",
        "corner_cutting",
        "--map",
        "regions",
        "--x",
        "a=-0.5:1",
        "--y",
        "b=-0.5:1",
        "--size",
        "24",
        "-o",
        csv.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let text = std::fs::read_to_string(&csv).unwrap();
    let rows: Vec<Vec<&str>> = text.lines().skip(1).map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 24 * 24);
    let regions: std::collections::BTreeSet<&str> = rows.iter().map(|r| r[4]).collect();
    for r in ["1", "2", "2'", "3", "3'", "4", "5"] {
        assert!(regions.contains(r), "region {r} missing: {regions:?}");
    }
    for row in rows.iter().step_by(37) {
        if row[2] != "converges" {
            continue;
        }
        let (code, out, _) = bcifs(&[
            "analyze",
            "curve",
            "corner_cutting",
            "--param",
            &format!("a={}", row[0]),
            "--param",
            &format!("b={}", row[1]),
            "--json",
        ]);
        assert_eq!(code, 0);
        let v = json(&out);
        if v["converges"] == true {
            assert_eq!(v["region"].as_str().unwrap_or(""), row[4], "at {row:?}");
        }
    }
    // A point given with --param is marked; half a point is an error.
    let marked = dir.join("marked.png");
    let base = [
        "analyze",
        "curve",
        "corner_cutting",
        "--map",
        "regions",
        "--x",
        "a=-0.5:1",
        "--y",
        "b=-0.5:1",
        "--size",
        "16",
    ];
    let mut args = base.to_vec();
    args.extend(["--param", "a=0.25", "--param", "b=0.25", "-o", marked.to_str().unwrap()]);
    assert_eq!(bcifs(&args).0, 0);
    let mut args = base.to_vec();
    args.extend(["--param", "a=0.25", "-o", marked.to_str().unwrap()]);
    let (code, _, err) = bcifs(&args);
    assert_eq!(code, 2);
    assert!(err.contains("give both a and b"), "{err}");
    for kind in ["roughness", "smooth"] {
        let png = dir.join(format!("{kind}.png"));
        let (code, _, err) = bcifs(&[
            "analyze",
            "curve",
            "corner_cutting",
            "--map",
            kind,
            "--x",
            "a=-0.5:1",
            "--y",
            "b=-0.5:1",
            "--size",
            "16",
            "-o",
            png.to_str().unwrap(),
        ]);
        assert_eq!(code, 0, "{err}");
        assert!(png.metadata().unwrap().len() > 0);
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Sokolov et al. 2010 §5: blending functions. They sum to 1; at Chaikin (a = b = 1/4)
/// they are the quadratic B-spline basis and u(t) is affine (linear
/// precision); at the paper's a = 1/20, b = 1/8 (Gregory region) F is
/// singular in t (its steepest chord grows with the depth) but not in u
/// (bounded), and u increases. `analyze blend` draws the three panels.
#[test]
fn blending_functions_and_the_non_singular_parameterization() {
    use bcifs::analysis::blending;
    let halves = |a: f64, b: f64| {
        let design = bcifs::builtin_design("corner_cutting").unwrap();
        let inst = bcifs::instantiate(&design, &[("a".to_string(), a), ("b".to_string(), b)]).unwrap();
        let root = inst.automaton.state_id("e").or_else(|| inst.automaton.states().next().map(|(i, _)| i)).unwrap();
        let arrows = inst.automaton.outgoing(root, bcifs::ArrowKind::Subdivision);
        (inst.automaton.arrow(arrows[0]).matrix.clone(), inst.automaton.arrow(arrows[1]).matrix.clone())
    };
    let (t0, t1) = halves(0.25, 0.25);
    let b = blending(&t0, &t1, 8).unwrap();
    for (t, f) in b.t.iter().zip(&b.f) {
        let basis = [(1.0 - t) * (1.0 - t) / 2.0, 0.5 + t - t * t, t * t / 2.0];
        for i in 0..3 {
            assert!((f[i] - basis[i]).abs() < 1e-12, "t = {t}: {f:?}");
        }
    }
    for (t, u) in b.t.iter().zip(&b.u) {
        assert!((u - (0.25 + t / 2.0)).abs() < 1e-12, "Chaikin's u is affine: u({t}) = {u}");
    }
    let (t0, t1) = halves(1.0 / 20.0, 1.0 / 8.0);
    let steepest = |depth: usize| {
        let b = blending(&t0, &t1, depth).unwrap();
        assert!(b.f.iter().all(|f| (f.iter().sum::<f64>() - 1.0).abs() < 1e-12));
        assert!(b.u.windows(2).all(|w| w[1] > w[0]), "u increases");
        let slope = |xs: &[f64]| {
            (0..b.f.len() - 1)
                .flat_map(|j| (0..3).map(move |i| (j, i)))
                .map(|(j, i)| ((b.f[j + 1][i] - b.f[j][i]) / (xs[j + 1] - xs[j])).abs())
                .fold(0.0, f64::max)
        };
        (slope(&b.t), slope(&b.u))
    };
    let ((t8, u8), (t12, u12)) = (steepest(8), steepest(12));
    assert!(t12 > 2.0 * t8, "F is singular in t: {t8} → {t12}");
    assert!(u12 < 1.2 * u8, "F is Lipschitz in u: {u8} → {u12}");
    let png = std::env::temp_dir().join(format!("bcifs-blend-{}.png", std::process::id()));
    let (code, out, err) = bcifs(&[
        "analyze",
        "blend",
        "corner_cutting",
        "--param",
        "a=1/20",
        "--param",
        "b=1/8",
        "-o",
        png.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("u(t) increasing"), "{out}");
    std::fs::remove_file(&png).unwrap();
}

/// `render --control` writes the model's control net: the closed control
/// polygon of the corner cutting (one two-vertex `l` per side), the 8 × 8
/// torus grid as a closed quad mesh facing outwards.
#[test]
fn control_nets_are_written() {
    let dir = scratch("control");
    let curve = dir.join("c.obj");
    let (code, _, err) = bcifs(&["render", "corner_cutting", "--control", "-o", curve.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    let text = std::fs::read_to_string(&curve).unwrap();
    let design = bcifs::builtin_design("corner_cutting").unwrap();
    let n = design.model().unwrap().points.len();
    assert_eq!(text.lines().filter(|l| l.starts_with("v ")).count(), n);
    assert_eq!(text.lines().filter(|l| l.starts_with("l ")).count(), n, "closed: a segment per side");
    let torus = dir.join("t.obj");
    let (code, _, err) = bcifs(&["render", "doo_sabin_torus", "--control", "--up", "z", "-o", torus.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    let mesh = bcifs::mesh::read_mesh(&torus).unwrap();
    assert_eq!(mesh.face_count(), 64);
    assert!(mesh.is_closed());
    assert!(mesh.signed_volume() > 0.0, "outwards");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `bcifs surface --print`: a Blender export as a generated automaton that
/// `solve` and `check` read unchanged (Doo-Sabin's quad weights free, every
/// constraint at zero), that `render` evaluates to the closed, outward limit
/// surface, and that `--print` refuses to write as a mesh.
#[test]
fn a_users_mesh_prints_as_an_automaton_that_solves_checks_and_renders() {
    let dir = scratch("surface-print");
    let path = |f: &str| dir.join(f).to_str().unwrap().to_string();
    let args = ["surface", "tests/data/torus12.obj", "--scheme", "doo-sabin", "--print", "-o"];
    let (code, _, err) = bcifs(&[&args[..], &[&path("torus.toml")]].concat());
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("constraints"), "{err}");
    let (code, out, err) = bcifs(&["solve", &path("torus.toml")]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("3 free parameters: alpha, beta, gamma"), "{}", &out[..out.len().min(300)]);
    let (code, out, err) = bcifs(&["check", &path("torus.toml"), "--param", "alpha=0.6"]);
    assert_eq!(code, 0, "{err}{out}");
    assert!(out.trim_end().ends_with("ok") && !out.contains("FAIL"), "{out}");
    let (code, _, err) = bcifs(&["render", &path("torus.toml"), "--depth", "2", "-o", &path("torus.obj")]);
    assert_eq!(code, 0, "{err}");
    let limit = bcifs::mesh::read_mesh(&dir.join("torus.obj")).unwrap();
    assert!(limit.is_closed(), "the welded limit surface is closed (read back: manifold, consistently oriented)");
    assert!(limit.signed_volume() > 0.0, "and faces outwards");
    // Without -o the automaton goes to standard output; a mesh extension is refused.
    let (code, out, _) = bcifs(&["surface", "tests/data/cube.off", "--scheme", "loop", "--triangulate", "--print"]);
    assert_eq!(code, 0);
    assert!(out.contains("name = \"mesh_loop\"") && out.contains("[constraints]"));
    let (code, _, err) = bcifs(&[&args[..], &[&path("torus.obj")]].concat());
    assert_ne!(code, 0);
    assert!(err.contains("-o FILE.toml"), "{err}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `bcifs surface … -o X.svg`: the limit surface as a vector picture, one
/// shaded polygon per face, painted far to near.
#[test]
fn surface_pictures_as_svg() {
    let dir = scratch("surface-svg");
    let out = dir.join("cube.svg");
    let (code, _, err) = bcifs(&[
        "surface",
        "tests/data/cube.off",
        "--scheme",
        "catmull-clark",
        "--depth",
        "2",
        "--size",
        "300x200",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.starts_with("<svg") && text.contains("width=\"300\" height=\"200\""));
    // The cube after two steps: 6 × 16 quads, each a polygon of four points.
    assert_eq!(text.matches("<polygon").count(), 96);
    let shades: std::collections::HashSet<&str> =
        text.match_indices("fill=\"#").map(|(i, _)| &text[i + 6..i + 13]).collect();
    assert!(shades.len() > 3, "faces turned differently are shaded differently: {shades:?}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A reader that closes the pipe early (`bcifs surface … --print | head`)
/// is the reader's choice: no panic, exit code 0, nothing on stderr.
#[test]
fn printed_automata_survive_a_closed_pipe() {
    use std::io::Read;
    use std::process::{Command, Stdio};
    let mut child = Command::new(env!("CARGO_BIN_EXE_bcifs"))
        .args(["surface", "tests/data/suzanne.obj", "--scheme", "catmull-clark", "--print"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut head = [0u8; 64];
    child.stdout.take().unwrap().read_exact(&mut head).unwrap();
    // Dropping the pipe's read end closes it before the 2 MB automaton is written.
    let out = child.wait_with_output().unwrap();
    assert!(head.starts_with(b"# Generated by bcifs"));
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(!String::from_utf8_lossy(&out.stderr).contains("panicked"));
}

/// Issue 23, item 6: a curve picture stops subdividing where its segments
/// are below a pixel (and says so): depths 60 and 1000 finish at once with
/// the picture of that depth; a sample count that cannot finish is refused
/// with the time it would take, before any work.
#[test]
fn pictures_that_cannot_finish_are_bounded() {
    let dir = scratch("bounded");
    let file = |name: &str| dir.join(name).display().to_string();
    let started = std::time::Instant::now();
    let (code, _, err) = bcifs(&["render", "levy", "--depth", "60", "-o", &file("deep.png")]);
    assert_eq!(code, 0, "{err}");
    let enough: usize = err
        .split("drawn at depth ")
        .nth(1)
        .and_then(|t| t.split(',').next())
        .and_then(|k| k.parse().ok())
        .unwrap_or_else(|| panic!("the picture's depth is said: {err}"));
    // 800 px over a curve of 2^(k/2) segment lengths: below a pixel from depth ~18.
    assert!((14..=22).contains(&enough), "{enough}");
    let (code, _, err) = bcifs(&["render", "levy", "--depth", "1000", "-o", &file("deeper.png")]);
    assert_eq!(code, 0, "{err}");
    let (code, _, err) = bcifs(&["render", "levy", "--depth", &enough.to_string(), "-o", &file("enough.png")]);
    assert_eq!(code, 0, "{err}");
    assert!(!err.contains("drawn at depth"), "the depth asked is enough: {err}");
    // The same pixels (the files' text chunks record the depth asked).
    let read = |n: &str| image::open(dir.join(n)).unwrap().to_rgb8();
    assert_eq!(read("deep.png"), read("enough.png"));
    assert_eq!(read("deeper.png"), read("enough.png"));
    // One level shallower, some segment is still longer than a pixel: another picture.
    let (code, _, _) = bcifs(&["render", "levy", "--depth", &(enough - 1).to_string(), "-o", &file("short.png")]);
    assert_eq!(code, 0);
    assert_ne!(read("short.png"), read("enough.png"));
    for out in ["y.png", "y.obj", "y.svg"] {
        let (code, _, err) = bcifs(&["render", "fern", "--random", "18446744073709551615", "-o", &file(out)]);
        assert_eq!(code, 2, "{out}: {err}");
        assert!(err.contains("years at 100 million samples a second"), "{out}: {err}");
        assert!(!dir.join(out).exists());
    }
    assert!(started.elapsed().as_secs() < 60, "bounded work");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Issue 23, item 11: the similarity dimension says whether it is the
/// Hausdorff dimension. Three maps of ratio 1/2 onto a segment (the
/// attractor is the segment, dimension 1) have similarity dimension log₂ 3
/// exceeding 1: the open set condition fails and the figure is an upper bound; the
/// Cantor set and the gasket satisfy it (their images of the control
/// simplex meet only on boundaries); the Lévy curve's test is not known.
#[test]
fn open_set_condition_is_stated() {
    let dir = scratch("osc");
    let system = |name: &str, maps: &[&str]| {
        let mut text = format!("name = \"{name}\"\n[[state]]\nname = \"s\"\ndim = 2\nkind = \"free\"\n");
        for (i, m) in maps.iter().enumerate() {
            text += &format!("[[arrow]]\nname = \"T{i}\"\nfrom = \"s\"\nto = \"s\"\nmatrix = {m}\n");
        }
        text += "[model]\nroot = \"s\"\npoints = [[0, 0], [1, 0]]\n";
        let path = dir.join(format!("{name}.toml"));
        std::fs::write(&path, text).unwrap();
        path.display().to_string()
    };
    let overlap = system(
        "overlap",
        &[r#"[["1", "1/2"], [0, "1/2"]]"#, r#"[["1/2", 0], ["1/2", "1"]]"#, r#"[["3/4", "1/4"], ["1/4", "3/4"]]"#],
    );
    let cantor = system("cantor", &[r#"[["1", "2/3"], [0, "1/3"]]"#, r#"[["1/3", 0], ["2/3", "1"]]"#]);
    for (file, holds, dimension) in [
        (overlap.as_str(), Some(false), 3f64.log2()),
        (cantor.as_str(), Some(true), 2f64.ln() / 3f64.ln()),
        ("gasket", Some(true), 3f64.log2()),
        ("levy", None, 2.0),
    ] {
        let (code, out, err) = bcifs(&["analyze", "dimension", file, "--json"]);
        assert_eq!(code, 0, "{file}: {err}");
        let v = json(&out);
        assert!((v["similarity_dimension"].as_f64().unwrap() - dimension).abs() < 1e-9, "{file}");
        assert_eq!(v["open_set_condition"].as_bool(), holds, "{file}: {}", v["open_set_reason"]);
        let (_, text, _) = bcifs(&["analyze", "dimension", file]);
        let bound = text.contains("only an upper bound of the Hausdorff dimension");
        assert_eq!(bound, holds != Some(true), "{file}: {text}");
    }
    // Issue 23, item 8: two control points in 3D (the ball of an IFS needs d + 1): no panic.
    let cantor3 = dir.join("cantor3.toml");
    std::fs::write(
        &cantor3,
        std::fs::read_to_string(&cantor).unwrap().replace("[[0, 0], [1, 0]]", "[[0, 0, 0], [1, 0, 1]]"),
    )
    .unwrap();
    let (code, out, err) = bcifs(&["analyze", "dimension", &cantor3.display().to_string(), "--json"]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(json(&out)["open_set_condition"], true);
    // The overlapping system's attractor is the segment: box counting sees 1, not 1.585.
    let (_, out, _) = bcifs(&["analyze", "dimension", &overlap, "--json"]);
    assert!((json(&out)["box_dimension"].as_f64().unwrap() - 1.0).abs() < 0.03);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Issue 23, item 9: `--drop` holds for the chaos game too. The gasket
/// without T0 is the IFS of the two maps halving towards corners 1 and 2:
/// its attractor is the side between them, where every sample lies; an
/// arrow that does not exist is refused.
#[test]
fn the_chaos_game_drops_arrows() {
    let path = std::env::temp_dir().join(format!("bcifs-drop-{}.obj", std::process::id()));
    let p = path.display().to_string();
    let (code, _, err) = bcifs(&["render", "gasket", "--random", "10000", "--drop", "T0", "--up", "z", "-o", &p]);
    assert_eq!(code, 0, "{err}");
    let text = std::fs::read_to_string(&path).unwrap();
    let points: Vec<Vec<f64>> = text
        .lines()
        .filter_map(|l| l.strip_prefix("v "))
        .map(|l| l.split_whitespace().map(|x| x.parse().unwrap()).collect())
        .collect();
    assert_eq!(points.len(), 10_000);
    // The side from (1, 0) to (1/2, √3/2): x + y/√3 = 1.
    for q in &points {
        assert!((q[0] + q[1] / 3f64.sqrt() - 1.0).abs() < 1e-9, "{q:?} is off the side");
    }
    let (code, _, err) = bcifs(&["render", "gasket", "--random", "10000", "--drop", "T7", "-o", &p]);
    assert_eq!(code, 2);
    assert!(err.contains("no subdivision arrow named `T7`"), "{err}");
    std::fs::remove_file(&path).unwrap();
}

/// Issue 23, item 14: an option that does nothing for the output asked says
/// so; a parameter given twice, or varied on both axes of a map, is refused.
#[test]
fn options_that_do_nothing_say_so() {
    let dir = scratch("idle");
    let at = |name: &str| dir.join(name).display().to_string();
    for (args, warning) in [
        (
            vec!["render", "fern", "--random", "1000", "--palette", "fire", "-o", &at("a.off")],
            "the .off file ignores them",
        ),
        (vec!["render", "fern", "--random", "1000", "--blur", "2", "-o", &at("b.obj")], "the .obj file ignores them"),
        (vec!["render", "levy", "--depth", "6", "--uv", "-o", &at("c.obj")], "this curve or point set has none"),
        (vec!["render", "levy", "--depth", "6", "--precision", "6", "-o", &at("d.png")], "the .png output ignores it"),
    ] {
        let (code, _, err) = bcifs(&args);
        assert_eq!(code, 0, "{args:?}: {err}");
        assert!(err.contains(warning), "{args:?}: {err}");
    }
    let (code, _, err) = bcifs(&["check", "corner_cutting", "--param", "a=0.1", "--param", "a=0.2"]);
    assert_eq!(code, 2);
    assert!(err.contains("`a` is given twice"), "{err}");
    let (code, _, err) =
        bcifs(&["analyze", "map", "corner_cutting", "--x", "a=0:1", "--y", "a=0:1", "--size", "8", "-o", &at("m.png")]);
    assert_eq!(code, 2);
    assert!(err.contains("both vary `a`"), "{err}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Issue 23, item 15: messages that say what is true. Parameters of 1e308
/// leave no JSR bounds, and the verdict says so rather than "undecided";
/// `analyze curve` prints numbers, not Rust debug values; 1e308 control
/// points are refused with their coordinate; a curve too large for the
/// solver is not an internal error.
#[test]
fn messages_say_what_is_true() {
    let (_, out, _) = bcifs(&["check", "corner_cutting", "--param", "a=1e308", "--param", "b=1e308"]);
    assert!(out.contains("JSR: not defined") && out.contains("convergence: not decided (no JSR bounds"), "{out}");
    assert!(!out.contains("straddle"), "{out}");
    let (code, out, err) = bcifs(&["analyze", "curve", "corner_cutting", "--param", "a=0", "--param", "b=0"]);
    assert_eq!(code, 0, "{err}");
    assert!(!out.contains("None") && !out.contains("Some(") && !out.contains("not rational"), "{out}");
    let (_, out, _) = bcifs(&["analyze", "curve", "corner_cutting", "--param", "a=0.2", "--param", "b=0.3"]);
    assert!(out.contains("T0: eigenvalues 1.000000, 0.500000, 0.200000; sub-dominant 0.500000"), "{out}");
    let (code, _, err) = bcifs(&["new", "curve", "--points", "100000"]);
    assert_eq!(code, 2);
    assert!(err.contains("at most 20000") && !err.contains("internal"), "{err}");
    let dir = scratch("huge");
    let huge = dir.join("huge.toml");
    let (_, text, _) = bcifs(&["show", "corner_cutting"]);
    let model = text.find("points = ").map(|i| &text[i..]).unwrap();
    let line = &model[..model.find('\n').unwrap()];
    std::fs::write(&huge, text.replace(line, "points = [[0, 0], [1e308, 0], [2, 1]]")).unwrap();
    let (code, _, err) =
        bcifs(&["render", &huge.display().to_string(), "-o", &dir.join("h.png").display().to_string()]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("coordinate 1e308"), "{err}");
    assert!(!dir.join("h.png").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Issue 23, items 19 and 20: a mesh file is Y-up, so its picture stands on
/// its feet: a box four times taller along the file's y than wide is drawn
/// taller than wide; `surface` refuses a file over `--max-output-gib`; the
/// summary counts faces (quads and triangles), not "quads".
#[test]
fn mesh_pictures_stand_up_and_sizes_are_checked() {
    let dir = scratch("upright");
    let mut obj = String::new();
    for &(x, y, z) in &[(0, 0, 0), (1, 0, 0), (1, 0, 1), (0, 0, 1), (0, 4, 0), (1, 4, 0), (1, 4, 1), (0, 4, 1)] {
        obj += &format!("v {x} {y} {z}\n");
    }
    // Outward faces of the box (counter-clockwise seen from outside).
    obj += "f 1 2 3 4\nf 5 8 7 6\nf 1 5 6 2\nf 2 6 7 3\nf 3 7 8 4\nf 4 8 5 1\n";
    let tall = dir.join("tall.obj");
    std::fs::write(&tall, obj).unwrap();
    let png = dir.join("tall.png");
    let (code, _, err) = bcifs(&[
        "surface",
        &tall.display().to_string(),
        "--scheme",
        "catmull-clark",
        "--depth",
        "2",
        "--net",
        "-o",
        &png.display().to_string(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("faces →"), "{err}");
    let img = image::open(&png).unwrap().to_rgb8();
    let ink: Vec<(u32, u32)> =
        img.enumerate_pixels().filter(|(_, _, p)| p.0.iter().any(|&c| c < 250)).map(|(x, y, _)| (x, y)).collect();
    let span = |f: &dyn Fn(&(u32, u32)) -> u32| ink.iter().map(f).max().unwrap() - ink.iter().map(f).min().unwrap();
    let (w, h) = (span(&|p| p.0), span(&|p| p.1));
    assert!(h > 2 * w, "the box stands: {w}×{h} pixels of ink");
    let (code, _, err) = bcifs(&[
        "surface",
        &tall.display().to_string(),
        "--scheme",
        "catmull-clark",
        "--depth",
        "14",
        "--max-output-gib",
        "1",
        "-o",
        &dir.join("big.obj").display().to_string(),
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("over the output limit of 1.0 GiB") && err.contains("hint: --max-output-gib"), "{err}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Issue 24, item 4: a mesh's generated automaton keeps the file's Y-up
/// axes (`up = "y"` in its model), so rendering it writes the surface in
/// the same axes as subdividing the mesh (Suzanne lay on her back); the
/// vertices of both files are the same points.
#[test]
fn a_mesh_automaton_renders_in_the_mesh_files_axes() {
    let dir = scratch("mesh-axes");
    let at = |name: &str| dir.join(name).display().to_string();
    let (code, _, err) =
        bcifs(&["surface", "tests/data/suzanne.obj", "--scheme", "catmull-clark", "--print", "-o", &at("s.toml")]);
    assert_eq!(code, 0, "{err}");
    assert!(std::fs::read_to_string(dir.join("s.toml")).unwrap().contains("up = \"y\""));
    let (code, _, err) = bcifs(&["render", &at("s.toml"), "--depth", "2", "-o", &at("rendered.obj")]);
    assert_eq!(code, 0, "{err}");
    let (code, _, err) = bcifs(&[
        "surface",
        "tests/data/suzanne.obj",
        "--scheme",
        "catmull-clark",
        "--depth",
        "2",
        "-o",
        &at("mesh.obj"),
    ]);
    assert_eq!(code, 0, "{err}");
    let points = |name: &str| -> Vec<[f64; 3]> {
        let mut v: Vec<[f64; 3]> = std::fs::read_to_string(dir.join(name))
            .unwrap()
            .lines()
            .filter_map(|l| l.strip_prefix("v "))
            .map(|l| {
                let x: Vec<f64> = l.split_whitespace().map(|t| t.parse().unwrap()).collect();
                [x[0], x[1], x[2]]
            })
            .collect();
        v.sort_by(|a, b| a[0].total_cmp(&b[0]));
        v
    };
    let (rendered, mesh) = (points("rendered.obj"), points("mesh.obj"));
    assert!(!mesh.is_empty());
    // Every point of one file is within 1e-9 of a point of the other (welding may count them differently).
    let near = |p: &[f64; 3], set: &[[f64; 3]]| {
        let from = set.partition_point(|q| q[0] < p[0] - 1e-9);
        set[from..].iter().take_while(|q| q[0] <= p[0] + 1e-9).any(|q| (0..3).all(|k| (q[k] - p[k]).abs() <= 1e-9))
    };
    let lost =
        rendered.iter().filter(|p| !near(p, &mesh)).count() + mesh.iter().filter(|p| !near(p, &rendered)).count();
    assert_eq!(lost, 0, "points of one file missing from the other (the same surface in the same axes)");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The first run: `bcifs gallery` says what it will write and how big before
/// it starts, stays under 100 MB by default, captions every entry with what
/// it shows, the paper and the command that makes it, and ends with the
/// path of `index.html`.
#[test]
fn the_gallery_announces_itself_stays_small_and_captions_every_entry() {
    let dir = std::env::temp_dir().join(format!("bcifs-gallery-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let (code, out, err) = bcifs(&["gallery", &dir.display().to_string()]);
    assert_eq!(code, 0, "{err}");
    let announced = err.lines().next().unwrap_or_default();
    assert!(announced.starts_with("bcifs gallery: ") && announced.contains("MB"), "{announced}");
    let last = out.lines().last().unwrap_or_default();
    assert!(last.contains(&format!("→ {} (", dir.join("index.html").display())), "{last}");
    let bytes: u64 = std::fs::read_dir(&dir).unwrap().flatten().map(|e| e.metadata().unwrap().len()).sum();
    assert!(bytes < 100_000_000, "the default gallery is {bytes} bytes");
    let said: f64 = announced.split("about ").nth(1).and_then(|s| s.split(' ').next()).unwrap().parse().unwrap();
    assert!((said * 1e6 / 2.0..said * 1e6 * 2.0).contains(&(bytes as f64)), "announced {said} MB, wrote {bytes} bytes");
    let index = std::fs::read_to_string(dir.join("index.html")).unwrap();
    let captions: Vec<&str> = index.split("<figcaption>").skip(1).collect();
    assert!(captions.len() > 50, "{} entries", captions.len());
    for c in &captions {
        assert!(c.contains("<i>From:</i>") && c.contains("<code>"), "{c}");
    }
    // An entry's command makes its picture: the corner cutting's, run here, draws the same pixels.
    let code_of = |name: &str| {
        let c = captions.iter().find(|c| c.starts_with(&format!("<b>{name}</b>"))).unwrap();
        c.split("<code>").nth(1).unwrap().split("</code>").next().unwrap().to_string()
    };
    let command = code_of("corner_cutting");
    let args: Vec<String> = command
        .split(' ')
        .skip(1)
        .map(|a| a.replace("corner_cutting.png", &dir.join("again.png").display().to_string()))
        .collect();
    let (code, _, err) = bcifs(&args.iter().map(String::as_str).collect::<Vec<_>>());
    assert_eq!(code, 0, "{command}: {err}");
    let (a, b) = (
        image::open(dir.join("again.png")).unwrap().to_rgb8(),
        image::open(dir.join("corner_cutting.png")).unwrap().to_rgb8(),
    );
    assert_eq!(a, b, "`{command}` draws the gallery's picture");
    // The deterministic fern reads as a fern: inked about as much as its chaos-game picture (at
    // depth 6 it was a faint scatter, 1/10 of it), its geometry file's coarser depth said.
    let ink = |file: &str| {
        let img = image::open(dir.join(file)).unwrap().to_luma8();
        img.pixels().filter(|p| p.0[0] < 200).count() as f64 / img.pixels().len() as f64
    };
    let (fern, chaos) = (ink("fern.png"), ink("fern-chaos.png"));
    assert!(fern > 0.6 * chaos, "fern.png inks {fern:.3} of its pixels, its chaos game {chaos:.3}");
    assert!(code_of("fern").contains("--tolerance"), "{}", code_of("fern"));
    let fern_caption = captions.iter().find(|c| c.starts_with("<b>fern</b>")).unwrap();
    assert!(fern_caption.contains("fern.obj</a> (depth"), "{fern_caption}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// `-o` through a symbolic link writes the file it names (the link stays);
/// a link to a device writes the device and reports its errors (`/dev/full`:
/// no space) instead of replacing the link with a file; an output that is
/// an input is refused before any work; a path under a file says so.
#[cfg(unix)]
#[test]
fn outputs_go_through_links_and_never_over_an_input() {
    let dir = scratch("links");
    let s = |p: &std::path::Path| p.to_str().unwrap().to_string();
    let target = dir.join("target.png");
    std::fs::write(&target, b"old").unwrap();
    let link = dir.join("link.png");
    std::os::unix::fs::symlink("target.png", &link).unwrap();
    let (code, _, err) = bcifs(&["render", "koch", "--depth", "4", "-o", &s(&link)]);
    assert_eq!(code, 0, "{err}");
    assert!(std::fs::symlink_metadata(&link).unwrap().file_type().is_symlink(), "the link stays a link");
    assert!(std::fs::read(&target).unwrap().starts_with(b"\x89PNG"), "its target holds the picture");
    let full = dir.join("full.obj");
    std::os::unix::fs::symlink("/dev/full", &full).unwrap();
    let (code, _, err) = bcifs(&["render", "koch", "--depth", "4", "-o", &s(&full)]);
    assert_ne!(code, 0);
    assert!(err.contains("No space left on device"), "{err}");
    assert!(std::fs::symlink_metadata(&full).unwrap().file_type().is_symlink());
    let null = dir.join("null.obj");
    std::os::unix::fs::symlink("/dev/null", &null).unwrap();
    assert_eq!(bcifs(&["render", "koch", "--depth", "4", "-o", &s(&null)]).0, 0);
    use std::os::unix::fs::FileTypeExt as _;
    assert!(std::fs::metadata("/dev/null").unwrap().file_type().is_char_device(), "/dev/null is still a device");
    // An output that is an input: the same path, another spelling, a link to it.
    let design = dir.join("a.toml");
    let (_, text, _) = bcifs(&["scheme", "ifs", "koch", "--print"]);
    std::fs::write(&design, &text).unwrap();
    let again = dir.join("again.obj");
    std::os::unix::fs::symlink("a.toml", &again).unwrap();
    for output in [s(&design), format!("{}/./a.toml", s(&dir)), s(&again)] {
        let (code, _, err) = bcifs(&["render", &s(&design), "-o", &output]);
        assert_ne!(code, 0, "{output}");
        assert!(err.contains("is the input"), "{output}: {err}");
        assert_eq!(std::fs::read_to_string(&design).unwrap(), text, "the input is untouched");
    }
    let mesh = dir.join("cube.off");
    std::fs::copy("tests/data/cube.off", &mesh).unwrap();
    let (code, _, err) = bcifs(&["surface", &s(&mesh), "--scheme", "catmull-clark", "-o", &s(&mesh)]);
    assert!(code != 0 && err.contains("is the input"), "{err}");
    assert_eq!(std::fs::read(&mesh).unwrap(), std::fs::read("tests/data/cube.off").unwrap());
    let file = dir.join("f");
    std::fs::write(&file, b"").unwrap();
    let (_, _, err) = bcifs(&["render", "koch", "-o", &format!("{}/out.png", s(&file))]);
    assert!(err.contains("is a file, not a directory"), "{err}");
    // Nothing left behind: no temporary files beside the targets.
    let left: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".tmp"))
        .collect();
    assert!(left.is_empty(), "{left:?}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Reading a device as an automaton or a mesh is refused at once, with the reason.
#[test]
fn devices_are_not_read_until_memory_runs_out() {
    for args in [
        vec!["check", "/dev/zero"],
        vec!["render", "/dev/urandom", "-o", "/tmp/bcifs-never.png"],
        vec!["solve", "/dev/zero"],
    ] {
        let (code, _, err) = bcifs(&args);
        assert_ne!(code, 0, "{args:?}");
        assert!(err.contains("NUL byte"), "{args:?}: {err}");
    }
}

/// A picture of points stops at the depth whose points fill its pixels (64
/// a pixel): the gasket at depth 60 (3⁶⁰ points) is the picture at depth
/// 15, drawn in a moment, and says so; a shallow depth is kept.
#[test]
fn a_deep_picture_of_points_stops_where_its_points_fill_the_pixels() {
    let dir = scratch("deep-points");
    let deep = dir.join("deep.png");
    let at15 = dir.join("at15.png");
    let (code, _, err) =
        bcifs(&["render", "gasket", "--depth", "60", "--size", "200x200", "-o", deep.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    // 3¹³ = 1,594,323 points ≤ 64 · 200² = 2,560,000 < 3¹⁴.
    assert!(err.contains("drawn at depth 13") && err.contains("1594323 points"), "{err}");
    assert_eq!(bcifs(&["render", "gasket", "--depth", "13", "--size", "200x200", "-o", at15.to_str().unwrap()]).0, 0);
    let pixels = |p: &std::path::Path| image::open(p).unwrap().to_rgb8().into_raw();
    assert!(pixels(&deep) == pixels(&at15), "the same picture");
    let (_, _, err) = bcifs(&["render", "gasket", "--depth", "5", "--size", "200x200", "-o", at15.to_str().unwrap()]);
    assert!(!err.contains("drawn at depth"), "{err}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Coordinates of ±1e308 are finite, but their subdivision's sums and its
/// normals' squares are not: such a mesh is refused with its scale before
/// any file is written (it gave `v -inf -inf inf`, `vn 0 0 0`, exit 0).
#[test]
fn a_mesh_whose_sums_overflow_is_refused_with_its_scale() {
    let dir = scratch("huge-mesh");
    let mesh = dir.join("huge.obj");
    std::fs::write(
        &mesh,
        "v -1e308 -1e308 0\nv 1e308 -1e308 0\nv 1e308 1e308 0\nv -1e308 1e308 0\nv 0 0 1e308\n\
         f 4 3 2 1\nf 1 2 5\nf 2 3 5\nf 3 4 5\nf 4 1 5\n",
    )
    .unwrap();
    for scheme in ["catmull-clark", "loop", "doo-sabin"] {
        for ext in ["obj", "png", "glb", "stl"] {
            let out = dir.join(format!("out-{scheme}.{ext}"));
            let mut args = vec!["surface", mesh.to_str().unwrap(), "--scheme", scheme, "-o", out.to_str().unwrap()];
            if scheme == "loop" {
                args.push("--triangulate");
            }
            let (code, _, err) = bcifs(&args);
            assert_ne!(code, 0, "{scheme} .{ext}");
            assert!(err.contains("-1e308") && err.contains("1e150"), "{scheme} .{ext}: {err}");
            assert!(!out.exists(), "{scheme} .{ext}: nothing written");
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Entries of 1e16 sum to 1 exactly in the family, but not in floating
/// point: `check` says that rounding lost the sums (as `render` refuses to
/// evaluate them), not that the constraints fail; 1e308 prints no NaN; the
/// spectra come by decreasing modulus.
#[test]
fn check_says_when_rounding_loses_the_column_sums() {
    let (code, out, _) = bcifs(&["check", "corner_cutting", "--param", "a=1e16"]);
    assert_eq!(code, 1);
    assert!(out.contains("lost to rounding") && !out.contains("some constraints do not hold"), "{out}");
    assert!(out.contains("magnitude 1e16"), "{out}");
    let (code, out, _) = bcifs(&["check", "corner_cutting", "--param", "a=1e308", "--param", "b=-1e308"]);
    assert_eq!(code, 1);
    assert!(!out.contains("NaN") && !out.contains("inf"), "{out}");
    let (_, out, _) = bcifs(&["check", "corner_cutting", "--param", "a=0.1", "--param", "b=0.3", "--json"]);
    let report = json(&out);
    assert!(report["rounding"].is_null());
    for (arrow, spectrum) in report["spectra"].as_object().unwrap() {
        let moduli: Vec<f64> =
            spectrum.as_array().unwrap().iter().map(|l| l[0].as_f64().unwrap().hypot(l[1].as_f64().unwrap())).collect();
        assert!(moduli.windows(2).all(|w| w[0] >= w[1]), "{arrow}: {moduli:?}");
    }
}

/// Options that would be ignored are refused, and so is a picture of
/// nothing: `--control` with `--random`, a tension `nan`, every arrow
/// dropped, an automaton without arrows (each wrote something with exit 0).
#[test]
fn ignored_options_and_empty_attractors_are_refused() {
    let dir = scratch("ignored");
    let out = dir.join("x.png");
    let out = out.to_str().unwrap();
    let empty = dir.join("empty.toml");
    std::fs::write(
        &empty,
        "name = \"empty\"\n[[state]]\nname = \"s\"\ndim = 3\nkind = \"free\"\n[model]\nroot = \"s\"\npoints = [[0, 0], [1, 0], [0, 1]]\n",
    )
    .unwrap();
    for (args, says) in [
        (vec!["render", "gasket", "--control", "--random", "1000", "-o", out], "--random"),
        (vec!["scheme", "ifs", "ternary5", "--omega", "nan", "-o", out], "is neither"),
        (vec!["scheme", "ifs", "ternary5", "--omega", "Inf", "-o", out], "is neither"),
        (vec!["render", "gasket", "--drop", "T0", "--drop", "T1", "--drop", "T2", "-o", out], "dropped"),
        (vec!["render", empty.to_str().unwrap(), "-o", out], "has no subdivision arrow"),
    ] {
        let (code, _, err) = bcifs(&args);
        assert_ne!(code, 0, "{args:?}");
        assert!(err.contains(says), "{args:?}: {err}");
        assert!(!std::path::Path::new(out).exists(), "{args:?}: nothing written");
    }
    // Dropping some arrows still draws what is left.
    assert_eq!(bcifs(&["render", "gasket", "--drop", "T0", "-o", out]).0, 0);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A constraint stated 20,000 times is one constraint: the same scalar
/// equations as stated once (they grew memory with the square of the copies).
#[test]
fn a_constraint_stated_again_is_counted_once() {
    let dir = scratch("duplicates");
    let text = std::fs::read_to_string("automata/corner_cutting.toml").unwrap();
    let once = "adjacency = [\"T0 b1 = T1 b0\"]";
    assert!(text.contains(once));
    let many = text.replace(once, &format!("adjacency = [{}]", vec!["\"T0 b1 = T1 b0\""; 20_000].join(", ")));
    let file = dir.join("dup.toml");
    std::fs::write(&file, many).unwrap();
    let (code, dup, err) = bcifs(&["solve", file.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    let (_, single, _) = bcifs(&["solve", "corner_cutting"]);
    assert_eq!(dup, single, "the same family and the same count of scalar equations");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `solve` says what it was given: a scheme's automaton, every matrix given,
/// has constraints that hold identically (it said "0 scalar equations, rank 0"
/// as though there were none); counts agree in number with their nouns.
#[test]
fn solve_counts_what_holds_without_solving() {
    let dir = scratch("solve-counts");
    let file = dir.join("bicubic.toml");
    let (code, text, err) = bcifs(&["scheme", "ifs", "bicubic", "--print"]);
    assert_eq!(code, 0, "{err}");
    std::fs::write(&file, text).unwrap();
    let (code, out, err) = bcifs(&["solve", file.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    assert!(out.starts_with("bicubic: no free parameter"), "{out}");
    let summary = out.lines().nth(1).unwrap();
    assert!(summary.contains("hold whatever the parameters; nothing to solve"), "{summary}");
    assert!(!summary.contains(": all 0 "), "the constraints compare entries: {summary}");
    let (_, out, _) = bcifs(&["solve", "corner_cutting"]);
    assert!(out.starts_with("corner_cutting: 2 free parameters: a, b\n"), "{out}");
    assert!(out.contains("26 scalar equations, rank 20"), "{out}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// An interrupted gallery leaves its folder as it was: it is written in a
/// staging folder beside it, moved in at the end, removed when interrupted.
#[cfg(unix)]
#[test]
fn an_interrupted_gallery_leaves_its_folder_as_it_was() {
    let dir = scratch("gallery-interrupted");
    let gallery = dir.join("g");
    std::fs::create_dir_all(&gallery).unwrap();
    std::fs::write(gallery.join("notes.txt"), "mine").unwrap();
    let child = std::process::Command::new(env!("CARGO_BIN_EXE_bcifs"))
        .args(["gallery", gallery.to_str().unwrap()])
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // Until the first entry is written into the staging folder.
    let staging = dir.join(format!(".g.partial.{}", child.id()));
    let started = std::time::Instant::now();
    while !std::fs::read_dir(&staging).is_ok_and(|mut d| d.next().is_some()) {
        assert!(started.elapsed() < std::time::Duration::from_secs(60), "the gallery writes into {staging:?}");
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let _ = Command::new("kill").args(["-INT", &child.id().to_string()]).status();
    let out = child.wait_with_output().unwrap();
    assert_eq!(out.status.code(), Some(130));
    let left: Vec<String> =
        std::fs::read_dir(&gallery).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    assert_eq!(left, ["notes.txt"], "the folder as it was");
    assert!(!staging.exists(), "no staging folder left");
    std::fs::remove_dir_all(&dir).unwrap();
}
