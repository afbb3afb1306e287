//! Parameter sweeps: one quantity at every pixel of a plane of two free
//! parameters of a family, computed band by band so that a sweep splits
//! over threads, processes or machines and gives the same array, bit for
//! bit. `analyze map` writes them (a picture, or CSV); the Python module's
//! `bcifs.sweep` returns them as arrays, on Dask workers when asked.

use std::fmt::Write as _;
use std::ops::Range;

use super::error::ReportError;
use crate::analysis::{JsrSettings, ParameterPlane, Verdict, curve_map_rows, verdict_map_rows};
use crate::design::Design;
use crate::family::solve;
use crate::progress::Cancel;

/// The memory one pixel of a dimension sweep may take (the points of its
/// evaluation): a pixel near the edge of the convergence domain contracts
/// so slowly that its points would take more, and is left NaN.
pub const SWEEP_MEMORY: usize = 16 << 20;

/// What a sweep computes at each pixel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SweepKind {
    /// The convergence verdict ([`SweepKind::verdict_code`]).
    Verdict,
    /// The region of Sokolov et al. 2010 Fig. 8 of a curve family, an index into [`REGIONS`].
    Region,
    /// The junction angle of a curve family's half-tangents, in degrees (NaN: none).
    Angle,
    /// The box-counting dimension of the attractor where the bounds prove
    /// convergence (NaN elsewhere, with too few scales, or where the points
    /// would take more than 16 MiB, `SWEEP_MEMORY`).
    Dimension,
    /// The porosity at depth [`SWEEP_DEPTH`] where the bounds prove convergence
    /// (the area or length its cells leave empty; NaN elsewhere).
    Porosity,
    /// The gliding-box lacunarity `Λ(9)` at depth [`SWEEP_DEPTH`] where the bounds
    /// prove convergence (how clustered the holes are; NaN elsewhere).
    Lacunarity,
}

/// The depth of porosity and lacunarity sweeps.
pub const SWEEP_DEPTH: usize = 4;

/// The regions of a region sweep, by code: `REGIONS[code]`.
pub const REGIONS: [&str; 10] = ["undecided", "1", "2", "2'", "3", "3'", "4", "5", "divergent", "degenerate"];

impl std::str::FromStr for SweepKind {
    type Err = ReportError;
    fn from_str(text: &str) -> Result<SweepKind, ReportError> {
        Ok(match text {
            "verdict" => SweepKind::Verdict,
            "region" | "regions" => SweepKind::Region,
            "angle" | "roughness" => SweepKind::Angle,
            "dimension" => SweepKind::Dimension,
            "porosity" => SweepKind::Porosity,
            "lacunarity" => SweepKind::Lacunarity,
            other => {
                return Err(ReportError::Unsupported(format!(
                    "unknown sweep `{other}`: expected verdict, region, angle, dimension, porosity or lacunarity"
                )));
            }
        })
    }
}

impl SweepKind {
    /// The name used by `analyze map --what` and `bcifs.sweep(what=…)`.
    pub fn name(self) -> &'static str {
        match self {
            SweepKind::Verdict => "verdict",
            SweepKind::Region => "region",
            SweepKind::Angle => "angle",
            SweepKind::Dimension => "dimension",
            SweepKind::Porosity => "porosity",
            SweepKind::Lacunarity => "lacunarity",
        }
    }

    /// The code of a verdict pixel: 1 converges, 0 undecided, -1 diverges
    /// although every matrix passes Sokolov et al. 2010 §3's per-matrix condition, -2
    /// a subdivision matrix fails it.
    pub fn verdict_code(verdict: Verdict, per_matrix: bool) -> i8 {
        match (verdict, per_matrix) {
            (Verdict::Converges, _) => 1,
            (Verdict::Undecided, _) => 0,
            (Verdict::Diverges, true) => -1,
            (Verdict::Diverges, false) => -2,
        }
    }

    /// The label of a code (verdicts and regions), as CSV writes it.
    pub fn label(self, value: f64) -> &'static str {
        match self {
            SweepKind::Verdict => match value as i8 {
                1 => "converges",
                0 => "undecided",
                -1 => "diverges",
                _ => "matrix fails",
            },
            SweepKind::Region => REGIONS.get(value as usize).copied().unwrap_or("undecided"),
            SweepKind::Angle | SweepKind::Dimension | SweepKind::Porosity | SweepKind::Lacunarity => "",
        }
    }
}

/// The pixels of a band of a sweep: codes (verdicts, regions) or values (angles, dimensions).
#[derive(Clone, Debug, PartialEq)]
pub enum SweepValues {
    /// Verdict codes or region indices.
    Codes(Vec<i8>),
    /// Angles or dimensions; NaN where there is none.
    Values(Vec<f64>),
}

impl SweepValues {
    /// The pixels of consecutive bands as one sweep (`rest` after `self`);
    /// bands of different kinds are joined as values.
    pub fn append(self, rest: SweepValues) -> SweepValues {
        match (self, rest) {
            (SweepValues::Codes(mut a), SweepValues::Codes(b)) => {
                a.extend(b);
                SweepValues::Codes(a)
            }
            (a, b) => SweepValues::Values([a.to_f64(), b.to_f64()].concat()),
        }
    }

    /// Every pixel as a number.
    pub fn to_f64(&self) -> Vec<f64> {
        match self {
            SweepValues::Codes(c) => c.iter().map(|&c| f64::from(c)).collect(),
            SweepValues::Values(v) => v.clone(),
        }
    }
}

/// `kind` at every pixel of the rows `rows` of `plane` (row by row, top
/// row first; the other parameters at their defaults), with the quick
/// bounds search or the full one (`thorough`). The rows of a whole sweep,
/// bit for bit, whatever the bands it is cut into.
///
/// # Errors
/// A family that does not solve, a parameter it does not have, a design
/// that is not a curve family for regions and angles, no model for dimensions.
///
/// # Example
/// ```
/// use bcifs::analysis::ParameterPlane;
/// use bcifs::report::{SweepKind, SweepValues, sweep};
/// let design = bcifs::builtin_design("corner_cutting").unwrap();
/// let plane = ParameterPlane { x: ("a".into(), 0.0, 0.5), y: ("b".into(), 0.0, 0.5), size: (4, 4) };
/// let SweepValues::Codes(top) = sweep(&design, &plane, SweepKind::Verdict, false, 0..2).unwrap() else { panic!() };
/// let SweepValues::Codes(all) = sweep(&design, &plane, SweepKind::Verdict, false, 0..4).unwrap() else { panic!() };
/// assert_eq!(top, all[..8]);
/// ```
pub fn sweep(
    design: &Design,
    plane: &ParameterPlane,
    kind: SweepKind,
    thorough: bool,
    rows: Range<usize>,
) -> Result<SweepValues, ReportError> {
    sweep_cancellable(design, plane, kind, thorough, rows, &Cancel::new())
}

/// [`sweep`], stopped when `cancel` is set: between pixels of a dimension
/// sweep (each evaluates an attractor), after the bounds of the others.
///
/// # Errors
/// As [`sweep`]; [`ReportError::Cancelled`].
pub fn sweep_cancellable(
    design: &Design,
    plane: &ParameterPlane,
    kind: SweepKind,
    thorough: bool,
    rows: Range<usize>,
    cancel: &Cancel,
) -> Result<SweepValues, ReportError> {
    let name = design.name();
    let family = solve(design).map_err(|e| ReportError::Unsupported(format!("{name}: {e}")))?;
    let settings = if thorough { JsrSettings::default() } else { JsrSettings::quick() };
    let instantiate = |e: crate::family::InstantiateError| ReportError::Unsupported(format!("{name}: {e}"));
    match kind {
        SweepKind::Verdict | SweepKind::Dimension | SweepKind::Porosity | SweepKind::Lacunarity => {
            let cells = verdict_map_rows(&family, plane, &settings, rows.clone()).map_err(instantiate)?;
            if kind == SweepKind::Verdict {
                return Ok(SweepValues::Codes(
                    cells.iter().map(|c| SweepKind::verdict_code(c.verdict, c.per_matrix)).collect(),
                ));
            }
            super::error::model_of(design)?;
            let w = plane.size.0;
            let first = rows.start.min(plane.size.1);
            // One pixel after another, each evaluation parallel inside: pixels in
            // parallel nest evaluations on the stacks of rayon's workers (a worker
            // waiting in one steals another's), which overflowed them.
            let mut values = Vec::with_capacity(cells.len());
            for (i, c) in cells.iter().enumerate() {
                if cancel.is_cancelled() {
                    return Err(ReportError::Cancelled);
                }
                if c.verdict != Verdict::Converges {
                    values.push(f64::NAN);
                    continue;
                }
                let at = plane.values_at(i % w, first + i / w);
                values.push(match kind {
                    SweepKind::Dimension => match super::dimension::dimension_within(design, &at, SWEEP_MEMORY, cancel)
                    {
                        Err(ReportError::Cancelled) => return Err(ReportError::Cancelled),
                        r => r.ok().and_then(|r| r.fit.map(|f| f.dimension)).unwrap_or(f64::NAN),
                    },
                    _ => holes(design, &at, kind),
                });
            }
            Ok(SweepValues::Values(values))
        }
        SweepKind::Region | SweepKind::Angle => {
            // The root must be a curve (checked on the plane's corner).
            let corner = plane.values_at(0, plane.size.1.saturating_sub(1));
            super::curve::curve_halves(design, &crate::family::instantiate(design, &corner)?)?;
            let root = design.model().map(|m| m.root(0).to_string()).unwrap_or_default();
            let cells = curve_map_rows(&family, plane, &settings, &root, rows).map_err(instantiate)?;
            Ok(if kind == SweepKind::Region {
                SweepValues::Codes(
                    cells
                        .iter()
                        .map(|c| REGIONS.iter().position(|r| Some(*r) == c.region()).unwrap_or(0) as i8)
                        .collect(),
                )
            } else {
                SweepValues::Values(cells.iter().map(|c| c.angle().unwrap_or(f64::NAN)).collect())
            })
        }
    }
}

/// A pixel of a porosity or lacunarity sweep: NaN where there is none.
fn holes(design: &Design, at: &[(String, f64)], kind: SweepKind) -> f64 {
    if kind == SweepKind::Porosity {
        // The measure alone (the cells on their patches), not the lacunarity's raster.
        let p = super::lacunarity::porosity(design, at, SWEEP_DEPTH);
        return p.ok().and_then(|p| p.last().copied()).unwrap_or(f64::NAN);
    }
    let Ok(l) = super::lacunarity::lacunarity_report(design, at, SWEEP_DEPTH) else { return f64::NAN };
    l.lacunarity.iter().find(|[r, _]| *r == 9.0).map_or(f64::NAN, |[_, v]| *v)
}

/// A whole sweep as CSV: a header `X,Y,what,label` and a row per pixel
/// (row by row, top row first): the parameter values at the pixel's
/// centre, the value (empty for NaN) and the label of codes.
pub fn sweep_csv(plane: &ParameterPlane, kind: SweepKind, values: &SweepValues) -> String {
    let mut text = format!("{},{},{},label\n", plane.x.0, plane.y.0, kind.name());
    for (i, v) in values.to_f64().into_iter().enumerate() {
        let (x, y) = plane.at(i % plane.size.0.max(1), i / plane.size.0.max(1));
        let value = if v.is_nan() { String::new() } else { v.to_string() };
        let _ = writeln!(text, "{x},{y},{value},{}", kind.label(v));
    }
    text
}
