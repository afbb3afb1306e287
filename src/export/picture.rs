//! Pictures as a sink: SVG and PNG files drawn from what is pushed into them.

use std::io;
use std::path::{Path, PathBuf};

use super::atomic::{check_target, write_atomic};
use super::png::{Matte, raster, write_png_matte};
use super::svg::{svg, svg_surface};
use super::view::{RasterSettings, RasterTooLarge};
use crate::geometry::{Shape, Sink};

/// A picture format.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PictureKind {
    /// SVG: 2D curves and points as they are, surfaces as flatly shaded polygons seen from the view.
    Svg,
    /// PNG: curves, points and shaded surfaces seen from the view.
    Png,
}

/// Why a picture could not be drawn.
#[derive(Debug, thiserror::Error)]
pub enum PictureError {
    /// Writing the file.
    #[error("cannot write {0}")]
    Io(PathBuf, #[source] io::Error),
    /// A picture over the memory limit.
    #[error(transparent)]
    TooLarge(#[from] RasterTooLarge),
    /// SVG of a 3D curve or point set.
    #[error("SVG output is for 2D shapes; this model is 3D (use .png or .obj)")]
    NotPlanar,
}

/// A [`Sink`] that draws what it is given. A picture paints every face far
/// to near and frames the whole shape, so it holds the shape in memory (see
/// [`crate::export::stream_picture`] for curves drawn while they are streamed);
/// [`PictureWriter::finish`] draws it and writes the file atomically.
///
/// ```
/// use bcifs::export::{PictureKind, PictureWriter, RasterSettings};
/// use bcifs::geometry::Sink;
/// let dir = std::env::temp_dir().join(format!("bcifs-picture-doc-{}", std::process::id()));
/// std::fs::create_dir_all(&dir)?;
/// let path = dir.join("square.svg");
/// let mut w = PictureWriter::create(&path, PictureKind::Svg, RasterSettings::default())?;
/// w.object("square")?;
/// w.vertices(2, &[0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0, 1.0], None)?;
/// w.polyline(0, 4, true)?;
/// w.finish()?;
/// assert!(std::fs::read_to_string(&path)?.starts_with("<svg"));
/// # std::fs::remove_dir_all(&dir)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub struct PictureWriter {
    path: PathBuf,
    kind: PictureKind,
    settings: RasterSettings,
    shape: Shape,
    text: Vec<(String, String)>,
}

impl PictureWriter {
    /// Starts a picture of `path`, drawn with `settings` (size, view, memory limit).
    ///
    /// # Errors
    /// The target cannot be written (a directory, a missing directory).
    pub fn create(path: &Path, kind: PictureKind, settings: RasterSettings) -> io::Result<PictureWriter> {
        check_target(path)?;
        Ok(PictureWriter { path: path.to_path_buf(), kind, settings, shape: Shape::default(), text: Vec::new() })
    }

    /// The same writer, recording `text` (keyword, text) in a PNG's `tEXt` chunks.
    pub fn with_text(mut self, text: Vec<(String, String)>) -> PictureWriter {
        self.text = text;
        self
    }

    /// The shape drawn so far.
    pub fn shape(&self) -> &Shape {
        &self.shape
    }

    /// Draws the picture and writes the file (atomically).
    ///
    /// # Errors
    /// A 3D curve to SVG, a picture over the memory limit, or an I/O error.
    pub fn finish(self) -> Result<(), PictureError> {
        write_picture(&self.shape, self.kind, &self.settings, &self.path, &self.text)
    }
}

/// Draws `shape` as a picture of `kind` with `settings` and writes it to
/// `path` atomically (a PNG with `text` in `tEXt` chunks): what
/// [`PictureWriter::finish`] does, for a shape already in memory.
///
/// # Errors
/// A 3D curve to SVG, a picture over the memory limit, or an I/O error.
pub fn write_picture(
    shape: &Shape,
    kind: PictureKind,
    settings: &RasterSettings,
    path: &Path,
    text: &[(String, String)],
) -> Result<(), PictureError> {
    let io = |e| PictureError::Io(path.to_path_buf(), e);
    let surface = !shape.quads.is_empty() || !shape.triangles.is_empty();
    match kind {
        PictureKind::Svg if surface => write_atomic(path, svg_surface(shape, settings).as_bytes()).map_err(io),
        PictureKind::Svg if shape.dim > 2 => Err(PictureError::NotPlanar),
        PictureKind::Svg => write_atomic(path, svg(shape, settings.width).as_bytes()).map_err(io),
        PictureKind::Png => {
            let matte = settings.transparent.then(|| Matte::of_shape(shape));
            write_png_matte(path, &raster(shape, settings)?, text, matte).map_err(io)
        }
    }
}

impl Sink for PictureWriter {
    fn object(&mut self, name: &str) -> io::Result<()> {
        self.shape.object(name)
    }
    fn vertices(&mut self, dim: usize, positions: &[f64], normals: Option<&[f64]>) -> io::Result<()> {
        self.shape.vertices(dim, positions, normals)
    }
    fn uvs(&mut self, uvs: &[f64]) -> io::Result<()> {
        self.shape.uvs(uvs)
    }
    fn polyline(&mut self, first: usize, count: usize, closed: bool) -> io::Result<()> {
        self.shape.polyline(first, count, closed)
    }
    fn faces(&mut self, quads: &[[usize; 4]], uvs: Option<&[[usize; 4]]>) -> io::Result<()> {
        self.shape.faces(quads, uvs)
    }
    fn triangles(&mut self, triangles: &[[usize; 3]]) -> io::Result<()> {
        self.shape.triangles(triangles)
    }
}
