//! Rendering a design to a file chosen by its extension (`.obj` streamed,
//! `.svg`, `.png`), and the curves of the normal-vector presets.

use std::path::{Path, PathBuf};

use anyhow::bail;
use bcifs::eval::{EvalError, EvalSettings};
use bcifs::geometry::Shape;
use bcifs::render::{Options, RenderError, Report, control_net, evaluate_design, model_of, write_shape};

use crate::cli::common::{check_threads, load, parse_params, progress_bar};

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
    #[command(flatten)]
    pub picture: crate::cli::common::PictureArgs,
    /// Output file: .obj, .off, .ply, .stl (streamed), .glb, .svg, .png, or .flame (a plain IFS of the plane).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Evaluate even a system whose convergence bounds prove it diverges.
    #[arg(long)]
    pub force: bool,
    /// Texture coordinates on meshes: one (u, v) parameterization of the whole grid or torus.
    #[arg(long)]
    pub uv: bool,
    /// The model axis that is up in OBJ and OFF files: y (the convention: model z becomes the file's y) or z (as is).
    #[arg(long, value_enum, default_value_t = bcifs::export::Up::Y)]
    pub up: bcifs::export::Up,
    /// PLY as text instead of binary little-endian.
    #[arg(long)]
    pub ascii: bool,
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
    /// Colour the vertices of a deterministic evaluation (OBJ, PLY, glTF) with --palette (default
    /// rainbow): by the `state` of the cell that makes them, the `level` at which they appear, or the
    /// `map`s that lead to them (as the chaos game colours, with --color and --color-speed).
    #[arg(long = "colour", alias = "colour-by", value_enum)]
    pub colour_by: Option<bcifs::eval::Colouring>,
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
    crate::cli::common::check_output(
        &args.output,
        &crate::cli::common::render_formats(),
        &[std::path::Path::new(&args.file)],
    )?;
    let design = load(&args.file)?;
    let started = std::time::Instant::now();
    if args.control {
        if args.random.is_some() {
            bail!("--control draws the control net: --random (the chaos game) does not apply to it");
        }
        let model = model_of(&design)?;
        let raster = args.picture.raster();
        let report = write_shape(&control_net(&model), design.name(), &raster, &args.output)?;
        print_report(&report, &format!("{} (control net)", design.name()), &args.output, started);
        return Ok(0);
    }
    let options = options(&args)?;
    let report = bcifs::render::render(&design, &options, &args.output)?;
    print_report(&report, design.name(), &args.output, started);
    Ok(0)
}

/// The render options the arguments ask for, checked.
fn options(args: &RenderArgs) -> anyhow::Result<Options> {
    if args.precision.is_some_and(|p| !(1..=15).contains(&p)) {
        bail!("--precision is a number of significant digits, 1 to 15 (the default is exact)");
    }
    if args.random.is_some() && (args.depth.is_some() || args.tolerance.is_some()) {
        bail!("--random draws points by the chaos game: --depth and --tolerance do not apply to it");
    }
    if !(args.max_output_gib.is_finite() && args.max_output_gib > 0.0) {
        bail!("--max-output-gib {}: expected a positive number of GiB", args.max_output_gib);
    }
    let threads = check_threads(args.threads)?;
    let memory = args.picture.memory();
    let mut options = Options { params: parse_params(&args.params)?, ..Options::default() };
    options.eval.depth = match (args.depth, args.tolerance) {
        (_, Some(eps)) if eps > 0.0 => bcifs::eval::Depth::Tolerance(eps),
        (_, Some(eps)) => bail!("the tolerance must be positive, not {eps}"),
        (Some(k), None) => bcifs::eval::Depth::Fixed(k),
        (None, None) => bcifs::eval::Depth::Fixed(bcifs::eval::DEFAULT_DEPTH),
    };
    options.eval.threads = threads;
    options.eval.memory_limit = memory;
    options.eval.dropped.clone_from(&args.drop);
    options.eval.force = args.force;
    options.eval.uv = args.uv;
    options.dedup = args.dedup;
    options.coordinates.up = args.up;
    options.coordinates = options.coordinates.with_precision(args.precision);
    options.ascii = args.ascii;
    options.max_output = (args.max_output_gib * (1u64 << 30) as f64) as u128;
    options.progress = progress_bar();
    options.cancel = crate::cli::common::interrupt().clone();
    options.provenance = Some(crate::cli::common::command_line());
    if let Some(n) = args.random {
        let mut r = bcifs::eval::RandomSettings::default().with_points(n).with_seed(args.seed);
        r.threads = threads;
        r.probabilities = parse_params(&args.probs)?;
        r.force = args.force;
        r.memory_limit = memory;
        r.colours = parse_params(&args.colours)?;
        r.colour_speed = args.colour_speed;
        r.dropped.clone_from(&args.drop);
        options.random = Some(r);
    }
    options.raster = args.picture.raster();
    options.tone = tone(args)?;
    options.colour = args.colour_by;
    options.arrow_colours = parse_params(&args.colours)?;
    options.colour_speed = Some(args.colour_speed);
    options.palette =
        args.palette.as_deref().map(bcifs::export::Palette::parse).transpose().map_err(anyhow::Error::msg)?;
    Ok(options)
}

/// The tone mapping of density pictures the arguments ask for, checked.
fn tone(args: &RenderArgs) -> anyhow::Result<bcifs::export::Tone> {
    use bcifs::export::Tone;
    let RenderArgs { brightness, gamma, supersample, vibrancy, colour_speed, blur, blur_curve, .. } = *args;
    if !(0.0..=1.0).contains(&colour_speed) {
        bail!("--color-speed is between 0 and 1");
    }
    let background = args
        .background
        .as_deref()
        .map(Tone::parse_colour)
        .transpose()
        .map_err(|e| anyhow::anyhow!("--background {e}"))?;
    Tone { brightness, gamma, vibrancy, supersample, blur, blur_curve, background }
        .checked()
        .map_err(|e| anyhow::anyhow!("--{e}"))
}

/// Tells stderr a render's warnings and notes.
pub fn warn(report: &Report) {
    for w in &report.warnings {
        eprintln!("warning: {w}");
    }
    for n in &report.notes {
        eprintln!("note: {n}");
    }
}

/// Tells stderr what a render did: its warnings and notes, then
/// `label: N vertices, M faces → OUT (T s)`.
pub fn print_report(report: &Report, label: &str, output: &Path, started: std::time::Instant) {
    warn(report);
    eprintln!(
        "{label}: {} vertices{}{} → {} ({:.2} s)",
        report.vertices,
        if report.faces > 0 { format!(", {} faces", report.faces) } else { String::new() },
        report.duplicates.map_or(String::new(), |n| format!(" ({n} exact duplicates dropped)")),
        output.display(),
        started.elapsed().as_secs_f64()
    );
}

/// Which form of a scheme to evaluate.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
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
        let options = Options {
            eval: EvalSettings::default().with_depth(depth).with_memory_limit(memory_limit),
            ..Default::default()
        };
        return evaluate_design(&design, &options, &mut Vec::new());
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
