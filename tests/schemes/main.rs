//! Integration tests of the scheme generators against the papers' numbers.
#![allow(clippy::needless_range_loop)] // index loops mirror the formulas they check

mod cli;
mod contour;
mod errata;
#[path = "../common/hausdorff.rs"]
mod hausdorff;
mod ifs;
mod normal;
mod oracle;
mod patterns;
mod polyhedral;
mod printing;
mod solids;
mod ternary;
mod triangles;
mod volumes;

use bcifs::Design;
use bcifs::eval::{EvalSettings, Evaluator};
use bcifs::geometry::Shape;

/// Evaluates a design (default parameters) with its model to depth `k`.
pub fn evaluate(design: &Design, k: usize) -> Shape {
    let inst = bcifs::instantiate(design, &[]).expect("instantiates");
    let model = design.model().cloned().expect("model");
    Evaluator::new(&inst.automaton, &model, EvalSettings::default().with_depth(k).with_threads(1))
        .expect("evaluable")
        .evaluate()
        .expect("fits")
}

/// Polyline length.
pub fn length(points: &[[f64; 2]], closed: bool) -> f64 {
    let d = |a: [f64; 2], b: [f64; 2]| ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt();
    let open: f64 = points.windows(2).map(|w| d(w[0], w[1])).sum();
    if closed { open + d(points[points.len() - 1], points[0]) } else { open }
}

/// 2D points of a shape.
pub fn points2(shape: &Shape) -> Vec<[f64; 2]> {
    shape.points().iter().map(|p| [p[0], p[1]]).collect()
}

/// 3D points from 2D points.
pub fn lift(points: &[[f64; 2]]) -> Vec<[f64; 3]> {
    points.iter().map(|p| [p[0], p[1], 0.0]).collect()
}
