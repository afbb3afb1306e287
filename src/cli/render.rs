//! Rendering a design to a file chosen by its extension (`.obj` streamed,
//! `.svg`, `.png`), and the curves of the normal-vector presets.

use std::path::{Path, PathBuf};

use anyhow::bail;
use bcifs::eval::{EvalError, EvalSettings, Evaluator, chaos_game};
use bcifs::export::{ObjWriter, RasterSettings, raster, svg, svg_surface, write_atomic, write_obj, write_png};
use bcifs::geometry::{Shape, Sink};
use bcifs::{Design, DesignInstantiateError, Model, instantiate};

use super::{check_threads, keyword, load, parse_params, parse_size, parse_view, progress_bar};

/// What to render and how.
#[derive(Clone, Debug, Default)]
pub struct RenderOptions {
    /// Parameter values (others: the file's defaults).
    pub params: Vec<(String, f64)>,
    /// Deterministic evaluation settings (depth or tolerance, threads, memory, start sets, dropped arrows).
    pub eval: EvalSettings,
    /// Chaos game instead of deterministic evaluation.
    pub random: Option<bcifs::eval::RandomSettings>,
    /// Picture settings for PNG.
    pub raster: RasterSettings,
    /// Which model axis is up in OBJ files (Y-up by convention).
    pub up: bcifs::export::Up,
    /// Largest OBJ output to write, in bytes (0: no limit).
    pub max_output: u128,
    /// Drop exact duplicate points of a point cloud.
    pub dedup: bool,
    /// Significant digits of OBJ coordinates (`None`: shortest round-trip).
    pub precision: Option<u32>,
    /// Tone mapping of chaos-game pictures (density images).
    pub tone: bcifs::export::Tone,
    /// Colour chaos-game pictures by the arrows applied, with this palette.
    pub palette: Option<bcifs::export::Palette>,
}

/// Why rendering failed.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// The design has no model to project with.
    #[error("`{0}` has no [model]: add control points to render it")]
    NoModel(String),
    /// Parameters or constraints.
    #[error(transparent)]
    Instantiate(#[from] DesignInstantiateError),
    /// Evaluation.
    #[error(transparent)]
    Eval(#[from] EvalError),
    /// Output format not known.
    #[error("unknown output format `{0}`: expected .obj, .svg or .png")]
    Format(String),
    /// A picture over the memory limit.
    #[error(transparent)]
    Raster(#[from] bcifs::export::RasterTooLarge),
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
    Scheme(bcifs::schemes::NormalSchemeError),
}

/// The arguments of `bcifs render`.
#[derive(clap::Args)]
pub struct RenderArgs {
    /// The automaton file (TOML), or the name of a shipped automaton.
    pub file: String,
    /// A parameter value, NAME=VALUE (repeatable).
    #[arg(long = "param", value_name = "NAME=VALUE")]
    pub params: Vec<String>,
    /// Subdivision depth.
    #[arg(long, conflicts_with = "tolerance")]
    pub depth: Option<usize>,
    /// Subdivide until every cell is smaller than this (modelling units): its part of the attractor for an IFS of affine contractions (a Hausdorff bound), its control polygon otherwise.
    #[arg(long)]
    pub tolerance: Option<f64>,
    /// Chaos game with this many points instead of deterministic evaluation.
    #[arg(long, value_name = "N")]
    pub random: Option<usize>,
    /// Seed of the chaos game.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Probability of an arrow in the chaos game, ARROW=P (repeatable; default ∝ |det|).
    #[arg(long = "prob", value_name = "ARROW=P")]
    pub probs: Vec<String>,
    /// Leave out a subdivision arrow (repeatable): a subset of the attractor.
    #[arg(long = "drop", value_name = "ARROW")]
    pub drop: Vec<String>,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
    /// In-memory limit in MiB for PNG/SVG output.
    #[arg(long, default_value_t = 4096)]
    pub memory_mib: usize,
    /// Picture size in pixels, WIDTHxHEIGHT.
    #[arg(long, default_value = "800x800")]
    pub size: String,
    /// View of 3D shapes: YAW,PITCH in degrees.
    #[arg(long, default_value = "30,35", allow_hyphen_values = true)]
    pub view: String,
    /// Output file: .obj (streamed), .svg or .png.
    #[arg(short, long)]
    pub output: PathBuf,
    /// Evaluate even a system whose convergence bounds prove it diverges.
    #[arg(long)]
    pub force: bool,
    /// Texture coordinates on meshes: one (u, v) parameterization of the whole grid or torus.
    #[arg(long)]
    pub uv: bool,
    /// The model axis that is up in OBJ files: y (the convention: model z becomes the file's y) or z (as is).
    #[arg(long, default_value = "y")]
    pub up: String,
    /// Largest OBJ file to write, in GiB (the estimate is checked before writing; raise it on purpose).
    #[arg(long, default_value_t = 4.0)]
    pub max_output_gib: f64,
    /// Drop exact duplicate points of a point cloud (evaluated in memory), reporting how many.
    #[arg(long)]
    pub dedup: bool,
    /// Write the model's control net instead of the attractor (the control polygon of a
    /// curve, the control grid of a surface as quads), to show next to the attractor.
    #[arg(long)]
    pub control: bool,
    /// Chaos game to PNG: log-density brightness b, v = (ln(1 + b·count) / ln(1 + b·max))^(1/gamma).
    #[arg(long, default_value_t = 1.0)]
    pub brightness: f64,
    /// Chaos game to PNG: the gamma of the tone mapping.
    #[arg(long, default_value_t = 2.2)]
    pub gamma: f64,
    /// Chaos game to PNG: cells per pixel side, averaged (1 to 8).
    #[arg(long, default_value_t = 1)]
    pub supersample: u32,
    /// OBJ coordinates with this many significant digits (1 to 15): smaller files, written faster
    /// (default: the shortest text that reads back to the same number, up to 17 digits).
    #[arg(long)]
    pub precision: Option<u32>,
    /// Chaos game to PNG: colour by the arrows applied, with this palette: fire, ocean, rainbow,
    /// viridis, sunset, or a picture file (its middle row, left to right).
    #[arg(long)]
    pub palette: Option<String>,
    /// Chaos game with --palette: the colour coordinate of an arrow, ARROW=C with C in [0, 1]
    /// (repeatable; the others are spread evenly in arrow order).
    #[arg(long = "color", value_name = "ARROW=C")]
    pub colours: Vec<String>,
    /// Chaos game with --palette: each step moves the colour coordinate this far towards the
    /// arrow's colour, c ← (1 − s) c + s c_arrow (flam3's colour speed).
    #[arg(long = "color-speed", default_value_t = 0.5)]
    pub colour_speed: f64,
    /// Chaos game with --palette: 1 keeps the hues as the density fades, 0 tone-maps each channel.
    #[arg(long, default_value_t = 1.0)]
    pub vibrancy: f64,
    /// Chaos game to PNG: density-estimation blur, the largest radius in pixels (sparse cells
    /// spread over radius/count^curve, dense ones stay sharp; 0: off).
    #[arg(long, default_value_t = 0.0)]
    pub blur: f64,
    /// Chaos game to PNG: how fast the blur radius shrinks with the count.
    #[arg(long = "blur-curve", default_value_t = 0.4)]
    pub blur_curve: f64,
    /// Chaos game to PNG: the background, RRGGBB in hexadecimal, white or black (default: white,
    /// black with --palette).
    #[arg(long)]
    pub background: Option<String>,
}

/// `bcifs render`: evaluates a design with its model and writes the file.
pub fn run(args: RenderArgs) -> anyhow::Result<u8> {
    let RenderArgs {
        file,
        params,
        depth,
        tolerance,
        random,
        seed,
        probs,
        drop,
        threads,
        memory_mib,
        size,
        view,
        output,
        force,
        uv,
        up,
        max_output_gib,
        dedup,
        control,
        brightness,
        gamma,
        supersample,
        palette,
        colours,
        colour_speed,
        vibrancy,
        blur,
        blur_curve,
        background,
        precision,
    } = args;
    super::check_output(&output, &["obj", "svg", "png"])?;
    if precision.is_some_and(|p| !(1..=15).contains(&p)) {
        bail!("--precision is a number of significant digits, 1 to 15 (the default is exact)");
    }
    if !(brightness > 0.0
        && brightness.is_finite()
        && gamma > 0.0
        && gamma.is_finite()
        && (1..=8).contains(&supersample))
    {
        bail!("--brightness and --gamma must be positive numbers, --supersample 1 to 8");
    }
    if !((0.0..=1.0).contains(&vibrancy) && (0.0..=1.0).contains(&colour_speed)) {
        bail!("--vibrancy and --color-speed are between 0 and 1");
    }
    if !(blur.is_finite() && (0.0..=64.0).contains(&blur) && blur_curve.is_finite() && blur_curve >= 0.0) {
        bail!("--blur is a radius from 0 to 64 pixels, --blur-curve a number from 0 up");
    }
    let palette = palette.map(|p| bcifs::export::Palette::parse(&p)).transpose().map_err(anyhow::Error::msg)?;
    let background = background.map(|b| parse_colour(&b)).transpose()?;
    let design = load(&file)?;
    if control {
        let model = model_of(&design)?;
        let (w, h) = parse_size(&size)?;
        let raster = RasterSettings::default().with_size(w, h).with_memory_limit(memory_mib.saturating_mul(1 << 20));
        let started = std::time::Instant::now();
        let summary = write_shape(&control_net(&model), design.name(), &raster, &output)?;
        summary.report(&format!("{} (control net)", design.name()), &output, started);
        return Ok(0);
    }
    if random.is_some() && (depth.is_some() || tolerance.is_some()) {
        bail!("--random draws points by the chaos game: --depth and --tolerance do not apply to it");
    }
    let flame = palette.is_some() || !colours.is_empty() || blur > 0.0 || vibrancy != 1.0 || background.is_some();
    let ext = output.extension().map(|e| e.to_string_lossy().to_lowercase()).unwrap_or_default();
    if flame && random.is_none() {
        eprintln!(
            "warning: --palette, --color, --blur, --vibrancy and --background shape chaos-game pictures (--random N); this render ignores them"
        );
    } else if flame && ext != "png" {
        eprintln!(
            "warning: --palette, --color, --blur, --vibrancy and --background shape density pictures (.png); the .{ext} file ignores them"
        );
    }
    if uv && ext != "obj" {
        eprintln!("warning: --uv writes texture coordinates into OBJ files; the .{ext} output ignores it");
    }
    if precision.is_some() && ext != "obj" {
        eprintln!("warning: --precision sets the digits of OBJ coordinates; the .{ext} output ignores it");
    }
    let threads = check_threads(threads)?;
    // A fully known automaton whose constraints fail is not what its file says.
    if let Err(bcifs::SolveError::Inconsistent { conflicts }) = bcifs::solve(&design)
        && !force
    {
        bail!("{}: the constraints do not hold ({}); render anyway with --force", design.name(), conflicts.join("; "));
    }
    let mut options = RenderOptions { params: parse_params(&params)?, ..RenderOptions::default() };
    options.eval.depth = match (depth, tolerance) {
        (_, Some(eps)) if eps > 0.0 => bcifs::eval::Depth::Tolerance(eps),
        (_, Some(eps)) => bail!("the tolerance must be positive, not {eps}"),
        (Some(k), None) => bcifs::eval::Depth::Fixed(k),
        (None, None) => bcifs::eval::Depth::Fixed(bcifs::eval::DEFAULT_DEPTH),
    };
    options.eval.threads = threads;
    options.eval.memory_limit = memory_mib.saturating_mul(1 << 20);
    options.eval.dropped = drop;
    options.eval.force = force;
    options.eval.uv = uv;
    options.dedup = dedup;
    options.up = keyword("up axis", &up, &[("y", bcifs::export::Up::Y), ("z", bcifs::export::Up::Z)])?;
    if !(max_output_gib.is_finite() && max_output_gib > 0.0) {
        bail!("--max-output-gib {max_output_gib}: expected a positive number of GiB");
    }
    options.max_output = (max_output_gib * (1u64 << 30) as f64) as u128;
    options.eval.progress = progress_bar();
    if let Some(n) = random {
        let mut r = bcifs::eval::RandomSettings::default().with_points(n).with_seed(seed);
        r.threads = threads;
        r.probabilities = parse_params(&probs)?;
        r.force = force;
        r.memory_limit = memory_mib.saturating_mul(1 << 20);
        r.colours = parse_params(&colours)?;
        r.colour_speed = colour_speed;
        r.progress = options.eval.progress.clone();
        r.dropped = options.eval.dropped.clone();
        options.random = Some(r);
    }
    let (w, h) = parse_size(&size)?;
    let (yaw, pitch) = parse_view(&view)?;
    options.raster = options.raster.with_size(w, h).with_view(yaw, pitch).with_memory_limit(options.eval.memory_limit);
    options.tone = bcifs::export::Tone { brightness, gamma, vibrancy, supersample, blur, blur_curve, background };
    options.palette = palette;
    options.precision = precision;
    let started = std::time::Instant::now();
    let summary = render(&design, &options, &output)?;
    summary.report(design.name(), &output, started);
    if summary.vertices == 0 {
        eprintln!("warning: the output is empty (every arrow dropped, or nothing to draw)");
    }
    Ok(0)
}

/// A colour: `RRGGBB` in hexadecimal (an optional `#`), `white` or `black`.
fn parse_colour(text: &str) -> anyhow::Result<[u8; 3]> {
    match text {
        "white" => return Ok([255; 3]),
        "black" => return Ok([0; 3]),
        _ => {}
    }
    let hex = text.trim_start_matches('#');
    let channel = |k: usize| hex.get(2 * k..2 * k + 2).and_then(|h| u8::from_str_radix(h, 16).ok());
    match (hex.len(), channel(0), channel(1), channel(2)) {
        (6, Some(r), Some(g), Some(b)) => Ok([r, g, b]),
        _ => bail!("--background {text}: expected RRGGBB in hexadecimal, white or black"),
    }
}

/// Refuses an OBJ output whose estimated size is over `max` (0: no limit)
/// or over the free space of the target's disk (with the temporary side
/// file, a streamed OBJ peaks at about 1.5 times its size).
pub(crate) fn check_disk(out: &Path, estimate: u128, max: u128) -> Result<(), RenderError> {
    let gib = |b: u128| b as f64 / (1u64 << 30) as f64;
    if max > 0 && estimate > max {
        return Err(RenderError::TooBig(format!(
            "the OBJ would take about {:.1} GiB, over --max-output-gib {:.1}: lower the depth or raise the limit",
            gib(estimate),
            gib(max)
        )));
    }
    let dir = out.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
    if let Ok(free) = fs4::available_space(dir)
        && estimate.saturating_mul(3) / 2 > u128::from(free)
    {
        return Err(RenderError::TooBig(format!(
            "the OBJ would take about {:.1} GiB (and half as much again while it is written); {} has {:.1} GiB free",
            gib(estimate),
            dir.display(),
            gib(u128::from(free))
        )));
    }
    Ok(())
}

/// What a render produced.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderSummary {
    /// Vertices written.
    pub vertices: usize,
    /// Faces written (quads and triangles).
    pub faces: usize,
    /// Exact duplicate points dropped (`--dedup`), `None` when not asked or not a point cloud.
    pub duplicates: Option<usize>,
}

impl RenderSummary {
    /// Tells stderr what went where: `label: N vertices, M faces → OUT (T s)`.
    pub fn report(&self, label: &str, output: &Path, started: std::time::Instant) {
        eprintln!(
            "{label}: {} vertices{}{} → {} ({:.2} s)",
            self.vertices,
            if self.faces > 0 { format!(", {} faces", self.faces) } else { String::new() },
            self.duplicates.map_or(String::new(), |n| format!(" ({n} exact duplicates dropped)")),
            output.display(),
            started.elapsed().as_secs_f64()
        );
    }
}

pub fn model_of(design: &Design) -> Result<Model, RenderError> {
    design.model().cloned().ok_or_else(|| RenderError::NoModel(design.name().to_string()))
}

/// Evaluates a design in memory (deterministic or random, as the options say).
///
/// # Errors
/// See [`RenderError`].
pub fn evaluate_design(design: &Design, options: &RenderOptions) -> Result<Shape, RenderError> {
    let model = model_of(design)?;
    let instance = instantiate(design, &options.params)?;
    let eval = options.eval.clone();
    Ok(match &options.random {
        Some(r) => chaos_game(&instance.automaton, &model, r)?,
        None => evaluator(&instance.automaton, &model, eval, design.name())?.evaluate()?,
    })
}

/// Drops the exact duplicate points of `shape` when `options.dedup` asks
/// for it: how many, or `None` (not asked, or not a point cloud: a warning).
fn dedup(shape: &mut Shape, options: &RenderOptions) -> Option<usize> {
    if !options.dedup {
        return None;
    }
    let dropped = shape.dedup_points();
    if dropped.is_none() {
        eprintln!("warning: --dedup applies to point clouds; this output has lines or faces, kept as is");
    }
    dropped
}

/// A chaos game whose points are streamed or counted, never held: its
/// memory check is for one batch.
fn streaming_game(
    automaton: &bcifs::Automaton<f64>,
    model: &Model,
    random: &bcifs::eval::RandomSettings,
) -> Result<bcifs::eval::ChaosGame, RenderError> {
    bcifs::eval::check_samples(random.points)?;
    let batch = random.clone().with_points(random.points.min(bcifs::eval::BATCH));
    Ok(bcifs::eval::ChaosGame::new(automaton, model, &batch)?)
}

/// An evaluator, its warnings (undecided convergence) told on stderr.
fn evaluator(
    automaton: &bcifs::Automaton<f64>,
    model: &Model,
    settings: EvalSettings,
    name: &str,
) -> Result<Evaluator, RenderError> {
    let ev = Evaluator::new(automaton, model, settings)?;
    for w in ev.warnings() {
        // Named: the gallery renders many designs in one run.
        eprintln!("warning: {name}: {w}");
    }
    Ok(ev)
}

/// Renders a design into `out`, choosing the format by extension: `.obj`
/// is streamed (any depth), `.svg` and `.png` are drawn from memory.
///
/// # Errors
/// See [`RenderError`]; nothing is left half-written.
pub fn render(design: &Design, options: &RenderOptions, out: &Path) -> Result<RenderSummary, RenderError> {
    let ext = out.extension().map(|e| e.to_string_lossy().to_lowercase()).unwrap_or_default();
    // A model in a mesh file's (Y-up) axes is drawn standing and written without a turn.
    let y_up = design.model().is_some_and(|m| m.y_up);
    let options = &RenderOptions { raster: options.raster.with_y_up(y_up), ..options.clone() };
    let io = |e: std::io::Error| RenderError::Io(out.to_path_buf(), e);
    match ext.as_str() {
        "obj" => {
            let model = model_of(design)?;
            let instance = instantiate(design, &options.params)?;
            let threads =
                options.eval.threads.unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
            let mut writer = ObjWriter::create(out)
                .and_then(|w| w.with_threads(threads))
                .map_err(io)?
                .with_up(options.up)
                .with_y_up_input(y_up)
                .with_precision(options.precision);
            if let (Some(random), false) = (&options.random, options.dedup) {
                // The chaos game streamed, a few chains at a time.
                let game = streaming_game(&instance.automaton, &model, random)?;
                check_disk(out, random.points as u128 * (3 + 22 * game.dim() as u128), options.max_output)?;
                writer.object(design.name()).map_err(io)?;
                game.stream(random.points, |xs| writer.vertices(game.dim(), xs, None)).map_err(io)?;
                writer.finish().map_err(io)?;
                return Ok(RenderSummary { vertices: random.points, faces: 0, duplicates: None });
            }
            if options.random.is_some() || options.dedup {
                // In memory: the chaos game's points, or a cloud to deduplicate.
                let mut shape = evaluate_design(design, options)?;
                let duplicates = dedup(&mut shape, options);
                if shape.objects.is_empty() {
                    writer.object(design.name()).map_err(io)?;
                }
                shape.replay(&mut writer).map_err(io)?;
                writer.finish().map_err(io)?;
                return Ok(RenderSummary {
                    vertices: shape.vertex_count(),
                    faces: shape.quads.len() + shape.triangles.len(),
                    duplicates,
                });
            }
            let eval = options.eval.clone();
            let ev = evaluator(&instance.automaton, &model, eval.clone(), design.name())?;
            if eval.uv && ev.polylines().is_some() {
                eprintln!("warning: --uv gives texture coordinates to surfaces; this curve or point set has none");
            }
            if let bcifs::eval::Depth::Fixed(k) = eval.depth {
                check_disk(out, ev.estimate_obj_bytes(k), options.max_output)?;
            }
            // Vertices, then elements: two streamed passes, no side file of elements.
            let (vertices, quads) = bcifs::export::write_evaluation(&ev, &mut writer).map_err(|e| match e {
                EvalError::Io(e) => io(e),
                other => other.into(),
            })?;
            let summary = RenderSummary { vertices, faces: quads, duplicates: None };
            writer.finish().map_err(io)?;
            Ok(summary)
        }
        "png" if options.random.is_some() && !options.dedup => {
            // A density picture: the samples are counted per pixel, never stored.
            let random = options.random.as_ref().expect("checked");
            let model = model_of(design)?;
            let instance = instantiate(design, &options.params)?;
            let game = streaming_game(&instance.automaton, &model, random)?;
            let palette = options.palette.as_ref();
            let img = bcifs::export::density_image(&game, random.points, &options.raster, &options.tone, palette)?;
            write_png(out, &img).map_err(io)?;
            Ok(RenderSummary { vertices: random.points, faces: 0, duplicates: None })
        }
        "png" if options.random.is_none() && !options.dedup => {
            // Curves and points are drawn while they are evaluated (twice streamed: the
            // frame, then the drawing); surfaces are drawn from memory.
            let model = model_of(design)?;
            let instance = instantiate(design, &options.params)?;
            let mut ev = evaluator(&instance.automaton, &model, options.eval.clone(), design.name())?;
            let needed = bcifs::export::picture_bytes(&options.raster);
            if ev.polylines().is_some() && needed > options.raster.memory_limit as u128 {
                let vertices = match options.eval.depth {
                    bcifs::eval::Depth::Fixed(k) => {
                        (0..ev.pieces().pieces.len()).fold(0usize, |a, p| a.saturating_add(ev.sample_count(p, k)))
                    }
                    bcifs::eval::Depth::Tolerance(_) => 0,
                };
                let (width, height, limit) = (options.raster.width, options.raster.height, options.raster.memory_limit);
                return Err(bcifs::export::RasterTooLarge { width, height, vertices, needed, limit }.into());
            }
            if let (Some(true), bcifs::eval::Depth::Fixed(k)) = (ev.polylines(), options.eval.depth) {
                // A curve: subdivided until its segments are below a pixel, not beyond.
                let enough = bcifs::export::curve_picture_depth(&mut ev, &options.raster, k)?;
                if enough < k {
                    eprintln!(
                        "note: the picture is drawn at depth {enough}, whose segments are below a pixel of the {}×{} picture (deeper ones only move the curve within its pixels); OBJ and SVG output keep depth {k}",
                        options.raster.width, options.raster.height
                    );
                }
            }
            if let Some((img, vertices)) = bcifs::export::picture(&ev, &options.raster)? {
                write_png(out, &img).map_err(io)?;
                return Ok(RenderSummary { vertices, faces: 0, duplicates: None });
            }
            // A surface: drawn at the depth whose quads are already below a pixel.
            let depth = match options.eval.depth {
                bcifs::eval::Depth::Fixed(k) => Some(k),
                bcifs::eval::Depth::Tolerance(eps) if ev.quads_at(0).is_some() => Some(ev.depth_for_tolerance(eps)?),
                bcifs::eval::Depth::Tolerance(_) => None,
            };
            if let Some(k) = depth {
                let enough = bcifs::export::picture_depth(&ev, &options.raster, k);
                if enough < k {
                    eprintln!(
                        "note: the picture is drawn at depth {enough}, whose {} quads outnumber the {}×{} pixels (deeper quads are smaller than a pixel); OBJ output keeps depth {k}",
                        ev.quads_at(enough).unwrap_or(0),
                        options.raster.width,
                        options.raster.height
                    );
                    ev.set_depth(bcifs::eval::Depth::Fixed(enough))?;
                }
            }
            let shape = ev.evaluate()?;
            write_shape(&shape, design.name(), &options.raster, out)
        }
        "svg" | "png" => {
            let mut shape = evaluate_design(design, options)?;
            let duplicates = dedup(&mut shape, options);
            Ok(RenderSummary { duplicates, ..write_shape(&shape, design.name(), &options.raster, out)? })
        }
        other => Err(RenderError::Format(other.to_string())),
    }
}

/// The control net of a model: the control polygon of a curve (closed for
/// closed layouts), the control grid of a sheet or torus as quads, the
/// points in order otherwise.
pub fn control_net(model: &Model) -> Shape {
    use bcifs::Layout;
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

/// Writes a shape held in memory to `out`, choosing the format by
/// extension: `.obj`, `.svg` (2D only) or `.png` (with `raster`).
///
/// # Errors
/// An unknown extension, a 3D shape to SVG, or an I/O error; nothing is
/// left half-written.
pub fn write_shape(
    shape: &Shape,
    name: &str,
    raster_settings: &RasterSettings,
    out: &Path,
) -> Result<RenderSummary, RenderError> {
    let ext = out.extension().map(|e| e.to_string_lossy().to_lowercase()).unwrap_or_default();
    let io = |e: std::io::Error| RenderError::Io(out.to_path_buf(), e);
    let summary = RenderSummary {
        vertices: shape.vertex_count(),
        faces: shape.quads.len() + shape.triangles.len(),
        duplicates: None,
    };
    match ext.as_str() {
        "obj" => write_obj(shape, name, out).map_err(io)?,
        "svg" if !shape.quads.is_empty() || !shape.triangles.is_empty() => {
            write_atomic(out, svg_surface(shape, raster_settings).as_bytes()).map_err(io)?;
        }
        "svg" => {
            if shape.dim > 2 {
                return Err(RenderError::NotPlanar);
            }
            write_atomic(out, svg(shape, raster_settings.width).as_bytes()).map_err(io)?;
        }
        "png" => write_png(out, &raster(shape, raster_settings)?).map_err(io)?,
        other => return Err(RenderError::Format(other.to_string())),
    }
    Ok(summary)
}

/// Which form of a scheme to evaluate.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SchemeForm {
    /// The automaton when the scheme has one, the direct polyline form otherwise.
    Auto,
    /// The direct polyline form (the paper's refinement rules).
    Direct,
    /// The automaton (BC-IFS) form.
    Automaton,
}

/// The curve of a normal-vector scheme on its initial polygon after `depth`
/// steps, in the requested form (both forms give the same points).
///
/// # Errors
/// A non-interpolatory scheme asked for in automaton form, or an evaluation error.
pub fn normal_shape(
    preset: &bcifs::schemes::NormalPreset,
    depth: usize,
    form: SchemeForm,
    memory_limit: usize,
) -> Result<Shape, RenderError> {
    let scheme = &preset.scheme;
    if preset.polygon.iter().flatten().any(|x| !x.is_finite()) {
        return Err(RenderError::Scheme(bcifs::schemes::NormalSchemeError::NotFinite));
    }
    let automaton = match form {
        SchemeForm::Auto => scheme.is_interpolatory(),
        SchemeForm::Direct => false,
        SchemeForm::Automaton => true,
    };
    if automaton {
        let design = scheme.design(preset.name, &preset.polygon, preset.closed).map_err(RenderError::Scheme)?;
        let options = RenderOptions {
            eval: EvalSettings::default().with_depth(depth).with_memory_limit(memory_limit),
            ..Default::default()
        };
        return evaluate_design(&design, &options);
    }
    let segments = if preset.closed { preset.polygon.len() } else { preset.polygon.len().saturating_sub(1) };
    let points = (segments as u128 * (scheme.arity() as u128).pow(depth.min(64) as u32) + 1) * 2 * 8;
    if points > memory_limit as u128 {
        return Err(RenderError::Eval(EvalError::TooLarge { estimate: points, limit: memory_limit }));
    }
    let pts = scheme.polygon(&preset.polygon, preset.closed, depth);
    let flat: Vec<f64> = pts.iter().flatten().copied().collect();
    Ok(Shape::polyline(preset.name, 2, &flat, preset.closed))
}
