//! Lacunar polygons whose topology is a polyhedron's circle packing (issue
//! 44, the 2025 CAGD paper's way): the counts of pieces and holes at every
//! depth, made here by a recursion on the polyhedron's faces (not by the
//! library), the default member's convergence, the tetrahedron's lace
//! being Sierpiński's gasket, and polyhedra that are refused with the reason.

use bcifs::render::{check_report, topology_report};
use bcifs::schemes::{POLYHEDRON_NAMES, Polyhedron, PolyhedronError, polyhedral_lace};

/// Pieces and holes of face `f`'s lace at depth `k`: a face's gap holds a copy of
/// every other face's and a hole for every vertex off it.
fn expected(p: &Polyhedron, f: usize, k: usize) -> (u64, i64) {
    if k == 0 {
        return (1, 0);
    }
    let mut cells = 0;
    let mut holes = (p.vertex_count() - p.faces()[f].len()) as i64;
    for g in (0..p.faces().len()).filter(|&g| g != f) {
        let (c, h) = expected(p, g, k - 1);
        cells += c;
        holes += h;
    }
    (cells, holes)
}

#[test]
fn every_polyhedron_makes_a_connected_lace_with_a_hole_per_vertex_off_each_face() {
    for name in POLYHEDRON_NAMES {
        let p = Polyhedron::named(name).unwrap();
        // The prism's and the pyramid's faces differ: a triangle and a quadrilateral each.
        let roots: Vec<usize> = match name {
            "prism" => vec![0, 2],
            "pyramid" => vec![0, 1],
            _ => vec![0],
        };
        for f in roots {
            let design = polyhedral_lace(&p, f, name).unwrap();
            let check = check_report(&design, &[]).unwrap();
            assert!(check.ok && check.converges == Some(true), "{name} face {f}: {:?}", check.converges);
            let depths = if p.faces().len() > 8 { 1..=2 } else { 1..=3 };
            for k in depths {
                let t = topology_report(&design, &[], k).unwrap();
                let (cells, holes) = expected(&p, f, k);
                assert_eq!((t.components, t.betti), (1, [1, holes, 0]), "{name} face {f} depth {k}");
                // Cells of five sides or more (the dodecahedron's) are written as fans but counted once.
                assert_eq!(t.cells as u64, cells, "{name} face {f} depth {k}");
                assert_eq!(t.vertices as i64 - t.edges as i64 + t.cells as i64, t.euler);
                // The copies touch at single points: the lace is pinched wherever two faces share an edge.
                assert!(t.pinches > 0);
            }
        }
    }
}

/// The tetrahedron's packing is Apollonian: its lace's default member is
/// Sierpiński's gasket exactly (every side split at its midpoint, no point
/// inside), so the depth-k corners are the points of the 2^k-ary grid and
/// the leaf triangles have 1/4^k of the area.
#[test]
fn the_tetrahedrons_lace_is_the_gasket() {
    let design = polyhedral_lace(&Polyhedron::named("tetrahedron").unwrap(), 0, "apollonian").unwrap();
    let family = bcifs::solve(&design).unwrap();
    let defaults = family.parameter_values(&[]).unwrap();
    assert!(
        defaults.iter().all(|v| (v - 0.5).abs() < 1e-15 || v.abs() < 1e-15 || (v - 1.0).abs() < 1e-15),
        "{defaults:?}"
    );
    let k = 4;
    let shape = crate::evaluate(&design, k);
    let model = design.model().unwrap();
    let corner = |j: usize| [model.points[j][0], model.points[j][1]];
    let (a, b, c) = (corner(0), corner(1), corner(2));
    let area =
        |p: [f64; 2], q: [f64; 2], r: [f64; 2]| ((q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0])) / 2.0;
    let whole = area(a, b, c);
    for i in 0..shape.vertex_count() {
        let p = shape.point(i);
        // Barycentric coordinates over the corners, times 2^k: integers.
        let (u, v) = (area([p[0], p[1]], b, c) / whole, area(a, [p[0], p[1]], c) / whole);
        for x in [u, v] {
            let scaled = x * f64::from(1 << k);
            assert!((scaled - scaled.round()).abs() < 1e-9, "{p:?} is off the grid");
        }
    }
    assert_eq!(shape.triangles.len(), 81);
    for t in &shape.triangles {
        let [p, q, r] = t.map(|i| shape.point(i));
        let s = area([p[0], p[1]], [q[0], q[1]], [r[0], r[1]]).abs();
        assert!((s - whole.abs() / 256.0).abs() < 1e-12, "{s}");
    }
}

/// What the generated file says and what it keeps: one state per face and
/// per valence, a copy of every other face in each, the constraints
/// commented; the defaults solved exactly (Tutte's points are rational).
#[test]
fn the_shipped_cube_lace_is_what_the_command_generates() {
    let shipped =
        |name: &str| std::fs::read_to_string(format!("{}/automata/{name}.toml", env!("CARGO_MANIFEST_DIR"))).unwrap();
    let made = polyhedral_lace(&Polyhedron::named("cube").unwrap(), 0, "cube_lace").unwrap();
    assert_eq!(shipped("cube_lace"), bcifs::write_design(&made));
    let text = bcifs::write_design(&made);
    for words in ["In face 0, the copies of faces", "turned over", "The gap of face 5"] {
        assert!(text.contains(words), "{words}");
    }
    let family = bcifs::solve(&made).unwrap();
    // 6 faces × 5 copies; the sides of valence 3 in two parts.
    assert_eq!(made.automaton().arrows().filter(|(_, a)| a.name.starts_with('S')).count(), 30);
    assert!(family.parameter_names().len() > 30);
    let made = polyhedral_lace(&Polyhedron::named("octahedron").unwrap(), 0, "octahedron_lace").unwrap();
    assert_eq!(shipped("octahedron_lace"), bcifs::write_design(&made));
}

#[test]
fn a_polyhedron_file_is_read_and_bad_ones_are_refused_with_the_reason() {
    let dir = std::env::temp_dir().join(format!("bcifs-polyhedral-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // A cube as Blender writes it (normals, texture coordinates, an object name, 1-based faces).
    let obj = dir.join("box.obj");
    std::fs::write(
        &obj,
        "# Blender 4.0\no Cube\nv 1 1 -1\nv 1 -1 -1\nv 1 1 1\nv 1 -1 1\nv -1 1 -1\nv -1 -1 -1\nv -1 1 1\nv -1 -1 1\n\
         vn 0 1 0\nvt 0.625 0.5\ns 0\nf 1/1/1 5/1/1 7/1/1 3/1/1\nf 4/1/1 3/1/1 7/1/1 8/1/1\nf 8/1/1 7/1/1 5/1/1 6/1/1\n\
         f 6/1/1 2/1/1 4/1/1 8/1/1\nf 2/1/1 1/1/1 3/1/1 4/1/1\nf 6/1/1 5/1/1 1/1/1 2/1/1\n",
    )
    .unwrap();
    let p = Polyhedron::named_or_read(obj.to_str().unwrap()).unwrap();
    assert_eq!((p.name(), p.vertex_count(), p.faces().len()), ("box", 8, 6));
    let design = polyhedral_lace(&p, 3, "box").unwrap();
    assert_eq!(topology_report(&design, &[], 2).unwrap().betti, [1, 24, 0]);
    // The same polyhedron as OFF, a triangular prism.
    let off = dir.join("prism.off");
    std::fs::write(
        &off,
        "OFF\n6 5 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 0 1\n0 1 1\n3 0 2 1\n3 3 4 5\n4 0 1 4 3\n4 1 2 5 4\n4 2 0 3 5\n",
    )
    .unwrap();
    let prism = Polyhedron::named_or_read(off.to_str().unwrap()).unwrap();
    assert_eq!(prism.faces(), Polyhedron::named("prism").unwrap().faces());
    let refused = |faces: Vec<Vec<usize>>, words: &str| {
        let e = Polyhedron::from_faces(faces).unwrap_err();
        assert!(matches!(e, PolyhedronError::Invalid(_)) && e.to_string().contains(words), "{e}");
    };
    let cube: Vec<Vec<usize>> = Polyhedron::named("cube").unwrap().faces().to_vec();
    refused(cube[..5].to_vec(), "face on one side only");
    let mut flipped = cube.clone();
    flipped[2].reverse();
    refused(flipped, "not oriented alike");
    refused(vec![vec![0, 1, 2], vec![0, 2, 1]], "valence 2");
    refused(vec![vec![0, 1], vec![1, 0]], "at least 3");
    refused(vec![vec![0, 1, 1, 2]], "each once");
    // A torus of 3 × 3 quadrilaterals: χ = 0.
    let torus: Vec<Vec<usize>> = (0..9)
        .map(|i| {
            let (a, b) = (i % 3, i / 3);
            let v = |x: usize, y: usize| (x % 3) + 3 * (y % 3);
            vec![v(a, b), v(a + 1, b), v(a + 1, b + 1), v(a, b + 1)]
        })
        .collect();
    refused(torus, "V − E + F = 9 − 18 + 9 = 0");
    // Two tetrahedra glued at a vertex: two fans there.
    let mut two = Polyhedron::named("tetrahedron").unwrap().faces().to_vec();
    two.extend(
        Polyhedron::named("tetrahedron")
            .unwrap()
            .faces()
            .iter()
            .map(|f| f.iter().map(|&v| if v == 0 { 0 } else { v + 3 }).collect()),
    );
    refused(two, "more than one fan");
    // Two triangles' worth of faces hung between vertices 0 and 1 on both sides: a 2-cut.
    refused(
        vec![vec![0, 2, 3], vec![2, 1, 3], vec![0, 3, 1, 4], vec![0, 4, 5], vec![4, 1, 5], vec![0, 5, 1, 2]],
        "removing vertices 0 and 1 cuts its graph in two",
    );
    let e = polyhedral_lace(&Polyhedron::named("cube").unwrap(), 6, "x").unwrap_err();
    assert_eq!(e.to_string(), "face 6: the polyhedron has faces 0 to 5");
    // A 200-sided prism: its lace would have 1,440,000 unknowns; refused at once, before the 2-cut search.
    let m = 200;
    let mut prism: Vec<Vec<usize>> = vec![(0..m).rev().collect(), (m..2 * m).collect()];
    prism.extend((0..m).map(|i| vec![i, (i + 1) % m, m + (i + 1) % m, m + i]));
    assert!(matches!(Polyhedron::from_faces(prism), Err(PolyhedronError::TooLarge { unknowns: 1_440_000, .. })));
    let e = Polyhedron::named_or_read("no-such-polyhedron").unwrap_err();
    assert!(matches!(e, PolyhedronError::Unknown(_)), "{e}");
    // The command line: the same file, and a bad one said with its path.
    let run = |args: &[&str]| std::process::Command::new(env!("CARGO_BIN_EXE_bcifs")).args(args).output().unwrap();
    let out = run(&["new", "polyhedron", obj.to_str().unwrap(), "--face", "3", "--name", "box"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert_eq!(String::from_utf8_lossy(&out.stdout), bcifs::write_design(&design));
    let open = dir.join("open.obj");
    std::fs::write(&open, "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 4 2\nf 2 4 3\n").unwrap();
    let out = run(&["new", "polyhedron", open.to_str().unwrap()]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && err.contains("open.obj") && err.contains("open there"), "{err}");
    std::fs::remove_dir_all(&dir).unwrap();
}
