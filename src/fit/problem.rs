//! A fit's objective: the residuals of a family member against the target,
//! with their Jacobian, and whether the member is proven to converge.

use std::collections::HashMap;

use nalgebra::{DMatrix, DVector};
use petgraph::stable_graph::EdgeIndex;

use super::nearest::KdTree;
use super::types::{BOX_SPREAD, FitError, FitTarget};
use crate::automaton::Automaton;
use crate::design::{Design, Model};
use crate::eval::{Directions, EvalSettings, Evaluator, Tangents};
use crate::family::Family;

/// What a number target measures.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Measure {
    Dimension,
    Angle,
    Porosity,
}

impl Measure {
    pub(crate) fn name(self) -> &'static str {
        match self {
            Measure::Dimension => "dimension",
            Measure::Angle => "angle",
            Measure::Porosity => "porosity",
        }
    }

    /// The values a member can have, and why, in a model space of `space` dimensions.
    fn range(self, space: usize) -> (f64, f64, String) {
        match self {
            Measure::Dimension => (0.0, space as f64, format!("a set in a {space}D model space")),
            Measure::Angle => (0.0, 180.0, "a junction angle in degrees".into()),
            Measure::Porosity => (0.0, 1.0, "the fraction of the cell left empty".into()),
        }
    }

    /// The residual's unit: a degree is small beside a dimension.
    fn scale(self) -> f64 {
        match self {
            Measure::Angle => 90.0,
            Measure::Dimension | Measure::Porosity => 1.0,
        }
    }
}

/// A number target's value at a member, and how far it can be trusted:
/// `within` is 0 for the exact measures (a similarity dimension, a junction
/// angle, a porosity: rounding only), [`BOX_SPREAD`] for a box count.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Measured {
    pub(crate) value: f64,
    pub(crate) within: f64,
}

/// A box count's difference step, relative to the parameter (at least 1):
/// its slopes are near 1 on the shipped curves, so a step of 0.02 each way
/// changes it by twice its spread ([`BOX_SPREAD`]).
const BOX_STEP: f64 = 0.02;

/// The points of a target, held for nearest-point queries, each with its
/// local frame: the directions along the target (its tangents, from the
/// principal axes of its nearest points), then across it.
struct Points {
    tree: KdTree,
    count: usize,
    /// The target's diagonal: distances are measured in its units.
    scale: f64,
    /// Per point: three orthonormal axes, each with its weight (1 across, [`ALONG`] along).
    frames: Vec<[([f64; 3], f64); 3]>,
}

/// The weight of an offset along the target against one across it: none
/// (point-to-plane ICP, point-to-line on curves). The distance between two
/// sets is what is fitted, not where the points fall along them; with
/// offsets along counted, the nearest points lock the fit in place (on
/// corner cutting, at a = 0.2065 instead of 0.2, one leaf spacing along).
const ALONG: f64 = 0.0;

/// The most memory a fit's leaf points and derivatives may take.
pub(crate) const FIT_MEMORY: usize = 1 << 30;

/// Neighbours whose principal axes give a target point's frame.
const NEIGHBOURS: usize = 16;

/// A member's verdict: proven to converge, or why not.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Proof {
    pub(crate) converges: bool,
    pub(crate) upper: f64,
    pub(crate) witness: Vec<String>,
}

/// The residuals of one member: their vector, and its Jacobian when asked.
pub(crate) struct Residuals {
    pub(crate) r: DVector<f64>,
    pub(crate) jacobian: Option<DMatrix<f64>>,
    /// The root-mean-square symmetric distance to the target points (in the model's units).
    pub(crate) distance: Option<f64>,
    /// The number targets' values.
    pub(crate) numbers: Vec<(Measure, Measured)>,
    /// The nearest points found at this member.
    pub(crate) pairs: Option<Pairs>,
}

/// Which points face which: each target point's nearest leaf point, each
/// leaf point's nearest target point (leaf numbers are the same for every
/// member at one depth), and the root-mean-square symmetric distance.
#[derive(Clone, Debug)]
pub(crate) struct Pairs {
    to_shape: Vec<usize>,
    to_target: Vec<usize>,
    distance: f64,
}

/// The design, its family and the target, ready to be evaluated at any parameter values.
pub(crate) struct Problem<'a> {
    pub(crate) design: &'a Design,
    family: Family,
    pub(crate) names: Vec<String>,
    model: Model,
    pub(crate) depth: usize,
    /// The depth the points are evaluated at now, and whether both ways
    /// count (a coarser depth's leaf points lie among the target's, not the
    /// other way round: only they are measured there).
    level: std::cell::Cell<(usize, bool)>,
    points: Option<Points>,
    pub(crate) numbers: Vec<(Measure, f64)>,
    /// The control points' coordinates among the unknowns, after the parameters (none unless asked).
    control: usize,
    /// The pose's unknowns after those (a scale and a shift per coordinate), or none.
    pose: usize,
}

impl<'a> Problem<'a> {
    /// The design's family and model with the target; the depth (given, or the one whose leaf points are as
    /// many as the target's, at most 10) chosen.
    pub(crate) fn new(
        design: &'a Design,
        target: &FitTarget,
        depth: Option<usize>,
        control_points: bool,
    ) -> Result<Problem<'a>, FitError> {
        let family = crate::family::solve(design).map_err(|e| FitError::Design(format!("{}: {e}", design.name())))?;
        let names = family.parameter_names();
        if names.is_empty() {
            return Err(FitError::NoParameter(design.name().to_string()));
        }
        let model = crate::report::model_of(design).map_err(|e| FitError::Design(e.to_string()))?;
        let mut numbers = Vec::new();
        for (measure, value) in [
            (Measure::Dimension, target.dimension),
            (Measure::Angle, target.angle),
            (Measure::Porosity, target.porosity),
        ] {
            if let Some(v) = value {
                if !v.is_finite() {
                    return Err(FitError::NotFinite(format!("the {} target is {v}", measure.name())));
                }
                let space = model.points.first().map_or(3, Vec::len);
                let (lo, hi, what) = measure.range(space);
                if !(lo..=hi).contains(&v) {
                    return Err(FitError::OutOfRange(format!(
                        "the {} target {} is outside [{lo}, {hi}]: {what}",
                        measure.name(),
                        super::types::shown(v)
                    )));
                }
                numbers.push((measure, v));
            }
        }
        let level = std::cell::Cell::new((depth.unwrap_or(0), true));
        let control = if control_points { model.points.iter().map(Vec::len).sum() } else { 0 };
        let mut problem = Problem {
            design,
            family,
            names,
            model,
            depth: depth.unwrap_or(0),
            level,
            points: None,
            numbers,
            control,
            pose: 0,
        };
        if !target.points.is_empty() {
            problem.points = Some(problem.target_points(&target.points)?);
            if target.free_pose {
                problem.pose = 1 + problem.evaluator(&problem.automaton(&problem.defaults())?, 0)?.pieces().dim;
            }
            if depth.is_none() {
                problem.depth = problem.matching_depth(target.points.len())?;
                problem.level.set((problem.depth, true));
            }
        } else if problem.numbers.is_empty() {
            return Err(FitError::EmptyTarget);
        }
        problem.check_size()?;
        problem.check_porosity()?;
        Ok(problem)
    }

    /// A porosity is the share of a cell its sub-cells leave empty: a design whose sub-cells
    /// measure more than their parent (a curve bending away from its chord: corner cutting's
    /// porosity is −0.147) has none to fit, and is refused before any step.
    fn check_porosity(&self) -> Result<(), FitError> {
        if !self.numbers.iter().any(|(m, _)| *m == Measure::Porosity) {
            return Ok(());
        }
        match self.measured(Measure::Porosity, &self.defaults()) {
            // The measure refuses cells that are no parts of their parent, and cells with no patch.
            Err(FitError::Design(why)) => Err(FitError::OutOfRange(format!(
                "{} at the defaults: {why}: a porosity is fitted on designs whose cells lie inside their parent \
                 (laces, solids, Cantor sets)",
                self.design.name()
            ))),
            other => other.map(|_| ()),
        }
    }

    fn target_points(&self, points: &[[f64; 3]]) -> Result<Points, FitError> {
        if let Some(p) = points.iter().find(|p| p.iter().any(|x| !x.is_finite())) {
            return Err(FitError::NotFinite(format!("a target point is {p:?}")));
        }
        let ev = self.evaluator(&self.automaton(&self.defaults())?, 0)?;
        let (dim, cells) = (ev.pieces().dim, ev.cell_dimension());
        if dim == 2 && points.iter().any(|p| p[2] != 0.0) {
            return Err(FitError::Dimension { model: 2, target: 3 });
        }
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        for p in points {
            (0..3).for_each(|a| (lo[a], hi[a]) = (lo[a].min(p[a]), hi[a].max(p[a])));
        }
        let diagonal = (0..3).map(|a| (hi[a] - lo[a]).powi(2)).sum::<f64>().sqrt();
        let tree = KdTree::new(points.to_vec());
        let frames = points.iter().map(|&q| frame(&tree, q, cells)).collect();
        Ok(Points { tree, count: points.len(), scale: diagonal.max(f64::MIN_POSITIVE), frames })
    }

    /// The depth whose distinct leaf points (the evaluation's vertices, welded) are nearest in number
    /// to `count` (the target's), at the defaults.
    fn matching_depth(&self, count: usize) -> Result<usize, FitError> {
        let defaults = self.defaults();
        let ev = self.evaluator(&self.automaton(&defaults)?, 0)?;
        let directions = no_directions();
        let (mut best, mut gap) = (0, f64::INFINITY);
        for k in 0..=10 {
            // Estimated before it is made: a depth past the target's size by far is not evaluated.
            if ev.total_samples(k) > 64 * count.max(1) {
                break;
            }
            let t = ev.tangents(k, &directions);
            let scale = t.points.iter().fold(1.0f64, |m, x| m.max(x.abs()));
            let key = |p: &[f64]| p.iter().map(|x| (x / scale * 1e9).round() as i64).collect::<Vec<_>>();
            let distinct = t.points.chunks(t.dim.max(1)).map(key).collect::<std::collections::HashSet<_>>().len();
            let g = (distinct.max(1) as f64 / count.max(1) as f64).ln().abs();
            if g < gap {
                (best, gap) = (k, g);
            }
        }
        Ok(best)
    }

    /// The leaf points and their derivatives at the fit's depth fit [`FIT_MEMORY`], estimated
    /// before any is made (a depth given by hand may be far past the target's).
    fn check_size(&self) -> Result<(), FitError> {
        if self.points.is_none() {
            return Ok(());
        }
        let ev = self.evaluator(&self.automaton(&self.defaults())?, 0)?;
        // Up to two points a leaf (an edge's ends), each with its coordinates along every unknown.
        let bytes = (ev.total_samples(self.depth) as u128)
            .saturating_mul(2 * 8 * ev.pieces().dim as u128)
            .saturating_mul(1 + self.unknowns() as u128);
        if bytes > FIT_MEMORY as u128 {
            return Err(FitError::TooLarge(format!(
                "depth {}: the leaf points and their derivatives would take about {} MiB, over the fit's {} MiB; lower the depth",
                self.depth,
                bytes >> 20,
                FIT_MEMORY >> 20
            )));
        }
        Ok(())
    }

    /// Measures the points at `depth` (both ways only at the fit's own depth).
    pub(crate) fn set_depth(&self, depth: usize) {
        self.level.set((depth, depth >= self.depth));
    }

    /// Whether a number target is a dimension (each measure a box count).
    pub(crate) fn measures_dimension(&self) -> bool {
        self.numbers.iter().any(|(m, _)| *m == Measure::Dimension)
    }

    /// Whether the fit measures points (else numbers only).
    pub(crate) fn has_points(&self) -> bool {
        self.points.is_some()
    }

    /// The parameters' defaults, in order, then the model's control points when they are fitted,
    /// then the pose's (scale 1, no shift).
    pub(crate) fn defaults(&self) -> Vec<f64> {
        let mut theta = self.family.parameter_values(&[]).unwrap_or_else(|_| vec![0.0; self.names.len()]);
        if self.control > 0 {
            theta.extend(self.model.points.iter().flatten());
        }
        theta.extend((0..self.pose).map(|k| if k == 0 { 1.0 } else { 0.0 }));
        theta
    }

    /// The unknowns: the parameters, the control points' coordinates when asked, and the pose's
    /// when the target's size and place are free.
    pub(crate) fn unknowns(&self) -> usize {
        self.names.len() + self.control + self.pose
    }

    /// The pose at `theta` (the scale `u` and shift `t` that map a shape point `x` to `u·(x − t)`
    /// in the target's units), when it is fitted.
    pub(crate) fn pose(&self, theta: &[f64]) -> Option<(f64, Vec<f64>)> {
        (self.pose > 0).then(|| {
            let at = self.names.len() + self.control;
            (theta[at], theta[at + 1..at + self.pose].to_vec())
        })
    }

    /// The model's control points at `theta`, when they are fitted.
    pub(crate) fn control_points(&self, theta: &[f64]) -> Option<Vec<Vec<f64>>> {
        (self.control > 0).then(|| {
            let mut at = self.names.len();
            self.model
                .points
                .iter()
                .map(|p| {
                    at += p.len();
                    theta[at - p.len()..at].to_vec()
                })
                .collect()
        })
    }

    /// The model at `theta`: its control points from `theta` when they are fitted.
    fn model_at(&self, theta: &[f64]) -> Model {
        let mut model = self.model.clone();
        if let Some(points) = self.control_points(theta) {
            model.points = points;
        }
        model
    }

    pub(crate) fn values(&self, theta: &[f64]) -> Vec<(String, f64)> {
        self.names.iter().cloned().zip(theta.iter().copied()).collect()
    }

    fn automaton(&self, theta: &[f64]) -> Result<Automaton<f64>, FitError> {
        Ok(self.family.instantiate(&self.values(theta)).map_err(|e| FitError::Design(e.to_string()))?.automaton)
    }

    fn evaluator(&self, automaton: &Automaton<f64>, depth: usize) -> Result<Evaluator, FitError> {
        evaluator_with(automaton, &self.model, depth)
    }

    /// Whether the joint spectral radius bounds prove that the member at `theta` converges.
    pub(crate) fn proof(&self, theta: &[f64]) -> Proof {
        let Ok(automaton) = self.automaton(theta) else {
            return Proof { converges: false, upper: f64::INFINITY, witness: Vec::new() };
        };
        match crate::analysis::jsr(&automaton, &crate::analysis::JsrSettings::default()) {
            Ok(j) => Proof { converges: j.verdict().converges() == Some(true), upper: j.upper, witness: j.witness },
            Err(_) => Proof { converges: false, upper: f64::INFINITY, witness: Vec::new() },
        }
    }

    /// The residuals at `theta` (points: both ways, each side's mean; numbers: their differences), with
    /// the Jacobian when `jacobian`: exact for the points (forward mode down the tree), central
    /// differences for the numbers (the reports that give them are not polynomials).
    pub(crate) fn residuals(&self, theta: &[f64], jacobian: bool) -> Result<Residuals, FitError> {
        self.residuals_paired(theta, jacobian, None)
    }

    /// [`Problem::residuals`] with the points paired as `pairs` says (the
    /// pairs of another member: the same leaf numbers), or as found afresh.
    pub(crate) fn residuals_paired(
        &self,
        theta: &[f64],
        jacobian: bool,
        pairs: Option<&Pairs>,
    ) -> Result<Residuals, FitError> {
        let (m, all) = (self.names.len(), self.unknowns());
        let mut rows: Vec<f64> = Vec::new();
        let mut jac: Vec<Vec<f64>> = Vec::new();
        let (mut distance, mut found) = (None, None);
        if let Some(points) = &self.points {
            let tangents = self.tangents(theta, jacobian)?;
            let tangents = match self.pose(theta) {
                Some((u, t)) => posed(&tangents, u, &t, jacobian),
                None => tangents,
            };
            let fresh = pair(points, &tangents);
            distance = Some(fresh.distance);
            let used = pairs.filter(|p| p.to_target.len() == tangents.len()).unwrap_or(&fresh);
            point_rows(points, &tangents, used, self.level.get().1, jacobian, &mut rows, &mut jac);
            found = Some(fresh);
        }
        let mut numbers = Vec::new();
        for &(measure, target) in &self.numbers {
            let value = self.measured(measure, theta)?;
            numbers.push((measure, value));
            rows.push((value.value - target) / measure.scale());
            if jacobian {
                let slope = |j| self.number_slope(measure, theta, j, value);
                let mut row = (0..m).map(slope).collect::<Result<Vec<_>, _>>()?;
                row.resize(all, 0.0);
                jac.push(row);
            }
        }
        let r = DVector::from_vec(rows);
        let jacobian = jacobian.then(|| DMatrix::from_fn(jac.len(), all, |i, j| jac[i][j]));
        Ok(Residuals { r, jacobian, distance, numbers, pairs: found })
    }

    /// The slope of a number target along parameter `j`: a central difference, one-sided where
    /// the measure has no value on one side (a curve whose junction angle ends there), none
    /// where it has none on either. A box count changes by steps (a box met or not): its
    /// difference spans [`BOX_STEP`] of the parameter, where the change outweighs its spread.
    fn number_slope(&self, measure: Measure, theta: &[f64], j: usize, at_theta: Measured) -> Result<f64, FitError> {
        let relative = if at_theta.within > 0.0 { BOX_STEP } else { 1e-6 };
        let h = relative * theta[j].abs().max(1.0);
        let at = |x: f64| {
            let mut t = theta.to_vec();
            t[j] += x;
            // A dimension only where the member is proven to converge (past the edge a box count
            // costs much, or the attractor is not there).
            if measure == Measure::Dimension && !self.proof(&t).converges {
                return None;
            }
            self.measured(measure, &t).ok().map(|m| m.value)
        };
        let slope = match (at(h), at(-h)) {
            (Some(p), Some(m)) => (p - m) / (2.0 * h),
            (Some(p), None) => (p - at_theta.value) / h,
            (None, Some(m)) => (at_theta.value - m) / h,
            (None, None) => 0.0,
        };
        Ok(slope / measure.scale())
    }

    /// A number target's value at `theta`, and how far it can be trusted.
    pub(crate) fn measured(&self, measure: Measure, theta: &[f64]) -> Result<Measured, FitError> {
        let values = self.values(theta);
        let report = |e: crate::report::ReportError| FitError::Design(e.to_string());
        let exact = |value: f64| Measured { value, within: 0.0 };
        match measure {
            Measure::Dimension => {
                // A similarity dimension where there is one (exact, and no points to count).
                if let Some(s) = crate::report::similarity_dimension(self.design, &values).map_err(report)? {
                    return Ok(exact(s));
                }
                let d = crate::report::dimension_report(self.design, &values).map_err(report)?;
                match (d.similarity, d.fit) {
                    (Some(s), _) => Ok(exact(s)),
                    (None, Some(f)) => Ok(Measured { value: f.dimension, within: BOX_SPREAD }),
                    (None, None) => {
                        Err(FitError::Design(format!("{}: no dimension at these parameters", self.design.name())))
                    }
                }
            }
            Measure::Angle => {
                let exact_values: Vec<(String, crate::algebra::Num)> =
                    values.iter().map(|(n, v)| (n.clone(), crate::algebra::Num::from_f64(*v))).collect();
                let a = crate::report::curve_analysis(self.design, &exact_values).map_err(report)?;
                a.report.junction_angle_deg.map(exact).ok_or_else(|| {
                    FitError::Design(format!("{}: no junction angle at these parameters", self.design.name()))
                })
            }
            Measure::Porosity => {
                let depth = self.depth.clamp(1, 4);
                let p = crate::report::porosity(self.design, &values, depth).map_err(report)?;
                p.last().copied().map(exact).ok_or_else(|| FitError::Design("no porosity".into()))
            }
        }
    }

    /// The leaf points at `theta` and, when `derivatives`, their derivatives along every parameter
    /// (then along every control point's coordinate, when they are fitted: the leaf points are
    /// linear in them, and each one's derivative is the evaluation with that coordinate 1, the
    /// others 0).
    fn tangents(&self, theta: &[f64], derivatives: bool) -> Result<Tangents, FitError> {
        let automaton = self.automaton(theta)?;
        let t = self.parameter_tangents(theta, &automaton, derivatives)?;
        if !derivatives || self.control == 0 {
            return Ok(t);
        }
        let mut columns = Vec::with_capacity(self.control);
        for (k, p) in self.model.points.iter().enumerate() {
            for a in 0..p.len() {
                let mut unit = self.model.clone();
                unit.points.iter_mut().flatten().for_each(|x| *x = 0.0);
                unit.points[k][a] = 1.0;
                let ev = evaluator_with(&automaton, &unit, self.level.get().0)?;
                columns.push(ev.tangents(self.level.get().0, &no_directions()).points);
            }
        }
        Ok(with_columns(&t, &columns))
    }

    fn parameter_tangents(
        &self,
        theta: &[f64],
        automaton: &Automaton<f64>,
        derivatives: bool,
    ) -> Result<Tangents, FitError> {
        let ev = evaluator_with(automaton, &self.model_at(theta), self.level.get().0)?;
        let m = if derivatives { self.names.len() } else { 0 };
        let mut matrices: HashMap<EdgeIndex, Vec<Option<Vec<f64>>>> = HashMap::new();
        let mut samples: Vec<Vec<Option<Vec<Vec<f64>>>>> = vec![vec![None; m]; ev.state_count()];
        for j in 0..m {
            let mut step = theta.to_vec();
            step[j] += 1.0;
            // Every entry is affine in the parameters: a unit step's difference is the derivative.
            let moved = self.automaton(&step)?;
            for (e, arrow) in automaton.arrows() {
                let d = &moved.arrow(e).matrix - &arrow.matrix;
                let d = &d;
                let row_major: Vec<f64> = (0..d.nrows()).flat_map(|i| (0..d.ncols()).map(move |c| d[(i, c)])).collect();
                let slot = matrices.entry(e).or_insert_with(|| vec![None; m]);
                slot[j] = row_major.iter().any(|x| *x != 0.0).then_some(row_major);
            }
            for (slot, slope) in samples.iter_mut().zip(self.sample_slopes(theta, j, &ev)) {
                slot[j] = slope;
            }
        }
        let matrix = |e: EdgeIndex, j: usize| matrices.get(&e).and_then(|v| v[j].as_deref());
        let sample = |s: usize, j: usize| samples[s][j].as_deref();
        Ok(ev.tangents(self.level.get().0, &Directions { count: m, matrix: &matrix, samples: &sample }))
    }

    /// The derivatives of every state's leaf samples (vertex fixed points, edge ends: rational in
    /// the parameters) along parameter `j`: none for a state whose samples do not move, else a
    /// central difference extrapolated once (Richardson: error of the order of h⁴). The
    /// evaluators at the steps are made once for all the states.
    fn sample_slopes(&self, theta: &[f64], j: usize, ev: &Evaluator) -> Vec<Option<Vec<Vec<f64>>>> {
        let states = ev.state_count();
        let at = |x: f64| -> Option<Vec<Vec<Vec<f64>>>> {
            let mut t = theta.to_vec();
            t[j] += x;
            let moved = self.evaluator(&self.automaton(&t).ok()?, 0).ok()?;
            Some((0..states).map(|s| moved.leaf_samples(s)).collect())
        };
        let h = 1e-3 * theta[j].abs().max(1.0);
        let (Some(plus), Some(minus)) = (at(h), at(-h)) else { return vec![None; states] };
        let moves: Vec<bool> =
            (0..states).map(|s| plus[s] != ev.leaf_samples(s) || minus[s] != ev.leaf_samples(s)).collect();
        if !moves.contains(&true) {
            return vec![None; states];
        }
        let (Some(half_plus), Some(half_minus)) = (at(h / 2.0), at(-h / 2.0)) else { return vec![None; states] };
        let diff = |p: &[Vec<f64>], q: &[Vec<f64>], step: f64| -> Vec<Vec<f64>> {
            p.iter().zip(q).map(|(a, b)| a.iter().zip(b).map(|(x, y)| (x - y) / (2.0 * step)).collect()).collect()
        };
        (0..states)
            .map(|s| {
                moves[s].then(|| {
                    let (wide, narrow) = (diff(&plus[s], &minus[s], h), diff(&half_plus[s], &half_minus[s], h / 2.0));
                    wide.iter()
                        .zip(&narrow)
                        .map(|(w, n)| w.iter().zip(n).map(|(a, b)| (4.0 * b - a) / 3.0).collect())
                        .collect()
                })
            })
            .collect()
    }
}

fn evaluator_with(automaton: &Automaton<f64>, model: &Model, depth: usize) -> Result<Evaluator, FitError> {
    Evaluator::new(automaton, model, EvalSettings::default().with_depth(depth))
        .map_err(|e| FitError::Design(e.to_string()))
}

fn no_directions() -> Directions<'static> {
    Directions { count: 0, matrix: &|_, _| None, samples: &|_, _| None }
}

/// `t` with more directions after its own: `columns[c]` holds every point's derivative along the
/// `c`-th (`dim` coordinates a point, in order).
fn with_columns(t: &Tangents, columns: &[Vec<f64>]) -> Tangents {
    let (d, m) = (t.dim, t.directions);
    let mut out = Tangents { dim: d, directions: m + columns.len(), points: t.points.clone(), ..Tangents::default() };
    for p in 0..t.len() {
        (0..m).for_each(|j| out.derivatives.extend_from_slice(t.derivative(p, j)));
        columns.iter().for_each(|c| out.derivatives.extend_from_slice(&c[p * d..(p + 1) * d]));
    }
    out
}

/// The leaf points `t` mapped by a pose, `x ↦ u·(x − shift)`, with their derivatives: along each
/// parameter `u·dx`, then along `u` (`x − shift`) and each shift (`−u` on its coordinate).
fn posed(t: &Tangents, u: f64, shift: &[f64], derivatives: bool) -> Tangents {
    let (d, m) = (t.dim, t.directions);
    let count = if derivatives { m + 1 + d } else { 0 };
    let mut out =
        Tangents { dim: d, directions: count, points: Vec::with_capacity(t.points.len()), ..Tangents::default() };
    for p in 0..t.len() {
        let x = &t.points[p * d..(p + 1) * d];
        out.points.extend((0..d).map(|a| u * (x[a] - shift[a])));
        if derivatives {
            (0..m).for_each(|j| out.derivatives.extend(t.derivative(p, j).iter().map(|v| u * v)));
            out.derivatives.extend((0..d).map(|a| x[a] - shift[a]));
            for k in 0..d {
                out.derivatives.extend((0..d).map(|a| if a == k { -u } else { 0.0 }));
            }
        }
    }
    out
}

/// The nearest points both ways between the target and the leaf points `t`.
fn pair(points: &Points, t: &Tangents) -> Pairs {
    let shape = shape_points(t);
    let shape_tree = KdTree::new(shape.clone());
    let (mut to_shape, mut to_target) = (Vec::with_capacity(points.count), Vec::with_capacity(shape.len()));
    let (mut sum_shape, mut sum_target) = (0.0, 0.0);
    for q in points.tree.points() {
        let (p, d2) = shape_tree.nearest(*q).expect("a shape has points");
        sum_shape += d2;
        to_shape.push(p);
    }
    for x in &shape {
        let (k, d2) = points.tree.nearest(*x).expect("a target has points");
        sum_target += d2;
        to_target.push(k);
    }
    let distance = ((sum_shape / points.count as f64 + sum_target / shape.len() as f64) / 2.0).sqrt();
    Pairs { to_shape, to_target, distance }
}

fn shape_points(t: &Tangents) -> Vec<[f64; 3]> {
    let d = t.dim;
    (0..t.len())
        .map(|p| {
            let mut x = [0.0; 3];
            x[..d].copy_from_slice(&t.points[p * d..(p + 1) * d]);
            x
        })
        .collect()
}

/// The points' residual rows for `pairs` (target to shape, then shape to target, each side divided
/// by the square root of its count and by the target's diagonal; each offset measured on the
/// target point's frame) and, when `jacobian`, their rows of the Jacobian.
fn point_rows(
    points: &Points,
    t: &Tangents,
    pairs: &Pairs,
    both: bool,
    jacobian: bool,
    rows: &mut Vec<f64>,
    jac: &mut Vec<Vec<f64>>,
) {
    let (d, m) = (t.dim, t.directions);
    let shape = shape_points(t);
    let mut push = |p: usize, k: usize, weight: f64| {
        let (x, q) = (shape[p], points.tree.points()[k]);
        for (axis, w) in &points.frames[k] {
            let along = |v: &dyn Fn(usize) -> f64| (0..d).map(|a| axis[a] * v(a)).sum::<f64>() * w * weight;
            rows.push(along(&|a| x[a] - q[a]));
            if jacobian {
                jac.push((0..m).map(|j| along(&|a| t.derivative(p, j)[a])).collect());
            }
        }
    };
    let w_target = 1.0 / (points.count as f64).sqrt() / points.scale;
    for (k, &p) in pairs.to_shape.iter().enumerate().filter(|_| both) {
        push(p, k, w_target);
    }
    let w_shape = 1.0 / (shape.len() as f64).sqrt() / points.scale;
    for (p, &k) in pairs.to_target.iter().enumerate() {
        push(p, k, w_shape);
    }
}

/// The frame of target point `q`: the principal axes of its nearest
/// points, the `cells` widest (along a curve, a surface) weighted [`ALONG`],
/// the others (across) 1.
fn frame(tree: &KdTree, q: [f64; 3], cells: usize) -> [([f64; 3], f64); 3] {
    let near = tree.nearest_k(q, NEIGHBOURS);
    let mut mean = [0.0; 3];
    near.iter().for_each(|&i| (0..3).for_each(|a| mean[a] += tree.points()[i][a] / near.len() as f64));
    let mut cov = nalgebra::Matrix3::<f64>::zeros();
    for &i in &near {
        let v = nalgebra::Vector3::from_fn(|a, _| tree.points()[i][a] - mean[a]);
        cov += v * v.transpose();
    }
    let eigen = cov.symmetric_eigen();
    let mut axes: Vec<(f64, [f64; 3])> =
        (0..3).map(|k| (eigen.eigenvalues[k], [0, 1, 2].map(|a| eigen.eigenvectors[(a, k)]))).collect();
    axes.sort_by(|a, b| b.0.total_cmp(&a.0));
    [0, 1, 2].map(|k| (axes[k].1, if k < cells { ALONG } else { 1.0 }))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The points' Jacobian is the residuals' derivative: central differences agree to 1e-6
    /// (the nearest points do not change over so small a step).
    #[test]
    fn the_jacobian_is_the_derivative_of_the_residuals() {
        for name in ["corner_cutting", "doo_sabin_torus"] {
            let design = crate::render::load(name).unwrap();
            let ev = crate::render::Options::default().with_depth(3);
            let shape = crate::render::evaluate_design(&design, &ev, &mut Vec::new()).unwrap();
            let moved = |p: &[f64; 3]| [p[0] * 1.01 + 0.003, p[1] * 1.01 - 0.002, p[2] * 1.01];
            let target = FitTarget { points: shape.points().iter().map(moved).collect(), ..Default::default() };
            let problem = Problem::new(&design, &target, Some(3), false).unwrap();
            let theta: Vec<f64> = problem.defaults().iter().map(|x| x + 0.01).collect();
            let res = problem.residuals(&theta, true).unwrap();
            let j = res.jacobian.unwrap();
            for k in 0..theta.len() {
                let h = 1e-7;
                let at = |x: f64| {
                    let mut t = theta.clone();
                    t[k] += x;
                    problem.residuals(&t, false).unwrap().r
                };
                let fd = (at(h) - at(-h)) / (2.0 * h);
                let err = (&fd - j.column(k)).amax();
                assert!(err < 1e-6 * fd.amax().max(1.0), "{name} parameter {k}: {err} (scale {})", fd.amax());
            }
        }
    }
}
