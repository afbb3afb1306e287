//! What a render takes and gives: the format, the options, the report, the errors.

use std::path::{Path, PathBuf};

use crate::eval::{EvalError, EvalSettings, RandomSettings};
use crate::export::{Coordinates, Palette, RasterSettings, RasterTooLarge, Tone};
use crate::progress::{Cancel, Progress};

/// An output format, by the file's extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// Wavefront OBJ, streamed (any size).
    Obj,
    /// OFF, streamed (faces and points; no curves).
    Off,
    /// PLY, streamed: binary little-endian, or ASCII with [`Options::ascii`].
    Ply,
    /// Binary STL, for 3D printing: surfaces only (curves and clouds refused).
    Stl,
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
    pub const ALL: [Format; 8] =
        [Format::Obj, Format::Off, Format::Ply, Format::Stl, Format::Glb, Format::Svg, Format::Png, Format::Flame];

    /// The file extension (lower case, without the dot).
    pub fn extension(self) -> &'static str {
        match self {
            Format::Obj => "obj",
            Format::Off => "off",
            Format::Ply => "ply",
            Format::Stl => "stl",
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

/// How to render: what [`render`](super::render) and [`render_mesh`](super::render_mesh) take.
#[derive(Clone, Debug, Default)]
pub struct Options {
    /// Parameter values (others: the design's defaults).
    pub params: Vec<(String, f64)>,
    /// Deterministic evaluation: depth or tolerance, threads, the memory limit (also the
    /// pictures' and the meshes'), start sets, dropped arrows, texture coordinates.
    pub eval: EvalSettings,
    /// The chaos game instead of deterministic evaluation.
    pub random: Option<RandomSettings>,
    /// Pictures: size, view, memory limit.
    pub raster: RasterSettings,
    /// Files: the up axis and the digits of coordinates.
    pub coordinates: Coordinates,
    /// Text instead of binary where a format has both (PLY).
    pub ascii: bool,
    /// Largest file to write, in bytes (0: no limit); the estimate is checked before writing.
    pub max_output: u128,
    /// Drop exact duplicate points of a point cloud (evaluated in memory).
    pub dedup: bool,
    /// Tone mapping of chaos-game pictures (density images).
    pub tone: Tone,
    /// Colour chaos-game pictures by the arrows applied, with this palette
    /// (and the vertices of [`Options::colour`]: default `rainbow`).
    pub palette: Option<Palette>,
    /// Colour the vertices of a deterministic evaluation by state, level or
    /// map (files with colours: OBJ, PLY, glTF); evaluated in memory.
    pub colour: Option<crate::eval::Colouring>,
    /// [`Options::colour`] by map: colour coordinates of arrows by name (the others spread evenly).
    pub arrow_colours: Vec<(String, f64)>,
    /// [`Options::colour`] by map: the colour speed (`None`: 1/2, as the chaos game's).
    pub colour_speed: Option<f64>,
    /// Told how far the work is (evaluation, chaos game).
    pub progress: Option<Progress>,
    /// Stops the work when set: [`RenderError::Cancelled`], nothing written.
    pub cancel: Cancel,
    /// What asked for the render (the command line), recorded in PNG pictures.
    pub provenance: Option<String>,
}

impl Options {
    /// The same options, `depth` subdivision steps.
    pub fn with_depth(mut self, depth: usize) -> Options {
        self.eval.depth = crate::eval::Depth::Fixed(depth);
        self
    }

    /// The same options, pictures of `width` × `height` pixels.
    pub fn with_size(mut self, width: u32, height: u32) -> Options {
        self.raster = self.raster.with_size(width, height);
        self
    }

    /// The same options, reporting progress to `progress`.
    pub fn with_progress(mut self, progress: Progress) -> Options {
        self.progress = Some(progress);
        self
    }

    /// The same options, stopped by `cancel`.
    pub fn with_cancel(mut self, cancel: Cancel) -> Options {
        self.cancel = cancel;
        self
    }

    /// The evaluation settings with the progress callback.
    pub(crate) fn eval_settings(&self) -> EvalSettings {
        let mut eval = self.eval.clone();
        if self.progress.is_some() {
            eval.progress.clone_from(&self.progress);
        }
        eval
    }

    /// The chaos-game settings with the progress callback, if the chaos game is asked.
    pub(crate) fn random_settings(&self) -> Option<RandomSettings> {
        let mut random = self.random.clone()?;
        if self.progress.is_some() {
            random.progress.clone_from(&self.progress);
        }
        random.cancel = Some(self.cancel.clone());
        Some(random)
    }

    /// The `tEXt` chunks of a PNG picture of `title` made with these
    /// options: `Software`, `Title`, `Comment` (parameters, depth or chaos
    /// game, size, view) and `Description` (the provenance, when given).
    pub fn png_text(&self, title: &str) -> Vec<(String, String)> {
        let mut settings = Vec::new();
        if !self.params.is_empty() {
            let params: Vec<String> = self.params.iter().map(|(n, v)| format!("{n}={v}")).collect();
            settings.push(format!("params {}", params.join(" ")));
        }
        settings.push(match (&self.random, self.eval.depth) {
            (Some(r), _) => format!("random {} seed {}", r.points, r.seed),
            (None, crate::eval::Depth::Fixed(k)) => format!("depth {k}"),
            (None, crate::eval::Depth::Tolerance(eps)) => format!("tolerance {eps}"),
        });
        let (raster, view) = (&self.raster, &self.raster.view);
        settings.push(format!("size {}x{}; view {},{}", raster.width, raster.height, view.yaw, view.pitch));
        let mut text = vec![
            ("Software".to_string(), format!("bcifs {}", env!("CARGO_PKG_VERSION"))),
            ("Title".to_string(), title.to_string()),
            ("Comment".to_string(), settings.join("; ")),
        ];
        if let Some(p) = &self.provenance {
            text.push(("Description".to_string(), p.clone()));
        }
        text
    }

    /// [`RenderError::Cancelled`] when the flag is set.
    pub(crate) fn check_cancel(&self) -> Result<(), RenderError> {
        if self.cancel.is_cancelled() { Err(RenderError::Cancelled) } else { Ok(()) }
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
    /// Exact duplicate points dropped ([`Options::dedup`]), `None` when not asked or not a cloud.
    pub duplicates: Option<usize>,
    /// What the user should know: options that did not apply, undecided convergence.
    pub warnings: Vec<String>,
    /// Choices made for them (a picture drawn at a shallower depth).
    pub notes: Vec<String>,
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
    #[error("{name}: the constraints do not hold ({}); render anyway with --force", conflicts.join("; "))]
    Inconsistent {
        /// The design.
        name: String,
        /// The conflicting equations.
        conflicts: Vec<String>,
    },
    /// Evaluation.
    #[error(transparent)]
    Eval(#[from] EvalError),
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
    /// [`Options::cancel`] was set.
    #[error("cancelled")]
    Cancelled,
}

impl From<crate::report::ReportError> for RenderError {
    fn from(e: crate::report::ReportError) -> RenderError {
        use crate::report::ReportError as R;
        match e {
            R::NoModel(name) => RenderError::NoModel(name),
            R::Instantiate(e) => RenderError::Instantiate(e),
            R::Eval(e) => RenderError::Eval(e),
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
        return Err(RenderError::TooBig(format!(
            "the file would take about {:.1} GiB, over --max-output-gib {:.1}: lower the depth or raise the limit",
            gib(estimate),
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
