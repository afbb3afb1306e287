//! The files a render writes, by format, behind the cancellation flag.

use std::io;
use std::path::Path;

use crate::export::Target;

use super::options::Options;
use super::output::{Format, RenderError};
use crate::export::{
    Coordinates, GltfWriter, ObjWriter, OffWriter, PictureKind, PictureWriter, PlyWriter, RasterSettings, StlWriter,
    ThreeMfWriter,
};
use crate::geometry::Sink;
use crate::progress::{Cancel, Progress};

/// Why only designs go to `.flame`.
pub(crate) const FLAME_HOLDS: &str =
    "a .flame file holds an IFS of the plane (render a design with the chaos game), not a mesh or a shape";

/// A file being written, in any format: OBJ and OFF streamed, pictures drawn at the end.
pub(crate) enum FileWriter {
    Obj(ObjWriter),
    Off(OffWriter),
    Ply(PlyWriter),
    Stl(StlWriter),
    ThreeMf(ThreeMfWriter),
    Glb(Box<GltfWriter>),
    Picture(PictureWriter),
}

/// How a file is written: the axes and digits of text formats, the threads
/// that format them, the settings of pictures.
pub(crate) struct WriteSettings<'a> {
    pub(crate) coordinates: Coordinates,
    pub(crate) threads: usize,
    pub(crate) raster: &'a RasterSettings,
    pub(crate) ascii: bool,
}

impl FileWriter {
    /// Starts writing `out` in `format`.
    pub(crate) fn create(
        out: &Target,
        format: Format,
        settings: &WriteSettings<'_>,
    ) -> Result<FileWriter, RenderError> {
        let io = |e| RenderError::Io(out.path().to_path_buf(), e);
        let (coordinates, raster) = (settings.coordinates, *settings.raster);
        Ok(match format {
            Format::Obj => FileWriter::Obj(
                ObjWriter::create_in(out)
                    .and_then(|w| w.with_threads(settings.threads))
                    .map_err(io)?
                    .with_coordinates(coordinates),
            ),
            Format::Off => FileWriter::Off(OffWriter::create_in(out).map_err(io)?.with_coordinates(coordinates)),
            Format::Ply => {
                FileWriter::Ply(PlyWriter::create_in(out, settings.ascii).map_err(io)?.with_coordinates(coordinates))
            }
            // The print formats are Z-up unless asked otherwise.
            Format::Stl => FileWriter::Stl(StlWriter::create_in(out).map_err(io)?.with_coordinates(print(coordinates))),
            Format::ThreeMf => {
                FileWriter::ThreeMf(ThreeMfWriter::create_in(out).map_err(io)?.with_coordinates(print(coordinates)))
            }
            Format::Glb => {
                FileWriter::Glb(Box::new(GltfWriter::create_in(out).map_err(io)?.with_coordinates(coordinates)))
            }
            Format::Svg | Format::Png => {
                let Target::Path(path) = out else {
                    return Err(RenderError::Unsupported("pictures in memory are render::picture_png's".into()));
                };
                let kind = if format == Format::Svg { PictureKind::Svg } else { PictureKind::Png };
                FileWriter::Picture(PictureWriter::create(path, kind, raster).map_err(io)?)
            }
            Format::Flame => return Err(RenderError::Unsupported(FLAME_HOLDS.into())),
        })
    }

    /// The sink, behind `cancel`.
    pub(crate) fn checked<'a>(&'a mut self, cancel: &'a Cancel) -> Checked<'a> {
        let sink: &mut dyn Sink = match self {
            FileWriter::Obj(w) => w,
            FileWriter::Off(w) => w,
            FileWriter::Ply(w) => w,
            FileWriter::Stl(w) => w,
            FileWriter::ThreeMf(w) => w,
            FileWriter::Glb(w) => w.as_mut(),
            FileWriter::Picture(w) => w,
        };
        Checked::new(sink, cancel)
    }

    /// Completes the file; its size in bytes.
    pub(crate) fn finish(self, target: &Target) -> Result<u64, RenderError> {
        let out = target.path();
        let io = |e| RenderError::Io(out.to_path_buf(), e);
        match self {
            FileWriter::Obj(w) => w.finish().map_err(io)?,
            FileWriter::Off(w) => w.finish().map_err(io)?,
            FileWriter::Ply(w) => w.finish().map_err(io)?,
            FileWriter::Stl(w) => w.finish().map_err(|e| unsupported(e, out))?,
            FileWriter::ThreeMf(w) => w.finish().map_err(|e| unsupported(e, out))?,
            FileWriter::Glb(w) => w.finish().map_err(|e| unsupported(e, out))?,
            FileWriter::Picture(w) => w.finish()?,
        }
        Ok(match target {
            Target::Path(path) => std::fs::metadata(path).map_or(0, |m| m.len()),
            Target::Memory(buffer) => buffer.len() as u64,
        })
    }
}

/// A format's refusal ([`std::io::ErrorKind::InvalidInput`]) as
/// [`RenderError::Unsupported`], other errors as I/O errors of `out`.
fn unsupported(e: io::Error, out: &Path) -> RenderError {
    match e.kind() {
        io::ErrorKind::InvalidInput => RenderError::Unsupported(e.to_string()),
        _ => RenderError::Io(out.to_path_buf(), e),
    }
}

/// A sink that stops with an [`io::ErrorKind::Interrupted`] error once the
/// flag is set (streamed writes check it at every batch), and counts what
/// goes through it.
pub(crate) struct Checked<'a> {
    sink: &'a mut dyn Sink,
    cancel: &'a Cancel,
    /// Vertices pushed.
    pub(crate) vertices: usize,
    /// Faces pushed (digons, which files leave out, not counted).
    pub(crate) faces: usize,
    /// Where the faces pushed are reported: `(done + faces, total)`.
    progress: Option<(&'a Progress, u64, u64)>,
}

impl<'a> Checked<'a> {
    /// `sink` behind `cancel`.
    pub(crate) fn new(sink: &'a mut dyn Sink, cancel: &'a Cancel) -> Checked<'a> {
        Checked { sink, cancel, vertices: 0, faces: 0, progress: None }
    }

    /// The same, its faces reported to `progress` as `(done + faces, total)`.
    pub(crate) fn with_progress(mut self, progress: Option<&'a Progress>, done: u64, total: u64) -> Checked<'a> {
        self.progress = progress.map(|p| (p, done, total));
        self
    }

    fn check(&self) -> io::Result<()> {
        self.cancel.check_io()
    }

    /// Counts `n` more faces (and reports them).
    fn count(&mut self, n: usize) {
        self.faces += n;
        if let Some((progress, done, total)) = self.progress {
            progress.report((done + self.faces as u64).min(total), total);
        }
    }
}

impl Sink for Checked<'_> {
    fn object(&mut self, name: &str) -> io::Result<()> {
        self.check()?;
        self.sink.object(name)
    }
    fn vertices(&mut self, dim: usize, positions: &[f64], normals: Option<&[f64]>) -> io::Result<()> {
        self.check()?;
        self.vertices += positions.len() / dim.max(1);
        self.sink.vertices(dim, positions, normals)
    }
    fn uvs(&mut self, uvs: &[f64]) -> io::Result<()> {
        self.check()?;
        self.sink.uvs(uvs)
    }
    fn polyline(&mut self, first: usize, count: usize, closed: bool) -> io::Result<()> {
        self.check()?;
        self.sink.polyline(first, count, closed)
    }
    fn faces(&mut self, quads: &[[usize; 4]], uvs: Option<&[[usize; 4]]>) -> io::Result<()> {
        self.check()?;
        self.count(quads.len());
        self.sink.faces(quads, uvs)
    }
    fn triangles(&mut self, triangles: &[[usize; 3]]) -> io::Result<()> {
        self.check()?;
        self.count(triangles.len());
        self.sink.triangles(triangles)
    }
    fn polygons(&mut self, starts: &[usize], corners: &[usize]) -> io::Result<()> {
        self.check()?;
        self.count(starts.windows(2).filter(|w| w[1] - w[0] >= 3).count());
        self.sink.polygons(starts, corners)
    }
    fn cloud(&mut self, first: usize, count: usize) -> io::Result<()> {
        self.sink.cloud(first, count)
    }
    fn group(&mut self, name: &str) -> io::Result<()> {
        self.sink.group(name)
    }
    fn textured_polygons(&mut self, starts: &[usize], corners: &[usize], uv_corners: &[usize]) -> io::Result<()> {
        self.check()?;
        self.count(starts.windows(2).filter(|w| w[1] - w[0] >= 3).count());
        self.sink.textured_polygons(starts, corners, uv_corners)
    }
    fn colours(&mut self, rgb: &[[u8; 3]]) -> io::Result<()> {
        self.sink.colours(rgb)
    }
    fn vertices_complete(&mut self) -> io::Result<()> {
        self.sink.vertices_complete()
    }
}

/// The error of a write into `out`: [`RenderError::Cancelled`] when the
/// flag stopped it, the I/O error otherwise.
pub(crate) fn write_error(options: &Options, out: &Path) -> impl Fn(io::Error) -> RenderError {
    let (cancelled, out) = (options.cancel.clone(), out.to_path_buf());
    move |e| if cancelled.is_cancelled() { RenderError::Cancelled } else { unsupported(e, &out) }
}

/// The coordinates of a print format (STL, 3MF): Z-up by convention.
fn print(coordinates: crate::export::Coordinates) -> crate::export::Coordinates {
    crate::export::Coordinates { up: coordinates.up.or(crate::export::Up::Z), ..coordinates }
}
