//! Pictures of a deterministic evaluation: the depth a picture needs (a
//! route's decision, so here and not in the writers), curves and points
//! drawn while they are streamed, surfaces from memory.

use super::job::Job;
use super::output::{RenderError, Report};
use crate::eval::{Depth, EvalError, Evaluator};
use crate::export::RasterSettings;

/// Segments per pixel beyond which a curve picture stops subdividing even
/// if some segment is still longer than a pixel (a curve that does not
/// contract, drawn when forced).
pub const SEGMENTS_PER_PIXEL: u128 = 64;

/// The depth a picture of a curve needs, at most `depth`: the first whose
/// segments are all shorter than a pixel (deeper ones only move the curve
/// within the pixels it covers), or whose segments outnumber the pixels
/// [`SEGMENTS_PER_PIXEL`] times. Each probe streams `ev` once at a
/// shallower depth (the depths before the answer cost less than the
/// answer's picture); `ev` is left at the depth returned. `depth` for points.
///
/// # Errors
/// An evaluation error.
pub fn curve_picture_depth(ev: &mut Evaluator, settings: &RasterSettings, depth: usize) -> Result<usize, EvalError> {
    let pixels = u128::from(settings.width.max(1)) * u128::from(settings.height.max(1));
    if ev.polylines() == Some(true) {
        for k in 0..depth {
            ev.set_depth(Depth::Fixed(k))?;
            let (vertices, longest) = crate::export::stream_extent(|sink| ev.stream(sink), settings)?;
            if vertices == 0 || longest < 1.0 || vertices as u128 >= SEGMENTS_PER_PIXEL * pixels {
                return Ok(k);
            }
        }
    }
    ev.set_depth(Depth::Fixed(depth))?;
    Ok(depth)
}

/// Points per pixel beyond which a picture of points stops subdividing:
/// deeper, the points only fill the pixels they already darken.
pub const POINTS_PER_PIXEL: u128 = 64;

/// The depth a picture of points (a plain IFS, a fractal cell) needs, at
/// most `depth`: the deepest whose points number at most
/// [`POINTS_PER_PIXEL`] times the pixels (at least depth 0). Counted, not
/// evaluated: the gasket at depth 60 would be 3⁶⁰ points.
pub fn point_picture_depth(ev: &Evaluator, settings: &RasterSettings, depth: usize) -> usize {
    let pixels = u128::from(settings.width.max(1)) * u128::from(settings.height.max(1));
    let points = |k: usize| ev.total_samples(k) as u128;
    (1..=depth).take_while(|&k| points(k) <= POINTS_PER_PIXEL * pixels).last().unwrap_or(0)
}

/// The depth a picture of a surface needs: the first one whose quads
/// outnumber the pixels (deeper, a quad is smaller than a pixel and the
/// picture changes only by sub-pixel shading), at most `depth`; `depth`
/// for curves and points, which are streamed.
pub fn picture_depth(ev: &Evaluator, settings: &RasterSettings, depth: usize) -> usize {
    let pixels = u128::from(settings.width.max(1)) * u128::from(settings.height.max(1));
    (0..depth).find(|&k| ev.quads_at(k).is_some_and(|q| q >= pixels)).unwrap_or(depth)
}

/// A picture of a deterministic evaluation: curves and points drawn while
/// they are evaluated (twice streamed: the frame, then the drawing), at the
/// depth whose segments are below a pixel; surfaces from memory, at the
/// depth whose quads are below a pixel.
pub(super) fn deterministic_image(
    job: &Job,
    report: &mut Report,
) -> Result<(image::RgbImage, Option<crate::export::Matte>), RenderError> {
    let options = &job.options;
    let mut ev = job.evaluator(&mut report.warnings)?;
    let raster = &options.raster();
    let needed = crate::export::picture_bytes(raster);
    if ev.polylines().is_some() && needed > raster.memory_limit as u128 {
        let vertices = match options.sampling.depth {
            Depth::Fixed(k) => ev.total_samples(k),
            Depth::Tolerance(_) => 0,
        };
        let (width, height, limit) = (raster.width, raster.height, raster.memory_limit);
        return Err(crate::export::RasterTooLarge { width, height, vertices, needed, limit }.into());
    }
    if let (Some(false), Depth::Fixed(k)) = (ev.polylines(), options.sampling.depth) {
        let enough = point_picture_depth(&ev, raster, k);
        report.depth = Some(enough);
        if enough < k {
            let points = ev.total_samples(enough);
            report.notes.push(format!(
                "the picture is drawn at depth {enough}: its {points} points are up to {} a pixel of the {}×{} picture (deeper ones only fill the pixels they darken); geometry files (OBJ, PLY, glTF) keep depth {k}",
                POINTS_PER_PIXEL,
                raster.width,
                raster.height
            ));
            ev.set_depth(Depth::Fixed(enough))?;
        }
    }
    if let (Some(true), Depth::Fixed(k)) = (ev.polylines(), options.sampling.depth) {
        let enough = curve_picture_depth(&mut ev, raster, k)?;
        report.depth = Some(enough);
        if enough < k {
            report.notes.push(format!(
                "the picture is drawn at depth {enough}, whose segments are below a pixel of the {}×{} picture (deeper ones only move the curve within its pixels); geometry files (OBJ, PLY, glTF, SVG) keep depth {k}",
                raster.width, raster.height
            ));
        }
    }
    options.check_cancel()?;
    if let Some(lines) = ev.polylines() {
        let stream = |sink: &mut dyn crate::geometry::Sink| ev.stream(sink).map_err(RenderError::from);
        let (img, vertices) = crate::export::stream_picture(lines, stream, raster)?;
        report.vertices = vertices;
        return Ok((img, raster.transparent.then(crate::export::Matte::default_ink)));
    }
    let depth = match options.sampling.depth {
        Depth::Fixed(k) => Some(k),
        Depth::Tolerance(eps) if ev.quads_at(0).is_some() => Some(ev.depth_for_tolerance(eps)?),
        Depth::Tolerance(_) => None,
    };
    if let Some(k) = depth {
        let enough = picture_depth(&ev, raster, k);
        report.depth = Some(enough);
        if enough < k {
            report.notes.push(format!(
                "the picture is drawn at depth {enough}, whose {} quads outnumber the {}×{} pixels (deeper quads are smaller than a pixel); geometry files (OBJ, PLY, glTF) keep depth {k}",
                ev.quads_at(enough).unwrap_or(0),
                raster.width,
                raster.height
            ));
            ev.set_depth(Depth::Fixed(enough))?;
        }
    }
    let shape = ev.evaluate()?;
    options.check_cancel()?;
    crate::export::finite_vertices(&shape.positions, Some(&shape.normals))
        .map_err(|e| RenderError::Unsupported(e.to_string()))?;
    report.vertices = shape.vertex_count();
    report.faces = shape.quads.len() + shape.triangles.len();
    let img = crate::export::raster(&shape, raster)?;
    Ok((img, raster.transparent.then(|| crate::export::Matte::of_shape(&shape))))
}

/// The deepest depth, up to `max_depth`, whose in-memory output of `design`
/// (at its default parameters) fits `budget` bytes; 1 when none does.
///
/// # Errors
/// The design cannot be evaluated.
pub fn depth_within(design: &crate::design::Design, budget: u128, max_depth: usize) -> Result<usize, RenderError> {
    let job = Job::new(design, &super::options::Options::default())?;
    let ev = job.evaluator(&mut Vec::new())?;
    Ok((1..=max_depth).take_while(|&k| ev.estimate_bytes(k) <= budget).last().unwrap_or(1))
}

/// The tolerance of a picture of a plain IFS drawn 800 pixels across
/// (deterministic points within half a pixel of the attractor: 1/400 of
/// the extent of its depth-4 points), or `None` when its output would not
/// fit three times `budget` bytes.
///
/// # Errors
/// The design cannot be evaluated.
pub fn tolerance_within(design: &crate::design::Design, budget: u128) -> Result<Option<f64>, RenderError> {
    let job = Job::new(design, &super::options::Options::default())?;
    let coarse =
        Evaluator::new(&job.automaton, &job.model, crate::eval::EvalSettings::default().with_depth(4))?.evaluate()?;
    let Some((lo, hi)) = coarse.bounds() else { return Ok(None) };
    let extent = lo.iter().zip(&hi).map(|(l, h)| h - l).fold(0.0, f64::max);
    if !(extent.is_finite() && extent > 0.0) {
        return Ok(None);
    }
    let eps = extent / 400.0;
    let memory = usize::try_from(budget.saturating_mul(3)).unwrap_or(usize::MAX);
    let settings = crate::eval::EvalSettings::default().with_tolerance(eps).with_memory_limit(memory);
    match Evaluator::new(&job.automaton, &job.model, settings)?.evaluate() {
        Ok(_) => Ok(Some(eps)),
        Err(EvalError::TooLarge { .. }) => Ok(None),
        Err(e) => Err(e.into()),
    }
}
