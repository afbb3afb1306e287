//! Shapes held in memory written to files, and the control nets of models.

use std::path::Path;

use super::checked::{FileWriter, WriteSettings, write_error};
use super::options::Options;
use super::output::{Format, RenderError, Report};
use crate::design::Model;
use crate::export::{Coordinates, PictureKind, RasterSettings, write_picture};
use crate::geometry::{Shape, Sink};

/// Writes a shape held in memory to `out`, the format chosen by its
/// extension (OBJ and OFF Y-up, as [`crate::export::Coordinates::default`]
/// says; SVG of 2D shapes or of surfaces as seen from the view; PNG with
/// `raster_settings`).
///
/// # Errors
/// An unknown extension, a 3D curve to SVG, curves to OFF, or an I/O
/// error; nothing is left half-written.
pub fn write_shape(
    shape: &Shape,
    name: &str,
    raster_settings: &RasterSettings,
    out: &Path,
) -> Result<Report, RenderError> {
    let text = [
        ("Software".to_string(), format!("bcifs {}", env!("CARGO_PKG_VERSION"))),
        ("Title".to_string(), name.to_string()),
    ];
    write_shape_text(shape, name, raster_settings, out, &text)
}

/// [`write_shape`] with the `tEXt` chunks of a PNG (keyword, text): `Software`,
/// `Title`, `Comment` (the settings), `Description` (the provenance), as `render` writes them.
///
/// # Errors
/// As [`write_shape`].
pub fn write_shape_text(
    shape: &Shape,
    name: &str,
    raster_settings: &RasterSettings,
    out: &Path,
    text: &[(String, String)],
) -> Result<Report, RenderError> {
    let coordinates = Coordinates { y_up_input: raster_settings.view.y_up, ..Default::default() };
    let settings = WriteSettings { coordinates, threads: 1, raster: raster_settings, ascii: false };
    write_shape_with(shape, name, &settings, out, text)
}

/// A shape in memory written with the options' axes, digits, text or
/// binary, picture settings and PNG text.
pub(crate) fn write_shape_options(
    shape: &Shape,
    name: &str,
    options: &Options,
    out: &Path,
) -> Result<Report, RenderError> {
    let settings = WriteSettings {
        coordinates: options.file.coordinates,
        threads: 1,
        raster: &options.raster(),
        ascii: options.file.ascii,
    };
    write_shape_with(shape, name, &settings, out, &options.png_text(name))
}

fn write_shape_with(
    shape: &Shape,
    name: &str,
    settings: &WriteSettings<'_>,
    out: &Path,
    text: &[(String, String)],
) -> Result<Report, RenderError> {
    let format = Format::of(out)?;
    let options = Options::default();
    let io = write_error(&options, out);
    let mut report = Report {
        format: Some(format),
        vertices: shape.vertex_count(),
        faces: shape.quads.len() + shape.triangles.len(),
        ..Report::default()
    };
    let kind = match format {
        Format::Svg => PictureKind::Svg,
        Format::Png => PictureKind::Png,
        Format::Flame => return Err(RenderError::Unsupported(super::checked::FLAME_HOLDS.into())),
        _ => {
            if format == Format::Off && shape.polylines().next().is_some() {
                return Err(RenderError::Unsupported(
                    "an OFF file holds faces and points, not curves: write curves as .obj or .svg".into(),
                ));
            }
            report.bytes = write_geometry(shape, name, settings, format, &crate::export::Target::from(out), &io)?;
            return Ok(report);
        }
    };
    write_picture(shape, kind, settings.raster, out, text)?;
    report.bytes = std::fs::metadata(out).map_or(0, |m| m.len());
    Ok(report)
}

/// A shape in memory written in a geometry `format` to `target` (a file or
/// a buffer); the bytes written.
pub(super) fn write_geometry(
    shape: &Shape,
    name: &str,
    settings: &WriteSettings<'_>,
    format: Format,
    target: &crate::export::Target,
    io: &dyn Fn(std::io::Error) -> RenderError,
) -> Result<u64, RenderError> {
    let mut writer = FileWriter::create(target, format, settings)?;
    let never = crate::progress::Cancel::default();
    let mut sink = writer.checked(&never);
    if shape.objects.is_empty() {
        sink.object(name).map_err(io)?;
    }
    shape.replay(&mut sink).map_err(io)?;
    writer.finish(target)
}

/// The control net of a model: the control polygon of a curve (closed for
/// closed layouts), the control grid of a sheet or torus as quads, the
/// points in order otherwise.
pub fn control_net(model: &Model) -> Shape {
    use crate::design::Layout;
    let dim = model.points.first().map_or(2, Vec::len);
    let flat: Vec<f64> = model.points.iter().flatten().copied().collect();
    let closed = matches!(model.layout, Layout::Closed | Layout::ClosedFrames);
    if !model.net.is_empty() {
        let mut shape = Shape::default();
        // Writing into memory cannot fail.
        let _ = shape.object("control net");
        let _ = shape.vertices(dim, &flat, None);
        // Quads stay quads; other faces become fans of triangles.
        let quads: Vec<[usize; 4]> =
            model.net.iter().filter(|f| f.len() == 4).map(|f| [f[0], f[1], f[2], f[3]]).collect();
        let fans: Vec<[usize; 3]> = model
            .net
            .iter()
            .filter(|f| f.len() != 4)
            .flat_map(|f| (1..f.len() - 1).map(move |k| [f[0], f[k], f[k + 1]]))
            .collect();
        let _ = shape.faces(&quads, None);
        let _ = shape.triangles(&fans);
        return shape;
    }
    match (model.layout, model.grid) {
        (Layout::Grid | Layout::Torus, Some((rows, cols))) if rows * cols == model.points.len() => {
            let wrap = model.layout == Layout::Torus;
            let (r_end, c_end) = if wrap { (rows, cols) } else { (rows - 1, cols - 1) };
            let mut quads: Vec<[usize; 4]> = (0..r_end)
                .flat_map(|r| (0..c_end).map(move |c| (r, c)))
                .map(|(r, c)| {
                    let at = |r: usize, c: usize| (r % rows) * cols + c % cols;
                    [at(r, c), at(r, c + 1), at(r + 1, c + 1), at(r + 1, c)]
                })
                .collect();
            // A closed net faces outwards, like the surfaces evaluated from it.
            if wrap && dim == 3 {
                let p = |i: usize| [0, 1, 2].map(|a| model.points[i][a]);
                let det = |a: [f64; 3], b: [f64; 3], c: [f64; 3]| {
                    a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                        + a[2] * (b[0] * c[1] - b[1] * c[0])
                };
                let volume: f64 =
                    quads.iter().map(|q| det(p(q[0]), p(q[1]), p(q[2])) + det(p(q[0]), p(q[2]), p(q[3]))).sum();
                if volume < 0.0 {
                    quads.iter_mut().for_each(|q| q.reverse());
                }
            }
            let mut shape = Shape::default();
            // Writing into memory cannot fail.
            let _ = shape.object("control net");
            let _ = shape.vertices(dim, &flat, None);
            let _ = shape.faces(&quads, None);
            shape
        }
        _ => Shape::polyline("control polygon", dim, &flat, closed),
    }
}
