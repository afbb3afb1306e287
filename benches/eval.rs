//! Evaluation and writing throughput against the targets (ratios to
//! a C baseline measured on this machine): Lévy depth 24 deterministic (1
//! and 2 threads), chaos game (one chain), Doo-Sabin 8×8 torus depth 8 in
//! memory, OBJ text rate, evaluation + OBJ together, and obj-exporter vs
//! the streaming writer on the same triangle mesh; the Menger sponge's
//! boundary mesh to STL, 3MF and PLY.

use std::hint::black_box;

use bcifs::eval::{ChaosGame, EvalSettings, Evaluator, RandomSettings};
use bcifs::export::ObjWriter;
use bcifs::geometry::Sink;
use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};

fn setup(name: &str) -> (bcifs::Automaton<f64>, bcifs::Model) {
    let design = bcifs::builtin_design(name).expect("shipped");
    let instance = bcifs::instantiate(&design, &[]).expect("instantiates");
    (instance.automaton, design.model().cloned().expect("model"))
}

fn levy(c: &mut Criterion) {
    let (a, model) = setup("levy");
    let mut g = c.benchmark_group("levy_depth24");
    g.sample_size(10);
    g.throughput(Throughput::Elements(1 << 24));
    for threads in [1, 2] {
        let ev = Evaluator::new(&a, &model, EvalSettings::default().with_depth(24).with_threads(threads))
            .expect("evaluable");
        let mut buf = Vec::new();
        ev.fill_piece(0, 24, &mut buf);
        g.bench_with_input(BenchmarkId::new("threads", threads), &threads, |b, _| {
            b.iter(|| ev.fill_piece(0, 24, black_box(&mut buf)))
        });
    }
    g.finish();
}

fn chaos(c: &mut Criterion) {
    let mut g = c.benchmark_group("chaos_game");
    g.sample_size(10);
    let n = 1 << 24;
    g.throughput(Throughput::Elements(n as u64));
    for name in ["levy", "fern"] {
        let (a, model) = setup(name);
        let game = ChaosGame::new(&a, &model, &RandomSettings::default().with_points(n).with_chains(1).with_threads(1))
            .expect("ok");
        let mut buf = Vec::new();
        game.run_into(&mut buf);
        g.bench_function(BenchmarkId::new("one_chain", name), |b| b.iter(|| game.run_into(black_box(&mut buf))));
    }
    // Issue 11: samples counted into a 1024² density picture, never stored (one thread,
    // then two): the fern in ink, the gasket coloured by its maps (flam3's benchmark).
    let raster = bcifs::export::RasterSettings::default().with_size(1024, 1024);
    let fire = bcifs::export::Palette::named("fire");
    // Issue 29: the gasket into a 4096² picture (16 MiB of byte counts per thread, 128 MiB
    // of colour lanes: those miss the caches), one thread, ink and coloured.
    let large = bcifs::export::RasterSettings::default().with_size(4096, 4096);
    for (name, palette) in [("gasket", None), ("gasket_colour", fire.as_ref())] {
        let (a, model) = setup("gasket");
        let settings = RandomSettings::default().with_points(1 << 16).with_threads(1);
        let game = ChaosGame::new(&a, &model, &settings).expect("ok");
        g.bench_function(BenchmarkId::new("density_4096_threads_1", name), |b| {
            b.iter(|| bcifs::export::density_counts(&game, n, &large, 1, palette).expect("fits"))
        });
    }
    for (name, palette) in [("fern", None), ("gasket_colour", fire.as_ref())] {
        let (a, model) = setup(name.trim_end_matches("_colour"));
        for threads in [1, 2] {
            let settings = RandomSettings::default().with_points(1 << 16).with_threads(threads);
            let game = ChaosGame::new(&a, &model, &settings).expect("ok");
            g.bench_function(BenchmarkId::new(format!("density_1024_{name}_threads"), threads), |b| {
                b.iter(|| bcifs::export::density_counts(&game, n, &raster, 1, palette).expect("fits"))
            });
        }
    }
    g.finish();
}

fn doo_sabin(c: &mut Criterion) {
    let (a, model) = setup("doo_sabin_torus");
    let mut g = c.benchmark_group("doo_sabin_torus8x8_depth8");
    g.sample_size(10);
    g.throughput(Throughput::Elements(64 << 16));
    for threads in [1, 2] {
        let ev =
            Evaluator::new(&a, &model, EvalSettings::default().with_depth(8).with_threads(threads)).expect("evaluable");
        g.bench_with_input(BenchmarkId::new("in_memory_threads", threads), &threads, |b, _| {
            b.iter_with_large_drop(|| ev.evaluate().expect("fits"))
        });
        // Re-evaluation into the same buffers (a designer changing a parameter):
        // no allocation, no page faults.
        let mut shape = ev.evaluate().expect("fits");
        g.bench_with_input(BenchmarkId::new("in_memory_reused_threads", threads), &threads, |b, _| {
            b.iter(|| ev.evaluate_into(black_box(&mut shape)).expect("fits"))
        });
    }
    g.finish();
}

fn obj(c: &mut Criterion) {
    let dir = std::env::temp_dir().join("bcifs-bench");
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join("bench.obj");
    let (a, model) = setup("doo_sabin_torus");
    let ev = Evaluator::new(&a, &model, EvalSettings::default().with_depth(6)).expect("evaluable");
    let shape = ev.evaluate().expect("fits");
    // The streaming writer takes usize indices; widen once, outside the timings.
    let wide = |v: &[bcifs::geometry::Quad]| v.iter().map(|q| q.map(|i| i as usize)).collect::<Vec<_>>();
    let (quads, quad_uvs) = (wide(&shape.quads), wide(&shape.quad_uvs));
    let write_with = |shape: &bcifs::geometry::Shape, threads: usize, digits: Option<u32>| {
        let mut w =
            ObjWriter::create(&path).expect("create").with_threads(threads).expect("threads").with_precision(digits);
        w.object("torus").expect("write");
        w.uvs(&shape.uvs).expect("write");
        w.vertices(shape.dim, &shape.positions, Some(&shape.normals)).expect("write");
        w.faces(&quads, (!quad_uvs.is_empty()).then_some(&quad_uvs[..])).expect("write");
        w.finish().expect("finish");
    };
    let write_shape = |shape: &bcifs::geometry::Shape| write_with(shape, 1, None);
    write_shape(&shape);
    let bytes = std::fs::metadata(&path).expect("written").len();
    let mut g = c.benchmark_group("obj");
    g.sample_size(10);
    g.throughput(Throughput::Bytes(bytes));
    g.bench_function("write_only/torus_depth6", |b| b.iter(|| write_shape(&shape)));
    // Issue 11: formatting in parallel chunks, and 6 significant digits (throughput: the exact file's bytes).
    g.bench_function("write_only_2_threads/torus_depth6", |b| b.iter(|| write_with(&shape, 2, None)));
    g.bench_function("write_only_precision6/torus_depth6", |b| b.iter(|| write_with(&shape, 1, Some(6))));
    g.bench_function("evaluate_and_stream/torus_depth6", |b| {
        b.iter(|| {
            let mut w = ObjWriter::create(&path).expect("create");
            ev.stream(&mut w).expect("stream");
            w.finish().expect("finish");
        })
    });
    // The same triangle mesh through obj-exporter and through ObjWriter.
    let tris: Vec<[usize; 3]> = quads.iter().flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]]).collect();
    let set = obj_exporter::ObjSet {
        material_library: None,
        objects: vec![obj_exporter::Object {
            name: "torus".into(),
            vertices: shape
                .positions
                .chunks_exact(3)
                .map(|p| obj_exporter::Vertex { x: p[0], y: p[1], z: p[2] })
                .collect(),
            tex_vertices: vec![],
            normals: shape
                .normals
                .chunks_exact(3)
                .map(|p| obj_exporter::Vertex { x: p[0], y: p[1], z: p[2] })
                .collect(),
            geometry: vec![obj_exporter::Geometry {
                material_name: None,
                shapes: tris
                    .iter()
                    .map(|t| obj_exporter::Shape {
                        primitive: obj_exporter::Primitive::Triangle(
                            (t[0], None, Some(t[0])),
                            (t[1], None, Some(t[1])),
                            (t[2], None, Some(t[2])),
                        ),
                        groups: vec![],
                        smoothing_groups: vec![],
                    })
                    .collect(),
            }],
        }],
    };
    let tri_path = dir.join("triangles.obj");
    g.bench_function("triangles/obj_exporter", |b| {
        b.iter(|| obj_exporter::export_to_file(&set, &tri_path).expect("write"))
    });
    g.bench_function("triangles/bcifs_streaming", |b| {
        b.iter(|| {
            let mut w = ObjWriter::create(&tri_path).expect("create");
            w.object("torus").expect("write");
            w.vertices(3, &shape.positions, Some(&shape.normals)).expect("write");
            w.triangles(&tris).expect("write");
            w.finish().expect("finish");
        })
    });
    g.finish();
    let _ = std::fs::remove_dir_all(&dir);
}

/// Issue 13: a 2000 × 2000 picture fitted in under 1 s (threshold, tracing,
/// corners, fits): a star of 10 sides and a disc drawn side by side.
fn contour_fit(c: &mut Criterion) {
    let (w, h) = (2000usize, 2000usize);
    let star: Vec<[f64; 2]> = (0..10)
        .map(|k| {
            let t = 0.2 + k as f64 * std::f64::consts::PI / 5.0;
            let r = if k % 2 == 0 { 700.0 } else { 300.0 };
            [800.0 + r * t.cos(), 1000.0 + r * t.sin()]
        })
        .collect();
    let inside = |x: f64, y: f64| {
        let mut inside = (x - 1650.0).hypot(y - 1000.0) <= 250.0;
        for k in 0..star.len() {
            let (a, b) = (star[k], star[(k + 1) % star.len()]);
            if (a[1] > y) != (b[1] > y) && x < a[0] + (y - a[1]) / (b[1] - a[1]) * (b[0] - a[0]) {
                inside = !inside;
            }
        }
        inside
    };
    let grey: Vec<u8> = (0..w * h).map(|i| if inside((i % w) as f64, (i / w) as f64) { 0 } else { 255 }).collect();
    let mut g = c.benchmark_group("contour");
    g.sample_size(10);
    g.bench_function("fit_2000x2000", |b| {
        b.iter(|| bcifs::contour::fit_contour(std::hint::black_box(&grey), w, h, &Default::default()).expect("a shape"))
    });
    g.finish();
}

/// Binary PLY against OBJ text (issue 25's target: ≥ 1 GB/s), the same
/// depth-8 torus held in memory (1.05 M vertices with normals, 1.05 M quads):
/// throughput in the bytes of each file.
fn ply(c: &mut Criterion) {
    let dir = std::env::temp_dir().join("bcifs-bench");
    std::fs::create_dir_all(&dir).expect("temp dir");
    let (a, model) = setup("doo_sabin_torus");
    let ev = Evaluator::new(&a, &model, EvalSettings::default().with_depth(8)).expect("evaluable");
    let shape = ev.evaluate().expect("fits");
    let quads: Vec<[usize; 4]> = shape.quads.iter().map(|q| q.map(|i| i as usize)).collect();
    let fill = |w: &mut dyn bcifs::geometry::Sink| {
        w.object("torus").expect("write");
        w.vertices(shape.dim, &shape.positions, Some(&shape.normals)).expect("write");
        w.faces(&quads, None).expect("write");
    };
    let (ply_path, obj_path) = (dir.join("bench.ply"), dir.join("bench-ply.obj"));
    let write_ply = || {
        let mut w = bcifs::export::PlyWriter::create(&ply_path, false).expect("create");
        fill(&mut w);
        w.finish().expect("finish");
    };
    let write_obj = || {
        let mut w = ObjWriter::create(&obj_path).expect("create");
        fill(&mut w);
        w.finish().expect("finish");
    };
    write_ply();
    write_obj();
    let mut g = c.benchmark_group("ply");
    g.sample_size(10);
    g.throughput(Throughput::Bytes(std::fs::metadata(&ply_path).expect("written").len()));
    g.bench_function("binary/torus_depth8", |b| b.iter(write_ply));
    g.throughput(Throughput::Bytes(std::fs::metadata(&obj_path).expect("written").len()));
    g.bench_function("obj_text/torus_depth8", |b| b.iter(write_obj));
    g.finish();
}

/// Issue 45: the Menger sponge's boundary mesh at levels 3 and 4, evaluated
/// and written as binary STL, 3MF and PLY (the side-by-side against
/// manifold3d's boolean sponge is `benches/peers/menger.py`), and the smooth
/// sponge on a twisted tricubic B-spline lattice to STL beside the affine one
/// (`smooth_stl` against `boundary_stl`: within 2× at level 4).
fn menger(c: &mut Criterion) {
    let dir = std::env::temp_dir().join("bcifs-bench");
    std::fs::create_dir_all(&dir).expect("temp dir");
    let design = bcifs::builtin_design("menger").expect("shipped");
    let smooth = bcifs::render::load("tricubic-sponge").expect("preset");
    let mut g = c.benchmark_group("menger");
    g.sample_size(10);
    for level in [3usize, 4] {
        let options = bcifs::render::Options::default().with_depth(level);
        for ext in ["stl", "3mf", "ply"] {
            let path = dir.join(format!("menger.{ext}"));
            g.bench_function(BenchmarkId::new(format!("boundary_{ext}"), level), |b| {
                b.iter(|| bcifs::render::render(&design, &options, black_box(&path)).expect("written"))
            });
        }
        let path = dir.join("smooth.stl");
        g.bench_function(BenchmarkId::new("smooth_stl", level), |b| {
            b.iter(|| bcifs::render::render(&smooth, &options, black_box(&path)).expect("written"))
        });
    }
    g.finish();
}

// Criterion's plots use plotters, whose `ab_glyph` fonts (enabled for the
// command line's plots) are registered by bcifs only: no plots here.
criterion_group! {
    name = benches;
    config = Criterion::default().without_plots();
    targets = levy, chaos, doo_sabin, obj, ply, contour_fit, menger
}
criterion_main!(benches);
