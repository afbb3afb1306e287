//! Rendering a design to a file, and the gallery of shipped automata. The
//! command line is a thin shell over these functions.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use crate::design::{Design, Model};
use crate::eval::{Depth, EvalError, EvalSettings, Evaluator, RandomSettings, chaos_game};
use crate::export::{ObjWriter, RasterSettings, raster, svg, write_atomic, write_obj, write_png};
use crate::family::{DesignInstantiateError, instantiate};
use crate::geometry::{Shape, Sink};

/// What to render and how.
#[derive(Clone, Debug, Default)]
#[non_exhaustive]
pub struct RenderOptions {
    /// Parameter values (others: the file's defaults).
    pub params: Vec<(String, f64)>,
    /// Deterministic evaluation settings (depth or tolerance, threads, memory, start sets, dropped arrows).
    pub eval: EvalSettings,
    /// Chaos game instead of deterministic evaluation.
    pub random: Option<RandomSettings>,
    /// Picture settings for PNG.
    pub raster: RasterSettings,
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
    /// Writing.
    #[error("cannot write {0}: {1}")]
    Io(PathBuf, std::io::Error),
    /// SVG of a 3D shape.
    #[error("SVG output is for 2D shapes; this model is 3D (use .png or .obj)")]
    NotPlanar,
    /// A normal-vector scheme that cannot take the requested form.
    #[error(transparent)]
    Scheme(crate::schemes::NormalSchemeError),
}

/// What a render produced.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderSummary {
    /// Vertices written.
    pub vertices: usize,
    /// Quads written.
    pub quads: usize,
}

fn model_of(design: &Design) -> Result<Model, RenderError> {
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
        None => Evaluator::new(&instance.automaton, &model, eval)?.evaluate()?,
    })
}

/// Renders a design into `out`, choosing the format by extension: `.obj`
/// is streamed (any depth), `.svg` and `.png` are drawn from memory.
///
/// # Errors
/// See [`RenderError`]; nothing is left half-written.
pub fn render(design: &Design, options: &RenderOptions, out: &Path) -> Result<RenderSummary, RenderError> {
    let ext = out.extension().map(|e| e.to_string_lossy().to_lowercase()).unwrap_or_default();
    let io = |e: std::io::Error| RenderError::Io(out.to_path_buf(), e);
    match ext.as_str() {
        "obj" => {
            let model = model_of(design)?;
            let instance = instantiate(design, &options.params)?;
            let mut writer = ObjWriter::create(out).map_err(io)?;
            match &options.random {
                Some(r) => {
                    let shape = chaos_game(&instance.automaton, &model, r)?;
                    writer.object(design.name()).map_err(io)?;
                    writer.vertices(shape.dim, &shape.positions, None).map_err(io)?;
                    writer.finish().map_err(io)?;
                    Ok(RenderSummary { vertices: shape.vertex_count(), quads: 0 })
                }
                None => {
                    let eval = options.eval.clone();
                    let ev = Evaluator::new(&instance.automaton, &model, eval)?;
                    let mut counter = Counter { inner: &mut writer, vertices: 0, quads: 0 };
                    ev.stream(&mut counter).map_err(|e| match e {
                        EvalError::Io(e) => io(e),
                        other => other.into(),
                    })?;
                    Ok(RenderSummary { vertices: counter.vertices, quads: counter.quads })
                }
            }
        }
        "svg" | "png" => {
            let shape = evaluate_design(design, options)?;
            write_shape(&shape, design.name(), &options.raster, out)
        }
        other => Err(RenderError::Format(other.to_string())),
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
    let summary = RenderSummary { vertices: shape.vertex_count(), quads: shape.quads.len() };
    match ext.as_str() {
        "obj" => write_obj(shape, name, out).map_err(io)?,
        "svg" => {
            if shape.dim > 2 {
                return Err(RenderError::NotPlanar);
            }
            write_atomic(out, svg(shape, raster_settings.width).as_bytes()).map_err(io)?;
        }
        "png" => write_png(out, &raster(shape, raster_settings)).map_err(io)?,
        other => return Err(RenderError::Format(other.to_string())),
    }
    Ok(summary)
}

/// Counts what passes through to another sink.
struct Counter<'a> {
    inner: &'a mut dyn Sink,
    vertices: usize,
    quads: usize,
}

impl Sink for Counter<'_> {
    fn object(&mut self, name: &str) -> std::io::Result<()> {
        self.inner.object(name)
    }
    fn vertices(&mut self, dim: usize, positions: &[f64], normals: Option<&[f64]>) -> std::io::Result<()> {
        self.vertices += positions.len() / dim.max(1);
        self.inner.vertices(dim, positions, normals)
    }
    fn uvs(&mut self, uvs: &[f64]) -> std::io::Result<()> {
        self.inner.uvs(uvs)
    }
    fn polyline(&mut self, first: usize, count: usize, closed: bool) -> std::io::Result<()> {
        self.inner.polyline(first, count, closed)
    }
    fn faces(&mut self, quads: &[[usize; 4]], uvs: Option<&[[usize; 4]]>) -> std::io::Result<()> {
        self.quads += quads.len();
        self.inner.faces(quads, uvs)
    }
    fn triangles(&mut self, triangles: &[[usize; 3]]) -> std::io::Result<()> {
        self.inner.triangles(triangles)
    }
    fn finish(&mut self) -> std::io::Result<()> {
        self.inner.finish()
    }
}

/// In-memory output budget of a gallery picture.
pub const GALLERY_BUDGET_BYTES: u128 = 12 << 20;
/// Deepest gallery depth.
pub const GALLERY_MAX_DEPTH: usize = 16;

/// One rendered gallery entry.
#[derive(Clone, Debug)]
pub struct GalleryEntry {
    /// Automaton name.
    pub name: String,
    /// Description.
    pub description: String,
    /// Depth used (`None`: chaos game).
    pub depth: Option<usize>,
    /// Files written, relative to the gallery directory.
    pub files: Vec<String>,
    /// Vertices and quads of the picture.
    pub summary: RenderSummary,
}

/// The deepest depth whose in-memory output fits the gallery budget.
///
/// # Errors
/// The design cannot be evaluated.
pub fn gallery_depth(design: &Design) -> Result<usize, RenderError> {
    let model = model_of(design)?;
    let instance = instantiate(design, &[])?;
    let ev = Evaluator::new(&instance.automaton, &model, EvalSettings::default())?;
    Ok((1..=GALLERY_MAX_DEPTH).take_while(|&k| ev.estimate_bytes(k) <= GALLERY_BUDGET_BYTES).last().unwrap_or(1))
}

/// What a gallery entry is made from.
#[derive(Clone, Debug)]
pub enum GallerySource {
    /// An automaton with a model, evaluated to the deepest depth within the budget
    /// (or to the given depth).
    Design(Box<Design>, Option<usize>),
    /// A shape computed directly (a scheme's polyline form), with its depth.
    Shape(Box<Shape>, usize),
}

/// The gallery: every shipped automaton with a model, every normal-vector
/// preset of seed 000 at the paper's depth, every scheme of the catalogue
/// (seeds 001 and 003): `(name, description, source)`.
pub fn gallery_items() -> Vec<(String, String, GallerySource)> {
    let mut items: Vec<(String, String, GallerySource)> = crate::BUILTIN_AUTOMATA
        .iter()
        .filter_map(|(n, _)| crate::builtin_design(n))
        .filter(|d| d.model().is_some())
        .map(|d| (d.name().to_string(), d.description().to_string(), GallerySource::Design(Box::new(d), None)))
        .collect();
    for name in crate::schemes::PRESET_NAMES {
        let Ok(preset) = crate::schemes::normal_preset(name) else { continue };
        let entry = format!("normal-{name}");
        let description = format!("{} (normal-vector scheme, seed 000)", preset.description);
        let source = match preset.scheme.design(&entry, &preset.polygon, preset.closed) {
            Ok(design) => GallerySource::Design(Box::new(design), Some(preset.depth)),
            Err(_) => match normal_shape(&preset, preset.depth, SchemeForm::Direct, GALLERY_BUDGET_BYTES as usize) {
                Ok(shape) => GallerySource::Shape(Box::new(shape), preset.depth),
                Err(_) => continue,
            },
        };
        items.push((entry, description, source));
    }
    for name in crate::schemes::IFS_NAMES {
        if let Ok(g) = crate::schemes::ifs_preset(name, None, None) {
            items.push((g.name().to_string(), g.description().to_string(), GallerySource::Design(Box::new(g), None)));
        }
    }
    items
}

/// Renders the gallery ([`gallery_items`]) into `dir`: a PNG and an OBJ each
/// (plus a chaos-game picture for plain IFS), and an `index.html`.
///
/// # Errors
/// The first entry that fails, or an I/O error.
pub fn gallery(dir: &Path, progress: bool) -> Result<Vec<GalleryEntry>, RenderError> {
    std::fs::create_dir_all(dir).map_err(|e| RenderError::Io(dir.to_path_buf(), e))?;
    let mut entries = Vec::new();
    let items = gallery_items();
    let bar = (progress && std::io::IsTerminal::is_terminal(&std::io::stderr()))
        .then(|| indicatif::ProgressBar::new(items.len() as u64));
    for (name, description, source) in items {
        if let Some(b) = &bar {
            b.set_message(name.clone());
        }
        let mut files = Vec::new();
        let (png, obj) = (format!("{name}.png"), format!("{name}.obj"));
        let (depth, summary) = match source {
            GallerySource::Shape(shape, depth) => {
                let summary = write_shape(&shape, &name, &RasterSettings::default(), &dir.join(&png))?;
                write_shape(&shape, &name, &RasterSettings::default(), &dir.join(&obj))?;
                files.extend([png, obj]);
                (depth, summary)
            }
            GallerySource::Design(design, fixed) => {
                let depth = match fixed {
                    Some(d) => d,
                    None => gallery_depth(&design)?,
                };
                let mut options = RenderOptions::default();
                options.eval.depth = Depth::Fixed(depth);
                let summary = render(&design, &options, &dir.join(&png))?;
                render(&design, &options, &dir.join(&obj))?;
                files.extend([png, obj]);
                let model = model_of(&design)?;
                let plain_ifs = model.layout == crate::design::Layout::Single
                    && design
                        .automaton()
                        .state_id(model.root(0))
                        .is_some_and(|r| design.automaton().state(r).kind == crate::space::CellKind::Free);
                if plain_ifs {
                    let mut random = options.clone();
                    random.random = Some(RandomSettings::default().with_points(2_000_000));
                    let png = format!("{name}-chaos.png");
                    render(&design, &random, &dir.join(&png))?;
                    files.push(png);
                }
                (depth, summary)
            }
        };
        entries.push(GalleryEntry { name, description, depth: Some(depth), files, summary });
        if let Some(b) = &bar {
            b.inc(1);
        }
    }
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    let mut html = String::from(
        "<!doctype html>\n<html><head><meta charset=\"utf-8\"><title>bcifs gallery</title>\n<style>body{font-family:sans-serif;margin:2em;background:#f6f7f9}figure{display:inline-block;margin:1em;background:white;padding:1em;box-shadow:0 1px 3px #0002;vertical-align:top}img{width:360px;height:360px;object-fit:contain}figcaption{max-width:360px}</style></head><body>\n<h1>bcifs gallery</h1>\n",
    );
    for e in &entries {
        let _ = write!(html, "<figure>");
        for f in e.files.iter().filter(|f| f.ends_with(".png")) {
            let _ = write!(html, "<img src=\"{f}\" alt=\"{}\">", e.name);
        }
        let obj: Vec<String> =
            e.files.iter().filter(|f| f.ends_with(".obj")).map(|f| format!("<a href=\"{f}\">{f}</a>")).collect();
        let _ = writeln!(
            html,
            "<figcaption><b>{}</b> — {}<br>depth {}, {} vertices{}; {}</figcaption></figure>",
            e.name,
            e.description,
            e.depth.map_or("-".into(), |d| d.to_string()),
            e.summary.vertices,
            if e.summary.quads > 0 { format!(", {} quads", e.summary.quads) } else { String::new() },
            obj.join(" ")
        );
    }
    html.push_str("</body></html>\n");
    write_atomic(&dir.join("index.html"), html.as_bytes()).map_err(|e| RenderError::Io(dir.join("index.html"), e))?;
    Ok(entries)
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
    preset: &crate::schemes::NormalPreset,
    depth: usize,
    form: SchemeForm,
    memory_limit: usize,
) -> Result<Shape, RenderError> {
    let scheme = &preset.scheme;
    if preset.polygon.iter().flatten().any(|x| !x.is_finite()) {
        return Err(RenderError::Scheme(crate::schemes::NormalSchemeError::NotFinite));
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

/// The plot of the ternary 5-point analysis: measured length growth per step
/// and the C0 contraction bound against ω, the line 1, the fractal intervals
/// shaded, and the paper's C0 bounds as vertical lines.
pub fn ternary5_plot(rows: &[crate::analysis::ternary::TernaryRow]) -> crate::export::Plot {
    use crate::analysis::ternary::{PAPER_RANGES, intervals};
    use crate::export::{Plot, Series};
    let series = |label: &str, f: &dyn Fn(&crate::analysis::ternary::TernaryRow) -> f64, color| Series {
        label: label.into(),
        points: rows.iter().map(|r| (r.omega, f(r))).collect(),
        color,
    };
    let mut bands: Vec<(f64, f64, [u8; 3], String)> = intervals(rows, |r| r.fractal())
        .into_iter()
        .map(|(a, b)| (a, b, [255, 222, 222], "fractal".to_string()))
        .collect();
    bands
        .extend(intervals(rows, |r| r.fails()).into_iter().map(|(a, b)| (a, b, [225, 225, 225], "not C0".to_string())));
    // One legend entry per kind.
    let mut seen = std::collections::HashSet::new();
    for b in &mut bands {
        if !seen.insert(b.3.clone()) {
            b.3.clear();
        }
    }
    let top = rows.iter().map(|r| r.growth.max(r.c0)).fold(1.5f64, f64::max).min(4.0);
    Plot {
        title: "TERNARY 5-POINT SCHEME".into(),
        x_label: "TENSION W".into(),
        y_label: "RATE PER STEP".into(),
        series: vec![
            series("LENGTH GROWTH", &|r| r.growth, [30, 70, 170]),
            series("C0 BOUND (<1: C0)", &|r| r.c0, [230, 120, 20]),
            series("C1 BOUND", &|r| r.c1, [40, 150, 60]),
        ],
        bands: bands.into_iter().map(|(a, b, c, l)| (a, b, c, l.to_uppercase())).collect(),
        hlines: vec![(1.0, [200, 0, 0])],
        vlines: vec![(PAPER_RANGES[0].1, [150, 0, 150]), (PAPER_RANGES[0].2, [150, 0, 150])],
        y_range: Some((0.0, top)),
    }
}
