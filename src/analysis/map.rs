//! Convergence verdicts over a plane of two parameters of a family: the
//! map a designer looks at to find where a family converges.

use rayon::prelude::*;

use super::jsr::{JsrSettings, Verdict, jsr_verdict};
use crate::algebra::{contractive_spectrum, eigenvalues};
use crate::automaton::{ArrowKind, Automaton};
use crate::family::{Family, InstantiateError, NumericFamily};

/// One pixel of a verdict map.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MapCell {
    /// What the joint spectral radius bounds prove.
    pub verdict: Verdict,
    /// Whether every square subdivision matrix passes the per-matrix
    /// eigenvalue test (Sokolov et al. 2010 §3: necessary, not sufficient).
    pub per_matrix: bool,
}

/// The per-matrix condition of Sokolov et al. 2010 §3: every square subdivision arrow
/// has one eigenvalue 1 and all others of modulus below 1.
pub fn per_matrix_condition(automaton: &Automaton<f64>) -> bool {
    automaton.arrows().all(|(id, a)| {
        a.kind != ArrowKind::Subdivision
            || !a.matrix.is_square()
            || !automaton.on_cycle(id)
            || eigenvalues(&a.matrix).is_some_and(|e| contractive_spectrum(&e, crate::algebra::tolerance::CONTRACTIVE))
    })
}

/// A rectangle of two free parameters of a family, sampled at pixel centres;
/// or a segment of one ([`ParameterPlane::line`]: y names the x parameter,
/// and only x varies).
#[derive(Clone, Debug, PartialEq)]
pub struct ParameterPlane {
    /// The parameter along x and its range.
    pub x: (String, f64, f64),
    /// The parameter along y and its range (y grows upwards: row 0 is the top).
    pub y: (String, f64, f64),
    /// Pixels along x and along y.
    pub size: (usize, usize),
}

impl ParameterPlane {
    /// The segment `from..to` of the parameter `name` in `n` pixels: a plane
    /// of one row whose y is its x (one-parameter families such as the
    /// ternary scheme's tension ω).
    pub fn line(name: &str, from: f64, to: f64, n: usize) -> ParameterPlane {
        ParameterPlane { x: (name.into(), from, to), y: (name.into(), from, to), size: (n, 1) }
    }

    /// Whether this is a [`ParameterPlane::line`]: only x varies.
    pub fn is_line(&self) -> bool {
        self.x.0 == self.y.0
    }

    /// The parameter values at the centre of pixel `(column, row)`, by name
    /// (one value on a line).
    pub fn values_at(&self, column: usize, row: usize) -> Vec<(String, f64)> {
        let (x, y) = self.at(column, row);
        if self.is_line() { vec![(self.x.0.clone(), x)] } else { vec![(self.x.0.clone(), x), (self.y.0.clone(), y)] }
    }

    /// The parameter values at the centre of pixel `(column, row)`.
    pub fn at(&self, column: usize, row: usize) -> (f64, f64) {
        let (w, h) = (self.size.0.max(1) as f64, self.size.1.max(1) as f64);
        let x = self.x.1 + (self.x.2 - self.x.1) * (column as f64 + 0.5) / w;
        let y = self.y.2 - (self.y.2 - self.y.1) * (row as f64 + 0.5) / h;
        (x, y)
    }
}

/// The convergence verdict and the per-matrix condition at every pixel of
/// `plane` (row by row, top row first), the other parameters at their
/// defaults, in parallel over rows. A pixel whose matrices are not
/// column-stochastic is `Undecided`.
///
/// # Errors
/// A parameter of the plane that the family does not have, or another
/// parameter without a default.
///
/// # Example
/// ```
/// use bcifs::analysis::{JsrSettings, ParameterPlane, Verdict, verdict_map};
/// let family = bcifs::solve(&bcifs::builtin_design("corner_cutting").unwrap()).unwrap();
/// let plane = ParameterPlane { x: ("a".into(), -1.0, 1.0), y: ("b".into(), -1.0, 1.0), size: (8, 8) };
/// let map = verdict_map(&family, &plane, &JsrSettings::quick()).unwrap();
/// assert_eq!(map.len(), 64);
/// assert!(map.iter().any(|c| c.verdict == Verdict::Converges) && map.iter().any(|c| c.verdict == Verdict::Diverges));
/// ```
pub fn verdict_map(
    family: &Family,
    plane: &ParameterPlane,
    settings: &JsrSettings,
) -> Result<Vec<MapCell>, InstantiateError> {
    verdict_map_rows(family, plane, settings, 0..plane.size.1)
}

/// [`verdict_map`] of the rows `rows` of `plane` only: the same pixels, bit
/// for bit, as the whole map's (a band of it, for sweeps split over
/// machines).
///
/// # Errors
/// As [`verdict_map`].
pub fn verdict_map_rows(
    family: &Family,
    plane: &ParameterPlane,
    settings: &JsrSettings,
    rows: std::ops::Range<usize>,
) -> Result<Vec<MapCell>, InstantiateError> {
    over_rows(family, plane, rows, |automaton| {
        let verdict = jsr_verdict(automaton, settings).unwrap_or(Verdict::Undecided);
        MapCell { verdict, per_matrix: per_matrix_condition(automaton) }
    })
}

/// `cell` at the centre of every pixel of the rows `rows` of `plane` (row
/// by row, top row first), the other parameters at their defaults, in parallel over rows
/// (one numeric automaton per thread, refilled at every pixel).
fn over_rows<T: Send>(
    family: &Family,
    plane: &ParameterPlane,
    rows: std::ops::Range<usize>,
    cell: impl Fn(&Automaton<f64>) -> T + Sync,
) -> Result<Vec<T>, InstantiateError> {
    let w = plane.size.0;
    let rows = rows.start.min(plane.size.1)..rows.end.min(plane.size.1);
    // Checks the names and the defaults once, before the threads start.
    let (xname, yname) = (plane.x.0.clone(), plane.y.0.clone());
    let base = family.parameter_values(&[(xname.clone(), plane.x.1), (yname.clone(), plane.y.1)])?;
    let names = family.parameter_names();
    let (ix, iy) =
        (names.iter().position(|n| *n == xname).unwrap_or(0), names.iter().position(|n| *n == yname).unwrap_or(0));
    let numeric = NumericFamily::new(family);
    let rows: Vec<Vec<T>> = rows
        .into_par_iter()
        .map_init(
            || (numeric.automaton(), base.clone()),
            |(automaton, x), row| {
                (0..w)
                    .map(|column| {
                        // On a line (iy = ix) x is the value that stays.
                        let (vx, vy) = plane.at(column, row);
                        x[iy] = vy;
                        x[ix] = vx;
                        numeric.fill(x, automaton);
                        cell(automaton)
                    })
                    .collect()
            },
        )
        .collect();
    Ok(rows.into_iter().flatten().collect())
}

/// A pixel of a curve-family map: the convergence verdict, the per-matrix
/// condition and the curve's differential behaviour there.
#[derive(Clone, Debug, PartialEq)]
pub struct CurveCell {
    /// The joint spectral radius verdict.
    pub verdict: Verdict,
    /// Sokolov et al. 2010 §3's per-matrix condition.
    pub per_matrix: bool,
    /// Half-tangents, junction angle and region (`None` when the pixel does not instantiate).
    pub report: Option<super::curve::CurveReport>,
}

impl CurveCell {
    /// The region of Sokolov et al. 2010 Fig. 8 where the bounds prove convergence,
    /// `divergent` where they prove divergence, `None` where undecided.
    pub fn region(&self) -> Option<&'static str> {
        match self.verdict {
            Verdict::Diverges => Some("divergent"),
            Verdict::Converges => self.report.as_ref().and_then(|r| r.region),
            Verdict::Undecided => None,
        }
    }

    /// The junction angle in degrees, where the halves have half-tangents.
    pub fn angle(&self) -> Option<f64> {
        self.report.as_ref().and_then(|r| r.junction_angle_deg)
    }
}

/// [`verdict_map`] with [`super::curve::curve_query`] at every pixel, for
/// a family whose state `root` is a curve with two subdivision arrows `T0`,
/// `T1` to itself (in the order of the automaton).
///
/// # Errors
/// As [`verdict_map`].
pub fn curve_map(
    family: &Family,
    plane: &ParameterPlane,
    settings: &JsrSettings,
    root: &str,
) -> Result<Vec<CurveCell>, InstantiateError> {
    curve_map_rows(family, plane, settings, root, 0..plane.size.1)
}

/// [`curve_map`] of the rows `rows` of `plane` only (a band of it, bit for bit).
///
/// # Errors
/// As [`verdict_map`].
pub fn curve_map_rows(
    family: &Family,
    plane: &ParameterPlane,
    settings: &JsrSettings,
    root: &str,
    rows: std::ops::Range<usize>,
) -> Result<Vec<CurveCell>, InstantiateError> {
    over_rows(family, plane, rows, |a| {
        // A matrix with an eigenvalue of modulus ≥ 1 on the differences already makes
        // the joint spectral radius ≥ 1: no bounds needed there.
        let per_matrix = per_matrix_condition(a);
        let verdict =
            if per_matrix { jsr_verdict(a, settings).unwrap_or(Verdict::Undecided) } else { Verdict::Diverges };
        let report = a.state_id(root).and_then(|r| {
            let arrows = a.outgoing(r, ArrowKind::Subdivision);
            (arrows.len() == 2)
                .then(|| super::curve::curve_query(&a.arrow(arrows[0]).matrix, &a.arrow(arrows[1]).matrix))
        });
        CurveCell { verdict, per_matrix, report }
    })
}
