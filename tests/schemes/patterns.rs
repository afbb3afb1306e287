//! Subdivision patterns (issue 44): a cell, its split and the sub-cells kept
//! make the whole automaton; the classical member is the classical set, and
//! the meshes have the topology the pattern implies.

use std::collections::{BTreeSet, HashMap};

use bcifs::schemes::{Pattern, PatternCell, PatternError, pattern_design};

/// The Euler characteristic `V − E + F` and the connected components of a
/// quad mesh (vertices: those the faces use; edges: distinct unordered pairs).
fn euler_and_components(quads: &[[u32; 4]]) -> (i64, usize) {
    let mut vertices = BTreeSet::new();
    let mut edges = BTreeSet::new();
    let mut parent: HashMap<usize, usize> = HashMap::new();
    fn root(parent: &mut HashMap<usize, usize>, v: usize) -> usize {
        let p = *parent.entry(v).or_insert(v);
        if p == v {
            return v;
        }
        let r = root(parent, p);
        parent.insert(v, r);
        r
    }
    for q in quads {
        for k in 0..4 {
            let (a, b) = (q[k] as usize, q[(k + 1) % 4] as usize);
            vertices.insert(a);
            edges.insert((a.min(b), a.max(b)));
            let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
            parent.insert(ra, rb);
        }
    }
    let roots: BTreeSet<usize> = vertices.iter().map(|&v| root(&mut parent, v)).collect();
    (vertices.len() as i64 - edges.len() as i64 + quads.len() as i64, roots.len())
}

#[test]
fn the_cantor_set_is_a_segment_pattern_with_the_subdivision_points_as_parameters() {
    let cantor = Pattern::parse(PatternCell::Segment, "3", Some("101"), 2).unwrap();
    let design = pattern_design(&cantor, "cantor").unwrap();
    let family = bcifs::solve(&design).unwrap();
    assert_eq!(family.parameter_names(), ["a", "b"], "where the first third ends and the last begins");
    // The shipped `cantor` is this pattern: its default member is the classical set, exactly.
    let shipped = bcifs::builtin_design("cantor").unwrap();
    assert_eq!(bcifs::write_design(&shipped).matches("default").count(), 2);
    for k in 1..=6 {
        let shape = crate::evaluate(&shipped, k);
        let xs: Vec<f64> = (0..shape.vertex_count()).map(|i| shape.point(i)[0]).collect();
        assert_eq!(xs.len(), 2 << k, "depth {k}: 2^k segments, two ends each");
        assert_eq!(shape.polylines().count(), 1 << k, "depth {k}: one segment per kept cell, no bridge over a gap");
        // The segments are the intervals of the Cantor set's k-th stage.
        let mut stage = vec![(0.0f64, 1.0f64)];
        for _ in 0..k {
            stage = stage.iter().flat_map(|&(a, b)| [(a, a + (b - a) / 3.0), (b - (b - a) / 3.0, b)]).collect();
        }
        for (i, (a, b)) in stage.iter().enumerate() {
            assert!((xs[2 * i] - a).abs() < 1e-12 && (xs[2 * i + 1] - b).abs() < 1e-12, "depth {k}: segment {i}");
        }
    }
}

#[test]
fn the_carpet_lace_has_8_to_the_k_faces_and_the_holes_the_pattern_implies() {
    let design = bcifs::builtin_design("carpet").unwrap();
    let family = bcifs::solve(&design).unwrap();
    assert_eq!(family.parameters.len(), 16, "4 split points on the sides, 3 weights at each of 4 inner nodes");
    for k in 1..=4usize {
        let shape = crate::evaluate(&design, k);
        assert_eq!(shape.quads.len(), 8usize.pow(k as u32), "depth {k}");
        // A connected sheet with (8^k − 1)/7 holes: χ = 1 − holes (welded through the shared sides).
        let holes = (8i64.pow(k as u32) - 1) / 7;
        assert_eq!(euler_and_components(&shape.quads), (1 - holes, 1), "depth {k}");
    }
    // The default member converges (the JSR bounds), as every family's does.
    let check = bcifs::render::check_report(&design, &[]).unwrap();
    assert!(check.converges == Some(true), "{:?}", check.converges);
}

#[test]
fn any_mask_makes_its_lace_and_every_equation_says_what_it_glues() {
    // A ring (the carpet's border only) of 5×5, a cross, and a diagonal pair touching at one corner.
    for (split, mask, faces, holes, components) in [
        ("5x5", "1111110001100011000111111", 16, 1, 1),
        ("3x3", "010111010", 5, 0, 1),
        ("2x2", "1001", 2, 0, 1),
        ("3x2", "101101", 4, 0, 2),
    ] {
        let pattern = Pattern::parse(PatternCell::Quad, split, Some(mask), 2).unwrap();
        let design = pattern_design(&pattern, "lace").unwrap();
        let text = bcifs::write_design(&design);
        let equations = text.lines().filter(|l| l.trim_start().starts_with("\"T")).count();
        let comments = text.lines().filter(|l| l.trim_start().starts_with("# (")).count();
        assert_eq!(equations, comments, "{mask}: every equation between sub-cells names them\n{text}");
        if mask == "1001" {
            assert!(text.contains("touch at one corner only (a pinch)"), "{text}");
        }
        // The printed file reads back to the same automaton (its comments aside).
        let again = bcifs::parse_design(&text, "lace.toml", "lace").unwrap();
        let bare = |t: &str| t.lines().filter(|l| !l.trim_start().starts_with('#')).collect::<Vec<_>>().join("\n");
        assert_eq!(bare(&bcifs::write_design(&again)), bare(&text));
        let shape = crate::evaluate(&design, 1);
        assert_eq!(shape.quads.len(), faces, "{mask}");
        let (euler, parts) = euler_and_components(&shape.quads);
        assert_eq!(parts, components, "{mask}");
        if mask != "1001" {
            assert_eq!(euler, components as i64 - holes, "{mask}: χ = components − holes");
        }
    }
}

#[test]
fn the_classical_member_of_a_cubic_patch_is_de_casteljau_exactly() {
    // Every part of a Bézier curve of degree 3 split in three: its control points are exact thirds.
    let m = bcifs::schemes::bezier_part(4, 1, 3);
    let third = |p: i64, q: i64| num_rational::BigRational::new(p.into(), q.into());
    // The middle third's first control point is the curve at 1/3: Bernstein weights (8, 12, 6, 1)/27.
    let column: Vec<_> = (0..4).map(|r| m[r][0].clone()).collect();
    assert_eq!(column, [third(8, 27), third(12, 27), third(6, 27), third(1, 27)]);
    // A carpet on a bicubic patch solves, and its default member is the patch subdivided.
    let pattern = Pattern::parse(PatternCell::Quad, "3x3", Some("111101111"), 4).unwrap();
    let design = pattern_design(&pattern, "carpet4").unwrap();
    let shape = crate::evaluate(&design, 2);
    assert_eq!(shape.quads.len(), 64);
    // On the unit square with the inner points raised by 1/2, a point of the surface at (u, v) has
    // z = 1/2 · b(u) b(v) with b the inner Bernstein mass 3t(1 − t): the corners of the cells are on it.
    let b = |t: f64| 3.0 * t * (1.0 - t);
    for i in 0..shape.vertex_count() {
        let p = shape.point(i);
        assert!((p[2] - 0.5 * b(p[0]) * b(p[1])).abs() < 1e-12, "{p:?} is off the bicubic patch");
    }
}

#[test]
fn bad_patterns_are_refused_before_any_solving() {
    let refused =
        |cell, split: &str, keep: Option<&str>, degree| Pattern::parse(cell, split, keep, degree).unwrap_err();
    assert!(matches!(refused(PatternCell::Quad, "3x3", Some("000000000"), 2), PatternError::Empty));
    assert!(matches!(
        refused(PatternCell::Quad, "3x3", Some("1111"), 2),
        PatternError::Mask { got: 4, expected: 9, .. }
    ));
    assert!(matches!(refused(PatternCell::Quad, "3", None, 2), PatternError::Split { .. }));
    assert!(matches!(refused(PatternCell::Segment, "1", None, 2), PatternError::Split { .. }));
    assert!(matches!(refused(PatternCell::Segment, "3", None, 5), PatternError::Degree(5)));
    assert!(matches!(refused(PatternCell::Segment, "3", Some("1x1"), 2), PatternError::MaskText(_)));
    let e = refused(PatternCell::Quad, "3x3", Some("1111"), 2).to_string();
    assert!(e.contains("4 flag(s) for 9 sub-cells (3x3)"), "{e}");
    // The command line says the same, with no automaton printed.
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_bcifs"))
        .args(["new", "pattern", "--cell", "quad", "--split", "3x3", "--keep", "1111"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(out.stdout.is_empty());
    assert!(String::from_utf8_lossy(&out.stderr).contains("4 flag(s) for 9 sub-cells"));
    // Legal but surprising: said, and the automaton printed all the same.
    for (args, says) in [
        (["--cell", "quad", "--split", "3x2", "--keep", "101101"], "make 2 separate pieces (4 at depth 2)"),
        (
            ["--cell", "triangle", "--split", "2", "--keep", "1011"],
            "3 place(s) where kept sub-cells touch at a corner or along an edge only",
        ),
    ] {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_bcifs"))
            .arg("new")
            .arg("pattern")
            .args(args)
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(0));
        assert!(String::from_utf8_lossy(&out.stdout).contains("[constraints]"));
        assert!(String::from_utf8_lossy(&out.stderr).contains(says), "{}", String::from_utf8_lossy(&out.stderr));
    }
}

#[test]
fn analyze_topology_counts_cells_components_and_betti_numbers() {
    use bcifs::render::topology_report;
    let carpet = bcifs::builtin_design("carpet").unwrap();
    for k in 1..=4usize {
        let t = topology_report(&carpet, &[], k).unwrap();
        let holes = (8i64.pow(k as u32) - 1) / 7;
        assert_eq!((t.cells, t.components, t.betti), (8usize.pow(k as u32), 1, [1, holes, 0]), "carpet depth {k}");
        assert_eq!(t.euler, 1 - holes);
    }
    for k in 1..=5usize {
        let t = topology_report(&bcifs::builtin_design("cantor").unwrap(), &[], k).unwrap();
        assert_eq!((t.cells, t.components, t.betti), (1 << k, 1 << k, [1 << k, 0, 0]), "cantor depth {k}");
    }
    // A closed surface: the torus has one void and two loops.
    let torus = topology_report(&bcifs::builtin_design("doo_sabin_torus").unwrap(), &[], 2).unwrap();
    assert_eq!((torus.euler, torus.betti), (0, [1, 2, 1]));
    // Two cells touching at a corner: one component, one pinch.
    let pinch = pattern_design(&Pattern::parse(PatternCell::Quad, "2x2", Some("1001"), 2).unwrap(), "pinch").unwrap();
    let t = topology_report(&pinch, &[], 1).unwrap();
    assert_eq!((t.components, t.pinches), (1, 1));
    assert_eq!(topology_report(&pinch, &[], 3).unwrap().pinches, 7, "2 + 4 + 1 corners at depths 1..3: 1 + 2 + 4");
    // The command line's JSON.
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_bcifs"))
        .args(["analyze", "topology", "carpet", "--depth", "2", "--json"])
        .output()
        .unwrap();
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["betti"], serde_json::json!([1, 9, 0]));
    assert_eq!(
        (json["cells"].as_u64(), json["components"].as_u64(), json["euler"].as_i64()),
        (Some(64), Some(1), Some(-8))
    );
}

#[test]
fn porosity_and_lacunarity_are_the_pattern_s() {
    use bcifs::render::lacunarity_report;
    // A flat carpet (the generator's unit square): each depth keeps 8/9 of the area.
    let flat =
        pattern_design(&Pattern::parse(PatternCell::Quad, "3x3", Some("111101111"), 2).unwrap(), "flat").unwrap();
    let l = lacunarity_report(&flat, &[], 5).unwrap();
    assert_eq!((l.dimension, l.grid, l.porosity.len()), (2, 243, 5));
    for (k, p) in l.porosity.iter().enumerate() {
        assert!((p - (1.0 - (8.0f64 / 9.0).powi(k as i32 + 1))).abs() < 1e-12, "depth {}: {p}", k + 1);
    }
    // On a grid the depth-5 cells fill exactly, Λ(1) is one over the filled fraction; Λ falls to 1.
    assert!((l.lacunarity[0][1] - (9.0f64 / 8.0).powi(5)).abs() < 1e-9, "{:?}", l.lacunarity);
    assert!(l.lacunarity.windows(2).all(|w| w[1][1] < w[0][1]), "{:?}", l.lacunarity);
    assert!((l.lacunarity.last().unwrap()[1] - 1.0).abs() < 1e-12);
    // A carpet with its hole in a corner is as porous, but its holes cluster: more lacunar at mid scales.
    let corner =
        pattern_design(&Pattern::parse(PatternCell::Quad, "3x3", Some("011111111"), 2).unwrap(), "corner").unwrap();
    let c = lacunarity_report(&corner, &[], 5).unwrap();
    assert!((c.porosity[4] - l.porosity[4]).abs() < 1e-12);
    assert!(c.lacunarity[2][1] > l.lacunarity[2][1], "{:?} vs {:?}", c.lacunarity, l.lacunarity);
    // The Cantor set: 1 − (2/3)^k of the length, Λ(1) = (3/2)^5.
    let cantor = lacunarity_report(&bcifs::builtin_design("cantor").unwrap(), &[], 5).unwrap();
    assert_eq!(cantor.dimension, 1);
    assert!((cantor.porosity[4] - (1.0 - (2.0f64 / 3.0).powi(5))).abs() < 1e-12);
    assert!((cantor.lacunarity[0][1] - 1.5f64.powi(5)).abs() < 1e-9);
    // The parameters move the holes: a member with a wider first third is less porous.
    let wide = lacunarity_report(&bcifs::builtin_design("cantor").unwrap(), &[("a".into(), 0.45)], 1).unwrap();
    assert!((wide.porosity[0] - (1.0 - 0.45 - 1.0 / 3.0)).abs() < 1e-12, "{:?}", wide.porosity);
    // Points have no measure: said, not a number.
    let e = lacunarity_report(&bcifs::builtin_design("gasket").unwrap(), &[], 3).unwrap_err();
    assert!(e.to_string().contains("points"), "{e}");
    // The command line's JSON.
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_bcifs"))
        .args(["analyze", "lacunarity", "cantor", "--depth", "2", "--json"])
        .output()
        .unwrap();
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["porosity"].as_array().map(Vec::len), Some(2));
    assert!(json["lacunarity"][0][1].as_f64().is_some());
}

#[test]
fn triangle_patterns_make_the_gasket_lace_and_any_mask_of_up_and_down_cells() {
    use bcifs::render::topology_report;
    // The shipped gasket lace: 3^k triangles, one component, (3^k − 1)/2 holes, its corners pinched.
    let gasket = bcifs::builtin_design("gasket_lace").unwrap();
    for k in 1..=5usize {
        let t = topology_report(&gasket, &[], k).unwrap();
        let holes = (3i64.pow(k as u32) - 1) / 2;
        assert_eq!((t.cells, t.components, t.betti), (3usize.pow(k as u32), 1, [1, holes, 0]), "gasket depth {k}");
        assert!(t.pinches > 0);
    }
    // Its default member is the classical gasket: the vertices at depth 4 are grid points of the 16-ary split.
    let shape = crate::evaluate(&gasket, 4);
    let h = 3f64.sqrt() / 2.0;
    for i in 0..shape.vertex_count() {
        let p = shape.point(i);
        let (b, a) = (p[1] / h * 16.0, (p[0] - p[1] / h / 2.0) * 16.0);
        assert!((a - a.round()).abs() < 1e-9 && (b - b.round()).abs() < 1e-9, "{p:?} is off the grid");
    }
    // Every cell of a 3-ary split kept: a disk of 9^k triangles, welded (χ = 1).
    let full = pattern_design(&Pattern::parse(PatternCell::Triangle, "3", None, 2).unwrap(), "full").unwrap();
    let t = topology_report(&full, &[], 2).unwrap();
    assert_eq!((t.cells, t.euler, t.betti, t.pinches), (81, 1, [1, 0, 0], 0));
    // Downward cells too: two of the nine left out (an upward and a downward one).
    let mask = Pattern::parse(PatternCell::Triangle, "3", Some("101111011"), 2).unwrap();
    let two = pattern_design(&mask, "two").unwrap();
    assert_eq!(topology_report(&two, &[], 1).unwrap().cells, 7);
    assert_eq!(topology_report(&two, &[], 2).unwrap().cells, 49);
    let check = bcifs::render::check_report(&two, &[]).unwrap();
    assert_eq!(check.converges, Some(true));
    // A triangle carries 2 to 4 control points a side (a Bézier triangle of degree 1 to 3), and its mask has n² flags.
    assert!(matches!(Pattern::parse(PatternCell::Triangle, "2", None, 5), Err(PatternError::Degree(5))));
    assert!(matches!(Pattern::parse(PatternCell::Tetrahedron, "2", None, 3), Err(PatternError::Degree(3))));
    assert!(matches!(
        Pattern::parse(PatternCell::Triangle, "2", Some("101"), 2),
        Err(PatternError::Mask { expected: 4, .. })
    ));
}

/// A point of the Bézier triangle of `d` points a side with net `net`
/// ([`bcifs::schemes::triangle_net`] order) at barycentric `(1 − u − v, u, v)`:
/// Bernstein's sum, written here from its definition.
fn bezier_triangle(net: &[Vec<f64>], d: usize, u: f64, v: f64) -> [f64; 3] {
    let m = (d - 1) as i32;
    let fact = |n: i32| (1..=n).map(f64::from).product::<f64>();
    let mut out = [0.0; 3];
    for (q, &(a, b)) in bcifs::schemes::triangle_net(d).iter().enumerate() {
        let (a, b) = (a as i32, b as i32);
        let i = m - a - b;
        let w = fact(m) / (fact(i) * fact(a) * fact(b)) * (1.0 - u - v).powi(i) * u.powi(a) * v.powi(b);
        (0..3).for_each(|x| out[x] += w * net[q][x]);
    }
    out
}

/// The gasket on curved triangles (issue 44: "laces on curved patches"): a
/// triangle of 3 or 4 control points a side is a Bézier triangle, its
/// classical member the patch subdivided at the midpoints exactly, so every
/// corner of a depth-k cell is the patch at its grid point; sides shared by
/// neighbours are glued whole (a full split is one disk), and the family's
/// other members keep the topology.
#[test]
fn triangles_of_higher_degree_are_bezier_triangles_subdivided_exactly() {
    use bcifs::render::topology_report;
    let shipped = bcifs::builtin_design("gasket_bezier").unwrap();
    for d in [3, 4] {
        let p = Pattern::parse(PatternCell::Triangle, "2", Some("1011"), d).unwrap();
        let design = if d == 4 { shipped.clone() } else { pattern_design(&p, "g").unwrap() };
        let net = design.model().unwrap().points.clone();
        let k = 4;
        // The corners of the kept upward cells on the 2^k grid, made here by the gasket's recursion.
        let mut expected: Vec<[f64; 3]> = Vec::new();
        let mut stack = vec![(0u32, 0u32, 1u32 << k)];
        while let Some((x, y, s)) = stack.pop() {
            if s == 1 {
                for (a, b) in [(x, y), (x + 1, y), (x, y + 1)] {
                    let n = f64::from(1u32 << k);
                    expected.push(bezier_triangle(&net, d, f64::from(a) / n, f64::from(b) / n));
                }
                continue;
            }
            let h = s / 2;
            stack.extend([(x, y, h), (x + h, y, h), (x, y + h, h)]);
        }
        let shape = crate::evaluate(&design, k);
        assert_eq!(shape.vertex_count(), (3usize.pow(k as u32 + 1) + 3) / 2, "degree {d}: welded corners");
        for i in 0..shape.vertex_count() {
            let p = shape.point(i);
            let near =
                expected.iter().map(|e| (0..3).map(|x| (e[x] - p[x]).powi(2)).sum::<f64>()).fold(f64::MAX, f64::min);
            assert!(near.sqrt() < 1e-12, "degree {d}: {p:?} is not on the patch ({})", near.sqrt());
        }
        for k in 1..=3usize {
            let t = topology_report(&design, &[], k).unwrap();
            assert_eq!(t.betti, [1, (3i64.pow(k as u32) - 1) / 2, 0], "degree {d} depth {k}");
        }
        // A rough member: the sides' split points moved, the same holes.
        let family = bcifs::solve(&design).unwrap();
        let moved: Vec<(String, f64)> = family
            .parameter_names()
            .iter()
            .enumerate()
            .map(|(i, n)| (n.clone(), 0.03 * ((i % 5) as f64 - 2.0)))
            .collect();
        let defaults = family.parameter_values(&[]).unwrap();
        let moved: Vec<(String, f64)> = moved.into_iter().zip(defaults).map(|((n, dv), v)| (n, v + dv)).collect();
        assert_eq!(topology_report(&design, &moved, 2).unwrap().betti, [1, 4, 0], "degree {d}");
    }
    // Every cell of a 3-ary split of a cubic triangle kept: neighbours share whole sides, one disk.
    let full = pattern_design(&Pattern::parse(PatternCell::Triangle, "3", None, 4).unwrap(), "full").unwrap();
    let t = topology_report(&full, &[], 2).unwrap();
    assert_eq!((t.cells, t.euler, t.betti, t.pinches), (81, 1, [1, 0, 0], 0));
    assert!(bcifs::write_design(&full).contains("side1 flip"));
}

#[test]
fn a_pattern_file_is_the_flags_written_down() {
    let carpet = Pattern::parse(PatternCell::Quad, "3x3", Some("111101111"), 2).unwrap();
    let text = carpet.to_toml("carpet");
    let (again, name) = Pattern::from_toml(&text, "carpet.toml").unwrap();
    assert_eq!((&again, name.as_str()), (&carpet, "carpet"));
    // Rows of the mask and a split as numbers read the same.
    let rows = "cell = \"quad\"\nsplit = [3, 3]\nkeep = [\"111\", \"101\", \"111\"]\n";
    assert_eq!(Pattern::from_toml(rows, "rows.toml").unwrap().0, carpet);
    // A file that does not read says where; a pattern that does not fit says what.
    let e = Pattern::from_toml("cell = \"quad\"\nsplit = [3, 3\n", "bad.toml").unwrap_err().to_string();
    assert!(e.starts_with("bad.toml:2:"), "{e}");
    let e = Pattern::from_toml("cell = \"quad\"\nsplit = 3\nkeep = \"101\"\nshape = 1\n", "x.toml")
        .unwrap_err()
        .to_string();
    assert!(e.contains("shape"), "{e}");
    let e = Pattern::from_toml("cell = \"cube\"\nsplit = 3\n", "x.toml").unwrap_err().to_string();
    assert!(e.contains("cell `cube`"), "{e}");
    // The command line reads it: the same automaton as its flags.
    let dir = std::env::temp_dir().join(format!("bcifs-pattern-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("carpet.toml");
    std::fs::write(&file, &text).unwrap();
    let run =
        |args: &[&str]| std::process::Command::new(env!("CARGO_BIN_EXE_bcifs")).args(args).output().unwrap().stdout;
    let from_file = run(&["new", "pattern", "--from", file.to_str().unwrap()]);
    let from_flags =
        run(&["new", "pattern", "--cell", "quad", "--split", "3x3", "--keep", "111101111", "--name", "carpet"]);
    assert!(!from_file.is_empty());
    assert_eq!(from_file, from_flags);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn porosity_and_lacunarity_sweep_over_two_parameters() {
    use bcifs::analysis::ParameterPlane;
    use bcifs::render::{SweepKind, sweep};
    let cantor = bcifs::builtin_design("cantor").unwrap();
    let plane = ParameterPlane { x: ("a".into(), 0.2, 0.4), y: ("b".into(), 0.6, 0.8), size: (4, 4) };
    let values = sweep(&cantor, &plane, "porosity".parse().unwrap(), false, 0..4).unwrap().to_f64();
    let mut checked = 0;
    for (i, v) in values.iter().enumerate() {
        let at = plane.values_at(i % 4, i / 4);
        let (a, b) = (at[0].1, at[1].1);
        // Two parts of lengths a and 1 − b at every depth: (a + 1 − b)^4 of the length is kept at depth 4.
        if !v.is_nan() {
            assert!((v - (1.0 - (a + 1.0 - b).powi(4))).abs() < 1e-9, "a = {a}, b = {b}: {v}");
            checked += 1;
        }
    }
    assert_eq!(checked, 16, "every member of this plane converges");
    let lacunar = sweep(&cantor, &plane, SweepKind::Lacunarity, false, 0..4).unwrap().to_f64();
    assert!(lacunar.iter().all(|l| *l >= 1.0), "{lacunar:?}");
    // Their colours are the library's palette (NaN grey).
    let grey = bcifs::render::sweep_colour(SweepKind::Porosity, f64::NAN);
    assert_ne!(bcifs::render::sweep_colour(SweepKind::Porosity, 0.5), grey);
}

#[test]
fn similarity_dimensions_of_the_classical_patterns_are_moran_s() {
    let report = |design: &bcifs::Design| bcifs::render::dimension_report(design, &[]).unwrap();
    let cantor = report(&bcifs::builtin_design("cantor").unwrap());
    assert!((cantor.similarity.unwrap() - 2f64.ln() / 3f64.ln()).abs() < 1e-9);
    let gasket = report(&bcifs::builtin_design("gasket_lace").unwrap());
    assert!((gasket.similarity.unwrap() - 3f64.ln() / 2f64.ln()).abs() < 1e-9);
    assert!((gasket.fit.unwrap().dimension - 3f64.ln() / 2f64.ln()).abs() < 0.01, "box counting agrees");
    let flat =
        pattern_design(&Pattern::parse(PatternCell::Quad, "3x3", Some("111101111"), 2).unwrap(), "flat").unwrap();
    assert!((report(&flat).similarity.unwrap() - 8f64.ln() / 3f64.ln()).abs() < 1e-9, "log 8 / log 3");
}

/// Issue 56 §7: a generator writes the exact fractions it knows — the
/// B-spline defaults of `new curve` (Schaefer et al. 2005: the transposed
/// blocks of the stationary scheme), the Doo-Sabin weights of `new
/// quad-patch` — never their decimal roundings.
#[test]
fn generators_write_their_defaults_exactly() {
    let new = |args: &[&str]| {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_bcifs")).arg("new").args(args).output().unwrap();
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        let text = String::from_utf8(out.stdout).unwrap();
        text.lines()
            .filter(|l| l.contains("default ="))
            .map(|l| l.split('"').nth(3).unwrap().to_string())
            .collect::<Vec<_>>()
    };
    assert_eq!(new(&["curve", "--points", "3", "--vertex", "2", "--arity", "3"]), ["7/9", "1/9", "1/3", "2/3"]);
    assert_eq!(new(&["quad-patch", "--symmetric"]), ["9/16", "3/16", "3/16"]);
    // Any size: every default a fraction, and the member it makes the uniform B-spline's (checked exactly).
    for (points, arity) in [(3, 2), (4, 2), (4, 3), (5, 2)] {
        let defaults = new(&[
            "curve",
            "--points",
            &points.to_string(),
            "--vertex",
            &(points - 1).to_string(),
            "--arity",
            &arity.to_string(),
        ]);
        assert!(!defaults.is_empty() && defaults.iter().all(|d| !d.contains('.')), "{points} {arity}: {defaults:?}");
        let design = bcifs::schemes::curve(points, points - 1, arity).unwrap();
        let exact = bcifs::schemes::bspline_segment_parts(points - 1, arity);
        let family = bcifs::solve(&design).unwrap();
        // The defaults, written in the family's order of parameters (a, b, …).
        let x: Vec<bcifs::render::Num> = defaults.iter().map(|d| d.parse().unwrap()).collect();
        assert_eq!(x.len(), family.parameter_names().len());
        for (l, m) in exact.iter().enumerate() {
            let member = family.exact_matrix(&format!("T{l}"), &x).unwrap();
            for (i, row) in m.iter().enumerate() {
                for (j, e) in row.iter().enumerate() {
                    assert_eq!(
                        member[i][j].to_string(),
                        e.to_string(),
                        "T{l}[{i}][{j}] of {points} points, arity {arity}"
                    );
                }
            }
        }
    }
}
