//! Writers: OBJ round trip through tobj, streaming, PNG, SVG, golden rasters.

use bcifs::eval::{EvalSettings, Evaluator};
use bcifs::export::{ObjWriter, RasterSettings, ascii, raster, svg};
use bcifs::geometry::Sink as _;

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
/// when any file of their directory is written; live ones are left alone.
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
    // Issue 23, item 16: a dead process's file of another target in the same directory goes too.
    assert!(!other.exists(), "another target's stale file is swept");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Density pictures of the chaos game (issue 11): the same seed gives the
/// same counts with 1 and 2 threads; the counts add up to the samples (the
/// frame, fitted on the first batch, holds at least 99.9% of them); a
/// picture over the memory limit is refused with what it needs.
#[test]
fn density_pictures_count_every_sample_once() {
    use bcifs::eval::{ChaosGame, RandomSettings};
    use bcifs::export::{RasterSettings, density_counts as density};
    let design = bcifs::builtin_design("fern").unwrap();
    let inst = bcifs::instantiate(&design, &[]).unwrap();
    let model = design.model().unwrap().clone();
    let points = 3_000_000;
    let raster = RasterSettings::default().with_size(200, 300);
    let counts = |threads: usize| {
        let mut settings = RandomSettings::default().with_points(1000).with_seed(5);
        settings.threads = Some(threads);
        let game = ChaosGame::new(&inst.automaton, &model, &settings).unwrap();
        density(&game, points, &raster, 2, None).unwrap()
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
    let e = density(&game, points, &small, 1, None).unwrap_err().to_string();
    assert!(e.contains("4000×4000"), "{e}");
}

/// Counts carried past a byte (issue 29: a thread counts a cell in a byte
/// and carries 256 into a 32-bit count when it wraps; the coloured path
/// counts in 16-bit lanes and carries at 255): on pictures so small that
/// cells get from a few to a million samples, the plain and the coloured
/// counts of the same samples agree cell by cell, with one thread and two,
/// and add up to the samples in the frame.
#[test]
fn density_counts_carry_past_a_byte() {
    use bcifs::eval::{ChaosGame, RandomSettings};
    use bcifs::export::{Palette, RasterSettings, density_counts as density};
    let fire = Palette::named("fire").unwrap();
    for (name, (w, h), s) in [("fern", (37, 53), 1), ("gasket", (2, 2), 1), ("gasket", (64, 64), 3)] {
        let design = bcifs::builtin_design(name).unwrap();
        let inst = bcifs::instantiate(&design, &[]).unwrap();
        let model = design.model().unwrap().clone();
        let points = 2_500_000;
        let raster = RasterSettings::default().with_size(w, h);
        let run = |threads: usize, palette: Option<&Palette>| {
            let settings = RandomSettings::default().with_points(1000).with_seed(11).with_threads(threads);
            let game = ChaosGame::new(&inst.automaton, &model, &settings).unwrap();
            density(&game, points, &raster, s, palette).unwrap().counts
        };
        let plain = run(1, None);
        assert_eq!(plain, run(2, None), "{name}: one thread and two");
        assert_eq!(plain, run(1, Some(&fire)), "{name}: the plain and the coloured counts");
        assert_eq!(plain, run(2, Some(&fire)), "{name}: the coloured counts with two threads");
        let total: u64 = plain.iter().map(|&c| u64::from(c)).sum();
        assert!(total as f64 >= 0.999 * points as f64 && total <= points as u64, "{name}: {total}");
        let most = plain.iter().max().copied().unwrap_or(0);
        assert!(most > 256, "{name}: some cell carries ({most})");
        assert!(plain.iter().any(|&c| c % 256 != 0 && c > 256), "{name}: a carried cell has a low byte too");
    }
}

/// Colour by the last map (issue 11), checked where the answer is known:
/// with colour speed 1 a sample's colour coordinate is that of the last
/// arrow applied, and the gasket's part towards corner `i` is the image of
/// map `T_i`, so every cell there has exactly `T_i`'s palette colour. The
/// same seed gives the same colour sums with 1 and 2 threads.
#[test]
fn density_colours_follow_the_last_map() {
    use bcifs::eval::{ChaosGame, RandomSettings};
    use bcifs::export::{Palette, RasterSettings, density_counts as density};
    let design = bcifs::builtin_design("gasket").unwrap();
    let inst = bcifs::instantiate(&design, &[]).unwrap();
    let model = design.model().unwrap().clone();
    let palette = Palette::named("rainbow").unwrap();
    let raster = RasterSettings::default().with_size(240, 240);
    let run = |threads: usize, speed: f64| {
        let mut settings = RandomSettings::default().with_points(1000).with_seed(3).with_threads(threads);
        settings.colour_speed = speed;
        settings.colours = vec![("T0".into(), 0.0), ("T1".into(), 0.5), ("T2".into(), 1.0)];
        let game = ChaosGame::new(&inst.automaton, &model, &settings).unwrap();
        density(&game, 2_000_000, &raster, 1, Some(&palette)).unwrap()
    };
    let (one, two) = (run(1, 1.0), run(2, 1.0));
    assert_eq!(one, two, "the same colours with any number of threads");
    assert_eq!(one.shift, 0);
    let colour_of = |c: f32| palette.at(c).map(u32::from);
    let (mut checked, w) = (0, one.width);
    for (i, (&n, sum)) in one.counts.iter().zip(&one.colours).enumerate() {
        if n == 0 {
            continue;
        }
        // Pixel (x, y), y down: the lower left sixth belongs to T0's part, the
        // lower right to T1's, the top to T2's (the frame is the triangle's box).
        let (x, y) = ((i % w) as f64 / w as f64, (i / w) as f64 / w as f64);
        let expected = match (x, y) {
            (x, y) if y > 0.62 && x < 0.4 => Some(colour_of(0.0)),
            (x, y) if y > 0.62 && x > 0.6 => Some(colour_of(0.5)),
            (x, y) if y < 0.38 && (0.38..0.62).contains(&x) => Some(colour_of(1.0)),
            _ => None,
        };
        if let Some(e) = expected {
            assert_eq!(*sum, e.map(|c| c * n), "cell {i} ({x:.2}, {y:.2}) of {n} samples");
            checked += 1;
        }
    }
    assert!(checked > 3000, "{checked} cells checked");
    // At speed 1/2 the colours blend: most cells are not one map's colour.
    let blended = run(1, 0.5);
    let pure = [0.0, 0.5, 1.0].map(colour_of);
    let mixed = blended
        .counts
        .iter()
        .zip(&blended.colours)
        .filter(|(n, s)| **n > 0 && !pure.iter().any(|p| p.map(|c| c * **n) == **s));
    assert!(mixed.count() > blended.counts.iter().filter(|n| **n > 0).count() / 2);
}

/// Tone mapping with a palette (issue 11): vibrancy 1 keeps each pixel's
/// hue (its channels in the ratios of its mean colour over a black
/// background), the density-estimation blur keeps the samples' mass and
/// spreads sparse ones (more pixels inked, the dense core unchanged in
/// total), and the settings that change the picture change it.
#[test]
fn density_tone_mapping_keeps_hues_and_mass() {
    use bcifs::eval::{ChaosGame, RandomSettings};
    use bcifs::export::{Palette, RasterSettings, Tone, density_counts as density};
    let design = bcifs::builtin_design("fern").unwrap();
    let inst = bcifs::instantiate(&design, &[]).unwrap();
    let model = design.model().unwrap().clone();
    let game = ChaosGame::new(&inst.automaton, &model, &RandomSettings::default().with_points(1000)).unwrap();
    let palette = Palette::named("sunset").unwrap();
    let dens = density(&game, 20_000, &RasterSettings::default().with_size(200, 200), 1, Some(&palette)).unwrap();
    let tone = Tone::default();
    let img = dens.image(&tone);
    let mut checked = 0;
    for (i, px) in img.pixels().enumerate() {
        let n = dens.counts[i];
        if n < 3 {
            continue;
        }
        let mean = dens.colours[i].map(|c| f64::from(c) / f64::from(n));
        let v = f64::from(px[0].max(px[1]).max(px[2])) / mean.iter().copied().fold(0.0, f64::max);
        for k in 0..3 {
            // Each channel is 255 · mean · v rounded: within 1 of the hue's ratio.
            assert!((f64::from(px[k]) - mean[k] * v).abs() <= 1.5, "pixel {i}: {px:?} vs mean {mean:?}");
        }
        checked += 1;
    }
    assert!(checked > 100, "{checked}");
    let inked = |img: &image::RgbImage| img.pixels().filter(|p| p.0 != [0, 0, 0]).count();
    let blurred = dens.image(&Tone { blur: 4.0, ..tone });
    assert!(inked(&blurred) > inked(&img) * 3 / 2, "{} vs {}", inked(&blurred), inked(&img));
    let flat = dens.image(&Tone { vibrancy: 0.0, ..tone });
    assert_ne!(flat, img, "vibrancy changes the picture");
    let white = dens.image(&Tone { background: Some([255; 3]), ..tone });
    assert_eq!(white.get_pixel(0, 0).0, [255; 3]);
}

/// Palettes by name (256 colours through their stops), from a picture's
/// middle row, and a clear error for neither.
#[test]
fn palettes_from_names_and_pictures() {
    use bcifs::export::Palette;
    for name in Palette::names() {
        let p = Palette::named(name).unwrap();
        assert_eq!(p.0.len(), 256, "{name}");
    }
    let fire = Palette::named("fire").unwrap();
    assert_eq!((fire.0[0], fire.0[255]), ([110, 0, 0], [255, 240, 150]));
    let dir = std::env::temp_dir().join(format!("bcifs-palette-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let strip =
        image::RgbImage::from_fn(64, 3, |x, y| image::Rgb(if y == 1 { [x as u8 * 4, 0, 255] } else { [9, 9, 9] }));
    let path = dir.join("strip.png");
    strip.save(&path).unwrap();
    let p = Palette::parse(path.to_str().unwrap()).unwrap();
    assert_eq!((p.0[0], p.0[4], p.0[255]), ([0, 0, 255], [4, 0, 255], [252, 0, 255]));
    let e = Palette::parse("no-such-palette").unwrap_err();
    assert!(e.contains("fire") && e.contains("no-such-palette"), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Deterministic pictures drawn while evaluating (issue 11): for curves
/// (open, closed, a union), and for point sets, the streamed picture is
/// the picture of the evaluated shape, pixel for pixel; a surface is left
/// to the in-memory path, at the depth whose quads outnumber the pixels.
#[test]
fn streamed_pictures_equal_the_in_memory_ones() {
    use bcifs::eval::{Depth, EvalSettings, Evaluator};
    use bcifs::export::{RasterSettings, raster, stream_picture};
    use bcifs::render::picture_depth;
    let picture = |ev: &Evaluator, settings| {
        let lines = ev.polylines()?;
        Some(stream_picture(lines, |sink| ev.stream(sink).map_err(bcifs::render::RenderError::from), settings).unwrap())
    };
    let raster_settings = RasterSettings::default().with_size(300, 200).with_view(20.0, 30.0);
    let cases =
        [("levy", 12, true), ("koch", 5, true), ("snowflake", 4, true), ("bezier-union", 5, true), ("fern", 7, false)];
    for (name, depth, lines) in cases {
        let design = match name {
            "snowflake" => bcifs::schemes::normal_preset(name).unwrap().design().unwrap(),
            "bezier-union" => bcifs::schemes::ifs_preset(name, None, None).unwrap(),
            _ => bcifs::builtin_design(name).unwrap(),
        };
        let inst = bcifs::instantiate(&design, &[]).unwrap();
        let model = design.model().unwrap().clone();
        let mut settings = EvalSettings::default();
        settings.depth = Depth::Fixed(depth);
        let ev = Evaluator::new(&inst.automaton, &model, settings).unwrap();
        assert_eq!(ev.polylines(), Some(lines), "{name}");
        let shape = ev.evaluate().unwrap();
        let (streamed, vertices) = picture(&ev, &raster_settings).expect("curves and points stream");
        assert_eq!(vertices, shape.vertex_count(), "{name}");
        let in_memory = raster(&shape, &raster_settings).unwrap();
        assert!(streamed == in_memory, "{name}: the streamed picture differs");
        let inked = streamed.pixels().filter(|p| p.0 != [255; 3]).count();
        assert!(inked > 200, "{name}: {inked} pixels inked");
    }
    let design = bcifs::builtin_design("doo_sabin_torus").unwrap();
    let inst = bcifs::instantiate(&design, &[]).unwrap();
    let ev = Evaluator::new(&inst.automaton, design.model().unwrap(), EvalSettings::default()).unwrap();
    assert!(picture(&ev, &raster_settings).is_none(), "surfaces are drawn from memory");
    // 64 patches: 4^5 · 64 = 65536 quads ≥ 300 · 200 pixels > 4^4 · 64.
    assert_eq!(picture_depth(&ev, &raster_settings, 12), 5);
    assert_eq!(picture_depth(&ev, &raster_settings, 3), 3);
}

/// OBJ text formatted in parallel is the text formatted on one thread,
/// byte for byte (issue 11); with `--precision 5` the file is smaller and
/// every coordinate reads back within half a unit of its fifth digit.
#[test]
fn obj_formatting_in_parallel_and_to_a_precision() {
    let (a, model, _) = load("doo_sabin_torus", &[]);
    let ev = Evaluator::new(&a, &model, EvalSettings::default().with_depth(5)).unwrap();
    let shape = ev.evaluate().unwrap();
    assert!(shape.vertex_count() > 8192 * 4, "large enough to be split");
    // A directory of its own: another test counts the temporary files of `temp`'s.
    let dir = temp("parallel");
    std::fs::create_dir_all(&dir).unwrap();
    let write = |name: &str, threads: usize, digits: Option<u32>| {
        let path = dir.join(name);
        let mut w = ObjWriter::create(&path).unwrap().with_threads(threads).unwrap().with_precision(digits);
        ev.stream(&mut w).unwrap();
        w.finish().unwrap();
        std::fs::read(&path).unwrap()
    };
    let (one, two, three) = (write("one.obj", 1, None), write("two.obj", 2, None), write("three.obj", 3, None));
    assert!(one == two && one == three, "the same text with 1, 2 and 3 threads");
    // The whole shape in one call per kind: cut into pieces formatted on the
    // pool's threads while the finished ones are written, in order.
    let replayed = |name: &str, threads: usize| {
        let path = dir.join(name);
        let mut w = ObjWriter::create(&path).unwrap().with_threads(threads).unwrap();
        shape.replay(&mut w).unwrap();
        w.finish().unwrap();
        std::fs::read(&path).unwrap()
    };
    let serial = replayed("replayed1.obj", 1);
    assert!(serial == replayed("replayed2.obj", 2) && serial == replayed("replayed5.obj", 5));
    // Told that every vertex is written, the writer puts the elements in
    // place instead of in its side file: the same bytes; a vertex after that is refused.
    let quads: Vec<[usize; 4]> = shape.quads.iter().map(|q| q.map(|v| v as usize)).collect();
    let sealed = |name: &str, seal: bool| {
        let path = dir.join(name);
        let mut w = ObjWriter::create(&path).unwrap().with_threads(2).unwrap();
        w.object("torus").unwrap();
        w.vertices(3, &shape.positions, None).unwrap();
        if seal {
            w.vertices_complete().unwrap();
        }
        w.group("all").unwrap();
        w.faces(&quads, None).unwrap();
        if seal {
            assert!(w.vertices(3, &shape.positions[..3], None).is_err(), "a vertex after the faces");
        }
        w.finish().unwrap();
        std::fs::read(&path).unwrap()
    };
    assert!(sealed("spooled.obj", false) == sealed("in_place.obj", true));
    let short = write("short.obj", 2, Some(5));
    assert!(short.len() < one.len() * 3 / 4, "{} vs {} bytes", short.len(), one.len());
    let (models, _) = tobj::load_obj(
        dir.join("short.obj"),
        &tobj::LoadOptions { single_index: false, triangulate: false, ..Default::default() },
    )
    .unwrap();
    let mesh = &models[0].mesh;
    assert_eq!(mesh.positions.len(), shape.positions.len());
    for (k, &i) in shape.quads.iter().flatten().enumerate() {
        let (i, j) = (i as usize, mesh.indices[k] as usize);
        let p = &shape.positions[3 * i..3 * i + 3];
        for (got, want) in mesh.positions[3 * j..3 * j + 3].iter().zip([p[0], p[2], -p[1]]) {
            assert!((got - want).abs() <= 5e-5 * want.abs() * 1.000_001, "corner {k}: {got} vs {want}");
        }
    }
}

/// Vertices, then elements, in two streamed passes (no side file): the
/// same bytes as one pass through the writer's spool, for a surface and a
/// curve, and the counts of what was written.
#[test]
fn two_pass_obj_equals_the_spooled_one() {
    let dir = temp("two-pass");
    std::fs::create_dir_all(&dir).unwrap();
    for (name, depth) in [("doo_sabin_torus", 4), ("levy", 10)] {
        let (a, model, _) = load(name, &[]);
        let ev = Evaluator::new(&a, &model, EvalSettings::default().with_depth(depth)).unwrap();
        let (one, two) = (dir.join(format!("{name}-1.obj")), dir.join(format!("{name}-2.obj")));
        let mut w = ObjWriter::create(&one).unwrap();
        ev.stream(&mut w).unwrap();
        w.finish().unwrap();
        let mut w = ObjWriter::create(&two).unwrap();
        let (vertices, faces) = bcifs::export::write_two_passes(&mut w, |sink| ev.stream(sink), None).unwrap();
        w.finish().unwrap();
        assert!(std::fs::read(&one).unwrap() == std::fs::read(&two).unwrap(), "{name}");
        let shape = ev.evaluate().unwrap();
        assert_eq!((vertices, faces), (shape.vertex_count(), shape.quads.len()), "{name}");
    }
}

/// A 3D chaos game seen from a view (issue 11): every sample lands in the
/// frame fitted on the first batch (but a few), the same counts with one
/// thread or two, and the picture turns with the view.
#[test]
fn density_of_a_surface_patch_in_3d() {
    use bcifs::eval::{ChaosGame, RandomSettings};
    use bcifs::export::{RasterSettings, density_counts as density};
    let design = bcifs::schemes::ifs_preset("box-spline", None, None).unwrap();
    let inst = bcifs::instantiate(&design, &[]).unwrap();
    let model = design.model().unwrap().clone();
    assert_eq!(model.points[0].len(), 3);
    let run = |threads: usize, yaw: f64| {
        let game =
            ChaosGame::new(&inst.automaton, &model, &RandomSettings::default().with_points(1000).with_threads(threads))
                .unwrap();
        density(&game, 500_000, &RasterSettings::default().with_size(160, 120).with_view(yaw, 35.0), 1, None).unwrap()
    };
    let (one, two) = (run(1, 30.0), run(2, 30.0));
    assert_eq!(one, two);
    let total: u64 = one.counts.iter().map(|&c| u64::from(c)).sum();
    assert!(total as f64 >= 0.999 * 500_000.0, "{total}");
    assert_ne!(run(1, 75.0).counts, one.counts, "another view, another picture");
}

/// Issue 23, item 2: a shape of several triangle meshes (the gallery's
/// icosahedron textures) writes each object's faces after its own `o` line,
/// so an importer makes one object per mesh, each with its own faces.
#[test]
fn each_object_keeps_its_triangles() {
    use bcifs::geometry::{Shape, Sink};
    let ico = bcifs::mesh::PolyMesh::icosahedron();
    let one = ico.limit(bcifs::mesh::Scheme::Loop, 1).unwrap();
    let mut all = Shape::default();
    for k in 0..3 {
        let first = all.vertex_count();
        let moved: Vec<f64> = one.positions.chunks_exact(3).flat_map(|p| [p[0] + 3.0 * k as f64, p[1], p[2]]).collect();
        let triangles: Vec<[usize; 3]> = one.triangles.iter().map(|t| t.map(|v| first + v)).collect();
        all.object(&format!("piece{k}")).unwrap();
        all.vertices(3, &moved, None).unwrap();
        all.triangles(&triangles).unwrap();
    }
    let path = temp("pieces.obj");
    let mut w = ObjWriter::create(&path).unwrap();
    all.replay(&mut w).unwrap();
    w.finish().unwrap();
    let (models, _) = tobj::load_obj(&path, &tobj::LoadOptions::default()).unwrap();
    assert_eq!(models.len(), 3, "one model per object");
    for (k, m) in models.iter().enumerate() {
        assert_eq!(m.name, format!("piece{k}"));
        assert_eq!(m.mesh.indices.len(), 3 * one.triangles.len(), "{}: its own triangles", m.name);
        // Every vertex of the piece lies in its own slot along x.
        let xs = m.mesh.positions.chunks_exact(3).map(|p| p[0] - 3.0 * k as f64);
        assert!(xs.into_iter().all(|x| x.abs() < 1.5), "{}: faces of another piece", m.name);
    }
    std::fs::remove_file(&path).unwrap();
}
