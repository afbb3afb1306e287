//! The exact solver on the shipped systems (issue: quad patch well under a second).

use criterion::{Criterion, criterion_group, criterion_main};

fn solve_benches(c: &mut Criterion) {
    for name in ["corner_cutting", "doo_sabin_quad"] {
        let design = bcifs::builtin_design(name).expect("shipped");
        c.bench_function(&format!("solve/{name}"), |b| {
            b.iter(|| bcifs::solve(std::hint::black_box(&design)).expect("consistent"))
        });
    }
    let text = bcifs::write_design(&bcifs::schemes::quad_patch(false).expect("generates"));
    c.bench_function("parse+solve/quad_patch_general", |b| {
        b.iter(|| bcifs::solve(&bcifs::parse_design(&text, "q", "q").expect("parses")).expect("consistent"))
    });
}

criterion_group!(benches, solve_benches);
criterion_main!(benches);
