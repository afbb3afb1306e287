//! Evaluates the Doo-Sabin torus of `automata/doo_sabin_torus.toml` in memory
//! and reports the mesh size: `cargo run --release --example mesh_torus -- DEPTH`.

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let depth: usize = std::env::args().nth(1).map_or(Ok(8), |s| s.parse())?;
    let design = bcifs::builtin_design("doo_sabin_torus").ok_or("shipped automaton")?;
    let instance = bcifs::instantiate(&design, &[])?;
    let model = design.model().cloned().ok_or("model")?;
    let ev = bcifs::eval::Evaluator::new(
        &instance.automaton,
        &model,
        bcifs::eval::EvalSettings::default().with_depth(depth),
    )?;
    let started = std::time::Instant::now();
    let shape = ev.evaluate()?;
    let seconds = started.elapsed().as_secs_f64();
    println!(
        "depth {depth}: {} vertices, {} quads in {seconds:.3} s ({:.1} M quads/s)",
        shape.vertex_count(),
        shape.quads.len(),
        shape.quads.len() as f64 / seconds / 1e6
    );
    if depth <= 6 {
        println!("Euler characteristic {}", shape.euler_characteristic());
    }
    Ok(())
}
