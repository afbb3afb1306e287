//! What a render gives: the format, the report, the errors, the room checks.

use std::path::{Path, PathBuf};

use crate::eval::EvalError;
use crate::export::RasterTooLarge;
/// An output format, by the file's extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// Wavefront OBJ, streamed (any size).
    Obj,
    /// OFF, streamed (faces and points; no curves).
    Off,
    /// PLY, streamed: binary little-endian, or ASCII with [`FileStyle::ascii`](super::FileStyle::ascii).
    Ply,
    /// Binary STL, for 3D printing: surfaces only (curves and clouds refused).
    Stl,
    /// 3MF, the 3D Manufacturing Format (slicers): one mesh, in millimetres (curves and clouds refused).
    ThreeMf,
    /// glTF 2.0 binary: one mesh and node per object, Y-up (at most 4 GiB).
    Glb,
    /// SVG, drawn from memory (2D shapes; surfaces as seen from the view).
    Svg,
    /// PNG picture.
    Png,
    /// flam3's XML for a plain IFS of the plane (the chaos game, for flam3-render and flame editors).
    Flame,
}

impl Format {
    /// Every format, in the order they are listed to users.
    pub const ALL: [Format; 9] = [
        Format::Obj,
        Format::Off,
        Format::Ply,
        Format::Stl,
        Format::ThreeMf,
        Format::Glb,
        Format::Svg,
        Format::Png,
        Format::Flame,
    ];

    /// The file extension (lower case, without the dot).
    pub fn extension(self) -> &'static str {
        match self {
            Format::Obj => "obj",
            Format::Off => "off",
            Format::Ply => "ply",
            Format::Stl => "stl",
            Format::ThreeMf => "3mf",
            Format::Glb => "glb",
            Format::Svg => "svg",
            Format::Png => "png",
            Format::Flame => "flame",
        }
    }

    /// A file of geometry (vertices and elements), not a picture.
    pub fn is_geometry(self) -> bool {
        !matches!(self, Format::Svg | Format::Png | Format::Flame)
    }

    /// A file for printing (STL, 3MF): sized in millimetres and checked ([`crate::report::printed`]).
    pub fn is_print(self) -> bool {
        matches!(self, Format::Stl | Format::ThreeMf)
    }

    /// The format holds vertex colours.
    pub fn has_colours(self) -> bool {
        matches!(self, Format::Obj | Format::Ply | Format::Glb)
    }

    /// The format holds vertex normals.
    pub fn has_normals(self) -> bool {
        matches!(self, Format::Obj | Format::Ply | Format::Glb)
    }

    /// The format holds texture coordinates.
    pub fn has_uvs(self) -> bool {
        matches!(self, Format::Obj | Format::Glb)
    }

    /// The format writes coordinates with chosen digits (text, or PLY's `float`/`double`).
    pub fn has_digits(self) -> bool {
        matches!(self, Format::Obj | Format::Off | Format::Ply)
    }

    /// The format of `path`, by its extension (any case).
    ///
    /// # Errors
    /// [`RenderError::Format`] for an extension no writer has.
    pub fn of(path: &Path) -> Result<Format, RenderError> {
        Format::from_extension(&path.extension().map(|e| e.to_string_lossy()).unwrap_or_default())
    }

    /// The format of an extension without its dot (any case): `obj`, `glb`…
    ///
    /// # Errors
    /// [`RenderError::Format`] for an extension no writer has.
    pub fn from_extension(extension: &str) -> Result<Format, RenderError> {
        let ext = extension.to_lowercase();
        Format::ALL.into_iter().find(|f| f.extension() == ext).ok_or(RenderError::Format(ext))
    }
}

/// What a render wrote.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Report {
    /// The format written.
    pub format: Option<Format>,
    /// Vertices written (points drawn, for pictures of curves and clouds).
    pub vertices: usize,
    /// Faces written (quads, triangles and larger faces).
    pub faces: usize,
    /// Bytes of the file.
    pub bytes: u64,
    /// The subdivision depth of the output, when one fixed depth made it
    /// (a picture may be drawn shallower than asked: see [`Report::notes`]).
    pub depth: Option<usize>,
    /// Exact duplicate points dropped ([`FileStyle::dedup`](super::FileStyle::dedup)), `None` when not asked or not a cloud.
    pub duplicates: Option<usize>,
    /// What the user should know: options that did not apply, undecided convergence.
    pub warnings: Vec<String>,
    /// Choices made for them (a picture drawn at a shallower depth).
    pub notes: Vec<String>,
    /// A print file's print report (STL, 3MF): the mesh written, in millimetres.
    pub print: Option<crate::report::PrintReport>,
}

/// Why a render failed.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// The design has no model to project with.
    #[error("`{0}` has no [model]: add control points to render it")]
    NoModel(String),
    /// Parameters or constraints.
    #[error(transparent)]
    Instantiate(#[from] crate::family::DesignInstantiateError),
    /// The constraints of a fully known automaton fail.
    #[error("{name}: the constraints do not hold ({}); render anyway by forcing it", conflicts.join("; "))]
    Inconsistent {
        /// The design.
        name: String,
        /// The conflicting equations.
        conflicts: Vec<String>,
    },
    /// Evaluation.
    #[error(transparent)]
    Eval(EvalError),
    /// A polygon mesh that cannot be subdivided: memory, the scheme's faces.
    #[error(transparent)]
    Mesh(#[from] crate::mesh::SubdivideError),
    /// Rule weights that diverge.
    #[error(transparent)]
    Weights(#[from] crate::analysis::WeightsError),
    /// Output format not known.
    #[error("unknown output format `.{0}`: expected .obj, .off, .ply, .stl, .glb, .svg, .png or .flame")]
    Format(String),
    /// A format that cannot hold this output.
    #[error("{0}")]
    Unsupported(String),
    /// A picture over the memory limit.
    #[error(transparent)]
    Raster(#[from] RasterTooLarge),
    /// Writing.
    #[error("cannot write {0}: {1}")]
    Io(PathBuf, std::io::Error),
    /// An output that would not fit the disk or the size limit.
    #[error("{0}")]
    TooBig(String),
    /// SVG of a 3D shape.
    #[error("SVG output is for 2D shapes; this model is 3D (use .png or .obj)")]
    NotPlanar,
    /// A normal-vector scheme that cannot take the requested form.
    #[error(transparent)]
    Scheme(#[from] crate::schemes::NormalSchemeError),
    /// [`Options::cancel`](super::Options::cancel) was set.
    #[error("cancelled")]
    Cancelled,
}

impl From<EvalError> for RenderError {
    /// An evaluation stopped by its flag is the render's [`RenderError::Cancelled`].
    fn from(e: EvalError) -> RenderError {
        match e {
            EvalError::Cancelled => RenderError::Cancelled,
            e => RenderError::Eval(e),
        }
    }
}

impl From<crate::report::ReportError> for RenderError {
    fn from(e: crate::report::ReportError) -> RenderError {
        use crate::report::ReportError as R;
        match e {
            R::NoModel(name) => RenderError::NoModel(name),
            R::Instantiate(e) => RenderError::Instantiate(e),
            R::Eval(e) => e.into(),
            R::Unsupported(why) => RenderError::Unsupported(why),
            R::Cancelled => RenderError::Cancelled,
        }
    }
}

impl From<crate::export::PictureError> for RenderError {
    fn from(e: crate::export::PictureError) -> RenderError {
        match e {
            crate::export::PictureError::Io(path, e) => RenderError::Io(path, e),
            crate::export::PictureError::TooLarge(e) => RenderError::Raster(e),
            crate::export::PictureError::NotPlanar => RenderError::NotPlanar,
        }
    }
}

/// [`check_disk`] for a file; for memory, the size limit alone (the output is held whole).
///
/// # Errors
/// [`RenderError::TooBig`] with the estimate and the limit.
pub fn check_room(target: &crate::export::Target, estimate: u128, side: u128, max: u128) -> Result<(), RenderError> {
    match target {
        crate::export::Target::Path(path) => check_disk(path, estimate, side, max),
        crate::export::Target::Memory(_) if max > 0 && estimate > max => Err(RenderError::TooBig(format!(
            "the output would take about {}, over the limit of {} for an output made in memory",
            crate::progress::bytes_text(estimate),
            crate::progress::bytes_text(max)
        ))),
        crate::export::Target::Memory(_) => Ok(()),
    }
}

/// Refuses an output whose estimated size is over `max` (0: no limit) or
/// over the free space of the target's disk (with its side files, a
/// streamed file peaks at about 1.5 times its size), plus `side` bytes of
/// other side files it needs while it is written (vertex normals streamed).
///
/// # Errors
/// [`RenderError::TooBig`] with the estimate and the limit.
pub fn check_disk(out: &Path, estimate: u128, side: u128, max: u128) -> Result<(), RenderError> {
    let gib = |b: u128| b as f64 / (1u64 << 30) as f64;
    if max > 0 && estimate > max {
        let size = if estimate >= 1 << 60 {
            crate::progress::bytes_text(estimate)
        } else {
            format!("about {:.1} GiB", gib(estimate))
        };
        return Err(RenderError::TooBig(format!(
            "the file would take {size}, over the output limit of {:.1} GiB: lower the depth or raise the limit",
            gib(max)
        )));
    }
    let dir = out.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
    if let Ok(free) = fs4::available_space(dir)
        && (estimate.saturating_mul(3) / 2).saturating_add(side) > u128::from(free)
    {
        return Err(RenderError::TooBig(format!(
            "the file would take about {:.1} GiB (and half as much again while it is written, {:.1} GiB of side files); {} has {:.1} GiB free",
            gib(estimate),
            gib(side),
            dir.display(),
            gib(u128::from(free))
        )));
    }
    Ok(())
}
