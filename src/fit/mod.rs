//! Inverse design: a family's free parameters fitted to what the designer
//! wants (points or a mesh the shape should pass through, a dimension, a
//! junction angle, a porosity), staying where convergence is proven.
//!
//! Least squares by Levenberg–Marquardt. For points, the residuals are the
//! distances both ways between the depth-k leaf points and the target's
//! (nearest points found again at every step, as in ICP); at a fixed depth
//! a leaf point is a polynomial in the parameters, and its derivatives are
//! carried down the subdivision tree exactly (forward mode,
//! [`crate::eval::Evaluator::tangents`]). Every step is checked by the joint
//! spectral radius bounds: a step to a member whose convergence is not
//! proven is refused (the damping grows), so the answer always converges,
//! and the report says when the target lies beyond the proven region.
//! Several starts (the defaults and a low-discrepancy sample of each
//! parameter's convergence range) are tried, the best kept.

mod nearest;
mod problem;
mod target;
mod types;

use nalgebra::{DMatrix, DVector};
use serde::Serialize;

use crate::design::Design;
use crate::progress::{Cancel, Progress};
#[cfg(test)]
use problem::Measure;
use problem::{Problem, Proof};
pub use target::{is_picture, picture_points, read_target, read_target_bytes};
pub use types::{BOX_SPREAD, FitError, FitTarget};

/// How the fit runs.
#[derive(Clone, Debug)]
pub struct FitOptions {
    /// The depth of the leaf points (`None`: the one whose points are as many as the target's).
    pub depth: Option<usize>,
    /// Starts run to the end (the best of a sample of the ranges, and the defaults).
    pub starts: usize,
    /// Levenberg–Marquardt iterations per start, at most.
    pub iterations: usize,
    /// Stops the fit: the best member so far is returned, marked interrupted.
    pub cancel: Cancel,
    /// Reports the iterations done against the budget.
    pub progress: Option<Progress>,
    /// Run from this member only (the parameters in order; [`fit_starts`] gives the starts a fit
    /// would take, so that a cluster runs one each).
    pub start: Option<Vec<f64>>,
    /// Fit the model's control points too (the leaf points are linear in them).
    pub control_points: bool,
}

impl Default for FitOptions {
    fn default() -> FitOptions {
        FitOptions {
            depth: None,
            starts: 4,
            iterations: 60,
            cancel: Cancel::new(),
            progress: None,
            start: None,
            control_points: false,
        }
    }
}

/// The members [`fit`] starts from (each proven to converge): the defaults, then the best of a
/// low-discrepancy sample of the parameters' convergence ranges, `settings.starts` in all — for
/// front ends that run the starts apart (on a cluster) with [`FitOptions::start`], keeping the
/// lowest residual.
///
/// # Errors
/// As [`fit`].
pub fn fit_starts(design: &Design, target: &FitTarget, settings: &FitOptions) -> Result<Vec<Vec<f64>>, FitError> {
    check_settings(settings)?;
    let problem = Problem::new(design, target, settings.depth, settings.control_points)?;
    let defaults = problem.defaults();
    let mut starts: Vec<Vec<f64>> = Vec::new();
    if problem.proof(&defaults).converges {
        starts.push(defaults);
    }
    starts.extend(sampled_starts(&problem, settings, starts.len()));
    let m = problem.names.len();
    Ok(starts
        .into_iter()
        .map(|mut s| {
            s.truncate(m);
            s
        })
        .collect())
}

/// A fit's outcome.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FitReport {
    /// The design's name.
    pub automaton: String,
    /// The fitted value of every free parameter, in order.
    pub parameters: Vec<(String, f64)>,
    /// The residual norm: the points' root-mean-square distances (both ways, in units of the
    /// target's diagonal) and the numbers' differences (an angle in right angles), combined.
    pub residual: f64,
    /// The root-mean-square symmetric distance to the target points, in the model's units.
    pub distance: Option<f64>,
    /// Each number target: what was asked, what was reached.
    pub numbers: Vec<NumberFit>,
    /// Whether the fitted member is proven to converge (always, unless the fit found none).
    pub converges: bool,
    /// The joint spectral radius upper bound of the fitted member.
    pub jsr_upper: f64,
    /// Why the target was not reached, when a step towards it left the proven region.
    pub reason: Option<String>,
    /// Levenberg–Marquardt iterations, over every start.
    pub iterations: usize,
    /// Starts run.
    pub starts: usize,
    /// The depth of the leaf points.
    pub depth: usize,
    /// Ctrl-C (the cancel flag) stopped the fit: the best member so far.
    pub interrupted: bool,
    /// With a free pose (a picture): the scale `u` and shift `t` that map the member's point `x`
    /// onto the target, `u·(x − t)`.
    pub pose: Option<(f64, Vec<f64>)>,
    /// The fitted control points, when they were fitted.
    pub control_points: Option<Vec<Vec<f64>>>,
}

/// A number target of a fit, and the value the fitted member has.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct NumberFit {
    /// What is measured: `dimension`, `angle` or `porosity`.
    pub name: String,
    /// The value asked for.
    pub target: f64,
    /// The fitted member's value.
    pub value: f64,
    /// How far `value` can be trusted: 0 for exact measures (a similarity dimension, a junction
    /// angle, a porosity), [`BOX_SPREAD`] for a box-counting dimension (its spread on curves
    /// whose dimension is known).
    pub within: f64,
    /// Whether `value` meets `target`: within `within`, or to a millionth (of 1 or the target)
    /// for an exact measure.
    pub reached: bool,
}

impl FitReport {
    /// The object `bcifs fit --json` prints: `parameters` (name → value), `residual`,
    /// `distance`, `numbers` (name → `{target, value, within, reached}`), `converges`, `jsr_upper`, `reason`,
    /// `iterations`, `starts`, `depth`, `interrupted`.
    pub fn to_json(&self) -> serde_json::Value {
        let parameters: serde_json::Map<String, serde_json::Value> =
            self.parameters.iter().map(|(n, v)| (n.clone(), serde_json::json!(v))).collect();
        let numbers: serde_json::Map<String, serde_json::Value> = self
            .numbers
            .iter()
            .map(|n| {
                let fields =
                    serde_json::json!({"target": n.target, "value": n.value, "within": n.within, "reached": n.reached});
                (n.name.clone(), fields)
            })
            .collect();
        serde_json::json!({
            "automaton": self.automaton, "parameters": parameters, "residual": self.residual,
            "distance": self.distance, "numbers": numbers, "converges": self.converges,
            "jsr_upper": if self.jsr_upper.is_finite() { serde_json::json!(self.jsr_upper) } else { serde_json::Value::Null },
            "reason": self.reason, "iterations": self.iterations, "starts": self.starts, "depth": self.depth,
            "interrupted": self.interrupted,
            "pose": self.pose.as_ref().map(|(u, t)| serde_json::json!({"scale": u, "shift": t})),
            "control_points": self.control_points,
        })
    }
}

/// Fits `design`'s free parameters to `target` (see the module's text).
///
/// ```
/// let design = bcifs::builtin_design("corner_cutting").unwrap();
/// // The depth-5 points of the member a = 0.2, b = 0.3, fitted from the defaults (0.25, 0.25).
/// let member = bcifs::render::Options { params: vec![("a".into(), 0.2), ("b".into(), 0.3)], ..Default::default() };
/// let shape = bcifs::render::evaluate_design(&design, &member.with_depth(5), &mut Vec::new()).unwrap();
/// let target = bcifs::fit::FitTarget { points: shape.points(), ..Default::default() };
/// let report = bcifs::fit::fit(&design, &target, &bcifs::fit::FitOptions::default()).unwrap();
/// assert!((report.parameters[0].1 - 0.2).abs() < 1e-6 && (report.parameters[1].1 - 0.3).abs() < 1e-6);
/// assert!(report.converges);
/// ```
///
/// # Errors
/// See [`FitError`]: all are found before any step.
pub fn fit(design: &Design, target: &FitTarget, settings: &FitOptions) -> Result<FitReport, FitError> {
    check_settings(settings)?;
    let problem = Problem::new(design, target, settings.depth, settings.control_points)?;
    let budget = (settings.starts.max(1) * settings.iterations) as u64;
    let (mut best, mut iterations, mut runs): (Option<Run>, usize, usize) = (None, 0, 0);
    let mut run_from = |start: Vec<f64>, best: &mut Option<Run>| -> Result<(), FitError> {
        let run = coarse_to_fine(&problem, start, settings, runs, budget)?;
        (iterations, runs) = (iterations + run.iterations, runs + 1);
        if best.as_ref().is_none_or(|b| run.cost < b.cost) {
            *best = Some(run);
        }
        Ok(())
    };
    let defaults = problem.defaults();
    if let Some(start) = &settings.start {
        // One given start (the pose, for a picture, where the defaults' is).
        let m = problem.names.len();
        if start.len() != m || start.iter().any(|x| !x.is_finite()) {
            return Err(FitError::NotFinite(format!("the start must be {m} finite numbers, not {start:?}")));
        }
        let theta: Vec<f64> = start.iter().chain(&defaults[m..]).copied().collect();
        if problem.proof(&theta).converges {
            run_from(theta, &mut best)?;
        }
    } else if problem.proof(&defaults).converges {
        run_from(defaults, &mut best)?;
    }
    // The other starts only when the defaults do not fit exactly (to rounding; a box count within its spread).
    if settings.start.is_none() && best.as_ref().is_none_or(|b| !b.met) {
        for start in sampled_starts(&problem, settings, usize::from(best.is_some())) {
            if settings.cancel.is_cancelled() || best.as_ref().is_some_and(|b| b.met) {
                break;
            }
            run_from(start, &mut best)?;
        }
    }
    if best.is_none() && !settings.cancel.is_cancelled() {
        return Err(FitError::NoProvenStart(format!(
            "{}: neither the defaults nor any sample of the parameters' ranges is proven to converge",
            design.name()
        )));
    }
    let best = best.ok_or_else(|| FitError::NoProvenStart("the fit was interrupted before its first start".into()))?;
    let proof = problem.proof(&best.theta);
    let residuals = problem.residuals(&best.theta, false)?;
    let numbers = number_fits(&problem, &residuals);
    Ok(FitReport {
        automaton: design.name().to_string(),
        parameters: problem.values(&best.theta),
        residual: (2.0 * best.cost).sqrt(),
        distance: residuals.distance,
        reason: reason(&problem, &best, &numbers, runs, iterations),
        numbers,
        converges: proof.converges,
        jsr_upper: proof.upper,
        iterations,
        starts: runs,
        depth: problem.depth,
        interrupted: settings.cancel.is_cancelled(),
        pose: problem.pose(&best.theta),
        control_points: problem.control_points(&best.theta),
    })
}

/// Why the target was not reached: a step towards it left the proven region, or a number was
/// missed (a compromise with the points, or no nearer member found); none when it was reached.
fn reason(problem: &Problem<'_>, best: &Run, numbers: &[NumberFit], runs: usize, iterations: usize) -> Option<String> {
    if let Some((theta, p)) = best.left.as_ref().filter(|_| best.cost > 1e-20) {
        return Some(outside(problem, theta, p));
    }
    let missed: Vec<String> = numbers.iter().filter(|n| !n.reached).map(missed).collect();
    let why = if problem.has_points() {
        "the least-squares compromise with the points (a number counts its difference in its unit, a right \
         angle for an angle; the points their RMS distance over the target's diagonal)"
            .to_string()
    } else {
        format!("no proven member nearer was found from {runs} start(s) ({iterations} iterations)")
    };
    (!missed.is_empty()).then(|| format!("{} not reached: {why}", missed.join(", ")))
}

/// The number targets at a member: asked, reached, and whether they meet.
fn number_fits(problem: &Problem<'_>, residuals: &problem::Residuals) -> Vec<NumberFit> {
    let fits = problem.numbers.iter().zip(&residuals.numbers);
    fits.map(|(&(measure, target), &(_, got))| NumberFit {
        name: measure.name().to_string(),
        target,
        value: got.value,
        within: got.within,
        reached: (target - got.value).abs() <= got.within.max(1e-6 * target.abs().max(1.0)),
    })
    .collect()
}

/// A number target missed, as text.
fn missed(n: &NumberFit) -> String {
    format!("{} {} ({} reached)", n.name, types::shown(n.target), types::shown(n.value))
}

/// The most starts a fit takes (each samples four members of the ranges before it runs).
pub const MAX_STARTS: usize = 1024;

/// Settings a fit can run with: at most [`MAX_STARTS`] starts and 10,000 iterations a start.
fn check_settings(settings: &FitOptions) -> Result<(), FitError> {
    if settings.starts > MAX_STARTS || settings.iterations > 10_000 {
        return Err(FitError::TooLarge(format!(
            "{} starts of {} iterations: at most {MAX_STARTS} starts of 10000 iterations",
            settings.starts, settings.iterations
        )));
    }
    Ok(())
}

/// A cost (half the squared residual norm) that only rounding leaves: the fit is exact.
const EXACT: f64 = 1e-26;

/// `design` with the fitted parameters as its defaults (and the fitted control points as its
/// model's, when they were fitted): the fitted design, as `-o fitted.toml` writes it.
///
/// # Errors
/// A parameter the design does not have, or a design that no longer builds.
pub fn fitted_design(design: &Design, report: &FitReport) -> Result<Design, FitError> {
    let mut builder = design.to_builder();
    for (name, value) in &report.parameters {
        // The shortest decimal that reads back as the same number (the file stays readable).
        builder.default_value(name, value.to_string());
    }
    if let (Some(points), Some(model)) = (&report.control_points, design.model()) {
        builder.model(crate::design::Model { points: points.clone(), ..model.clone() });
    }
    builder.build().map_err(|e| FitError::Design(e.to_string()))
}

/// One start's run: where it ended, its cost, and the last step refused as unproven.
struct Run {
    theta: Vec<f64>,
    cost: f64,
    /// Every target is met: to rounding, or within a box count's spread.
    met: bool,
    iterations: usize,
    left: Option<(Vec<f64>, Proof)>,
}

/// The reason given when a step towards the target left the proven region.
fn outside(problem: &Problem<'_>, theta: &[f64], proof: &Proof) -> String {
    let at: Vec<String> = problem.values(theta).iter().map(|(n, v)| format!("{n} = {v:.6}")).collect();
    let why = if proof.witness.is_empty() {
        format!("its joint spectral radius bound is {:.4}, not below 1", proof.upper)
    } else {
        format!("the cycle {} has spectral radius at least 1 (bound {:.4})", proof.witness.join(" "), proof.upper)
    };
    format!(
        "the target lies towards members whose convergence is not proven ({}: {why}); the answer is the nearest proven member",
        at.join(", ")
    )
}

/// The best members of a low-discrepancy sample of the parameters' convergence ranges (each proven
/// to converge), `settings.starts − taken` of them, best first.
fn sampled_starts(problem: &Problem<'_>, settings: &FitOptions, taken: usize) -> Vec<Vec<f64>> {
    let defaults = problem.defaults();
    let m = defaults.len() - (problem.unknowns() - problem.names.len());
    let mut ranges: Vec<(f64, f64)> = if m <= 12 {
        crate::report::parameter_ranges(problem.design)
            .map(|r| r.iter().map(|p| p.range).collect())
            .unwrap_or_else(|_| defaults[..m].iter().map(|&d| (d - 0.1, d + 0.1)).collect())
    } else {
        defaults[..m].iter().map(|&d| (d - d.abs().max(1.0) / 12.0, d + d.abs().max(1.0) / 12.0)).collect()
    };
    // The pose starts where the defaults' does (scale 1, no shift).
    ranges.extend(defaults[m..].iter().map(|&d| (d, d)));
    // A Kronecker sequence: frac(k·α_i) with α_i the square roots of primes, spread over each range.
    let alphas = [2f64, 3.0, 5.0, 7.0, 11.0, 13.0, 17.0, 19.0, 23.0, 29.0, 31.0, 37.0].map(|p| p.sqrt().fract());
    let mut sampled: Vec<(f64, Vec<f64>)> = Vec::new();
    for k in 1..=(4 * settings.starts.max(1)) {
        let theta: Vec<f64> = ranges
            .iter()
            .enumerate()
            .map(|(i, (lo, hi))| lo + (hi - lo) * (k as f64 * alphas[i % alphas.len()] + 0.5 / (i + 1) as f64).fract())
            .collect();
        if settings.cancel.is_cancelled() {
            break;
        }
        if !problem.proof(&theta).converges {
            continue;
        }
        if let Ok(r) = problem.residuals(&theta, false) {
            sampled.push((r.r.norm_squared(), theta));
        }
    }
    sampled.sort_by(|a, b| a.0.total_cmp(&b.0));
    sampled.into_iter().map(|(_, t)| t).take(settings.starts.max(1).saturating_sub(taken)).collect()
}

/// Depths the points are first fitted at, below the fit's own.
const COARSER: usize = 3;

/// [`levenberg_marquardt`] at coarser depths first (a few leaf points each
/// near one target point: pairs that cannot be mistaken), each depth
/// starting where the one before ended, then at the fit's depth.
fn coarse_to_fine(
    problem: &Problem<'_>,
    theta: Vec<f64>,
    settings: &FitOptions,
    start: usize,
    budget: u64,
) -> Result<Run, FitError> {
    let first = if problem.has_points() {
        problem.depth.saturating_sub(COARSER).max(1).min(problem.depth)
    } else {
        problem.depth
    };
    let (mut theta, mut iterations, mut left) = (theta, 0, None);
    for depth in first..problem.depth {
        problem.set_depth(depth);
        let run = levenberg_marquardt(problem, theta, settings, start, budget)?;
        (theta, iterations, left) = (run.theta, iterations + run.iterations, run.left.or(left));
    }
    problem.set_depth(problem.depth);
    let run = levenberg_marquardt(problem, theta, settings, start, budget)?;
    Ok(Run { iterations: iterations + run.iterations, left: run.left.or(left), ..run })
}

/// Levenberg–Marquardt from `theta`, every trial step checked for proven
/// convergence. The nearest points are paired once an iteration and kept
/// through its trial steps (the cost it decreases is smooth), then paired
/// afresh (as ICP alternates); it stops when a fresh pairing no longer
/// lowers the cost.
fn levenberg_marquardt(
    problem: &Problem<'_>,
    mut theta: Vec<f64>,
    settings: &FitOptions,
    start: usize,
    budget: u64,
) -> Result<Run, FitError> {
    let mut res = problem.residuals(&theta, true)?;
    let mut cost = res.r.norm_squared() / 2.0;
    let (mut lambda, mut iterations, mut left) = (1e-3, 0, None);
    while iterations < settings.iterations && cost > EXACT * 1e-4 && !settings.cancel.is_cancelled() {
        iterations += 1;
        if let Some(p) = &settings.progress {
            p.report((start * settings.iterations + iterations) as u64, budget);
        }
        let (j, pairs) = (res.jacobian.take().expect("asked for"), res.pairs.take());
        let (g, h) = (j.transpose() * &res.r, j.transpose() * &j);
        let damping = damping(&h);
        let mut accepted = None;
        for _ in 0..16 {
            let mut a = h.clone();
            for i in 0..a.nrows() {
                a[(i, i)] += lambda * damping[i];
            }
            let Some(delta) = a.lu().solve(&(-&g)) else { break };
            let trial: Vec<f64> = theta.iter().zip(delta.iter()).map(|(t, d)| t + d).collect();
            // The cost first (cheap), the proof only for a step that lowers it; for a dimension
            // the other way round (its box count costs seconds near the edge of the proven region,
            // where a member past it may have many points or none).
            let lower = || {
                problem.residuals_paired(&trial, false, pairs.as_ref()).is_ok_and(|r| r.r.norm_squared() / 2.0 < cost)
            };
            let proof_first = problem.measures_dimension();
            if !proof_first && !lower() {
                lambda *= 10.0;
                continue;
            }
            let proof = problem.proof(&trial);
            if !proof.converges {
                left = Some((trial, proof));
                lambda *= 10.0;
                continue;
            }
            if proof_first && !lower() {
                lambda *= 10.0;
                continue;
            }
            accepted = Some((trial, delta));
            break;
        }
        let Some((trial, delta)) = accepted else { break };
        let fresh = problem.residuals(&trial, true)?;
        let new_cost = fresh.r.norm_squared() / 2.0;
        if new_cost < cost {
            let small = delta.norm() <= 1e-10 * (DVector::from_vec(theta.clone()).norm() + 1e-12);
            let stalled = cost - new_cost <= 1e-12 * cost;
            (theta, res, cost, lambda) = (trial, fresh, new_cost, (lambda / 3.0).max(1e-12));
            if (small && stalled) || met(problem, &res) {
                break;
            }
        } else {
            // Paired afresh, the step does not pay: shorter steps from the same member.
            lambda *= 10.0;
            if lambda > 1e12 {
                break;
            }
            res = problem.residuals(&theta, true)?;
        }
    }
    Ok(Run { theta, cost, met: cost <= EXACT || met(problem, &res), iterations, left })
}

/// A fit of numbers only whose every number is a box count met within its
/// spread: nearer is noise.
fn met(problem: &Problem<'_>, res: &problem::Residuals) -> bool {
    !problem.has_points()
        && problem
            .numbers
            .iter()
            .zip(&res.numbers)
            .all(|(&(_, want), &(_, got))| got.within > 0.0 && (got.value - want).abs() <= got.within)
}

/// Levenberg–Marquardt's damping per unknown: Marquardt's `diag(JᵀJ)` (steps
/// that do not depend on the unknowns' units), floored at its mean. Without
/// the floor, an unknown the residuals hardly see gets a step of the
/// residual over its tiny slope: a number target (one residual, many
/// parameters) then moves every insensitive parameter far (a carpet's porosity
/// stalled at 0.27 for 0.3), where the floor gives the least-norm step.
fn damping(h: &DMatrix<f64>) -> Vec<f64> {
    let n = h.nrows().max(1);
    let mean = (0..h.nrows()).map(|i| h[(i, i)]).sum::<f64>() / n as f64;
    (0..h.nrows()).map(|i| h[(i, i)].max(mean) + 1e-12).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every measure named: the CLI's flags and the JSON's fields say these.
    #[test]
    fn measures_are_named() {
        assert_eq!(
            [Measure::Dimension, Measure::Angle, Measure::Porosity].map(Measure::name),
            ["dimension", "angle", "porosity"]
        );
    }
}
