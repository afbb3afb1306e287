//! The local corner-cutting curve of Sokolov et al. 2010 §3 built in code: the same
//! design as `automata/corner_cutting.toml`, solved exactly, instantiated
//! at the parameters you pick, evaluated and written as OBJ.
//!
//! `cargo run --release --example corner_cutting -- A B DEPTH OUT.obj`
//! (defaults: `1/4 1/4 8 corner_cutting.obj`, Chaikin's scheme).

use bcifs::eval::{EvalSettings, Evaluator};
use bcifs::{CellKind, Design, Layout, Model};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let number = |i: usize, default: f64| -> Result<f64, Box<dyn std::error::Error>> {
        match args.get(i) {
            None => Ok(default),
            Some(text) => Ok(bcifs::algebra::Surd::parse(text)?.to_f64()),
        }
    };
    let (a, b) = (number(0, 0.25)?, number(1, 0.25)?);
    let depth: usize = args.get(2).map_or(Ok(8), |s| s.parse())?;
    let out = args.get(3).map_or("corner_cutting.obj", String::as_str);

    // An edge with 3 control points whose ends are vertices with 2: the two
    // halves T0, T1 and the vertex rule Tv are unknown; the constraints say
    // that the halves meet and that the ends subdivide as vertices.
    let hexagon = [[0.0, 0.0], [2.0, 0.0], [3.0, 1.5], [2.0, 3.0], [0.0, 3.0], [-1.0, 1.5]];
    let design = Design::builder("corner_cutting")
        .description("local corner-cutting curve, 3 control points, vertex support 2")
        .state("e", 3, CellKind::Edge)
        .state("v", 2, CellKind::Vertex)
        .unknown("T0", "e", "e")
        .unknown("T1", "e", "e")
        .unknown("Tv", "v", "v")
        .select("b0", "e", "v", [0, 1])
        .select("b1", "e", "v", [1, 2])
        .adjacency("T0 b1 = T1 b0")
        .incidence("T0 b0 = b0 Tv")
        .incidence("T1 b1 = b1 Tv")
        .name_entry("a", "T0[1][0]")
        .name_entry("b", "T0[0][1]")
        .model(Model::new("e", hexagon.iter().map(|p| p.to_vec()).collect()).with_layout(Layout::Closed))
        .build()?;

    let family = bcifs::solve(&design)?;
    println!("{}: free parameters {}", design.name(), family.parameter_names().join(", "));
    for (arrow, rows) in family.matrices_text() {
        println!("{arrow} = {rows:?}");
    }

    let instance = family.instantiate(&[("a".into(), a), ("b".into(), b)])?;
    let model = design.model().ok_or("the design has a model")?;
    let shape = Evaluator::new(&instance.automaton, model, EvalSettings::default().with_depth(depth))?.evaluate()?;
    bcifs::export::write_obj(&shape, design.name(), std::path::Path::new(out))?;
    println!("a = {a}, b = {b}, depth {depth}: {} vertices → {out}", shape.vertex_count());
    Ok(())
}
