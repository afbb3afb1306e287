//! The exact solver on the shipped systems (issue: quad patch well under a second).

use criterion::{Criterion, criterion_group, criterion_main};

fn solve_benches(c: &mut Criterion) {
    for name in ["corner_cutting", "doo_sabin_quad"] {
        let design = bcifs::builtin_design(name).expect("shipped");
        c.bench_function(&format!("solve/{name}"), |b| {
            b.iter(|| bcifs::solve(std::hint::black_box(&design)).expect("consistent"))
        });
    }
    // Issue 29: the generated Catmull-Clark automaton of Suzanne (312 states, 2,055
    // constraints), parsed and solved from its text as `bcifs solve` does (target ≤ 0.3 s).
    let suzanne =
        bcifs::mesh::read_mesh(std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/suzanne.obj")))
            .expect("shipped mesh");
    let automaton =
        bcifs::schemes::mesh_automaton(&suzanne, bcifs::mesh::Scheme::CatmullClark, None).expect("generates");
    let suzanne_text = bcifs::write_design(&automaton);
    let mut g = c.benchmark_group("suzanne_catmull_clark");
    g.sample_size(10);
    g.bench_function("parse+solve", |b| {
        b.iter(|| {
            let design = bcifs::parse_design(&suzanne_text, "s", "s").expect("parses");
            bcifs::solution(&design).as_ref().as_ref().expect("consistent").dof()
        })
    });
    // `bcifs check`: parsed, solved, instantiated at the defaults, checked (its joint spectral
    // radius bounds included).
    g.bench_function("parse+check", |b| {
        b.iter(|| {
            let design = bcifs::parse_design(&suzanne_text, "s", "s").expect("parses");
            let instance = bcifs::instantiate(&design, &[]).expect("defaults");
            bcifs::analysis::check(&instance.automaton, &instance.values, bcifs::analysis::DEFAULT_CHECK_TOLERANCE)
                .expect("checks")
        })
    });
    g.finish();
    // The Loop automaton of an irregular closed mesh of 5,120 triangles (852 states,
    // 6,585 constraints), parsed and solved, then checked: the "bunny".
    let irregular = bcifs::mesh::read_mesh(std::path::Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/irregular5120.obj"
    )))
    .expect("shipped mesh");
    let design = bcifs::schemes::mesh_automaton(&irregular, bcifs::mesh::Scheme::Loop, None).expect("generates");
    let irregular_text = bcifs::write_design(&design);
    let instance = bcifs::instantiate(&design, &[]).expect("defaults");
    let mut g = c.benchmark_group("irregular5120_loop");
    g.sample_size(10);
    g.bench_function("parse+solve", |b| {
        b.iter(|| bcifs::solve(&bcifs::parse_design(&irregular_text, "i", "i").expect("parses")).expect("consistent"))
    });
    g.bench_function("check", |b| {
        b.iter(|| {
            bcifs::analysis::check(&instance.automaton, &instance.values, bcifs::analysis::DEFAULT_CHECK_TOLERANCE)
                .expect("checks")
        })
    });
    g.finish();
    let text = bcifs::write_design(&bcifs::schemes::quad_patch(false).expect("generates"));
    c.bench_function("parse+solve/quad_patch_general", |b| {
        b.iter(|| bcifs::solve(&bcifs::parse_design(&text, "q", "q").expect("parses")).expect("consistent"))
    });
}

/// Issue 14 targets: the check of the corner cutting answers in under 50 ms
/// at any point; a 256 × 256 verdict map of its triangle takes seconds (a
/// 64 × 64 map here, 1/16 of the pixels).
fn convergence_benches(c: &mut Criterion) {
    let family = bcifs::solve(&bcifs::builtin_design("corner_cutting").expect("shipped")).expect("consistent");
    let mut g = c.benchmark_group("convergence");
    g.sample_size(10);
    // The slowest points seen: near the divergence boundary, and a point the paper gets wrong.
    for (a, b) in [(-0.3, 0.45), (-0.9, 0.95), (0.25, 0.25)] {
        let instance = family.instantiate(&[("a".into(), a), ("b".into(), b)]).expect("values");
        g.bench_function(format!("check/corner_cutting_a{a}_b{b}"), |bench| {
            bench.iter(|| {
                bcifs::analysis::check(std::hint::black_box(&instance.automaton), &instance.values, 1e-9)
                    .expect("checks")
            })
        });
    }
    let plane =
        bcifs::analysis::ParameterPlane { x: ("a".into(), -1.0, 2.0), y: ("b".into(), -1.0, 2.0), size: (64, 64) };
    g.bench_function("verdict_map/corner_cutting_64x64_quick", |bench| {
        bench.iter(|| {
            bcifs::analysis::verdict_map(&family, &plane, &bcifs::analysis::JsrSettings::quick()).expect("map")
        })
    });
    // Issue 16: a 512 × 512 curve map (regions, half-tangents and verdicts at every pixel) under 2 s.
    let plane =
        bcifs::analysis::ParameterPlane { x: ("a".into(), -1.0, 1.0), y: ("b".into(), -1.0, 1.0), size: (512, 512) };
    g.bench_function("curve_map/corner_cutting_512x512_quick", |bench| {
        bench.iter(|| {
            bcifs::analysis::curve_map(&family, &plane, &bcifs::analysis::JsrSettings::quick(), "e").expect("map")
        })
    });
    g.finish();
}

// Criterion's plots use plotters, whose `ab_glyph` fonts (enabled for the
// command line's plots) are registered by bcifs only: no plots here.
criterion_group! {
    name = benches;
    config = Criterion::default().without_plots();
    targets = solve_benches, convergence_benches
}
criterion_main!(benches);
