//! Integration tests of evaluation and export.
#![allow(clippy::needless_range_loop)] // index loops mirror the formulas they check

mod clients;
mod curves;
mod export;
mod fit;
mod formats;
mod gltf;
#[path = "../common/hausdorff.rs"]
mod hausdorff;
mod surfaces;

use bcifs::eval::{EvalSettings, Evaluator};
use bcifs::geometry::Shape;
use bcifs::{Design, Model, builtin_design, instantiate};

/// A shipped design instantiated with `params`, and its model.
pub fn load(name: &str, params: &[(&str, f64)]) -> (bcifs::Automaton<f64>, Model, Design) {
    let design = builtin_design(name).expect("shipped");
    let values: Vec<(String, f64)> = params.iter().map(|(n, v)| (n.to_string(), *v)).collect();
    let inst = instantiate(&design, &values).expect("instantiates");
    let model = design.model().cloned().expect("has a model");
    (inst.automaton, model, design)
}

/// Deterministic evaluation in memory.
pub fn eval(name: &str, params: &[(&str, f64)], settings: EvalSettings) -> Shape {
    let (a, model, _) = load(name, params);
    Evaluator::new(&a, &model, settings).expect("evaluable").evaluate().expect("fits")
}
