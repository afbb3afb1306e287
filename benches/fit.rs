//! Issue 47: time per fit. Members rendered at known parameters fitted back
//! from the defaults (noise-free, so each ends exactly), with one evaluation
//! of the same points as the baseline measured in the same run; a porosity
//! target against one measurement of the porosity.

use criterion::{Criterion, criterion_group, criterion_main};

fn fit_benches(c: &mut Criterion) {
    let mut g = c.benchmark_group("fit");
    g.sample_size(10);
    for (name, depth, params) in [
        ("corner_cutting", 6, vec![("a", 0.1), ("b", 0.35)]),
        ("doo_sabin_torus", 2, vec![("alpha", 0.62), ("beta", 0.13), ("gamma", 0.2)]),
    ] {
        let design = bcifs::render::load(name).expect("shipped");
        let params: Vec<(String, f64)> = params.iter().map(|(n, v)| (n.to_string(), *v)).collect();
        let options = bcifs::render::Options { params, ..Default::default() }.with_depth(depth);
        let evaluate = || bcifs::render::evaluate_design(&design, &options, &mut Vec::new()).expect("evaluates");
        let target = bcifs::fit::FitTarget { points: evaluate().points(), ..Default::default() };
        g.bench_function(format!("{name}/evaluate"), |b| b.iter(evaluate));
        g.bench_function(format!("{name}/fit"), |b| {
            b.iter(|| bcifs::fit::fit(&design, &target, &bcifs::fit::FitOptions::default()).expect("fits"))
        });
    }
    let cantor = bcifs::render::load("cantor").expect("shipped");
    let dimension = bcifs::fit::FitTarget { dimension: Some(0.5), ..Default::default() };
    g.bench_function("cantor/dimension", |b| {
        b.iter(|| bcifs::fit::fit(&cantor, &dimension, &bcifs::fit::FitOptions::default()).expect("fits"))
    });
    // A number on a lace: the carpet's porosity from 0.16 (its defaults) to 0.5, against one
    // measurement of it.
    let carpet = bcifs::render::load("carpet").expect("shipped");
    let porosity = bcifs::fit::FitTarget { porosity: Some(0.5), ..Default::default() };
    g.bench_function("carpet/porosity-measure", |b| {
        b.iter(|| bcifs::report::porosity(&carpet, &[], 1).expect("measures"))
    });
    g.bench_function("carpet/porosity", |b| {
        b.iter(|| bcifs::fit::fit(&carpet, &porosity, &bcifs::fit::FitOptions::default()).expect("fits"))
    });
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().without_plots();
    targets = fit_benches
}
criterion_main!(benches);
