//! Writers: OBJ round trip through tobj, streaming, PNG, SVG, golden rasters.

use bcifs::eval::{EvalSettings, Evaluator};
use bcifs::export::{ObjWriter, RasterSettings, ascii, raster, svg};

use super::{eval, load};

fn temp(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("bcifs-export-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// Write the torus, read it back with tobj: same counts, same positions
/// (shortest round-trip text, so exact), normals and texture coordinates.
#[test]
fn obj_round_trip_through_tobj() {
    let (a, model, _) = load("doo_sabin_torus", &[]);
    let ev = Evaluator::new(&a, &model, EvalSettings::default().with_depth(3)).unwrap();
    let shape = ev.evaluate().unwrap();
    let path = temp("torus.obj");
    let mut w = ObjWriter::create(&path).unwrap();
    ev.stream(&mut w).unwrap();
    w.finish().unwrap();
    let (models, _) =
        tobj::load_obj(&path, &tobj::LoadOptions { single_index: false, triangulate: false, ..Default::default() })
            .unwrap();
    assert_eq!(models.len(), 1);
    let mesh = &models[0].mesh;
    // tobj renumbers the vertices a model uses: compare through the faces.
    assert_eq!(mesh.positions.len(), shape.positions.len(), "vertex count");
    assert_eq!(mesh.face_arities.len(), shape.quads.len());
    assert!(mesh.face_arities.iter().all(|&n| n == 4));
    for (k, &i) in shape.quads.iter().flatten().enumerate() {
        let (i, j) = (i as usize, mesh.indices[k] as usize);
        // Shortest round-trip text: positions come back bit for bit, Y-up
        // (model z is the file's y: (x, y, z) → (x, z, −y)).
        let p = &shape.positions[3 * i..3 * i + 3];
        assert_eq!(&mesh.positions[3 * j..3 * j + 3], &[p[0], p[2], -p[1]], "corner {k}");
    }
    // Shared corners stay shared: as many distinct indices as vertices.
    let mut used: Vec<u32> = mesh.indices.clone();
    used.sort_unstable();
    used.dedup();
    assert_eq!(used.len(), shape.vertex_count());
    assert_eq!(mesh.normals.len(), shape.normals.len());
    assert_eq!(mesh.texcoords.len(), shape.uvs.len());
    // No temporary file is left behind.
    let leftovers = std::fs::read_dir(path.parent().unwrap())
        .unwrap()
        .filter(|e| e.as_ref().is_ok_and(|e| e.file_name().to_string_lossy().ends_with(".tmp")));
    assert_eq!(leftovers.count(), 0);
}

/// Curves stream too: the OBJ holds every vertex and one two-vertex `l`
/// record per segment (what MeshLab, Blender and trimesh load whole).
#[test]
fn curves_stream_to_obj() {
    let (a, model, _) = load("koch", &[]);
    let ev = Evaluator::new(&a, &model, EvalSettings::default().with_depth(7).with_memory_limit(1)).unwrap();
    assert!(ev.evaluate().is_err(), "in memory is over the 1-byte limit");
    let path = temp("koch.obj");
    let mut w = ObjWriter::create(&path).unwrap();
    ev.stream(&mut w).unwrap();
    w.finish().unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    let vertices = text.lines().filter(|l| l.starts_with("v ")).count();
    assert_eq!(vertices, 4usize.pow(7) + 1);
    // Lines chain: each `l` starts where the previous ended.
    let lines: Vec<Vec<usize>> = text
        .lines()
        .filter(|l| l.starts_with("l "))
        .map(|l| l[2..].split(' ').map(|x| x.parse().unwrap()).collect())
        .collect();
    assert_eq!(lines.len(), vertices - 1, "one record per segment");
    assert!(lines.iter().all(|l| l.len() == 2));
    assert_eq!(lines[0][0], 1);
    assert_eq!(*lines.last().unwrap().last().unwrap(), vertices);
    for w in lines.windows(2) {
        assert_eq!(w[0].last(), w[1].first());
    }
}

/// A failed write leaves no file behind.
#[test]
fn nothing_is_half_written() {
    let missing = std::env::temp_dir().join("bcifs-no-such-dir").join("x.obj");
    assert!(ObjWriter::create(&missing).is_err());
    let path = temp("dropped.obj");
    {
        let mut w = ObjWriter::create(&path).unwrap();
        bcifs::geometry::Sink::vertices(&mut w, 2, &[1.0, 2.0], None).unwrap();
        // Dropped without finish.
    }
    assert!(!path.exists());
}

#[test]
fn png_has_the_requested_size_and_ink() {
    let shape = eval("levy", &[], EvalSettings::default().with_depth(10));
    let img = raster(&shape, &RasterSettings::default().with_size(300, 200)).unwrap();
    assert_eq!(img.dimensions(), (300, 200));
    let dark = img.pixels().filter(|p| p[0] < 128).count();
    assert!(dark > 1000, "{dark} dark pixels");
    let torus = eval("doo_sabin_torus", &[], EvalSettings::default().with_depth(2));
    let img = raster(&torus, &RasterSettings::default().with_size(120, 120)).unwrap();
    let shaded = img.pixels().filter(|p| p[0] < 250).count();
    assert!(shaded > 120 * 120 / 4, "{shaded}");
    let doc = svg(&shape, 400);
    assert!(doc.starts_with("<svg") && doc.trim_end().ends_with("</svg>") && doc.contains("<path"));
}

fn golden(actual: &str, expected: &str) {
    if std::env::var_os("BCIFS_PRINT_GOLDEN").is_some() {
        println!("{actual}");
    }
    if actual.trim() != expected.trim() {
        panic!("raster differs:\n--- expected\n{}\n--- actual\n{}", expected.trim(), actual.trim());
    }
}

/// Golden ASCII rasters: the Koch curve (depth 3) and the Sierpinski branch
/// state of the two-state fern, each drawn on a small grid.
#[test]
fn golden_rasters() {
    let koch = eval("koch", &[], EvalSettings::default().with_depth(3));
    let img = raster(&koch, &RasterSettings::default().with_size(40, 14)).unwrap();
    golden(&ascii(&img), KOCH);
    let (a, mut model, _) = load("fern_sierpinski", &[]);
    model.roots = vec!["sierpinski".into()];
    let s = Evaluator::new(
        &a,
        &model,
        EvalSettings::default().with_depth(6).with_start("sierpinski", vec![vec![1.0 / 3.0; 3]]),
    )
    .unwrap()
    .evaluate()
    .unwrap();
    let img = raster(&s, &RasterSettings::default().with_size(24, 24)).unwrap();
    golden(&ascii(&img), SIERPINSKI);
}

const KOCH: &str = "
........................................
........................................
...................###..................
..................##.##.................
................#.##.##.#...............
..............#####...#####.............
..............##.........##.............
..............##.........##.............
.............###.........###............
.......##.......#.......#.......##......
.....######...##.........##...######....
...##.#..#.##.##.........##.##.#..#.##..
.######..######...........######..######
.#####....#####...........#####....#####
";
const SIERPINSKI: &str = "
#.......................
##......................
###.....................
####....................
##.##...................
######..................
#######.................
###...##................
####..###...............
##.#..#..#..............
########.##.............
############............
##..........#...........
###.........##..........
####........###.........
##.##.......#..#........
######......##.##.......
#######.....######......
##....##....##...##.....
###...###...##...###....
####..####..####.####...
##.##.##.##.##.####.##..
#######################.
########################
";

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig { cases: 24, .. Default::default() })]

    /// Every OBJ the writer produces re-reads with tobj to the same counts:
    /// corner-cutting curves at any admissible parameters and depth, and the
    /// Doo-Sabin torus at any depth.
    #[test]
    fn written_obj_files_reread_with_the_same_counts(a in 0.05f64..0.45, b in 0.05f64..0.45, depth in 1usize..7) {
        let (automaton, model, _) = load("corner_cutting", &[("a", a), ("b", b)]);
        let ev = Evaluator::new(&automaton, &model, EvalSettings::default().with_depth(depth)).unwrap();
        let shape = ev.evaluate().unwrap();
        let path = temp(&format!("prop-{depth}-{}.obj", (a * 1e6) as u64));
        let mut w = ObjWriter::create(&path).unwrap();
        ev.stream(&mut w).unwrap();
        w.finish().unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        proptest::prop_assert_eq!(text.lines().filter(|l| l.starts_with("v ")).count(), shape.vertex_count());
        proptest::prop_assert_eq!(text.lines().filter(|l| l.starts_with("l ")).count(), shape.vertex_count());
        let (torus, tmodel, _) = load("doo_sabin_torus", &[]);
        let ev = Evaluator::new(&torus, &tmodel, EvalSettings::default().with_depth(depth.min(4))).unwrap();
        let shape = ev.evaluate().unwrap();
        let mut w = ObjWriter::create(&path).unwrap();
        ev.stream(&mut w).unwrap();
        w.finish().unwrap();
        let (models, _) = tobj::load_obj(&path, &tobj::LoadOptions { single_index: false, triangulate: false, ..Default::default() }).unwrap();
        proptest::prop_assert_eq!(models[0].mesh.positions.len(), shape.positions.len());
        proptest::prop_assert_eq!(models[0].mesh.face_arities.len(), shape.quads.len());
        std::fs::remove_file(&path).unwrap();
    }
}

/// Temporary files of a dead process (an interrupted earlier run) are swept
/// when the same target is written again; live ones are left alone.
#[test]
fn stale_temporary_files_are_swept() {
    let dir = std::env::temp_dir().join(format!("bcifs-stale-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let dead = (4_000_000u32..4_100_000).find(|p| !std::path::Path::new(&format!("/proc/{p}")).exists()).unwrap();
    let stale = dir.join(format!(".x.obj.partial.{dead}.0.tmp"));
    let stale_elements = dir.join(format!(".x.obj.elements.{dead}.1.tmp"));
    let mine = dir.join(format!(".x.obj.partial.{}.999.tmp", std::process::id()));
    let other = dir.join(format!(".y.obj.partial.{dead}.0.tmp"));
    for f in [&stale, &stale_elements, &mine, &other] {
        std::fs::write(f, b"old").unwrap();
    }
    let w = ObjWriter::create(&dir.join("x.obj")).unwrap();
    w.finish().unwrap();
    assert!(!stale.exists() && !stale_elements.exists(), "swept");
    assert!(mine.exists(), "a live process's file stays");
    assert!(other.exists(), "another target's file stays");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Density pictures of the chaos game (issue 11): the same seed gives the
/// same counts with 1 and 2 threads; the counts add up to the samples (the
/// frame, fitted on the first batch, holds at least 99.9% of them); a
/// picture over the memory limit is refused with what it needs.
#[test]
fn density_pictures_count_every_sample_once() {
    use bcifs::eval::{ChaosGame, RandomSettings};
    use bcifs::export::{RasterSettings, density};
    let design = bcifs::builtin_design("fern").unwrap();
    let inst = bcifs::instantiate(&design, &[]).unwrap();
    let model = design.model().unwrap().clone();
    let points = 3_000_000;
    let raster = RasterSettings::default().with_size(200, 300);
    let counts = |threads: usize| {
        let mut settings = RandomSettings::default().with_points(1000).with_seed(5);
        settings.threads = Some(threads);
        let game = ChaosGame::new(&inst.automaton, &model, &settings).unwrap();
        density(&game, points, &raster, 2).unwrap()
    };
    let (one, two) = (counts(1), counts(2));
    assert_eq!(one, two, "the same picture with any number of threads");
    let total: u64 = one.counts.iter().map(|&c| u64::from(c)).sum();
    assert!(total as f64 >= 0.999 * points as f64 && total <= points as u64, "{total}");
    assert_eq!((one.width, one.height, one.supersample, one.counts.len()), (200, 300, 2, 400 * 600));
    let inked = one.counts.iter().filter(|&&c| c > 0).count();
    assert!(inked > 10_000, "the fern covers many cells: {inked}");
    let game = ChaosGame::new(&inst.automaton, &model, &RandomSettings::default().with_points(1000)).unwrap();
    let small = RasterSettings::default().with_size(4000, 4000).with_memory_limit(1 << 20);
    let e = density(&game, points, &small, 1).unwrap_err().to_string();
    assert!(e.contains("4000×4000"), "{e}");
}
