//! What `analyze curve` finds at one parameter point (Sokolov et al. 2010 §4): the
//! one place the object is made; the command line prints it as text or
//! JSON, the Python module returns it as a dict.

use petgraph::graph::EdgeIndex;
use serde_json::{Value, json};

use super::error::ReportError;
use crate::algebra::{Num, Surd};
use crate::analysis::{CurveReport, ExactCurveReport, JsrSettings, Verdict, curve_query, jsr, per_matrix_condition};
use crate::automaton::ArrowKind;
use crate::design::Design;
use crate::family::{Instance, instantiate, solve};
use crate::space::CellKind;

/// The differential behaviour of a curve family at one point: eigenvalues,
/// half-tangents, junction angle and region of Sokolov et al. 2010 Fig. 8, with the
/// convergence verdict; decided in exact arithmetic where the halves are
/// rational `3 × 3` matrices.
#[derive(Clone, Debug)]
pub struct CurveAnalysis {
    /// The design's name.
    pub automaton: String,
    /// The parameter values used (the given ones and the defaults).
    pub parameters: Vec<(String, f64)>,
    /// The names of the two halves' arrows (`T0`, `T1`).
    pub names: [String; 2],
    /// The floating-point query, with the exact answers in place where they decide something.
    pub report: CurveReport,
    /// The joint spectral radius verdict (`None`: undecided).
    pub converges: Option<bool>,
    /// Sokolov et al. 2010 §3's per-matrix condition.
    pub per_matrix: bool,
    /// The region: `divergent` where the bounds prove divergence, none where undecided.
    pub region: Option<&'static str>,
    /// The exact query, when the halves are rational `3 × 3`.
    pub exact: Option<ExactCurveReport>,
    /// The half-tangents as directions in modelling space (unit vectors:
    /// the barycentric half-tangents applied to the model's first control
    /// points), when the curve has half-tangents and a model of that many points.
    pub directions: Option<[Vec<f64>; 2]>,
}

/// Exact numbers as text.
fn strings(v: &[Surd]) -> Vec<String> {
    v.iter().map(ToString::to_string).collect()
}

/// Serialised as [`CurveAnalysis::to_json`] makes it (its keys name the design's arrows).
impl serde::Serialize for CurveAnalysis {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        self.to_json().serialize(serializer)
    }
}

impl CurveAnalysis {
    /// The object `analyze curve --json` prints.
    pub fn to_json(&self) -> Value {
        let (names, report) = (&self.names, &self.report);
        let pair = |a: Value, b: Value| {
            let mut m = serde_json::Map::new();
            m.insert(names[0].clone(), a);
            m.insert(names[1].clone(), b);
            Value::Object(m)
        };
        let exact = self.exact.as_ref().map(|e| {
            json!({
                "eigenvalues": pair(json!(strings(&e.eigenvalues[0])), json!(strings(&e.eigenvalues[1]))),
                "subdominant": pair(json!(e.subdominant[0].as_ref().map(ToString::to_string)),
                                    json!(e.subdominant[1].as_ref().map(ToString::to_string))),
                "half_tangents": e.half_tangents.as_ref().map(|[s, t]| json!({"start": strings(s), "end": strings(t)})),
            })
        });
        let parameters: serde_json::Map<String, Value> =
            self.parameters.iter().map(|(n, v)| (n.clone(), json!(v))).collect();
        json!({
            "automaton": self.automaton, "parameters": parameters, "converges": self.converges,
            "per_matrix_condition": self.per_matrix,
            "eigenvalues": pair(json!(report.eigenvalues[0]), json!(report.eigenvalues[1])),
            "subdominant": pair(json!(report.subdominant[0]), json!(report.subdominant[1])),
            "half_tangents": report.half_tangents.as_ref().map(|[s, e]| json!({"start": s, "end": e})),
            "junction_angle_deg": report.junction_angle_deg,
            "c1_necessary": report.c1_necessary,
            "region": self.region,
            "region_meaning": self.region.map(region_meaning),
            "directions": self.directions.as_ref().map(|[s, e]| json!({"start": s, "end": e})),
            "exact": exact,
        })
    }
}

/// The two subdivision arrows `T0`, `T1` of the model's root of `design`
/// in `instance`: the root must be an edge state with two subdivision
/// arrows to itself.
///
/// # Errors
/// No model, or a root that is not such a curve.
pub fn curve_halves(design: &Design, instance: &Instance) -> Result<[EdgeIndex; 2], ReportError> {
    let automaton = &instance.automaton;
    let not_curve = || {
        ReportError::Unsupported(
            "a curve root (an edge state with two subdivision arrows to itself, T0 and T1) is needed".to_string(),
        )
    };
    let model = design.model().ok_or_else(|| ReportError::NoModel(design.name().to_string()))?;
    let root = automaton.state_id(model.root(0)).ok_or_else(not_curve)?;
    let arrows = automaton.outgoing(root, ArrowKind::Subdivision);
    if automaton.state(root).kind != CellKind::Edge
        || arrows.len() != 2
        || arrows.iter().any(|&e| automaton.arrow_ends(e).1 != root)
    {
        return Err(not_curve());
    }
    Ok([arrows[0], arrows[1]])
}

/// `analyze curve` at `params` (exact values: `1/20` and `0.05` are the
/// same point; the defaults are read as the decimals they print as).
///
/// # Errors
/// Parameters that do not instantiate, no model, a root that is not a curve.
///
/// # Example
/// ```
/// use bcifs::algebra::Num;
/// let design = bcifs::builtin_design("corner_cutting").unwrap();
/// let at = [("a".to_string(), "1/4".parse::<Num>().unwrap()), ("b".to_string(), "1/4".parse::<Num>().unwrap())];
/// let analysis = bcifs::report::curve_analysis(&design, &at).unwrap();
/// assert_eq!(analysis.converges, Some(true));
/// assert_eq!(analysis.region, Some("1")); // Chaikin: tangent continuous
/// ```
pub fn curve_analysis(design: &Design, params: &[(String, Num)]) -> Result<CurveAnalysis, ReportError> {
    let values: Vec<(String, f64)> = params.iter().map(|(n, v)| (n.clone(), v.to_f64())).collect();
    let instance = instantiate(design, &values)?;
    let arrows = curve_halves(design, &instance)?;
    let automaton = &instance.automaton;
    let (t0, t1) = (&automaton.arrow(arrows[0]).matrix, &automaton.arrow(arrows[1]).matrix);
    let names = arrows.map(|e| automaton.arrow(e).name.clone());
    let mut report = curve_query(t0, t1);
    let exact = exact_query(design, params, &instance.parameters, &names);
    if let Some(e) = &exact {
        // The exact answers replace the floating-point ones where they decide something.
        report.region = e.region;
        report.c1_necessary = e.c1_necessary;
        report.junction_angle_deg = e.junction_angle_deg;
        report.half_tangents =
            e.half_tangents.as_ref().map(|[s, t]| [s, t].map(|v| v.iter().map(Surd::to_f64).collect()));
    }
    let verdict = jsr(automaton, &JsrSettings::default()).ok().map(|j| j.verdict());
    let region = match verdict {
        Some(Verdict::Diverges) => Some("divergent"),
        Some(Verdict::Converges) => report.region,
        _ => None,
    };
    let directions = report.half_tangents.as_ref().and_then(|[s, e]| {
        let points = &design.model()?.points;
        let direction = |v: &[f64]| -> Option<Vec<f64>> {
            let d = points.first()?.len();
            let w: Vec<f64> = (0..d).map(|a| v.iter().zip(points).map(|(c, p)| c * p[a]).sum()).collect();
            let len = w.iter().map(|x| x * x).sum::<f64>().sqrt();
            (points.len() >= v.len() && len > 0.0).then(|| w.iter().map(|x| x / len).collect())
        };
        Some([direction(s)?, direction(e)?])
    });
    Ok(CurveAnalysis {
        automaton: design.name().to_string(),
        parameters: instance.parameters.clone(),
        names,
        per_matrix: per_matrix_condition(automaton),
        directions,
        report,
        converges: verdict.and_then(|v| v.converges()),
        region,
        exact,
    })
}

/// What a region of Sokolov et al. 2010's Fig. 8 means for the curve at
/// the junction of its halves (one line; the guide's curve-family tutorial
/// says more).
pub fn region_meaning(region: &str) -> &'static str {
    match region {
        "1" => {
            "the half-tangents are collinear and point the same way: smooth where the curve is C1 (Gregory's region)"
        }
        "2" | "2'" => "the half-tangents are collinear but point opposite ways: a cusp",
        "3" | "3'" => "one half-tangent lies along the middle control edge, the other not: a corner",
        "4" => "neither half-tangent lies along the middle control edge: a corner",
        "5" => {
            "a corner, the curve oscillating about its half-tangents (the smallest eigenvalue is negative): rough, fractal-looking"
        }
        "divergent" => "the subdivision diverges: no curve",
        "degenerate" => "tied or zero eigenvalues: no half-tangents to compare",
        _ => "not decided",
    }
}

/// The exact query when the curve's halves are rational `3 × 3` at the
/// parameter values: the given values exactly, the defaults as the
/// decimals they print as.
fn exact_query(
    design: &Design,
    given: &[(String, Num)],
    values: &[(String, f64)],
    names: &[String; 2],
) -> Option<ExactCurveReport> {
    let family = solve(design).ok()?;
    let x: Vec<Num> = family
        .parameter_names()
        .iter()
        .map(|n| {
            given
                .iter()
                .rev()
                .find(|(g, _)| g == n)
                .map(|(_, v)| v.clone())
                .unwrap_or_else(|| Num::from_f64(values.iter().find(|(m, _)| m == n).map_or(f64::NAN, |(_, v)| *v)))
        })
        .collect();
    let t0 = family.exact_matrix(&names[0], &x)?;
    let t1 = family.exact_matrix(&names[1], &x)?;
    crate::analysis::curve_query_exact(&t0, &t1)
}
