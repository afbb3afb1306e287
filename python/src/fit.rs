//! `bcifs.fit`: a design's free parameters fitted to points, a mesh, a picture or numbers.

use pyo3::prelude::*;

use crate::cancel::interruptible;
use crate::{Design, err, json_object};

/// The target points: a file (OBJ, OFF, PLY: vertices; PNG: an outline), an
/// (n, 2) or (n, 3) array-like, or anything with `vertices` (a `bcifs.Mesh`,
/// a trimesh mesh).
fn target_points(py: Python<'_>, design: &Design, target: &Bound<'_, PyAny>) -> PyResult<(Vec<[f64; 3]>, bool)> {
    let os = py.import("os")?;
    if target.is_instance_of::<pyo3::types::PyString>() || target.hasattr("__fspath__")? {
        let path: std::path::PathBuf = os.call_method1("fspath", (target,))?.extract()?;
        let picture = bcifs::render::is_picture(&path.to_string_lossy());
        return Ok((bcifs::render::read_target(&path, &design.inner).map_err(err)?, picture));
    }
    let array = if target.hasattr("vertices")? { target.getattr("vertices")? } else { target.clone() };
    let numpy = py.import("numpy")?;
    let array = numpy.call_method1("asarray", (array, numpy.getattr("float64")?))?;
    let shape: Vec<usize> = array.getattr("shape")?.extract()?;
    if shape.len() != 2 || !(2..=3).contains(&shape[1]) {
        return Err(err(format!("target: expected an (n, 2) or (n, 3) array of points, not shape {shape:?}")));
    }
    let rows: Vec<Vec<f64>> = array.call_method0("tolist")?.extract()?;
    Ok((rows.into_iter().map(|r| [r[0], r[1], r.get(2).copied().unwrap_or(0.0)]).collect(), false))
}

/// The library's target: the points of `target` (a picture's pose free) and the numbers.
fn fit_target(
    py: Python<'_>,
    design: &Design,
    target: Option<&Bound<'_, PyAny>>,
    dimension: Option<f64>,
    angle: Option<f64>,
    porosity: Option<f64>,
) -> PyResult<bcifs::render::FitTarget> {
    let (points, free_pose) = target.map(|t| target_points(py, design, t)).transpose()?.unwrap_or_default();
    Ok(bcifs::render::FitTarget { points, dimension, angle, porosity, free_pose })
}

/// Fits `design`'s free parameters to a target (points: a file path, an
/// array, a `bcifs.Mesh`; and/or numbers: `dimension`, `angle` in degrees,
/// `porosity`), staying where convergence is proven: the fitted design (its
/// parameters as defaults) and the report `bcifs fit --json` prints
/// (`parameters`, `residual`, `converges`, `reason`…). `progress(done,
/// total)` follows the iterations; Ctrl-C returns the best member so far
/// (`interrupted` true). `start` (the parameters in order) runs from that
/// member only, `control_points=True` fits the model's control points too
/// (the report's `control_points`, the fitted design's model), `free_pose` fits a scale and a shift of the shape onto the
/// points (a picture's outline, given as points): what `bcifs.fit(...,
/// client=)` sends each worker.
#[pyfunction]
#[pyo3(signature = (design, target=None, dimension=None, angle=None, porosity=None, depth=None, starts=4, progress=None, start=None, free_pose=false, control_points=false))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn fit<'py>(
    py: Python<'py>,
    design: &Design,
    target: Option<&Bound<'py, PyAny>>,
    dimension: Option<f64>,
    angle: Option<f64>,
    porosity: Option<f64>,
    depth: Option<usize>,
    starts: usize,
    progress: Option<&Bound<'py, PyAny>>,
    start: Option<Vec<f64>>,
    free_pose: bool,
    control_points: bool,
) -> PyResult<(Design, Bound<'py, PyAny>)> {
    let mut target = fit_target(py, design, target, dimension, angle, porosity)?;
    target.free_pose |= free_pose;
    let inner = design.inner.clone();
    let report = interruptible(py, progress, move |cancel, reporter| {
        let options = bcifs::render::FitOptions {
            depth,
            starts,
            cancel,
            progress: reporter,
            start,
            control_points,
            ..Default::default()
        };
        let report = bcifs::render::fit(&inner, &target, &options)?;
        let fitted = bcifs::render::fitted_design(&inner, &report)?;
        Ok::<_, bcifs::render::FitError>((fitted, report))
    })?
    .map_err(err)?;
    let (fitted, report) = report;
    let dict = json_object(py, &report.to_json())?;
    Ok((Design { inner: fitted }, dict))
}

/// The members `fit` would start from (each a list of the parameters in
/// order), and the target's points as an (n, 3) list with whether their pose
/// is free (a picture): what a cluster's workers are sent.
#[pyfunction]
#[pyo3(signature = (design, target=None, dimension=None, angle=None, porosity=None, depth=None, starts=4))]
#[allow(clippy::too_many_arguments, clippy::type_complexity)]
pub(crate) fn fit_starts(
    py: Python<'_>,
    design: &Design,
    target: Option<&Bound<'_, PyAny>>,
    dimension: Option<f64>,
    angle: Option<f64>,
    porosity: Option<f64>,
    depth: Option<usize>,
    starts: usize,
) -> PyResult<(Vec<Vec<f64>>, Vec<[f64; 3]>, bool)> {
    let target = fit_target(py, design, target, dimension, angle, porosity)?;
    let (points, free_pose) = (target.points.clone(), target.free_pose);
    let options = bcifs::render::FitOptions { depth, starts, ..Default::default() };
    let inner = &design.inner;
    let list = py.detach(|| bcifs::render::fit_starts(inner, &target, &options)).map_err(err)?;
    Ok((list, points, free_pose))
}
