//! What `analyze dimension` finds, and the convergence ranges of a family's
//! parameters (the range of a front end's slider).

use serde_json::{Value, json};

use super::error::ReportError;
use crate::design::Design;
use crate::family::{instantiate, solve};
use crate::progress::Cancel;

/// What `analyze dimension` finds: the box-counting dimension of points
/// within `resolution` of the attractor, the similarity dimension and the
/// open set condition when the maps are similarities.
#[derive(Clone, Debug)]
pub struct DimensionReport {
    /// The design's name.
    pub automaton: String,
    /// The parameter values used.
    pub parameters: Vec<(String, f64)>,
    /// Points sampled.
    pub points: usize,
    /// Their distance to the attractor, at most.
    pub resolution: f64,
    /// The box-counting fit (`None`: not enough scales).
    pub fit: Option<crate::analysis::BoxCount>,
    /// The similarity dimension, when every map is a similarity.
    pub similarity: Option<f64>,
    /// The open set condition, when there is a similarity dimension.
    pub open_set: Option<crate::analysis::OpenSet>,
}

/// Serialised as [`DimensionReport::to_json`] makes it (its keys name the design's arrows).
impl serde::Serialize for DimensionReport {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        self.to_json().serialize(serializer)
    }
}

impl DimensionReport {
    /// The object `analyze dimension --json` prints.
    pub fn to_json(&self) -> Value {
        let parameters: serde_json::Map<String, Value> =
            self.parameters.iter().map(|(n, v)| (n.clone(), json!(v))).collect();
        let fit = self
            .fit
            .as_ref()
            .map(|f| json!({"r2": f.r2, "scales": f.scales.iter().map(|(e, n)| json!([e, n])).collect::<Vec<_>>()}));
        let open_set = self.open_set.as_ref();
        json!({
            "automaton": self.automaton, "parameters": parameters,
            "box_dimension": self.fit.as_ref().map(|f| f.dimension), "fit": fit,
            "similarity_dimension": self.similarity, "points": self.points,
            "open_set_condition": open_set.and_then(|o| o.holds),
            "open_set_reason": open_set.map(|o| o.reason.clone()),
            "similarity_dimension_is": open_set.map(|o| if o.holds == Some(true) { "the Hausdorff dimension" } else { "an upper bound of the Hausdorff dimension" }),
        })
    }
}

/// The memory of [`dimension_report`]: the default in-memory limit of meshes.
pub const DIMENSION_MEMORY: usize = crate::mesh::DEFAULT_MESH_MEMORY;

/// The dimensions of `design`'s attractor at `params` (see [`DimensionReport`]).
///
/// # Errors
/// Parameters that do not instantiate, no model, an evaluation error, an
/// empty attractor, points and boxes over [`DIMENSION_MEMORY`].
pub fn dimension_report(design: &Design, params: &[(String, f64)]) -> Result<DimensionReport, ReportError> {
    dimension_within(design, params, DIMENSION_MEMORY, &Cancel::new())
}

/// [`dimension_report`] within `memory` bytes (the points' evaluation and
/// the box keys, estimated before either is made), stopped when `cancel`
/// is set: what a server answering many requests calls.
///
/// # Errors
/// As [`dimension_report`]; [`ReportError::Eval`] with
/// [`crate::eval::EvalError::TooLarge`] over the budget;
/// [`ReportError::Cancelled`].
pub fn dimension_within(
    design: &Design,
    params: &[(String, f64)],
    memory: usize,
    cancel: &Cancel,
) -> Result<DimensionReport, ReportError> {
    use crate::eval::{EvalError, EvalSettings, Evaluator};
    let stop = || if cancel.is_cancelled() { Err(ReportError::Cancelled) } else { Ok(()) };
    let instance = instantiate(design, params)?;
    let model = super::error::model_of(design)?;
    // The extent from a coarse evaluation, then points within 1/1024 of it.
    let coarse_ev = Evaluator::new(&instance.automaton, &model, EvalSettings::default().with_depth(4))?;
    let pieces = coarse_ev.pieces();
    let first = pieces.pieces.first();
    let root = |p: &crate::eval::Piece| petgraph::graph::NodeIndex::new(p.state);
    let similarity = similarity_of(&instance.automaton, &coarse_ev);
    let open_set = first
        .zip(similarity)
        .map(|(p, s)| crate::analysis::open_set_condition(&instance.automaton, root(p), &p.control, pieces.dim, s));
    stop()?;
    let coarse = coarse_ev.evaluate()?;
    let (lo, hi) = coarse.bounds().ok_or_else(|| ReportError::Unsupported("the attractor is empty".into()))?;
    let extent = (0..3).map(|a| hi[a] - lo[a]).fold(0.0, f64::max);
    // Surfaces have many more cells per unit of resolution: a quarter of it, and
    // the quads' centres and edge midpoints as samples too (within O(h²) of a smooth sheet).
    let solid = coarse_ev.volumes();
    let surface = !coarse.quads.is_empty() && !solid;
    let uniform = surface || solid;
    let mut resolution = extent / if surface { 256.0 } else { 1024.0 };
    // Three fifths of the budget for the points: the box keys (8 bytes a
    // sample, six samples a quad) take a little over a third as much.
    let points_budget = memory / 5 * 3;
    // A surface's or a solid's points are a uniform depth, known before they
    // are made: the finest resolution whose points fit; the report gives the
    // resolution used, and says when it leaves too few scales to count boxes
    // (the similarity dimension is reported all the same).
    while uniform && resolution < extent / 4.0 {
        match coarse_ev.depth_for_tolerance_within(resolution, points_budget) {
            Ok(k) if coarse_ev.estimate_bytes(k) <= points_budget as u128 => break,
            Ok(_) | Err(EvalError::TooLarge { .. }) => {}
            Err(e) => return Err(e.into()),
        }
        resolution *= 2.0;
    }
    stop()?;
    let settings = EvalSettings::default().with_tolerance(resolution).with_memory_limit(points_budget);
    let shape = Evaluator::new(&instance.automaton, &model, settings)?.evaluate()?;
    stop()?;
    let samples = shape.vertex_count() + 5 * shape.quads.len();
    let keys = (samples * crate::analysis::BOX_KEY_BYTES) as u128;
    let held = shape.vertex_count() as u128 * 48 + shape.quads.len() as u128 * 32;
    if keys + held > memory as u128 {
        return Err(EvalError::TooLarge { estimate: keys + held, limit: memory }.into());
    }
    let shape = &shape;
    let points = || {
        let mid = |a: [f64; 3], b: [f64; 3]| [0, 1, 2].map(|k| (a[k] + b[k]) / 2.0);
        (0..shape.vertex_count()).map(|i| shape.point(i)).chain(shape.quads.iter().flat_map(move |q| {
            let p = q.map(|i| shape.point(i as usize));
            [mid(p[0], p[1]), mid(p[1], p[2]), mid(p[2], p[3]), mid(p[3], p[0]), mid(p[0], p[2])]
        }))
    };
    // Quads (a surface's, a solid's faces) are sampled at half their size.
    let finest = if shape.quads.is_empty() { resolution } else { resolution / 2.0 };
    let fit = crate::analysis::box_dimension_of(points, finest, cancel).map_err(|_| ReportError::Cancelled)?;
    Ok(DimensionReport {
        automaton: design.name().to_string(),
        parameters: instance.parameters.clone(),
        points: shape.vertex_count(),
        resolution,
        fit,
        similarity,
        open_set,
    })
}

/// The similarity dimension of `design`'s attractor at `params` (Moran, Mauldin–Williams), when
/// its maps are similarities of modelling space: [`DimensionReport::similarity`] without the
/// box count (what a fit measures, many times).
///
/// ```
/// let cantor = bcifs::builtin_design("cantor").unwrap();
/// let d = bcifs::report::similarity_dimension(&cantor, &[])?.unwrap();
/// assert!((d - 2f64.ln() / 3f64.ln()).abs() < 1e-12);
/// # Ok::<(), bcifs::report::ReportError>(())
/// ```
///
/// # Errors
/// Parameters that do not instantiate, no model, an evaluation error.
pub fn similarity_dimension(design: &Design, params: &[(String, f64)]) -> Result<Option<f64>, ReportError> {
    use crate::eval::{EvalSettings, Evaluator};
    let instance = instantiate(design, params)?;
    let model = super::error::model_of(design)?;
    let ev = Evaluator::new(&instance.automaton, &model, EvalSettings::default().with_depth(4))?;
    Ok(similarity_of(&instance.automaton, &ev))
}

/// The similarity dimension of the attractor of the first piece `evaluator` draws, if any.
fn similarity_of(automaton: &crate::automaton::Automaton<f64>, evaluator: &crate::eval::Evaluator) -> Option<f64> {
    let pieces = evaluator.pieces();
    let p = pieces.pieces.first()?;
    let root = petgraph::graph::NodeIndex::new(p.state);
    crate::analysis::similarity_dimension(automaton, root, &p.control, pieces.dim)
}

/// A free parameter of a family with its default and the interval around
/// it where the bounds prove convergence (the other parameters at their
/// defaults): the range of a front end's slider.
#[derive(Clone, Debug, PartialEq)]
pub struct ParameterRange {
    /// The parameter.
    pub name: String,
    /// Its default value.
    pub default: f64,
    /// The interval `(lo, hi)` holding the default, sampled 12 times each way
    /// over `max(|default|, 1)`; a 1/12 of that each side where even the
    /// next sample does not converge.
    pub range: (f64, f64),
}

/// The free parameters of `design` with their convergence ranges (see [`ParameterRange`]).
///
/// # Errors
/// A design that does not solve, or a free parameter without a default.
///
/// # Example
/// ```
/// let design = bcifs::builtin_design("corner_cutting").unwrap();
/// let ranges = bcifs::report::parameter_ranges(&design).unwrap();
/// assert_eq!(ranges[0].name, "a");
/// assert!(ranges[0].range.0 < 0.25 && 0.25 < ranges[0].range.1);
/// ```
pub fn parameter_ranges(design: &Design) -> Result<Vec<ParameterRange>, ReportError> {
    let family = solve(design).map_err(|e| ReportError::Unsupported(format!("{}: {e}", design.name())))?;
    let defaults =
        family.parameter_values(&[]).map_err(|e| ReportError::Unsupported(format!("{}: {e}", design.name())))?;
    // The check's verdict (its joint spectral radius bounds), without the rest of the check.
    let converges = |name: &str, x: f64| {
        let Ok(instance) = crate::family::instantiate(design, &[(name.to_string(), x)]) else { return false };
        let settings = crate::analysis::JsrSettings::default();
        crate::analysis::jsr(&instance.automaton, &settings).ok().and_then(|j| j.verdict().converges()).unwrap_or(false)
    };
    // The parameters, and each one's two directions, on the pool's threads (a generated mesh
    // automaton has a dozen weights: 40 s for Suzanne's Catmull-Clark one a direction at a time).
    use rayon::prelude::*;
    let named: Vec<(String, f64)> = family.parameter_names().into_iter().zip(defaults).collect();
    Ok(named
        .into_par_iter()
        .map(|(name, default)| {
            let span = default.abs().max(1.0);
            // The farthest sample converging, walking from the default one twelfth of the span a step.
            let reach = |direction: f64| {
                (1..=12)
                    .map(|k| default + direction * span * f64::from(k) / 12.0)
                    .take_while(|&x| converges(&name, x))
                    .last()
                    .unwrap_or(default)
            };
            let (lo, hi) = rayon::join(|| reach(-1.0), || reach(1.0));
            let range = if lo == hi { (default - span / 12.0, default + span / 12.0) } else { (lo, hi) };
            ParameterRange { name, default, range }
        })
        .collect())
}
