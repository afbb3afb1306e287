//! What a render takes, grouped by meaning: what is sampled, the budget,
//! the look of pictures, the style of files. Every front end fills it
//! through [`super::keys`] (one description of its keys, validated once);
//! the evaluation's, the chaos game's and the pictures' settings are
//! derived from it, so no setting is held twice.

use std::time::Duration;

use crate::eval::{Colouring, Depth, EvalSettings, RandomSettings};
use crate::export::{Coordinates, Palette, RasterSettings, Tone, View};
use crate::progress::{Cancel, Progress};

use super::output::RenderError;

/// How to render: what [`render`](super::render) and [`render_mesh`](super::render_mesh) take.
///
/// ```
/// use bcifs::render::{Options, Value};
/// let options = Options::from_values([("depth", Value::from(6)), ("size", Value::from("200x100"))])?;
/// assert_eq!((options.look.width, options.look.height), (200, 100));
/// assert!(Options::from_values([("precision", Value::from(40))]).is_err());
/// # Ok::<(), bcifs::render::OptionError>(())
/// ```
#[derive(Clone, Debug, Default)]
pub struct Options {
    /// Parameter values (others: the design's defaults).
    pub params: Vec<(String, f64)>,
    /// What is sampled: a depth, a tolerance or the chaos game, and which arrows.
    pub sampling: Sampling,
    /// What the work may take: memory, output size, threads, time.
    pub budget: Budget,
    /// How pictures look: size, view, tone, palette, vertex colours.
    pub look: Look,
    /// How files are written: axes, digits, text or binary.
    pub file: FileStyle,
    /// Told how far the work is (evaluation, chaos game).
    pub progress: Option<Progress>,
    /// Stops the work when set: [`RenderError::Cancelled`], nothing written.
    pub cancel: Cancel,
    /// What asked for the render (the command line), recorded in PNG pictures.
    pub provenance: Option<String>,
}

/// What is sampled.
#[derive(Clone, Debug)]
pub struct Sampling {
    /// The deterministic evaluation's depth or tolerance (unused by the chaos game).
    pub depth: Depth,
    /// The chaos game's points, instead of the deterministic evaluation.
    pub samples: Option<usize>,
    /// The chaos game's seed: the same seed gives the same points, whatever the thread count.
    pub seed: u64,
    /// The chaos game's probabilities by arrow name (normalised per target state); the others by `|det|`.
    pub probabilities: Vec<(String, f64)>,
    /// Subdivision arrows left out (a subset of the attractor).
    pub dropped: Vec<String>,
    /// Start sets: barycentric points per state name, emitted at leaves instead of the kind's default.
    pub start: Vec<(String, Vec<Vec<f64>>)>,
    /// Evaluate even a system whose convergence bounds prove it diverges.
    pub force: bool,
}

impl Default for Sampling {
    fn default() -> Sampling {
        Sampling {
            depth: Depth::default(),
            samples: None,
            seed: DEFAULT_SEED,
            probabilities: Vec::new(),
            dropped: Vec::new(),
            start: Vec::new(),
            force: false,
        }
    }
}

/// The chaos game's default seed, the same in every front end.
pub const DEFAULT_SEED: u64 = 1;

/// What the work may take. The command line's is [`Budget::default`]; the
/// explorer's, the gallery's and Blender's are [`super::Profile`]s.
#[derive(Clone, Debug, PartialEq)]
pub struct Budget {
    /// In-memory limit in bytes (evaluation, pictures, meshes, outputs made in memory).
    pub memory: usize,
    /// Largest output in bytes (0: no limit), the estimate checked before writing.
    pub output: u128,
    /// Worker threads (`None`: all cores).
    pub threads: Option<usize>,
    /// The longest a front end lets one render run before it cancels it (`None`: no limit).
    pub time: Option<Duration>,
    /// The deepest fixed depth accepted.
    pub max_depth: usize,
    /// The longest side of a picture, in pixels.
    pub max_side: u32,
}

impl Default for Budget {
    fn default() -> Budget {
        Budget {
            memory: crate::eval::DEFAULT_MEMORY_LIMIT,
            output: 4 << 30,
            threads: None,
            time: None,
            max_depth: crate::eval::MAX_DEPTH,
            max_side: u32::MAX,
        }
    }
}

impl Budget {
    /// The worker threads: the number asked, or all cores.
    pub fn thread_count(&self) -> usize {
        self.threads.unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
    }
}

/// How pictures look.
#[derive(Clone, Debug, PartialEq)]
pub struct Look {
    /// Picture width in pixels.
    pub width: u32,
    /// Picture height in pixels.
    pub height: u32,
    /// Where 3D shapes are seen from.
    pub view: View,
    /// PNG with a transparent background.
    pub transparent: bool,
    /// Tone mapping of chaos-game pictures (density images).
    pub tone: Tone,
    /// Colour chaos-game pictures by the arrows applied, with this palette
    /// (and the vertices of [`Look::colour`]: default `rainbow`).
    pub palette: Option<Palette>,
    /// Colour the vertices of a deterministic evaluation by state, level or
    /// map (files with colours: OBJ, PLY, glTF); evaluated in memory.
    pub colour: Option<Colouring>,
    /// Colour coordinates of arrows by name, in `[0, 1]` (the others spread evenly).
    pub arrow_colours: Vec<(String, f64)>,
    /// How far each step moves the colour coordinate towards its arrow's (flam3's colour speed).
    pub colour_speed: f64,
}

impl Default for Look {
    fn default() -> Look {
        let raster = RasterSettings::default();
        Look {
            width: raster.width,
            height: raster.height,
            view: raster.view,
            transparent: false,
            tone: Tone::default(),
            palette: None,
            colour: None,
            arrow_colours: Vec::new(),
            colour_speed: RandomSettings::default().colour_speed,
        }
    }
}

/// How files are written.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FileStyle {
    /// The up axis and the digits of coordinates.
    pub coordinates: Coordinates,
    /// Text instead of binary where a format has both (PLY).
    pub ascii: bool,
    /// Drop exact duplicate points of a point cloud (evaluated in memory).
    pub dedup: bool,
    /// Texture coordinates on meshes: one parameterization `(u, v)` of the whole grid or torus.
    pub uv: bool,
    /// A surface (a lace) written as a closed shell of this thickness ([`crate::mesh::thicken`]).
    pub thickness: Option<f64>,
    /// How print files (STL, 3MF) are sized and checked.
    pub print: crate::report::PrintStyle,
}

impl Options {
    /// The same options, `depth` subdivision steps.
    pub fn with_depth(mut self, depth: usize) -> Options {
        self.sampling.depth = Depth::Fixed(depth);
        self
    }

    /// The same options, pictures of `width` × `height` pixels.
    pub fn with_size(mut self, width: u32, height: u32) -> Options {
        (self.look.width, self.look.height) = (width, height);
        self
    }

    /// The same options, `points` points of the chaos game instead of the deterministic evaluation.
    pub fn with_chaos(mut self, points: usize) -> Options {
        self.sampling.samples = Some(points);
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

    /// The same options within `budget`.
    pub fn with_budget(mut self, budget: Budget) -> Options {
        self.budget = budget;
        self
    }

    /// The deterministic evaluation's settings.
    pub fn eval_settings(&self) -> EvalSettings {
        EvalSettings {
            depth: self.sampling.depth,
            threads: self.budget.threads,
            memory_limit: self.budget.memory,
            start: self.sampling.start.clone(),
            dropped: self.sampling.dropped.clone(),
            progress: self.progress.clone(),
            force: self.sampling.force,
            uv: self.file.uv,
            cancel: Some(self.cancel.clone()),
        }
    }

    /// The chaos game's settings, if the chaos game is asked.
    pub fn random_settings(&self) -> Option<RandomSettings> {
        Some(self.colour_settings(self.sampling.samples?))
    }

    /// The chaos game's settings for `points` points (the colour
    /// coordinates are also those of vertices coloured by map).
    pub(crate) fn colour_settings(&self, points: usize) -> RandomSettings {
        let mut random = RandomSettings::default().with_points(points).with_seed(self.sampling.seed);
        random.probabilities.clone_from(&self.sampling.probabilities);
        random.threads = self.budget.threads;
        random.force = self.sampling.force;
        random.memory_limit = self.budget.memory;
        random.colours.clone_from(&self.look.arrow_colours);
        random.colour_speed = self.look.colour_speed;
        random.progress.clone_from(&self.progress);
        random.cancel = Some(self.cancel.clone());
        random.dropped.clone_from(&self.sampling.dropped);
        random
    }

    /// The pictures' settings.
    pub fn raster(&self) -> RasterSettings {
        let Look { width, height, view, transparent, .. } = self.look;
        let mut raster = RasterSettings::default().with_size(width, height).with_view(view.yaw, view.pitch);
        raster = raster.with_y_up(view.y_up).with_memory_limit(self.budget.memory).with_transparent(transparent);
        raster
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
        settings.push(match (self.sampling.samples, self.sampling.depth) {
            (Some(n), _) => format!("random {n} seed {}", self.sampling.seed),
            (None, Depth::Fixed(k)) => format!("depth {k}"),
            (None, Depth::Tolerance(eps)) => format!("tolerance {eps}"),
        });
        let (look, view) = (&self.look, &self.look.view);
        settings.push(format!("size {}x{}; view {},{}", look.width, look.height, view.yaw, view.pitch));
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
